// SPDX-License-Identifier: BSD-3-Clause
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

#include <nacre/dyn/kernels.hpp>

#include <Eigen/Dense>

namespace dyntest {

/// omega^2 of the linearised undamped system (elastic
/// interfaces: energy 1/2 k |jump|^2, Hessian k I), free elements only, assembled on the host
/// from the model's own tables (elements + every interface of the model, UE's joints included);
/// the exact explicit critical step is 2 / omega_max.
inline Eigen::VectorXd linear_spectrum(dyn::Params p, const Setup& st, const deck::Mortar& mo) {
  dyn::HostMap map;
  p.dt = 1.0;  // (the step enters only (M + h/2 C)^-1, not used here)
  auto m = dyn::build_model(p, st.s, st.f, mo, map);
  auto K = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.K);
  auto M = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.mass);
  auto E = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.ielem);
  auto N = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.inode);
  auto XI = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.ixi);
  auto L = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.ilen);
  auto KK = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.ikind);
  auto SH = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.ishape);  // interface -> shape
  auto D = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.drive);
  // global dof numbering of the free, active dofs
  std::vector<int> id(static_cast<std::size_t>(m.n_elem) * m.nd, -1);
  int n = 0;
  for (int e = 0; e < m.n_elem; ++e)
    if (D(e) == 0)
      for (int d = 0; d < 2 * map.type_nodes[map.elem_type[e]]; ++d) id[e * m.nd + d] = n++;
  Eigen::MatrixXd Kg = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd Mg(n);
  for (int e = 0; e < m.n_elem; ++e) {
    const int t = map.elem_type[e];
    for (int i = 0; i < m.nd; ++i) {
      const int I = id[e * m.nd + i];
      if (I < 0) continue;
      Mg(I) = M(t, i);
      for (int j = 0; j < m.nd; ++j)
        if (id[e * m.nd + j] >= 0) Kg(I, id[e * m.nd + j]) += K(t, i, j);
    }
  }
  const auto q = cohesive::gauss_legendre(4);
  for (int i = 0; i < m.n_iface; ++i) {
    const double klt = m.laws[KK(SH(i))].k * L(SH(i)) * p.thickness;
    for (int g = 0; g < q.n; ++g) {
      const double xa = XI(SH(i), 0) + q.s[g] * (XI(SH(i), 1) - XI(SH(i), 0)), xb = XI(SH(i), 2) + q.s[g] * (XI(SH(i), 3) - XI(SH(i), 2));
      const double Nn[4] = {-(1 - xa), -xa, 1 - xb, xb};
      for (int c = 0; c < 2; ++c)
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b) {
            const int I = id[E(i, a / 2) * m.nd + 2 * N(SH(i), a) + c], J = id[E(i, b / 2) * m.nd + 2 * N(SH(i), b) + c];
            if (I >= 0 && J >= 0) Kg(I, J) += q.w[g] * klt * Nn[a] * Nn[b];
          }
    }
  }
  const Eigen::VectorXd mis = Mg.cwiseInverse().cwiseSqrt();
  const Eigen::MatrixXd S = mis.asDiagonal() * Kg * mis.asDiagonal();
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S, Eigen::EigenvaluesOnly).eigenvalues();  // omega^2, ascending
}
inline double exact_critical_step(const dyn::Params& p, const Setup& st, const deck::Mortar& mo) {
  return 2.0 / std::sqrt(linear_spectrum(p, st, mo).maxCoeff());
}

/// Index of dof d of element e in the flattened state arrays (LayoutLeft: element fastest).
inline std::size_t at(int ne, int e, int d) { return static_cast<std::size_t>(e) + static_cast<std::size_t>(ne) * d; }

}  // namespace dyntest
