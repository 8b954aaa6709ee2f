// SPDX-License-Identifier: BSD-3-Clause
// A rank's colouring (include/nacre/mc/halo.hpp says why halo bricks are not swept).
#include <nacre/mc/halo.hpp>

namespace nacre::mc {

Colouring local_colouring(const par::Decomposition& d, const Colouring& global) {
  Colouring c;
  c.name = global.name;
  c.n_colours = global.n_colours;
  for (std::size_t k = 0; k < d.bricks.size(); ++k) {
    const bool owned = static_cast<int>(k) < d.n_owned;
    const int g = d.bricks[k];
    c.colour.push_back(owned ? global.colour[g] : -1);
    c.tile.push_back(owned && !global.tile.empty() ? global.tile[g] : -1);
  }
  return c;
}

}  // namespace nacre::mc
