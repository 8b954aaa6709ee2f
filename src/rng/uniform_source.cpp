// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/rng/on_batch.hpp>
#include <nacre/rng/philox.hpp>
#include <nacre/rng/uniform_source.hpp>

namespace nacre::rng {

void PhiloxSource::fill(const Backend& backend, std::uint64_t draw, const AnyBatch& batch) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::philox");
  on_batch(backend, batch, [&](const auto& space, const auto& b) { philox_fill(space, seed_, draw, b.streams, b.u); });
}

}  // namespace nacre::rng
