// SPDX-License-Identifier: BSD-3-Clause
// The AES random-number sources (aes-ctr, mt-aes): definition, determinism, independence of
// streams and of the batch, thread-count independence, and a statistical smoke test.
#include <nacre/aes/aes128.hpp>
#include <nacre/rng/aes_sources.hpp>
#include <nacre/rng/registry.hpp>

#include <catch2/catch_test_macros.hpp>
#include <openssl/evp.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

// A one-thread instance of the default execution space. partition_space(space, 1, 1) splits the
// space's threads between two instances: Kokkos 4.6 refuses it on a 1-thread space ("Instance has
// no resource allocated to it"; 5.2 accepts it), where the space itself already is one thread.
[[maybe_unused]] static nacre::ExecSpace one_thread_instance() {
  if (nacre::ExecSpace().concurrency() < 2) return nacre::ExecSpace();
  return Kokkos::Experimental::partition_space(nacre::ExecSpace(), 1, 1)[0];
}

namespace {

using HostBits = Kokkos::View<std::uint64_t* [4], Kokkos::LayoutLeft, Kokkos::HostSpace>;
using HostU = Kokkos::View<double* [4], Kokkos::LayoutLeft, Kokkos::HostSpace>;

nacre::rng::StreamIds<> ids_of(const std::vector<std::uint64_t>& v) {
  Kokkos::View<std::uint64_t*, nacre::MemSpace> d("ids", v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (std::size_t i = 0; i < v.size(); ++i) h(i) = v[i];
  Kokkos::deep_copy(d, h);
  return d;
}

std::vector<std::uint64_t> iota_ids(std::size_t n, std::uint64_t first = 0) {
  std::vector<std::uint64_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = first + i;
  return v;
}

HostU fill(nacre::rng::UniformSource& s, std::uint64_t draw, const std::vector<std::uint64_t>& ids) {
  nacre::rng::UniformTable<> u("u", ids.size());
  s.fill(draw, ids_of(ids), u);
  HostU h("h", ids.size());
  Kokkos::deep_copy(h, u);
  return h;
}

template <class Src>
HostBits bits(Src& s, std::uint64_t draw, const std::vector<std::uint64_t>& ids, bool plain = false) {
  nacre::aes::BitsTable<> b("b", ids.size());
  if constexpr (std::is_same_v<Src, nacre::aes::MtAesSource>) {
    if (plain) s.fill_plain_bits(draw, ids_of(ids), b);
    else s.fill_bits(draw, ids_of(ids), b);
  } else {
    s.fill_bits(draw, ids_of(ids), b);
  }
  HostBits h("h", ids.size());
  Kokkos::deep_copy(h, b);
  return h;
}

void openssl_block(const nacre::aes::Key128& key, std::uint64_t lo, std::uint64_t hi,
                   std::uint64_t& clo, std::uint64_t& chi) {
  unsigned char in[16], out[32];
  std::memcpy(in, &lo, 8);
  std::memcpy(in + 8, &hi, 8);
  EVP_CIPHER_CTX* ctx = EVP_CIPHER_CTX_new();
  EVP_EncryptInit_ex(ctx, EVP_aes_128_ecb(), nullptr, key.bytes, nullptr);
  EVP_CIPHER_CTX_set_padding(ctx, 0);
  int len = 0;
  EVP_EncryptUpdate(ctx, out, &len, in, 16);
  EVP_CIPHER_CTX_free(ctx);
  std::memcpy(&clo, out, 8);
  std::memcpy(&chi, out + 8, 8);
}

bool same(const HostU& a, const HostU& b) {
  if (a.extent(0) != b.extent(0)) return false;
  for (std::size_t i = 0; i < a.extent(0); ++i)
    for (int c = 0; c < 4; ++c)
      if (std::memcmp(&a(i, c), &b(i, c), sizeof(double)) != 0) return false;
  return true;
}

}  // namespace

TEST_CASE("aes-ctr block (s, d, h) is AES_k(s || 2d+h) with the documented key", "[rng][aes]") {
  const std::uint64_t seed = 0xC0FFEE;
  nacre::aes::AesCtrSource src(seed);
  const auto key = nacre::aes::aes_ctr_key(seed);
  const std::vector<std::uint64_t> ids = {0, 1, 2, 77, 1ull << 40, ~0ull};
  for (const std::uint64_t d : {0ull, 1ull, 12345ull, (1ull << 62) + 3}) {
    const auto b = bits(src, d, ids);
    const auto u = fill(src, d, ids);
    for (std::size_t i = 0; i < ids.size(); ++i)
      for (int h = 0; h < 2; ++h) {
        std::uint64_t lo, hi;
        openssl_block(key, ids[i], 2 * d + std::uint64_t(h), lo, hi);
        REQUIRE(b(i, 2 * h) == lo);
        REQUIRE(b(i, 2 * h + 1) == hi);
        REQUIRE(u(i, 2 * h) == nacre::rng::to_unit_double(lo));
        REQUIRE(u(i, 2 * h + 1) == nacre::rng::to_unit_double(hi));
      }
  }
}

TEST_CASE("mt-aes: raw MT per stream, whitened by AES-ECB, independent of the batch", "[rng][aes]") {
  const std::uint64_t seed = 42;
  constexpr int M = nacre::aes::MtAesSource::kMtStreams;
  nacre::aes::MtAesSource src(seed);
  const auto key = nacre::aes::mt_aes_key(seed);
  // Streams below M see their MT unmodified; stream s + q*M sees the same MT with q in the high
  // 64 bits.
  const std::vector<std::uint64_t> ids = {0, 5, M - 1, M + 5, 3 * M + 5};
  std::vector<std::mt19937> mts;
  for (const int m : {0, 5, M - 1}) {
    std::seed_seq seq{std::uint32_t(seed), std::uint32_t(seed >> 32), std::uint32_t(m), 0x6d74u};
    mts.emplace_back(seq);
  }
  for (std::uint64_t d = 0; d < 3; ++d) {
    const auto p = bits(src, d, ids, /*plain=*/true);
    const auto c = bits(src, d, ids);
    std::uint64_t w[3][8];
    for (int k = 0; k < 3; ++k)
      for (auto& x : w[k]) x = mts[std::size_t(k)]();
    for (int k = 0; k < 3; ++k)
      for (int q = 0; q < 4; ++q) REQUIRE(p(std::size_t(k), q) == (w[k][2 * q] | (w[k][2 * q + 1] << 32)));
    for (int q = 0; q < 4; ++q) {
      REQUIRE(p(3, q) == (p(1, q) ^ ((q & 1) ? 1u : 0u)));
      REQUIRE(p(4, q) == (p(1, q) ^ ((q & 1) ? 3u : 0u)));
    }
    for (std::size_t i = 0; i < ids.size(); ++i)
      for (int h = 0; h < 2; ++h) {
        std::uint64_t lo, hi;
        openssl_block(key, p(i, 2 * h), p(i, 2 * h + 1), lo, hi);
        REQUIRE(c(i, 2 * h) == lo);
        REQUIRE(c(i, 2 * h + 1) == hi);
      }
  }
}

TEST_CASE("mt-aes: repeated draws, skipped draws, subsets and order of the batch", "[rng][aes]") {
  const std::uint64_t seed = 7;
  const auto all = iota_ids(3000);
  nacre::aes::MtAesSource a(seed), b(seed), c(seed);
  const auto a0 = fill(a, 0, all);
  const auto a1 = fill(a, 1, all);
  CHECK(same(a1, fill(a, 1, all)));  // a repeated draw is answered identically
  const auto a4 = fill(a, 4, all);
  CHECK_THROWS_AS(a.fill(3, ids_of(all), nacre::rng::UniformTable<>("u", all.size())),
                  std::logic_error);
  // Jumping straight to draw 4 gives the same numbers as going through 0, 1.
  CHECK(same(a4, fill(b, 4, all)));
  // A subset in another order (e.g. one colour of bricks) gets the same rows.
  const std::vector<std::uint64_t> sub = {2999, 17, 1024, 0, 2048, 5};
  fill(c, 0, sub);  // same draw answered for different batches
  const auto c0 = fill(c, 0, {5, 17});
  for (int col = 0; col < 4; ++col) {
    CHECK(c0(0, col) == a0(5, col));
    CHECK(c0(1, col) == a0(17, col));
  }
  const auto c1 = fill(c, 1, sub);
  for (std::size_t i = 0; i < sub.size(); ++i)
    for (int col = 0; col < 4; ++col) CHECK(c1(i, col) == a1(std::size_t(sub[i]), col));
}

TEST_CASE("AES sources are deterministic, and differ between streams, draws and seeds", "[rng][aes]") {
  for (const char* kind : {"aes-ctr", "mt-aes"}) {
    INFO(kind);
    const auto ids = iota_ids(2000, 100);
    auto s1 = nacre::rng::make_uniform_source(kind, 1);
    auto s2 = nacre::rng::make_uniform_source(kind, 1);
    auto s3 = nacre::rng::make_uniform_source(kind, 2);
    CHECK(s1->name() == kind);
    const auto u10 = fill(*s1, 10, ids);
    CHECK(same(u10, fill(*s2, 10, ids)));
    CHECK_FALSE(same(u10, fill(*s3, 10, ids)));
    CHECK_FALSE(same(u10, fill(*s1, 11, ids)));
    std::set<double> seen;
    for (std::size_t i = 0; i < ids.size(); ++i)
      for (int col = 0; col < 4; ++col) {
        REQUIRE(u10(i, col) >= 0.0);
        REQUIRE(u10(i, col) < 1.0);
        seen.insert(u10(i, col));
      }
    CHECK(seen.size() == 4 * ids.size());  // no repeats among 8000 53-bit values
  }
}

TEST_CASE("AES sources are bit-identical whatever the thread count", "[rng][aes]") {
  // The test binary is registered with --kokkos-num-threads=1 and =2; each run compares the
  // parallel fill with a serial host reference computed block by block (OpenSSL), so both runs
  // produce the same bits.
  const std::uint64_t seed = 2718;
  const auto ids = iota_ids(4099, 1ull << 33);
  nacre::aes::AesCtrSource src(seed);
  const auto key = nacre::aes::aes_ctr_key(seed);
  const auto b = bits(src, 5, ids);
  for (std::size_t i = 0; i < ids.size(); i += 97)
    for (int h = 0; h < 2; ++h) {
      std::uint64_t lo, hi;
      openssl_block(key, ids[i], 10 + std::uint64_t(h), lo, hi);
      REQUIRE(b(i, 2 * h) == lo);
      REQUIRE(b(i, 2 * h + 1) == hi);
    }
  // And on a one-thread partition of the default execution space vs. the whole space.
  nacre::aes::Key128 k = key;
  const std::size_t n = 16 * 2 * ids.size();
  Kokkos::View<std::uint8_t*, nacre::MemSpace> in("in", n), o1("o1", n), o2("o2", n);
  Kokkos::deep_copy(in, std::uint8_t(3));
  nacre::aes::aes128_ecb_encrypt(nacre::ExecSpace(), k, in, o1);
  const auto part = one_thread_instance();
  nacre::aes::aes128_ecb_encrypt(part, k, in, o2);
  Kokkos::fence();
  part.fence();
  auto h1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), o1);
  auto h2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), o2);
  CHECK(std::memcmp(h1.data(), h2.data(), n) == 0);
}

TEST_CASE("AES sources: uniformity (chi-square) and serial correlation smoke test", "[rng][aes]") {
  for (const char* kind : {"aes-ctr", "mt-aes"}) {
    INFO(kind);
    auto src = nacre::rng::make_uniform_source(kind, 99);
    const std::size_t n = 1 << 14;
    const auto ids = iota_ids(n);
    constexpr int kBins = 64;
    std::vector<double> counts(kBins, 0.0);
    double sxy = 0, sx = 0, sy = 0, sxx = 0, syy = 0;  // lag-1 along draws of one stream
    double cxy = 0;                                      // neighbouring columns
    std::size_t total = 0, pairs = 0;
    HostU prev;
    for (std::uint64_t d = 0; d < 4; ++d) {
      const auto u = fill(*src, d, ids);
      for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c) {
          counts[std::size_t(u(i, c) * kBins)] += 1;
          ++total;
          if (c < 3) cxy += (u(i, c) - 0.5) * (u(i, c + 1) - 0.5);
        }
      if (d > 0)
        for (std::size_t i = 0; i < n; ++i) {
          const double x = prev(i, 0), y = u(i, 0);
          sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
          ++pairs;
        }
      prev = u;
    }
    const double expect = double(total) / kBins;
    double chi2 = 0;
    for (const double c : counts) chi2 += (c - expect) * (c - expect) / expect;
    // 63 degrees of freedom: mean 63, sd 11.2; 130 is beyond p = 1e-6.
    CHECK(chi2 < 130.0);
    CHECK(chi2 > 20.0);
    const double np = double(pairs);
    const double r = (sxy / np - (sx / np) * (sy / np)) /
                     std::sqrt((sxx / np - (sx / np) * (sx / np)) * (syy / np - (sy / np) * (sy / np)));
    // Correlation of independent uniforms: sd 1/sqrt(N); 5 sd.
    CHECK(std::abs(r) < 5.0 / std::sqrt(np));
    const double rc = (cxy / double(4 * n * 3)) * 12.0;  // cov / var(U), var(U) = 1/12
    CHECK(std::abs(rc) < 5.0 / std::sqrt(double(4 * n * 3)));
  }
}
