#include <nacre/rng/philox.hpp>
#include <nacre/rng/uniform_source.hpp>

namespace nacre::rng {

void PhiloxSource::fill(const Backend& backend, std::uint64_t draw, const AnyBatch& batch) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::philox");
  std::visit(
      [&](const auto& b) {
        using MS = typename std::decay_t<decltype(b)>::memory_space;
        backend.visit_in<MS>([&](const auto& space) { philox_fill(space, seed_, draw, b.streams, b.u); });
      },
      batch);
}

}  // namespace nacre::rng
