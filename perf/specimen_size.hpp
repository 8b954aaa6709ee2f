// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Specimen dimensions for a target brick count (benchmarks): 3.5 x 1 bricks, 3:2 aspect,
/// notch over 40 % of the width. Callers set the notch height and wall angle.
#include <nacre/deck/deck.hpp>

#include <algorithm>
#include <cmath>

namespace nacre {

inline void size_specimen(deck::Geometry& g, long bricks) {
  const double area = 3.5 * static_cast<double>(bricks);
  g.height = std::floor(std::sqrt(area / 1.5));
  g.width = area / g.height;
  g.notch_length = 0.4 * g.width;
}

/// \brief The Monte Carlo benchmarks' specimen and mortar: sized as above, notched at mid-height,
/// the brittle mortar of the tests (bed x1 0.002, x2 0.004; head 0.001, 0.002).
inline deck::Deck mc_bench_deck(long bricks) {
  deck::Deck d;
  size_specimen(d.geometry, bricks);
  d.geometry.notch_y = std::floor(0.5 * d.geometry.height);
  d.mortar.bed = {100.0, 0.002, 0.004};
  d.mortar.head = {100.0, 0.001, 0.002};
  return d;
}

/// \brief The dynamics benchmarks' specimen (units mm): sized as above, the width rounded to a
/// multiple of half a brick (the running bond then leaves whole and half bricks only, no slivers:
/// a clipped sliver is a stiffer element type and sets a smaller critical step), bricks
/// 0.105 x 0.03 mm, the notch over 40 % of the width at mid-height.
inline void size_dyn_specimen(deck::Geometry& g, long bricks) {
  size_specimen(g, bricks);
  g.width = std::max(3.5, std::round(g.width / 1.75) * 1.75);
  g.notch_length = 0.4 * g.width;
  const double L = 0.03;
  g.width *= L, g.height *= L, g.notch_length *= L;
  g.brick_width = 3.5 * L, g.brick_height = L;
  g.notch_y = std::floor(0.5 * g.height / L) * L;
}

}  // namespace nacre
