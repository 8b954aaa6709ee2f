// SPDX-License-Identifier: BSD-3-Clause
// Chapter 4's experiments for the three dynamic methods (issue 8): critical step against
// stiffness ratio, time per step against bricks (and the J^-1 apply variants alone), total
// speed-up to the same simulated time, strain-energy error against step (fitted order), memory
// per brick, accuracy against wall time, and where BIE fails. One subcommand per experiment,
// each writing one CSV; perf/bie/run_bie_bench.sh runs them and perf/bie/plot_bie.py charts them.
// Never part of the tests (timings are not tests).
#include <nacre/dyn/bie.hpp>
#include <nacre/dyn/model.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/perf/bounds.hpp>

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace nacre;
using Exec = Kokkos::DefaultExecutionSpace;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kBrickH = 0.0307;  // mm, Table 4.1 (E / (k L) = ratio with L = kBrickH)

struct Setup {
  geometry::Specimen s;
  geometry::Interfaces f;
};

/// A running-bond wall of about `bricks` bricks, physically square, notch over 30 % of the width
/// at mid-height (clipped and split pieces, as the decks have).
Setup specimen(long bricks, double notch = 0.3) {
  deck::Geometry g;
  g.brick_height = kBrickH, g.brick_width = 3.5 * kBrickH;
  const int nx = std::max(2, static_cast<int>(std::lround(std::sqrt(static_cast<double>(bricks) / 3.5))));
  const int ny = std::max(3, static_cast<int>(std::lround(static_cast<double>(bricks) / nx)));
  g.width = nx * g.brick_width, g.height = ny * g.brick_height;
  g.overlap = 0.5, g.angle_deg = 0, g.notch_length = notch * g.width, g.notch_y = 0.5 * g.height + 0.5 * kBrickH;
  g.min_piece_fraction = 0.02, g.driven_rows = 1;
  Setup st;
  st.s = geometry::build_specimen(g);
  st.f = geometry::find_interfaces(st.s, g);
  return st;
}

deck::Mortar mortar() {  // Table 4.1: k = 700 daN/mm^3, k x1 = 7.06 daN/mm^2, k x1 x2 = 2.2 daN/mm
  const double k = 7000, kx1 = 70.626, kx1x2 = 22;
  return deck::Mortar{{k, kx1 / k, kx1x2 / kx1}, {k, kx1 / k, kx1x2 / kx1}};
}

dyn::Params params(dyn::Method m, double ratio) {
  dyn::Params p;
  p.method = m;
  p.youngs_modulus = 214.99 * ratio;
  p.rate = 20.0, p.ramp_time = 2e-6, p.ramp = dyn::Ramp::smooth, p.tension = 0, p.bending = 1;
  return p;
}

double estimate(dyn::Params p, const Setup& st) {
  p.dt = 1.0;
  dyn::HostMap map;
  return dyn::build_model(p, st.s, st.f, mortar(), map).step_estimate;
}

const char* name(dyn::Method m) { return m == dyn::Method::ue ? "ue" : (m == dyn::Method::be ? "be" : "bie"); }

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string t;
  while (std::getline(ss, t, ',')) v.push_back(std::stod(t));
  return v;
}

double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

/// Largest stable step: critical_step started from 0.9x the Gershgorin estimate (BIE: from the
/// BE estimate, which is a stable start for it too).
double crit(dyn::Params p, const Setup& st, long steps, double rtol) {
  auto q = p;
  if (q.method == dyn::Method::bie) q.method = dyn::Method::be;
  p.dt = 0.9 * estimate(q, st);
  return dyn::critical_step(p, st.s, st.f, mortar(), steps, rtol);
}

struct Variant {
  dyn::Method m;
  dyn::BieSolve solve = dyn::BieSolve::shared_gemm;
  int nb = 4;
  std::string label() const {
    if (m != dyn::Method::bie) return name(m);
    std::string s = std::string("bie_") + dyn::bie_solve_name(solve);
    if (solve == dyn::BieSolve::reordered) s += std::to_string(nb);
    return s;
  }
};

std::vector<Variant> all_variants() {
  std::vector<Variant> v{{dyn::Method::ue}, {dyn::Method::be}};
  for (auto s : {dyn::BieSolve::row, dyn::BieSolve::reordered, dyn::BieSolve::batched, dyn::BieSolve::shared_gemm}) {
    if (!dyn::bie_solve_available(s)) {
      std::cerr << "bie_bench: SKIPPING bie_solve = batched (Kokkos Kernels not in this build)\n";
      continue;
    }
    if (s == dyn::BieSolve::reordered)
      for (int nb : {2, 4, 5, 10}) v.push_back({dyn::Method::bie, s, nb});
    else
      v.push_back({dyn::Method::bie, s});
  }
  return v;
}

// ---------------------------------------------------------------- critical step vs ratio
void critical(long bricks, const std::string& ratios, long steps, double rtol, std::ostream& out) {
  const auto st = specimen(bricks);
  out << "method,ratio,bricks,critical_step_s,estimate_s,rtol,trial_steps\n";
  for (double r : parse_list(ratios))
    for (auto m : {dyn::Method::ue, dyn::Method::be, dyn::Method::bie}) {
      const auto p = params(m, r);
      const double h = crit(p, st, steps, rtol);
      auto q = p;
      if (q.method == dyn::Method::bie) q.method = dyn::Method::be;
      out << name(m) << "," << r << "," << st.s.size() << "," << h << "," << estimate(q, st) << "," << rtol << ","
          << steps << "\n";
      std::cerr << "critical " << name(m) << " ratio " << r << ": " << h << " s\n";
    }
}

// ---------------------------------------------------------------- time per step vs bricks
void timing(const std::string& sizes, double ratio, long steps, std::ostream& out) {
  out << "label,method,bricks,threads,s_per_step,solve_s_per_apply,solve_gflops,bytes,triad_gbs\n";
  const int threads = Exec().concurrency();
  // the triad a = b + s c over 2^24 doubles, best of 5 (the machine's streaming rate now; perf/bounds.hpp)
  const double triad = perf::triad(Exec(), std::size_t(1) << 24, 5).bytes_per_s / 1e9;
  for (double nbk : parse_list(sizes)) {
    const auto st = specimen(static_cast<long>(nbk));
    const double hbe = estimate(params(dyn::Method::be, ratio), st);
    for (const auto& v : all_variants()) {
      auto p = params(v.m, ratio);
      p.bie_solve = v.solve, p.bie_block = v.nb;
      // a stable step for each method; the cost per step does not depend on it
      p.dt = v.m == dyn::Method::ue ? 0.5 * estimate(p, st) : (v.m == dyn::Method::be ? 0.5 * hbe : 4 * hbe);
      dyn::Simulation sim(p, st.s, st.f, mortar());
      sim.advance(Exec{}, 32);  // warm-up
      double best = 1e30;
      for (int rep = 0; rep < 3; ++rep) {
        const auto t0 = Clock::now();
        if (!sim.advance(Exec{}, steps)) std::cerr << "timing: " << v.label() << " unstable: " << sim.why() << "\n";
        Exec().fence();
        best = std::min(best, seconds(t0) / static_cast<double>(steps));
      }
      // the J^-1 apply alone (BIE): in place on a residual block, best of 5 x 20 applies
      double solve = 0, gflops = 0;
      if (v.m == dyn::Method::bie) {
        dyn::HostMap map;
        const auto m = dyn::build_model(p, st.s, st.f, mortar(), map);
        const auto b = dyn::build_bie_tables(m);
        dyn::DofView<Exec::memory_space> R("R", m.n_elem, b.n2);
        Kokkos::deep_copy(R, 1e-3);
        dyn::BieSolveOp<Exec::memory_space> op{b.Jinv, b.slot_type, b.tile_start, b.tile_count, R, b.n2};
        const int ntile = static_cast<int>(b.tile_start.extent(0));
        solve = 1e30;
        for (int rep = 0; rep < 5; ++rep) {
          const auto t0 = Clock::now();
          for (int k = 0; k < 20; ++k) dyn::bie_solve(Exec{}, op, v.solve, v.nb, m.n_elem, ntile);
          Exec().fence();
          solve = std::min(solve, seconds(t0) / 20);
        }
        gflops = 2.0 * b.n2 * b.n2 * m.n_elem / solve / 1e9;
      }
      out << v.label() << "," << name(v.m) << "," << st.s.size() << "," << threads << "," << best << "," << solve << ","
          << gflops << "," << sim.bytes() << "," << triad << "\n";
      out.flush();
      std::cerr << "timing " << v.label() << " bricks " << st.s.size() << " threads " << threads << ": " << best * 1e3
                << " ms/step\n";
    }
  }
}

// ---------------------------------------------------------------- speedup and accuracy: the variants
// UE, BE, BIE iterated, BIE split (index 0..3). --damped puts Table 4.2's damping (the 10k-brick row
// of ratio r) on every method and caps each method's step by its undamped critical step, as
// nacre_perf_dyn_step does (the bisection of an explicit method under heavy stiffness damping finds
// growth too slow for its trials, docs/methods.md "Damped").
const dyn::Method kVariantMethod[4] = {dyn::Method::ue, dyn::Method::be, dyn::Method::bie, dyn::Method::bie};
const char* const kVariantName[4] = {"ue", "be", "bie", "bie_split"};

dyn::Params variant_params(int k, double r, bool damped) {
  dyn::Params p = params(kVariantMethod[k], r);
  if (damped) dyn::table_4_2_damping(10206, r, p.alpha_d, p.beta_d);
  if (k == 3) p.bie_scheme = dyn::BieScheme::split;
  return p;
}

double variant_crit(int k, double r, bool damped, const Setup& st, long crit_steps) {
  const double h = crit(variant_params(k, r, damped), st, crit_steps, 0.02);
  return damped ? std::min(h, crit(variant_params(k, r, false), st, crit_steps, 0.02)) : h;
}

// ---------------------------------------------------------------- speed-up to the same time
// --damped: Table 4.2's damping on every method and BIE's split step (bie_split) beside the
// iterated one (variant_params); the simulated time is bie_steps steps of the larger BIE step.
void speedup(long bricks, const std::string& ratios, long bie_steps, long crit_steps, double safety, bool damped,
             std::ostream& out) {
  const auto st = specimen(bricks);
  out << "method,ratio,bricks,critical_step_s,step_used_s,steps,sim_time_s,wall_s,s_per_step,speedup_vs_ue,"
         "speedup_vs_be,stable,alpha_d,beta_d\n";
  const int nm = damped ? 4 : 3;
  for (double r : parse_list(ratios)) {
    double h[4], wall[4], sps[4];
    long n[4];
    bool ok[4];
    for (int k = 0; k < nm; ++k) h[k] = variant_crit(k, r, damped, st, crit_steps);
    const double T = bie_steps * safety * (damped ? std::max(h[2], h[3]) : h[2]);
    for (int k = 0; k < nm; ++k) {
      auto p = variant_params(k, r, damped);
      p.dt = safety * h[k];
      n[k] = std::lround(std::ceil(T / p.dt));
      p.dt = T / static_cast<double>(n[k]);
      dyn::Simulation sim(p, st.s, st.f, mortar());
      const auto t0 = Clock::now();
      ok[k] = sim.advance(Exec{}, n[k]);
      Exec().fence();
      wall[k] = seconds(t0), sps[k] = wall[k] / static_cast<double>(n[k]);
      std::cerr << "speedup " << kVariantName[k] << " ratio " << r << ": " << n[k] << " steps, " << wall[k] << " s"
                << (ok[k] ? "" : " UNSTABLE") << "\n";
    }
    for (int k = 0; k < nm; ++k) {
      const auto p = variant_params(k, r, damped);
      out << kVariantName[k] << "," << r << "," << st.s.size() << "," << h[k] << "," << T / n[k] << "," << n[k] << "," << T
          << "," << wall[k] << "," << sps[k] << "," << wall[0] / wall[k] << "," << wall[1] / wall[k] << "," << ok[k]
          << "," << p.alpha_d << "," << p.beta_d << "\n";
    }
    out.flush();
  }
}

// ---------------------------------------------------------------- accuracy: error vs step and wall time
struct History {
  std::vector<double> strain;
  double wall = 0;
  bool ok = true;
  double newton = 0;
  double dt = 0;  ///< the step actually used (T / n, n a multiple of the samples, <= the one asked for)
};
History history(dyn::Params p, const Setup& st, double T, int samples) {
  History hst;
  // n a multiple of `samples`: every run samples the history at exactly the same times
  const long n = samples * std::max(1L, static_cast<long>(std::ceil(T / p.dt / samples - 1e-9)));
  p.dt = T / static_cast<double>(n);
  hst.dt = p.dt;
  dyn::Simulation sim(p, st.s, st.f, mortar());
  const auto t0 = Clock::now();
  long done = 0;
  for (int k = 1; k <= samples; ++k) {
    const long target = n / samples * k;
    if (!sim.advance(Exec{}, target - done)) {
      hst.ok = false;
      break;
    }
    done = target;
    hst.strain.push_back(sim.energies().strain);
    hst.newton = std::max(hst.newton, sim.bie_residual());
  }
  Exec().fence();
  hst.wall = seconds(t0);
  return hst;
}
double history_error(const History& a, const History& ref) {
  if (!a.ok || a.strain.size() != ref.strain.size()) return std::nan("");
  double e = 0, s = 0;
  for (std::size_t k = 0; k < ref.strain.size(); ++k)
    e = std::max(e, std::abs(a.strain[k] - ref.strain[k])), s = std::max(s, std::abs(ref.strain[k]));
  return e / s;
}

// --damped: Table 4.2's damping on every method, references included (variant_params); the
// horizon in steps of the larger BIE step.
void accuracy(long bricks, double ratio, long crit_steps, double T_in_bie_steps, int levels, bool damped,
              std::ostream& out) {
  const auto st = specimen(bricks);
  double h[4];
  for (int k = 0; k < 4; ++k) h[k] = variant_crit(k, ratio, damped, st, crit_steps);
  const double T = T_in_bie_steps * std::max(h[2], h[3]);
  const int samples = 16;
  // common reference: BE (the bolted model) at 1/8 of its smallest step below; UE's own
  // reference at 1/8 of its smallest step (UE is a different model: stiff joints, not bolts)
  const double fine = std::pow(0.5, levels + 2);
  auto pbe = variant_params(1, ratio, damped);
  pbe.dt = h[1] * fine;
  const History ref_be = history(pbe, st, T, samples);
  auto pue = variant_params(0, ratio, damped);
  pue.dt = h[0] * fine;
  const History ref_ue = history(pue, st, T, samples);
  std::cerr << "accuracy: references done (BE " << ref_be.wall << " s, UE " << ref_ue.wall << " s)\n";
  out << "method,ratio,bricks,step_s,step_over_critical,sim_time_s,wall_s,err_own_ref,err_bolted_ref,final_strain,stable,"
         "newton_residual,alpha_d,beta_d\n";
  for (int k = 0; k < 4; ++k)
    for (int l = 0; l <= levels; ++l) {
      auto p = variant_params(k, ratio, damped);
      p.dt = 0.95 * h[k] * std::pow(0.5, l);
      const History a = history(p, st, T, samples);
      const History& own = k == 0 ? ref_ue : ref_be;
      out << kVariantName[k] << "," << ratio << "," << st.s.size() << "," << a.dt << "," << a.dt / h[k] << "," << T << ","
          << a.wall << "," << history_error(a, own) << "," << history_error(a, ref_be) << ","
          << (a.strain.empty() ? 0.0 : a.strain.back()) << "," << a.ok << "," << a.newton << "," << p.alpha_d << ","
          << p.beta_d << "\n";
      out.flush();
      std::cerr << "accuracy " << kVariantName[k] << " h/hcrit " << p.dt / h[k] << ": err " << history_error(a, own) << "\n";
    }
}

// ---------------------------------------------------------------- where BIE fails
void fail(long bricks, const std::string& ratios, long crit_steps, double T_in_bie_steps, std::ostream& out) {
  const auto st = specimen(bricks);
  out << "ratio,bricks,step_s,step_over_be_critical,step_over_bie_critical,stable,err_bolted_ref,newton_residual,wall_s,"
         "stable_reevaluated,err_reevaluated\n";
  for (double r : parse_list(ratios)) {
    const double hbe = crit(params(dyn::Method::be, r), st, crit_steps, 0.02);
    const double hbie = crit(params(dyn::Method::bie, r), st, crit_steps, 0.02);
    const double T = T_in_bie_steps * hbie;
    auto pref = params(dyn::Method::be, r);
    pref.dt = 0.25 * hbe;
    const History ref = history(pref, st, T, 16);
    for (double f = 1; f <= 1.5 * hbie / hbe + 1e-9 && f <= 128; f *= std::sqrt(2.0)) {
      auto p = params(dyn::Method::bie, r);
      p.dt = f * hbe;
      const History a = history(p, st, T, 16);
      p.bie_reuse_force = false;  // interface force re-evaluated at x_{n+1}: the Newton residual is measured
      const History x = history(p, st, T, 16);
      out << r << "," << st.s.size() << "," << a.dt << "," << a.dt / hbe << "," << a.dt / hbie << "," << a.ok << ","
          << history_error(a, ref) << "," << x.newton << "," << a.wall << "," << x.ok << "," << history_error(x, ref)
          << "\n";
      out.flush();
      std::cerr << "fail ratio " << r << " h/hBE " << f << ": ok " << a.ok << " err " << history_error(a, ref) << "\n";
    }
  }
}

// ---------------------------------------------------------------- memory per brick
void memory(const std::string& sizes, double ratio, std::ostream& out) {
  out << "method,shared,bricks,element_types,bytes,bytes_per_brick\n";
  for (double nbk : parse_list(sizes)) {
    const auto st = specimen(static_cast<long>(nbk));
    const double hbe = estimate(params(dyn::Method::be, ratio), st);
    for (auto m : {dyn::Method::ue, dyn::Method::be, dyn::Method::bie})
      for (bool share : {true, false}) {
        auto p = params(m, ratio);
        p.share_element_matrices = share;
        p.dt = 0.5 * hbe;
        dyn::Simulation sim(p, st.s, st.f, mortar());
        out << name(m) << "," << share << "," << st.s.size() << "," << sim.element_types() << "," << sim.bytes() << ","
            << static_cast<double>(sim.bytes()) / static_cast<double>(st.s.size()) << "\n";
        out.flush();
      }
  }
}

}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard guard(argc, argv);
  CLI::App app{"nacre BIE / dynamics experiments (issue 8)"};
  app.allow_extras();
  app.fallthrough();  // --out after the subcommand name
  std::string out_path = "-";
  app.add_option("--out", out_path, "CSV output (- for stdout)");
  long bricks = 400, steps = 1000, bie_steps = 100;
  double ratio = 500, rtol = 0.02, safety = 0.95, horizon = 40;
  int levels = 4;
  std::string ratios = "1,10,50,100,500", sizes = "1000,5000,10000,25000,50000";
  auto* c = app.add_subcommand("critical", "critical step vs stiffness ratio (UE, BE, BIE)");
  c->add_option("--bricks", bricks), c->add_option("--ratios", ratios), c->add_option("--steps", steps),
      c->add_option("--rtol", rtol);
  auto* t = app.add_subcommand("timing", "time per step vs bricks, every method and J^-1 variant");
  t->add_option("--sizes", sizes), t->add_option("--ratio", ratio), t->add_option("--steps", steps);
  auto* s = app.add_subcommand("speedup", "wall time to the same simulated time at each method's critical step");
  s->add_option("--bricks", bricks), s->add_option("--ratios", ratios), s->add_option("--bie-steps", bie_steps),
      s->add_option("--steps", steps), s->add_option("--safety", safety);
  bool damped_speedup = false;
  s->add_flag("--damped", damped_speedup, "Table 4.2's Rayleigh damping on every method; BIE's split step beside");
  auto* a = app.add_subcommand("accuracy", "strain-energy history error vs step and wall time");
  a->add_option("--bricks", bricks), a->add_option("--ratio", ratio), a->add_option("--steps", steps),
      a->add_option("--horizon", horizon, "simulated time in BIE critical steps"), a->add_option("--levels", levels);
  bool damped = false;
  a->add_flag("--damped", damped, "Table 4.2's Rayleigh damping on every method (and the references)");
  auto* f = app.add_subcommand("fail", "BIE error and stability as the step grows beyond BE's critical step");
  f->add_option("--bricks", bricks), f->add_option("--ratios", ratios), f->add_option("--steps", steps),
      f->add_option("--horizon", horizon, "simulated time in BIE critical steps");
  auto* m = app.add_subcommand("memory", "bytes per brick, shared vs per-element matrices");
  m->add_option("--sizes", sizes), m->add_option("--ratio", ratio);
  app.require_subcommand(1);
  CLI11_PARSE(app, argc, argv);
  std::ofstream file;
  if (out_path != "-") file.open(out_path);
  std::ostream& out = out_path == "-" ? std::cout : file;
  out.precision(10);
  if (*c) critical(bricks, ratios, steps, rtol, out);
  if (*t) timing(sizes, ratio, steps, out);
  if (*s) speedup(bricks, ratios, bie_steps, steps, safety, damped_speedup, out);
  if (*a) accuracy(bricks, ratio, steps, horizon, levels, damped, out);
  if (*f) fail(bricks, ratios, steps, horizon, out);
  if (*m) memory(sizes, ratio, out);
  return 0;
}
