#include <nacre/rng/philox.hpp>
#include <nacre/rng/uniform_source.hpp>
#include <nacre/aes/aes_sources.hpp>

#include <stdexcept>

namespace nacre::rng {

void PhiloxSource::fill(const ExecSpace& space, std::uint64_t draw, StreamIds<> streams, UniformTable<> u) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::philox");
  const std::uint64_t seed = seed_;
  Kokkos::parallel_for(
      "nacre::rng::philox_fill", Kokkos::RangePolicy<ExecSpace>(space, 0, streams.extent(0)),
      KOKKOS_LAMBDA(const std::size_t i) {
        double r[4];
        philox_uniforms(seed, streams(i), draw, r);
        for (int k = 0; k < 4; ++k) u(i, k) = r[k];
      });
}

namespace {
constexpr std::string_view kKinds[] = {"philox", "aes-ctr", "mt-aes"};
}

bool is_uniform_source_kind(std::string_view kind) {
  for (auto k : kKinds)
    if (k == kind) return true;
  return false;
}

std::string uniform_source_kinds() {
  std::string s;
  for (auto k : kKinds) {
    if (!s.empty()) s += ", ";
    s += '"';
    s += k;
    s += '"';
  }
  return s;
}

std::unique_ptr<UniformSource> make_uniform_source(std::string_view kind, std::uint64_t seed) {
  if (kind == "philox") return std::make_unique<PhiloxSource>(seed);
  if (kind == "aes-ctr") return aes::make_aes_ctr_source(seed);
  if (kind == "mt-aes") return aes::make_mt_aes_source(seed);
  throw std::invalid_argument("unknown random generator '" + std::string(kind) +
                              "', expected one of " + uniform_source_kinds());
}

}  // namespace nacre::rng
