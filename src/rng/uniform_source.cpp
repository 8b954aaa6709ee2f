#include <nacre/rng/philox.hpp>
#include <nacre/rng/uniform_source.hpp>

namespace nacre::rng {

void PhiloxSource::fill(const ExecSpace& space, std::uint64_t draw, StreamIds<> streams, UniformTable<> u) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::philox");
  philox_fill(space, seed_, draw, streams, u);
}

}  // namespace nacre::rng
