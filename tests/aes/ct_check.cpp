// SPDX-License-Identifier: BSD-3-Clause
// Constant-time check of nacre's bitsliced AES under valgrind memcheck.
//
//   valgrind --error-exitcode=1 nacre_aes_ct_check nacre   -> must report nothing (exit 0)
//   valgrind --error-exitcode=1 nacre_aes_ct_check table   -> must report errors (exit 1)
//
// Memcheck tracks, bit by bit, which values derive from memory marked undefined and reports a
// conditional jump, or a memory address, computed from such a value ("Conditional jump or move
// depends on uninitialised value(s)", "Use of uninitialised value of size 8"). Marking the key
// and the plaintext undefined therefore turns memcheck into a detector of secret-dependent
// branches and secret-dependent memory addresses (Adam Langley's ctgrind technique). The
// program runs the exact functions of the Kokkos kernels (aes/bitsliced.hpp: key expansion,
// round-key masks, transposition, rounds) for the build's host word and for the GPU's 32-bit
// word, then a textbook byte-oriented AES whose S-box is a table look-up, which memcheck must
// catch. Without valgrind the program only checks the FIPS-197 vectors.
//
// Built without -march flags (valgrind does not decode AVX-512) and without nacre_lib.
#include <nacre/aes/bitsliced.hpp>

#include <valgrind/memcheck.h>

#include <cstdio>
#include <cstring>
#include <string_view>
#include <vector>

namespace {

using namespace nacre::aes;

const std::uint8_t kKeyC1[16] = {0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07,
                                 0x08, 0x09, 0x0a, 0x0b, 0x0c, 0x0d, 0x0e, 0x0f};
const std::uint8_t kPtC1[16] = {0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77,
                                0x88, 0x99, 0xaa, 0xbb, 0xcc, 0xdd, 0xee, 0xff};
const std::uint8_t kCtC1[16] = {0x69, 0xc4, 0xe0, 0xd8, 0x6a, 0x7b, 0x04, 0x30,
                                0xd8, 0xcd, 0xb7, 0x80, 0x70, 0xb4, 0xc5, 0x5a};

/// nacre's path: key expansion, masks, bitsliced encryption of kBlocks<W> blocks in place.
template <class W>
void nacre_encrypt(const std::uint8_t* key, std::uint8_t* data) {
  using L = typename bitslice::WordTraits<W>::lane;
  Key128 k;
  std::memcpy(k.bytes, key, 16);
  const RoundKeys rk = expand_key(k);
  std::vector<L> masks(bitslice::kMaskCount);
  bitslice::round_key_masks<L>(rk, masks.data());
  std::vector<L> lanes(16 * bitslice::kBlocks<W> / sizeof(L));
  std::memcpy(lanes.data(), data, 16 * bitslice::kBlocks<W>);
  bitslice::encrypt_blocks<W>(masks.data(), lanes.data());
  std::memcpy(data, lanes.data(), 16 * bitslice::kBlocks<W>);
}

// ---- The deliberately leaky variant: textbook AES with an S-box table (FIPS-197 §5.1.1).
std::uint8_t g_sbox[256];

void table_encrypt(const std::uint8_t* key, std::uint8_t* blk) {
  std::uint8_t rk[176];
  std::memcpy(rk, key, 16);
  std::uint8_t rcon = 1;
  for (int i = 16; i < 176; i += 4) {
    std::uint8_t t[4] = {rk[i - 4], rk[i - 3], rk[i - 2], rk[i - 1]};
    if (i % 16 == 0) {
      const std::uint8_t t0 = t[0];
      t[0] = std::uint8_t(g_sbox[t[1]] ^ rcon);  // secret-dependent address
      t[1] = g_sbox[t[2]];
      t[2] = g_sbox[t[3]];
      t[3] = g_sbox[t0];
      rcon = std::uint8_t((rcon << 1) ^ ((rcon >> 7) * 0x1b));
    }
    for (int j = 0; j < 4; ++j) rk[i + j] = std::uint8_t(rk[i - 16 + j] ^ t[j]);
  }
  auto xt = [](std::uint8_t a) { return std::uint8_t((a << 1) ^ ((a >> 7) * 0x1b)); };
  std::uint8_t s[16];
  for (int i = 0; i < 16; ++i) s[i] = blk[i] ^ rk[i];
  for (int r = 1; r <= 10; ++r) {
    std::uint8_t u[16];
    for (int c = 0; c < 4; ++c)
      for (int row = 0; row < 4; ++row) u[row + 4 * c] = g_sbox[s[row + 4 * ((c + row) & 3)]];
    if (r < 10) {
      for (int c = 0; c < 4; ++c) {
        const std::uint8_t* a = u + 4 * c;
        const std::uint8_t t = a[0] ^ a[1] ^ a[2] ^ a[3];
        std::uint8_t b[4];
        for (int row = 0; row < 4; ++row)
          b[row] = std::uint8_t(a[row] ^ t ^ xt(std::uint8_t(a[row] ^ a[(row + 1) & 3])));
        std::memcpy(u + 4 * c, b, 4);
      }
    }
    for (int i = 0; i < 16; ++i) s[i] = u[i] ^ rk[16 * r + i];
  }
  std::memcpy(blk, s, 16);
}

/// True when every bit of buf is undefined for memcheck (the secret really flowed through).
bool all_undefined(const std::uint8_t* buf, std::size_t n) {
  if (!RUNNING_ON_VALGRIND) return true;
  std::vector<std::uint8_t> vbits(n);
  if (VALGRIND_GET_VBITS(buf, vbits.data(), n) != 1) return false;
  for (const std::uint8_t v : vbits)
    if (v != 0xFF) return false;
  return true;
}

template <class W>
int run_nacre(const char* word) {
  constexpr std::size_t n = 16 * bitslice::kBlocks<W>;
  // 1. Correctness with defined data: FIPS-197 C.1 in every block.
  std::vector<std::uint8_t> data(n);
  for (std::size_t b = 0; b < n / 16; ++b) std::memcpy(data.data() + 16 * b, kPtC1, 16);
  nacre_encrypt<W>(kKeyC1, data.data());
  for (std::size_t b = 0; b < n / 16; ++b)
    if (std::memcmp(data.data() + 16 * b, kCtC1, 16) != 0) {
      std::printf("FAIL: %s word: wrong ciphertext in block %zu\n", word, b);
      return 2;
    }
  // 2. The same with key and plaintext marked undefined: memcheck must stay silent.
  std::uint8_t key[16];
  std::memcpy(key, kKeyC1, 16);
  VALGRIND_MAKE_MEM_UNDEFINED(key, sizeof key);
  VALGRIND_MAKE_MEM_UNDEFINED(data.data(), n);
  nacre_encrypt<W>(key, data.data());
  if (!all_undefined(data.data(), n)) {
    std::printf("FAIL: %s word: the ciphertext is not tainted by the secret inputs\n", word);
    return 3;
  }
  std::printf("nacre AES, %s word (%d blocks): ran on secret key and data\n", word,
              bitslice::kBlocks<W>);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view mode = argc > 1 ? argv[1] : "nacre";
  std::printf("running under valgrind: %s\n", RUNNING_ON_VALGRIND ? "yes" : "no");
  if (mode == "nacre") {
    if (const int rc = run_nacre<bitslice::HostWord>(bitslice::WordTraits<bitslice::HostWord>::name))
      return rc;
    if (const int rc = run_nacre<std::uint32_t>("uint32 (GPU)")) return rc;
    return 0;
  }
  if (mode == "table") {
    for (int x = 0; x < 256; ++x) g_sbox[x] = bitslice::sbox_byte(std::uint8_t(x));
    std::uint8_t blk[16];
    std::memcpy(blk, kPtC1, 16);
    table_encrypt(kKeyC1, blk);
    if (std::memcmp(blk, kCtC1, 16) != 0) {
      std::printf("FAIL: table AES is wrong\n");
      return 2;
    }
    std::uint8_t key[16];
    std::memcpy(key, kKeyC1, 16);
    VALGRIND_MAKE_MEM_UNDEFINED(key, sizeof key);
    VALGRIND_MAKE_MEM_UNDEFINED(blk, sizeof blk);
    table_encrypt(key, blk);
    std::printf("table AES ran on secret key and data (memcheck should have reported it)\n");
    return 0;
  }
  std::printf("usage: %s nacre|table\n", argv[0]);
  return 2;
}
