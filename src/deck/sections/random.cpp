// SPDX-License-Identifier: BSD-3-Clause
// [random]: seed and generator of the reproducible random streams.
#include "../section.hpp"

#include <nacre/rng/kinds.hpp>

#include <limits>

namespace nacre::deck::detail {

void read_random(Section& top, Deck& d) {
  Section r = top.sub("random");
  std::int64_t seed = 1;
  r.integer("seed", {}, seed, 0, std::numeric_limits<long>::max(), "a non-negative integer");
  d.seed = static_cast<std::uint64_t>(seed);
  if (const toml::node* n = r.find("generator", {})) {
    auto v = n->value_exact<std::string>();
    if (!v || !rng::is_uniform_source_kind(*v))
      r.fail("generator", "expected one of " + rng::uniform_source_kinds());
    d.solver.rng = *v;
  }
  r.reject_unknown({"seed", "generator"});
}

}  // namespace nacre::deck::detail
