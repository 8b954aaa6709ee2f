// SPDX-License-Identifier: BSD-3-Clause
// Monte Carlo colour sweeps spread over MPI ranks (include/nacre/par/): time per cycle split
// into the sweep and the halo exchange (pack, MPI, unpack, the stale energies recomputed), the
// bytes and messages a cycle sends, the halo's size and the load balance, for strong scaling (a
// fixed specimen) or weak scaling (--per-rank: bricks per rank fixed). With --check it also
// runs the one-process sweep on rank 0 and compares every pose bit for bit.
//
//   mpiexec -n P nacre_perf_par --bricks 100000 --cycles 20 --csv out.csv [--check] [--per-rank]
//   mpiexec -n 1 nacre_perf_par --model-only --bricks 1000000 --ranks 4,16,64,256,1024 --csv halo.csv
//
// --model-only decomposes in one process for each rank count of --ranks (no sweeps): the halo
// bytes and messages per rank that docs/scaling.md's model takes. perf/run_par_scaling.sh runs
// both and writes perf/results/par/.
#include <nacre/loading/pattern.hpp>
#include <nacre/mc/colouring.hpp>
#include <nacre/mc/kernels.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/par/comm.hpp>
#include <nacre/par/decomposition.hpp>
#include <nacre/mc/halo.hpp>

#include "specimen_size.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <numeric>
#include <sstream>

using namespace nacre;

namespace {

using MS = MemSpace;
using Clock = std::chrono::steady_clock;
constexpr std::uint64_t kSeed = 2017;

deck::Deck deck_for(long bricks) {
  deck::Deck d = mc_bench_deck(bricks);
  d.load.tension = 1.0, d.load.bending = 0.5;
  return d;
}

struct Specimen {
  geometry::Specimen s;
  geometry::Interfaces f;
  geometry::Adjacency adj;
  mc::Colouring col;
};

Specimen make(const deck::Deck& d, const std::string& colouring) {
  Specimen w;
  w.s = geometry::build_specimen(d.geometry);
  w.f = geometry::find_interfaces(w.s, d.geometry);
  w.adj = geometry::build_adjacency(w.s.size(), w.f);
  std::vector<bool> free;
  for (auto v : w.s.drive) free.push_back(v == geometry::Drive::free);
  w.col = mc::colour_graph(colouring, w.s, w.adj, free, 1);
  return w;
}

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

long sweep(const mc::Model<MS>& m, int c, long cycle, Field<double, MS> cache, Field<double, MS> de) {
  return mc::sweep_colour(ExecSpace{}, m, m.colour_tiles[c], m.colour_tiles[c + 1],
                          mc::PhiloxUniforms<MS>{m.id, kSeed, static_cast<std::uint64_t>(cycle)}, cache, de, 2e-5, 1e-5,
                          1e-7);
}

/// Poses of the owned bricks in the specimen's numbering (5 words each).
std::vector<double> owned_poses(const mc::Model<MS>& m, int n_owned) {
  auto p = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.pose);
  std::vector<double> out(5 * static_cast<std::size_t>(n_owned));
  for (int k = 0; k < m.n_bricks; ++k)
    if (m.perm[k] < n_owned)
      for (int w = 0; w < 5; ++w) out[5 * static_cast<std::size_t>(m.perm[k]) + w] = p(k, w);
  return out;
}

void append(const std::string& path, const std::string& header, const std::string& row) {
  const bool fresh = !std::ifstream(path).good();
  std::ofstream o(path, std::ios::app);
  if (fresh) o << header << '\n';
  o << row << '\n';
}

}  // namespace

int main(int argc, char* argv[]) {
  par::Environment mpi(argc, argv);
  Kokkos::ScopeGuard guard(argc, argv);
  CLI::App app{"nacre_perf_par: Monte Carlo sweeps over MPI ranks"};
  long bricks = 100000;
  int cycles = 20, repeats = 3;
  bool per_rank = false, check = false, model_only = false;
  std::string csv, colouring = "natural", ranks_list = "4,16,64,256,1024";
  app.add_option("--bricks", bricks, "bricks of the specimen (per rank with --per-rank)");
  app.add_option("--cycles", cycles, "cycles per timed repeat");
  app.add_option("--repeats", repeats, "timed repeats (the fastest is reported)");
  app.add_option("--colouring", colouring, "colouring strategy (natural, tiles, ...)");
  app.add_flag("--per-rank", per_rank, "weak scaling: --bricks per rank");
  app.add_flag("--check", check, "compare the poses with one process bit for bit (rank 0 runs it too)");
  app.add_flag("--model-only", model_only, "decompose for each of --ranks in one process; no sweeps");
  app.add_option("--ranks", ranks_list, "rank counts for --model-only");
  app.add_option("--csv", csv, "append a row per run here")->required();
  CLI11_PARSE(app, argc, argv);

  const par::Comm comm = par::Comm::world();
  if (model_only) {
    const auto d = deck_for(bricks);
    const Specimen w = make(d, colouring);
    std::stringstream in(ranks_list);
    for (std::string tok; std::getline(in, tok, ',');) {
      const int P = std::stoi(tok);
      // the busiest rank's halo (messages sized by rank 0's lists would understate a corner)
      long long max_halo = 0, max_owned = 0, min_owned = 1LL << 60, max_nb = 0, total_halo = 0;
      for (int r = 0; r < P; ++r) {
        const auto dd = par::decompose(r, P, w.s, w.f, w.adj, w.col.tile);
        const long long halo = static_cast<long long>(dd.bricks.size()) - dd.n_owned;
        max_halo = std::max(max_halo, halo), total_halo += halo;
        max_owned = std::max<long long>(max_owned, dd.n_owned), min_owned = std::min<long long>(min_owned, dd.n_owned);
        max_nb = std::max<long long>(max_nb, static_cast<long long>(dd.neighbours.size()));
        if (P > 64 && r >= 64) break;  // a sample of ranks is enough for the large counts
      }
      std::ostringstream row;
      row << P << ',' << w.s.size() << ',' << w.col.n_colours << ',' << min_owned << ',' << max_owned << ',' << max_halo
          << ',' << max_nb << ',' << max_halo * mc::kPoseWords * 8;
      append(csv, "ranks,bricks,colours,min_owned,max_owned,max_halo_bricks,max_neighbours,max_bytes_per_cycle",
             row.str());
      std::cout << row.str() << std::endl;
    }
    return 0;
  }

  const long total = per_rank ? bricks * comm.size() : bricks;
  const auto d = deck_for(total);
  const Specimen w = make(d, colouring);
  const auto dd = par::decompose(comm.rank(), comm.size(), w.s, w.f, w.adj, w.col.tile);
  const auto ls = par::local_specimen(dd, w.s);
  const auto lf = par::local_interfaces(dd, w.f);
  mc::Model<MS> m = mc::build_model(ExecSpace{}, ls, lf, geometry::build_adjacency(ls.size(), lf),
                                    mc::local_colouring(dd, w.col), d.mortar, 4);
  mc::PoseHalo<MS> halo(ExecSpace{}, dd, w.col, m);
  Field<double, MS> cache("nacre::perf::cache", std::max(m.n_interfaces, 1)),
      de("nacre::perf::de", std::max(m.n_free, 1));
  mc::apply_load(ExecSpace{}, m, loading::Pattern{d.load.tension, d.load.bending, d.geometry.width}, 0.004);
  halo.exchange(ExecSpace{}, comm, m, -1);
  mc::interface_energies(ExecSpace{}, m, cache);

  double best = 1e300, best_sweep = 0, best_exchange = 0;
  long long accepted = 0;
  long cycle = 0;
  for (int rep = 0; rep < repeats; ++rep) {
    comm.barrier();
    double t_sweep = 0, t_exchange = 0;
    const auto t0 = Clock::now();
    for (int k = 0; k < cycles; ++k, ++cycle)
      for (int c = 0; c < w.col.n_colours; ++c) {
        const auto a = Clock::now();
        accepted += sweep(m, c, cycle, cache, de);
        ExecSpace{}.fence();
        const auto b = Clock::now();
        halo.exchange(ExecSpace{}, comm, m, c, cache);
        t_sweep += seconds(a, b), t_exchange += seconds(b, Clock::now());
      }
    const double t = comm.max(seconds(t0, Clock::now()));
    if (t < best)
      best = t, best_sweep = comm.max(t_sweep), best_exchange = comm.max(t_exchange);
    else
      (void)comm.max(t_sweep), (void)comm.max(t_exchange);
  }
  accepted = comm.sum(accepted);
  const long long bytes = comm.sum(halo.cycle_bytes());
  long long counts[3] = {static_cast<long long>(dd.bricks.size()) - dd.n_owned, dd.n_owned,
                         static_cast<long long>(halo.neighbours().size()) * w.col.n_colours};
  comm.sum(counts, 3);
  const double max_owned = comm.max(dd.n_owned), min_owned = -comm.max(-static_cast<double>(dd.n_owned));

  std::string agree = "not checked";
  if (check) {
    // every rank's owned poses against one process's run of the same cycles
    std::vector<double> mine = owned_poses(m, dd.n_owned);
    const auto all = comm.gather(mine);
    if (comm.rank() == 0) {
      mc::Model<MS> g = mc::build_model(ExecSpace{}, w.s, w.f, w.adj, w.col, d.mortar, 4);
      Field<double, MS> gc("nacre::perf::gcache", g.n_interfaces), gd("nacre::perf::gde", std::max(g.n_free, 1));
      mc::apply_load(ExecSpace{}, g, loading::Pattern{d.load.tension, d.load.bending, d.geometry.width}, 0.004);
      mc::interface_energies(ExecSpace{}, g, gc);
      for (long k = 0; k < cycle; ++k)
        for (int c = 0; c < w.col.n_colours; ++c) sweep(g, c, k, gc, gd);
      const auto ref = owned_poses(g, g.n_bricks);
      long long differ = 0;
      for (int q = 0; q < comm.size(); ++q) {
        const auto dq = par::decompose(q, comm.size(), w.s, w.f, w.adj, w.col.tile);
        for (int k = 0; k < dq.n_owned; ++k)
          differ += std::memcmp(&all[q][5 * static_cast<std::size_t>(k)],
                                &ref[5 * static_cast<std::size_t>(dq.bricks[k])], 5 * sizeof(double)) != 0;
      }
      agree = differ == 0 ? "bit-identical" : std::to_string(differ) + " bricks differ";
    }
  }
  if (comm.rank() == 0) {
    const double per_cycle = best / cycles;
    std::ostringstream row;
    row << comm.size() << ',' << dd.dims[0] << 'x' << dd.dims[1] << ',' << w.s.size() << ',' << w.col.n_colours << ','
        << Kokkos::DefaultExecutionSpace().concurrency() << ',' << cycles << ',' << per_cycle << ','
        << best_sweep / cycles << ',' << best_exchange / cycles << ',' << bytes << ',' << counts[2] << ',' << counts[0]
        << ',' << min_owned << ',' << max_owned << ',' << accepted << ',' << agree;
    append(csv,
           "ranks,grid,bricks,colours,threads_per_rank,cycles,s_per_cycle,sweep_s_per_cycle,exchange_s_per_cycle,"
           "bytes_per_cycle,messages_per_cycle,halo_bricks,min_owned,max_owned,accepted,agreement",
           row.str());
    std::cout << row.str() << std::endl;
  }
  return 0;
}
