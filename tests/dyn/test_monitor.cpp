// SPDX-License-Identifier: BSD-3-Clause
// The dynamic run's stability monitor (monitor.hpp, docs/dynamics.md "Stability monitor"): the
// step bound against the exact spectrum, its penalty stiffening against the closed form, the
// balance check stopping a bad run at a state whose books close, the adaptive step restarting bit
// for bit, and the sliver mass scaling raising the step of a rotated wall.
#include "common.hpp"

#include <nacre/dyn/monitor.hpp>

#include <catch2/catch_test_macros.hpp>

#include <algorithm>
#include <cmath>
#include <string>

using namespace dyntest;

namespace {
dyn::Params loaded(dyn::Method m, double r = 50) {
  auto p = params(r, m);
  p.rate = 20.0;
  p.ramp_time = 2e-6;
  p.ramp = dyn::Ramp::smooth;
  p.tension = 0, p.bending = 1;
  return p;
}
bool same_state(const dyn::StateArrays& a, const dyn::StateArrays& b) {
  for (const char* k : {"u", "v", "a", "acc"})
    if (a.at(k) != b.at(k)) return false;
  return true;
}
}  // namespace

TEST_CASE("dyn monitor: the step bound is >= the exact omega_max and within the interfaces' Gershgorin slack",
          "[dyn][monitor]") {
  const auto st = make(wall(4, 6));
  for (auto method : {dyn::Method::be, dyn::Method::ue}) {
    auto p = params(50, method);
    p.rate = 1.0;
    const Eigen::VectorXd w2 = linear_spectrum(p, st, mortar());
    const double exact = 2.0 / std::sqrt(w2.maxCoeff());
    p.dt = 0.1 * exact;
    dyn::Simulation sim(p, st.s, st.f, mortar());
    const auto r = sim.step_check();
    INFO("method " << int(method) << " bound " << r.bound << " exact 2/omega_max " << exact);
    // an upper bound of omega_max (element eigenvalue + a Gershgorin bound of the interfaces): a
    // step no larger than the exact one, and close to it (the interfaces are soft next to the bricks)
    CHECK(r.bound <= exact * (1 + 1e-9));
    CHECK(r.bound >= 0.8 * exact);
    CHECK(r.estimate == r.bound);
    CHECK(r.bound_start == r.bound);
    CHECK(r.element >= 0);
  }
}

TEST_CASE("dyn monitor: a pressed joint lowers the bound as the penalty's stiffness 1.875 k (dn/x1)^4 says",
          "[dyn][monitor]") {
  // three bricks in a column, the outer ones held: press the middle one onto the lower by 2 x1
  const auto st = make(wall(1, 3, 0, 0.0));
  auto p = params(1, dyn::Method::be);  // soft bricks: the interface row shows in the bound
  p.rate = 1.0;
  p.dt = 1e-9;
  p.bie_reuse_force = true;
  const auto mo = mortar();
  dyn::Simulation sim(p, st.s, st.f, mo);
  const auto r0 = sim.step_check();
  auto state = sim.save_state();
  const double x1 = mo.bed.x1;
  // the model's element order follows the bricks (row by row): the middle brick's element is 1;
  // every one of its nodes -2 x1 in y (LayoutLeft order in the state: element fastest)
  auto& u = state.at("u");
  const std::size_t ne = 3, nd = u.size() / ne;
  for (std::size_t j = 1; j < nd; j += 2) u[1 + ne * j] = -2.0 * x1;
  sim.restore_state(state);
  const auto r1 = sim.step_check();
  INFO("bound elastic " << r0.bound << " pressed " << r1.bound << " penetration " << r1.penetration);
  CHECK(r1.bound < r0.bound);
  CHECK(std::abs(r1.penetration - 2.0) < 1e-9);
  CHECK(r1.iface >= 0);
  // the interface part of omega^2 grows by at most 1 + 1.875 * 2^4 = 31 (normal along y: the whole
  // penalty term in the y row), so the bound can fall by at most sqrt(31)
  CHECK(r1.bound >= r0.bound / std::sqrt(31.0) * (1 - 1e-9));
}

TEST_CASE("dyn monitor: a step above the critical one stops at a state whose books close", "[dyn][monitor]") {
  const auto st = make(wall(4, 6));
  auto p = loaded(dyn::Method::be);
  const double h = 2.0 / std::sqrt(linear_spectrum(p, st, mortar()).maxCoeff());
  // 1 % above the exact critical step of the undamped run: the top mode grows 1.33x per step from
  // rounding, so the books break after the first chunk (they are checked from step 32 on)
  p.dt = 1.01 * h;
  p.balance_tolerance = 1e-3;
  dyn::Simulation sim(p, st.s, st.f, mortar());
  const bool ok = sim.advance(Kokkos::DefaultExecutionSpace{}, 20000);
  INFO(sim.why());
  REQUIRE_FALSE(ok);
  const auto e = sim.energies();
  INFO("kept step " << sim.steps() << " balance " << e.balance_residual);
  CHECK(sim.steps() >= 32);
  CHECK(std::string(sim.why()).find("energy balance") != std::string::npos);
  CHECK(std::abs(e.balance_residual) <= 1e-3);
  CHECK(std::isfinite(e.kinetic));
  // without the balance check the same run goes on past that step (the kinetic bound is loose)
  auto q = p;
  q.balance_tolerance = 0;
  dyn::Simulation loose(q, st.s, st.f, mortar());
  loose.advance(Kokkos::DefaultExecutionSpace{}, 20000);
  CHECK(loose.steps() > sim.steps());
}

TEST_CASE("dyn monitor: the fixed step stops when the estimate falls below it, naming the place", "[dyn][monitor]") {
  const auto st = make(wall(4, 6));
  auto p = loaded(dyn::Method::be);
  p.dt = 1e-9;
  const double h = dyn::Simulation(p, st.s, st.f, mortar()).step_report().estimate;
  p.dt = 1.05 * h;
  p.step_check = true;
  dyn::Simulation sim(p, st.s, st.f, mortar());
  REQUIRE_FALSE(sim.advance(Kokkos::DefaultExecutionSpace{}, 64));
  const std::string why = sim.why();
  INFO(why);
  CHECK(why.find("estimated critical step") != std::string::npos);
  CHECK(why.find("brick") != std::string::npos);
  CHECK(sim.steps() == 0);  // back to the chunk's start, the last state that passed every check
  // below the estimate the run goes on
  p.dt = 0.5 * h;
  dyn::Simulation ok(p, st.s, st.f, mortar());
  CHECK(ok.advance(Kokkos::DefaultExecutionSpace{}, 64));
}

TEST_CASE("dyn monitor: the adaptive step follows a falling bound and restarts bit for bit", "[dyn][monitor][restart]") {
  // soft bricks driven together fast: the joints interpenetrate and the penalty stiffens them
  const auto st = make(wall(4, 6));
  auto p = params(1, dyn::Method::be);
  p.rate = 4000.0, p.ramp_time = 0, p.tension = -1.0, p.bending = 0.0;
  p.dt = 1e-9;
  const double h = dyn::Simulation(p, st.s, st.f, mortar()).step_report().estimate;
  p.dt = 0.5 * h;
  p.step_check = true;
  p.dt_mode = dyn::DtMode::adaptive;
  p.balance_tolerance = 1e-3;
  dyn::Simulation a(p, st.s, st.f, mortar());
  REQUIRE(a.advance(Kokkos::DefaultExecutionSpace{}, 3200));
  INFO("dt now " << a.dt() << " start " << p.dt << " changes " << a.step_report().dt_changes << " bound "
                 << a.step_report().bound << " of " << a.step_report().bound_start);
  REQUIRE(a.step_report().dt_changes > 0);
  CHECK(a.dt() < p.dt);
  CHECK(std::abs(a.dt() / p.dt - std::min(1.0, a.step_report().bound / a.step_report().bound_start)) < 0.11);
  CHECK(std::abs(a.energies().balance_residual) <= 1e-3);
  const auto saved = a.save_state();
  REQUIRE(a.advance(Kokkos::DefaultExecutionSpace{}, 640));
  dyn::Simulation b(p, st.s, st.f, mortar());
  b.restore_state(saved);
  CHECK(b.dt() == saved.at("clock")[4]);
  REQUIRE(b.advance(Kokkos::DefaultExecutionSpace{}, 640));
  CHECK(b.time() == a.time());
  CHECK(same_state(a.save_state(), b.save_state()));
}

TEST_CASE("dyn monitor: sliver mass scaling raises a rotated wall's step to the target at a small mass cost",
          "[dyn][monitor]") {
  auto g = wall(12, 12);
  g.angle_deg = 30.0;
  const auto st = make(g);
  auto p = loaded(dyn::Method::be);
  p.dt = 1e-9;
  const dyn::Simulation raw(p, st.s, st.f, mortar());
  p.sliver_step_ratio = 0.5;
  const dyn::Simulation scaled(p, st.s, st.f, mortar());
  const double h0 = raw.step_report().bound, h1 = scaled.step_report().bound;
  INFO("bound unscaled " << h0 << " scaled " << h1 << " elements " << scaled.sliver_elements() << " mass +"
                         << scaled.sliver_mass_added());
  CHECK(raw.sliver_elements() == 0);
  CHECK(scaled.sliver_elements() > 0);
  CHECK(h1 > 2.0 * h0);
  CHECK(scaled.sliver_mass_added() > 0);
  CHECK(scaled.sliver_mass_added() < 0.05);
  // the unrotated wall has no element that far from the median: nothing changes
  const auto st0 = make(wall(12, 12));
  CHECK(dyn::Simulation(p, st0.s, st0.f, mortar()).sliver_elements() == 0);
}
