// SPDX-License-Identifier: BSD-3-Clause
// The dynamics kernels, written once, run on every backend a run can choose (tests/backends.hpp
// RunBackends: the host backends of a host build, the device and the host backends of a CUDA
// build, each with the model in its own memory) and
// must leave the same bits as on the reference of their kind of arithmetic (RefSpace below: the
// default space, or the default host space for a CUDA build's host backends): a notched wall driven to rupture,
// velocity Verlet (BE) per element with the dense (M + h/2 C)^-1 and over the tiles with its
// diagonal, and BIE's iterated and split steps fused
// over the tiles and unfused (residual, shared_gemm solve, update), each step's phases launched
// on the backend's instance as dyn::Simulation launches them on the run's. On every backend the
// per-element and tiled walks, and the fused and unfused BIE steps, also agree bit for bit.
#include "../backends.hpp"
#include "common.hpp"

#include <nacre/dyn/bie.hpp>
#include <nacre/dyn/kernels.hpp>

#include <catch2/catch_template_test_macros.hpp>
#include <catch2/catch_test_macros.hpp>

#include <cstring>
#include <iostream>
#include <type_traits>
#include <vector>

using namespace dyntest;

namespace {

/// The state one run leaves: u, v, a, the element books and the interface forces, flattened.
using State = std::vector<double>;

template <class View>
void append(State& out, const View& v) {
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, v);
  out.insert(out.end(), h.data(), h.data() + h.span());
}

/// A weak mortar (k x1 = 0.7, k x1 x2 = 0.001 N/mm): joints soften and rupture within the steps run.
const deck::Mortar kWeakSoft = mortar(7000, 0.7, 0.001);

enum class Walk { per_element, tiled, bie_unfused, bie_fused };

/// `steps` steps of p on `space` (the phases of dyn::Simulation's step, without its monitor).
template <class ExecutionSpace>
State run(const ExecutionSpace& space, dyn::Params p, const Setup& st, Walk walk, int steps) {
  using Mem = typename ExecutionSpace::memory_space;  // the model in the backend's own memory
  dyn::HostMap map;
  const auto m = dyn::build_model<Mem>(p, st.s, st.f, kWeakSoft, map);
  const bool bie = p.method == dyn::Method::bie;
  const int ne = m.n_elem, nd = m.nd;
  dyn::DofView<Mem> u("u", ne, nd), v("v", ne, nd), a("a", ne, nd), pn("pn", ne, nd), vn("vn", ne, nd),
      R("R", ne, 2 * nd);
  dyn::AccView<Mem> acc("acc", ne, bie ? dyn::kAccColsBie : dyn::kAccColsExplicit);
  dyn::DrivenAccView<Mem> dacc("dacc", std::max(m.n_driven, 1));
  dyn::IforceView<Mem> iforce("iforce", std::max(m.n_iface, 1));
  const dyn::InterfaceOp<Mem> op(m, u, iforce);
  const loading::Ramp ramp{loading::Profile::smooth, p.rate, p.ramp_time, 0.0};
  dyn::Integrator<Mem> it(m, u, v, a, acc, dacc, iforce);
  auto at = [&](long n) {
    const auto o = ramp(static_cast<double>(n) * p.dt);
    it.D = o.D, it.Dd = o.rate, it.Ddd = o.accel;
    it.D_prev = ramp.displacement(static_cast<double>(n > 0 ? n - 1 : 0) * p.dt);
  };
  at(0);
  dyn::impose_drive(space, it, ne);
  dyn::BieTables<Mem> tables;
  dyn::BieStepPlan plan;
  if (bie) {
    tables = dyn::build_bie_tables(m);
    const int n_tiles = static_cast<int>(tables.tile_start.extent(0));
    plan = dyn::BieStepPlan{dyn::BieSolve::shared_gemm, 0, p.bie_iterations, p.bie_reuse_force, ne, m.n_iface, n_tiles};
  }
  auto bie_of = [&] {
    return dyn::BieIntegrator<Mem>{it, tables.slot_of_elem, pn, vn, R, tables.Jinv, tables.jq, tables.jr, tables.Jv};
  };
  const dyn::BieSolveOp<Mem> solve{tables.Jinv, tables.slot_type, tables.tile_start, tables.tile_count, R, tables.n2};
  const bool split = p.bie_scheme == dyn::BieScheme::split;
  if (bie) dyn::bie_accelerations(space, bie_of(), op, ne, m.n_iface, split);
  for (long n = 1; n <= steps; ++n) {
    at(n);
    switch (walk) {
    case Walk::per_element:  // the dense (M + h/2 C)^-1 product per element
      dyn::verlet_step(space, dyn::ElementTiles<false>{}, dyn::AinvDense{}, it, op, ne, m.n_iface);
      break;
    case Walk::tiled:  // over the tiles, its exact zeros skipped (C = alpha M: the inverse is diagonal)
      REQUIRE(m.ainv_diagonal);
      dyn::verlet_step(space, dyn::ElementTiles<true>{}, dyn::AinvDiagonal{}, it, op, ne, m.n_iface);
      break;
    case Walk::bie_unfused:
      if (split)
        dyn::bie_step(space, dyn::BieSplitScheme{}, std::false_type{}, dyn::JinvDense{}, bie_of(), op, solve, plan);
      else
        dyn::bie_step(space, dyn::BieIterateScheme{}, std::false_type{}, dyn::JinvDense{}, bie_of(), op, solve, plan);
      break;
    case Walk::bie_fused:  // the dense J^-1 apply: the unfused solve's sums in the same order
      if (split)
        dyn::bie_step(space, dyn::BieSplitScheme{}, std::true_type{}, dyn::JinvDense{}, bie_of(), op, solve, plan);
      else
        dyn::bie_step(space, dyn::BieIterateScheme{}, std::true_type{}, dyn::JinvDense{}, bie_of(), op, solve, plan);
      break;
    }
  }
  space.fence();
  State s;
  append(s, u), append(s, v), append(s, a), append(s, acc), append(s, iforce);
  return s;
}

bool same_bits(const State& x, const State& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
}

/// A notched wall (kWeakSoft) opened fast enough that joints soften and rupture within the steps run.
dyn::Params cracking(dyn::Method m) {
  auto p = params(500, m);
  p.rate = 20000.0;  // mm/s
  p.ramp_time = 2e-7;
  p.tension = 1, p.bending = 0.5;
  p.alpha_d = 1e5;  // Rayleigh damping on: C enters every integrator
  dyn::HostMap map;
  auto q = p;
  q.dt = 1.0;
  p.dt = 0.5 * dyn::build_model(q, make(wall(8, 6, 3)).s, make(wall(8, 6, 3)).f, kWeakSoft, map).step_estimate;
  if (m == dyn::Method::bie) p.dt *= 4;
  return p;
}

/// The reference a backend must match bit for bit: the default space where the backend shares its
/// memory (a host build; the device of a CUDA build), else the default host space (a CUDA build's
/// host backends: the host's arithmetic, not the device's; Backend::bit_compatible).
template <class E>
using RefSpace = std::conditional_t<std::is_same_v<MemOf<E>, MemOf<Kokkos::DefaultExecutionSpace>>,
                                    Kokkos::DefaultExecutionSpace, Kokkos::DefaultHostExecutionSpace>;

}  // namespace

TEMPLATE_LIST_TEST_CASE("dyn kernels leave the same bits on every backend", "[dyn][backends]",
                        nacre::test::RunBackends) {
  const TestType space;
  INFO("backend " << TestType::name() << " (enabled: " << nacre::test::host_backend_names() << ")");
  const auto st = make(wall(8, 6, 3));
  constexpr int kSteps = 300;
  SECTION("velocity Verlet (BE), per element and tiled") {
    const auto p = cracking(dyn::Method::be);
    const State ref = run(RefSpace<TestType>{}, p, st, Walk::per_element, kSteps);
    CHECK(same_bits(run(space, p, st, Walk::per_element, kSteps), ref));
    CHECK(same_bits(run(space, p, st, Walk::tiled, kSteps), ref));
  }
  for (const auto scheme : {dyn::BieScheme::iterate, dyn::BieScheme::split}) {
    DYNAMIC_SECTION("BIE " << (scheme == dyn::BieScheme::split ? "split" : "iterated") << ", unfused and fused") {
      auto p = cracking(dyn::Method::bie);
      p.bie_scheme = scheme;
      const State ref = run(RefSpace<TestType>{}, p, st, Walk::bie_unfused, kSteps / 3);
      CHECK(same_bits(run(space, p, st, Walk::bie_unfused, kSteps / 3), ref));
      CHECK(same_bits(run(space, p, st, Walk::bie_fused, kSteps / 3), ref));
    }
  }
}

TEMPLATE_LIST_TEST_CASE("dyn::Simulation on a chosen backend: the same state bit for bit as on the reference one",
                        "[dyn][backends]", nacre::test::RunBackends) {
  // the top layer on the backend (Simulation holds a Backend: every launch of a step, a check,
  // the books and the roll-back copies go to its instance), BE and BIE, through the monitor
  const auto st = make(wall(8, 6, 3));
  for (const auto method : {dyn::Method::be, dyn::Method::bie}) {
    const auto p = cracking(method);
    dyn::Simulation ref(Backend(RefSpace<TestType>{}), p, st.s, st.f, kWeakSoft),
        sim(Backend(TestType{}), p, st.s, st.f, kWeakSoft);
    REQUIRE(ref.advance(150));
    REQUIRE(sim.advance(150));
    const auto a = ref.save_state(), b = sim.save_state();
    REQUIRE(a.size() == b.size());
    for (const auto& [name, x] : a) {
      INFO(TestType::name() << ", method " << (method == dyn::Method::bie ? "bie" : "be") << ", array " << name);
      CHECK(same_bits(x, b.at(name)));
    }
    CHECK(sim.energies().balance_residual == ref.energies().balance_residual);
  }
}

TEST_CASE("dyn backend runs crack the wall (the bit-for-bit test compares a state that moved)", "[dyn][backends]") {
  const auto st = make(wall(8, 6, 3));
  const auto p = cracking(dyn::Method::be);
  dyn::Simulation sim(p, st.s, st.f, kWeakSoft);
  REQUIRE(sim.advance(Kokkos::DefaultExecutionSpace{}, 300));
  CHECK(sim.energies().cohesive > 0);
  INFO("D = " << sim.displacement() << ", ruptured " << sim.ruptured());
  CHECK(sim.ruptured() > 0);
}
