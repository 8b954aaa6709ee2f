// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Philox4x32-10 counter-based generator (Salmon et al., SC'11), device-callable.
///
/// Written out here (40 lines) instead of depending on Random123 in the library, so nacre
/// builds wherever Kokkos does; the tests check it bit-for-bit against Random123.
#include <Kokkos_Core.hpp>
#include <cstdint>

namespace nacre::rng {

/// \brief 128 random bits: the unit every nacre generator produces per (stream, counter).
struct Block128 {
  std::uint32_t w[4];
};

namespace detail {
KOKKOS_INLINE_FUNCTION void mulhilo32(std::uint32_t a, std::uint32_t b, std::uint32_t& hi,
                                      std::uint32_t& lo) {
  const std::uint64_t p = static_cast<std::uint64_t>(a) * b;
  hi = static_cast<std::uint32_t>(p >> 32);
  lo = static_cast<std::uint32_t>(p);
}

inline constexpr std::uint32_t kPhiloxW0 = 0x9E3779B9u, kPhiloxW1 = 0xBB67AE85u;  ///< key schedule
/// \brief One Philox4x32 round of ctr under the round key (k0, k1).
KOKKOS_INLINE_FUNCTION void philox_round(Block128& ctr, std::uint32_t k0, std::uint32_t k1) {
  constexpr std::uint32_t M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;
  std::uint32_t hi0, lo0, hi1, lo1;
  mulhilo32(M0, ctr.w[0], hi0, lo0);
  mulhilo32(M1, ctr.w[2], hi1, lo1);
  const Block128 next{{hi1 ^ ctr.w[1] ^ k0, lo1, hi0 ^ ctr.w[3] ^ k1, lo0}};
  ctr = next;
}
}  // namespace detail

/// \brief Philox4x32 with 10 rounds: ctr -> 128-bit block under a 64-bit key.
KOKKOS_INLINE_FUNCTION Block128 philox4x32_10(Block128 ctr, std::uint32_t k0, std::uint32_t k1) {
  for (int r = 0; r < 10; ++r) {
    detail::philox_round(ctr, k0, k1);
    k0 += detail::kPhiloxW0;
    k1 += detail::kPhiloxW1;
  }
  return ctr;
}

/// \brief Two blocks under one key, their rounds interleaved (philox4x32_10 of each, the same
/// bits): the key schedule is computed once, and the two independent chains of multiplies overlap.
KOKKOS_INLINE_FUNCTION void philox4x32_10_pair(Block128& a, Block128& b, std::uint32_t k0, std::uint32_t k1) {
  for (int r = 0; r < 10; ++r) {
    detail::philox_round(a, k0, k1);
    detail::philox_round(b, k0, k1);
    k0 += detail::kPhiloxW0;
    k1 += detail::kPhiloxW1;
  }
}

}  // namespace nacre::rng
