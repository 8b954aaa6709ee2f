#include <nacre/rng/philox.hpp>
#include <nacre/rng/uniform_source.hpp>

namespace nacre::rng {

void PhiloxSource::fill(const Backend& backend, std::uint64_t draw, StreamIds<> streams, UniformTable<> u) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::philox");
  backend.visit([&](const auto& space) { philox_fill(space, seed_, draw, streams, u); });
}

}  // namespace nacre::rng
