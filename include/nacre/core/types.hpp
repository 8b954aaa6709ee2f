// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Execution/memory spaces and View aliases shared by every area of nacre.
#include <Kokkos_Core.hpp>
#include <Kokkos_Profiling_ScopedRegion.hpp>
#include <cstdint>

namespace nacre {

using ExecSpace = Kokkos::DefaultExecutionSpace;
using MemSpace = ExecSpace::memory_space;
using HostSpace = Kokkos::HostSpace;
/// \brief The memory space of execution space E (where a solver built for E keeps its model).
template <class E>
using MemOf = typename E::memory_space;

/// \brief Per-entity scalar field (structure of arrays: one contiguous array per quantity, so
/// consecutive threads read consecutive addresses on GPUs and vector lanes on CPUs).
template <class T, class MS = MemSpace>
using Field = Kokkos::View<T*, MS>;

/// \brief Read-only alias for gathers through neighbour indices (texture/L1 path on GPUs).
template <class T, class MS = MemSpace>
using ConstGather = Kokkos::View<const T*, MS, Kokkos::MemoryTraits<Kokkos::RandomAccess>>;

}  // namespace nacre
