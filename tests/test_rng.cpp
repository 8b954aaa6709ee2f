// The generator interface and Philox.
#include <nacre/rng/philox.hpp>
#include <nacre/rng/uniform_source.hpp>

#include <catch2/catch_test_macros.hpp>

#include <cmath>
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
