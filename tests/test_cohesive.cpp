// The cohesive law (MODEL.md §2) and its integration along an interface.
#include <nacre/cohesive/interface_energy.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>
#include <catch2/generators/catch_generators.hpp>

#include <cmath>
#include <random>

using namespace nacre::cohesive;

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

namespace {
// A segment of length 2 along x between two bricks; the gap varies linearly from g0 to g1.
double segment_energy(const Quadrature& q, double g0x, double g0y, double g1x, double g1y) {
  return gap_energy(law, q, Gap{g0x, g0y, g1x, g1y, 0.0, 1.0}, 2.0);
}
double reference_energy(double g0x, double g0y, double g1x, double g1y) {
  // composite midpoint rule, 20000 panels: error ~1e-9 relative even across kinks
  const int n = 20000;
  double e = 0;
  for (int i = 0; i < n; ++i) {
    const double s = (i + 0.5) / n;
    const double gx = g0x + s * (g1x - g0x), gy = g0y + s * (g1y - g0y);
    e += energy_density(law, gy, gx);
  }
  return 2.0 * e / n;
}
}  // namespace

TEST_CASE("interface quadrature: exact where the density is polynomial, converging across kinks",
          "[cohesive][quadrature]") {
  SECTION("elastic range: 2 points are exact") {
    const double ref = reference_energy(0.001, 0.004, -0.002, 0.008);
    CHECK(segment_energy(gauss_legendre(2), 0.001, 0.004, -0.002, 0.008) == Catch::Approx(ref).epsilon(1e-7));
  }
  SECTION("interpenetration (degree-6 penalty): 4 points are exact") {
    // dn < 0 all along, |gap| < x1: f quadratic + g degree 6
    const double ref = reference_energy(0.0, -0.002, 0.0, -0.006);
    CHECK(segment_energy(gauss_legendre(4), 0.0, -0.002, 0.0, -0.006) == Catch::Approx(ref).epsilon(1e-7));
    CHECK(std::abs(segment_energy(gauss_legendre(2), 0.0, -0.002, 0.0, -0.006) - ref) > 1e-6 * ref);
  }
  SECTION("gap through all branches: error falls with the number of points") {
    // normal opening from 0 to 0.05 along the segment crosses x1, x2 and x1 + x2
    const double ref = reference_energy(0.0, 0.0, 0.0, 0.05);
    double prev = 1e300;
    for (int n : {2, 4, 8}) {
      const double err = std::abs(segment_energy(gauss_legendre(n), 0.0, 0.0, 0.0, 0.05) - ref) / ref;
      CHECK(err < prev);
      prev = err;
    }
    CHECK(prev < 1e-2);  // 8 points: under 1 % even with three kinks inside one segment
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
