// SPDX-License-Identifier: BSD-3-Clause
// nacre's bitsliced AES-128: FIPS-197 vectors, the S-box circuit, every bitsliced word type, and
// bit-for-bit equality with OpenSSL's AES-128-ECB on random keys, sizes and alignments.
#include <nacre/aes/aes128.hpp>
#include <nacre/aes/bitsliced.hpp>

#include <catch2/catch_test_macros.hpp>
#include <catch2/generators/catch_generators.hpp>
#include <openssl/evp.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// A one-thread instance of the default execution space. partition_space(space, 1, 1) splits the
// space's threads between two instances: Kokkos 4.6 refuses it on a 1-thread space ("Instance has
// no resource allocated to it"; 5.2 accepts it), where the space itself already is one thread.
[[maybe_unused]] static nacre::ExecSpace one_thread_instance() {
  if (nacre::ExecSpace().concurrency() < 2) return nacre::ExecSpace();
  return Kokkos::Experimental::partition_space(nacre::ExecSpace(), 1, 1)[0];
}

namespace {

using nacre::aes::Key128;
using Bytes = std::vector<std::uint8_t>;

Bytes hex(const std::string& s) {
  Bytes b(s.size() / 2);
  for (std::size_t i = 0; i < b.size(); ++i) b[i] = std::uint8_t(std::stoul(s.substr(2 * i, 2), nullptr, 16));
  return b;
}

Key128 key_of(const Bytes& b) {
  Key128 k{};
  std::memcpy(k.bytes, b.data(), 16);
  return k;
}

Bytes openssl_ecb(const Key128& key, const std::uint8_t* in, std::size_t n) {
  Bytes out(n + 16);
  EVP_CIPHER_CTX* ctx = EVP_CIPHER_CTX_new();
  REQUIRE(ctx != nullptr);
  REQUIRE(EVP_EncryptInit_ex(ctx, EVP_aes_128_ecb(), nullptr, key.bytes, nullptr) == 1);
  EVP_CIPHER_CTX_set_padding(ctx, 0);
  int len = 0, fin = 0;
  REQUIRE(EVP_EncryptUpdate(ctx, out.data(), &len, in, int(n)) == 1);
  REQUIRE(EVP_EncryptFinal_ex(ctx, out.data() + len, &fin) == 1);
  EVP_CIPHER_CTX_free(ctx);
  out.resize(std::size_t(len + fin));
  return out;
}

/// Encrypt bytes through the Kokkos ECB kernel (default execution space).
Bytes nacre_ecb(const Key128& key, const Bytes& in) {
  Kokkos::View<std::uint8_t*, nacre::MemSpace> d("in", in.size()), o("out", in.size());
  auto h = Kokkos::create_mirror_view(d);
  std::memcpy(h.data(), in.data(), in.size());
  Kokkos::deep_copy(d, h);
  nacre::aes::aes128_ecb_encrypt(key, d, o);
  Kokkos::deep_copy(h, o);
  return Bytes(h.data(), h.data() + in.size());
}

// GF(2^8) reference S-box: inverse by exponentiation, then the affine map (FIPS-197 §5.1.1).
std::uint8_t gmul(std::uint8_t a, std::uint8_t b) {
  std::uint8_t p = 0;
  for (int i = 0; i < 8; ++i) {
    if (b & 1) p ^= a;
    const bool hi = a & 0x80;
    a = std::uint8_t(a << 1);
    if (hi) a ^= 0x1B;
    b >>= 1;
  }
  return p;
}
std::uint8_t sbox_ref(std::uint8_t x) {
  std::uint8_t inv = 1;
  for (int i = 0; i < 254; ++i) inv = gmul(inv, x);  // x^254 = x^-1 (0 -> 0)
  if (x == 0) inv = 0;
  auto rotl = [](std::uint8_t v, int s) { return std::uint8_t((v << s) | (v >> (8 - s))); };
  return std::uint8_t(inv ^ rotl(inv, 1) ^ rotl(inv, 2) ^ rotl(inv, 3) ^ rotl(inv, 4) ^ 0x63);
}

template <class W>
void check_word_against_openssl(std::mt19937_64& rng) {
  using T = nacre::aes::bitslice::WordTraits<W>;
  using L = typename T::lane;
  constexpr int nb = nacre::aes::bitslice::kBlocks<W>;
  Key128 key{};
  for (auto& b : key.bytes) b = std::uint8_t(rng());
  Bytes pt(16 * nb);
  for (auto& b : pt) b = std::uint8_t(rng());
  std::vector<L> masks(nacre::aes::bitslice::kMaskCount);
  nacre::aes::bitslice::round_key_masks<L>(nacre::aes::expand_key(key), masks.data());
  std::vector<L> lanes(pt.size() / sizeof(L));
  std::memcpy(lanes.data(), pt.data(), pt.size());
  nacre::aes::bitslice::encrypt_blocks<W>(masks.data(), lanes.data());
  Bytes ct(pt.size());
  std::memcpy(ct.data(), lanes.data(), ct.size());
  CHECK(ct == openssl_ecb(key, pt.data(), pt.size()));
}

}  // namespace

TEST_CASE("S-box circuit equals the FIPS-197 S-box on all 256 inputs", "[aes]") {
  for (int x = 0; x < 256; ++x) {
    INFO("x = " << x);
    CHECK(nacre::aes::bitslice::sbox_byte(std::uint8_t(x)) == sbox_ref(std::uint8_t(x)));
  }
}

TEST_CASE("Key expansion matches FIPS-197 Appendix A.1", "[aes]") {
  const auto rk = nacre::aes::expand_key(key_of(hex("2b7e151628aed2a6abf7158809cf4f3c")));
  CHECK(Bytes(rk.bytes[1], rk.bytes[1] + 16) == hex("a0fafe1788542cb123a339392a6c7605"));
  CHECK(Bytes(rk.bytes[10], rk.bytes[10] + 16) == hex("d014f9a8c9ee2589e13f0cc8b6630ca6"));
}

TEST_CASE("Bitsliced transposition is an involution and a transpose", "[aes]") {
  std::mt19937_64 rng(7);
  std::uint64_t a[64], b[64];
  for (auto& x : a) x = rng();
  std::memcpy(b, a, sizeof a);
  nacre::aes::bitslice::transpose(b);
  for (int j = 0; j < 64; ++j)
    for (int k = 0; k < 64; ++k) REQUIRE(((b[k] >> j) & 1) == ((a[j] >> k) & 1));
  nacre::aes::bitslice::transpose(b);
  CHECK(std::memcmp(a, b, sizeof a) == 0);
}

TEST_CASE("FIPS-197 Appendix B and C.1 vectors through the Kokkos kernel", "[aes]") {
  SECTION("Appendix B") {
    const Key128 key = key_of(hex("2b7e151628aed2a6abf7158809cf4f3c"));
    CHECK(nacre_ecb(key, hex("3243f6a8885a308d313198a2e0370734")) ==
          hex("3925841d02dc09fbdc118597196a0b32"));
  }
  SECTION("Appendix C.1") {
    const Key128 key = key_of(hex("000102030405060708090a0b0c0d0e0f"));
    CHECK(nacre_ecb(key, hex("00112233445566778899aabbccddeeff")) ==
          hex("69c4e0d86a7b0430d8cdb78070b4c55a"));
    // The same block many times over (several chunks, a padded tail): all equal to the vector.
    Bytes many;
    for (int i = 0; i < 1500; ++i) {
      const Bytes b = hex("00112233445566778899aabbccddeeff");
      many.insert(many.end(), b.begin(), b.end());
    }
    const Bytes ct = nacre_ecb(key, many);
    for (int i = 0; i < 1500; ++i)
      REQUIRE(Bytes(ct.begin() + 16 * i, ct.begin() + 16 * i + 16) ==
              hex("69c4e0d86a7b0430d8cdb78070b4c55a"));
  }
}

TEST_CASE("Every bitsliced word type (GPU uint32 included) agrees with OpenSSL", "[aes]") {
  std::mt19937_64 rng(11);
  check_word_against_openssl<std::uint32_t>(rng);
  check_word_against_openssl<std::uint64_t>(rng);
#ifdef NACRE_AES_HAVE_VECTOR_EXT
  check_word_against_openssl<nacre::aes::bitslice::u64x2>(rng);
  check_word_against_openssl<nacre::aes::bitslice::u64x4>(rng);
  check_word_against_openssl<nacre::aes::bitslice::u64x8>(rng);
#endif
}

TEST_CASE("ECB kernel equals OpenSSL on random keys, sizes and alignments", "[aes]") {
  INFO("layout: " << nacre::aes::aes128_layout_description());
  std::mt19937_64 rng(2024);
  const std::size_t nblocks_list[] = {0, 1, 2, 3, 31, 255, 511, 512, 513, 1023, 1025, 2047, 4099};
  const std::size_t offsets[] = {0, 1, 3, 7, 8, 13, 16, 21, 32, 47};
  int trial = 0;
  for (const std::size_t nb : nblocks_list) {
    for (int rep = 0; rep < 3; ++rep, ++trial) {
      Key128 key{};
      for (auto& b : key.bytes) b = std::uint8_t(rng());
      const std::size_t n = 16 * nb;
      const std::size_t ioff = offsets[rng() % std::size(offsets)];
      const std::size_t ooff = offsets[rng() % std::size(offsets)];
      INFO("trial " << trial << ": " << nb << " blocks, input offset " << ioff
                    << ", output offset " << ooff);
      Kokkos::View<std::uint8_t*, nacre::MemSpace> bin("bin", n + 64), bout("bout", n + 64);
      auto hin = Kokkos::create_mirror_view(bin);
      for (std::size_t i = 0; i < hin.extent(0); ++i) hin(i) = std::uint8_t(rng());
      Kokkos::deep_copy(bin, hin);
      Kokkos::deep_copy(bout, std::uint8_t(0xA5));
      auto in = Kokkos::subview(bin, std::make_pair(ioff, ioff + n));
      auto out = Kokkos::subview(bout, std::make_pair(ooff, ooff + n));
      nacre::aes::aes128_ecb_encrypt(key, in, out);
      auto hout = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bout);
      const Bytes expect = openssl_ecb(key, hin.data() + ioff, n);
      REQUIRE(Bytes(hout.data() + ooff, hout.data() + ooff + n) == expect);
      // Bytes around the output window are untouched.
      for (std::size_t i = 0; i < ooff; ++i) REQUIRE(hout(i) == 0xA5);
      for (std::size_t i = ooff + n; i < n + 64; ++i) REQUIRE(hout(i) == 0xA5);
      // In place.
      nacre::aes::aes128_ecb_encrypt(key, in, Kokkos::subview(bin, std::make_pair(ioff, ioff + n)));
      auto hin2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bin);
      REQUIRE(Bytes(hin2.data() + ioff, hin2.data() + ioff + n) == expect);
    }
  }
}

TEST_CASE("ECB rejects lengths that are not a multiple of 16 and overlapping buffers", "[aes]") {
  const Key128 key{};
  for (const std::size_t n : {1, 15, 17, 31, 100}) {
    Kokkos::View<std::uint8_t*, nacre::MemSpace> a("a", n), b("b", n);
    CHECK_THROWS_AS(nacre::aes::aes128_ecb_encrypt(key, a, b), std::invalid_argument);
  }
  Kokkos::View<std::uint8_t*, nacre::MemSpace> a("a", 64), b("b", 48);
  CHECK_THROWS_AS(nacre::aes::aes128_ecb_encrypt(key, a, b), std::invalid_argument);
  auto x = Kokkos::subview(a, std::make_pair(0, 48));
  auto y = Kokkos::subview(a, std::make_pair(16, 64));
  CHECK_THROWS_AS(nacre::aes::aes128_ecb_encrypt(key, x, y), std::invalid_argument);
  try {
    Kokkos::View<std::uint8_t*, nacre::MemSpace> c("c", 33);
    nacre::aes::aes128_ecb_encrypt(key, c, c);
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("multiple of the 16-byte AES block") != std::string::npos);
  }
}

TEST_CASE("ECB output is the same on a one-thread instance and on the whole machine", "[aes]") {
  // Kokkos partitions the default (host) execution space into instances with fewer threads; with
  // --kokkos-num-threads=2 this compares a 1-thread run against a 2-thread run in one process.
  std::mt19937_64 rng(99);
  Key128 key{};
  for (auto& b : key.bytes) b = std::uint8_t(rng());
  const std::size_t n = 16 * 5000 + 16 * 7;
  Kokkos::View<std::uint8_t*, nacre::MemSpace> in("in", n), o1("o1", n), o2("o2", n);
  auto h = Kokkos::create_mirror_view(in);
  for (std::size_t i = 0; i < n; ++i) h(i) = std::uint8_t(rng());
  Kokkos::deep_copy(in, h);
  nacre::aes::aes128_ecb_encrypt(nacre::ExecSpace(), key, in, o1);
  const auto part = one_thread_instance();
  INFO("default concurrency " << nacre::ExecSpace().concurrency() << ", partition concurrency "
                              << part.concurrency());
  nacre::aes::aes128_ecb_encrypt(part, key, in, o2);
  part.fence();
  Kokkos::fence();
  auto h1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), o1);
  auto h2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), o2);
  CHECK(std::memcmp(h1.data(), h2.data(), n) == 0);
  CHECK(Bytes(h1.data(), h1.data() + n) == openssl_ecb(key, h.data(), n));
}
