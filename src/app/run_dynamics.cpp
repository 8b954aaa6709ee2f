// SPDX-License-Identifier: BSD-3-Clause
// The dynamic-run driver: deck -> dyn::Params, specimen and interfaces, the dyn::Simulation
// advanced in chunks (one chunk per time-series row), progress with ETA, dumps + checkpoints,
// restart, and the stop on instability (exit 3, last good outputs kept, no NaN written).
#include <nacre/app/run_dynamics.hpp>

#include "driver.hpp"
#include "dyn_fields.hpp"
#include "progress.hpp"

#include <nacre/app/restart.hpp>
#include <nacre/app/signals.hpp>
#include <nacre/core/build_info.hpp>
#include <nacre/par/comm.hpp>
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
#include <optional>
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
  // docs/methods.md "The split step", perf/results/dyn_step_split_closed_form/ (and the run of cd4ac60)
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
dyn::StepReport estimated_step(const Backend& backend, const dyn::Params& p, const Setup& s, const deck::Deck& d) {
  Kokkos::Profiling::ScopedRegion region("nacre::app::estimated_step");
  dyn::Params q = p;
  if (!(q.dt > 0)) q.dt = 1e-9;  // any positive step: the bound does not depend on it
  dyn::Simulation sim(backend, q, s.specimen, s.interfaces, d.mortar);
  return sim.step_check();
}

int print_critical_step(const deck::Deck& d, bool quiet, const Backend& backend) {
  const Setup s = build(d);
  dyn::Params p = dynamics_params(d, s.specimen.size());
  p.dt = 0;
  // on the backend the run would take (its arithmetic: a device's bisection may end a bit
  // elsewhere than the host's)
  const dyn::StepReport est = estimated_step(backend, p, s, d);
  const double h =
      dyn::critical_step(backend, p, s.specimen, s.interfaces, d.mortar, critical_trial_steps, critical_rtol);
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
  std::printf(
      "nacre: %s: %zu bricks, method %s%s, E = %.6g N/mm^2 (ratio %.4g), alpha_d = %.6g 1/s, beta_d = %.6g s, on %s\n",
      d.path.c_str(), s.specimen.size(), method_name(p.method), scheme_label(p), p.youngs_modulus, d.dynamics.ratio(),
      p.alpha_d, p.beta_d, backend.name().c_str());
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

namespace {

/// One dynamic run, from the deck to the last row: the simulation set up on the run's
/// execution-space instance (its step from dt or dt_fraction, a restart's state), the writer,
/// the row / dump / checkpoint cycle, and the three ways a run ends (done, unstable, a signal).
/// Each phase is one member; run() strings them together.
class DynamicRun {
public:
  DynamicRun(const deck::Deck& d, const DynRunOptions& opt)
      : d_(d), D_(d.dynamics), opt_(opt), comm_(opt.comm), root_(opt.comm.rank() == 0),
        session_(d, opt.quiet, opt.tty, opt.backend), log_(session_.log()), setup_(build(d)),
        p_(dynamics_params(d, setup_.specimen.size())), crack_(setup_.specimen, setup_.interfaces, d.geometry),
        rayleigh_(fracture::rayleigh_speed_plane_stress(p_.youngs_modulus, p_.poisson, p_.density)) {}

  int run() {
    log_start();
    make_simulation();
    log_model();
    comm_.barrier();  // every rank has read the checkpoint (restart) before rank 0 sets up the directory
    open_writer();
    t_run_ = elapsed();
    step0_ = sim_->steps();
    if (opt_.restart.empty()) {
      prev_time_ = sim_->time();
      if (const int rc = write_start(); rc >= 0) return rc;
    } else {
      prev_time_ = sim_->time(), prev_extension_ = read_crack().extension, have_prev_ = true;
    }
    return loop();
  }

private:
  static constexpr int kContinue = -1;

  [[nodiscard]] double elapsed() const { return session_.elapsed(); }
  [[nodiscard]] bool adaptive() const { return p_.dt_mode == dyn::DtMode::adaptive; }
  // fixed dt: the step count is known; adaptive: the run ends at end_time (the count is an estimate)
  [[nodiscard]] bool finished() const {
    return adaptive() ? sim_->time() >= D_.end_time * (1 - 1e-12) : sim_->steps() >= fixed_total_;
  }
  [[nodiscard]] long total_now() const {
    if (!adaptive()) return fixed_total_;
    return sim_->steps() + std::max(0L, static_cast<long>(std::ceil((D_.end_time - sim_->time()) / sim_->dt() - 1e-9)));
  }

    void log_start() const {
    std::ostringstream o;
    o << setup_.specimen.size() << " bricks, " << setup_.interfaces.size() << " interfaces, dynamics "
      << method_name(p_.method) << scheme_label(p_) << " (E = " << p_.youngs_modulus << " N/mm^2, alpha_d = "
      << p_.alpha_d << " 1/s, beta_d = " << p_.beta_d << " s)";
    if (comm_.size() > 1) o << ", " << comm_.size() << " MPI ranks";
    session_.log_start(o.str());
  }

  /// The simulation at the step the run takes: a restart's, the deck's dt, or dt_fraction of the
  /// estimated (BIE iterated with stiffness damping: also bisected) critical step; a restart's state.
  void make_simulation() {
    const std::string& restart = opt_.restart;
    if (!restart.empty()) {
      cp_ = validated_dyn_checkpoint(d_, restart, opt_.extend);
      check_restart_backend(restart, cp_.backend, session_.backend().name());
      p_.dt = cp_.dt;  // the run continues with the step it started with
      h_crit_ = cp_.critical_step, worst_balance_ = cp_.worst_balance;  // (its summary: the whole run's)
    }
    const bool from_fraction = restart.empty() && D_.dt <= 0;
    if (from_fraction) p_.dt = 1e-9;  // replaced below, before the first step
    sim_.emplace(session_.backend(), p_, setup_.specimen, setup_.interfaces, d_.mortar, comm_);
    if (from_fraction) take_step_from_fraction();
    fixed_total_ = std::max(1L, static_cast<long>(std::ceil(D_.end_time / p_.dt - 1e-9)));
    if (restart.empty()) return;
    sim_->restore_state(cp_.state);
    if (sim_->steps() != cp_.step)
      throw std::runtime_error(restart + ": restored state is at step " + std::to_string(sim_->steps()) +
                               ", the checkpoint says " + std::to_string(cp_.step));
    if (log_)
      *log_ << "nacre: restarting from " << restart << " at step " << cp_.step << ", t = " << cp_.time << " s"
            << (!cp_.backend.empty() && cp_.backend != session_.backend().name()
                    ? " (written on " + cp_.backend + ", continued on " + session_.backend().name() + ": the same bits)"
                    : std::string())
            << "\n";
  }

  void take_step_from_fraction() {
    h_crit_ = take_initial_step(*sim_, p_, d_, session_.backend(), setup_.specimen, setup_.interfaces, log_);
    if (log_)
      *log_ << "nacre: estimated critical step " << h_crit_ << " s, dt = " << D_.dt_fraction << " x = " << p_.dt
            << " s (" << elapsed() << " s)\n";
  }

  void log_model() const {
    if (!log_) return;
    const auto& sim = *sim_;
    *log_ << "nacre: dt = " << p_.dt << " s, " << total_now() << " steps to t = " << D_.end_time << " s; "
          << sim.element_types() << " element types, " << sim.bytes() / 1048576.0 << " MiB on the device\n";
    if (sim.sliver_elements() > 0)
      *log_ << "nacre: " << sim.sliver_elements() << " sliver elements (step bound below " << p_.sliver_step_ratio
            << " of the median element's) mass-scaled: +" << 100 * sim.sliver_mass_added()
            << " % of the specimen's mass, the elements' step bound x" << sim.sliver_step_gain() << "\n";
    *log_ << "nacre: stability monitor: balance within " << D_.balance_tolerance << ", dt "
          << (adaptive() ? "adaptive" : "fixed") << ", estimated critical step " << sim.step_report().estimate
          << " s at the start\n";
  }

  /// Whether any rank says yes: the decisions every rank must take together (a finiteness check
  /// that only rank 0's gathered arrays can make).
  [[nodiscard]] bool any_rank(bool x) const { return comm_.size() > 1 ? comm_.max(x ? 1.0 : 0.0) > 0 : x; }
  /// The first SIGINT / SIGTERM any rank received (one process: its own).
  [[nodiscard]] int agreed_signal() const {
    return comm_.size() > 1 ? static_cast<int>(comm_.max(pending_signal())) : pending_signal();
  }

  void open_writer() {
    dyn::Snapshot first = sim_->snapshot();  // (a gather: every rank)
    if (!root_) return;                      // rank 0 writes
    fields_.emplace(setup_.specimen, setup_.interfaces, std::move(first));
    // series.csv and dumps named with 9 digits: names sort by step up to 1e9 steps (the limit)
    io::RunWriter::Options wo;
    wo.directory = d_.output.directory, wo.hdf5 = d_.output.hdf5, wo.csv_header = series_header();
    wo.csv_name = io::names::dyn_table, wo.dump_digits = 9, wo.elements = fields_->mesh();
    writer_.emplace(session_.open_writer(wo, setup_.specimen, setup_.interfaces, opt_.restart, cp_.step));
  }

  /// The crack now (fracture/crack.hpp).
  fracture::CrackReading read_crack() {
    sim_->interface_damage(iface_dmg_, iface_state_, &iface_energy_);  // (a gather: every rank)
    if (!root_) return {};
    return crack_.measure(iface_state_, iface_energy_);
  }
  /// A dump's fields plus the interface field "crack": the path from the notch (docs/fracture.md).
  io::Snapshot dump_fields(long step, const dyn::Snapshot& snap) const {
    io::Snapshot o = fields_->fields(step, snap);
    o.fields.push_back({io::Centre::interface, "crack", crack_.crack_mask(snap.iface_state), 1});
    return o;
  }

  SeriesRow make_row() {
    const auto& sim = *sim_;
    SeriesRow r;
    r.crack = read_crack();
    if (have_prev_ && sim.time() > prev_time_)
      r.crack_speed = (r.crack.extension - prev_extension_) / (sim.time() - prev_time_);
    r.crack_speed_rayleigh = r.crack_speed / rayleigh_;
    prev_time_ = sim.time(), prev_extension_ = r.crack.extension, have_prev_ = true;
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
  }

  DynCheckpoint checkpoint() const {
    DynCheckpoint c;
    c.step = sim_->steps();
    c.time = sim_->time();
    c.dt = p_.dt;
    c.end_time = D_.end_time;
    c.method = method_name(p_.method);
    c.backend = session_.backend().name();
    c.state = sim_->save_state();
    c.critical_step = h_crit_;
    c.worst_balance = worst_balance_;
    return c;
  }

  void summary() {
    const auto& sim = *sim_;
    nlohmann::ordered_json j;
    const auto& sr = sim.step_report();
    const auto null = nlohmann::ordered_json(nullptr);
    j["deck"] = d_.path;
    j["solver"] = "dynamics";
    j["method"] = method_name(p_.method);
    j["bie_scheme"] = p_.method == dyn::Method::bie
                          ? nlohmann::ordered_json(p_.bie_scheme == dyn::BieScheme::split ? "split" : "iterate")
                          : null;
    j["status"] = status_;
    j["bricks"] = setup_.specimen.size();
    j["interfaces"] = setup_.interfaces.size();
    j["element_types"] = sim.element_types();
    j["device_bytes"] = sim.bytes();
    j["youngs_modulus"] = p_.youngs_modulus;
    j["stiffness_ratio"] = D_.ratio();
    j["alpha_d"] = p_.alpha_d;
    j["beta_d"] = p_.beta_d;
    j["dt"] = p_.dt;
    j["dt_mode"] = adaptive() ? "adaptive" : "fixed";
    j["dt_final"] = sim.dt();
    j["dt_changes"] = sr.dt_changes;
    j["critical_estimate"] = sr.estimate;
    j["step_bound_start"] = sr.bound_start;
    j["controlling_brick"] = sr.brick;
    j["growth_longest_run"] = sr.growth_longest;
    j["balance_tolerance"] = D_.balance_tolerance;
    j["worst_balance_residual"] = worst_balance_;
    j["sliver_step_ratio"] = p_.sliver_step_ratio;
    j["sliver_elements"] = sim.sliver_elements();
    j["sliver_mass_added"] = sim.sliver_mass_added();
    j["sliver_step_gain"] = sim.sliver_step_gain();
    j["why"] = why_.empty() ? null : nlohmann::ordered_json(why_);
    j["critical_step"] = h_crit_ > 0 ? nlohmann::ordered_json(h_crit_) : null;
    j["steps"] = sim.steps();
    j["time"] = sim.time();
    j["end_time"] = D_.end_time;
    j["ruptured"] = sim.ruptured();
    {
      auto& c = j["crack"];
      fracture::put_json(c, read_crack(), crack_.notch_tip_x());
      c["rayleigh_speed"] = rayleigh_;
      c["thickness"] = p_.thickness;  // fracture_energy / thickness per unit crack length: G (N/mm)
      c["bed_work_of_fracture"] = d_.mortar.bed.k * d_.mortar.bed.x1 * d_.mortar.bed.x2;
      // the R-curve of the rows so far (rank 0 writes), before the summary that quotes its ratio
      const double ratio =
          writer_ ? write_r_curve(*writer_, p_.thickness, c["bed_work_of_fracture"].get<double>(), nullptr) : NAN;
      c["toughening_ratio"] = std::isfinite(ratio) ? nlohmann::ordered_json(ratio) : null;
      ratio_ = ratio;
    }
    j["threads"] = session_.backend().concurrency();
    j["execution_space"] = session_.backend().kokkos_name();
    j["backend"] = session_.backend().name();
    j["seconds"] = elapsed();
    j["seconds_per_step"] = seconds_per_step();
    fracture::put_damage_json(j, d_);
    put_build_json(j);
    par::put_placement_json(j, session_.backend().concurrency());
    j["ranks"] = comm_.size();
    const long long halo = sim.halo_bytes();  // (every rank)
    const long n = sim.steps() - step0_;
    j["halo_bytes_per_exchange"] = halo;
    j["halo_exchanges_per_step"] = n > 0 ? static_cast<double>(sim.halo_exchanges()) / static_cast<double>(n) : 0.0;
    if (!writer_) return;  // (ruptured, read_crack, halo_bytes: every rank)
    // invalid UTF-8 (a deck path in another encoding) is replaced, never an invalid file
    writer_->summary(j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
  }
  [[nodiscard]] double seconds_per_step() const {
    const long n = sim_->steps() - step0_;
    return n > 0 ? (elapsed() - t_run_) / static_cast<double>(n) : 0.0;
  }

  /// Stop on instability: the rows, dump and checkpoint written so far are all finite and stay.
  int unstable(const std::string& message) {
    if (session_.progress()) std::fprintf(stderr, "\n");
    status_ = "unstable";
    why_ = message;
    if (writer_) writer_->flush_rows();
    summary();
    if (!writer_) return exit_unstable;
    std::cerr << "nacre: error: unstable: " << message << "\n"
              << "nacre: kept " << writer_->rows() << " rows of series.csv; last dump and checkpoint at step "
              << writer_->last_dump_step() << "; try a smaller dt (nacre " << d_.path << " --critical-step)\n";
    return exit_unstable;
  }
  static std::string at(long step, double t) { return " at step " + std::to_string(step) + ", t = " + num(t) + " s"; }

  /// Row, dump and checkpoint of step 0 (a new run); kContinue or the exit code.
  int write_start() {
    const SeriesRow r = make_row();
    if (auto q = non_finite(r); any_rank(!q.empty())) return unstable("non-finite " + q + " at step 0");
    if (writer_) writer_->row(r.step, series_line(r), false);
    const dyn::Snapshot snap = sim_->snapshot();
    if (auto q = first_non_finite(snap); any_rank(!q.empty())) return unstable("non-finite " + q + " at step 0");
    const DynCheckpoint c = checkpoint();
    if (!writer_) return kContinue;
    writer_->dump(dump_fields(0, snap));
    writer_->checkpoint(to_named(c, d_));
    return kContinue;
  }

  /// Time spent since the run (re)started and the estimate of what is left, from the steps done.
  [[nodiscard]] std::pair<double, double> spent_left(long step) const {
    const double frac = static_cast<double>(step - step0_) / static_cast<double>(std::max(1L, total_now() - step0_));
    const double spent = elapsed() - t_run_;
    return {spent, frac > 0 ? spent / frac - spent : -1.0};
  }

  /// Advance to the next row (the next csv_interval or dump_interval step) and write it; the
  /// dump and checkpoint where due. kContinue or the exit code.
  int advance_one_row(bool& dumped) {
    long step = sim_->steps();
    long next = std::min(total_now(), (step / D_.csv_interval + 1) * D_.csv_interval);
    if (D_.dump_interval > 0) next = std::min(next, (step / D_.dump_interval + 1) * D_.dump_interval);
    bool ok;
    {
      Kokkos::Profiling::ScopedRegion region("nacre::app::advance");
      ok = sim_->advance(next - step);
    }
    if (!ok) return unstable(sim_->why());
    step = sim_->steps();
    const SeriesRow r = make_row();
    if (auto q = non_finite(r); any_rank(!q.empty())) return unstable("non-finite " + q + at(step, r.time));
    // advance() checked this state (its last chunk ends here), balance included: the row's books close
    if (writer_) writer_->row(step, series_line(r), false);
    if (dyn::balance_checked(step)) worst_balance_ = std::max(worst_balance_, std::abs(r.e.balance_residual));
    dumped = finished() || (D_.dump_interval > 0 && step % D_.dump_interval == 0);
    if (dumped) {
      const dyn::Snapshot snap = sim_->snapshot();
      if (auto q = first_non_finite(snap); any_rank(!q.empty())) return unstable("non-finite " + q + at(step, r.time));
      DynCheckpoint c = checkpoint();
      if (auto q = non_finite(c.state); any_rank(!q.empty())) return unstable("non-finite " + q + at(step, r.time));
      if (writer_) {
        writer_->dump(dump_fields(step, snap));  // the rows first, then the dump, then the checkpoint
        writer_->checkpoint(to_named(c, d_));
      }
      last_flush_ = elapsed();
    } else if (writer_ && elapsed() - last_flush_ > 2.0) {
      writer_->flush_rows();
      last_flush_ = elapsed();
    }
    report(r, dumped);
    return kContinue;
  }

  /// The log line of a dump, the heartbeat off a terminal, the progress line on one.
  void report(const SeriesRow& r, bool dumped) {
    const long step = r.step;
    if (log_ && !session_.progress() && (dumped || session_.heartbeat_due())) {
      session_.line_written();
      if (dumped) {
        *log_ << "  step " << step << "/" << total_now() << ": t = " << r.time << " s, D = " << r.displacement
              << ", F = " << r.reaction << ", kinetic " << r.e.kinetic << ", balance " << r.e.balance_residual
              << ", ruptured " << r.ruptured << "\n";
      } else {
        const auto [spent, left] = spent_left(step);
        *log_ << "  step " << step << "/" << total_now() << " in progress: t = " << r.time
              << " s, D = " << r.displacement << ", F = " << r.reaction << ", ruptured " << r.ruptured << ", elapsed "
              << hms(spent) << ", left ~" << hms(left) << "\n";
      }
    }
    if (session_.progress_due(finished())) {
      session_.line_written();
      const auto [spent, left] = spent_left(step);
      std::fprintf(stderr, "\r  step %ld/%ld  t %.4g/%.4g s  D %.4g  F %.4g  ruptured %d  elapsed %s  left ~%s   ",
                   step, total_now(), r.time, D_.end_time, r.displacement, r.reaction, r.ruptured, hms(spent).c_str(),
                   hms(left).c_str());
      std::fflush(stderr);
    }
  }

  /// SIGINT/SIGTERM before the end: the checkpoint of this completed step (unless the row's
  /// dump wrote it), the summary, exit 128 + signal.
  int interrupted(int sig, bool dumped) {
    if (session_.progress()) std::fprintf(stderr, "\n");
    const long step = sim_->steps();
    if (!dumped) {  // the rows so far are written; the checkpoint holds this completed step
      DynCheckpoint c = checkpoint();
      if (auto q = non_finite(c.state); any_rank(!q.empty()))
        return unstable("non-finite " + q + at(step, sim_->time()));
      if (writer_) writer_->checkpoint(to_named(c, d_));  // after the rows it continues
    }
    if (writer_) writer_->flush_rows();
    status_ = "interrupted";
    summary();
    if (!writer_) return 128 + sig;
    return session_.stopped_by_signal(sig, "step " + std::to_string(step) + " (t = " + num(sim_->time()) + " s)",
                                      *writer_);
  }

  int loop() {
    SignalGuard signals;  // SIGINT/SIGTERM: stop after the chunk in progress with a checkpoint
        last_flush_ = elapsed();
    session_.line_written();
    while (!finished()) {
      bool dumped = false;
      if (const int rc = advance_one_row(dumped); rc != kContinue) return rc;
      if (const int sig = agreed_signal(); sig != 0 && !finished()) return interrupted(sig, dumped);
    }
    return done();
  }

  int done() {
    if (session_.progress()) std::fprintf(stderr, "\n");
    if (writer_) writer_->flush_rows();
    summary();
    const int ruptured = sim_->ruptured();  // (every rank)
    if (!writer_) return 0;
    if (log_)
      *log_ << "nacre: done in " << elapsed() << " s; " << sim_->steps() << " steps (" << seconds_per_step() * 1e6
            << " us/step), t = " << sim_->time() << " s, " << ruptured << " interfaces ruptured\n"
            << "nacre: R-curve: toughening ratio "
            << (std::isfinite(ratio_) ? format_real(ratio_, 4) : std::string("n/a (the crack grew at fewer than 2 rows)"))
            << " (r_curve.csv)\n";
    return session_.complete(*writer_, "series.csv, nacre.xdmf, checkpoint.h5, summary.json", "dyn");
  }

  const deck::Deck& d_;
  const deck::Dynamics& D_;
  const DynRunOptions& opt_;
  double ratio_ = NAN;  ///< the R-curve's toughening ratio at the last summary
  const par::Comm comm_;
  const bool root_;  ///< rank 0: logs and writes
  RunSession session_;
  std::ostream* log_;

  const Setup setup_;
  dyn::Params p_;
  const fracture::CrackTracker crack_;
  const double rayleigh_;  ///< the bricks' Rayleigh speed: the crack-tip speed's scale

  DynCheckpoint cp_;
  double h_crit_ = 0;  ///< the estimated critical step a dt_fraction deck took its dt from
  long fixed_total_ = 1;
  std::optional<dyn::Simulation> sim_;
  std::optional<DynFields> fields_;
  std::optional<io::RunWriter> writer_;
  std::vector<double> iface_dmg_, iface_energy_;
  std::vector<int> iface_state_;
  double prev_time_ = 0, prev_extension_ = 0;  ///< the previous row's (a restart: the restored state's)
  bool have_prev_ = false;
  double t_run_ = 0;
  long step0_ = 0;
  std::string status_ = "done", why_;
  double worst_balance_ = 0;  ///< the largest |balance residual| of the rows the balance check covers
    double last_flush_ = 0;
};

}  // namespace

double take_initial_step(dyn::Simulation& sim, dyn::Params& p, const deck::Deck& d, const Backend& backend,
                         const geometry::Specimen& s, const geometry::Interfaces& f, std::ostream* log) {
  double h = sim.step_report().estimate;
  if (!std::isfinite(h) || h <= 0) throw std::runtime_error("critical step estimate failed (" + num(h) + ")");
  if (!estimate_bounds_step(p)) {  // the iterated BIE step with stiffness damping: bisect too
    Kokkos::Profiling::ScopedRegion region("nacre::app::critical_step");
    dyn::Params q = p;
    q.dt = 0;  // bracketed from the model's estimate, as --critical-step does
    const double hb = dyn::critical_step(backend, q, s, f, d.mortar, critical_trial_steps, critical_rtol);
    if (!std::isfinite(hb) || hb <= 0) throw std::runtime_error("critical step search failed (" + num(hb) + ")");
    if (log)
      *log << "nacre: the iterated BIE step with stiffness damping: bisected critical step " << hb
           << " s against the estimate " << h << " s; the smaller is used\n";
    h = std::min(h, hb);
  }
  p.dt = d.dynamics.dt_fraction * h;
  deck::check_time_steps(d, p.dt, "dynamics.dt_fraction");  // e.g. end_time = 1e20: refused, not overflowed
  sim.set_initial_dt(p.dt);
  return h;
}

int run_dynamics(const deck::Deck& d, const DynRunOptions& opt) { return DynamicRun(d, opt).run(); }

}  // namespace nacre::app
