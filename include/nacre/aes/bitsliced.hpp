// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The per-thread core of nacre's bitsliced, constant-time AES-128 (FIPS-197).
///
/// Everything here is a KOKKOS_INLINE_FUNCTION working on plain arrays, so one source serves the
/// Kokkos kernels (aes/bitsliced_kernel.hpp), the host and the valgrind constant-time check
/// (tests/aes/ct_check.cpp), which calls these functions directly.
///
/// Layout ("full" bitslicing). A bitsliced word W holds one bit of many blocks: the state of
/// kBlocks<W> blocks is 128 words, word k = 8*byte + bit holding bit `bit` (LSB = 0) of state
/// byte `byte` (FIPS-197 order: byte = row + 4*column) of every block, one block per bit of W.
/// Consequences:
///   * SubBytes is the Boyar–Peralta Boolean circuit (115 gates: 32 AND, 79 XOR, 4 XNOR) applied
///     to the 8 words of each byte position, 16 times per round;
///   * ShiftRows is a renaming of words (no instruction at all);
///   * MixColumns is XORs only (xtime of a bitsliced byte is a renaming plus 3 XORs);
///   * AddRoundKey XORs each word with an all-ones or all-zero mask (one per round-key bit).
/// There are no table look-ups, no branches and no addresses that depend on the key or the data;
/// every loop bound and index is a compile-time constant. The price is the transposition of the
/// blocks into and out of bitsliced form (a log-depth SWAPMOVE network, also constant time).
///
/// Word choice (compile-time, see HostWord and ExecWord in bitsliced_kernel.hpp):
///   * CPU: a GCC/Clang vector-extension word as wide as the widest SIMD register the build
///     targets (512 bits with AVX-512: 512 blocks per thread; 256 with AVX2; 128 otherwise). The
///     128-word state then lives in L1 (16 KiB with the round buffer), every gate of the circuit
///     is one SIMD instruction over 512 blocks, and GCC fuses XOR/AND chains into vpternlogq.
///     Kasper–Schwabe's byte-sliced layout (8 blocks per 8 x 128-bit registers) needs pshufb for
///     ShiftRows and rotations for MixColumns, which do not widen portably; full bitslicing
///     needs only AND/XOR/NOT/shift, so it widens to any vector length without changes.
///   * GPU: 32-bit words (32 blocks per thread, 128 registers of state): GPU registers are 32-bit,
///     so the dissertation's 8 x 64-bit words cost every gate twice (its "117 x 2"); with 32
///     blocks per thread each gate is one 32-bit LOP3-able instruction and ShiftRows needs no
///     prmt byte permutes at all. (CUDA/HIP/SYCL device code never sees vector extensions.)
#include <Kokkos_Core.hpp>

#include <cstdint>
#include <type_traits>

// Device compilers (and their host passes) get plain integer words only.
#if defined(__CUDACC__) || defined(__HIPCC__) || defined(__SYCL_DEVICE_ONLY__) || \
    defined(KOKKOS_ENABLE_SYCL) || defined(KOKKOS_ENABLE_OPENMPTARGET)
#ifndef NACRE_AES_NO_VECTOR_EXT
#define NACRE_AES_NO_VECTOR_EXT 1
#endif
#endif
#if !defined(NACRE_AES_NO_VECTOR_EXT) && (defined(__GNUC__) || defined(__clang__))
#define NACRE_AES_HAVE_VECTOR_EXT 1
#endif

// x86 fast path of the transposition for the 512-bit word (aes/transpose_gfni.hpp): only with
// AVX-512 F/BW/VBMI + GFNI, never for a device compiler or its host pass. NACRE_AES_NO_GFNI=1
// forces the portable SWAPMOVE network (used by the tests to compare both).
#if defined(NACRE_AES_HAVE_VECTOR_EXT) && defined(__x86_64__) && defined(__AVX512F__) && \
    defined(__AVX512BW__) && defined(__AVX512VBMI__) && defined(__GFNI__) &&            \
    !defined(NACRE_AES_NO_GFNI) && !defined(__CUDACC__) && !defined(__HIPCC__)
#define NACRE_AES_GFNI_TRANSPOSE 1
#endif

// "unroll" for the device passes (and clang); "GCC unroll" for g++. nvcc's host pass is neither:
// its front end rejects "GCC unroll" (#1675-D) and g++ after it would not know "unroll", so the
// host side of a CUDA build (the Serial/OpenMP fallback, not the fast path) gets no pragma.
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__) || defined(__clang__)
#define NACRE_AES_UNROLL _Pragma("unroll")
#elif defined(__GNUC__) && !defined(__CUDACC__)
#define NACRE_AES_UNROLL _Pragma("GCC unroll 128")
#else
#define NACRE_AES_UNROLL
#endif

#ifdef NACRE_AES_GFNI_TRANSPOSE
#include <nacre/aes/transpose_gfni.hpp>
#endif

namespace nacre::aes {

/// \brief An AES-128 key (16 bytes, FIPS-197 byte order).
struct Key128 {
  std::uint8_t bytes[16];
};

/// \brief The 11 expanded round keys (FIPS-197 §5.2), round r in bytes[r].
struct RoundKeys {
  std::uint8_t bytes[11][16];
};

namespace bitslice {

// ---------------------------------------------------------------------------------------------
// Words
// ---------------------------------------------------------------------------------------------

#ifdef NACRE_AES_HAVE_VECTOR_EXT
typedef std::uint64_t u64x2 __attribute__((vector_size(16)));
typedef std::uint64_t u64x4 __attribute__((vector_size(32)));
typedef std::uint64_t u64x8 __attribute__((vector_size(64)));
#endif

/// \brief lane: the integer type one block-row of the transposition is made of; lanes: how many
/// of them a word holds. A word holds lanes * lane_bits blocks; block j*lanes + l sits in bit j of
/// lane l (so the `lanes` blocks of one transposition row are adjacent in memory).
template <class W>
struct WordTraits;

template <>
struct WordTraits<std::uint32_t> {
  using lane = std::uint32_t;
  static constexpr int lanes = 1;
  static constexpr int lane_bits = 32;
  static constexpr const char* name = "uint32";
  KOKKOS_INLINE_FUNCTION static lane get(const std::uint32_t& w, int) { return w; }
  KOKKOS_INLINE_FUNCTION static void set(std::uint32_t& w, int, lane v) { w = v; }
};

template <>
struct WordTraits<std::uint64_t> {
  using lane = std::uint64_t;
  static constexpr int lanes = 1;
  static constexpr int lane_bits = 64;
  static constexpr const char* name = "uint64";
  KOKKOS_INLINE_FUNCTION static lane get(const std::uint64_t& w, int) { return w; }
  KOKKOS_INLINE_FUNCTION static void set(std::uint64_t& w, int, lane v) { w = v; }
};

#ifdef NACRE_AES_HAVE_VECTOR_EXT
template <>
struct WordTraits<u64x2> {
  using lane = std::uint64_t;
  static constexpr int lanes = 2;
  static constexpr int lane_bits = 64;
  static constexpr const char* name = "u64x2 (128-bit vector extension)";
  static lane get(const u64x2& w, int l) { return w[l]; }
  static void set(u64x2& w, int l, lane v) { w[l] = v; }
  /// Rows of both halves of 2 consecutive blocks: even = low 64 bits, odd = high 64 bits.
  static void deinterleave(const unsigned char* src, u64x2& even, u64x2& odd) {
    u64x2 v0, v1;
    __builtin_memcpy(&v0, src, sizeof v0);
    __builtin_memcpy(&v1, src + 16, sizeof v1);
    even = __builtin_shufflevector(v0, v1, 0, 2);
    odd = __builtin_shufflevector(v0, v1, 1, 3);
  }
  static void interleave(const u64x2& even, const u64x2& odd, unsigned char* dst) {
    const u64x2 v0 = __builtin_shufflevector(even, odd, 0, 2);
    const u64x2 v1 = __builtin_shufflevector(even, odd, 1, 3);
    __builtin_memcpy(dst, &v0, sizeof v0);
    __builtin_memcpy(dst + 16, &v1, sizeof v1);
  }
};
template <>
struct WordTraits<u64x4> {
  using lane = std::uint64_t;
  static constexpr int lanes = 4;
  static constexpr int lane_bits = 64;
  static constexpr const char* name = "u64x4 (256-bit vector extension)";
  static lane get(const u64x4& w, int l) { return w[l]; }
  static void set(u64x4& w, int l, lane v) { w[l] = v; }
  /// Rows of both halves of 4 consecutive blocks: even = low 64 bits, odd = high 64 bits.
  static void deinterleave(const unsigned char* src, u64x4& even, u64x4& odd) {
    u64x4 v0, v1;
    __builtin_memcpy(&v0, src, sizeof v0);
    __builtin_memcpy(&v1, src + 32, sizeof v1);
    even = __builtin_shufflevector(v0, v1, 0, 2, 4, 6);
    odd = __builtin_shufflevector(v0, v1, 1, 3, 5, 7);
  }
  static void interleave(const u64x4& even, const u64x4& odd, unsigned char* dst) {
    const u64x4 v0 = __builtin_shufflevector(even, odd, 0, 4, 1, 5);
    const u64x4 v1 = __builtin_shufflevector(even, odd, 2, 6, 3, 7);
    __builtin_memcpy(dst, &v0, sizeof v0);
    __builtin_memcpy(dst + 32, &v1, sizeof v1);
  }
};
template <>
struct WordTraits<u64x8> {
  using lane = std::uint64_t;
  static constexpr int lanes = 8;
  static constexpr int lane_bits = 64;
  static constexpr const char* name = "u64x8 (512-bit vector extension)";
  static lane get(const u64x8& w, int l) { return w[l]; }
  static void set(u64x8& w, int l, lane v) { w[l] = v; }
  /// Rows of both halves of 8 consecutive blocks: even = low 64 bits, odd = high 64 bits.
  static void deinterleave(const unsigned char* src, u64x8& even, u64x8& odd) {
    u64x8 v0, v1;
    __builtin_memcpy(&v0, src, sizeof v0);
    __builtin_memcpy(&v1, src + 64, sizeof v1);
    even = __builtin_shufflevector(v0, v1, 0, 2, 4, 6, 8, 10, 12, 14);
    odd = __builtin_shufflevector(v0, v1, 1, 3, 5, 7, 9, 11, 13, 15);
  }
  static void interleave(const u64x8& even, const u64x8& odd, unsigned char* dst) {
    const u64x8 v0 = __builtin_shufflevector(even, odd, 0, 8, 1, 9, 2, 10, 3, 11);
    const u64x8 v1 = __builtin_shufflevector(even, odd, 4, 12, 5, 13, 6, 14, 7, 15);
    __builtin_memcpy(dst, &v0, sizeof v0);
    __builtin_memcpy(dst + 64, &v1, sizeof v1);
  }
};
#endif

/// \brief Blocks processed by one thread holding one bitsliced state of words W.
template <class W>
inline constexpr int kBlocks = WordTraits<W>::lanes * WordTraits<W>::lane_bits;
/// \brief Lanes per 16-byte block.
template <class W>
inline constexpr int kLanesPerBlock = 128 / WordTraits<W>::lane_bits;
/// \brief Round-key masks: one lane-wide all-ones/all-zero mask per bit of the 11 round keys.
inline constexpr int kMaskCount = 11 * 128;

/// \brief The host word for this build: as wide as the widest SIMD register targeted (see above;
/// override with -DNACRE_AES_HOST_WORD_BITS=64/128/256/512).
#if defined(NACRE_AES_HAVE_VECTOR_EXT)
#if defined(NACRE_AES_HOST_WORD_BITS)
#if NACRE_AES_HOST_WORD_BITS == 512
using HostWord = u64x8;
#elif NACRE_AES_HOST_WORD_BITS == 256
using HostWord = u64x4;
#elif NACRE_AES_HOST_WORD_BITS == 128
using HostWord = u64x2;
#else
using HostWord = std::uint64_t;
#endif
#elif defined(__AVX512F__)
using HostWord = u64x8;
#elif defined(__AVX__)
using HostWord = u64x4;
#else
using HostWord = u64x2;
#endif
#else
using HostWord = std::uint64_t;
#endif

// ---------------------------------------------------------------------------------------------
// SubBytes: Boyar–Peralta circuit
// ---------------------------------------------------------------------------------------------

/// \brief The AES S-box on 8 bitsliced words, q[0] = least significant bit ... q[7] = most.
///
/// Circuit: J. Boyar and R. Peralta, "A new combinational logic minimization technique with
/// applications to cryptology", SEA 2010 / IACR ePrint 2009/191: 115 gates (32 AND, 79 XOR,
/// 4 XNOR) in three layers: a linear top layer (23 XOR), the shared non-linear core (32 AND,
/// 30 XOR) and a linear bottom layer (26 XOR, 4 XNOR); in the transcription
/// used by BearSSL's constant-time AES (aes_ct.c): there x0 is the most significant input bit and
/// s0 the most significant output bit. Verified exhaustively against the S-box in the tests.
template <class W>
KOKKOS_INLINE_FUNCTION void sbox(W* q) {
  const W x0 = q[7], x1 = q[6], x2 = q[5], x3 = q[4], x4 = q[3], x5 = q[2], x6 = q[1], x7 = q[0];

  // Top linear transformation.
  const W y14 = x3 ^ x5;
  const W y13 = x0 ^ x6;
  const W y9 = x0 ^ x3;
  const W y8 = x0 ^ x5;
  const W t0 = x1 ^ x2;
  const W y1 = t0 ^ x7;
  const W y4 = y1 ^ x3;
  const W y12 = y13 ^ y14;
  const W y2 = y1 ^ x0;
  const W y5 = y1 ^ x6;
  const W y3 = y5 ^ y8;
  const W t1 = x4 ^ y12;
  const W y15 = t1 ^ x5;
  const W y20 = t1 ^ x1;
  const W y6 = y15 ^ x7;
  const W y10 = y15 ^ t0;
  const W y11 = y20 ^ y9;
  const W y7 = x7 ^ y11;
  const W y17 = y10 ^ y11;
  const W y19 = y10 ^ y8;
  const W y16 = t0 ^ y11;
  const W y21 = y13 ^ y16;
  const W y18 = x0 ^ y16;

  // Non-linear section.
  const W t2 = y12 & y15;
  const W t3 = y3 & y6;
  const W t4 = t3 ^ t2;
  const W t5 = y4 & x7;
  const W t6 = t5 ^ t2;
  const W t7 = y13 & y16;
  const W t8 = y5 & y1;
  const W t9 = t8 ^ t7;
  const W t10 = y2 & y7;
  const W t11 = t10 ^ t7;
  const W t12 = y9 & y11;
  const W t13 = y14 & y17;
  const W t14 = t13 ^ t12;
  const W t15 = y8 & y10;
  const W t16 = t15 ^ t12;
  const W t17 = t4 ^ t14;
  const W t18 = t6 ^ t16;
  const W t19 = t9 ^ t14;
  const W t20 = t11 ^ t16;
  const W t21 = t17 ^ y20;
  const W t22 = t18 ^ y19;
  const W t23 = t19 ^ y21;
  const W t24 = t20 ^ y18;

  const W t25 = t21 ^ t22;
  const W t26 = t21 & t23;
  const W t27 = t24 ^ t26;
  const W t28 = t25 & t27;
  const W t29 = t28 ^ t22;
  const W t30 = t23 ^ t24;
  const W t31 = t22 ^ t26;
  const W t32 = t31 & t30;
  const W t33 = t32 ^ t24;
  const W t34 = t23 ^ t33;
  const W t35 = t27 ^ t33;
  const W t36 = t24 & t35;
  const W t37 = t36 ^ t34;
  const W t38 = t27 ^ t36;
  const W t39 = t29 & t38;
  const W t40 = t25 ^ t39;

  const W t41 = t40 ^ t37;
  const W t42 = t29 ^ t33;
  const W t43 = t29 ^ t40;
  const W t44 = t33 ^ t37;
  const W t45 = t42 ^ t41;
  const W z0 = t44 & y15;
  const W z1 = t37 & y6;
  const W z2 = t33 & x7;
  const W z3 = t43 & y16;
  const W z4 = t40 & y1;
  const W z5 = t29 & y7;
  const W z6 = t42 & y11;
  const W z7 = t45 & y17;
  const W z8 = t41 & y10;
  const W z9 = t44 & y12;
  const W z10 = t37 & y3;
  const W z11 = t33 & y4;
  const W z12 = t43 & y13;
  const W z13 = t40 & y5;
  const W z14 = t29 & y2;
  const W z15 = t42 & y9;
  const W z16 = t45 & y14;
  const W z17 = t41 & y8;

  // Bottom linear transformation.
  const W t46 = z15 ^ z16;
  const W t47 = z10 ^ z11;
  const W t48 = z5 ^ z13;
  const W t49 = z9 ^ z10;
  const W t50 = z2 ^ z12;
  const W t51 = z2 ^ z5;
  const W t52 = z7 ^ z8;
  const W t53 = z0 ^ z3;
  const W t54 = z6 ^ z7;
  const W t55 = z16 ^ z17;
  const W t56 = z12 ^ t48;
  const W t57 = t50 ^ t53;
  const W t58 = z4 ^ t46;
  const W t59 = z3 ^ t54;
  const W t60 = t46 ^ t57;
  const W t61 = z14 ^ t57;
  const W t62 = t52 ^ t58;
  const W t63 = t49 ^ t58;
  const W t64 = z4 ^ t59;
  const W t65 = t61 ^ t62;
  const W t66 = z1 ^ t63;
  const W s0 = t59 ^ t63;
  const W s6 = t56 ^ ~t62;
  const W s7 = t48 ^ ~t60;
  const W t67 = t64 ^ t65;
  const W s3 = t53 ^ t66;
  const W s4 = t51 ^ t66;
  const W s5 = t47 ^ t65;
  const W s1 = t64 ^ ~s3;
  const W s2 = t55 ^ ~t67;

  q[7] = s0;
  q[6] = s1;
  q[5] = s2;
  q[4] = s3;
  q[3] = s4;
  q[2] = s5;
  q[1] = s6;
  q[0] = s7;
}

// ---------------------------------------------------------------------------------------------
// Key expansion (constant time: the S-box is the same circuit, on the 4 bytes of a word)
// ---------------------------------------------------------------------------------------------

/// \brief SubWord of FIPS-197 on a little-endian packed word (byte 0 in the low 8 bits): the 4
/// bytes are bitsliced into 8 words of 4 used bits and pushed through the circuit.
KOKKOS_INLINE_FUNCTION std::uint32_t sub_word(std::uint32_t w) {
  std::uint32_t q[8];
  NACRE_AES_UNROLL
  for (int i = 0; i < 8; ++i) {
    q[i] = 0;
    NACRE_AES_UNROLL
    for (int b = 0; b < 4; ++b) q[i] |= ((w >> (8 * b + i)) & 1u) << b;
  }
  sbox(q);
  std::uint32_t r = 0;
  NACRE_AES_UNROLL
  for (int i = 0; i < 8; ++i) {
    NACRE_AES_UNROLL
    for (int b = 0; b < 4; ++b) r |= ((q[i] >> b) & 1u) << (8 * b + i);
  }
  return r;
}

/// \brief The S-box of one byte, through the circuit (constant time; for tests and key setup).
KOKKOS_INLINE_FUNCTION std::uint8_t sbox_byte(std::uint8_t x) {
  return static_cast<std::uint8_t>(sub_word(x) & 0xFFu);
}

}  // namespace bitslice

/// \brief FIPS-197 §5.2 key expansion, table-free and branch-free in the key: SubWord is the
/// bitsliced circuit; the round constants are indexed by the public round number only.
KOKKOS_INLINE_FUNCTION RoundKeys expand_key(const Key128& key) {
  std::uint32_t w[44];
  NACRE_AES_UNROLL
  for (int i = 0; i < 4; ++i)
    w[i] = std::uint32_t(key.bytes[4 * i]) | (std::uint32_t(key.bytes[4 * i + 1]) << 8) |
           (std::uint32_t(key.bytes[4 * i + 2]) << 16) | (std::uint32_t(key.bytes[4 * i + 3]) << 24);
  std::uint32_t rcon = 1;
  for (int i = 4; i < 44; ++i) {
    std::uint32_t t = w[i - 1];
    if (i % 4 == 0) {  // public: depends on the loop index only
      t = bitslice::sub_word((t >> 8) | (t << 24)) ^ rcon;
      rcon = ((rcon << 1) ^ (0x11Bu & (0u - (rcon >> 7)))) & 0xFFu;  // xtime, branch-free
    }
    w[i] = w[i - 4] ^ t;
  }
  RoundKeys rk{};
  for (int r = 0; r < 11; ++r)
    for (int c = 0; c < 4; ++c)
      for (int b = 0; b < 4; ++b)
        rk.bytes[r][4 * c + b] = static_cast<std::uint8_t>(w[4 * r + c] >> (8 * b));
  return rk;
}

namespace bitslice {

/// \brief Round-key masks: masks[128*r + 8*byte + bit] is all ones where bit `bit` of byte
/// `byte` of round key r is set, else zero (computed arithmetically, no branch).
template <class Lane>
KOKKOS_INLINE_FUNCTION void round_key_masks(const RoundKeys& rk, Lane* masks) {
  for (int r = 0; r < 11; ++r)
    for (int b = 0; b < 16; ++b)
      NACRE_AES_UNROLL
      for (int i = 0; i < 8; ++i)
        masks[128 * r + 8 * b + i] = Lane(0) - Lane((rk.bytes[r][b] >> i) & 1u);
}

// ---------------------------------------------------------------------------------------------
// Transposition into / out of bitsliced form
// ---------------------------------------------------------------------------------------------

/// \brief Lane mask with bit p set where (p & s) == 0.
template <class Lane>
KOKKOS_INLINE_FUNCTION constexpr Lane swap_mask(int s) {
  Lane m = 0;
  for (int p = 0; p < int(8 * sizeof(Lane)); ++p)
    if ((p & s) == 0) m |= Lane(1) << p;
  return m;
}

/// \brief In-place transpose of the lane_bits x lane_bits bit matrix held in a[0..lane_bits)
/// (independently in each lane): afterwards bit j of a[k] is the old bit k of a[j]. Six (five)
/// SWAPMOVE stages of 32 (16) swaps, each 3 XOR, 1 AND and 2 shifts.
template <class W>
KOKKOS_INLINE_FUNCTION void transpose(W* a) {
  using L = typename WordTraits<W>::lane;
  constexpr int n = WordTraits<W>::lane_bits;
  NACRE_AES_UNROLL
  for (int s = n / 2; s >= 1; s >>= 1) {
    const L m = swap_mask<L>(s);
    NACRE_AES_UNROLL
    for (int k = 0; k < n; ++k) {
      if (k & s) continue;  // public index pattern
      const W t = ((a[k] >> s) ^ a[k + s]) & m;
      a[k + s] ^= t;
      a[k] ^= t << s;
    }
  }
}

/// \brief Bitslice kBlocks<W> blocks (lanes, little-endian, block b = lanes[b*P .. b*P+P)) into
/// the 128-word state st.
template <class W>
KOKKOS_INLINE_FUNCTION void load_state(const typename WordTraits<W>::lane* blocks, W* st) {
  using T = WordTraits<W>;
  constexpr int n = T::lane_bits, P = kLanesPerBlock<W>;
  if constexpr (T::lanes > 1 && P == 2) {
    // SIMD words: the `lanes` blocks of row j are 2*lanes consecutive 64-bit lanes; two vector
    // loads and two shuffles give row j of both halves.
    NACRE_AES_UNROLL
    for (int j = 0; j < n; ++j)
      T::deinterleave(reinterpret_cast<const unsigned char*>(blocks) + 16 * T::lanes * j, st[j],
                      st[n + j]);
    transpose(st);
    transpose(st + n);
  } else {
    NACRE_AES_UNROLL
    for (int p = 0; p < P; ++p) {
      W* rows = st + p * n;
      NACRE_AES_UNROLL
      for (int j = 0; j < n; ++j)
        NACRE_AES_UNROLL
        for (int l = 0; l < T::lanes; ++l) T::set(rows[j], l, blocks[(j * T::lanes + l) * P + p]);
      transpose(rows);
    }
  }
}

/// \brief Inverse of load_state (destroys st).
template <class W>
KOKKOS_INLINE_FUNCTION void store_state(W* st, typename WordTraits<W>::lane* blocks) {
  using T = WordTraits<W>;
  constexpr int n = T::lane_bits, P = kLanesPerBlock<W>;
  if constexpr (T::lanes > 1 && P == 2) {
    transpose(st);
    transpose(st + n);
    NACRE_AES_UNROLL
    for (int j = 0; j < n; ++j)
      T::interleave(st[j], st[n + j], reinterpret_cast<unsigned char*>(blocks) + 16 * T::lanes * j);
  } else {
    NACRE_AES_UNROLL
    for (int p = 0; p < P; ++p) {
      W* rows = st + p * n;
      transpose(rows);
      NACRE_AES_UNROLL
      for (int j = 0; j < n; ++j)
        NACRE_AES_UNROLL
        for (int l = 0; l < T::lanes; ++l) blocks[(j * T::lanes + l) * P + p] = T::get(rows[j], l);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Rounds
// ---------------------------------------------------------------------------------------------

/// \brief out = ShiftRows(in) ^ round key m (the last round).
template <class W>
KOKKOS_INLINE_FUNCTION void shift_add(const W* in, W* out,
                                      const typename WordTraits<W>::lane* m) {
  NACRE_AES_UNROLL
  for (int c = 0; c < 4; ++c)
    NACRE_AES_UNROLL
    for (int r = 0; r < 4; ++r) {
      const W* x = in + 8 * (r + 4 * ((c + r) & 3));
      W* o = out + 8 * (r + 4 * c);
      const typename WordTraits<W>::lane* mk = m + 8 * (r + 4 * c);
      NACRE_AES_UNROLL
      for (int i = 0; i < 8; ++i) o[i] = x[i] ^ mk[i];
    }
}

/// \brief out = SubBytes(in ^ round key m) (the first round's AddRoundKey and S-boxes, one
/// pass: each byte's 8 words are loaded, keyed, substituted and stored once).
template <class W>
KOKKOS_INLINE_FUNCTION void add_sub(const W* in, W* out, const typename WordTraits<W>::lane* m) {
  NACRE_AES_UNROLL
  for (int p = 0; p < 16; ++p) {
    W q[8];
    NACRE_AES_UNROLL
    for (int i = 0; i < 8; ++i) q[i] = in[8 * p + i] ^ m[8 * p + i];
    sbox(q);
    NACRE_AES_UNROLL
    for (int i = 0; i < 8; ++i) out[8 * p + i] = q[i];
  }
}

/// \brief out = SubBytes(MixColumns(ShiftRows(in)) ^ round key m): the linear layer of one
/// round fused with the S-boxes of the next, so the state makes one trip through memory per
/// round (the 128 words do not fit the registers). ShiftRows is folded into the indices: output
/// column c row r reads input byte (r, c + r mod 4). With t = a0^a1^a2^a3 and
/// d = a_r ^ a_{r+1}, MixColumns gives b_r = a_r ^ t ^ xtime(d), xtime(d) = (d7, d0^d7, d1,
/// d2^d7, d3^d7, d4, d5, d6) (bit 0 first; multiplication by x modulo x^8+x^4+x^3+x+1).
template <class W>
KOKKOS_INLINE_FUNCTION void mix_add_sub(const W* in, W* out,
                                        const typename WordTraits<W>::lane* m) {
  NACRE_AES_UNROLL
  for (int c = 0; c < 4; ++c) {
    const W* a[4] = {in + 8 * (0 + 4 * ((c + 0) & 3)), in + 8 * (1 + 4 * ((c + 1) & 3)),
                     in + 8 * (2 + 4 * ((c + 2) & 3)), in + 8 * (3 + 4 * ((c + 3) & 3))};
    W t[8];
    NACRE_AES_UNROLL
    for (int i = 0; i < 8; ++i) t[i] = a[0][i] ^ a[1][i] ^ a[2][i] ^ a[3][i];
    NACRE_AES_UNROLL
    for (int r = 0; r < 4; ++r) {
      const W* x = a[r];
      const W* y = a[(r + 1) & 3];
      const typename WordTraits<W>::lane* mk = m + 8 * (r + 4 * c);
      const W d7 = x[7] ^ y[7];
      W q[8];
      q[0] = x[0] ^ t[0] ^ d7 ^ mk[0];
      q[1] = x[1] ^ t[1] ^ (x[0] ^ y[0]) ^ d7 ^ mk[1];
      q[2] = x[2] ^ t[2] ^ (x[1] ^ y[1]) ^ mk[2];
      q[3] = x[3] ^ t[3] ^ (x[2] ^ y[2]) ^ d7 ^ mk[3];
      q[4] = x[4] ^ t[4] ^ (x[3] ^ y[3]) ^ d7 ^ mk[4];
      q[5] = x[5] ^ t[5] ^ (x[4] ^ y[4]) ^ mk[5];
      q[6] = x[6] ^ t[6] ^ (x[5] ^ y[5]) ^ mk[6];
      q[7] = x[7] ^ t[7] ^ (x[6] ^ y[6]) ^ mk[7];
      sbox(q);
      W* o = out + 8 * (r + 4 * c);
      NACRE_AES_UNROLL
      for (int i = 0; i < 8; ++i) o[i] = q[i];
    }
  }
}

/// \brief AES-128 on a bitsliced state: a (in/out) and b (scratch) are 128 words each; masks
/// are the 11*128 round-key masks (round_key_masks). Eleven passes over the state: S(a ^ k0), nine
/// times S(MixColumns(ShiftRows(.)) ^ k_r), and the final ShiftRows(.) ^ k10.
template <class W>
KOKKOS_INLINE_FUNCTION void encrypt_state(W* a, W* b, const typename WordTraits<W>::lane* masks) {
  add_sub(a, a, masks);  // in place: each byte reads and writes its own 8 words
  for (int r = 1; r < 9; r += 2) {
    mix_add_sub(a, b, masks + 128 * r);
    mix_add_sub(b, a, masks + 128 * (r + 1));
  }
  mix_add_sub(a, b, masks + 128 * 9);
  shift_add(b, a, masks + 128 * 10);
}

/// \brief True where the word has the x86 GFNI transposition (aes/transpose_gfni.hpp).
template <class W>
inline constexpr bool kGfniTranspose =
#ifdef NACRE_AES_GFNI_TRANSPOSE
    std::is_same_v<W, u64x8>;
#else
    false;
#endif

/// \brief True where encrypt_blocks_io can read and write the blocks at any byte address (SIMD
/// host words): the kernel then skips its staging copies.
template <class W>
inline constexpr bool kDirectIO = (WordTraits<W>::lanes > 1);

/// \brief Encrypt kBlocks<W> blocks from in to out (16 * kBlocks<W> bytes each, any alignment,
/// identical or disjoint): SIMD host words only (kDirectIO<W>).
template <class W>
inline void encrypt_blocks_io(const typename WordTraits<W>::lane* masks, const unsigned char* in,
                              unsigned char* out) {
  static_assert(kDirectIO<W>, "encrypt_blocks_io needs a SIMD host word");
  alignas(64) W a[128];
  alignas(64) W b[128];
#ifdef NACRE_AES_GFNI_TRANSPOSE
  if constexpr (kGfniTranspose<W>) {
    // The first round's AddRoundKey + S-boxes run on each byte's 8 words as the transposition's
    // second pass produces them, and the last round's ShiftRows + AddRoundKey as the inverse
    // pass consumes them: no separate trips through memory for either.
    __m512i* ta = reinterpret_cast<__m512i*>(a);
    __m512i* tb = reinterpret_cast<__m512i*>(b);
    const gfni::Indices ix = gfni::indices();
    gfni::load_pass1(in, tb);
    NACRE_AES_UNROLL
    for (int p = 0; p < 16; ++p) {
      __m512i w[8];
      gfni::load_pass2(tb, p, w, ix);
      W q[8];
      NACRE_AES_UNROLL
      for (int i = 0; i < 8; ++i) q[i] = W(w[i]) ^ masks[8 * p + i];
      sbox(q);
      NACRE_AES_UNROLL
      for (int i = 0; i < 8; ++i) a[8 * p + i] = q[i];
    }
    for (int r = 1; r < 9; r += 2) {
      mix_add_sub(a, b, masks + 128 * r);
      mix_add_sub(b, a, masks + 128 * (r + 1));
    }
    mix_add_sub(a, b, masks + 128 * 9);
    const typename WordTraits<W>::lane* m10 = masks + 128 * 10;
    NACRE_AES_UNROLL
    for (int c = 0; c < 4; ++c)
      NACRE_AES_UNROLL
      for (int r = 0; r < 4; ++r) {  // ShiftRows: output (r, c) reads byte (r, c + r mod 4)
        const int p = r + 4 * c;
        const W* x = b + 8 * (r + 4 * ((c + r) & 3));
        __m512i w[8];
        NACRE_AES_UNROLL
        for (int i = 0; i < 8; ++i) w[i] = __m512i(x[i] ^ m10[8 * p + i]);
        gfni::store_pass2(w, p, ta, ix);
      }
    gfni::store_pass1(ta, out);
    return;
  }
#endif
  load_state(reinterpret_cast<const typename WordTraits<W>::lane*>(in), a);
  encrypt_state(a, b, masks);
  store_state(a, reinterpret_cast<typename WordTraits<W>::lane*>(out));
}

/// \brief Encrypt kBlocks<W> blocks in place (lanes little-endian, block b = blocks[b*P ..]).
template <class W>
KOKKOS_INLINE_FUNCTION void encrypt_blocks(const typename WordTraits<W>::lane* masks,
                                           typename WordTraits<W>::lane* blocks) {
  if constexpr (kGfniTranspose<W>) {
    encrypt_blocks_io<W>(masks, reinterpret_cast<const unsigned char*>(blocks),
                         reinterpret_cast<unsigned char*>(blocks));
  } else {
    W a[128], b[128];
    load_state(blocks, a);
    encrypt_state(a, b, masks);
    store_state(a, blocks);
  }
}

}  // namespace bitslice
}  // namespace nacre::aes
