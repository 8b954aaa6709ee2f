// SPDX-License-Identifier: BSD-3-Clause
// Interfaces: forces = -dE/du by finite differences (all branches of the law, UE's internal
// joints included), element forces = -d(1/2 u^T K u)/du, and the quadrature rule along a
// segment against a fine composite reference.
#include "common.hpp"

#include <nacre/dyn/kernels.hpp>

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_floating_point.hpp>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <random>

using namespace dyntest;
using Exec = Kokkos::DefaultExecutionSpace;
using Mem = Exec::memory_space;

namespace {

/// Energies and forces of a model at a host displacement vector x (element-major, x[e * nd + d]).
struct Probe {
  dyn::Model<> m;
  dyn::HostMap map;
  dyn::DofView<Mem> u;
  dyn::IforceView<Mem> f;
  nacre::SumWorkspace<Mem> ws;
  Probe(const dyn::Params& p, const Setup& st, const deck::Mortar& mo) {
    m = dyn::build_model(p, st.s, st.f, mo, map);
    u = dyn::DofView<Mem>("u", m.n_elem, m.nd);
    f = dyn::IforceView<Mem>("f", std::max(m.n_iface, 1));
  }
  [[nodiscard]] int n() const { return m.n_elem * m.nd; }
  void set(const Eigen::VectorXd& x) {
    auto h = Kokkos::create_mirror_view(u);
    for (int e = 0; e < m.n_elem; ++e)
      for (int d = 0; d < m.nd; ++d) h(e, d) = x(e * m.nd + d);
    Kokkos::deep_copy(u, h);
  }
  double cohesive(const Eigen::VectorXd& x) {
    set(x);
    return dyn::cohesive_energy(Exec{}, ws, dyn::InterfaceOp<Mem>(m, u, f), m.n_iface);
  }
  double strain(const Eigen::VectorXd& x) {
    set(x);
    return dyn::element_sum(Exec{}, ws, dyn::StrainEnergy<Mem>{m.type, m.K, u, m.nd}, m.n_elem);
  }
  /// Interface forces assembled on host from the kernel's per-interface rows.
  Eigen::VectorXd iface_force(const Eigen::VectorXd& x) {
    set(x);
    dyn::force(Exec{}, dyn::InterfaceOp<Mem>(m, u, f), m.n_iface);
    auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, f);
    auto he = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.ielem);
    auto hn = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.inode);   // per shape
    auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.ishape);  // interface -> shape
    Eigen::VectorXd F = Eigen::VectorXd::Zero(n());
    for (int i = 0; i < m.n_iface; ++i)
      for (int k = 0; k < 4; ++k) {
        const int e = he(i, k / 2), node = hn(hs(i), k);
        F(e * m.nd + 2 * node) += hf(i, 2 * k);
        F(e * m.nd + 2 * node + 1) += hf(i, 2 * k + 1);
      }
    return F;
  }
  /// -K u per element (the element term of final_integrate).
  Eigen::VectorXd element_force(const Eigen::VectorXd& x) {
    auto K = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.K);
    Eigen::VectorXd F = Eigen::VectorXd::Zero(n());
    for (int e = 0; e < m.n_elem; ++e) {
      const int t = map.elem_type[e];
      for (int i = 0; i < m.nd; ++i)
        for (int j = 0; j < m.nd; ++j) F(e * m.nd + i) -= K(t, i, j) * x(e * m.nd + j);
    }
    return F;
  }
  /// Active dof mask (padding dofs of smaller elements excluded).
  [[nodiscard]] std::vector<int> active() const {
    std::vector<int> a;
    for (int e = 0; e < m.n_elem; ++e)
      for (int d = 0; d < 2 * map.type_nodes[map.elem_type[e]]; ++d) a.push_back(e * m.nd + d);
    return a;
  }
};

}  // namespace

TEST_CASE("dyn interfaces: forces equal -dE/du by central differences on every branch", "[dyn][interface][fd]") {
  // a notched wall with clipped and notch-split bricks; x1 = 0.01, rupture at 0.03 mm
  const auto st = make(wall(3, 4, 1.0));
  const deck::Mortar mo{{7000, 0.01, 0.02}, {5000, 0.008, 0.015}};
  for (auto method : {dyn::Method::be, dyn::Method::ue}) {
    auto p = params(50, method);
    p.dt = 1e-9;
    Probe pr(p, st, mo);
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> U(-0.02, 0.02);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(pr.n());
    for (int k : pr.active()) x(k) = U(rng);
    const Eigen::VectorXd F = pr.iface_force(x), Fe = pr.element_force(x);
    const double h = 1e-8;
    double worst = 0, worst_e = 0;
    for (int k : pr.active()) {
      Eigen::VectorXd xp = x, xm = x;
      xp(k) += h, xm(k) -= h;
      const double fd = -(pr.cohesive(xp) - pr.cohesive(xm)) / (2 * h);
      worst = std::max(worst, std::abs(fd - F(k)));
      const double fde = -(pr.strain(xp) - pr.strain(xm)) / (2 * h);
      worst_e = std::max(worst_e, std::abs(fde - Fe(k)));
    }
    INFO("method " << int(method) << " max|F| " << F.cwiseAbs().maxCoeff() << " worst " << worst);
    CHECK(worst < 1e-5 * F.cwiseAbs().maxCoeff());
    CHECK(worst_e < 1e-6 * Fe.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("dyn interfaces: the energy along a segment is exact on every branch, against a fine reference",
          "[dyn][interface][quadrature]") {
  // two stacked bricks, one bed joint; side a at rest, side b's edge nodes moved so that the
  // jump runs linearly from (dn0, dt0) to (dn1, dt1) along the segment
  const auto st = make(wall(1, 2, 0, 0.0));
  REQUIRE(st.f.size() == 1);
  const deck::Mortar mo{{7000, 0.01, 0.02}, {7000, 0.01, 0.02}};
  auto p = params(1, dyn::Method::be);
  p.dt = 1e-9;
  Probe pr(p, st, mo);
  auto E = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, pr.m.ielem);
  auto N = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, pr.m.inode);
  auto XI = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, pr.m.ixi);
  const double nx = st.f.nx[0], ny = st.f.ny[0], len = st.f.length[0];
  const auto law = mo.bed;
  auto energy_with = [&](int points, double dn0, double dt0, double dn1, double dt1) {
    // nodal values at the edge parameters 0 and 1 from the jump at the segment ends
    const double xb0 = XI(0, 2), xb1 = XI(0, 3);
    auto at_xi = [&](double xi, double v0, double v1) { return v0 + (xi - xb0) / (xb1 - xb0) * (v1 - v0); };
    Eigen::VectorXd x = Eigen::VectorXd::Zero(pr.n());
    for (int k = 0; k < 2; ++k) {
      const double xi = k == 0 ? 0.0 : 1.0, dn = at_xi(xi, dn0, dn1), dt = at_xi(xi, dt0, dt1);
      const int e = E(0, 1), node = N(0, 2 + k);
      const double xi_node = k == 0 ? 0.0 : 1.0;  // node n0 at edge parameter 0, n1 at 1
      (void)xi_node;
      x(e * pr.m.nd + 2 * node) = dn * nx - dt * ny;
      x(e * pr.m.nd + 2 * node + 1) = dn * ny + dt * nx;
    }
    auto saved = pr.m.quad;
    pr.m.quad = cohesive::gauss_legendre(points);
    const double v = pr.cohesive(x);
    pr.m.quad = saved;
    return v;
  };
  auto reference = [&](double dn0, double dt0, double dn1, double dt1) {
    const int panels = 200000;
    double s = 0;
    for (int i = 0; i < panels; ++i) {
      const double t = (i + 0.5) / panels;
      s += cohesive::energy_density(law, dn0 + t * (dn1 - dn0), dt0 + t * (dt1 - dt0));
    }
    return s / panels * len * p.thickness;
  };
  // the law's exact integral (cohesive::integrate), whatever the rule the model holds (its
  // points serve only a damage history): elastic, penetrating, and every branch in one segment
  for (const auto& c :
       {std::array<double, 4>{0.002, 0.001, 0.006, -0.004}, std::array<double, 4>{-0.009, 0.0, -0.002, 0.001},
        std::array<double, 4>{-0.004, 0.003, 0.04, -0.01}}) {
    const double ref = reference(c[0], c[1], c[2], c[3]);
    const double e2 = energy_with(2, c[0], c[1], c[2], c[3]), e4 = energy_with(4, c[0], c[1], c[2], c[3]);
    INFO("reference " << ref << " with a 2-point rule held " << e2 << ", 4 points " << e4);
    CHECK_THAT(e4, Catch::Matchers::WithinRel(ref, 1e-9));
    CHECK(e2 == e4);
  }
}
