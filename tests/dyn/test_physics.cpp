// SPDX-License-Identifier: BSD-3-Clause
// Physics of the explicit integrators against exact answers: free thermal expansion, static
// response to a prescribed force, the frequency of a bar of bricks, energy conservation over
// 1e5 steps, the critical step against 2/omega_max of the linearised system, and the quadrature
// rule along an interface against a fine reference.
//
// Tests tagged [.tiny] run models of a few bricks for 1e3-1e5 steps: they are bound by kernel
// launch latency, not work, so CTest runs them on one thread (tests/CMakeLists.txt); they are
// hidden from the default discovery.
#include "common.hpp"

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_floating_point.hpp>

#include <cmath>
#include <numbers>

using namespace dyntest;
using Exec = Kokkos::DefaultExecutionSpace;

namespace {
/// One free brick (no interfaces).
Setup single_brick() {
  Setup st;
  st.s = geometry::build_specimen(wall(1, 1));
  for (auto& d : st.s.drive) d = geometry::Drive::free;
  return st;
}
int elements(const dyn::StateArrays& s) { return static_cast<int>(s.at("shape")[0]); }
int dofs(const dyn::StateArrays& s) { return static_cast<int>(s.at("shape")[1]); }
}  // namespace

TEST_CASE("dyn physics: a free brick with an eigenstrain expands by eps L with zero stress", "[dyn][physics][thermal][.tiny]") {
  const auto st = single_brick();
  REQUIRE(st.s.size() == 1);
  for (int variant : {0, 1, 2}) {  // BE, UE, BIE's split step (damped: the deck default)
    const auto method = variant == 0 ? dyn::Method::be : (variant == 1 ? dyn::Method::ue : dyn::Method::bie);
    auto p = params(1, method);
    if (method == dyn::Method::bie) p.bie_scheme = dyn::BieScheme::split;
    p.thermal_strain = 1e-3;
    p.alpha_d = 2e7;  // mass-proportional damping brings it to rest
    p.dt = 1.0;
    dyn::HostMap map;
    p.dt = 0.5 * dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
    dyn::Simulation sim(p, st.s, st.f, mortar());
    REQUIRE(sim.advance(Exec{}, 6000));
    const auto snap = sim.snapshot();
    double err = 0, smax = 0;
    for (std::size_t k = 0; k < snap.ux.size(); ++k) {
      err = std::max(err, std::abs(snap.ux[k] - p.thermal_strain * (snap.node_x[k] - st.s.cx[0])));
      err = std::max(err, std::abs(snap.uy[k] - p.thermal_strain * (snap.node_y[k] - st.s.cy[0])));
    }
    for (std::size_t t = 0; t < snap.tri_sxx.size(); ++t)
      smax = std::max({smax, std::abs(snap.tri_sxx[t]), std::abs(snap.tri_syy[t]), std::abs(snap.tri_sxy[t])});
    INFO("method " << int(method) << " err " << err << " smax " << smax);
    CHECK(err < 1e-9 * p.thermal_strain * kBrickW);
    CHECK(smax < 1e-8 * p.youngs_modulus * p.thermal_strain);
  }
}

TEST_CASE("dyn physics: a force on the top edge gives the closed-form static displacement", "[dyn][physics][force][.tiny]") {
  // two bricks stacked (nu = 0): the bottom one driven at D = 0, the top one free under a line
  // load f: uniform stress sigma = f / t, joint opening sigma / k, top edge at sigma/k + sigma h/E.
  auto g = wall(1, 2, 0, 0.0);
  const auto st = make(g);
  REQUIRE(st.s.size() == 2);
  for (auto method : {dyn::Method::be, dyn::Method::bie}) {  // BIE: the split step (damped)
  INFO("method " << int(method));
  auto p = params(1, method);
  if (method == dyn::Method::bie) p.bie_scheme = dyn::BieScheme::split;
  p.poisson = 0;
  p.force_top = 10.0;  // N/mm, below k x1 = 70.6 N/mm^2: the joint stays elastic
  p.alpha_d = 1.6e7, p.beta_d = 2e-9;
  p.dt = 1.0;
  dyn::HostMap map;
  p.dt = 0.8 * dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
  dyn::Simulation sim(p, st.s, st.f, mortar());
  REQUIRE(sim.advance(Exec{}, 20000));
  const auto snap = sim.snapshot();
  const double sigma = p.force_top / p.thickness, k = mortar().bed.k;
  const double top = sigma / k + sigma * kBrickH / p.youngs_modulus;
  int checked = 0;
  for (std::size_t n = 0; n < snap.uy.size(); ++n)
    if (std::abs(snap.node_y[n] - g.height) < 1e-12) {
      CHECK_THAT(snap.uy[n], Catch::Matchers::WithinRel(top, 1e-8));
      ++checked;
    }
  CHECK(checked == 2);
  for (std::size_t t = 0; t < snap.tri_brick.size(); ++t)
    if (snap.tri_brick[t] == (st.s.cy[0] > st.s.cy[1] ? 0 : 1)) CHECK_THAT(snap.tri_syy[t], Catch::Matchers::WithinRel(sigma, 1e-8));
  }
}

TEST_CASE("dyn physics: the reaction of a driven column matches the closed form, the damped balance closes",
          "[dyn][physics][reaction][.tiny]") {
  // three bricks stacked (nu = 0), bottom and top driven apart by D (tension), the middle one
  // free: at rest the stress sigma is uniform, D = 2 sigma / k + sigma h / E (two joints and one
  // brick in series), and the reaction on the top edge is sigma W t.
  const auto st = make(wall(1, 3, 0, 0.0));
  REQUIRE(st.s.size() == 3);
  for (auto method : {dyn::Method::be, dyn::Method::ue, dyn::Method::bie}) {  // BIE: the split step (damped)
    auto p = params(1, method);
    if (method == dyn::Method::bie) p.bie_scheme = dyn::BieScheme::split;
    p.poisson = 0;
    p.tension = 1, p.bending = 0;
    p.rate = 50, p.ramp_time = 2e-6, p.ramp = dyn::Ramp::smooth, p.final_displacement = 1e-4;
    p.alpha_d = 1.6e7;
    p.dt = 1.0;
    dyn::HostMap map;
    p.dt = 0.8 * dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
    dyn::Simulation sim(p, st.s, st.f, mortar());
    const long n = method == dyn::Method::ue ? 60000 : 20000;
    REQUIRE(sim.advance(Exec{}, n));
    REQUIRE(sim.displacement() == p.final_displacement);
    const double k = mortar().bed.k, E = p.youngs_modulus;
    double sigma = p.final_displacement / (2 / k + kBrickH / E);
    if (method == dyn::Method::ue) {
      // UE: the free brick's internal joints (stiffness k_int on the two diagonals) add the
      // compliance of a uniform stress crossing them; measured against BE's exact value below
      sigma = 0;
    }
    const double R = sim.reaction();
    const auto e = sim.energies();
    INFO("method " << int(method) << " reaction " << R << " closed form " << p.final_displacement / (2 / k + kBrickH / E) * kBrickW
                   << " balance residual " << e.balance_residual << " kinetic " << e.kinetic);
    if (sigma > 0) CHECK_THAT(R, Catch::Matchers::WithinRel(sigma * kBrickW * p.thickness, 1e-6));
    else CHECK_THAT(R, Catch::Matchers::WithinRel(p.final_displacement / (2 / k + kBrickH / E) * kBrickW, 2e-2));
    CHECK(e.kinetic < 1e-8 * e.external_work);
    // the work of the machine (including the impulsive stop at final_displacement) equals strain
    // + cohesive energy + damping loss up to the Verlet error of the potential energy
    CHECK(std::abs(e.balance_residual) < 1e-4);
  }
}

TEST_CASE("dyn physics: a bar of bricks vibrates at the analytical bar frequency", "[dyn][physics][vibration]") {
  // N bricks stacked (free-free, nu = 0): a bar of modulus E_eff = h / (h/E + 1/k) (bricks and
  // bed joints in series, joints massless), first frequency omega = pi c / L, c = sqrt(E_eff/rho).
  const int nb = 24;
  auto st = make(wall(1, nb, 0, 0.0));
  REQUIRE(st.s.size() == static_cast<std::size_t>(nb));
  for (auto& d : st.s.drive) d = geometry::Drive::free;
  auto p = params(1, dyn::Method::be);
  p.poisson = 0;
  p.dt = 1.0;
  dyn::HostMap map;
  p.dt = 0.5 * dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
  dyn::Simulation sim(p, st.s, st.f, mortar());
  const double L = nb * kBrickH, k = mortar().bed.k;
  const double Eeff = kBrickH / (kBrickH / p.youngs_modulus + 1.0 / k);
  const double omega = std::numbers::pi / L * std::sqrt(Eeff / p.density);
  // initial velocity in the first mode, small enough to stay elastic
  auto s0 = sim.save_state();
  const auto snap0 = sim.snapshot();
  const int ne = elements(s0), nd = dofs(s0), nn = nd / 2;
  for (int e = 0; e < ne; ++e)
    for (int j = 0; j < nn; ++j) s0["v"][at(ne, e, 2 * j + 1)] = 1.0 * std::cos(std::numbers::pi * snap0.node_y[e * nn + j] / L);
  sim.restore_state(s0);
  // elongation signal: mean u_y of the top edge minus that of the bottom edge; zero crossings
  std::vector<double> tz;
  double prev = 0;
  const int per_step = 1;
  for (int n = 0; n < 4000 && tz.size() < 7; ++n) {
    REQUIRE(sim.advance(Exec{}, per_step));
    const auto sn = sim.snapshot();
    double top = 0, bot = 0;
    int ct = 0, cb = 0;
    for (std::size_t q = 0; q < sn.uy.size(); ++q) {
      if (sn.node_y[q] > L - 1e-12) top += sn.uy[q], ++ct;
      if (sn.node_y[q] < 1e-12) bot += sn.uy[q], ++cb;
    }
    const double el = top / ct - bot / cb;
    if (n > 0 && ((prev < 0) != (el < 0))) tz.push_back(sim.time() - p.dt * el / (el - prev));
    prev = el;
  }
  REQUIRE(tz.size() >= 7);
  const double period = (tz[6] - tz[0]) / 3.0;
  const double measured = 2 * std::numbers::pi / period;
  INFO("omega measured " << measured << " analytical " << omega << " rel " << measured / omega - 1);
  // error budget: spatial discretisation of the mode (lumped masses at 3 levels per brick,
  // O((pi/N)^2) ~ 1e-3 here) plus the Verlet phase error (omega h)^2/24 < 1e-4.
  CHECK(std::abs(measured / omega - 1) < 5e-3);
}

TEST_CASE("dyn physics: undamped, unruptured runs conserve energy over 1e5 steps", "[dyn][physics][energy][.tiny]") {
  const auto st = make(wall(2, 3));
  for (auto method : {dyn::Method::be, dyn::Method::ue}) {
    auto p = params(50, method);
    p.dt = 1.0;
    dyn::HostMap map;
    p.dt = 0.5 * dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
    dyn::Simulation sim(p, st.s, st.f, mortar());
    // initial velocities on the free elements (driven ones stay at D = 0): a smooth field
    auto s0 = sim.save_state();
    const auto snap0 = sim.snapshot();
    const int ne = elements(s0), nd = dofs(s0), nn = nd / 2;
    auto drive_of = [&](int e) { return st.s.drive[snap0.tri_brick[method == dyn::Method::be ? 4 * e : e]]; };
    for (int e = 0; e < ne; ++e) {
      if (drive_of(e) != geometry::Drive::free) continue;
      for (int j = 0; j < nn; ++j) {
        const double x = snap0.node_x[e * nn + j], y = snap0.node_y[e * nn + j];
        s0["v"][at(ne, e, 2 * j)] = 2.0 * std::sin(40 * y + 3 * x);
        s0["v"][at(ne, e, 2 * j + 1)] = 2.0 * std::cos(25 * x - 7 * y);
      }
    }
    sim.restore_state(s0);
    auto total = [&] {
      const auto e = sim.energies();
      return e.strain + e.kinetic + e.cohesive;
    };
    const double e0 = total();
    REQUIRE(e0 > 0);
    // deviation |E - E0| / E0 sampled every 100 steps: its maximum over the first 1e4 steps
    // (many periods of the lowest mode) and over the last 5e4 steps
    double early = 0, late = 0;
    const int chunk = 100, chunks = 1000;  // 1e5 steps
    for (int c = 0; c < chunks; ++c) {
      REQUIRE(sim.advance(Exec{}, chunk));
      const double dev = std::abs(total() - e0) / e0;
      if (c < 100) early = std::max(early, dev);
      if (c >= chunks / 2) late = std::max(late, dev);
    }
    REQUIRE(sim.steps() == 100000);
    CHECK(sim.ruptured() == 0);
    CHECK(sim.energies().external_work == 0);
    INFO("method " << int(method) << " E0 " << e0 << " max deviation first 1e4 steps " << early
                   << ", last 5e4 steps " << late);
    // Velocity Verlet is symplectic: on this (nearly linear, conservative) system the energy
    // oscillates by O((omega h)^2) about a conserved shadow energy and does not drift (rounding
    // adds a random walk of ~1e-16 sqrt(1e5) ~ 3e-14). So: the deviation stays below 2e-2
    // (omega_max h <= 1 with h = half the Gershgorin-safe step, little energy in the top modes)
    // and the late deviation is no larger than the early one (factor 1.5 for beating): a drift
    // of the size of the oscillation over 1e5 steps would fail this.
    CHECK(early < 2e-2);
    CHECK(late < 1.5 * early + 1e-12);
  }
}

TEST_CASE("dyn physics: the critical step is 2/omega_max, above it a run is caught, below it is stable",
          "[dyn][physics][stability][.tiny]") {
  const auto st = make(wall(2, 3));
  for (double r : {1.0, 500.0})
    for (auto method : {dyn::Method::be, dyn::Method::ue}) {
      auto p = params(r, method);
      p.rate = 5.0, p.ramp_time = 0, p.tension = 0.3, p.bending = 1;
      const double hc = exact_critical_step(p, st, mortar());
      const double found = dyn::critical_step(p, st.s, st.f, mortar(), 2000, 0.005);
      INFO("r " << r << " method " << int(method) << " exact " << hc << " bisection " << found);
      CHECK(std::abs(found / hc - 1) < 0.02);
      if (r == 500) {
        p.dt = 1.02 * hc;
        dyn::Simulation above(p, st.s, st.f, mortar());
        CHECK_FALSE(above.advance(Exec{}, 3000));
        INFO(above.why());
        CHECK(above.why().find("step") != std::string::npos);
        CHECK(above.steps() < 3000);
        // the state was left at the last good step: finite energies
        const auto e = above.energies();
        CHECK(std::isfinite(e.kinetic + e.strain + e.cohesive));
        p.dt = 0.98 * hc;
        dyn::Simulation below(p, st.s, st.f, mortar());
        CHECK(below.advance(Exec{}, 3000));
        CHECK(below.why().empty());
      }
    }
}

TEST_CASE("dyn physics: Rayleigh damping decays a mode at zeta = alpha/(2 omega) + beta omega/2", "[dyn][physics][damping][.tiny]") {
  const int nb = 24;
  auto st = make(wall(1, nb, 0, 0.0));
  for (auto& d : st.s.drive) d = geometry::Drive::free;
  auto p = params(1, dyn::Method::be);
  p.poisson = 0;
  const double L = nb * kBrickH, k = mortar().bed.k;
  const double Eeff = kBrickH / (kBrickH / p.youngs_modulus + 1.0 / k);
  const double omega = std::numbers::pi / L * std::sqrt(Eeff / p.density);
  p.alpha_d = 2 * 0.03 * omega, p.beta_d = 2 * 0.02 / omega;
  // C = alpha M + beta K with K the bricks' stiffness (the joints are undamped springs): the
  // beta part acts on the share of the mode's strain energy held by the bricks,
  // (h/E) / (h/E + 1/k) (one half at r = 1), so zeta = 0.03 + 0.02 * share.
  const double share = (kBrickH / p.youngs_modulus) / (kBrickH / p.youngs_modulus + 1.0 / k);
  const double zeta = p.alpha_d / (2 * omega) + share * p.beta_d * omega / 2;
  p.dt = 1.0;
  dyn::HostMap map;
  p.dt = 0.5 * dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
  dyn::Simulation sim(p, st.s, st.f, mortar());
  auto s0 = sim.save_state();
  const auto snap0 = sim.snapshot();
  const int ne = elements(s0), nn = dofs(s0) / 2;
  for (int e = 0; e < ne; ++e)
    for (int j = 0; j < nn; ++j) s0["v"][at(ne, e, 2 * j + 1)] = std::cos(std::numbers::pi * snap0.node_y[e * nn + j] / L);
  sim.restore_state(s0);
  // peaks of |elongation| between zero crossings
  std::vector<double> peaks;
  double prev = 0, peak = 0;
  for (int n = 0; n < 6000 && peaks.size() < 8; ++n) {
    REQUIRE(sim.advance(Exec{}, 1));
    const auto sn = sim.snapshot();
    double top = 0, bot = 0;
    int ct = 0, cb = 0;
    for (std::size_t q = 0; q < sn.uy.size(); ++q) {
      if (sn.node_y[q] > L - 1e-12) top += sn.uy[q], ++ct;
      if (sn.node_y[q] < 1e-12) bot += sn.uy[q], ++cb;
    }
    const double el = top / ct - bot / cb;
    if (n > 0 && ((prev < 0) != (el < 0))) peaks.push_back(peak), peak = 0;
    peak = std::max(peak, std::abs(el));
    prev = el;
  }
  REQUIRE(peaks.size() >= 8);
  // half periods 1..7 (the first is partial); amplitude ratio per half period exp(-pi zeta / sqrt(1 - zeta^2))
  const double dec = std::log(peaks[1] / peaks[7]) / 6;
  const double measured = dec / std::sqrt(std::numbers::pi * std::numbers::pi + dec * dec);
  INFO("zeta expected " << zeta << " measured " << measured);
  CHECK(std::abs(measured / zeta - 1) < 0.01);
}

TEST_CASE("dyn physics: Table 4.2 damping (alpha_d in 1e6/s, beta_d in us) damps the specimen's lowest modes sensibly",
          "[dyn][physics][damping][.tiny]") {
  // The lowest modes of a square specimen of the tabulated size: omega_1 from the exact spectrum
  // of a small square specimen (21 x 21 brick heights, top and bottom rows clamped), scaled by
  // the size ratio (omega ~ 1 / side for the same shape).
  const auto st = make(wall(6, 21));
  for (double r : {1.0, 500.0}) {
    auto p = params(r, dyn::Method::be);
    const auto w2 = linear_spectrum(p, st, mortar());
    const double w1 = std::sqrt(w2(0));
    for (std::size_t bricks : {10206ul, 201600ul}) {
      double a, b;
      dyn::table_4_2_damping(bricks, r, a, b);
      const double side_ratio = std::sqrt(3.5 * bricks) / 21.0;  // side of the specimen in brick heights / 21
      const double omega = w1 / side_ratio;
      const double zeta = a / (2 * omega) + b * omega / 2;  // (beta part: an upper bound, see above)
      INFO("r " << r << " bricks " << bricks << " omega_1 " << omega << " rad/s, zeta_1 " << zeta << " (alpha part "
                << a / (2 * omega) << ")");
      // with alpha_d read as 1/s zeta_1 would be ~1e-6; as 1e6/s the lowest mode is damped but
      // not overdamped, which is what a quasi-static fracture run needs
      CHECK(zeta > 0.05);
      CHECK(zeta < 1.0);
    }
  }
}
