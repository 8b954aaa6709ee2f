// SPDX-License-Identifier: BSD-3-Clause
// The cohesive law (MODEL.md §2), its integration along an interface (energy and end forces from
// one quadrature loop), the law table by joint kind, and the rigid-brick gap.
#include <nacre/cohesive/law_table.hpp>
#include <nacre/cohesive/segment.hpp>
#include <nacre/kinematics/rigid.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>
#include <catch2/generators/catch_generators.hpp>

#include <cmath>
#include <random>

using namespace nacre::cohesive;
using nacre::kinematics::Pose;
using nacre::kinematics::Segment;
using nacre::kinematics::interface_energy;

namespace {
const Law law{100.0, 0.01, 0.03};  // rupture at 0.04, work to failure k x1 x2 = 0.03
}

TEST_CASE("f is continuous with continuous slope at x1, x2 and x1 + x2", "[cohesive]") {
  for (double x : {law.x1, law.x2, law.x1 + law.x2}) {
    const double h = 1e-9;
    CHECK(f_energy(law, x - h) == Catch::Approx(f_energy(law, x + h)).margin(1e-9));
    CHECK(f_slope(law, x - h) == Catch::Approx(f_slope(law, x + h)).margin(1e-6));
  }
  CHECK(f_energy(law, 1.0) == Catch::Approx(law.k * law.x1 * law.x2));  // ruptured plateau
  CHECK(f_slope(law, 0.5 * law.x1) == Catch::Approx(law.k * 0.5 * law.x1));
  CHECK(f_slope(law, 0.5 * (law.x1 + law.x2)) == Catch::Approx(law.k * law.x1));  // plateau
  CHECK(f_slope(law, law.x2 + 0.5 * law.x1) == Catch::Approx(0.5 * law.k * law.x1));  // softening
  CHECK(f_slope(law, 1.0) == 0.0);
  CHECK(g_energy(law, 0.001) == 0.0);
  CHECK(g_energy(law, -law.x1) == Catch::Approx(0.0625 * law.k * law.x1 * law.x1));
}

TEST_CASE("f' and g' are the derivatives of f and g (central differences)", "[cohesive]") {
  const double h = 1e-7;
  for (double x = -0.02; x <= 0.06; x += 0.0007) {
    if (x > 0) {
      const double fd = (f_energy(law, x + h) - f_energy(law, x - h)) / (2 * h);
      CHECK(f_slope(law, x) == Catch::Approx(fd).margin(1e-5));
    }
    const double gd = (g_energy(law, x + h) - g_energy(law, x - h)) / (2 * h);
    CHECK(g_slope(law, x) == Catch::Approx(gd).margin(1e-5));
  }
}

TEST_CASE("traction = gradient of the energy density in (dn, dt)", "[cohesive]") {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> U(-0.05, 0.05);
  const double h = 1e-8;
  int checked = 0;
  for (int k = 0; k < 2000; ++k) {
    const double dn = U(gen), dt = U(gen), d = std::hypot(dn, dt);
    // skip points within h of a branch point, where the density is only C1
    bool near = false;
    for (double b : {law.x1, law.x2, law.x1 + law.x2}) near |= std::abs(d - b) < 1e-6;
    if (near || std::abs(dn) < 1e-6) continue;
    double fn, ft;
    traction(law, dn, dt, fn, ft);
    const double gn = (energy_density(law, dn + h, dt) - energy_density(law, dn - h, dt)) / (2 * h);
    const double gt = (energy_density(law, dn, dt + h) - energy_density(law, dn, dt - h)) / (2 * h);
    CHECK(fn == Catch::Approx(gn).margin(1e-5));
    CHECK(ft == Catch::Approx(gt).margin(1e-5));
    ++checked;
  }
  CHECK(checked > 1900);
  double fn, ft;
  traction(law, 0.0, 0.0, fn, ft);  // d = 0 limit
  CHECK(fn == 0.0);
  CHECK(ft == 0.0);
}

TEST_CASE("Gauss-Legendre rules integrate polynomials of degree 2n-1 exactly", "[cohesive][quadrature]") {
  for (int n = 1; n <= 8; ++n) {
    const Quadrature q = gauss_legendre(n);
    for (int p = 0; p <= 2 * n - 1; ++p) {
      double s = 0;
      for (int k = 0; k < n; ++k) s += q.w[k] * std::pow(q.s[k], p);
      CHECK(s == Catch::Approx(1.0 / (p + 1)).epsilon(1e-13));
    }
  }
}

TEST_CASE("interface energy: uniform opening of a rigid pair, and its force", "[cohesive]") {
  // brick a below, brick b above, horizontal bed joint of length 3 at y = 0.5 above a's centroid
  const Segment sg{-1.5, 0.5, 1.5, 0.5, -1.5, -0.5, 1.5, -0.5, 0.0, 1.0, 3.0};
  const Quadrature q = gauss_legendre(4);
  const Pose a{0, 0, 0};
  for (double d : {0.005, 0.02, 0.035, 0.05}) {
    const Pose b{0, d, 0};
    CHECK(interface_energy(law, q, sg, a, b) == Catch::Approx(3.0 * f_energy(law, d)));
    // force on b along the normal = -dE/dd = -L f'(d), the law's normal traction times length
    const double h = 1e-8;
    const double dE = (interface_energy(law, q, sg, a, {0, d + h, 0}) - interface_energy(law, q, sg, a, {0, d - h, 0})) / (2 * h);
    double fn, ft;
    traction(law, d, 0.0, fn, ft);
    CHECK(dE == Catch::Approx(3.0 * fn).margin(1e-4));
  }
  // a rigid motion of both bricks together stores no energy
  // b's centroid sits 1 above a's: rotating the pair by t about a's centroid moves b's centroid
  const double t = 0.05;
  const Pose ra{0, 0, t}, rb{-std::sin(t) * 1.0, std::cos(t) * 1.0 - 1.0, t};
  CHECK(interface_energy(law, q, sg, ra, rb) == Catch::Approx(0.0).margin(1e-20));
}

TEST_CASE("law: Cartesian and local forms agree, the traction is the gradient of the density",
          "[cohesive]") {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> U(-0.05, 0.05), A(0.0, 6.283185307179586);
  for (int trial = 0; trial < 200; ++trial) {
    const double gx = U(gen), gy = U(gen), a = A(gen), scale = 1.0 + 0.2 * U(gen);  // normal not unit
    const double nx = scale * std::cos(a), ny = scale * std::sin(a);
    const double ux = nx / scale, uy = ny / scale;
    const double dn = gx * ux + gy * uy, dt = -gx * uy + gy * ux;
    INFO("gap " << gx << ", " << gy << ", normal angle " << a);
    CHECK(law(EnergyTag{}, gx, gy, nx, ny) == Catch::Approx(law(EnergyTag{}, dn, dt)).epsilon(1e-12).margin(1e-18));
    double tx, ty, fn, ft;
    law(TractionTag{}, gx, gy, nx, ny, tx, ty);
    law(TractionTag{}, dn, dt, fn, ft);
    CHECK(tx == Catch::Approx(fn * ux - ft * uy).epsilon(1e-10).margin(1e-14));
    CHECK(ty == Catch::Approx(fn * uy + ft * ux).epsilon(1e-10).margin(1e-14));
    const double h = 1e-8;
    const double ex = (law(EnergyTag{}, gx + h, gy, nx, ny) - law(EnergyTag{}, gx - h, gy, nx, ny)) / (2 * h);
    const double ey = (law(EnergyTag{}, gx, gy + h, nx, ny) - law(EnergyTag{}, gx, gy - h, nx, ny)) / (2 * h);
    CHECK(tx == Catch::Approx(ex).margin(1e-5));
    CHECK(ty == Catch::Approx(ey).margin(1e-5));
  }
}

TEST_CASE("law table: one law per joint kind, a rigid model has no internal joints", "[cohesive]") {
  using nacre::geometry::JointKind;
  const Law bed{100.0, 0.01, 0.02}, head{50.0, 0.005, 0.01}, internal{5000.0, 1.0, 1.0};
  const LawTable t = make_law_table(bed, head, internal);
  CHECK(t[JointKind::bed].k == 100.0);
  CHECK(t[JointKind::head].x1 == 0.005);
  CHECK(t[JointKind::internal].k == 5000.0);
  CHECK(t[static_cast<std::uint8_t>(1)].k == 50.0);  // as stored per interface in a model
  const LawTable rigid = make_law_table(bed, head);
  CHECK(rigid[JointKind::internal](EnergyTag{}, 0.3, -0.2) == 0.0);  // kNoJoint: no energy
  double fn = 1, ft = 1;
  rigid[JointKind::internal](TractionTag{}, 0.3, -0.2, fn, ft);
  CHECK(fn == 0.0);
  CHECK(ft == 0.0);
}
