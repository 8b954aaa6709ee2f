// SPDX-License-Identifier: BSD-3-Clause
// Monte Carlo solver: the elastic limit against an exact linear solve, energy bookkeeping,
// determinism (same bits for 1 and 2 threads: see tests/CMakeLists.txt).
#include <nacre/mc/output.hpp>
#include <nacre/mc/solver.hpp>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include "elastic_exact.hpp"
#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include "wall_specimen.hpp"

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

using namespace nacre;

namespace {

deck::Deck small_deck() {
  deck::Deck d;
  d.geometry.width = 14.0;
  d.geometry.height = 6.0;
  d.geometry.brick_width = 3.5;
  d.geometry.brick_height = 1.0;
  d.geometry.notch_length = 0.0;
  d.geometry.notch_y = 3.0;
  d.mortar.bed = {100.0, 0.01, 0.02};
  d.mortar.head = {50.0, 0.01, 0.02};
  d.load.tension = 1.0;
  d.load.bending = 0.5;
  d.solver.colouring = "natural";
  d.solver.quadrature_points = 4;
  d.output.hdf5 = false;
  d.output.charts = false;
  return d;
}

/// A notched specimen that cracks within a few adaptive load steps, with predictor.
deck::Deck cracking_deck() {
  auto d = small_deck();
  test::notched_21x8(d);
  test::cracking_path(d);
  return d;
}


}  // namespace

TEST_CASE("elastic limit: the Monte Carlo minimum matches the exact linear solve", "[mc][physics]") {
  auto d = small_deck();
  d.solver.temperature = 0.0;  // pure descent: thermal energy would bias the minimum
  // Fixed trial steps: at T = 0 the acceptance target of eq. 2.7 (40-60 %) is out of reach near
  // a minimum, so adaptation would shrink the step to its floor and the descent would stall
  // (measured: 3 % energy error instead of < 1e-4; see docs/design.md).
  d.solver.step = d.solver.min_step = d.solver.max_step = 1e-6;
  d.solver.rot_step = d.solver.min_rot_step = d.solver.max_rot_step = 1e-6;
  d.solver.adapt_interval = 0;
  auto st = test::make_setup(d);
  const double D = 1e-4;  // separations ~1e-5 << x1: quadratic regime
  const double exact = test::exact_elastic_energy(d, st.s, st.f, D);
  mc::Solver solver(d, st.s, st.f);
  solver.set_load(D);
  const double e_start = solver.energy();
  double e = e_start;
  for (int block = 0; block < 400; ++block) {
    for (int c = 0; c < 100; ++c) solver.cycle();
    e = solver.energy();
    if ((e - exact) / exact < 2e-5) break;
  }
  INFO("exact " << exact << ", MC " << e << ", start " << e_start);
  CHECK(e_start > 2 * exact);  // the test starts far from the minimum
  CHECK(e >= exact * (1 - 1e-6));  // the linear solve is the minimum (up to geometric nonlinearity)
  CHECK((e - exact) / exact < 1e-4);  // stated tolerance: relative energy error 1e-4
}

TEST_CASE("tracked energy equals the exact reduction, zero load gives zero energy", "[mc]") {
  auto d = small_deck();
  d.solver.temperature = 1e-6;
  d.solver.step = 1e-4, d.solver.min_step = 1e-4, d.solver.max_step = 1e-4;
  d.solver.rot_step = 1e-4, d.solver.min_rot_step = 1e-4, d.solver.max_rot_step = 1e-4;
  auto st = test::make_setup(d);
  mc::Solver solver(d, st.s, st.f);
  CHECK(solver.energy() == 0.0);
  solver.set_load(0.005);
  const double e0 = solver.energy();
  // E_tracked = E(start) + sum of accepted dE; after N cycles it must match a fresh reduction
  double tracked = e0;
  for (int c = 0; c < 200; ++c) {
    const double before = solver.tracked_energy();
    solver.cycle();
    tracked += solver.tracked_energy() - before;
  }
  const double exact = solver.energy();
  CHECK(tracked == Catch::Approx(exact).epsilon(1e-10));  // sum of accepted changes is exact
  CHECK(exact < e0);  // Metropolis at low temperature lowers the energy
  CHECK(solver.reaction() > 0);  // opening load: the specimen resists
}

TEST_CASE("reaction = dE/dD of the relaxed energy (envelope theorem)", "[mc][physics]") {
  auto d = small_deck();
  d.solver.temperature = 0.0;
  d.solver.step = d.solver.min_step = d.solver.max_step = 1e-6;  // fixed, as in the elastic test
  d.solver.rot_step = d.solver.min_rot_step = d.solver.max_rot_step = 1e-6;
  auto st = test::make_setup(d);
  // In the elastic regime E_min(D) = c D^2 exactly (linearised), so dE/dD = 2 E / D.
  mc::Solver solver(d, st.s, st.f);
  const double D = 1e-4;
  solver.set_load(D);
  for (int c = 0; c < 20000; ++c) solver.cycle();
  const double e = solver.energy();
  CHECK(solver.reaction() == Catch::Approx(2 * e / D).epsilon(2e-2));
}

TEST_CASE("the sweep's interface-energy cache holds each interface's energy at the current poses, bit for bit",
          "[mc][physics]") {
  // The sweep sums cached energies for the old pose and writes a trial's new values back on
  // acceptance (its own and the neighbours' shared entries): after many sweeps the cache must be
  // exactly what a fresh evaluation gives, elastic and damaged interfaces alike, on both schedules.
  const auto d = cracking_deck();
  const auto w = test::wall_of(d.geometry);
  const ExecSpace space;
  for (const char* colouring : {"natural", "tiles"}) {
    CAPTURE(colouring);
    auto m = mc::build_model(space, w.s, w.f, w.adj, mc::colour_graph(colouring, w.s, w.adj, w.free, 1), d.mortar, 4);
    mc::apply_load(space, m, loading::Pattern{d.load.tension, d.load.bending, d.geometry.width}, 0.012);
    Field<double> cache("nacre::test::cache", m.n_interfaces), fresh("nacre::test::fresh", m.n_interfaces);
    Field<double> de("nacre::test::de", m.n_free);
    rng::UniformTable<> u("nacre::test::u", m.n_free);
    auto hu = Kokkos::create_mirror_view(u);
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    mc::interface_energies(space, m, cache);
    long accepted = 0;
    for (int cyc = 0; cyc < 30; ++cyc) {
      for (int b = 0; b < m.n_free; ++b)
        for (int k = 0; k < 4; ++k) hu(b, k) = U(gen);
      Kokkos::deep_copy(space, u, hu);
      for (std::size_t c = 0; c + 1 < m.colour_tiles.size(); ++c)
        accepted += mc::sweep_colour(space, m, m.colour_tiles[c], m.colour_tiles[c + 1], mc::TableUniforms<MemSpace>{u},
                                     cache, de, 2e-4, 1e-4, 1e-7);
    }
    CHECK(accepted > 0);
    CHECK(accepted < 30L * m.n_free);
    Field<std::int8_t> state("nacre::test::state", m.n_interfaces);
    mc::interface_state(space, m, Field<double>(), state);
    mc::interface_energies(space, m, fresh);
    space.fence();
    auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cache);
    auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fresh);
    auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), state);
    int damaged = 0;
    for (int i = 0; i < m.n_interfaces; ++i) damaged += hs(i) > 0;
    CHECK(damaged > 0);  // the non-elastic branches are exercised too
    CHECK(std::memcmp(hc.data(), hf.data(), sizeof(double) * m.n_interfaces) == 0);
  }
}

TEST_CASE("Philox numbers generated inside the sweep are those of the Philox table", "[mc][determinism]") {
  // The solver draws Philox in place (PhiloxUniforms) instead of filling the table first: the
  // same trials must come out, bit for bit, as from the table PhiloxSource fills.
  const auto d = cracking_deck();
  const auto w = test::wall_of(d.geometry);
  const ExecSpace space;
  const auto c = mc::colour_graph("tiles", w.s, w.adj, w.free, 1);
  const std::uint64_t seed = 0x5eed1234abcdull;
  rng::PhiloxSource source(seed);
  std::vector<double> poses[2];
  long accepted[2] = {0, 0};
  for (int in_place = 0; in_place < 2; ++in_place) {
    auto m = mc::build_model(space, w.s, w.f, w.adj, c, d.mortar, 4);
    mc::apply_load(space, m, loading::Pattern{d.load.tension, d.load.bending, d.geometry.width}, 0.006);
    Field<double> cache("nacre::test::cache", m.n_interfaces), de("nacre::test::de", m.n_free);
    rng::UniformTable<> u("nacre::test::u", m.n_free);
    mc::interface_energies(space, m, cache);
    for (std::uint64_t cyc = 0; cyc < 10; ++cyc) {
      if (!in_place) source.fill(Backend(space), cyc, Kokkos::subview(m.id, Kokkos::make_pair(0, m.n_free)), u);
      for (std::size_t k = 0; k + 1 < m.colour_tiles.size(); ++k) {
        if (in_place)
          accepted[1] += mc::sweep_colour(space, m, m.colour_tiles[k], m.colour_tiles[k + 1], mc::PhiloxUniforms<MemSpace>{m.id, seed, cyc},
                           cache, de, 2e-4, 1e-4, 1e-7);
        else
          accepted[0] += mc::sweep_colour(space, m, m.colour_tiles[k], m.colour_tiles[k + 1], mc::TableUniforms<MemSpace>{u}, cache, de,
                           2e-4, 1e-4, 1e-7);
      }
    }
    auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.pose);
    poses[in_place].assign(hp.data(), hp.data() + hp.size());
  }
  REQUIRE(poses[0].size() == poses[1].size());
  CHECK(std::memcmp(poses[0].data(), poses[1].data(), sizeof(double) * poses[0].size()) == 0);
  CHECK(accepted[0] == accepted[1]);
  CHECK(accepted[1] > 0);
}

TEST_CASE("a full run is repeatable and writes its fingerprint for the thread-count comparison",
          "[mc][determinism]") {
  auto d = cracking_deck();
  d.solver.adapt_interval = 20;
  d.solver.window_size = 60, d.solver.convergence_rep = 20;
  d.solver.window_mul = 10, d.solver.window_upper_mul = 40;
  const char* gen = std::getenv("NACRE_TEST_RNG");
  if (gen) d.solver.rng = gen;
  auto st = test::make_setup(d);
  auto run = [&]() {
    mc::Solver solver(d, st.s, st.f);
    std::vector<mc::StepRecord> rows;
    solver.run([&](const mc::StepRecord& r) { rows.push_back(r); });
    std::vector<double> x, y, t;
    solver.poses(x, y, t);
    // FNV-1a over the bits of every pose and every step's energy and cycle count
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* p, std::size_t n) {
      for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
    };
    for (std::size_t i = 0; i < x.size(); ++i) mix(&x[i], 8), mix(&y[i], 8), mix(&t[i], 8);
    for (auto& r : rows) mix(&r.energy, 8), mix(&r.cycles, sizeof r.cycles), mix(&r.ruptured, sizeof r.ruptured);
    return std::make_pair(h, rows);
  };
  std::ostringstream fingerprints;
  for (const char* colouring : {"natural", "tiles"}) {
    d.solver.colouring = colouring;
    const auto [h1, rows1] = run();
    const auto [h2, rows2] = run();
    CHECK(h1 == h2);
    REQUIRE(rows1.size() >= 3);
    CHECK(rows1.back().displacement == Catch::Approx(0.02));
    fingerprints << d.solver.rng << " " << colouring << " " << std::hex << h1 << "\n";
  }
  if (const char* out = std::getenv("NACRE_HASH_OUT")) std::ofstream(out) << fingerprints.str();
}

TEST_CASE("a run restarted from a checkpoint continues bit for bit", "[mc][restart]") {
  auto d = cracking_deck();
  d.solver.adapt_interval = 7;  // adaptation windows straddle load steps
  d.solver.window_size = 60, d.solver.convergence_rep = 20;
  d.solver.window_mul = 10, d.solver.window_upper_mul = 40;
  d.solver.colouring = "tiles";
  for (const bool per_brick : {false, true}) {
  CAPTURE(per_brick);
  d.solver.per_brick_steps = per_brick;
  auto st = test::make_setup(d);
  std::vector<mc::StepRecord> full;
  mc::Checkpoint cp;
  {
    mc::Solver solver(d, st.s, st.f);
    solver.run([&](const mc::StepRecord& r) {
      full.push_back(r);
      if (r.step == 2) cp = solver.checkpoint();
    });
  }
  REQUIRE(full.size() > 3);
  // through a file, as the app does
  const auto path = std::filesystem::temp_directory_path() / "nacre_test_checkpoint.h5";
  io::write_checkpoint(path, mc::to_named(cp, "fingerprint", "deck text", d.load.final_displacement));
  const mc::Checkpoint back = mc::from_named(io::read_checkpoint(path), st.s.size(),
                                             static_cast<std::size_t>(mc::Solver(d, st.s, st.f).model().n_free));
  std::filesystem::remove(path);
  CHECK(back.pose == cp.pose);
  CHECK(back.global_cycle == cp.global_cycle);
  mc::Solver resumed(d, st.s, st.f);
  resumed.restore(back);
  std::vector<mc::StepRecord> rest;
  resumed.run([&](const mc::StepRecord& r) { rest.push_back(r); });
  REQUIRE(rest.size() == full.size() - 2);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    CHECK(rest[i].step == full[i + 2].step);
    CHECK(rest[i].energy == full[i + 2].energy);  // bit for bit
    CHECK(rest[i].cycles == full[i + 2].cycles);
    CHECK(rest[i].displacement == full[i + 2].displacement);
  }
  }
}

TEST_CASE("adaptive step size (eq. 2.7) pulls the acceptance into [0.4, 0.6] from a bad start",
          "[mc][adaptive]") {
  auto d = small_deck();
  d.solver.temperature = 1e-7;
  // start far too large (almost every trial rejected) and far too small (almost all accepted),
  // with one global step and with a step per brick
  for (const bool per_brick : {false, true})
  for (double start : {1e-3, 1e-9}) {
    CAPTURE(per_brick, start);
    d.solver.per_brick_steps = per_brick;
    d.solver.step = start, d.solver.min_step = 1e-12, d.solver.max_step = 1e-2;
    d.solver.rot_step = start, d.solver.min_rot_step = 1e-12, d.solver.max_rot_step = 1e-2;
    d.solver.adapt_interval = 10;
    auto st = test::make_setup(d);
    mc::Solver solver(d, st.s, st.f);
    solver.set_load(1e-3);
    const long n = solver.model().n_free;
    long first = 0;
    for (int c = 0; c < 10; ++c) first += solver.cycle();
    for (int c = 0; c < 2000; ++c) solver.cycle();
    long acc = 0;
    for (int c = 0; c < 10; ++c) acc += solver.cycle();  // one adaptation window
    const double a0 = static_cast<double>(first) / (10.0 * n), a = static_cast<double>(acc) / (10.0 * n);
    INFO("acceptance first " << a0 << ", later " << a << ", step " << solver.step_size());
    CHECK((a0 < 0.2 || a0 > 0.8));  // the start really was bad
    CHECK(a > 0.3);
    CHECK(a < 0.7);
  }
}

TEST_CASE("adaptive displacement backtracks a step that takes too long and still finishes",
          "[mc][adaptive]") {
  auto d = cracking_deck();
  d.load.initial_step = 0.01, d.load.min_step = 0.001, d.load.max_step = 0.01;
  d.solver.adapt_interval = 20;
  d.solver.window_size = 60, d.solver.convergence_rep = 20;
  // c_u = 4 x 20 = 80 cycles < window + repetitions: the first attempt of every step above the
  // minimum increment must fail and be retried smaller, down to the minimum, which then runs on
  d.solver.window_mul = 2, d.solver.window_upper_mul = 4;
  // the paper's criterion: with the residual one, the polish would converge every first attempt
  d.solver.convergence = "window";
  d.solver.polish = "none";
  auto st = test::make_setup(d);
  mc::Solver solver(d, st.s, st.f);
  std::vector<mc::StepRecord> rows;
  solver.run([&](const mc::StepRecord& r) { rows.push_back(r); });
  REQUIRE(!rows.empty());
  CHECK(rows.front().reverts > 0);
  CHECK(rows.front().increment < 0.01);
  CHECK(rows.back().displacement == Catch::Approx(0.02));
  for (const auto& r : rows) CHECK(r.increment >= 0.001 * (1 - 1e-12));
}
