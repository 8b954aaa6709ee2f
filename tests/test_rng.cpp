// SPDX-License-Identifier: BSD-3-Clause
// The generator interface and Philox.
#include <nacre/rng/philox.hpp>
#include <nacre/rng/registry.hpp>

#include <catch2/catch_test_macros.hpp>

#include <cmath>
#include <stdexcept>
#include <vector>

#if __has_include(<Random123/philox.h>)
#include <Random123/philox.h>
#define NACRE_HAVE_R123 1
#endif

using namespace nacre;

TEST_CASE("Philox4x32-10 matches Random123 bit for bit", "[rng]") {
#ifdef NACRE_HAVE_R123
  r123::Philox4x32_R<10> ref;
  for (std::uint32_t k = 0; k < 50; ++k) {
    const r123::Philox4x32_R<10>::ctr_type c = {{k * 2654435761u, k, ~k, 12345u + k}};
    const r123::Philox4x32_R<10>::key_type key = {{0xdeadbeefu ^ k, k * 7u}};
    const auto r = ref(c, key);
    const auto mine = rng::philox4x32_10(rng::Block128{{c.v[0], c.v[1], c.v[2], c.v[3]}}, key.v[0], key.v[1]);
    for (int i = 0; i < 4; ++i) CHECK(mine.w[i] == r.v[i]);
  }
#else
  SKIP("Random123 headers not available");
#endif
  // Random123's published known-answer vector (kat_vectors: philox4x32 10 rounds, all zeros)
  const auto z = rng::philox4x32_10(rng::Block128{{0, 0, 0, 0}}, 0, 0);
  CHECK(z.w[0] == 0x6627e8d5u);
  CHECK(z.w[1] == 0xe169c58du);
  CHECK(z.w[2] == 0xbc57ac4cu);
  CHECK(z.w[3] == 0x9b00dbd8u);
}

TEST_CASE("philox_uniforms are the doubles of the Philox blocks of counters (stream, 2 draw) and (stream, 2 draw + 1)",
          "[rng]") {
  // philox_uniforms runs the two blocks interleaved under one key schedule (philox4x32_10_pair):
  // it must give what two separate philox4x32_10 calls give, bit for bit, high halves included.
  const std::uint64_t seeds[] = {0, 5, 0x5eed1234abcdull, 0xfedcba9876543210ull};
  const std::uint64_t streams[] = {0, 1, 299999, 0x1234567890abull};
  const std::uint64_t draws[] = {0, 1, 77, 0x80000001ull, 0xfffffffffffull};
  for (const auto seed : seeds)
    for (const auto stream : streams)
      for (const auto d : draws) {
        double u[4];
        rng::philox_uniforms(seed, stream, d, u);
        for (int half = 0; half < 2; ++half) {
          const std::uint64_t c = 2 * d + static_cast<std::uint64_t>(half);
          const auto r = rng::philox4x32_10(
              rng::Block128{{static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32),
                             static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(c >> 32)}},
              static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32));
          const double lo = static_cast<double>(((std::uint64_t(r.w[1]) << 32) | r.w[0]) >> 11) * 0x1.0p-53;
          const double hi = static_cast<double>(((std::uint64_t(r.w[3]) << 32) | r.w[2]) >> 11) * 0x1.0p-53;
          CHECK(u[2 * half] == lo);
          CHECK(u[2 * half + 1] == hi);
        }
      }
}

namespace {
std::vector<double> draw(rng::UniformSource& src, std::uint64_t d, const std::vector<std::uint64_t>& ids) {
  Kokkos::View<std::uint64_t*> s("ids", ids.size());
  auto hs = Kokkos::create_mirror_view(s);
  for (std::size_t i = 0; i < ids.size(); ++i) hs(i) = ids[i];
  Kokkos::deep_copy(s, hs);
  rng::UniformTable<> u("u", ids.size());
  src.fill(d, s, u);
  auto hu = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), u);
  std::vector<double> v;
  for (std::size_t i = 0; i < ids.size(); ++i)
    for (int j = 0; j < 4; ++j) v.push_back(hu(i, j));
  return v;
}
}  // namespace

TEST_CASE("uniforms depend only on (seed, stream, draw), not on batch order", "[rng]") {
  for (const char* kind : {"philox", "aes-ctr"}) {
    CAPTURE(kind);
    auto a = rng::make_uniform_source(kind, 99);
    auto b = rng::make_uniform_source(kind, 99);
    const auto fwd = draw(*a, 5, {0, 1, 2, 3, 4, 5, 6, 7});
    const auto rev = draw(*b, 5, {7, 6, 5, 4, 3, 2, 1, 0});
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 4; ++j) CHECK(fwd[4 * i + j] == rev[4 * (7 - i) + j]);
    auto c = rng::make_uniform_source(kind, 100);
    CHECK(draw(*c, 5, {0})[0] != fwd[0]);  // another seed, other numbers
    for (double v : fwd) {
      CHECK(v >= 0.0);
      CHECK(v < 1.0);
    }
  }
}

TEST_CASE("to_unit_double is exact and unbiased at the ends", "[rng]") {
  CHECK(rng::to_unit_double(0) == 0.0);
  CHECK(rng::to_unit_double(~0ull) == 1.0 - std::ldexp(1.0, -53));
  CHECK(rng::to_unit_double(1ull << 63) == 0.5);
}

TEST_CASE("Philox uniforms: mean, variance and lag-1 correlation", "[rng]") {
  auto src = rng::make_uniform_source("philox", 1);
  std::vector<std::uint64_t> ids(50000);
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  const auto v = draw(*src, 0, ids);
  double m = 0, q = 0, c = 0;
  for (double x : v) m += x;
  m /= v.size();
  for (std::size_t i = 0; i < v.size(); ++i) {
    q += (v[i] - m) * (v[i] - m);
    if (i + 1 < v.size()) c += (v[i] - m) * (v[i + 1] - m);
  }
  q /= v.size();
  c /= (v.size() - 1) * q;
  const double n = static_cast<double>(v.size());
  CHECK(std::abs(m - 0.5) < 5 * std::sqrt(1.0 / 12 / n));
  CHECK(std::abs(q - 1.0 / 12) < 0.005);
  CHECK(std::abs(c) < 5 / std::sqrt(n));
}

TEST_CASE("every generator a deck may name is made by the registry, under its own name", "[rng]") {
  for (const auto kind : rng::kGeneratorKinds) {
    CAPTURE(kind);
    CHECK(rng::is_uniform_source_kind(kind));
    const auto src = rng::make_uniform_source(kind, 1);
    REQUIRE(src);
    CHECK(src->name() == kind);
  }
  CHECK(!rng::is_uniform_source_kind("mersenne"));
  CHECK_THROWS_AS(rng::make_uniform_source("mersenne", 1), std::invalid_argument);
}
