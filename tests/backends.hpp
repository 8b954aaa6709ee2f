// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The host backends of the installed Kokkos, as a type list for Catch2's
// TEMPLATE_LIST_TEST_CASE (Cabana style): a test written once runs on Kokkos::Serial and on
// Kokkos::OpenMP where the installed Kokkos enables them (Debian's 5.2 has OpenMP only; a
// Serial+OpenMP build, e.g. Kokkos 4.6, runs both).
#include <nacre/core/backend.hpp>

#include <Kokkos_Core.hpp>

#include <string>
#include <tuple>
#include <variant>

namespace nacre::test {

#ifdef KOKKOS_ENABLE_SERIAL
using SerialBackend = std::tuple<Kokkos::Serial>;
#else
using SerialBackend = std::tuple<>;
#endif
#ifdef KOKKOS_ENABLE_OPENMP
using OpenMPBackend = std::tuple<Kokkos::OpenMP>;
#else
using OpenMPBackend = std::tuple<>;
#endif

/// \brief Enabled host execution spaces.
using HostBackends = decltype(std::tuple_cat(std::declval<SerialBackend>(), std::declval<OpenMPBackend>()));

/// \brief The backends a run can choose (nacre::Backend), default first: the host backends in a
/// host build, the device and the host backends in a CUDA build. A solver keeps its model in the
/// chosen backend's memory; the solvers' and the generators' tests use this list.
template <class V>
struct TupleOf;
template <class... T>
struct TupleOf<std::variant<T...>> {
  using type = std::tuple<T...>;
};
using RunBackends = typename TupleOf<nacre::AnySpace>::type;

/// \brief Names of the enabled host backends, for the log of a test run.
inline std::string host_backend_names() {
  std::string s;
#ifdef KOKKOS_ENABLE_SERIAL
  s += "Serial ";
#endif
#ifdef KOKKOS_ENABLE_OPENMP
  s += "OpenMP ";
#endif
  return s;
}

}  // namespace nacre::test
