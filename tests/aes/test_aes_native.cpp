// SPDX-License-Identifier: BSD-3-Clause
// nacre's bitsliced AES compiled the way src/aes is (-march=native under NACRE_AES_NATIVE): the
// x86 GFNI transposition (aes/transpose_gfni.hpp) checked as a transposition (every block's bit k
// lands in word k, at one position per block, the positions a bijection) and as the exact
// inverse of its store pass, and the whole cipher on that path, from and to unaligned buffers,
// against OpenSSL and against the portable SWAPMOVE path of the same word. On a machine or build
// without GFNI + AVX-512 the GFNI cases are not compiled and the portable path is checked alone.
#include <nacre/aes/bitsliced.hpp>

#include <catch2/catch_test_macros.hpp>
#include <openssl/evp.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace {

namespace bs = nacre::aes::bitslice;
using W = bs::HostWord;
using L = bs::WordTraits<W>::lane;
constexpr int kB = bs::kBlocks<W>;
using Bytes = std::vector<std::uint8_t>;

// (used only by the GFNI cases: maybe_unused keeps -Werror builds without GFNI quiet)
[[maybe_unused]] Bytes openssl_ecb(const nacre::aes::Key128& key, const std::uint8_t* in,
                                   std::size_t n) {
  Bytes out(n + 16);
  EVP_CIPHER_CTX* ctx = EVP_CIPHER_CTX_new();
  REQUIRE(ctx != nullptr);
  REQUIRE(EVP_EncryptInit_ex(ctx, EVP_aes_128_ecb(), nullptr, key.bytes, nullptr) == 1);
  EVP_CIPHER_CTX_set_padding(ctx, 0);
  int len = 0;
  REQUIRE(EVP_EncryptUpdate(ctx, out.data(), &len, in, int(n)) == 1);
  EVP_CIPHER_CTX_free(ctx);
  out.resize(std::size_t(len));
  return out;
}

/// Bit k (0..127, little-endian byte order: k = 8 * byte + bit) of block b.
int block_bit(const Bytes& blocks, int b, int k) {
  return (blocks[std::size_t(16 * b + k / 8)] >> (k % 8)) & 1;
}

/// Bit `pos` (0 .. kB-1) of a word, positions numbered lane by lane.
int word_bit(const W& w, int pos) {
  constexpr int lb = bs::WordTraits<W>::lane_bits;
  return int((bs::WordTraits<W>::get(w, pos / lb) >> (pos % lb)) & 1);
}

/// Check that load (bytes -> 128 words) is a transposition with one bit position per block and
/// that store inverts it.
template <class Load, class Store>
void check_transposition(Load load, Store store) {
  std::mt19937_64 rng(5);
  // Where does each block go? Only block b all ones: every word must hold exactly one set bit,
  // at the same position for all 128 words.
  std::vector<int> pos(kB, -1), owner(kB, -1);
  for (int b = 0; b < kB; ++b) {
    Bytes in(16 * kB, 0);
    std::memset(in.data() + 16 * b, 0xFF, 16);
    alignas(64) W st[128];
    load(in.data(), st);
    for (int k = 0; k < 128; ++k) {
      int ones = 0, where = -1;
      for (int p = 0; p < kB; ++p)
        if (word_bit(st[k], p)) ++ones, where = p;
      REQUIRE(ones == 1);
      if (k == 0) pos[b] = where;
      REQUIRE(where == pos[b]);
    }
    REQUIRE(owner[pos[b]] == -1);  // a bijection
    owner[pos[b]] = b;
  }
  // Random blocks: word k, position pos[b] = bit k of block b; store inverts load.
  Bytes in(16 * kB);
  for (auto& x : in) x = std::uint8_t(rng());
  alignas(64) W st[128];
  load(in.data(), st);
  for (int b = 0; b < kB; ++b)
    for (int k = 0; k < 128; ++k) REQUIRE(word_bit(st[k], pos[b]) == block_bit(in, b, k));
  Bytes back(16 * kB + 3, 0xA5);
  store(st, back.data() + 3);  // unaligned output
  CHECK(std::memcmp(back.data() + 3, in.data(), in.size()) == 0);
  CHECK(back[0] == 0xA5);
}

}  // namespace

TEST_CASE("Portable transposition of the native word is a transposition and invertible", "[aes]") {
  INFO("word: " << bs::WordTraits<W>::name);
  check_transposition(
      [](const std::uint8_t* in, W* st) {
        std::vector<L> lanes(2 * kB);
        std::memcpy(lanes.data(), in, 16 * kB);
        bs::load_state<W>(lanes.data(), st);
      },
      [](W* st, std::uint8_t* out) {
        std::vector<L> lanes(2 * kB);
        bs::store_state<W>(st, lanes.data());
        std::memcpy(out, lanes.data(), 16 * kB);
      });
}

#ifdef NACRE_AES_GFNI_TRANSPOSE
TEST_CASE("GFNI transposition is a transposition and its store pass the inverse", "[aes]") {
  check_transposition(
      [](const std::uint8_t* in, W* st) {
        alignas(64) W tmp[128];
        bs::gfni::load_state(in + 0, reinterpret_cast<__m512i*>(st),
                             reinterpret_cast<__m512i*>(tmp));
      },
      [](W* st, std::uint8_t* out) {
        alignas(64) W tmp[128];
        bs::gfni::store_state(reinterpret_cast<const __m512i*>(st), out,
                              reinterpret_cast<__m512i*>(tmp));
      });
}

TEST_CASE("GFNI path equals OpenSSL and the portable path, unaligned and in place", "[aes]") {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 8; ++trial) {
    nacre::aes::Key128 key{};
    for (auto& b : key.bytes) b = std::uint8_t(rng());
    std::vector<L> masks(bs::kMaskCount);
    bs::round_key_masks<L>(nacre::aes::expand_key(key), masks.data());
    const int ioff = trial % 5, ooff = (3 * trial) % 7;
    Bytes in(16 * kB + 8), out(16 * kB + 8, 0);
    for (auto& x : in) x = std::uint8_t(rng());
    bs::encrypt_blocks_io<W>(masks.data(), in.data() + ioff, out.data() + ooff);
    const Bytes expect = openssl_ecb(key, in.data() + ioff, 16 * kB);
    REQUIRE(Bytes(out.begin() + ooff, out.begin() + ooff + 16 * kB) == expect);
    // The portable SWAPMOVE path of the same word (the rounds are shared, the transposition not).
    std::vector<L> lanes(2 * kB);
    std::memcpy(lanes.data(), in.data() + ioff, 16 * kB);
    {
      alignas(64) W a[128], b[128];
      bs::load_state<W>(lanes.data(), a);
      bs::encrypt_state<W>(a, b, masks.data());
      bs::store_state<W>(a, lanes.data());
    }
    REQUIRE(std::memcmp(lanes.data(), expect.data(), expect.size()) == 0);
    // In place.
    bs::encrypt_blocks_io<W>(masks.data(), in.data() + ioff, in.data() + ioff);
    REQUIRE(Bytes(in.begin() + ioff, in.begin() + ioff + 16 * kB) == expect);
  }
}
#endif  // without GFNI only the portable case above is compiled (tests.cmake says so)
