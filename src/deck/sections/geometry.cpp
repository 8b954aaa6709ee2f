// SPDX-License-Identifier: BSD-3-Clause
// [geometry]: specimen and wall (required section).
#include "../section.hpp"

namespace nacre::deck::detail {

void read_geometry(Section& top, Deck& d) {
  Section g = top.sub("geometry");
  if (!g.present()) top.fail("geometry", "missing section; expected a [geometry] table");
  auto& G = d.geometry;
  g.number("width", {}, G.width, positive, "a positive length", true);
  g.number("height", {}, G.height, positive, "a positive length", true);
  g.number("brick_width", {}, G.brick_width, positive, "a positive length", true);
  g.number("brick_height", {}, G.brick_height, positive, "a positive length", true);
  g.number("overlap", {}, G.overlap, [](double v) { return v >= 0 && v < 1; }, "a fraction in [0, 1)");
  g.number("angle", {}, G.angle_deg, [](double v) { return v >= -180 && v <= 180; }, "degrees in [-180, 180]");
  g.number("notch_length", {}, G.notch_length, non_negative, "a non-negative length");
  G.notch_y = 0.5 * G.height;
  g.number("notch_y", {}, G.notch_y, non_negative, "a height in [0, height]");
  g.number("min_piece_fraction", {}, G.min_piece_fraction, [](double v) { return v >= 0 && v < 1; },
           "a fraction in [0, 1)");
  g.integer("driven_rows", {}, G.driven_rows, 1, 1000, "an integer in [1, 1000]");
  if (G.notch_length >= G.width)
    g.fail("notch_length", "notch longer than the specimen; expected notch_length < width");
  if (G.notch_y > G.height) g.fail("notch_y", "notch above the specimen; expected notch_y <= height");
  if (G.brick_width > G.width || G.brick_height > G.height)
    g.fail("brick_width", "brick larger than the specimen; expected brick_width <= width and brick_height <= height");
  if (2.0 * G.driven_rows * G.brick_height >= G.height)
    g.fail("driven_rows", "driven rows cover the whole specimen; expected 2 * driven_rows * brick_height < height");
  g.reject_unknown({"width", "height", "brick_width", "brick_height", "overlap", "angle", "notch_length",
                    "notch_y", "min_piece_fraction", "driven_rows"});
}

}  // namespace nacre::deck::detail
