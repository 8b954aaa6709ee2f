// SPDX-License-Identifier: BSD-3-Clause
// Time per step of the explicit dynamics (UE, BE) against the number of bricks, set against the
// memory-bandwidth bound measured in the same run: bytes a step must move at least are counted
// from the model's array sizes (Simulation::step_bytes: every model view read once, the state
// arrays u, v, a, acc read and written once; not the interface force rows, BIE's p_n / v_n or
// the roll-back copy, which a step need not stream), and a Kokkos STREAM triad a = b + s c gives
// the attainable bandwidth on the same threads. Wall and CPU time (process CPU time / threads:
// robust to other processes on a shared machine; the triad is timed the same way). Also bytes
// per brick with and without shared element matrices. The column bytes_per_step_held is the
// previous count (all bytes held, incl. the interface force rows and the roll-back copy).
//
//   nacre_perf_dyn_step --bricks 10000,50000,100000 --methods ue,be --steps 200 --csv FILE
//
// Damping (default none, C = 0): --damping table42 sets Rayleigh C = alpha_d M + beta_d K from
// Table 4.2 (dyn::table_4_2_damping: nearest tabulated brick count to --bricks, nearest ratio);
// table42_mass its alpha_d only (beta_d = 0, the README BIE deck's damping);
// --alpha/--beta (1/s, s) give them directly. Damped runs use each method's step found with the
// damping of that size, capped by its undamped one (see below), so dt is per method and size.
//
// Run once per thread count (--kokkos-num-threads=N); perf/run_dyn_bench.sh does that and charts.
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>

#include <nacre/perf/bounds.hpp>
#include <nacre/perf/tool_timer.hpp>

#include "specimen_size.hpp"

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

using namespace nacre;

namespace {

using clock_type = std::chrono::steady_clock;
double seconds_since(clock_type::time_point t0) {
  return std::chrono::duration<double>(clock_type::now() - t0).count();
}
/// CPU time of the process (all threads), s.
double process_cpu() { return perf::process_cpu_seconds(); }

/// Specimen of ~`bricks` bricks of 0.105 x 0.03 mm (MODEL.md §5: L ~ 30 µm), notched, in bending.
deck::Deck deck_for(long bricks, double ratio) {
  deck::Deck d;
  size_dyn_specimen(d.geometry, bricks);
  const double kx1 = 70.63;  // Table 4.1 k x1 at r = 500, N/mm^2
  d.mortar.bed = d.mortar.head = {7000.0, kx1 / 7000.0, 22.0 / kx1};
  d.load.tension = 0, d.load.bending = 1, d.load.final_displacement = 0.01;
  d.dynamics.enabled = true;
  d.dynamics.stiffness_ratio = ratio;
  return d;
}

dyn::Params params_for(const deck::Deck& d, dyn::Method m) {
  dyn::Params p;
  p.method = m;
  p.youngs_modulus = d.dynamics.modulus();
  p.rate = 1000.0;  // mm/s: a load is on, so the interface kernels do real work
  p.ramp = dyn::Ramp::smooth, p.ramp_time = 1e-6;  // no impulsive start (its kinetic energy trips the blow-up bound)
  p.final_displacement = d.load.final_displacement;
  p.tension = d.load.tension, p.bending = d.load.bending;
  return p;
}

dyn::Method method_of(const std::string& name) {
  return name == "ue" ? dyn::Method::ue : (name == "bie" || name == "bie_dense" || name == "bie_split") ? dyn::Method::bie : dyn::Method::be;
}

std::size_t state_bytes(const dyn::StateArrays& s) {
  std::size_t b = 0;
  for (const char* k : {"u", "v", "a", "acc", "dacc"})
    if (auto it = s.find(k); it != s.end()) b += it->second.size() * sizeof(double);
  return b;
}

}  // namespace

int main(int argc, char* argv[]) {
  Kokkos::ScopeGuard guard(argc, argv);
  CLI::App cli{"nacre dynamics time per step vs bricks, against a Kokkos triad"};
  std::vector<long> sizes{10000, 50000, 100000};
  std::vector<std::string> methods{"ue", "be"};
  long steps = 200;
  int blocks = 3;
  double ratio = 500;
  std::size_t triad_n = std::size_t(1) << 25;
  std::string csv, profile_csv;
  int bie_iterations = 0;  // 0: the Params default (2, as the dissertation)
  cli.add_option("--bricks", sizes)->delimiter(',');
  cli.add_option("--methods", methods)->delimiter(',');
  cli.add_option("--steps", steps, "steps per timed block");
  cli.add_option("--blocks", blocks, "timed blocks (best is kept)");
  cli.add_option("--ratio", ratio, "stiffness ratio r");
  std::string apply = "automatic";
  cli.add_option("--apply", apply, "element apply: automatic, per_element or tiled");
  std::string damping = "none";
  cli.add_option("--damping", damping,
                 "Rayleigh damping: none, table42 (Table 4.2 by brick count and ratio) or table42_mass (its alpha_d "
                 "only, beta_d = 0: inputs/dynamic_bie.toml's choice)")
      ->check(CLI::IsMember({"none", "table42", "table42_mass"}));
  double alpha_opt = -1, beta_opt = -1;
  cli.add_option("--alpha", alpha_opt, "Rayleigh alpha_d, 1/s (with --beta; overrides --damping)");
  cli.add_option("--beta", beta_opt, "Rayleigh beta_d, s (with --alpha; overrides --damping)");
  cli.add_option("--bie-iterations", bie_iterations,
                 "BIE: iterations with the constant J per step (heavily stiffness-damped bricks need 3)");
  cli.add_option("--triad-n", triad_n, "doubles per triad array");
  cli.add_option("--csv", csv)->required();
  cli.add_option("--profile-csv", profile_csv,
                 "after the timed blocks, one more block with every kernel timed (Kokkos tool callbacks): "
                 "ms per step per kernel appended here");
  cli.allow_extras();
  CLI11_PARSE(cli, argc, argv);
  std::cout << std::unitbuf;  // progress lines reach a log even when a time limit kills the run (seen on an H100)
  if (bie_iterations < 0 || bie_iterations > 16) {
    std::cerr << "[dyn_step] --bie-iterations: expected 1 to 16 (0: the default, 2)\n";
    return 2;
  }
  if ((alpha_opt >= 0) != (beta_opt >= 0)) {
    std::cerr << "[dyn_step] --alpha and --beta go together (both >= 0)\n";
    return 2;
  }
  // Rayleigh (alpha_d, beta_d) for a specimen of ~n bricks
  auto damping_for = [&](long n, double& a, double& b) {
    a = 0, b = 0;
    if (alpha_opt >= 0) a = alpha_opt, b = beta_opt;
    else if (damping != "none") {
      dyn::table_4_2_damping(static_cast<std::size_t>(n), ratio, a, b);
      if (damping == "table42_mass") b = 0;
    }
  };
  // what a method name and a size set beyond params_for: the damping, the J^-1 apply form
  // (bie_dense: dense apply and full last iteration, the comparison) and BIE's iterations
  auto variant = [&](dyn::Params& q, const std::string& mname, long n) {
    damping_for(n, q.alpha_d, q.beta_d);
    q.bie_block_structure = mname != "bie_dense";
    if (mname == "bie_split") q.bie_scheme = dyn::BieScheme::split;
    if (bie_iterations > 0) q.bie_iterations = bie_iterations;
  };

  const Kokkos::DefaultExecutionSpace space;
  const int threads = space.concurrency();
  const perf::Triad measured = perf::triad(space, triad_n, 10);
  const double triad = measured.bytes_per_s, triad_cpu = measured.cpu_bytes_per_s;
  std::cout << "[dyn_step] " << threads << " threads: triad " << triad / 1e9 << " GB/s wall, " << triad_cpu / 1e9
            << " GB/s CPU time (" << triad_n << " doubles per array)\n";
  const bool header = !std::ifstream(csv).good();
  std::ofstream out(csv, std::ios::app);
  if (header)
    out << "method,bricks,threads,element_types,steps,seconds_per_step,bytes_per_step,state_bytes,device_bytes,"
           "bytes_per_brick,bytes_per_brick_unshared,effective_bandwidth,triad_bandwidth,bound_ratio,dt,"
           "cpu_seconds_per_step,triad_bandwidth_cpu,bound_ratio_cpu,bytes_per_step_held,alpha_d,beta_d\n";
  // a stable step per method (and per damping: per size when damped) from a small specimen of the
  // same bricks (the critical step is local)
  std::map<std::pair<std::string, long>, double> dt;
  {
    const deck::Deck ds = deck_for(600, ratio);
    geometry::Specimen ss = geometry::build_specimen(ds.geometry);
    const geometry::Interfaces fs = geometry::find_interfaces(ss, ds.geometry);
    std::map<std::pair<std::string, std::pair<double, double>>, double> found;
    for (long n : sizes)
      for (const auto& mname : methods) {
        dyn::Params q = params_for(ds, method_of(mname));
        variant(q, mname, n);
        const auto key = std::make_pair(mname, std::make_pair(q.alpha_d, q.beta_d));
        if (!found.count(key)) {
          double h = dyn::critical_step(q, ss, fs, ds.mortar, 1000, 0.05);
          if (q.alpha_d != 0 || q.beta_d != 0) {
            // Damped, the bisection's 1000-step trial can pass unstable steps: BE's (M + h/2 C)^-1
            // (central differences, average velocity) keeps the undamped limit h omega_max <= 2
            // whatever C, but above it the growth per step ~ (Omega^2 - 4) / (2 xi Omega) is small
            // for xi ~ 1e2 (BE at 0.5 x the damped bisection's step, 600 bricks, Table 4.2 at 10k:
            // blow-up at step 2690). So the step is min(damped, undamped) critical step.
            dyn::Params q0 = q;
            q0.alpha_d = q0.beta_d = 0;
            const double h0 = dyn::critical_step(q0, ss, fs, ds.mortar, 1000, 0.05);
            std::cout << "[dyn_step] " << mname << " critical step damped " << h << " s, undamped " << h0 << " s\n";
            h = std::min(h, h0);
          }
          found[key] = 0.5 * h;
          std::cout << "[dyn_step] " << mname << " alpha_d " << q.alpha_d << " /s, beta_d " << q.beta_d
                    << " s: dt = 0.5 x critical = " << found[key] << " s (600 bricks, rtol 0.05)\n";
        }
        dt[{mname, n}] = found[key];
      }
  }
  for (long n : sizes) {
    const deck::Deck d = deck_for(n, ratio);
    geometry::Specimen s = geometry::build_specimen(d.geometry);
    const geometry::Interfaces f = geometry::find_interfaces(s, d.geometry);
    for (const auto& mname : methods) {
      const dyn::Method m = method_of(mname);
      dyn::Params p = params_for(d, m);
      p.dt = dt[{mname, n}];
      variant(p, mname, n);
      p.element_apply = apply == "tiled" ? dyn::ElementApply::tiled
                        : apply == "per_element" ? dyn::ElementApply::per_element
                                                 : dyn::ElementApply::automatic;
      std::size_t unshared = 0;
      {
        dyn::Params q = p;
        q.share_element_matrices = false;
        unshared = dyn::Simulation(q, s, f, d.mortar).bytes();
      }
      dyn::Simulation sim(p, s, f, d.mortar);
      if (!sim.advance(space, 20)) {
        std::cerr << "[dyn_step] " << mname << " " << n << ": unstable warm-up: " << sim.why() << "\n";
        return 1;
      }
      double best = 1e300, best_cpu = 1e300;
      for (int b = 0; b < blocks; ++b) {
        space.fence();
        const auto t0 = clock_type::now();
        const double c0 = process_cpu();
        const bool ok = sim.advance(space, steps);
        space.fence();
        const double t = seconds_since(t0) / static_cast<double>(steps);
        best_cpu = std::min(best_cpu, (process_cpu() - c0) / static_cast<double>(steps) / threads);
        if (!ok) {
          std::cerr << "[dyn_step] " << mname << " " << n << ": unstable: " << sim.why() << "\n";
          return 1;
        }
        best = std::min(best, t);
      }
      const std::size_t held = sim.bytes(), st = state_bytes(sim.save_state());
      const double moved = static_cast<double>(sim.step_bytes());  // the least a step must stream
      const double eff = moved / best;
      const double bound_cpu = best_cpu / (moved / triad_cpu);
      const double nb = static_cast<double>(sim.bricks());
      out << mname << "," << sim.bricks() << "," << threads << "," << sim.element_types() << "," << steps << ","
          << best << "," << moved << "," << st << "," << held << "," << static_cast<double>(held) / nb << ","
          << static_cast<double>(unshared) / nb << "," << eff << "," << triad << "," << triad / eff << "," << p.dt
          << "," << best_cpu << "," << triad_cpu << "," << bound_cpu << "," << held << "," << p.alpha_d << "," << p.beta_d << "\n";
      out.flush();
      if (!profile_csv.empty()) {
        const bool ph = !std::ifstream(profile_csv).good();
        std::ofstream pout(profile_csv, std::ios::app);
        if (ph) pout << "method,bricks,threads,kernel,ms_per_step,cpu_ms_per_step,calls_per_step,share_of_step\n";
        perf::ToolClock::Table table;
        double total = 0;
        bool ok = false;
        {
          const perf::ToolTimer timer(perf::ToolTimer::kernels);
          space.fence();
          const auto t0 = clock_type::now();
          ok = sim.advance(space, steps);
          space.fence();
          total = seconds_since(t0);
          table = timer.clock().kernels();
        }
        if (!ok) return 1;
        double covered = 0;
        for (const auto& [name, e] : table) {
          covered += e.seconds;
          pout << mname << "," << sim.bricks() << "," << threads << "," << name << ","
               << 1e3 * e.seconds / static_cast<double>(steps) << ","
               << 1e3 * e.cpu_seconds / static_cast<double>(steps) << ","
               << static_cast<double>(e.calls) / static_cast<double>(steps) << "," << e.seconds / total << "\n";
          std::cout << "[dyn_step]   " << name << ": " << 1e3 * e.seconds / static_cast<double>(steps)
                    << " ms/step (" << 100 * e.seconds / total << " %), master-thread CPU "
                    << 1e3 * e.cpu_seconds / static_cast<double>(steps) << " ms/step\n";
        }
        pout << mname << "," << sim.bricks() << "," << threads << ",(outside kernels),"
             << 1e3 * (total - covered) / static_cast<double>(steps) << ",,0," << (total - covered) / total << "\n";
      }
      std::cout << "[dyn_step] " << mname << " " << sim.bricks() << " bricks, " << threads << " threads: "
                << best * 1e3 << " ms/step, " << moved / 1e6 << " MB/step, " << eff / 1e9 << " GB/s = triad / "
                << triad / eff << "; CPU " << best_cpu * 1e3 << " ms/step = bound x " << bound_cpu << "; "
                << moved / nb << " B/brick moved, " << static_cast<double>(held) / nb << " B/brick held shared, "
                << static_cast<double>(unshared) / nb << " unshared\n";
    }
  }
  return 0;
}
