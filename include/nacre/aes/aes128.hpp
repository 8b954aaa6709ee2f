// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief nacre's AES-128 encryption: bitsliced, table-free and constant time, as Kokkos kernels.
///
/// ECB over any buffer whose length is a multiple of 16 bytes. The cipher is the full
/// bitslicing described in aes/bitsliced.hpp (Boyar–Peralta S-box circuit, ShiftRows by
/// renaming, MixColumns by XORs, round keys as masks in team scratch memory); the Kokkos kernel
/// (aes/bitsliced_kernel.hpp) stages loads and stores through team scratch so that global memory
/// is read and written contiguously. No branch and no memory address depends on the key or the
/// data, key expansion included (checked under valgrind by tests/aes/ct_check.cpp).
#include <nacre/aes/bitsliced.hpp>
#include <nacre/core/backend.hpp>
#include <nacre/core/types.hpp>

#include <cstdint>
#include <string>

namespace nacre::aes {

/// \brief Encrypt `in` into `out` with AES-128-ECB under `key`, on execution space instance
/// `space` (asynchronous like any Kokkos kernel: fence before reading `out` on the host).
///
/// \throws std::invalid_argument when in.extent(0) is not a multiple of 16, when out has a
/// different length, or when in and out overlap without being the same buffer (in-place
/// encryption, out.data() == in.data(), is allowed). Any alignment of the views is accepted.
template <class ExecSpace>
void aes128_ecb_encrypt(const ExecSpace& space, const Key128& key,
                        Kokkos::View<const std::uint8_t*, typename ExecSpace::memory_space> in,
                        Kokkos::View<std::uint8_t*, typename ExecSpace::memory_space> out);

/// \brief aes128_ecb_encrypt on the default execution space instance.
void aes128_ecb_encrypt(const Key128& key, Kokkos::View<const std::uint8_t*, MemSpace> in,
                        Kokkos::View<std::uint8_t*, MemSpace> out);

/// \brief aes128_ecb_encrypt on a backend chosen at run time that reaches the default memory space
/// (core/backend.hpp; std::logic_error on one that does not: a host backend of a CUDA build).
void aes128_ecb_encrypt(const Backend& backend, const Key128& key, Kokkos::View<const std::uint8_t*, MemSpace> in,
                        Kokkos::View<std::uint8_t*, MemSpace> out);

/// \brief In-place AES-128-ECB on the default execution space instance.
void aes128_ecb_encrypt(const Key128& key, Kokkos::View<std::uint8_t*, MemSpace> inout);

/// \brief The bitsliced word the kernel uses on ExecSpace and the blocks one thread encrypts at
/// once, e.g. "u64x8 (512-bit vector extension), 512 blocks/thread, team size 1".
template <class ExecSpace = ExecSpace>
[[nodiscard]] std::string aes128_layout_description();

extern template void aes128_ecb_encrypt<ExecSpace>(
    const ExecSpace&, const Key128&, Kokkos::View<const std::uint8_t*, ExecSpace::memory_space>,
    Kokkos::View<std::uint8_t*, ExecSpace::memory_space>);
extern template std::string aes128_layout_description<ExecSpace>();
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
// Device builds also provide the host execution space (tests compare the two).
extern template void aes128_ecb_encrypt<Kokkos::DefaultHostExecutionSpace>(
    const Kokkos::DefaultHostExecutionSpace&, const Key128&,
    Kokkos::View<const std::uint8_t*, Kokkos::HostSpace>, Kokkos::View<std::uint8_t*, Kokkos::HostSpace>);
extern template std::string aes128_layout_description<Kokkos::DefaultHostExecutionSpace>();
#endif

}  // namespace nacre::aes
