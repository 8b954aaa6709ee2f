#pragma once
// Small specimens and parameters shared by the dynamics tests (units N, mm, t, s).
#include <nacre/dyn/model.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>

namespace dyntest {

using namespace nacre;

inline constexpr double kBrickH = 0.0307;           // mm: E / (k L) = r with L = kBrickH
inline constexpr double kBrickW = 3.5 * kBrickH;    // aspect ratio 3.5

/// Table 4.1 at stiffness ratio r: E = 214.99 r N/mm^2, k = 7000 N/mm^3, k x1 ~ 70.6 N/mm^2,
/// k x1 x2 = 22 N/mm.
inline dyn::Params params(double r, dyn::Method method) {
  dyn::Params p;
  p.method = method;
  p.youngs_modulus = 214.99 * r;
  p.poisson = 0.35;
  p.density = 3.7e-9;
  p.thickness = 1.0;
  return p;
}
inline deck::Mortar mortar(double k = 7000, double kx1 = 70.626, double kx1x2 = 22) {
  const double x1 = kx1 / k, x2 = kx1x2 / kx1;
  return deck::Mortar{{k, x1, x2}, {k, x1, x2}};
}

/// A running-bond wall of nx x ny bricks (no notch unless notch_bricks > 0).
inline deck::Geometry wall(int nx, int ny, double notch_bricks = 0, double overlap = 0.5) {
  deck::Geometry g;
  g.brick_width = kBrickW, g.brick_height = kBrickH;
  g.width = nx * kBrickW, g.height = ny * kBrickH;
  g.overlap = overlap;
  g.angle_deg = 0;
  g.notch_length = notch_bricks * kBrickW;
  g.notch_y = 0.5 * g.height;
  g.min_piece_fraction = 0.02;
  g.driven_rows = 1;
  return g;
}

struct Setup {
  geometry::Specimen s;
  geometry::Interfaces f;
};
inline Setup make(const deck::Geometry& g) {
  Setup st;
  st.s = geometry::build_specimen(g);
  st.f = geometry::find_interfaces(st.s, g);
  return st;
}

}  // namespace dyntest
