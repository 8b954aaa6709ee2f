// SPDX-License-Identifier: BSD-3-Clause
// Specimen construction and interface detection on small hand-checked walls.
#include <nacre/geometry/specimen.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include <cmath>
#include <numeric>

using namespace nacre;
using namespace nacre::geometry;

namespace {
deck::Geometry tiny() {
  deck::Geometry g;
  g.width = 7.0;
  g.height = 2.0;
  g.brick_width = 3.5;
  g.brick_height = 1.0;
  g.overlap = 0.5;
  g.angle_deg = 0;
  g.notch_length = 0;
  g.notch_y = 1.0;
  g.min_piece_fraction = 0.0;
  return g;
}
/// A wall of the deck's default bricks without a notch (its line at mid-height).
deck::Geometry unnotched(double width, double height) {
  deck::Geometry g;
  g.width = width;
  g.height = height;
  g.notch_length = 0;
  g.notch_y = 0.5 * height;
  return g;
}
double total(const Interfaces& f, JointKind k) {
  double s = 0;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f.kind[i] == k) s += f.length[i];
  return s;
}
int count(const Interfaces& f, JointKind k) {
  int c = 0;
  for (std::size_t i = 0; i < f.size(); ++i) c += f.kind[i] == k;
  return c;
}
}  // namespace

TEST_CASE("two-row running bond: bricks, partial bricks, joints", "[geometry]") {
  auto g = tiny();
  Specimen s = build_specimen(g);
  // row 0: [0,3.5] [3.5,7]; row 1 shifted by 1.75: [0,1.75] [1.75,5.25] [5.25,7]
  REQUIRE(s.size() == 5);
  CHECK(std::accumulate(s.area.begin(), s.area.end(), 0.0) == Catch::Approx(14.0));
  Interfaces f = find_interfaces(s, g);
  CHECK(count(f, JointKind::bed) == 4);
  CHECK(count(f, JointKind::head) == 3);
  CHECK(total(f, JointKind::bed) == Catch::Approx(7.0));
  CHECK(total(f, JointKind::head) == Catch::Approx(3.0));
  int top = 0, bottom = 0;
  for (auto d : s.drive) top += d == Drive::top, bottom += d == Drive::bottom;
  CHECK(top == 3);
  CHECK(bottom == 2);
}

TEST_CASE("the notch removes the bonds along it", "[geometry]") {
  auto g = tiny();
  g.notch_length = 3.0;  // along y = 1, the bed joint between the rows
  Specimen s = build_specimen(g);
  Interfaces f = find_interfaces(s, g);
  // bed joints [0,1.75] gone, [1.75,3.5] cut to [3,3.5]; head joints untouched
  CHECK(count(f, JointKind::bed) == 3);
  CHECK(total(f, JointKind::bed) == Catch::Approx(7.0 - 1.75 - 1.25));
  CHECK(count(f, JointKind::head) == 3);
}

TEST_CASE("rotated, notched walls: area conserved, segments consistent, nothing crosses the notch",
          "[geometry]") {
  for (double angle : {0.0, 17.0, 30.0, 45.0, -60.0, 90.0}) {
    deck::Geometry g;
    g.width = 30;
    g.height = 20;
    g.brick_width = 3.5;
    g.brick_height = 1.0;
    g.angle_deg = angle;
    g.notch_length = 12;
    g.notch_y = 10.3;
    g.min_piece_fraction = 0.0;
    Specimen s = build_specimen(g);
    CAPTURE(angle);
    CHECK(std::accumulate(s.area.begin(), s.area.end(), 0.0) == Catch::Approx(600.0).epsilon(1e-9));
    Interfaces f = find_interfaces(s, g);
    REQUIRE(f.size() > 2 * s.size());
    for (std::size_t i = 0; i < f.size(); ++i) {
      const int a = f.a[i], b = f.b[i];
      // both local frames name the same points
      CHECK(s.cx[a] + f.ra0x[i] == Catch::Approx(s.cx[b] + f.rb0x[i]).margin(1e-9));
      CHECK(s.cy[a] + f.ra1y[i] == Catch::Approx(s.cy[b] + f.rb1y[i]).margin(1e-9));
      CHECK(std::hypot(f.nx[i], f.ny[i]) == Catch::Approx(1.0));
      // normal points from a towards b
      const double mx = 0.5 * (f.ra0x[i] + f.ra1x[i]), my = 0.5 * (f.ra0y[i] + f.ra1y[i]);
      CHECK(mx * f.nx[i] + my * f.ny[i] > 0);
      // no bond crosses the notch slit (y = 10.3, x < 12)
      const double y0 = s.cy[a] + f.ra0y[i], y1 = s.cy[a] + f.ra1y[i];
      const double x0 = s.cx[a] + f.ra0x[i], x1 = s.cx[a] + f.ra1x[i];
      if ((y0 - 10.3) * (y1 - 10.3) < -1e-12) {
        const double xc = x0 + (10.3 - y0) / (y1 - y0) * (x1 - x0);
        CHECK(xc >= 12.0 - 0.5 * std::hypot(3.5, 1.0) - 1e-9);  // only bricks past the tip stay whole
      }
    }
  }
}

TEST_CASE("interface search scales linearly: about three interfaces per brick", "[geometry]") {
  const deck::Geometry g = unnotched(350, 100);
  Specimen s = build_specimen(g);
  Interfaces f = find_interfaces(s, g);
  const double per_brick = static_cast<double>(f.size()) / s.size();
  CHECK(s.size() > 9000);
  CHECK(per_brick > 2.8);
  CHECK(per_brick < 3.1);
  auto adj = build_adjacency(s.size(), f);
  CHECK(adj.offset.back() == static_cast<int>(2 * f.size()));
}

TEST_CASE("centroids and areas far from the origin carry the rounding of the coordinates only", "[geometry]") {
  // A strip of the README BIE deck's bricks (0.105 x 0.03 mm) reaching 78.5 mm from the origin:
  // every whole brick has the same area, and its corners lie at +-w/2, +-h/2 from its centroid.
  // The shoelace on absolute coordinates cancelled there (errors ~4e-11 mm, areas off by ~2e-12
  // relative) and split equal bricks into element types of their own (dyn/model.cpp).
  deck::Geometry g = unnotched(78.54, 0.3);
  g.brick_width = 0.105;
  g.brick_height = 0.03;
  g.angle_deg = 0;
  const Specimen s = build_specimen(g);
  const double full = g.brick_width * g.brick_height;
  int whole = 0;
  double worst_area = 0, worst_corner = 0;
  for (std::size_t b = 0; b < s.size(); ++b) {
    if (s.vertex_count(b) != 4 || std::abs(s.area[b] - full) > 1e-6 * full) continue;
    ++whole;
    worst_area = std::max(worst_area, std::abs(s.area[b] - full) / full);
    for (int v = s.poly_offset[b]; v < s.poly_offset[b + 1]; ++v)
      worst_corner = std::max({worst_corner, std::abs(std::abs(s.vx[v] - s.cx[b]) - 0.5 * g.brick_width),
                               std::abs(std::abs(s.vy[v] - s.cy[b]) - 0.5 * g.brick_height)});
  }
  INFO("whole bricks " << whole << ", worst relative area error " << worst_area << ", worst corner offset error "
                       << worst_corner << " mm");
  CHECK(whole > 7000);
  CHECK(worst_area < 5e-13);    // a few ulp(78.5 mm) / w: the corners' own rounding (absolute: 1.8e-12)
  CHECK(worst_corner < 1e-13);  // a few ulps of 78.5 mm, 1.4e-14 (absolute: 4.2e-11)
}
