// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief x86 fast path of the bitslice transposition for the 512-bit word (u64x8): byte
/// exchanges between registers (vpermt2b / vpunpck*qdq) and one GF(2) affine transform
/// (vgf2p8affineqb, GFNI) that transposes the 8 x 8 bit matrix in every 64-bit lane.
///
/// Why: the portable SWAPMOVE network (bitsliced.hpp, transpose) costs 6 stages x 32 swaps x
/// 6 operations per 64 x 64 bit matrix, about 4,600 instructions and 3,000 stores (the 64-word
/// matrix does not fit the 32 registers, so every stage goes through L1) for the two
/// transpositions of 512 blocks: 30 % of the cipher. Here a transposition is 7 exchange stages of
/// 128 shuffles plus 128 GFNI instructions, in two register-blocked passes (256 stores).
///
/// The bit movement, in index bits: a 512-block chunk is 128 registers of 64 bytes; a bit is
/// addressed by (register rho[0..7), byte beta[0..6), bit i[0..3)). Loaded straight from memory,
/// rho = block >> 2, beta = 16 * (block & 3) + byte position p, i = bit. The state word k needs
/// rho = (p, i). Pass 1 (groups of 16 registers): exchange rho_m <-> beta_m for m = 0..3 (the
/// register bit and the byte-index bit trade places: p moves into the register index), then the
/// GFNI transpose swaps the byte-in-qword bits beta_0..2 (now block bits) with the bit index.
/// Pass 2 (groups of 8 registers, one byte position p): exchange rho_{4+m} <-> beta_m for
/// m = 0..2, moving the bit index into the register. Every step is an involution and the GFNI
/// constant is chosen so that the 8 x 8 transform is one too, so store_state runs the same steps
/// in the opposite order. The block <-> bit-position assignment inside a word differs from the
/// portable path; nothing outside load/store depends on it (the rounds work word-wise).
///
/// Constant time: shuffle indices and the GFNI matrix are compile-time constants; no branch or
/// address depends on data. Compiled only with AVX-512 F/BW/VBMI and GFNI and never by a device
/// compiler or its host pass (bitsliced.hpp defines NACRE_AES_GFNI_TRANSPOSE accordingly); the
/// portable path stays compiled and tested (tests/aes/test_aes.cpp runs both against OpenSSL).
// The ISA this file is written for; elsewhere it declares nothing (bitsliced.hpp includes it
// only under the same condition, so it also compiles alone on any target).
#if defined(__x86_64__) && defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512VBMI__) && defined(__GFNI__)
#include <immintrin.h>

#include <cstdint>

namespace nacre::aes::bitslice::gfni {

/// vpermt2b indices that exchange the register bit of a pair (a: 0, b: 1) with byte-index bit m
/// (m = 0..2); output s is the one whose former byte bit m was s. Compile-time constants.
struct IndexTable {
  alignas(64) std::uint8_t v[3][2][64];
};
constexpr IndexTable make_index_table() {
  IndexTable t{};
  for (int m = 0; m < 3; ++m)
    for (int s = 0; s < 2; ++s)
      for (int j = 0; j < 64; ++j) {
        const int src = (j >> m) & 1;  // the output's byte bit m names the source register
        t.v[m][s][j] = std::uint8_t((src << 6) | (j & ~(1 << m)) | (s << m));
      }
  return t;
}
inline constexpr IndexTable kIndexTable = make_index_table();

struct Indices {
  __m512i lo[3], hi[3];
};

inline __attribute__((always_inline)) Indices indices() {
  Indices ix;
  for (int m = 0; m < 3; ++m) {
    ix.lo[m] = _mm512_load_si512(kIndexTable.v[m][0]);
    ix.hi[m] = _mm512_load_si512(kIndexTable.v[m][1]);
  }
  return ix;
}

/// Exchange the register bit (a = 0, b = 1) with byte bit m of every pair, in place.
template <int m>
inline __attribute__((always_inline)) void exchange(__m512i& a, __m512i& b, const Indices& ix) {
  if constexpr (m == 3) {  // byte bit 3 = qword within the 128-bit lane: unpack is exact
    const __m512i x = _mm512_unpacklo_epi64(a, b);
    const __m512i y = _mm512_unpackhi_epi64(a, b);
    a = x;
    b = y;
  } else {
    const __m512i x = _mm512_permutex2var_epi8(a, ix.lo[m], b);
    const __m512i y = _mm512_permutex2var_epi8(a, ix.hi[m], b);
    a = x;
    b = y;
  }
}

/// 8 x 8 bit transpose of every qword, as an involution: result byte j, bit k = source byte
/// 7 - k, bit 7 - j (matrix constant byte j = 1 << (7 - j)).
inline __attribute__((always_inline)) __m512i transpose8(__m512i v) {
  return _mm512_gf2p8affine_epi64_epi8(_mm512_set1_epi64(0x0102040810204080LL), v, 0);
}

/// Exchanges rho_m <-> beta_m, m = 0..3, on 16 registers r[0..16) (rho = register index bits).
inline __attribute__((always_inline)) void pass1_exchanges(__m512i* r, const Indices& ix) {
  for (int j = 0; j < 16; j += 2) exchange<0>(r[j], r[j + 1], ix);
  for (int j = 0; j < 16; ++j)
    if (!(j & 2)) exchange<1>(r[j], r[j + 2], ix);
  for (int j = 0; j < 16; ++j)
    if (!(j & 4)) exchange<2>(r[j], r[j + 4], ix);
  for (int j = 0; j < 8; ++j) exchange<3>(r[j], r[j + 8], ix);
}

/// Exchanges rho_{4+m} <-> beta_m, m = 0..2, on the 8 registers of one byte position.
inline __attribute__((always_inline)) void pass2_exchanges(__m512i* r, const Indices& ix) {
  for (int j = 0; j < 8; j += 2) exchange<0>(r[j], r[j + 1], ix);
  for (int j = 0; j < 8; ++j)
    if (!(j & 2)) exchange<1>(r[j], r[j + 2], ix);
  for (int j = 0; j < 4; ++j) exchange<2>(r[j], r[j + 4], ix);
}

/// Load pass 1: 8192 bytes at in (any alignment) -> tmp[0..128) (64-byte aligned): register
/// 16 g + p then holds byte position p of its blocks, bit index 7 - i in byte bits 0..2.
inline void load_pass1(const void* in, __m512i* tmp) {
  const Indices ix = indices();
  const char* src = static_cast<const char*>(in);
  for (int g = 0; g < 8; ++g) {
    __m512i r[16];
    for (int j = 0; j < 16; ++j) r[j] = _mm512_loadu_si512(src + 64 * (16 * g + j));
    pass1_exchanges(r, ix);
    for (int j = 0; j < 16; ++j) tmp[16 * g + j] = transpose8(r[j]);
  }
}

/// Load pass 2 for byte position p: w[i] = state word 8 p + i (bit i of byte p of every block).
inline __attribute__((always_inline)) void load_pass2(const __m512i* tmp, int p, __m512i* w,
                                                      const Indices& ix) {
  __m512i r[8];
  for (int g = 0; g < 8; ++g) r[g] = tmp[16 * g + p];
  pass2_exchanges(r, ix);
  for (int g = 0; g < 8; ++g) w[7 - g] = r[g];
}

/// Inverse of load_pass2: the 8 words w[i] of byte position p -> tmp.
inline __attribute__((always_inline)) void store_pass2(const __m512i* w, int p, __m512i* tmp,
                                                       const Indices& ix) {
  __m512i r[8];
  for (int g = 0; g < 8; ++g) r[g] = w[7 - g];
  pass2_exchanges(r, ix);  // the three exchanges touch disjoint bits: they commute
  for (int g = 0; g < 8; ++g) tmp[16 * g + p] = r[g];
}

/// Inverse of load_pass1: tmp -> 8192 bytes at out (any alignment).
inline void store_pass1(const __m512i* tmp, void* out) {
  const Indices ix = indices();
  char* dst = static_cast<char*>(out);
  for (int g = 0; g < 8; ++g) {
    __m512i r[16];
    for (int j = 0; j < 16; ++j) r[j] = transpose8(tmp[16 * g + j]);
    pass1_exchanges(r, ix);
    for (int j = 0; j < 16; ++j) _mm512_storeu_si512(dst + 64 * (16 * g + j), r[j]);
  }
}

/// Bitslice 512 blocks (8192 bytes at in, any alignment) into st[0..128) (st[8p + i] = bit i of
/// byte p of every block); tmp: 128 x 64 bytes of scratch, 64-byte aligned.
inline void load_state(const void* in, __m512i* st, __m512i* tmp) {
  load_pass1(in, tmp);
  const Indices ix = indices();
  for (int p = 0; p < 16; ++p) load_pass2(tmp, p, st + 8 * p, ix);
}

/// Inverse of load_state: st to 8192 bytes at out (any alignment).
inline void store_state(const __m512i* st, void* out, __m512i* tmp) {
  const Indices ix = indices();
  for (int p = 0; p < 16; ++p) store_pass2(st + 8 * p, p, tmp, ix);
  store_pass1(tmp, out);
}

}  // namespace nacre::aes::bitslice::gfni

#endif  // AVX-512 F/BW/VBMI + GFNI
