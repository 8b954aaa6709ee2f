// Simulation-level tests: both methods run a loaded wall with a closed energy balance, restart
// is bit for bit, element types are shared, bytes are reported.
#include "common.hpp"

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_floating_point.hpp>

#include <cmath>

using namespace dyntest;
using Catch::Matchers::WithinAbs;

namespace {
dyn::Params loaded(dyn::Method m, double r = 50) {
  auto p = params(r, m);
  p.rate = 20.0;                // mm/s
  p.ramp_time = 2e-6;
  p.ramp = dyn::Ramp::smooth;
  p.tension = 0, p.bending = 1;
  return p;
}
}  // namespace

TEST_CASE("dyn: BE and UE advance a loaded wall, energy balance closes", "[dyn][simulation]") {
  const auto st = make(wall(4, 6));
  for (auto method : {dyn::Method::be, dyn::Method::ue}) {
    auto p = loaded(method);
    p.dt = 1.0;  // only for the estimate
    dyn::HostMap map;
    const double est = dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
    p.dt = 0.2 * est;
    dyn::Simulation sim(p, st.s, st.f, mortar());
    const bool ok = sim.advance(Kokkos::DefaultExecutionSpace{}, 3000);
    INFO(sim.why());
    REQUIRE(ok);
    const auto e = sim.energies();
    INFO("method " << int(method) << " W " << e.external_work << " S " << e.strain << " K " << e.kinetic << " C "
                   << e.cohesive << " res " << e.balance_residual << " D " << sim.displacement());
    CHECK(e.external_work > 0);
    CHECK(e.strain > 0);
    CHECK(e.cohesive > 0);
    CHECK(std::abs(e.balance_residual) < 1e-6);
    CHECK(sim.reaction() > 0);
    const auto snap = sim.snapshot();
    CHECK(snap.tri_brick.size() == 4 * st.s.size());
    CHECK(snap.iface_damage.size() == st.f.size());
  }
}

TEST_CASE("dyn: save_state / restore_state continue bit for bit", "[dyn][restart]") {
  const auto st = make(wall(3, 4));
  for (auto method : {dyn::Method::be, dyn::Method::ue}) {
    auto p = loaded(method);
    p.dt = 1e-9;
    dyn::Simulation a(p, st.s, st.f, mortar());
    REQUIRE(a.advance(Kokkos::DefaultExecutionSpace{}, 100));
    const auto saved = a.save_state();
    REQUIRE(a.advance(Kokkos::DefaultExecutionSpace{}, 150));
    dyn::Simulation b(p, st.s, st.f, mortar());
    b.restore_state(saved);
    REQUIRE(b.steps() == 100);
    REQUIRE(b.advance(Kokkos::DefaultExecutionSpace{}, 150));
    const auto sa = a.save_state(), sb = b.save_state();
    for (const auto& [k, v] : sa) CHECK(v == sb.at(k));
    auto bad = saved;
    bad["u"].pop_back();
    CHECK_THROWS(b.restore_state(bad));
  }
}

TEST_CASE("dyn: element types are shared; bytes per brick with and without sharing", "[dyn][memory]") {
  const auto st = make(wall(20, 60, 8));  // 20 bricks x 60 rows, notch 8 bricks long
  for (auto method : {dyn::Method::be, dyn::Method::ue}) {
    auto p = params(50, method);
    p.dt = 1e-9;
    dyn::Simulation shared(p, st.s, st.f, mortar());
    p.share_element_matrices = false;
    dyn::Simulation own(p, st.s, st.f, mortar());
    const double n = static_cast<double>(st.s.size());
    INFO("method " << (method == dyn::Method::be ? "BE" : "UE") << ": " << st.s.size() << " bricks, "
                   << shared.element_types() << " types; bytes per brick shared " << shared.bytes() / n
                   << ", per element " << own.bytes() / n);
    CHECK(shared.element_types() < static_cast<int>(st.s.size()));
    CHECK(own.element_types() == static_cast<int>(method == dyn::Method::be ? st.s.size() : 4 * st.s.size()));
    CHECK(shared.bytes() < own.bytes());
  }
}
