// SPDX-License-Identifier: BSD-3-Clause
// Simulation-level tests: both methods run a loaded wall with a closed energy balance, restart
// is bit for bit, element types are shared, bytes are reported.
#include "common.hpp"

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_floating_point.hpp>

#include <cmath>
#include <vector>

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

TEST_CASE("dyn: element types are shared, bytes per brick with and without sharing", "[dyn][memory]") {
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

// The tiled element apply's work list (build_model): every free element in exactly one tile,
// a tile of at most kTile elements of one type, increasing, inside one window of kTileWindow
// elements; tiles ordered by window, then type, then element, only the last tile of a (window,
// type) run partial; driven elements listed apart, in order. With and without shared types
// (unshared, every element its own type: the case whose tile build was quadratic).
TEST_CASE("dyn: element tiles cover each free element once, one type per tile, window by window", "[dyn][model]") {
  const auto st = make(wall(12, 20, 4));
  for (auto method : {dyn::Method::be, dyn::Method::ue})
    for (bool share : {true, false}) {
      auto p = params(50, method);
      p.dt = 1e-9;
      p.share_element_matrices = share;
      dyn::HostMap map;
      const auto m = dyn::build_model(p, st.s, st.f, mortar(), map);
      INFO((method == dyn::Method::be ? "BE" : "UE") << (share ? ", shared types" : ", own types") << ": "
                                                     << m.n_elem << " elements, " << m.n_types << " types, "
                                                     << m.n_tiles << " tiles");
      const auto T = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.type);
      const auto D = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.drive);
      const auto TS = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.tile_start);
      const auto TE = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.tile_elem);
      const auto DR = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.driven);
      REQUIRE(m.n_types > 1);
      if (!share) REQUIRE(m.n_types == m.n_elem);
      std::vector<int> seen(m.n_elem, 0);
      bool ok = true;
      for (int w = 0; w < m.n_tiles; ++w) {
        const int b0 = TS(w), nb = TS(w + 1) - b0;
        ok = ok && nb >= 1 && nb <= dyn::kTile;
        const int e0 = TE(b0), win = e0 / dyn::kTileWindow;
        for (int b = 0; b < nb; ++b) {
          const int e = TE(b0 + b);
          ++seen[e];
          ok = ok && D(e) == 0 && T(e) == T(e0) && e / dyn::kTileWindow == win && (b == 0 || e > TE(b0 + b - 1));
        }
        if (w + 1 < m.n_tiles) {  // order against the next tile
          const int f0 = TE(TS(w + 1)), wn = f0 / dyn::kTileWindow, last = TE(b0 + nb - 1);
          const bool same_run = wn == win && T(f0) == T(e0);
          ok = ok && (wn > win || (wn == win && T(f0) >= T(e0))) && (!same_run || (nb == dyn::kTile && f0 > last));
        }
      }
      CHECK(ok);
      int free_once = 0, driven = 0;
      for (int e = 0; e < m.n_elem; ++e) {
        if (D(e) == 0) free_once += seen[e] == 1;
        else {
          CHECK(seen[e] == 0);
          REQUIRE(driven < m.n_driven);
          CHECK(DR(driven++) == e);
        }
      }
      CHECK(driven == m.n_driven);
      CHECK(free_once + driven == m.n_elem);
    }
}

TEST_CASE("dyn: irreversible damage under a load-unload programme: books close, history restarts bit for bit",
          "[dyn][damage][restart]") {
  const auto st = make(wall(4, 6, 1.0));  // notched: the joints ahead of the notch pass x1
  deck::Mortar mo = mortar();
  mo.damage = cohesive::Damage::irreversible, mo.damage_auto = false;
  for (const auto method : {dyn::Method::be, dyn::Method::bie}) {
    CAPTURE(int(method));
    auto p = loaded(method);
    p.dt = 1.0;  // only for the estimate
    dyn::HostMap map;
    const double est = dyn::build_model(p, st.s, st.f, mo, map).step_estimate;
    p.dt = 0.4 * est;
    const double peak = 0.1;  // mm: the joints ahead of the notch pass x1 (0.0101 mm)
    const long leg = 3000;    // steps per leg
    p.rate = peak / (leg * p.dt), p.ramp_time = 0.1 * leg * p.dt;
    p.programme = {peak, 0.0};
    dyn::Simulation sim(p, st.s, st.f, mo);
    const auto ex = Kokkos::DefaultExecutionSpace{};
    auto dissipated = [&] {
      std::vector<double> dmg, e;
      std::vector<int> state;
      sim.interface_damage(dmg, state, &e);
      double s = 0;
      for (double x : e) s += x;
      return s;
    };
    REQUIRE(sim.advance(ex, leg + leg / 10));  // past the peak (the ramp delays it by half its time)
    const double d_peak = dissipated();
    INFO("D " << sim.displacement() << ", dissipated " << d_peak);
    CHECK(d_peak > 0);
    CHECK(sim.displacement() < peak);  // on the way down
    const auto saved = sim.save_state();
    REQUIRE(saved.count("history"));
    REQUIRE(sim.advance(ex, leg));
    CHECK(sim.displacement() == 0.0);  // held at the programme's last target
    const auto e = sim.energies();
    const double d_end = dissipated();
    INFO("end: W " << e.external_work << " C " << e.cohesive << " S " << e.strain << " K " << e.kinetic << " res "
                   << e.balance_residual << " dissipated " << d_end);
    CHECK(std::abs(e.balance_residual) < 1e-3);
    CHECK(d_end >= d_peak);
    CHECK(e.cohesive >= d_end * (1 - 1e-12));  // psi >= D(kappa): the joints hold at least what they dissipated
    // the same steps from the saved state: every array, the history included, bit for bit
    dyn::Simulation b(p, st.s, st.f, mo);
    b.restore_state(saved);
    REQUIRE(b.advance(ex, leg));
    const auto sa = sim.save_state(), sb = b.save_state();
    for (const auto& [k, v] : sa) {
      CAPTURE(k);
      CHECK(v == sb.at(k));
    }
    auto no_history = saved;
    no_history.erase("history");
    dyn::Simulation c(p, st.s, st.f, mo);
    CHECK_THROWS(c.restore_state(no_history));
  }
}
