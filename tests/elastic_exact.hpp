// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The exact minimum of the linearised (small-rotation, elastic) spring network of a specimen: the
// closed form the Monte Carlo and Newton tests check their elastic minima against.
#include <nacre/deck/deck.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/cohesive/quadrature.hpp>
#include <nacre/loading/pattern.hpp>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <catch2/catch_test_macros.hpp>

#include <vector>

namespace nacre::test {

/// Exact minimum of the linearised spring network: E(q) = 1/2 sum_i k L int |B(s) q|^2 ds with
/// small-rotation kinematics, driven dofs prescribed, solved by sparse Cholesky (Eigen).
inline double exact_elastic_energy(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
                                   double D) {
  const int n = static_cast<int>(s.size());
  const loading::Pattern lp{d.load.tension, d.load.bending, d.geometry.width};
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3 * n);
  std::vector<bool> fixed(3 * n, false);
  for (int b = 0; b < n; ++b)
    if (s.drive[b] != geometry::Drive::free) {
      const auto p = loading::rigid_pose(lp, static_cast<int>(s.drive[b]), s.cx[b], s.cy[b], D);
      q(3 * b) = p.x, q(3 * b + 1) = p.y, q(3 * b + 2) = p.t;
      fixed[3 * b] = fixed[3 * b + 1] = fixed[3 * b + 2] = true;
    }
  std::vector<Eigen::Triplet<double>> trip;
  const auto gl = cohesive::gauss_legendre(2);  // exact for a quadratic density
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto& law = f.kind[i] == geometry::JointKind::bed ? d.mortar.bed : d.mortar.head;
    const int dof[6] = {3 * f.a[i], 3 * f.a[i] + 1, 3 * f.a[i] + 2, 3 * f.b[i], 3 * f.b[i] + 1, 3 * f.b[i] + 2};
    for (int k = 0; k < gl.n; ++k) {
      const double sk = gl.s[k];
      const double rax = f.ra0x[i] + sk * (f.ra1x[i] - f.ra0x[i]), ray = f.ra0y[i] + sk * (f.ra1y[i] - f.ra0y[i]);
      const double rbx = f.rb0x[i] + sk * (f.rb1x[i] - f.rb0x[i]), rby = f.rb0y[i] + sk * (f.rb1y[i] - f.rb0y[i]);
      // gap = u_b + t_b (-rby, rbx) - u_a - t_a (-ray, rax)
      const double B[2][6] = {{-1, 0, ray, 1, 0, -rby}, {0, -1, -rax, 0, 1, rbx}};
      const double c = law.k * f.length[i] * gl.w[k];
      for (int r = 0; r < 6; ++r)
        for (int cidx = 0; cidx < 6; ++cidx)
          trip.emplace_back(dof[r], dof[cidx], c * (B[0][r] * B[0][cidx] + B[1][r] * B[1][cidx]));
    }
  }
  Eigen::SparseMatrix<double> K(3 * n, 3 * n);
  K.setFromTriplets(trip.begin(), trip.end());
  // partition into free (f) and fixed (c): K_ff q_f = -K_fc q_c
  std::vector<int> fi, map(3 * n, -1);
  for (int k = 0; k < 3 * n; ++k)
    if (!fixed[k]) map[k] = static_cast<int>(fi.size()), fi.push_back(k);
  std::vector<Eigen::Triplet<double>> tff;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<long>(fi.size()));
  for (int col = 0; col < K.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, col); it; ++it) {
      const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
      if (map[r] < 0) continue;
      if (map[c] >= 0)
        tff.emplace_back(map[r], map[c], it.value());
      else
        rhs(map[r]) -= it.value() * q(c);
    }
  Eigen::SparseMatrix<double> Kff(static_cast<long>(fi.size()), static_cast<long>(fi.size()));
  Kff.setFromTriplets(tff.begin(), tff.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> chol(Kff);
  REQUIRE(chol.info() == Eigen::Success);
  const Eigen::VectorXd qf = chol.solve(rhs);
  for (std::size_t k = 0; k < fi.size(); ++k) q(fi[k]) = qf(static_cast<long>(k));
  return 0.5 * q.dot(K * q);
}

}  // namespace nacre::test
