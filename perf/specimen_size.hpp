#pragma once
/// \file
/// \brief Specimen dimensions for a target brick count (benchmarks): 3.5 x 1 bricks, 3:2 aspect,
/// notch over 40 % of the width. Callers set the notch height and wall angle.
#include <nacre/deck/deck.hpp>

#include <cmath>

namespace nacre {

inline void size_specimen(deck::Geometry& g, long bricks) {
  const double area = 3.5 * static_cast<double>(bricks);
  g.height = std::floor(std::sqrt(area / 1.5));
  g.width = area / g.height;
  g.notch_length = 0.4 * g.width;
}

}  // namespace nacre
