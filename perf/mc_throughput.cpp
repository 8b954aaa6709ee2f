// SPDX-License-Identifier: BSD-3-Clause
// Sweep throughput (brick trials per second) of nacre's colour-parallel Kokkos sweep against a
// plain serial reference written the obvious way: array of structs, bricks visited in wall
// order (no colouring), std::mt19937_64 for the random numbers, every trial evaluating the
// brick's interfaces at the old and at the trial pose (no energy cache), each pose's rotation
// evaluated once per pose change (sin and cos kept with the pose, as nacre does). Same physics
// (the same cohesive functions), same specimen, same temperature and step sizes.
//
//   nacre_perf_mc --bricks 10000,100000,300000 --cycles 20 [--reference] --csv FILE
//
// Run it once per thread count (--kokkos-num-threads=N); perf/run_mc_bench.sh does that and
// charts the result.
#include <nacre/geometry/specimen.hpp>
#include <nacre/mc/solver.hpp>

#include "specimen_size.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <ctime>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

using namespace nacre;

namespace {

deck::Deck deck_for(long bricks) {
  deck::Deck d = mc_bench_deck(bricks);
  d.solver.temperature = 1e-7;
  d.solver.step = d.solver.min_step = d.solver.max_step = 2e-5;
  d.solver.rot_step = d.solver.min_rot_step = d.solver.max_rot_step = 1e-5;
  d.solver.colouring = "natural";
  return d;
}

// ---------------------------------------------------------------- the serial reference
struct RefBrick {
  double x, y, t;
  kinematics::Frame frame;  // the pose with its rotation evaluated (two sines per pose change)
  bool free;
  std::vector<int> ifaces;
};
struct RefIface {
  int a, b;
  kinematics::Segment seg;
  cohesive::Law law;
};

double reference_run(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
                     double load, int cycles, long& trials, double& energy_out) {
  std::vector<RefBrick> bricks(s.size());
  std::vector<RefIface> ifs(f.size());
  const loading::Pattern lp{d.load.tension, d.load.bending, d.geometry.width};
  for (std::size_t i = 0; i < s.size(); ++i) {
    bricks[i].free = s.drive[i] == geometry::Drive::free;
    const auto p = bricks[i].free ? kinematics::Pose{0, 0, 0} : loading::rigid_pose(lp, static_cast<int>(s.drive[i]), s.cx[i], s.cy[i], load);
    bricks[i].x = p.x, bricks[i].y = p.y, bricks[i].t = p.t;
    bricks[i].frame = kinematics::make_frame(p);
  }
  for (std::size_t i = 0; i < f.size(); ++i) {
    ifs[i] = {f.a[i], f.b[i],
              {f.ra0x[i], f.ra0y[i], f.ra1x[i], f.ra1y[i], f.rb0x[i], f.rb0y[i], f.rb1x[i], f.rb1y[i], f.nx[i],
               f.ny[i], f.length[i]},
              f.kind[i] == geometry::JointKind::bed ? d.mortar.bed : d.mortar.head};
    bricks[f.a[i]].ifaces.push_back(static_cast<int>(i));
    bricks[f.b[i]].ifaces.push_back(static_cast<int>(i));
  }
  const auto q = cohesive::gauss_legendre(d.solver.quadrature_points);
  std::mt19937_64 gen(d.seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double T = d.solver.temperature, st = d.solver.step, sr = d.solver.rot_step;
  // the reference gets the same one-trigonometry-per-pose evaluation as nacre's kernel: a trial
  // evaluates the sines of its trial pose only; the neighbours' and the old pose's are kept
  auto brick_energy = [&](std::size_t b, const kinematics::Frame& p) {
    double e = 0;
    for (int i : bricks[b].ifaces) {
      const auto& in = ifs[i];
      const auto& o = bricks[in.a == static_cast<int>(b) ? in.b : in.a];
      const kinematics::Frame& po = o.frame;
      e += in.a == static_cast<int>(b) ? kinematics::interface_energy(in.law, q, in.seg, p, po)
                                       : kinematics::interface_energy(in.law, q, in.seg, po, p);
    }
    return e;
  };
  trials = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int c = 0; c < cycles; ++c)
    for (std::size_t b = 0; b < bricks.size(); ++b) {
      if (!bricks[b].free) continue;
      const kinematics::Pose old{bricks[b].x, bricks[b].y, bricks[b].t};
      const kinematics::Pose trial{old.x + st * (2 * U(gen) - 1), old.y + st * (2 * U(gen) - 1), old.t + sr * (2 * U(gen) - 1)};
      const kinematics::Frame ft = kinematics::make_frame(trial);
      const double dE = brick_energy(b, ft) - brick_energy(b, bricks[b].frame);
      if (dE <= 0 || U(gen) < std::exp(-dE / T))
        bricks[b].x = trial.x, bricks[b].y = trial.y, bricks[b].t = trial.t, bricks[b].frame = ft;
      ++trials;
    }
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double e = 0;
  for (const auto& in : ifs) {
    const auto &A = bricks[in.a], &B = bricks[in.b];
    e += kinematics::interface_energy(in.law, q, in.seg, kinematics::Pose{A.x, A.y, A.t}, kinematics::Pose{B.x, B.y, B.t});
  }
  energy_out = e;
  return sec;
}

}  // namespace

int main(int argc, char* argv[]) {
  std::vector<char*> kargs{argv[0]}, aargs{argv[0]};
  for (int i = 1; i < argc; ++i) (std::string_view(argv[i]).starts_with("--kokkos-") ? kargs : aargs).push_back(argv[i]);
  CLI::App cli{"nacre MC sweep throughput"};
  std::vector<long> sizes{10000, 100000, 300000};
  int cycles = 20, repeats = 3;
  bool reference = false;
  std::vector<std::string> colourings{"tiles", "natural"};
  std::string csv = "mc_throughput.csv";
  cli.add_option("--bricks", sizes, "specimen sizes (bricks)")->delimiter(',');
  cli.add_option("--cycles", cycles, "timed cycles per block");
  cli.add_option("--repeats", repeats, "timed blocks; the fastest counts");
  cli.add_flag("--reference", reference, "also time the serial array-of-structs reference");
  cli.add_option("--colouring", colourings, "sweep schedules to time")->delimiter(',');
  cli.add_option("--csv", csv, "append results to this CSV");
  CLI11_PARSE(cli, static_cast<int>(aargs.size()), aargs.data());
  int kargc = static_cast<int>(kargs.size());
  Kokkos::ScopeGuard guard(kargc, kargs.data());
  const int threads = Kokkos::DefaultExecutionSpace().concurrency();
  const bool header = !std::ifstream(csv).good();
  std::ofstream out(csv, std::ios::app);
  out << std::setprecision(17);  // energy_after to the last bit: builds that must agree are compared by it
  if (header) out << "bricks,free_bricks,implementation,threads,cycles,seconds,trials_per_second,sweep_seconds,rng_seconds,energy_after,cpu_seconds,trials_per_cpu_second\n";
  for (long n : sizes) {
    const deck::Deck d = deck_for(n);
    auto s = geometry::build_specimen(d.geometry);
    auto f = geometry::find_interfaces(s, d.geometry);
    const double load = 0.002;
    for (const auto& colouring : colourings) {
      deck::Deck dc = d;
      dc.solver.colouring = colouring;
      mc::Solver solver(dc, s, f);
      solver.set_load(load);
      solver.cycle();  // warm-up
      Kokkos::fence();
      const mc::PhaseTimes before = solver.times();
      // best of `repeats` blocks: the shared 2-core machine interrupts now and then
      // cpu: process CPU seconds (all threads) of the fastest-CPU block: on a loaded machine the
      // wall time measures the neighbours, trials per CPU-second still measures the code
      double sec = 1e300, cpu = 1e300;
      for (int rep = 0; rep < repeats; ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        for (int c = 0; c < cycles; ++c) solver.cycle();
        Kokkos::fence();
        sec = std::min(sec, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        cpu = std::min(cpu, static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
      }
      const long trials = static_cast<long>(solver.model().n_free) * cycles;
      out << s.size() << "," << solver.model().n_free << ",nacre-" << colouring << "," << threads << "," << cycles << "," << sec << ","
          << trials / sec << "," << (solver.times().sweep - before.sweep) / repeats << "," << (solver.times().rng - before.rng) / repeats << ","
          << solver.energy() << "," << cpu << "," << trials / cpu << "\n";
      std::cout << "nacre-" << colouring << " " << s.size() << " bricks, " << threads << " threads: " << trials / sec / 1e6
                << " M trials/s\n";
    }
    if (reference) {
      long trials = 0;
      double e = 0;
      // the reference warms up too (one cycle), then the same timed blocks, fastest counts
      reference_run(d, s, f, load, 1, trials, e);
      double sec = 1e300;
      for (int rep = 0; rep < repeats; ++rep) sec = std::min(sec, reference_run(d, s, f, load, cycles, trials, e));
      out << s.size() << "," << trials / cycles << ",reference,1," << cycles << "," << sec << "," << trials / sec
          << "," << sec << ",0," << e << "," << sec << "," << trials / sec << "\n";
      std::cout << "reference " << s.size() << " bricks, 1 thread: " << trials / sec / 1e6 << " M trials/s\n";
    }
  }
  return 0;
}
