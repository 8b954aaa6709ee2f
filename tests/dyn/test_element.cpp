// SPDX-License-Identifier: BSD-3-Clause
// Element library: CSTs and bolting against closed forms (mass, rigid-body modes, homogeneous
// strain energy, patch test, uniaxial stress, thermal load).
#include "common.hpp"

#include <nacre/dyn/element.hpp>
#include <nacre/dyn/model.hpp>

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_floating_point.hpp>

using namespace nacre::dyn;
using Catch::Matchers::WithinRel;
using Catch::Matchers::WithinAbs;

namespace {
const Material kMat{214.99 * 500, 0.35, 3.7e-9, 0.7};
// a whole brick and a clipped pentagon (corner cut), vertices relative to their centroid
std::vector<double> rect_x() { return {-0.5 * dyntest::kBrickW, 0.5 * dyntest::kBrickW, 0.5 * dyntest::kBrickW, -0.5 * dyntest::kBrickW}; }
std::vector<double> rect_y() { return {-0.5 * dyntest::kBrickH, -0.5 * dyntest::kBrickH, 0.5 * dyntest::kBrickH, 0.5 * dyntest::kBrickH}; }
void pentagon(std::vector<double>& x, std::vector<double>& y, double& area) {
  const double w = dyntest::kBrickW, h = dyntest::kBrickH;
  std::vector<double> X{0, w, w, 0.4 * w, 0}, Y{0, 0, 0.6 * h, h, h};
  double a = 0, cx = 0, cy = 0;
  for (int i = 0; i < 5; ++i) {
    const int j = (i + 1) % 5;
    const double c = X[i] * Y[j] - X[j] * Y[i];
    a += 0.5 * c, cx += (X[i] + X[j]) * c, cy += (Y[i] + Y[j]) * c;
  }
  cx /= 6 * a, cy /= 6 * a;
  x.clear(), y.clear();
  for (int i = 0; i < 5; ++i) x.push_back(X[i] - cx), y.push_back(Y[i] - cy);
  area = a;
}
// nodal displacement of a linear field u = G x + c at the element's nodes
Eigen::VectorXd linear_field(const ElementMatrices& e, double exx, double eyy, double gxy, double rot = 0,
                             double cx = 0, double cy = 0) {
  Eigen::VectorXd u(2 * e.nodes);
  for (int k = 0; k < e.nodes; ++k) {
    u(2 * k) = exx * e.x[k] + (0.5 * gxy - rot) * e.y[k] + cx;
    u(2 * k + 1) = (0.5 * gxy + rot) * e.x[k] + eyy * e.y[k] + cy;
  }
  return u;
}
}  // namespace

TEST_CASE("dyn element: bolting keeps total mass, zero-energy rigid modes and homogeneous strain energy",
          "[dyn][element]") {
  std::vector<double> px, py;
  double parea;
  pentagon(px, py, parea);
  const double rect_area = dyntest::kBrickW * dyntest::kBrickH;
  for (int shape = 0; shape < 2; ++shape) {
    const auto X = shape ? px : rect_x(), Y = shape ? py : rect_y();
    const double area = shape ? parea : rect_area;
    const auto b = bolted_brick(X, Y, kMat);
    const auto tris = unbolted_brick(X, Y, kMat);
    CHECK(b.nodes == static_cast<int>(X.size()) + 1);
    // total mass in each direction = rho A t, bolted and unbolted
    double mx = 0, my = 0, mu = 0;
    for (int k = 0; k < b.nodes; ++k) mx += b.mass(2 * k), my += b.mass(2 * k + 1);
    for (const auto& t : tris) mu += t.mass.sum() / 2;
    CHECK_THAT(mx, WithinRel(kMat.rho * area * kMat.thickness, 1e-13));
    CHECK_THAT(my, WithinRel(kMat.rho * area * kMat.thickness, 1e-13));
    CHECK_THAT(mu, WithinRel(kMat.rho * area * kMat.thickness, 1e-13));
    // the mass-weighted centre of the lumped masses is the centroid (momentum of rigid motion exact)
    double sx = 0, sy = 0;
    for (int k = 0; k < b.nodes; ++k) sx += b.mass(2 * k) * b.x[k], sy += b.mass(2 * k) * b.y[k];
    CHECK_THAT(sx / mx, WithinAbs(0, 1e-12 * dyntest::kBrickW));
    CHECK_THAT(sy / mx, WithinAbs(0, 1e-12 * dyntest::kBrickW));
    // rigid-body modes: K r = 0 (translations, rotation)
    const double kn = b.K.norm();
    for (int m = 0; m < 3; ++m) {
      const auto r = linear_field(b, 0, 0, 0, m == 2 ? 1.0 : 0.0, m == 0, m == 1);
      CHECK((b.K * r).norm() < 1e-12 * kn * r.norm());
    }
    // homogeneous strain: 1/2 u^T K u = 1/2 eps^T D eps A t, bolted = sum of the triangles
    const Eigen::Vector3d eps(1e-3, -4e-4, 7e-4);
    const auto u = linear_field(b, eps(0), eps(1), eps(2));
    const double exact = 0.5 * eps.dot(plane_stress(kMat.E, kMat.nu) * eps) * area * kMat.thickness;
    CHECK_THAT(0.5 * u.dot(b.K * u), WithinRel(exact, 1e-12));
    double tri_sum = 0;
    for (const auto& t : tris) {
      const auto ut = linear_field(t, eps(0), eps(1), eps(2));
      tri_sum += 0.5 * ut.dot(t.K * ut);
    }
    CHECK_THAT(tri_sum, WithinRel(exact, 1e-12));
    // thermal load: an isotropic eigenstrain eps is balanced exactly by u = eps x (K u = Theta)
    const auto uth = linear_field(b, 2e-3, 2e-3, 0);
    CHECK((b.K * uth - 2e-3 * b.theta_unit).norm() < 1e-12 * (2e-3 * b.theta_unit).norm());
  }
}

TEST_CASE("dyn element: patch test, the centre node of a bolted brick reproduces a uniform strain",
          "[dyn][element][patch]") {
  std::vector<double> px, py;
  double parea;
  pentagon(px, py, parea);
  for (int shape = 0; shape < 2; ++shape) {
    const auto b = bolted_brick(shape ? px : rect_x(), shape ? py : rect_y(), kMat);
    const Eigen::Vector3d eps(2e-4, 5e-4, -3e-4);
    const auto exact = linear_field(b, eps(0), eps(1), eps(2), 1e-4, 1e-5, -2e-5);
    // corners prescribed (dof 2..), centre node free (dof 0, 1): K_cc u_c = -K_cb u_b
    const int nd = 2 * b.nodes;
    const Eigen::Matrix2d Kcc = b.K.topLeftCorner(2, 2);
    const Eigen::Vector2d uc = Kcc.ldlt().solve(-b.K.topRightCorner(2, nd - 2) * exact.tail(nd - 2));
    CHECK_THAT(uc(0), WithinAbs(exact(0), 1e-14));
    CHECK_THAT(uc(1), WithinAbs(exact(1), 1e-14));
    // every triangle has the stress D eps
    Eigen::VectorXd u = exact;
    u.head(2) = uc;
    const Eigen::Vector3d sig = plane_stress(kMat.E, kMat.nu) * eps;
    const int n = b.nodes - 1;
    for (int i = 0; i < n; ++i) {
      const auto t = fan_triangle(n, i);
      std::array<double, 3> x{}, y{};
      double ut[6];
      for (int c = 0; c < 3; ++c) x[c] = b.x[t[c]], y[c] = b.y[t[c]], ut[2 * c] = u(2 * t[c]), ut[2 * c + 1] = u(2 * t[c] + 1);
      const auto s = cst_stress(cst(x, y), plane_stress(kMat.E, kMat.nu), ut, 0.0);
      CHECK((s - sig).norm() < 1e-9 * sig.norm());
    }
  }
}

TEST_CASE("dyn element: one brick under uniaxial stress matches the closed form", "[dyn][element]") {
  const auto b = bolted_brick(rect_x(), rect_y(), kMat);
  const double w = dyntest::kBrickW, h = dyntest::kBrickH, sigma = 3.0;  // N/mm^2
  // nodes: 0 centre, 1 (-w/2,-h/2), 2 (w/2,-h/2), 3 (w/2,h/2), 4 (-w/2,h/2)
  Eigen::VectorXd f = Eigen::VectorXd::Zero(10);
  f(2 * 3 + 1) = f(2 * 4 + 1) = 0.5 * sigma * w * kMat.thickness;  // consistent load of a uniform traction
  // supports: node 1 fixed (x, y), node 2 fixed in y: no rigid motion, no lateral restraint
  std::vector<int> freed;
  for (int d = 0; d < 10; ++d)
    if (d != 2 && d != 3 && d != 5) freed.push_back(d);
  Eigen::MatrixXd Kf(freed.size(), freed.size());
  Eigen::VectorXd ff(freed.size());
  for (std::size_t i = 0; i < freed.size(); ++i) {
    ff(i) = f(freed[i]);
    for (std::size_t j = 0; j < freed.size(); ++j) Kf(i, j) = b.K(freed[i], freed[j]);
  }
  const Eigen::VectorXd uf = Kf.ldlt().solve(ff);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(10);
  for (std::size_t i = 0; i < freed.size(); ++i) u(freed[i]) = uf(i);
  const double ey = sigma / kMat.E, ex = -kMat.nu * sigma / kMat.E;
  CHECK_THAT(u(2 * 3 + 1), WithinRel(ey * h, 1e-10));   // top elongation sigma h / E
  CHECK_THAT(u(2 * 4 + 1), WithinRel(ey * h, 1e-10));
  CHECK_THAT(u(2 * 2), WithinRel(ex * w, 1e-10));       // lateral contraction -nu sigma w / E
  CHECK_THAT(u(2 * 3), WithinRel(ex * w, 1e-10));
  for (int i = 0; i < 4; ++i) {
    const auto t = fan_triangle(4, i);
    std::array<double, 3> x{}, y{};
    double ut[6];
    for (int c = 0; c < 3; ++c) x[c] = b.x[t[c]], y[c] = b.y[t[c]], ut[2 * c] = u(2 * t[c]), ut[2 * c + 1] = u(2 * t[c] + 1);
    const auto s = cst_stress(cst(x, y), plane_stress(kMat.E, kMat.nu), ut, 0.0);
    CHECK_THAT(s(1), WithinRel(sigma, 1e-10));
    CHECK_THAT(s(0), WithinAbs(0, 1e-9 * sigma));
    CHECK_THAT(s(2), WithinAbs(0, 1e-9 * sigma));
  }
}

TEST_CASE("dyn gather entry: every field round-trips up to the largest interface index", "[dyn][element]") {
  // 25 bits of interface index (a signed int's 24 stopped UE at 2.4 M bricks on an H200:
  // 27,438,515 interfaces at 3.9 M bricks), 1 of side and 3 + 3 of local nodes
  for (const int i : {0, 1, 12345, (1 << 24) - 1, 1 << 24, 27438514, nacre::dyn::kMaxGatherIface - 1})
    for (int side = 0; side < 2; ++side)
      for (int n0 = 0; n0 < 8; ++n0)
        for (int n1 = 0; n1 < 8; ++n1) {
          const auto f = nacre::dyn::gather_fields(nacre::dyn::gather_entry(i, side, n0, n1));
          REQUIRE(f.iface == i);
          REQUIRE(f.side == side);
          REQUIRE(f.n0 == n0);
          REQUIRE(f.n1 == n1);
        }
}
