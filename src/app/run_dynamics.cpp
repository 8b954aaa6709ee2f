// The dynamic-run driver: deck -> dyn::Params, specimen and interfaces, the dyn::Simulation
// advanced in chunks (one chunk per time-series row), progress with ETA, dumps + checkpoints,
// restart, and the stop on instability (exit 3, last good outputs kept, no NaN written).
#include <nacre/app/run_dynamics.hpp>

#include "driver.hpp"
#include "dyn_fields.hpp"
#include "progress.hpp"

#include <nacre/app/signals.hpp>
#include <nacre/core/format.hpp>
#include <nacre/deck/limits.hpp>
#include <nacre/dyn/bie.hpp>
#include <nacre/fracture/crack.hpp>
#include <nacre/io/results.hpp>
#include <nacre/geometry/specimen.hpp>

#include <Kokkos_Core.hpp>
#include <Kokkos_Profiling_ScopedRegion.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <utility>

namespace nacre::app {

namespace {

/// Bisection settings of the critical step (docs/dynamics.md states the criterion).
constexpr long critical_trial_steps = 2000;
constexpr double critical_rtol = 0.01;
/// Element growth check (docs/dynamics.md "Stability monitor"): stable runs measured (the README
/// decks, rotated walls, compression, a 50 m/s impact) show at most 5 checks in a row of a share
/// growing 1.5x, 3 of one growing 2x or 3x; a stop needs 6 in a row of 3x (729x in 192 steps).
constexpr double kGrowthFactor = 3.0;
constexpr int kGrowthChecks = 6;

const char* method_name(dyn::Method m) { return m == dyn::Method::ue ? "ue" : (m == dyn::Method::bie ? "bie" : "be"); }

std::string num(double v) { return format_real(v, 10); }

struct Setup {
  geometry::Specimen specimen;
  geometry::Interfaces interfaces;
};

Setup build(const deck::Deck& d) {
  Kokkos::Profiling::ScopedRegion region("nacre::geometry::build");
  Setup s;
  s.specimen = geometry::build_specimen(d.geometry);
  s.interfaces = geometry::find_interfaces(s.specimen, d.geometry);
  return s;
}

/// The first non-finite quantity of a row, or "".
std::string non_finite(const SeriesRow& r) {
  const std::pair<double, const char*> v[] = {{r.time, "time"},
                                              {r.displacement, "applied displacement"},
                                              {r.e.strain, "strain energy"},
                                              {r.e.kinetic, "kinetic energy"},
                                              {r.e.cohesive, "cohesive energy"},
                                              {r.e.damping_dissipated, "damping dissipation"},
                                              {r.e.external_work, "external work"},
                                              {r.e.balance_residual, "energy balance residual"},
                                              {r.reaction, "reaction force"}};
  for (auto [x, name] : v)
    if (!std::isfinite(x)) return name;
  return "";
}

/// The first non-finite state value ("state array v[12]"), or "".
std::string non_finite(const dyn::StateArrays& a) {
  for (const auto& [k, v] : a)
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i])) return "state array " + k + "[" + std::to_string(i) + "]";
  return "";
}

/// " (split step)" / " (iterated step)" after BIE's name in the log lines, nothing for UE and BE.
const char* scheme_label(const dyn::Params& p) {
  if (p.method != dyn::Method::bie) return "";
  return p.bie_scheme == dyn::BieScheme::split ? " (split step)" : " (iterated step)";
}

}  // namespace

dyn::Params dynamics_params(const deck::Deck& d, std::size_t bricks) {
  const auto& D = d.dynamics;
  dyn::Params p;
  p.method = D.method;  // one enum (dyn/params.hpp)
  dyn::parse_bie_solve(D.bie_solve, p.bie_solve);  // validated by the deck reader
  p.bie_block = D.bie_block;
  p.bie_iterations = D.bie_iterations;
  p.youngs_modulus = D.modulus();
  p.poisson = D.poisson;
  p.density = D.density;
  p.thickness = D.thickness;
  p.internal_stiffness_factor = D.internal_stiffness_factor;
  switch (D.damping) {
    case deck::Dynamics::Damping::table: dyn::table_4_2_damping(bricks, D.ratio(), p.alpha_d, p.beta_d); break;
    case deck::Dynamics::Damping::none: p.alpha_d = p.beta_d = 0; break;
    case deck::Dynamics::Damping::explicit_values: p.alpha_d = D.alpha_d, p.beta_d = D.beta_d; break;
  }
  // "auto": the split step where C != 0 (it keeps the undamped step at one J^-1 apply), eq. 4.6's
  // iterations where C = 0 (the same step to rounding at the same cost: the dissertation's step kept);
  // docs/methods.md "The split step", perf/results/dyn_step_split_phi
  const bool damped = p.alpha_d != 0.0 || p.beta_d != 0.0;
  p.bie_scheme = D.bie_scheme == "split" || (D.bie_scheme == "auto" && damped) ? dyn::BieScheme::split
                                                                               : dyn::BieScheme::iterate;
  p.dt = D.dt;
  p.rate = D.rate;
  p.ramp_time = D.ramp_time;
  p.ramp = D.ramp;
  p.final_displacement = d.load.final_displacement;
  p.programme = d.load.programme;
  p.tension = d.load.tension;
  p.bending = d.load.bending;
  p.thermal_strain = D.thermal_strain;
  p.force_top = D.force_top;
  p.share_element_matrices = D.share_element_matrices;
  // the stability monitor, all on (docs/dynamics.md "Stability monitor")
  p.balance_tolerance = D.balance_tolerance;
  p.growth_factor = kGrowthFactor, p.growth_checks = kGrowthChecks;
  p.step_check = true;
  p.dt_mode = D.dt_mode == "adaptive" ? dyn::DtMode::adaptive : dyn::DtMode::fixed;
  p.sliver_step_ratio = D.sliver_step_ratio;
  p.quadrature_points = D.quadrature_points;
  return p;
}

/// Whether the estimate (monitor.hpp StepBound) bounds the method's step: it treats BIE's bricks
/// as unconditionally stable, which eq. 4.6's iterated step with stiffness damping is not (its
/// limit falls to a fraction of the split step's, docs/methods.md "The split step"). There the
/// bisection is the reference and the run takes the smaller of the two.
bool estimate_bounds_step(const dyn::Params& p) {
  return !(p.method == dyn::Method::bie && p.bie_scheme == dyn::BieScheme::iterate && p.beta_d != 0.0);
}

/// The stability monitor's estimate of the critical step at the start (monitor.hpp StepBound),
/// and the elements it scaled: a Simulation built at the model's own start estimate.
dyn::StepReport estimated_step(const dyn::Params& p, const Setup& s, const deck::Deck& d) {
  Kokkos::Profiling::ScopedRegion region("nacre::app::estimated_step");
  dyn::Params q = p;
  if (!(q.dt > 0)) q.dt = 1e-9;  // any positive step: the bound does not depend on it
  dyn::Simulation sim(q, s.specimen, s.interfaces, d.mortar);
  return sim.step_check();
}

int print_critical_step(const deck::Deck& d, bool quiet) {
  const Setup s = build(d);
  dyn::Params p = dynamics_params(d, s.specimen.size());
  p.dt = 0;
  const dyn::StepReport est = estimated_step(p, s, d);
  const double h = dyn::critical_step(p, s.specimen, s.interfaces, d.mortar, critical_trial_steps, critical_rtol);
  if (!std::isfinite(h) || h <= 0 || !(est.estimate > 0)) {
    std::cerr << "nacre: error: critical step search failed (bisected " << h << ", estimated " << est.estimate << ")\n";
    return 1;
  }
  // the step the run's dt_fraction takes (run_dynamics: the same rule)
  const double critical = estimate_bounds_step(p) ? est.estimate : std::min(est.estimate, h);
  if (quiet) {
    std::printf("%.6g\n", critical);
    return 0;
  }
  std::printf("nacre: %s: %zu bricks, method %s%s, E = %.6g N/mm^2 (ratio %.4g), alpha_d = %.6g 1/s, beta_d = %.6g s\n",
              d.path.c_str(), s.specimen.size(), method_name(p.method), scheme_label(p), p.youngs_modulus,
              d.dynamics.ratio(), p.alpha_d, p.beta_d);
  if (estimate_bounds_step(p))
    std::printf("critical step: %.6g s (estimated: 2 / sqrt of the largest element eigenvalue of M^-1 K plus the "
                "interfaces' Gershgorin bound%s, at brick %d; what the run's dt_fraction and monitor use)\n",
                est.estimate, p.method == dyn::Method::bie ? " (BIE: interfaces only, the explicit part)" : "",
                est.brick);
  else
    std::printf("critical step: %.6g s (the smaller of the estimate %.6g s, which treats the bricks as implicit and "
                "unconditionally stable, and the bisection below: eq. 4.6's iterated step with stiffness damping is "
                "limited by the damping too; what the run's dt_fraction uses)\n",
                critical, est.estimate);
  std::printf("bisected step: %.6g s (relative tolerance %g: %ld-step trials from rest under the deck's load, "
              "finite with the balance within %g) = %.3f x the estimate%s\n",
              h, critical_rtol, critical_trial_steps, p.balance_tolerance, h / est.estimate,
              h < est.estimate ? "; BELOW the estimate: keep dt under the bisected step"
                               : (h > 1.05 * est.estimate ? "; above it: a trial from rest does not excite every "
                                                            "mode (a weakly unstable damped one grows too slowly "
                                                            "to be seen in it)"
                                                          : ""));
  if (d.dynamics.dt > 0)
    std::printf("deck dt = %.6g s = %.3f x critical%s\n", d.dynamics.dt, d.dynamics.dt / critical,
                d.dynamics.dt > critical ? " (ABOVE the critical step: the run stops at a check)" : "");
  else
    std::printf("deck dt_fraction = %g: dt = %.6g s\n", d.dynamics.dt_fraction, d.dynamics.dt_fraction * critical);
  return 0;
}

DynCheckpoint validated_dyn_checkpoint(const deck::Deck& d, const std::string& restart, bool extend) {
  DynCheckpoint cp = read_dyn_checkpoint(restart, d);
  const char* method = method_name(d.dynamics.method);
  if (cp.method != method)
    throw io::CheckpointError(restart + ": checkpoint of method " + cp.method + ", the deck says " + method + " (" +
                              d.where("dynamics.method") + ")");
  char b[256];
  const double end = d.dynamics.end_time;
  if (cp.end_time > 0 && cp.end_time != end && !extend) {
    std::snprintf(b, sizeof b, ": the checkpoint's run ends at end_time = %.9g s, this deck at %.9g s (", cp.end_time, end);
    throw io::CheckpointError(restart + b + d.where("dynamics.end_time") +
                              "); pass --extend to continue the run to the deck's end_time");
  }
  if (!(cp.time < end * (1 - 1e-12))) {
    std::snprintf(b, sizeof b, ": the checkpoint is at t = %.9g s, at or beyond this deck's end_time = %.9g s (", cp.time, end);
    throw io::CheckpointError(restart + b + d.where("dynamics.end_time") +
                              "): nothing to continue; raise end_time and pass --extend to run further");
  }
  return cp;
}

int run_dynamics(const deck::Deck& d, const DynRunOptions& opt) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(clock::now() - t0).count(); };
  const bool quiet = opt.quiet, tty = opt.tty;
  const std::string& restart = opt.restart;
  std::ostream* log = quiet ? nullptr : &std::cout;
  const auto& D = d.dynamics;

  const Setup setup = build(d);
  const auto& specimen = setup.specimen;
  const auto& interfaces = setup.interfaces;
  dyn::Params p = dynamics_params(d, specimen.size());
  if (log)
    *log << "nacre: " << d.path << ": " << specimen.size() << " bricks, " << interfaces.size()
         << " interfaces, dynamics " << method_name(p.method) << scheme_label(p) << " (E = " << p.youngs_modulus
         << " N/mm^2, alpha_d = " << p.alpha_d << " 1/s, beta_d = " << p.beta_d << " s), "
         << Kokkos::DefaultExecutionSpace::name() << " with " << Kokkos::DefaultExecutionSpace().concurrency()
         << " threads\n";

  DynCheckpoint cp;
  double h_crit = 0;  // the estimated critical step a dt_fraction deck took its dt from
  if (!restart.empty()) {
    cp = validated_dyn_checkpoint(d, restart, opt.extend);
    p.dt = cp.dt;  // the run continues with the step it started with
  }
  const bool from_fraction = restart.empty() && D.dt <= 0;
  if (from_fraction) p.dt = 1e-9;  // replaced below, before the first step
  dyn::Simulation sim(p, specimen, interfaces, d.mortar);
  if (from_fraction) {
    h_crit = sim.step_report().estimate;
    if (!std::isfinite(h_crit) || h_crit <= 0)
      throw std::runtime_error("critical step estimate failed (" + num(h_crit) + ")");
    if (!estimate_bounds_step(p)) {  // the iterated BIE step with stiffness damping: bisect too
      Kokkos::Profiling::ScopedRegion region("nacre::app::critical_step");
      dyn::Params q = p;
      q.dt = 0;  // bracketed from the model's estimate, as --critical-step does
      const double hb = dyn::critical_step(q, specimen, interfaces, d.mortar, critical_trial_steps, critical_rtol);
      if (!std::isfinite(hb) || hb <= 0) throw std::runtime_error("critical step search failed (" + num(hb) + ")");
      if (log)
        *log << "nacre: the iterated BIE step with stiffness damping: bisected critical step " << hb
             << " s against the estimate " << h_crit << " s; the smaller is used\n";
      h_crit = std::min(h_crit, hb);
    }
    p.dt = D.dt_fraction * h_crit;
    deck::check_time_steps(d, p.dt, "dynamics.dt_fraction");  // e.g. end_time = 1e20: refused, not overflowed
    sim.set_initial_dt(p.dt);
    if (log)
      *log << "nacre: estimated critical step " << h_crit << " s, dt = " << D.dt_fraction << " x = " << p.dt << " s ("
           << elapsed() << " s)\n";
  }
  // fixed dt: the step count is known; adaptive: the run ends at end_time (the count is an estimate)
  const bool adaptive = p.dt_mode == dyn::DtMode::adaptive;
  const long fixed_total = std::max(1L, static_cast<long>(std::ceil(D.end_time / p.dt - 1e-9)));
  auto finished = [&] { return adaptive ? sim.time() >= D.end_time * (1 - 1e-12) : sim.steps() >= fixed_total; };
  auto total_now = [&] {
    if (!adaptive) return fixed_total;
    return sim.steps() + std::max(0L, static_cast<long>(std::ceil((D.end_time - sim.time()) / sim.dt() - 1e-9)));
  };
  const long total = total_now();
  if (!restart.empty()) {
    sim.restore_state(cp.state);
    if (sim.steps() != cp.step)
      throw std::runtime_error(restart + ": restored state is at step " + std::to_string(sim.steps()) +
                               ", the checkpoint says " + std::to_string(cp.step));
    if (log) *log << "nacre: restarting from " << restart << " at step " << cp.step << ", t = " << cp.time << " s\n";
  }
  if (log)
    *log << "nacre: dt = " << p.dt << " s, " << total << " steps to t = " << D.end_time << " s; "
         << sim.element_types() << " element types, " << sim.bytes() / 1048576.0 << " MiB on the device\n";
  if (log && sim.sliver_elements() > 0)
    *log << "nacre: " << sim.sliver_elements() << " sliver elements (step bound below " << p.sliver_step_ratio
         << " of the median element's) mass-scaled: +" << 100 * sim.sliver_mass_added()
         << " % of the specimen's mass, the elements' step bound x" << sim.sliver_step_gain() << "\n";
  if (log)
    *log << "nacre: stability monitor: balance within " << D.balance_tolerance << ", dt " << (adaptive ? "adaptive" : "fixed")
         << ", estimated critical step " << sim.step_report().estimate << " s at the start\n";

  const DynFields fields(specimen, interfaces, sim.snapshot());
  std::optional<io::RunWriter::Resume> resume;
  if (!restart.empty()) {
    resume = io::RunWriter::Resume{cp.step, std::filesystem::path(restart).parent_path()};
    if (resume->source_directory.empty()) resume->source_directory = ".";
  }
  // series.csv and dumps named with 9 digits: names sort by step up to 1e9 steps (the limit)
  io::RunWriter::Options wo;
  wo.directory = d.output.directory, wo.hdf5 = d.output.hdf5, wo.csv_header = series_header();
  wo.csv_name = io::names::dyn_table, wo.dump_digits = 9, wo.elements = fields.mesh();
  io::RunWriter writer(wo, specimen, interfaces, resume);
  if (log && writer.stale_temporaries_removed() > 0)
    *log << "nacre: removed " << writer.stale_temporaries_removed() << " stale temporary file(s) of a killed run in "
         << writer.directory().string() << "/\n";
  // the crack of every row (fracture/crack.hpp) and its tip speed against the bricks' Rayleigh speed
  const fracture::CrackTracker crack(specimen, interfaces, d.geometry);
  const double rayleigh = fracture::rayleigh_speed_plane_stress(p.youngs_modulus, p.poisson, p.density);
  std::vector<double> iface_dmg, iface_energy;
  std::vector<int> iface_state;
  auto read_crack = [&] {
    sim.interface_damage(iface_dmg, iface_state, &iface_energy);
    return crack.measure(iface_state, iface_energy);
  };
  // the dumps' interface field "crack": the path from the notch (docs/fracture.md)
  auto with_crack = [&](io::Snapshot o, const dyn::Snapshot& snap) {
    o.fields.push_back({io::Centre::interface, "crack", crack.crack_mask(snap.iface_state), 1});
    return o;
  };
  // the previous row's time and extension (a restart reads them from the restored state: its row)
  double prev_time = sim.time(), prev_extension = restart.empty() ? 0.0 : read_crack().extension;
  bool have_prev = !restart.empty();
  auto make_row = [&] {
    SeriesRow r;
    r.crack = read_crack();
    if (have_prev && sim.time() > prev_time)
      r.crack_speed = (r.crack.extension - prev_extension) / (sim.time() - prev_time);
    r.crack_speed_rayleigh = r.crack_speed / rayleigh;
    prev_time = sim.time(), prev_extension = r.crack.extension, have_prev = true;
    r.step = sim.steps();
    r.time = sim.time();
    r.displacement = sim.displacement();
    r.e = sim.energies();
    r.reaction = sim.reaction();
    r.ruptured = sim.ruptured();
    r.dt = sim.dt();
    r.critical_estimate = sim.step_report().estimate;
    r.seconds = elapsed();
    return r;
  };
  auto checkpoint = [&] {
    DynCheckpoint c;
    c.step = sim.steps();
    c.time = sim.time();
    c.dt = p.dt;
    c.end_time = D.end_time;
    c.method = method_name(p.method);
    c.state = sim.save_state();
    return c;
  };
  const double t_run = elapsed();
  const long step0 = sim.steps();
  std::string status = "done", why;
  double worst_balance = 0;  // the largest |balance residual| of the rows the balance check covers
  const bool progress = tty && d.output.progress && !quiet;

  auto summary = [&] {
    nlohmann::ordered_json j;
    const auto& sr = sim.step_report();
    j["deck"] = d.path;
    j["solver"] = "dynamics";
    j["method"] = method_name(p.method);
    j["bie_scheme"] = p.method == dyn::Method::bie ? nlohmann::ordered_json(p.bie_scheme == dyn::BieScheme::split ? "split" : "iterate")
                                                   : nlohmann::ordered_json(nullptr);
    j["status"] = status;
    j["bricks"] = specimen.size();
    j["interfaces"] = interfaces.size();
    j["element_types"] = sim.element_types();
    j["device_bytes"] = sim.bytes();
    j["youngs_modulus"] = p.youngs_modulus;
    j["stiffness_ratio"] = D.ratio();
    j["alpha_d"] = p.alpha_d;
    j["beta_d"] = p.beta_d;
    j["dt"] = p.dt;
    j["dt_mode"] = adaptive ? "adaptive" : "fixed";
    j["dt_final"] = sim.dt();
    j["dt_changes"] = sr.dt_changes;
    j["critical_estimate"] = sr.estimate;
    j["step_bound_start"] = sr.bound_start;
    j["controlling_brick"] = sr.brick;
    j["growth_longest_run"] = sr.growth_longest;
    j["balance_tolerance"] = D.balance_tolerance;
    j["worst_balance_residual"] = worst_balance;
    j["sliver_step_ratio"] = p.sliver_step_ratio;
    j["sliver_elements"] = sim.sliver_elements();
    j["sliver_mass_added"] = sim.sliver_mass_added();
    j["sliver_step_gain"] = sim.sliver_step_gain();
    j["why"] = why.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(why);
    j["critical_step"] = h_crit > 0 ? nlohmann::ordered_json(h_crit) : nlohmann::ordered_json(nullptr);
    j["steps"] = sim.steps();
    j["time"] = sim.time();
    j["end_time"] = D.end_time;
    j["ruptured"] = sim.ruptured();
    {
      auto& c = j["crack"];
      fracture::put_json(c, read_crack(), crack.notch_tip_x());
      c["rayleigh_speed"] = rayleigh;
      c["thickness"] = p.thickness;  // fracture_energy / thickness per unit crack length: G (N/mm)
      c["bed_work_of_fracture"] = d.mortar.bed.k * d.mortar.bed.x1 * d.mortar.bed.x2;
    }
    j["threads"] = Kokkos::DefaultExecutionSpace().concurrency();
    j["execution_space"] = Kokkos::DefaultExecutionSpace::name();
    j["seconds"] = elapsed();
    j["seconds_per_step"] = sim.steps() > step0 ? (elapsed() - t_run) / static_cast<double>(sim.steps() - step0) : 0.0;
    // invalid UTF-8 (a deck path in another encoding) is replaced, never an invalid file
    fracture::put_damage_json(j, d);
    writer.summary(j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
  };
  // Stop on instability: the rows, dump and checkpoint written so far are all finite and stay.
  auto unstable = [&](const std::string& message) {
    if (progress) std::fprintf(stderr, "\n");
    status = "unstable";
    why = message;
    writer.flush_rows();
    summary();
    std::cerr << "nacre: error: unstable: " << message << "\n"
              << "nacre: kept " << writer.rows() << " rows of series.csv; last dump and checkpoint at step "
              << writer.last_dump_step() << "; try a smaller dt (nacre " << d.path << " --critical-step)\n";
    return exit_unstable;
  };

  if (restart.empty()) {
    const SeriesRow r = make_row();
    if (auto q = non_finite(r); !q.empty()) return unstable("non-finite " + q + " at step 0");
    writer.row(r.step, series_line(r), false);
    const dyn::Snapshot snap = sim.snapshot();
    if (auto q = first_non_finite(snap); !q.empty()) return unstable("non-finite " + q + " at step 0");
    writer.dump(with_crack(fields.fields(0, snap), snap));
    writer.checkpoint(to_named(checkpoint(), d));
  }

  SignalGuard signals;  // SIGINT/SIGTERM: stop after the chunk in progress with a checkpoint
  double last_flush = elapsed(), last_progress = -1;
  // off a terminal: a plain log line at most every [output] heartbeat seconds between dumps
  const bool heartbeat = !tty && log && d.output.heartbeat > 0;
  double last_line = elapsed();
  // time spent since the run (re)started and the estimate of what is left, from the steps done
  auto spent_left = [&](long step) {
    const double frac = static_cast<double>(step - step0) / static_cast<double>(std::max(1L, total_now() - step0));
    const double spent = elapsed() - t_run;
    return std::pair{spent, frac > 0 ? spent / frac - spent : -1.0};
  };
  const Kokkos::DefaultExecutionSpace space;
  long step = sim.steps();
  while (!finished()) {
    const long total_est = total_now();
    long next = std::min(total_est, (step / D.csv_interval + 1) * D.csv_interval);
    if (D.dump_interval > 0) next = std::min(next, (step / D.dump_interval + 1) * D.dump_interval);
    bool ok;
    {
      Kokkos::Profiling::ScopedRegion region("nacre::app::advance");
      ok = sim.advance(space, next - step);
    }
    if (!ok) return unstable(sim.why());
    step = sim.steps();
    const SeriesRow r = make_row();
    if (auto q = non_finite(r); !q.empty())
      return unstable("non-finite " + q + " at step " + std::to_string(step) + ", t = " + num(r.time) + " s");
    // advance() checked this state (its last chunk ends here), balance included: the row's books close
    writer.row(step, series_line(r), false);
    if (dyn::balance_checked(step)) worst_balance = std::max(worst_balance, std::abs(r.e.balance_residual));
    const bool dump = finished() || (D.dump_interval > 0 && step % D.dump_interval == 0);
    if (dump) {
      const dyn::Snapshot snap = sim.snapshot();
      if (auto q = first_non_finite(snap); !q.empty())
        return unstable("non-finite " + q + " at step " + std::to_string(step) + ", t = " + num(r.time) + " s");
      DynCheckpoint c = checkpoint();
      if (auto q = non_finite(c.state); !q.empty())
        return unstable("non-finite " + q + " at step " + std::to_string(step) + ", t = " + num(r.time) + " s");
      writer.dump(with_crack(fields.fields(step, snap), snap));  // the rows first, then the dump, then the checkpoint
      writer.checkpoint(to_named(c, d));
      last_flush = elapsed();
      if (log && !progress) {
        last_line = elapsed();
        *log << "  step " << step << "/" << total_now() << ": t = " << r.time << " s, D = " << r.displacement
             << ", F = " << r.reaction << ", kinetic " << r.e.kinetic << ", balance " << r.e.balance_residual
             << ", ruptured " << r.ruptured << "\n";
      }
    } else {
      if (elapsed() - last_flush > 2.0) {
        writer.flush_rows();
        last_flush = elapsed();
      }
      if (heartbeat && elapsed() - last_line >= d.output.heartbeat) {
        last_line = elapsed();
        const auto [spent, left] = spent_left(step);
        *log << "  step " << step << "/" << total_now() << " in progress: t = " << r.time << " s, D = " << r.displacement
             << ", F = " << r.reaction << ", ruptured " << r.ruptured << ", elapsed " << hms(spent) << ", left ~"
             << hms(left) << "\n";
      }
    }
    if (const int sig = pending_signal(); sig != 0 && !finished()) {
      if (progress) std::fprintf(stderr, "\n");
      if (!dump) {  // the rows so far are written; the checkpoint holds this completed step
        DynCheckpoint c = checkpoint();
        if (auto q = non_finite(c.state); !q.empty())
          return unstable("non-finite " + q + " at step " + std::to_string(step) + ", t = " + num(r.time) + " s");
        writer.checkpoint(to_named(c, d));  // after the rows it continues
      }
      writer.flush_rows();
      status = "interrupted";
      summary();
      std::cerr << "nacre: " << signal_name(sig) << " received: stopped after step " << step << " (t = " << r.time
                << " s); checkpoint written to " << writer.checkpoint_path().string()
                << "\nnacre: continue with: nacre " << d.path << " -o " << writer.directory().string() << " --restart "
                << writer.checkpoint_path().string() << "\n";
      return 128 + sig;
    }
    if (progress && (elapsed() - last_progress > 0.25 || finished())) {
      last_progress = elapsed();
      const auto [spent, left] = spent_left(step);
      std::fprintf(stderr, "\r  step %ld/%ld  t %.4g/%.4g s  D %.4g  F %.4g  ruptured %d  elapsed %s  left ~%s   ",
                   step, total_now(), r.time, D.end_time, r.displacement, r.reaction, r.ruptured, hms(spent).c_str(),
                   hms(left).c_str());
      std::fflush(stderr);
    }
  }
  if (progress) std::fprintf(stderr, "\n");
  writer.flush_rows();
  summary();
  if (log) {
    const double per = sim.steps() > step0 ? (elapsed() - t_run) / static_cast<double>(sim.steps() - step0) : 0;
    *log << "nacre: done in " << elapsed() << " s; " << sim.steps() << " steps (" << per * 1e6 << " us/step), t = "
         << sim.time() << " s, " << sim.ruptured() << " interfaces ruptured\n";
    *log << "nacre: results in " << writer.directory().string()
         << "/ (series.csv, nacre.xdmf, checkpoint.h5, summary.json)\n";
  }
  if (const int sig = pending_signal()) {  // in the last chunk: the results are complete
    std::cerr << "nacre: " << signal_name(sig) << " received during the last chunk: results complete, charts skipped\n";
    return 128 + sig;
  }
  if (d.output.charts && !run_charts("nacre_dyn_plot.py", writer.directory(), log)) return 1;
  return 0;
}

}  // namespace nacre::app
