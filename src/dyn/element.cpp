// SPDX-License-Identifier: BSD-3-Clause
// Element library: CST matrices and bolting (see include/nacre/dyn/element.hpp for the why).
#include <nacre/dyn/element.hpp>
#include <nacre/dyn/model.hpp>

#include <stdexcept>
#include <string>

namespace nacre::dyn {

Eigen::Matrix3d plane_stress(double E, double nu) {
  Eigen::Matrix3d D;
  const double c = E / (1.0 - nu * nu);
  D << c, c * nu, 0, c * nu, c, 0, 0, 0, c * 0.5 * (1.0 - nu);
  return D;
}

Cst cst(const std::array<double, 3>& x, const std::array<double, 3>& y) {
  Cst c;
  const double two_a = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (!(two_a > 0))
    throw std::runtime_error("dyn: triangle with non-positive area " + std::to_string(0.5 * two_a) +
                             " (brick polygon not convex or not counter-clockwise?)");
  c.area = 0.5 * two_a;
  c.B.setZero();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double b = (y[j] - y[k]) / two_a, cc = (x[k] - x[j]) / two_a;
    c.B(0, 2 * i) = b;
    c.B(1, 2 * i + 1) = cc;
    c.B(2, 2 * i) = cc;
    c.B(2, 2 * i + 1) = b;
  }
  return c;
}

ElementMatrices triangle_element(const std::array<double, 3>& x, const std::array<double, 3>& y,
                                 const Material& m) {
  const Cst c = cst(x, y);
  const Eigen::Matrix3d D = plane_stress(m.E, m.nu);
  ElementMatrices e;
  e.nodes = 3;
  const double at = c.area * m.thickness;
  e.K = c.B.transpose() * D * c.B * at;
  e.mass = Eigen::VectorXd::Constant(6, m.rho * at / 3.0);
  const Eigen::Vector3d eps(1.0, 1.0, 0.0);
  e.theta_unit = c.B.transpose() * (D * eps) * at;
  e.x.assign(x.begin(), x.end());
  e.y.assign(y.begin(), y.end());
  return e;
}

namespace {
std::array<double, 3> tri_x(const std::vector<double>& px, int n, int i, bool ycoord,
                            const std::vector<double>& py) {
  const auto t = fan_triangle(n, i);
  std::array<double, 3> r{};
  for (int k = 0; k < 3; ++k) r[k] = t[k] == 0 ? 0.0 : (ycoord ? py : px)[t[k] - 1];
  return r;
}
}  // namespace

std::vector<ElementMatrices> unbolted_brick(const std::vector<double>& px,
                                            const std::vector<double>& py, const Material& m) {
  const int n = static_cast<int>(px.size());
  std::vector<ElementMatrices> out;
  out.reserve(n);
  for (int i = 0; i < n; ++i) out.push_back(triangle_element(tri_x(px, n, i, false, py), tri_x(px, n, i, true, py), m));
  return out;
}

ElementMatrices bolted_brick(const std::vector<double>& px, const std::vector<double>& py,
                             const Material& m) {
  const int n = static_cast<int>(px.size());
  const int nd = 2 * (n + 1);
  ElementMatrices e;
  e.nodes = n + 1;
  e.K = Eigen::MatrixXd::Zero(nd, nd);
  e.mass = Eigen::VectorXd::Zero(nd);
  e.theta_unit = Eigen::VectorXd::Zero(nd);
  e.x.assign(1, 0.0);
  e.y.assign(1, 0.0);
  e.x.insert(e.x.end(), px.begin(), px.end());
  e.y.insert(e.y.end(), py.begin(), py.end());
  const auto tris = unbolted_brick(px, py, m);
  // eq. 4.5: entries of triangle i at its local dof r go to the bolted dof map(r)
  for (int i = 0; i < n; ++i) {
    const auto t = fan_triangle(n, i);
    for (int r = 0; r < 6; ++r) {
      const int R = 2 * t[r / 2] + r % 2;
      e.mass(R) += tris[i].mass(r);
      e.theta_unit(R) += tris[i].theta_unit(r);
      for (int c = 0; c < 6; ++c) e.K(R, 2 * t[c / 2] + c % 2) += tris[i].K(r, c);
    }
  }
  return e;
}

Eigen::Vector3d cst_stress(const Cst& c, const Eigen::Matrix3d& D, const double* u, double eps_th) {
  Eigen::Matrix<double, 6, 1> ue;
  for (int k = 0; k < 6; ++k) ue(k) = u[k];
  Eigen::Vector3d eps = c.B * ue;
  eps(0) -= eps_th;
  eps(1) -= eps_th;
  return D * eps;
}

void triangle_stress(const double x[3], const double y[3], const double u[6], double E, double nu,
                     double eps_th, double sig[3], double& area) {
  const Cst c = cst({x[0], x[1], x[2]}, {y[0], y[1], y[2]});
  const Eigen::Vector3d s = cst_stress(c, plane_stress(E, nu), u, eps_th);
  sig[0] = s(0), sig[1] = s(1), sig[2] = s(2);
  area = c.area;
}

}  // namespace nacre::dyn
