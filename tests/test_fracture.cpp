// SPDX-License-Identifier: BSD-3-Clause
// The crack reading (fracture/crack.hpp) against cracks drawn by hand on a notched running-bond
// wall, where tip, extension, path length, deflection and joint counts are known exactly; the
// Rayleigh speed against the classical root for a Poisson solid.
#include <nacre/fracture/crack.hpp>
#include <nacre/fracture/r_curve.hpp>
#include <nacre/io/csv.hpp>

#include "wall_specimen.hpp"

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_string.hpp>

#include <cmath>
#include <vector>

using namespace nacre;
using Catch::Approx;
using Catch::Matchers::ContainsSubstring;

namespace {

struct Seg {
  double x0, y0, x1, y1;
};

// the 21 x 8 wall of bricks 3.5 x 1 notched over 8 along y = 4
struct Fixture {
  deck::Geometry g;
  test::Wall w;
  Fixture() {
    g.width = 21, g.height = 8, g.notch_length = 8, g.notch_y = 4;
    g.brick_width = 3.5, g.brick_height = 1.0;
    w = test::wall_of(g);
  }
  [[nodiscard]] Seg seg(std::size_t i) const {
    const auto a = static_cast<std::size_t>(w.f.a[i]);
    Seg s{w.s.cx[a] + w.f.ra0x[i], w.s.cy[a] + w.f.ra0y[i], w.s.cx[a] + w.f.ra1x[i], w.s.cy[a] + w.f.ra1y[i]};
    if (s.x0 > s.x1 || (s.x0 == s.x1 && s.y0 > s.y1)) std::swap(s.x0, s.x1), std::swap(s.y0, s.y1);
    return s;
  }
  // bed joints along y between x = from and x = to
  void bed(std::vector<int>& st, double y, double from, double to, int value = 2) const {
    for (std::size_t i = 0; i < w.f.size(); ++i) {
      const Seg s = seg(i);
      if (std::abs(s.y0 - y) < 1e-9 && std::abs(s.y1 - y) < 1e-9 && s.x0 >= from - 1e-9 && s.x1 <= to + 1e-9)
        st[i] = value;
    }
  }
};

// a wall of bricks 3.5 x 1 at 30 degrees, notched from the left along y = notch_y
deck::Geometry rotated(double width, double height, double notch_length, double notch_y) {
  deck::Geometry g;
  g.width = width, g.height = height, g.notch_length = notch_length, g.notch_y = notch_y, g.angle_deg = 30;
  g.brick_width = 3.5, g.brick_height = 1.0;
  return g;
}

}  // namespace

TEST_CASE("crack: an intact specimen has no crack, its tip is the notch tip", "[fracture]") {
  Fixture F;
  const fracture::CrackTracker t(F.w.s, F.w.f, F.g);
  std::vector<int> st(F.w.f.size(), 0);
  const auto r = t.measure(st);
  CHECK(r.interfaces == 0);
  CHECK(r.tip_x == 8.0);
  CHECK(r.tip_y == 4.0);
  CHECK(r.extension == 0.0);
  CHECK(r.path_length == 0.0);
  CHECK(r.process_zone == 0);
  CHECK(t.notch_tip_x() == 8.0);
  std::vector<int> wrong(F.w.f.size() + 1, 0);
  CHECK_THROWS(t.measure(wrong));
}

TEST_CASE("crack: a straight crack along the ligament's bed joint", "[fracture]") {
  Fixture F;
  const fracture::CrackTracker t(F.w.s, F.w.f, F.g);
  std::vector<int> st(F.w.f.size(), 0);
  F.bed(st, 4.0, 8.0, 15.0);
  const auto r = t.measure(st);
  REQUIRE(r.interfaces > 0);
  CHECK(r.head == 0);
  CHECK(r.bed == r.interfaces);
  CHECK(r.tip_y == Approx(4.0));
  CHECK(r.extension == Approx(r.tip_x - 8.0));
  CHECK(r.tip_x > 12.0);
  CHECK(r.tip_x <= 15.0 + 1e-9);
  CHECK(r.path_length == Approx(r.extension));
  CHECK(r.deflection == Approx(1.0));
  // a ruptured joint away from the crack is no part of it
  std::vector<int> st2 = st;
  F.bed(st2, 1.0, 0.0, 21.0);
  const auto r2 = t.measure(st2);
  CHECK(r2.interfaces == r.interfaces);
  CHECK(r2.tip_x == r.tip_x);
  // a gap at the notch tip: nothing is connected
  std::vector<int> st3(F.w.f.size(), 0);
  F.bed(st3, 4.0, 9.0, 15.0);
  CHECK(t.measure(st3).interfaces == 0);
  // the crack's interfaces, for the dumps
  const auto members = t.crack_interfaces(st2);
  CHECK(static_cast<int>(members.size()) == r.interfaces);
  for (int i : members) CHECK(st2[i] == 2);
}

TEST_CASE("crack: a crack that steps up one row through a head joint", "[fracture]") {
  Fixture F;
  const fracture::CrackTracker t(F.w.s, F.w.f, F.g);
  // the first head joint between y = 4 and 5 beyond x = 10
  int head = -1;
  double xh = 1e300;
  for (std::size_t i = 0; i < F.w.f.size(); ++i) {
    const Seg s = F.seg(i);
    if (F.w.f.kind[i] == geometry::JointKind::head && std::abs(s.y0 - 4) < 1e-9 && std::abs(s.y1 - 5) < 1e-9 &&
        s.x0 > 10 && s.x0 < xh)
      head = static_cast<int>(i), xh = s.x0;
  }
  REQUIRE(head >= 0);
  std::vector<int> st(F.w.f.size(), 0);
  F.bed(st, 4.0, 8.0, xh);
  st[head] = 2;
  F.bed(st, 5.0, xh, xh + 7.0);
  const auto r = t.measure(st);
  CHECK(r.head == 1);
  CHECK(r.tip_y == Approx(5.0));
  const double tip = r.tip_x;
  CHECK(tip > xh + 3);
  CHECK(r.extension == Approx(tip - 8.0));
  CHECK(r.path_length == Approx((xh - 8.0) + 1.0 + (tip - xh)));
  CHECK(r.deflection == Approx(r.path_length / r.extension));
  CHECK(r.deflection > 1.0);
  // the same crack with the step's bed joints at y = 4 still ruptured ahead: the tip is the
  // furthest point along the ligament, the path the shortest way to it
  F.bed(st, 4.0, xh, tip + 3.5);
  const auto r2 = t.measure(st);
  CHECK(r2.tip_x > tip);
  CHECK(r2.tip_y == Approx(4.0));
  CHECK(r2.path_length == Approx(r2.extension));
}

TEST_CASE("crack: the process zone is the softening joints connected to the crack", "[fracture]") {
  Fixture F;
  const fracture::CrackTracker t(F.w.s, F.w.f, F.g);
  std::vector<int> st(F.w.f.size(), 0);
  F.bed(st, 4.0, 8.0, 11.5);
  const double tip = t.measure(st).tip_x;
  F.bed(st, 4.0, tip, tip + 3.5, 1);  // softening ahead of the tip
  F.bed(st, 1.0, 0.0, 21.0, 1);       // softening elsewhere: not connected
  const auto r = t.measure(st);
  CHECK(r.tip_x == tip);
  CHECK(r.process_zone >= 1);
  CHECK(r.process_zone_extent > 0);
  CHECK(r.process_zone_extent <= 3.5 + 1e-9);
  int ahead = 0;
  for (std::size_t i = 0; i < F.w.f.size(); ++i) ahead += st[i] == 1 && std::abs(F.seg(i).y0 - 4) < 1e-9;
  CHECK(r.process_zone == ahead);
  // nothing ruptured: the zone grows from the notch
  std::vector<int> s0(F.w.f.size(), 0);
  F.bed(s0, 4.0, 8.0, 11.5, 1);
  const auto r0 = t.measure(s0);
  CHECK(r0.interfaces == 0);
  CHECK(r0.process_zone >= 1);
  CHECK(r0.process_zone_extent > 2.0);
}

TEST_CASE("crack: a rotated wall's notch tip is the end of the last brick it splits", "[fracture]") {
  const deck::Geometry g = rotated(21, 8, 8, 4);
  const auto w = test::wall_of(g);
  const fracture::CrackTracker t(w.s, w.f, g);
  CHECK(t.notch_tip_x() >= 8.0 - 3.5);
  CHECK(t.notch_tip_x() <= 8.0 + 3.6);
  std::vector<int> all(w.f.size(), 2);  // everything ruptured: the crack reaches the far edge
  const auto r = t.measure(all);
  CHECK(r.interfaces > static_cast<int>(0.95 * static_cast<double>(w.f.size())));
  CHECK(r.tip_x == Approx(21.0).margin(1e-6));
}

TEST_CASE("crack: the notch tip of a rotated wall whose split corner was dropped as a sliver", "[fracture]") {
  // the README deck at 30 degrees: the last brick the notch splits loses its piece above the
  // line (below min_piece_fraction), so the notch's free face ends at x = 24.12, past
  // notch_length; the joints that meet the line there are the crack's roots
  const deck::Geometry g = rotated(80, 40, 24, 20);
  const auto w = test::wall_of(g);
  const fracture::CrackTracker t(w.s, w.f, g);
  // the joints touching the notch line furthest along it
  double xmax = -1;
  std::vector<int> touching;
  for (std::size_t i = 0; i < w.f.size(); ++i) {
    const auto a = static_cast<std::size_t>(w.f.a[i]);
    for (auto [x, y] : {std::pair{w.s.cx[a] + w.f.ra0x[i], w.s.cy[a] + w.f.ra0y[i]},
                        std::pair{w.s.cx[a] + w.f.ra1x[i], w.s.cy[a] + w.f.ra1y[i]}})
      if (std::abs(y - 20.0) < 1e-9 && x <= 30.0) {
        if (x > xmax + 1e-9) xmax = x, touching.clear();
        if (std::abs(x - xmax) <= 1e-9) touching.push_back(static_cast<int>(i));
      }
  }
  REQUIRE(!touching.empty());
  CHECK(t.notch_tip_x() == Approx(xmax).margin(1e-9));
  std::vector<int> st(w.f.size(), 0);
  for (int i : touching) st[i] = 2;
  const auto r = t.measure(st);
  CHECK(r.interfaces == static_cast<int>(touching.size()));
  CHECK(r.extension >= 0.0);
}

TEST_CASE("Rayleigh speed: the Poisson solid's root, plane stress", "[fracture]") {
  // plane stress with nu = 1/3 is plane strain with nu' = nu / (1 + nu) = 1/4, whose Rayleigh
  // root is c_R / c_s = sqrt(2 - 2 / sqrt(3))
  const double E = 21499.0, rho = 3.7e-9, nu = 1.0 / 3.0;
  const double cs = std::sqrt(E / (2 * rho * (1 + nu)));
  CHECK(fracture::rayleigh_speed_plane_stress(E, nu, rho) / cs ==
        Approx(std::sqrt(2 - 2 / std::sqrt(3.0))).epsilon(1e-10));
  // nu = 0.35: within 0.5 % of Viktorov's approximation (0.862 + 1.14 nu') / (1 + nu')
  const double n2 = 0.35 / 1.35, cs2 = std::sqrt(E / (2 * rho * 1.35));
  CHECK(fracture::rayleigh_speed_plane_stress(E, 0.35, rho) / cs2 ==
        Approx((0.862 + 1.14 * n2) / (1 + n2)).epsilon(5e-3));
  CHECK_THROWS(fracture::rayleigh_speed_plane_stress(-1.0, 0.3, rho));
}

TEST_CASE("the R-curve: a point where the extension grows, G_R per unit thickness, the toughening ratio over the second half",
          "[fracture][r_curve]") {
  // rows before the crack leaves the notch (the last one is the base), a repeated extension skipped
  const std::vector<double> a{0, 0, 1, 2, 2, 3}, w{0, 0.5, 1.5, 3.5, 3.6, 5.6};
  const fracture::RCurve c = fracture::r_curve(a, w, 2.0, 0.5);
  REQUIRE(c.points.size() == 3);
  CHECK(c.points[0].extension == 1);
  CHECK(c.points[0].G_R == 0.5);  // (1.5 - 0.5) / 1 / 2
  CHECK(c.points[0].toughening == 1);
  CHECK(c.points[1].G_R == 1);  // (3.5 - 1.5) / 1 / 2
  CHECK(c.points[2].G_R == Catch::Approx(1.05).epsilon(1e-15));  // from the point before, not the skipped row
  // the second half: from the first point at or past 1.5 (extension 2) to the last
  CHECK(c.toughening_ratio == Catch::Approx((5.6 - 3.5) / 1 / 2 / 0.5).epsilon(1e-15));
  const std::string csv = fracture::r_curve_csv(c);
  CHECK(csv.starts_with("extension,fracture_energy,G_R,toughening\n1,1.5,0.5,1\n"));
  const io::CsvTable back = io::parse_csv(csv, "r_curve.csv");
  CHECK(back.numbers("G_R") == std::vector<double>{c.points[0].G_R, c.points[1].G_R, c.points[2].G_R});
  SECTION("one point: no ratio") {
    CHECK(std::isnan(fracture::r_curve({0, 1}, {0, 1}, 1, 1).toughening_ratio));
    CHECK(fracture::r_curve({0, 0}, {0, 0}, 1, 1).points.empty());
  }
  SECTION("a table with a row short of a field, or text where a number belongs, is refused by name") {
    CHECK_THROWS_WITH(io::parse_csv("a,b\n1,2\n3\n", "t.csv"), ContainsSubstring("t.csv:3"));
    CHECK_THROWS_WITH(io::parse_csv("a,b\n1,x\n", "t.csv").numbers("b"), ContainsSubstring("'x' is not a number"));
    CHECK_THROWS_WITH(io::parse_csv("a,b\n1,2\n", "t.csv").numbers("c"), ContainsSubstring("no column 'c'"));
    CHECK(io::parse_csv("a,method\n1,newton\n", "t.csv").rows[0][1] == "newton");
  }
}
