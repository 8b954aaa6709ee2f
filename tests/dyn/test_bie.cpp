// SPDX-License-Identifier: BSD-3-Clause
// BIE: the Jacobian of eq. 4.7 and its inverse, the four J^-1 apply variants agree,
// second-order convergence, stability at 10x BE's critical step, restart and determinism.
#include "common.hpp"

#include <nacre/dyn/bie.hpp>

#include <Eigen/Dense>
#include <catch2/catch_test_macros.hpp>
#include <catch2/generators/catch_generators.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

using namespace dyntest;
using Exec = Kokkos::DefaultExecutionSpace;

namespace {
dyn::Params loaded(double r, dyn::Method m) {
  auto p = params(r, m);
  p.rate = 20.0;  // mm/s
  p.ramp_time = 2e-6;
  p.ramp = dyn::Ramp::smooth;
  p.tension = 0, p.bending = 1;
  return p;
}
double estimate(dyn::Params p, const Setup& st) {
  p.dt = 1.0;
  dyn::HostMap map;
  return dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
}
/// `steps` steps of p with the block-structured J^-1 (index 0) and the dense one (1); checks that
/// u and v agree within `rtol` of their largest entry and returns both runs' energies.
std::vector<dyn::Energies> check_block_vs_dense(const dyn::Params& p, const Setup& st, int steps, double rtol) {
  std::vector<dyn::StateArrays> states;
  std::vector<dyn::Energies> energies;
  for (bool structured : {true, false}) {
    auto q = p;
    q.bie_block_structure = structured;
    dyn::Simulation sim(q, st.s, st.f, mortar());
    REQUIRE(sim.advance(Exec{}, steps));
    states.push_back(sim.save_state());
    energies.push_back(sim.energies());
  }
  for (const char* k : {"u", "v"}) {
    const auto& x = states[0].at(k);
    const auto& y = states[1].at(k);
    REQUIRE(x.size() == y.size());
    double worst = 0, scale = 0;
    std::size_t differ = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      worst = std::max(worst, std::abs(x[i] - y[i])), scale = std::max(scale, std::abs(y[i]));
      differ += !(x[i] == y[i]);
    }
    INFO("array " << k << ": " << differ << " of " << x.size() << " entries differ, worst " << worst << " of " << scale);
    CHECK(scale > 0);
    CHECK(worst <= rtol * scale);
  }
  return energies;
}
/// check_block_vs_dense over 300 steps of a damped run, and its strain and dissipated energies
/// within 1e-8 of the dense form's.
void check_damped_block_vs_dense(const dyn::Params& p, const Setup& st) {
  const auto e = check_block_vs_dense(p, st, 300, 1e-8);
  CHECK(e[0].strain > 0);
  CHECK(e[0].damping_dissipated > 0);
  INFO("strain " << e[0].strain << " vs " << e[1].strain << ", damping " << e[0].damping_dissipated << " vs "
                 << e[1].damping_dissipated);
  CHECK(std::abs(e[0].strain - e[1].strain) <= 1e-8 * e[1].strain);
  CHECK(std::abs(e[0].damping_dissipated - e[1].damping_dissipated) <= 1e-8 * e[1].damping_dissipated);
}
}  // namespace

TEST_CASE("bie: J J^-1 = I for every element type, condition number checked", "[dyn][bie]") {
  const auto st = make(wall(5, 6, 1.5));  // notch: clipped and split pieces, several types
  for (bool damped : {false, true}) {
    auto p = params(500, dyn::Method::bie);
    if (damped) dyn::table_4_2_damping(10206, 500, p.alpha_d, p.beta_d);
    p.dt = 20 * estimate(p, st);
    dyn::HostMap map;
    const auto m = dyn::build_model(p, st.s, st.f, mortar(), map);
    const auto b = dyn::build_bie_tables(m);
    REQUIRE(m.n_types > 1);
    CHECK(b.max_condition > 1);
    CHECK(std::isfinite(b.max_condition));
    const int nd = m.nd, n = 2 * nd;
    auto Jinv = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, b.Jinv);
    auto K = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.K);
    auto M = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.mass);
    for (int t = 0; t < m.n_types; ++t) {
      // eq. 4.7 built here independently, blockwise: [[I + h^2/4 M^-1 K, h^2/4 M^-1 C],
      // [h/2 M^-1 K, I + h/2 M^-1 C]] on the type's active dof (identity on padding)
      Eigen::MatrixXd Km = Eigen::MatrixXd::Zero(nd, nd), Mi = Eigen::MatrixXd::Zero(nd, nd);
      for (int i = 0; i < nd; ++i) {
        Mi(i, i) = M(t, i) > 0 ? 1.0 / M(t, i) : 0.0;
        for (int j = 0; j < nd; ++j) Km(i, j) = K(t, i, j);
      }
      Eigen::MatrixXd Mm = Eigen::MatrixXd::Zero(nd, nd);
      for (int i = 0; i < nd; ++i) Mm(i, i) = M(t, i);
      const Eigen::MatrixXd C = p.alpha_d * Mm + p.beta_d * Km;
      const double h = p.dt;
      Eigen::MatrixXd J(n, n);
      J << Eigen::MatrixXd::Identity(nd, nd) + 0.25 * h * h * Mi * Km, 0.25 * h * h * Mi * C, 0.5 * h * Mi * Km,
          Eigen::MatrixXd::Identity(nd, nd) + 0.5 * h * Mi * C;
      Eigen::MatrixXd Ji(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) Ji(i, j) = Jinv(t, i, j);
      // compare in the dimensionless form D J D^-1 (D = diag(I, h I)): p and v rows have different units
      Eigen::VectorXd d = Eigen::VectorXd::Ones(n);
      d.tail(nd).setConstant(h);
      const Eigen::MatrixXd prod = d.asDiagonal() * (J * Ji) * d.cwiseInverse().asDiagonal();
      const double err = (prod - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff();
      INFO("type " << t << " cond " << b.max_condition << " damped " << damped);
      CHECK(err < 1e-15 * b.max_condition * n);
      CHECK(err < 1e-9);
    }
  }
}

TEST_CASE("bie: the J^-1 apply variants give the same result to rounding", "[dyn][bie]") {
  const auto st = make(wall(6, 6, 2.0));
  for (bool share : {true, false}) {
    auto p = params(500, dyn::Method::bie);
    dyn::table_4_2_damping(10206, 500, p.alpha_d, p.beta_d);
    p.share_element_matrices = share;
    p.dt = 10 * estimate(p, st);
    dyn::HostMap map;
    const auto m = dyn::build_model(p, st.s, st.f, mortar(), map);
    const auto b = dyn::build_bie_tables(m);
    const int n = b.n2, ne = m.n_elem;
    dyn::DofView<Kokkos::DefaultExecutionSpace::memory_space> R("R", ne, n);
    auto Rh = Kokkos::create_mirror(R);  // a separate copy (the mirror view of a host view is itself)
    std::mt19937_64 g(42);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int s = 0; s < ne; ++s)
      for (int j = 0; j < n; ++j) Rh(s, j) = u(g);
    // reference: Eigen product per slot
    auto Jh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, b.Jinv);
    auto ty = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, b.slot_type);
    std::vector<double> ref(static_cast<std::size_t>(ne) * n);
    for (int s = 0; s < ne; ++s)
      for (int i = 0; i < n; ++i) {
        long double y = 0;
        for (int j = 0; j < n; ++j) y += static_cast<long double>(Jh(ty(s), i, j)) * Rh(s, j);
        ref[static_cast<std::size_t>(s) * n + i] = static_cast<double>(y);
      }
    struct V {
      dyn::BieSolve s;
      int nb;
    };
    std::vector<V> vs{{dyn::BieSolve::row, 0},       {dyn::BieSolve::reordered, 2}, {dyn::BieSolve::reordered, 4},
                      {dyn::BieSolve::reordered, 5}, {dyn::BieSolve::reordered, 10}, {dyn::BieSolve::shared_gemm, 0}};
    if (dyn::bie_solve_available(dyn::BieSolve::batched)) vs.push_back({dyn::BieSolve::batched, 0});
    else WARN("Kokkos Kernels not in this build: the batched GEMV variant is skipped");
    for (const auto& v : vs) {
      Kokkos::deep_copy(R, Rh);
      dyn::BieSolveOp<Kokkos::DefaultExecutionSpace::memory_space> op{b.Jinv, b.slot_type, b.tile_start,
                                                                       b.tile_count, R, n};
      dyn::bie_solve(Exec{}, op, v.s, v.nb, ne, static_cast<int>(b.tile_start.extent(0)));
      auto out = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, R);
      double worst = 0, scale = 0;
      for (int s = 0; s < ne; ++s)
        for (int i = 0; i < n; ++i) {
          const double r = ref[static_cast<std::size_t>(s) * n + i];
          worst = std::max(worst, std::abs(out(s, i) - r));
          scale = std::max(scale, std::abs(r));
        }
      INFO("variant " << dyn::bie_solve_name(v.s) << " NB " << v.nb << " share " << share);
      CHECK(worst <= 1e-13 * scale);
    }
  }
  // and whole runs: the same energies to rounding for every variant
  const auto st2 = make(wall(4, 6));
  std::vector<double> strain;
  auto strain_after_300 = [&](const auto& configure) {
    auto p = loaded(500, dyn::Method::bie);
    configure(p);
    p.dt = 10 * estimate(p, st2);
    dyn::Simulation sim(p, st2.s, st2.f, mortar());
    REQUIRE(sim.advance(Exec{}, 300));
    strain.push_back(sim.energies().strain);
  };
  for (auto v : {dyn::BieSolve::row, dyn::BieSolve::reordered, dyn::BieSolve::shared_gemm})
    strain_after_300([v](auto& p) { p.bie_solve = v; });
  // shared_gemm with the dense J^-1 and the full last iteration: the same form as row
  strain_after_300([](auto& p) { p.bie_block_structure = false; });
  INFO("strain row " << strain[0] << " reordered " << strain[1] << " shared_gemm (reduced) " << strain[2]
                     << " shared_gemm (dense) " << strain[3]);
  CHECK(std::abs(strain[1] - strain[0]) <= 1e-12 * strain[0]);
  CHECK(std::abs(strain[3] - strain[0]) <= 1e-12 * strain[0]);
  // C = 0: the reduced last iteration (BieIterFinalLinearTileTag) is the same step in exact
  // arithmetic, not the same operations: it does not fold the rounding of u_1 = p_n + dp
  // (eps |p_n|, large against one step's dp) back into v as the full form does, so 300 steps
  // differ by ~1e-10 relative (the next test bounds it)
  CHECK(std::abs(strain[2] - strain[0]) <= 1e-8 * strain[0]);
}

TEST_CASE("bie: with C = 0 the block-structured J^-1 and the reduced last iteration equal the dense form to rounding",
          "[dyn][bie]") {
  const auto st = make(wall(6, 6, 2.0));
  auto p = loaded(500, dyn::Method::bie);
  p.dt = 10 * estimate(p, st);
  {  // the tables: J^-1 = [[A^-1, 0], [B, I]] with exact zeros and ones
    dyn::HostMap map;
    const auto m = dyn::build_model(p, st.s, st.f, mortar(), map);
    const auto b = dyn::build_bie_tables(m);
    REQUIRE(b.block_lower);
    auto Jh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, b.Jinv);
    int bad = 0;
    for (int t = 0; t < m.n_types; ++t)
      for (int i = 0; i < m.nd; ++i)
        for (int j = 0; j < m.nd; ++j) {
          bad += Jh(t, i, m.nd + j) != 0.0;
          bad += Jh(t, m.nd + i, m.nd + j) != (i == j ? 1.0 : 0.0);
        }
    CHECK(bad == 0);
    // stiffness damping fills the blocks: not this block form (the velocity-first apply, below)
    auto q = p;
    q.alpha_d = 1e5, q.beta_d = 1e-9;
    dyn::HostMap map2;
    CHECK_FALSE(dyn::build_bie_tables(dyn::build_model(q, st.s, st.f, mortar(), map2)).block_lower);
  }
  const auto e = check_block_vs_dense(p, st, 300, 1e-8);
  const double strain[2] = {e[0].strain, e[1].strain};
  CHECK(strain[0] > 0);
  INFO("strain " << strain[0] << " vs " << strain[1] << ", relative difference " << std::abs(strain[0] - strain[1]) / strain[1]);
  // equal to rounding: the full form folds the rounding of u_1 = p_n + dp (eps |p_n|) into v
  // through B G_p each step, the reduced form does not; measured 5e-10 after 300 steps, while
  // changing the J^-1 apply's summation order alone gives < 1e-12 (previous test)
  CHECK(std::abs(strain[0] - strain[1]) <= 1e-8 * strain[1]);
}

TEST_CASE("bie: with mass-proportional damping the block apply equals the dense J^-1 to rounding", "[dyn][bie]") {
  // C = alpha M (Table 4.2's alpha_d, beta_d = 0: inputs/dynamic_bie.toml): J^-1 g = [S^-1 g~;
  // L g~ + g_v / c], g~ = g_p - (b/c) g_v. The tables' dense J^-1 is the exact inverse to rounding,
  // and the tiled block apply (first nd columns, scaled input) follows the dense apply.
  const auto st = make(wall(6, 6, 2.0));
  auto p = loaded(500, dyn::Method::bie);
  p.alpha_d = 1.058e5;
  p.dt = 10 * estimate(p, st);
  {
    dyn::HostMap map;
    const auto m = dyn::build_model(p, st.s, st.f, mortar(), map);
    const auto b = dyn::build_bie_tables(m);
    REQUIRE(b.block_lower);
    CHECK(b.jq > 0);
    CHECK(b.jr < 1);
    CHECK(b.max_identity_error < 1e-10);  // D J D^-1 times the blockwise inverse, against I
  }
  check_damped_block_vs_dense(p, st);
}

TEST_CASE("bie: with stiffness damping the velocity-first apply equals the dense J^-1 to rounding", "[dyn][bie]") {
  // C = alpha M + beta K (Table 4.2): J_p - h/2 J_v = [I, -h/2 I] on the dofs with mass, so the
  // tiled apply forms y_v = Jv [g_p - h/2 g_v; g_v] and y_p = g_p - h/2 g_v + h/2 y_v
  const auto st = make(wall(6, 6, 2.0));  // whole, clipped and notch-split bricks (padded dofs)
  auto p = loaded(500, dyn::Method::bie);
  dyn::table_4_2_damping(10206, 500, p.alpha_d, p.beta_d);
  p.dt = 8 * estimate(p, st);
  p.element_apply = dyn::ElementApply::tiled;  // the fused tiled path on every backend (a GPU's default is per element)
  {
    dyn::HostMap map;
    const auto m = dyn::build_model(p, st.s, st.f, mortar(), map);
    const auto b = dyn::build_bie_tables(m);
    REQUIRE(b.vfirst);
    CHECK_FALSE(b.block_lower);
    REQUIRE(b.Jv.extent(1) == static_cast<std::size_t>(m.nd));
    REQUIRE(b.Jv.extent(2) == static_cast<std::size_t>(2 * m.nd));
    // Jv against J^-1 itself, on a random g: J^-1 g = [g~_p + h/2 Jv g~; Jv g~] (host, every type)
    const auto Jh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, b.Jinv);
    const auto Vh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, b.Jv);
    const auto Mh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.mass);
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> U(-1, 1);
    const int nd = m.nd;
    for (int t = 0; t < m.n_types; ++t) {
      std::vector<double> g(2 * nd), gt(2 * nd), dense(2 * nd, 0.0), yv(nd, 0.0);
      for (int i = 0; i < nd; ++i) g[i] = U(gen), g[nd + i] = U(gen) / m.h;  // velocities scaled like positions / h
      gt = g;
      for (int i = 0; i < nd; ++i)
        if (Mh(t, i) > 0) gt[i] -= 0.5 * m.h * g[nd + i];
      for (int i = 0; i < 2 * nd; ++i)
        for (int j = 0; j < 2 * nd; ++j) dense[i] += Jh(t, i, j) * g[j];
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < 2 * nd; ++j) yv[i] += Vh(t, i, j) * gt[j];
      double worst = 0, scale = 0;
      for (int i = 0; i < nd; ++i) {
        const double yp = gt[i] + (Mh(t, i) > 0 ? 0.5 * m.h : 0.0) * yv[i];
        worst = std::max({worst, std::abs(yp - dense[i]), m.h * std::abs(yv[i] - dense[nd + i])});
        scale = std::max({scale, std::abs(dense[i]), m.h * std::abs(dense[nd + i])});
      }
      INFO("type " << t << ": worst " << worst << " of " << scale);
      CHECK(worst <= 1e-10 * scale);
    }
  }
  check_damped_block_vs_dense(p, st);
}

TEST_CASE("bie: strain energy converges at second order in the step", "[dyn][bie]") {
  const auto st = make(wall(3, 4));
  // undamped; mass-proportional damping (Table 4.2's alpha_d); the same with the force re-evaluated;
  // the split step (BieScheme::split) with mass-proportional damping.
  // (Table 4.2's beta_d makes the brick's highest modes overdamped far beyond 2 / h: implicit
  // midpoint is not L-stable and lets them ring with factor ~ -1, so the asymptotic range starts
  // only at h beta omega_max^2 < 2; docs/methods.md, "where BIE fails".)
  const int mode = GENERATE(0, 1, 2, 3);
  auto p = loaded(500, dyn::Method::bie);
  if (mode > 0) p.alpha_d = 1.058e5;
  p.bie_reuse_force = mode != 2;
  if (mode == 3) p.bie_scheme = dyn::BieScheme::split;
  const double H = 8 * estimate(p, st);
  const double T = 256 * H;  // ramp and some vibration, elastic throughout
  p.ramp_time = 0.5 * T;
  // strain-energy history at 8 times; error = max over them (one time alone can sit on a zero
  // crossing of the error)
  auto run = [&](double h) {
    auto q = p;
    q.dt = h;
    dyn::Simulation sim(q, st.s, st.f, mortar());
    std::vector<double> e;
    const long n = std::lround(T / h);
    for (int k = 1; k <= 8; ++k) {
      REQUIRE(sim.advance(Exec{}, n / 8));
      e.push_back(sim.energies().strain);
    }
    REQUIRE(sim.ruptured() == 0);
    return e;
  };
  const auto refh = run(H / 32);
  const double ref = refh.back();
  std::vector<double> hs{H, H / 2, H / 4}, err;
  for (double h : hs) {
    const auto e = run(h);
    double m = 0;
    for (std::size_t k = 0; k < e.size(); ++k) m = std::max(m, std::abs(e[k] - refh[k]));
    err.push_back(m);
  }
  // least-squares slope of log err against log h
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < hs.size(); ++k) {
    const double x = std::log(hs[k]), y = std::log(err[k]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double nk = static_cast<double>(hs.size());
  const double order = (nk * sxy - sx * sy) / (nk * sxx - sx * sx);
  INFO("mode " << mode << " errors " << err[0] << " " << err[1] << " " << err[2] << " ref " << ref << " order " << order);
  CHECK(order > 1.8);
  CHECK(order < 2.2);
}

TEST_CASE("bie: stable at 10x BE's critical step (ratio 500), BE is not", "[dyn][bie][stability]") {
  const auto st = make(wall(4, 6));
  auto pb = loaded(500, dyn::Method::be);
  pb.dt = estimate(pb, st);
  const double hbe = dyn::critical_step(pb, st.s, st.f, mortar(), 1000, 0.05);
  auto p = loaded(500, dyn::Method::bie);
  p.dt = 10 * hbe;
  dyn::Simulation sim(p, st.s, st.f, mortar());
  const bool ok = sim.advance(Exec{}, 4000);
  INFO(sim.why() << " hBE " << hbe);
  REQUIRE(ok);
  const auto e = sim.energies();
  INFO("W " << e.external_work << " S " << e.strain << " K " << e.kinetic << " res " << e.balance_residual
            << " newton residual " << sim.bie_residual() << " cond " << sim.jacobian_condition());
  CHECK(e.strain > 0);
  CHECK(e.kinetic <= e.external_work);
  CHECK(std::abs(e.balance_residual) < 0.05);
  CHECK(sim.jacobian_condition() > 1);
  // with the interface force re-evaluated at x_{n+1}: the same run, and what the neglected
  // interface Jacobian leaves unconverged after two iterations is small
  auto px = p;
  px.bie_reuse_force = false;
  dyn::Simulation sx(px, st.s, st.f, mortar());
  REQUIRE(sx.advance(Exec{}, 4000));
  INFO("newton residual " << sx.bie_residual() << " strain " << sx.energies().strain);
  CHECK(sx.bie_residual() < 1e-2);
  CHECK(sx.bie_residual() > 0);
  CHECK(std::abs(sx.energies().strain - e.strain) <= 1e-9 * e.strain);  // C = 0: the same scheme
  // the same step is far beyond BE's critical step: the explicit method blows up and says so
  pb.dt = 10 * hbe;
  dyn::Simulation be(pb, st.s, st.f, mortar());
  CHECK_FALSE(be.advance(Exec{}, 4000));
  CHECK(!be.why().empty());
}

TEST_CASE("bie: with Table 4.2's stiffness damping two iterations limit the step, more restore it",
          "[dyn][bie][stability]") {
  // Heavily stiffness-damped brick modes (h beta omega^2 >> 1) make the two iterations with the
  // constant J (interface Jacobian neglected) converge slowly: the truncated iteration, not the
  // method, sets BIE's limit (docs/methods.md "Damped"); bie_iterations = 4 lifts it.
  const auto st = make(wall(4, 6));
  auto p = loaded(500, dyn::Method::bie);
  dyn::table_4_2_damping(10206, 500, p.alpha_d, p.beta_d);
  p.dt = 10 * estimate(loaded(500, dyn::Method::be), st);
  std::vector<double> hc;
  for (int it : {2, 4}) {
    auto q = p;
    q.bie_iterations = it;
    hc.push_back(dyn::critical_step(q, st.s, st.f, mortar(), 1000, 0.05));
  }
  auto p0 = p;
  p0.alpha_d = p0.beta_d = 0;
  const double h0 = dyn::critical_step(p0, st.s, st.f, mortar(), 1000, 0.05);
  INFO("critical step: 2 iterations " << hc[0] << ", 4 iterations " << hc[1] << ", undamped " << h0);
  CHECK(hc[0] < 0.6 * h0);
  CHECK(hc[1] > 1.5 * hc[0]);
  // at 1.4x the two-iteration limit: four iterations run 4000 steps stable, two blow up
  for (int it : {4, 2}) {
    auto q = p;
    q.bie_iterations = it;
    q.dt = 1.4 * hc[0];
    dyn::Simulation sim(q, st.s, st.f, mortar());
    const bool ok = sim.advance(Exec{}, 4000);
    INFO("iterations " << it << ": " << sim.why());
    CHECK(ok == (it == 4));
  }
}

TEST_CASE("bie: the split step equals eq. 4.6's step to rounding when C = 0", "[dyn][bie][split]") {
  // Undamped, the converged eq. 4.6 (trapezoidal elastic part, interface force explicit in p and
  // trapezoidal in v) and kick / midpoint / kick are the same map (docs/methods.md "The split
  // step"); both at 10x BE's step on a loaded wall, 3000 steps.
  const auto st = make(wall(4, 6));
  auto p = loaded(500, dyn::Method::bie);
  p.dt = 10 * estimate(loaded(500, dyn::Method::be), st);
  std::vector<dyn::StateArrays> s;
  std::vector<dyn::Energies> e;
  for (auto scheme : {dyn::BieScheme::iterate, dyn::BieScheme::split}) {
    auto q = p;
    q.bie_scheme = scheme;
    dyn::Simulation sim(q, st.s, st.f, mortar());
    REQUIRE(sim.advance(Exec{}, 3000));
    s.push_back(sim.save_state());
    e.push_back(sim.energies());
    if (scheme == dyn::BieScheme::split) CHECK(sim.bie_residual() == 0.0);  // nothing iterated
  }
  // (a = M^-1 (F - K p) cancels ~1e6-fold on these stiff bricks: its rounding is not the scheme's)
  for (const char* k : {"u", "v"}) {
    const auto& x = s[0].at(k);
    const auto& y = s[1].at(k);
    double worst = 0, scale = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      worst = std::max(worst, std::abs(x[i] - y[i])), scale = std::max(scale, std::abs(x[i]));
    INFO("array " << k << " worst " << worst << " of " << scale);
    CHECK(scale > 0);
    CHECK(worst <= 1e-8 * scale);  // measured 6e-13 (u) and 9e-10 (v)
  }
  INFO("strain " << e[0].strain << " vs " << e[1].strain << ", residual " << e[1].balance_residual);
  CHECK(std::abs(e[0].strain - e[1].strain) <= 1e-9 * e[0].strain);
  CHECK(std::abs(e[1].balance_residual) < 0.05);
}

TEST_CASE("bie: with Table 4.2's stiffness damping the split step keeps the undamped step", "[dyn][bie][split][stability]") {
  // The split step treats K and C by implicit midpoint exactly (one J^-1 apply), so heavily
  // damped brick modes cannot limit it: its critical step is the interface's, as without damping,
  // where the two-iteration scheme loses more than 40 % (the test above).
  const auto st = make(wall(4, 6));
  auto p = loaded(500, dyn::Method::bie);
  dyn::table_4_2_damping(10206, 500, p.alpha_d, p.beta_d);
  p.dt = 10 * estimate(loaded(500, dyn::Method::be), st);
  auto ps = p;
  ps.bie_scheme = dyn::BieScheme::split;
  const double h2 = dyn::critical_step(p, st.s, st.f, mortar(), 1000, 0.05);
  const double hs = dyn::critical_step(ps, st.s, st.f, mortar(), 1000, 0.05);
  auto p0 = ps;
  p0.alpha_d = p0.beta_d = 0;
  const double h0 = dyn::critical_step(p0, st.s, st.f, mortar(), 1000, 0.05);
  INFO("critical step: two iterations " << h2 << ", split " << hs << ", split undamped " << h0);
  CHECK(hs >= 0.9 * h0);
  CHECK(hs > 1.6 * h2);
  // at 1.4x the two-iteration limit the split runs 4000 steps stable with a closed energy balance
  ps.dt = 1.4 * h2;
  dyn::Simulation sim(ps, st.s, st.f, mortar());
  const bool ok = sim.advance(Exec{}, 4000);
  INFO(sim.why());
  REQUIRE(ok);
  const auto e = sim.energies();
  INFO("W " << e.external_work << " D " << e.damping_dissipated << " res " << e.balance_residual);
  CHECK(e.damping_dissipated > 0);
  CHECK(std::abs(e.balance_residual) < 1e-2);
}

TEST_CASE("bie: with Table 4.2's damping the split step converges at second order to BE's solution",
          "[dyn][bie][split]") {
  // An independent reference for the damped split step: BE (explicit, C through (M + h/2 C)^-1)
  // at a quarter of its undamped critical step solves the same equations; the split's strain-energy
  // history converges to it at second order from half its own critical step down, so a wrong
  // alpha or beta term (which would converge to another solution) fails here.
  const auto st = make(wall(3, 4));
  auto p = loaded(500, dyn::Method::bie);
  dyn::table_4_2_damping(10206, 500, p.alpha_d, p.beta_d);
  p.bie_scheme = dyn::BieScheme::split;
  p.dt = 10 * estimate(loaded(500, dyn::Method::be), st);
  const double H = 0.5 * dyn::critical_step(p, st.s, st.f, mortar(), 1000, 0.05);
  const double T = 64 * H;
  p.ramp_time = 0.5 * T;
  auto history = [&](dyn::Params q, double h) {
    const long n = 8 * std::lround(std::ceil(T / h / 8));
    q.dt = T / static_cast<double>(n);
    dyn::Simulation sim(q, st.s, st.f, mortar());
    std::vector<double> e;
    for (int k = 1; k <= 8; ++k) {
      REQUIRE(sim.advance(Exec{}, n / 8));
      e.push_back(sim.energies().strain);
    }
    return e;
  };
  auto pb = p;
  pb.method = dyn::Method::be;
  auto pb0 = pb;
  pb0.alpha_d = pb0.beta_d = 0;
  pb0.dt = estimate(pb0, st);
  const double hbe = dyn::critical_step(pb0, st.s, st.f, mortar(), 1000, 0.05);
  const auto ref = history(pb, 0.25 * hbe);
  double scale = 0;
  for (double x : ref) scale = std::max(scale, std::abs(x));
  std::vector<double> hs{H, H / 2, H / 4}, err;
  for (double h : hs) {
    const auto e = history(p, h);
    double m = 0;
    for (std::size_t k = 0; k < e.size(); ++k) m = std::max(m, std::abs(e[k] - ref[k]));
    err.push_back(m / scale);
  }
  const double order = std::log(err[0] / err[2]) / std::log(4.0);
  INFO("H " << H << " (BE critical " << hbe << "), errors " << err[0] << " " << err[1] << " " << err[2] << ", order "
            << order);
  CHECK(err[0] < 1e-2);
  CHECK(err[2] < err[1]);
  CHECK(err[1] < err[0]);
  CHECK(order > 1.8);
  CHECK(order < 2.2);
}

TEST_CASE("bie: energy balance closes with damping, save_state / restore_state bit for bit", "[dyn][bie][restart]") {
  const auto st = make(wall(3, 4));
  auto p = loaded(50, dyn::Method::bie);
  p.bie_scheme = GENERATE(dyn::BieScheme::iterate, dyn::BieScheme::split);
  dyn::table_4_2_damping(10206, 50, p.alpha_d, p.beta_d);
  p.dt = 4 * estimate(p, st);
  dyn::Simulation a(p, st.s, st.f, mortar());
  REQUIRE(a.advance(Exec{}, 200));
  const auto saved = a.save_state();
  const auto e200 = a.energies();
  UNSCOPED_INFO("at the save: W " << e200.external_work << " S " << e200.strain << " K " << e200.kinetic << " C "
                << e200.cohesive << " D " << e200.damping_dissipated << " res " << e200.balance_residual);
  REQUIRE(a.advance(Exec{}, 300));
  const auto e = a.energies();
  INFO("W " << e.external_work << " D " << e.damping_dissipated << " res " << e.balance_residual);
  CHECK(e.damping_dissipated > 0);
  CHECK(std::abs(e.balance_residual) < 1e-2);
  dyn::Simulation b(p, st.s, st.f, mortar());
  b.restore_state(saved);
  REQUIRE(b.advance(Exec{}, 300));
  const auto sa = a.save_state(), sb = b.save_state();
  for (const auto& [k, v] : sa) CHECK(v == sb.at(k));
}

namespace {
std::uint64_t fnv(const std::vector<double>& v, std::uint64_t h = 1469598103934665603ull) {
  for (double x : v) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, 8);
    for (int k = 0; k < 8; ++k) h = (h ^ ((bits >> (8 * k)) & 0xff)) * 1099511628211ull;
  }
  return h;
}
}  // namespace

TEST_CASE("bie: a cracking run is bit-identical for any thread count", "[bie-determinism]") {
  const auto st = make(wall(6, 6, 2.5));
  const deck::Mortar weak{{7000, 0.0005, 0.001}, {7000, 0.0005, 0.001}};
  std::ostringstream prints;
  // shared_gemm undamped: J^-1 applied blockwise (BieTables::block_lower)
  for (int run = 0; run < 3; ++run) {
    const auto v = run == 0 ? dyn::BieSolve::row : dyn::BieSolve::shared_gemm;
    auto p = params(100, dyn::Method::bie);
    p.rate = 2000.0, p.ramp_time = 1e-6, p.ramp = dyn::Ramp::smooth;
    p.tension = 0.2, p.bending = 1;
    if (run < 2) p.alpha_d = 1e5, p.beta_d = 1e-9;
    p.bie_solve = v;
    p.dt = 1.0;
    dyn::HostMap map;
    p.dt = 4 * dyn::build_model(p, st.s, st.f, weak, map).step_estimate;
    dyn::Simulation sim(p, st.s, st.f, weak);
    const bool ok = sim.advance(Exec{}, 600);
    INFO(sim.why());
    REQUIRE(ok);
    INFO("ruptured " << sim.ruptured() << " D " << sim.displacement());
    CHECK(sim.ruptured() > 0);
    const auto s = sim.save_state();
    const auto e = sim.energies();
    std::uint64_t h = fnv(s.at("u"));
    h = fnv(s.at("v"), h);
    h = fnv(s.at("acc"), h);
    h = fnv({e.strain, e.kinetic, e.cohesive, e.external_work, e.damping_dissipated, sim.reaction()}, h);
    prints << dyn::bie_solve_name(v) << (run == 2 ? " undamped " : " ") << sim.ruptured() << " " << std::hex << h << std::dec << "\n";
  }
  if (const char* out = std::getenv("NACRE_HASH_OUT")) std::ofstream(out) << prints.str();
}

TEST_CASE("bie: a notched wall cracks from the notch tip at 10x BE's critical step", "[dyn][bie]") {
  const auto g = wall(8, 8, 3.0);  // notch 3 bricks long on the mid-height bed joint
  const auto st = make(g);
  const deck::Mortar weak{{7000, 0.0005, 0.001}, {7000, 0.0005, 0.001}};
  auto pb = params(500, dyn::Method::be);
  pb.rate = 2000.0, pb.ramp_time = 1e-6, pb.ramp = dyn::Ramp::smooth, pb.tension = 0, pb.bending = 1;
  pb.dt = 1.0;
  dyn::HostMap map;
  pb.dt = dyn::build_model(pb, st.s, st.f, weak, map).step_estimate;
  const double hbe = dyn::critical_step(pb, st.s, st.f, weak, 1000, 0.05);
  auto p = pb;
  p.method = dyn::Method::bie;
  p.dt = 10 * hbe;
  dyn::Simulation sim(p, st.s, st.f, weak);
  long steps = 0;
  while (sim.ruptured() == 0 && steps < 20000) {
    const bool ok = sim.advance(Exec{}, 50);
    INFO(sim.why());
    REQUIRE(ok);
    steps += 50;
  }
  INFO("steps " << steps << " dt " << p.dt << " hBE " << hbe << " D " << sim.displacement());
  REQUIRE(sim.ruptured() > 0);
  // every ruptured interface lies at the notch tip (within one brick length of it)
  const auto snap = sim.snapshot();
  const double tipx = g.notch_length, tipy = g.notch_y;
  int near = 0, ruptured = 0;
  for (std::size_t i = 0; i < st.f.size(); ++i) {
    if (snap.iface_state[i] != 2) continue;
    ++ruptured;
    const int a = st.f.a[i];
    const double mx = st.s.cx[a] + 0.5 * (st.f.ra0x[i] + st.f.ra1x[i]);
    const double my = st.s.cy[a] + 0.5 * (st.f.ra0y[i] + st.f.ra1y[i]);
    near += std::hypot(mx - tipx, my - tipy) < g.brick_width;
  }
  CHECK(ruptured > 0);
  CHECK(near == ruptured);
  const auto e = sim.energies();
  CHECK(std::abs(e.balance_residual) < 0.05);
}
