#include <nacre/rng/philox.hpp>
#include <nacre/rng/uniform_source.hpp>

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

}  // namespace nacre::rng
