// SPDX-License-Identifier: BSD-3-Clause
// The 2-D decomposition and the Monte Carlo halo exchange (include/nacre/par/): a colour-swept
// cycle on several ranks must leave the bits of one process. Checked twice: P ranks emulated in
// this process (messages handed over in memory: every build, every P), and the MPI ranks this
// test runs on (mpiexec -np 1, 2, 4 in CTest when built with NACRE_ENABLE_MPI).
#include "../dyn/common.hpp"
#include "../wall_specimen.hpp"

#include <nacre/core/deterministic_sum.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/loading/pattern.hpp>
#include <nacre/mc/colouring.hpp>
#include <nacre/mc/kernels.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/mc/solver.hpp>
#include <nacre/par/comm.hpp>
#include <nacre/par/decomposition.hpp>
#include <nacre/mc/halo.hpp>

#include <catch2/catch_test_macros.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace nacre;

namespace {

using MS = MemSpace;
using Model = mc::Model<MS>;
constexpr std::uint64_t kSeed = 2017;
constexpr double kLoad = 0.012, kStep = 2e-4, kRotStep = 1e-4, kTemperature = 1e-7;

deck::Deck par_deck(double angle) {
  deck::Deck d;
  d.geometry.width = 30, d.geometry.height = 12;
  d.geometry.brick_width = 3.5, d.geometry.brick_height = 1.0;
  d.geometry.notch_length = 10, d.geometry.notch_y = 6;
  d.geometry.angle_deg = angle;
  d.mortar.bed = {100.0, 0.002, 0.004};
  d.mortar.head = {100.0, 0.001, 0.002};
  d.load.tension = 1.0, d.load.bending = 0.5;
  return d;
}

/// What a run leaves, in the specimen's numbering: 5 pose words per brick, the cached energy per
/// interface, and the accepted trials of each colour sweep (summed over ranks).
struct State {
  std::vector<double> pose, energy;
  std::vector<long long> accepted;
};

struct Rank {
  par::Decomposition d;
  Model m;
  std::unique_ptr<mc::PoseHalo<MS>> halo;
  Field<double, MS> cache, de;
};

Rank make_rank(const test::Wall& w, const deck::Deck& dk, const mc::Colouring& global, int rank, int size) {
  Rank r;
  r.d = par::decompose(rank, size, w.s, w.f, w.adj, global.tile);
  const auto ls = par::local_specimen(r.d, w.s);
  const auto lf = par::local_interfaces(r.d, w.f);
  const auto ladj = geometry::build_adjacency(ls.size(), lf);
  r.m = mc::build_model(ExecSpace{}, ls, lf, ladj, mc::local_colouring(r.d, global), dk.mortar, 4);
  r.halo = std::make_unique<mc::PoseHalo<MS>>(ExecSpace{}, r.d, global, r.m);
  r.cache = Field<double, MS>("nacre::test::par_cache", std::max(r.m.n_interfaces, 1));
  r.de = Field<double, MS>("nacre::test::par_de", std::max(r.m.n_free, 1));
  return r;
}

void start(const deck::Deck& dk, const Model& m) {
  mc::apply_load(ExecSpace{}, m, loading::Pattern{dk.load.tension, dk.load.bending, dk.geometry.width}, kLoad);
}

long sweep(const Model& m, int c, long cycle, Field<double, MS> cache, Field<double, MS> de) {
  return mc::sweep_colour(ExecSpace{}, m, m.colour_tiles[c], m.colour_tiles[c + 1],
                          mc::PhiloxUniforms<MS>{m.id, kSeed, static_cast<std::uint64_t>(cycle)}, cache, de, kStep,
                          kRotStep, kTemperature);
}

/// The owned part of a rank's (or the whole) model in the specimen's numbering: bricks
/// `global_brick[k]` for local bricks k < n_owned, interfaces where `owned_iface`.
void collect(const Model& m, Field<double, MS> cache, const std::vector<int>& global_brick, int n_owned,
             const std::vector<int>& global_iface, const std::vector<char>& owned_iface, State& out) {
  auto p = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.pose);
  auto c = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cache);
  for (int k = 0; k < m.n_bricks; ++k) {
    const int local = m.perm[k];
    if (local >= n_owned) continue;
    for (int w = 0; w < mc::kPoseWords; ++w) out.pose[5 * global_brick[local] + w] = p(k, w);
  }
  for (int i = 0; i < m.n_interfaces; ++i) {
    const int local = m.iface_perm[i];
    if (owned_iface[local]) out.energy[global_iface[local]] = c(i);
  }
}

State blank(const test::Wall& w) {
  State s;
  s.pose.assign(5 * w.s.size(), std::nan(""));
  s.energy.assign(w.f.size(), std::nan(""));
  return s;
}

/// One process: the reference.
State one_process(const test::Wall& w, const deck::Deck& dk, const mc::Colouring& col, int cycles) {
  Model m = mc::build_model(ExecSpace{}, w.s, w.f, w.adj, col, dk.mortar, 4);
  Field<double, MS> cache("nacre::test::cache", m.n_interfaces), de("nacre::test::de", m.n_free);
  start(dk, m);
  mc::interface_energies(ExecSpace{}, m, cache);
  State s = blank(w);
  for (int cyc = 0; cyc < cycles; ++cyc)
    for (int c = 0; c < col.n_colours; ++c) s.accepted.push_back(sweep(m, c, cyc, cache, de));
  std::vector<int> all_b(w.s.size()), all_i(w.f.size());
  std::iota(all_b.begin(), all_b.end(), 0), std::iota(all_i.begin(), all_i.end(), 0);
  collect(m, cache, all_b, static_cast<int>(w.s.size()), all_i, std::vector<char>(w.f.size(), 1), s);
  return s;
}

/// P ranks in this process: after each colour every rank's message to q is handed to q.
State emulated(const test::Wall& w, const deck::Deck& dk, const mc::Colouring& col, int P, int cycles) {
  std::vector<Rank> ranks;
  for (int r = 0; r < P; ++r) ranks.push_back(make_rank(w, dk, col, r, P));
  auto deliver = [&](int colour, bool refresh) {
    std::vector<std::vector<std::vector<double>>> out(P), in(P);
    for (int r = 0; r < P; ++r) out[r] = ranks[r].halo->pack(ExecSpace{}, ranks[r].m, colour);
    for (int r = 0; r < P; ++r) {
      in[r] = ranks[r].halo->receive_buffers(colour);
      const auto& nb = ranks[r].halo->neighbours();
      for (std::size_t k = 0; k < nb.size(); ++k) {
        const auto& qnb = ranks[nb[k]].halo->neighbours();
        const auto back = std::find(qnb.begin(), qnb.end(), r) - qnb.begin();
        REQUIRE(back < static_cast<long>(qnb.size()));
        REQUIRE(out[nb[k]][back].size() == in[r][k].size());
        in[r][k] = out[nb[k]][back];
      }
    }
    for (int r = 0; r < P; ++r)
      ranks[r].halo->unpack(ExecSpace{}, ranks[r].m, colour, in[r], refresh ? ranks[r].cache : Field<double, MS>{});
  };
  for (auto& r : ranks) start(dk, r.m);
  deliver(-1, false);
  for (auto& r : ranks) mc::interface_energies(ExecSpace{}, r.m, r.cache);
  State s = blank(w);
  for (int cyc = 0; cyc < cycles; ++cyc)
    for (int c = 0; c < col.n_colours; ++c) {
      long long acc = 0;
      for (auto& r : ranks) acc += sweep(r.m, c, cyc, r.cache, r.de);
      deliver(c, true);
      s.accepted.push_back(acc);
    }
  for (auto& r : ranks) collect(r.m, r.cache, r.d.bricks, r.d.n_owned, r.d.interfaces, r.d.iface_owned, s);
  return s;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

mc::Colouring colouring(const test::Wall& w, const std::string& name) {
  return mc::colour_graph(name, w.s, w.adj, w.free, 1);
}

}  // namespace

TEST_CASE("decomposition: every brick and interface owned once, halos and messages consistent", "[par]") {
  for (const double angle : {0.0, 30.0}) {
    const auto dk = par_deck(angle);
    const auto w = test::wall_of(dk.geometry);
    for (const std::string name : {"natural", "tiles"}) {
      const auto col = colouring(w, name);
      for (int P : {1, 2, 3, 4, 6}) {
        CAPTURE(angle, name, P);
        std::vector<par::Decomposition> ds;
        for (int r = 0; r < P; ++r) ds.push_back(par::decompose(r, P, w.s, w.f, w.adj, col.tile));
        CHECK(ds[0].dims[0] * ds[0].dims[1] == P);
        std::vector<int> owned(w.s.size(), 0), iowned(w.f.size(), 0);
        for (const auto& d : ds) {
          for (int k = 0; k < d.n_owned; ++k) {
            ++owned[d.bricks[k]];
            CHECK(d.owner[d.bricks[k]] == d.rank);
          }
          // the halo is exactly the other ranks' neighbours of owned bricks
          std::set<int> halo;
          for (int k = 0; k < d.n_owned; ++k)
            for (int j = w.adj.offset[d.bricks[k]]; j < w.adj.offset[d.bricks[k] + 1]; ++j)
              if (d.owner[w.adj.neighbour[j]] != d.rank) halo.insert(w.adj.neighbour[j]);
          CHECK(std::vector<int>(d.bricks.begin() + d.n_owned, d.bricks.end()) ==
                std::vector<int>(halo.begin(), halo.end()));
          for (std::size_t i = 0; i < d.interfaces.size(); ++i) iowned[d.interfaces[i]] += d.iface_owned[i];
          // what r sends q is what q receives from r, brick for brick
          for (std::size_t k = 0; k < d.neighbours.size(); ++k) {
            const auto& e = ds[d.neighbours[k]];
            const auto back = std::find(e.neighbours.begin(), e.neighbours.end(), d.rank) - e.neighbours.begin();
            REQUIRE(back < static_cast<long>(e.neighbours.size()));
            std::vector<int> sent, got;
            for (int b : d.send[k]) sent.push_back(d.bricks[b]);
            for (int b : e.recv[back]) got.push_back(e.bricks[b]);
            CHECK(sent == got);
          }
        }
        CHECK(std::all_of(owned.begin(), owned.end(), [](int n) { return n == 1; }));
        CHECK(std::all_of(iowned.begin(), iowned.end(), [](int n) { return n == 1; }));
        // a tile is swept in order by one thread: never split between ranks
        for (std::size_t i = 0; i < w.s.size(); ++i)
          for (std::size_t k = 0; k < w.s.size() && col.tile[i] >= 0; ++k)
            if (col.tile[k] == col.tile[i]) CHECK(ds[0].owner[k] == ds[0].owner[i]);
      }
    }
  }
}

TEST_CASE("Monte Carlo colour sweeps on P emulated ranks leave the bits of one process", "[par][mc]") {
  for (const double angle : {0.0, 30.0}) {
    const auto dk = par_deck(angle);
    const auto w = test::wall_of(dk.geometry);
    for (const std::string name : {"natural", "tiles"}) {
      const auto col = colouring(w, name);
      const State ref = one_process(w, dk, col, 6);
      long long moved = 0;
      for (auto a : ref.accepted) moved += a;
      CHECK(moved > 0);  // the sweeps did something
      for (int P : {1, 2, 3, 4}) {
        CAPTURE(angle, name, P);
        const State got = emulated(w, dk, col, P, 6);
        CHECK(same_bits(got.pose, ref.pose));
        CHECK(same_bits(got.energy, ref.energy));
        CHECK(got.accepted == ref.accepted);
      }
    }
  }
}

TEST_CASE("Monte Carlo colour sweeps on the MPI ranks of this run leave the bits of one process", "[par][mc][mpi]") {
  const par::Comm comm = par::Comm::world();
  for (const double angle : {0.0, 30.0}) {
    const auto dk = par_deck(angle);
    const auto w = test::wall_of(dk.geometry);
    const auto col = colouring(w, "natural");
    const State ref = one_process(w, dk, col, 6);
    Rank r = make_rank(w, dk, col, comm.rank(), comm.size());
    start(dk, r.m);
    r.halo->exchange(ExecSpace{}, comm, r.m, -1);
    mc::interface_energies(ExecSpace{}, r.m, r.cache);
    std::vector<long long> accepted;
    for (int cyc = 0; cyc < 6; ++cyc)
      for (int c = 0; c < col.n_colours; ++c) {
        accepted.push_back(comm.sum(static_cast<long long>(sweep(r.m, c, cyc, r.cache, r.de))));
        r.halo->exchange(ExecSpace{}, comm, r.m, c, r.cache);
      }
    CAPTURE(angle, comm.rank(), comm.size());
    CHECK(accepted == ref.accepted);
    // the total energy summed over ranks (each its owned interfaces) has the one-process bits
    SumWorkspace<MS> ws;
    Model whole = mc::build_model(ExecSpace{}, w.s, w.f, w.adj, col, dk.mortar, 4);
    {
      auto h = Kokkos::create_mirror_view(whole.pose);
      for (int k = 0; k < whole.n_bricks; ++k)
        for (int q = 0; q < 5; ++q) h(k, q) = ref.pose[5 * whole.perm[k] + q];
      Kokkos::deep_copy(whole.pose, h);
    }
    const double e_ref = mc::total_energy(ExecSpace{}, whole, ws);
    Kokkos::View<char*, MS> owned("nacre::test::owned", std::max(r.m.n_interfaces, 1));
    {
      auto h = Kokkos::create_mirror_view(owned);
      for (int i = 0; i < r.m.n_interfaces; ++i) h(i) = r.d.iface_owned[r.m.iface_perm[i]];
      Kokkos::deep_copy(owned, h);
    }
    const mc::InterfaceEvaluator<MS> ev(r.m);
    const double e = deterministic_sum(
        ExecSpace{}, "nacre::test::par_energy", ws, 0, r.m.n_interfaces,
        KOKKOS_LAMBDA(const int i) { return owned(i) ? ev.energy(i) : 0.0; }, par::Reduce{&comm, r.d.owned_interfaces});
    CHECK(std::memcmp(&e, &e_ref, sizeof e) == 0);
    // every rank's poses, gathered on rank 0, are the one-process poses
    State mine = blank(w);
    collect(r.m, r.cache, r.d.bricks, r.d.n_owned, r.d.interfaces, r.d.iface_owned, mine);
    std::vector<double> owned_poses;
    for (int k = 0; k < r.d.n_owned; ++k)
      for (int q = 0; q < 5; ++q) owned_poses.push_back(mine.pose[5 * r.d.bricks[k] + q]);
    const auto all = comm.gather(owned_poses);
    if (comm.rank() == 0) {
      std::vector<double> pose(5 * w.s.size(), std::nan(""));
      for (int q = 0; q < comm.size(); ++q) {
        const auto d = par::decompose(q, comm.size(), w.s, w.f, w.adj, col.tile);
        REQUIRE(all[q].size() == 5u * d.n_owned);
        for (int k = 0; k < d.n_owned; ++k)
          std::copy(all[q].begin() + 5 * k, all[q].begin() + 5 * k + 5, pose.begin() + 5 * d.bricks[k]);
      }
      CHECK(same_bits(pose, ref.pose));
    }
  }
}

TEST_CASE("the Monte Carlo solver spread over the MPI ranks of this run follows the one-process load path bit for bit",
          "[par][mc][mpi][solver]") {
  const par::Comm comm = par::Comm::world();
  struct Case {
    double angle;
    const char* colouring;
    const char* relaxation;  // "auto": trust-region Newton (the factor on rank 0), bursts of Monte Carlo
  };
  for (const auto& [angle, colouring, relaxation] :
       {Case{0.0, "tiles", "monte-carlo"}, Case{30.0, "natural", "monte-carlo"}, Case{30.0, "tiles", "auto"}}) {
    deck::Deck dk = par_deck(angle);
    test::cracking_path(dk);
    dk.load.final_displacement = 0.016;  // three or four adaptive steps, joints softening
    dk.solver.relaxation = relaxation;
    dk.solver.polish = "fire";
    dk.solver.colouring = colouring;
    if (std::string(relaxation) == "auto") dk.mortar.damage = cohesive::Damage::reversible;  // Newton's law
    auto s = geometry::build_specimen(dk.geometry);
    const auto f = geometry::find_interfaces(s, dk.geometry);
    std::vector<mc::StepRecord> ref, got;
    mc::Solver one(Backend{}, dk, s, f, nullptr);
    one.run([&](const mc::StepRecord& r) { ref.push_back(r); });
    mc::Solver spread(Backend{}, dk, s, f, nullptr, comm);
    spread.run([&](const mc::StepRecord& r) { got.push_back(r); });
    CAPTURE(angle, colouring, relaxation, comm.rank(), comm.size());
    REQUIRE(ref.size() >= 3);
    REQUIRE(got.size() == ref.size());
    const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    for (std::size_t k = 0; k < ref.size(); ++k) {
      CAPTURE(k);
      CHECK(ref[k].converged);
      CHECK(got[k].converged == ref[k].converged);
      CHECK(got[k].cycles == ref[k].cycles);
      CHECK(got[k].reverts == ref[k].reverts);
      CHECK(got[k].polish_iterations == ref[k].polish_iterations);
      CHECK(got[k].inner_iterations == ref[k].inner_iterations);
      CHECK(got[k].method == ref[k].method);
      CHECK(got[k].ruptured == ref[k].ruptured);
      CHECK(same(got[k].displacement, ref[k].displacement));
      CHECK(same(got[k].energy, ref[k].energy));
      CHECK(same(got[k].reaction, ref[k].reaction));
      CHECK(same(got[k].residual, ref[k].residual));
      CHECK(same(got[k].acceptance, ref[k].acceptance));
      CHECK(same(got[k].step_size, ref[k].step_size));
    }
    std::vector<double> x0, y0, t0, x1, y1, t1;
    one.poses(x0, y0, t0);
    spread.poses(x1, y1, t1);
    CHECK(same_bits(x1, x0));
    CHECK(same_bits(y1, y0));
    CHECK(same_bits(t1, t0));
    // the checkpoint and the interface states of N ranks are those of one process, on rank 0
    // (the others get the scalars and empty arrays)
    const mc::Checkpoint c0 = one.checkpoint(), c1 = spread.checkpoint();
    const bool root = comm.rank() == 0;
    const auto expect = [&](const std::vector<double>& v) { return root ? v : std::vector<double>(); };
    CHECK(same_bits(c1.pose, expect(c0.pose)));
    CHECK(same_bits(c1.previous_pose, expect(c0.previous_pose)));
    CHECK(same_bits(c1.brick_step, expect(c0.brick_step)));
    CHECK(same_bits(c1.history, expect(c0.history)));
    CHECK(c1.global_cycle == c0.global_cycle);
    CHECK(c1.accepted_total == c0.accepted_total);
    CHECK(c1.trials_total == c0.trials_total);
    CHECK(same(c1.step_size, c0.step_size));
    std::vector<double> e0, e1;
    const auto s0 = one.interface_states(&e0);
    CHECK(spread.interface_states(&e1) == (root ? s0 : std::vector<std::int8_t>()));
    CHECK(same_bits(e1, expect(e0)));
    if (comm.size() > 1) {  // what is not spread yet says so
      deck::Deck nd = dk;
      nd.solver.relaxation = "monte-carlo";
      nd.solver.polish = "anneal";
      CHECK_THROWS_AS(mc::Solver(Backend{}, nd, s, f, nullptr, comm), std::invalid_argument);
    }
  }
}

TEST_CASE("a checkpoint of one process restarts on the MPI ranks of this run (and theirs on one process)",
          "[par][mc][mpi][solver]") {
  const par::Comm comm = par::Comm::world();
  deck::Deck dk = par_deck(0.0);
  test::cracking_path(dk);
  dk.solver.relaxation = "monte-carlo";
  dk.solver.colouring = "natural";
  dk.solver.per_brick_steps = true;
  dk.mortar.damage = cohesive::Damage::irreversible;  // a damage history to carry over
  auto s = geometry::build_specimen(dk.geometry);
  const auto f = geometry::find_interfaces(s, dk.geometry);
  // a first leg to D = 0.008 on one process, then on to 0.016 from its checkpoint: on one
  // process and on this run's ranks, the same steps and poses
  deck::Deck first = dk;
  first.load.final_displacement = 0.008;
  mc::Solver start(Backend{}, first, s, f, nullptr);
  start.run(nullptr);
  const mc::Checkpoint cp = start.checkpoint();
  dk.load.final_displacement = 0.016;
  std::vector<mc::StepRecord> ref, got;
  mc::Solver one(Backend{}, dk, s, f, nullptr);
  one.restore(cp);
  one.run([&](const mc::StepRecord& r) { ref.push_back(r); });
  mc::Solver spread(Backend{}, dk, s, f, nullptr, comm);
  spread.restore(cp);
  spread.run([&](const mc::StepRecord& r) { got.push_back(r); });
  CAPTURE(comm.rank(), comm.size());
  REQUIRE(!ref.empty());
  REQUIRE(got.size() == ref.size());
  for (std::size_t k = 0; k < ref.size(); ++k) {
    CHECK(got[k].cycles == ref[k].cycles);
    CHECK(std::memcmp(&got[k].energy, &ref[k].energy, sizeof(double)) == 0);
  }
  const mc::Checkpoint a = one.checkpoint(), b = spread.checkpoint();  // (gathered to rank 0)
  if (comm.rank() == 0) {
    CHECK(same_bits(b.pose, a.pose));
    CHECK(same_bits(b.history, a.history));
    CHECK(same_bits(b.brick_step, a.brick_step));
  } else {
    CHECK(b.pose.empty());
  }
  CHECK(!a.history.empty());
}

// The dynamic solver (src/dyn) spread over this run's ranks (dyn/halo.hpp): every book, the
// reaction, the ruptures, the step bound, the snapshot and the saved state are the bits of one
// process, for UE, BE and BIE (split; iterated without damping, where the kept force's last
// iteration leaves p, and with it, where it moves p after the last force pass), with irreversible
// damage; a state saved by one
// process restores on the ranks and the run continues on the one-process path.
TEST_CASE("the dynamic solver spread over the MPI ranks of this run steps as one process, bit for bit",
          "[par][dyn][mpi][solver]") {
  const par::Comm comm = par::Comm::world();
  deck::Geometry g = dyntest::wall(6, 12, 2.0);
  g.angle_deg = 15;  // clipped bricks: several element types
  const auto st = dyntest::make(g);
  deck::Mortar mo = dyntest::mortar(7000, 14, 0.056);  // brittle: joints rupture within the run
  mo.damage = cohesive::Damage::irreversible;
  struct Case {
    dyn::Method method;
    dyn::BieScheme scheme;
    bool damped;
  };
  for (const Case c :
       {Case{dyn::Method::ue, dyn::BieScheme::iterate, true}, Case{dyn::Method::be, dyn::BieScheme::iterate, true},
        Case{dyn::Method::bie, dyn::BieScheme::split, true}, Case{dyn::Method::bie, dyn::BieScheme::iterate, false},
        Case{dyn::Method::bie, dyn::BieScheme::iterate, true}}) {
    dyn::Params p = dyntest::params(100, c.method);
    p.bie_scheme = c.scheme;
    if (c.damped) dyn::table_4_2_damping(st.s.size(), 100, p.alpha_d, p.beta_d);
    p.rate = 40000, p.ramp_time = 2e-7, p.ramp = dyn::Ramp::smooth, p.final_displacement = 0.2;
    p.tension = 0, p.bending = 1;
    p.dt = 1e-9;
    dyn::Simulation one(Backend{}, p, st.s, st.f, mo), spread(Backend{}, p, st.s, st.f, mo, comm);
    const double h = 0.5 * one.step_report().estimate;
    CAPTURE(static_cast<int>(c.method), static_cast<int>(c.scheme), comm.rank(), comm.size(), h);
    REQUIRE(spread.step_report().estimate == one.step_report().estimate);
    one.set_initial_dt(h), spread.set_initial_dt(h);
    auto same_books = [&](const dyn::Simulation& a, const dyn::Simulation& b) {
      const dyn::Energies x = a.energies(), y = b.energies();
      CHECK(std::memcmp(&x, &y, sizeof x) == 0);
      const double ra = a.reaction(), rb = b.reaction();
      CHECK(std::memcmp(&ra, &rb, sizeof ra) == 0);
      CHECK(a.ruptured() == b.ruptured());
      CHECK(a.max_penetration() == b.max_penetration());
      CHECK(a.time() == b.time());
    };
    for (int k = 0; k < 8; ++k) {
      REQUIRE(one.advance(512));
      REQUIRE(spread.advance(512));
      same_books(one, spread);
    }
    if (c.method != dyn::Method::ue) CHECK(one.ruptured() > 0);  // (UE's smaller step: not yet)
    const dyn::StepReport ra = one.step_check(), rb = spread.step_check();
    CHECK(ra.bound == rb.bound);
    CHECK(ra.element == rb.element);
    CHECK(ra.iface == rb.iface);
    const dyn::StateArrays sa = one.save_state(), sb = spread.save_state();  // (gathered to rank 0)
    const dyn::Snapshot na = one.snapshot(), nb = spread.snapshot();
    if (comm.rank() == 0) {
      for (const auto& [name, x] : sa) {
        CAPTURE(name);
        REQUIRE(sb.count(name));
        CHECK(same_bits(sb.at(name), x));
      }
      CHECK(same_bits(nb.ux, na.ux));
      CHECK(same_bits(nb.vy, na.vy));
      CHECK(same_bits(nb.tri_syy, na.tri_syy));
      CHECK(same_bits(nb.iface_damage, na.iface_damage));
      CHECK(nb.iface_state == na.iface_state);
    } else {
      CHECK(sb.at("u").empty());
      CHECK(nb.ux.empty());
    }
    // one process's state restored on the ranks (every rank reads the whole arrays)
    dyn::Simulation resumed(Backend{}, p, st.s, st.f, mo, comm);
    resumed.set_initial_dt(h);
    resumed.restore_state(sa);
    REQUIRE(one.advance(256));
    REQUIRE(resumed.advance(256));
    same_books(one, resumed);
  }
}
