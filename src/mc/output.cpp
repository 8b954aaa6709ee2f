// SPDX-License-Identifier: BSD-3-Clause
// The MC solver's outputs in io's solver-neutral terms: CSV rows, dump snapshot,
// summary, and the checkpoint as named arrays, range-checked on the way back.
#include <nacre/core/build_info.hpp>
#include <nacre/par/comm.hpp>
#include <nacre/kinematics/rigid.hpp>
#include <nacre/mc/output.hpp>
#include <nacre/core/format.hpp>

#include <Kokkos_Core.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>

namespace nacre::mc {

namespace {
std::string num(double v) { return format_real(v, 10); }
}  // namespace

std::string csv_header() {
  return "step,displacement,energy,reaction,cycles,acceptance,ruptured,converged,step_size,"
         "rot_step,increment,reverts,seconds,residual,polish_iterations,cg_iterations,method," +
         fracture::csv_header() + "\n";
}

std::string csv_row(const StepRecord& r, const fracture::CrackReading& crack) {
  return std::to_string(r.step) + "," + num(r.displacement) + "," + num(r.energy) + "," + num(r.reaction) + "," +
         std::to_string(r.cycles) + "," + num(r.acceptance) + "," + std::to_string(r.ruptured) + "," +
         (r.converged ? "1" : "0") + "," + num(r.step_size) + "," + num(r.rot_step) + "," + num(r.increment) + "," +
         std::to_string(r.reverts) + "," + num(r.seconds) + "," + num(r.residual) + "," +
         std::to_string(r.polish_iterations) + "," + std::to_string(r.inner_iterations) + "," + r.method + "," +
         fracture::csv_columns(crack, 10) + "\n";
}

io::Snapshot snapshot(Solver& solver, const geometry::Specimen& s, const geometry::Interfaces& f, int step) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::snapshot");
  OutputFields of = solver.output_fields();  // gathered to rank 0 when spread over ranks
  io::Snapshot snap;
  snap.step = step;
  if (of.x.size() != s.size()) return snap;  // another rank's: no fields (rank 0 writes)
  std::vector<double>&x = of.x, &y = of.y, &t = of.theta;
  const std::size_t n = s.size(), ni = f.size();
  std::vector<double> pts(2 * s.vx.size()), ipts(4 * ni);
  std::vector<kinematics::Frame> frame(n);  // each brick's rotation once, not once per point
  for (std::size_t b = 0; b < n; ++b) frame[b] = kinematics::make_frame(kinematics::Pose{x[b], y[b], t[b]});
  auto moved = [&](std::size_t b, double px, double py, double& ox, double& oy) {
    double dx, dy;
    kinematics::point_displacement(frame[b], px - s.cx[b], py - s.cy[b], dx, dy);
    ox = px + dx, oy = py + dy;
  };
  for (std::size_t b = 0; b < n; ++b)
    for (int v = s.poly_offset[b]; v < s.poly_offset[b + 1]; ++v) moved(b, s.vx[v], s.vy[v], pts[2 * v], pts[2 * v + 1]);
  for (std::size_t i = 0; i < ni; ++i) {  // interface drawn on brick a's face
    const std::size_t a = f.a[i];
    moved(a, s.cx[a] + f.ra0x[i], s.cy[a] + f.ra0y[i], ipts[4 * i], ipts[4 * i + 1]);
    moved(a, s.cx[a] + f.ra1x[i], s.cy[a] + f.ra1y[i], ipts[4 * i + 2], ipts[4 * i + 3]);
  }
  snap.time = solver.load();
  snap.reals["displacement"] = solver.load();
  snap.reals["energy"] = solver.tracked_energy();
  snap.integers["cycle"] = static_cast<std::int64_t>(solver.global_cycle());
  using io::Centre;
  snap.fields.push_back({Centre::vertex, "points", std::move(pts), 2});
  snap.fields.push_back({Centre::brick, "energy", std::move(of.brick_energy), 1});
  snap.fields.push_back({Centre::brick, "x", std::move(x), 1});
  snap.fields.push_back({Centre::brick, "y", std::move(y), 1});
  snap.fields.push_back({Centre::brick, "theta", std::move(t), 1});
  snap.fields.push_back({Centre::interface, "points", std::move(ipts), 2});
  snap.fields.push_back({Centre::interface, "state", std::move(of.interface_state), 1});
  snap.fields.push_back({Centre::interface, "energy", std::move(of.interface_energy), 1});
  return snap;
}

std::string summary_json(const Solver& solver, const deck::Deck& d, int steps, double seconds,
                         const fracture::CrackReading& crack, double notch_tip_x, double toughening_ratio) {
  const Sizes z = solver.sizes();  // the specimen's, not a rank's part
  const auto& pt = solver.times();
  nlohmann::ordered_json j;
  j["deck"] = d.path;
  j["solver"] = "mc";
  j["bricks"] = z.bricks;
  j["free_bricks"] = z.free_bricks;
  j["interfaces"] = z.interfaces;
  j["colouring"] = solver.colouring_name();
  j["colouring_rule"] = d.solver.colouring;
  j["colours"] = z.colours;
  j["rng"] = d.solver.rng;
  j["seed"] = d.seed;
  const Backend backend = solver.backend();
  j["ranks"] = z.ranks;
  if (z.ranks > 1) j["halo_messages"] = z.halo_messages;
  j["threads"] = backend.concurrency();  // per rank
  j["execution_space"] = backend.kokkos_name();
  j["backend"] = backend.name();
  j["steps"] = steps;
  j["cycles"] = solver.global_cycle();
  j["seconds"] = seconds;
  j["cpu_seconds"] = static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
  j["phase_seconds"] = {{"rng", pt.rng}, {"sweep", pt.sweep}, {"energy", pt.energy}, {"polish", pt.polish}};
  j["relaxation"] = d.solver.relaxation;
  j["convergence"] = d.solver.convergence;
  j["residual_tolerance"] = d.solver.residual_tolerance;
  j["polish"] = d.solver.polish;
  j["residual_scale"] = {{"force", solver.residual_scale().force}, {"moment", solver.residual_scale().moment}};
  j["max_step_residual"] = solver.max_step_residual();
  j["polish_iterations"] = solver.polish_iterations_total();
  j["cg_iterations"] = solver.run_state().cg_iterations;
  nlohmann::ordered_json presim = nlohmann::ordered_json::object();
  for (const auto& [name, sec] : solver.presim()) presim[name] = sec;
  j["presimulation_seconds_per_cycle"] = presim;
  if (!solver.presim().empty()) j["presimulation_pick"] = solver.colouring_name();
  // invalid UTF-8 (a deck path in another encoding) is replaced, never an invalid file
  fracture::put_json(j["crack"], crack, notch_tip_x);
  j["crack"]["thickness"] = 1.0;  // energies per unit depth: fracture_energy per unit crack length is G
  j["crack"]["bed_work_of_fracture"] = d.mortar.bed.k * d.mortar.bed.x1 * d.mortar.bed.x2;
  j["crack"]["toughening_ratio"] = std::isfinite(toughening_ratio) ? nlohmann::ordered_json(toughening_ratio) : nullptr;
  fracture::put_damage_json(j, d);
  put_build_json(j);
  par::put_placement_json(j, backend.concurrency());
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

io::Checkpoint to_named(const Checkpoint& c, const std::string& fingerprint, const std::string& deck_text,
                        double final_displacement, int legs) {
  io::Checkpoint n;
  n.fingerprint = fingerprint;
  n.strings["solver"] = "mc";
  n.strings["colouring"] = c.colouring;
  n.strings["backend"] = c.backend;
  n.strings["deck"] = deck_text;
  n.integers["bricks"] = static_cast<std::int64_t>(c.pose.size() / 3);
  n.integers["step"] = c.run.step;
  n.integers["have_previous"] = c.run.have_previous ? 1 : 0;
  n.integers["global_cycle"] = static_cast<std::int64_t>(c.global_cycle);
  n.integers["accepted_total"] = c.accepted_total;
  n.integers["trials_total"] = c.trials_total;
  n.integers["window_accepted"] = c.window_accepted;
  n.integers["window_trials"] = c.window_trials;
  n.reals["increment"] = c.run.increment;
  n.reals["previous_increment"] = c.run.previous_increment;
  n.reals["max_step_residual"] = c.run.max_residual;
  n.integers["polish_iterations"] = c.run.polish_iterations;
  n.integers["cg_iterations"] = c.run.cg_iterations;
  n.integers["leg"] = c.run.leg;
  n.integers["legs"] = legs;
  n.reals["displacement"] = c.displacement;
  n.reals["step_size"] = c.step_size;
  n.reals["rot_step"] = c.rot_step;
  n.reals["final_displacement"] = final_displacement;
  n.arrays["pose"] = c.pose;
  n.arrays["previous_pose"] = c.previous_pose;
  if (!c.brick_step.empty()) n.arrays["brick_step"] = c.brick_step;
  if (!c.history.empty()) n.arrays["history"] = c.history;
  return n;
}

Checkpoint from_named(const io::Checkpoint& n, std::size_t n_bricks, std::size_t n_free) {
  auto bad = [](const std::string& what) { throw io::CheckpointError(what); };
  if (n.string("solver") != "mc") bad("it was written by the '" + n.string("solver") + "' solver, not by Monte Carlo");
  Checkpoint c;
  c.colouring = n.string("colouring");
  if (n.strings.count("backend")) c.backend = n.string("backend");  // (older checkpoints: the default)
  const std::int64_t bricks = n.integer("bricks");
  if (bricks != static_cast<std::int64_t>(n_bricks))
    bad("it holds " + std::to_string(bricks) + " bricks, the deck's specimen has " + std::to_string(n_bricks));
  auto count = [&](const char* name, std::int64_t hi) {
    const std::int64_t v = n.integer(name);
    if (v < 0 || v > hi) bad(std::string(name) + " = " + std::to_string(v) + " is out of range [0, " + std::to_string(hi) + "]");
    return v;
  };
  constexpr std::int64_t big = std::int64_t(1) << 62;
  c.run.step = static_cast<int>(count("step", 1000000000));
  const std::int64_t have_prev = count("have_previous", 1);
  c.run.have_previous = have_prev != 0;
  const std::int64_t cycles = count("global_cycle", big);
  c.global_cycle = static_cast<std::uint64_t>(cycles);
  c.trials_total = count("trials_total", big);
  c.accepted_total = count("accepted_total", c.trials_total);
  c.window_trials = count("window_trials", c.trials_total);
  c.window_accepted = count("window_accepted", c.window_trials);
  if (static_cast<double>(c.trials_total) != static_cast<double>(cycles) * static_cast<double>(n_free))
    bad("trials_total = " + std::to_string(c.trials_total) +
        " is not global_cycle x free bricks = " + std::to_string(cycles) + " x " + std::to_string(n_free));
  auto real = [&](const char* name, bool positive) {
    const double v = n.real(name);
    if (!std::isfinite(v) || v < 0 || (positive && v == 0))
      bad(std::string(name) + " = " + num(v) + " is not " + (positive ? "positive" : "non-negative") + " and finite");
    return v;
  };
  c.run.increment = real("increment", false);
  c.run.previous_increment = real("previous_increment", false);
  c.run.max_residual = real("max_step_residual", false);
  c.run.polish_iterations = count("polish_iterations", big);
  c.run.cg_iterations = n.integers.count("cg_iterations") ? count("cg_iterations", big) : 0;  // (older nacre: none)
  c.run.leg = n.integers.count("leg") ? static_cast<int>(count("leg", 1000)) : 0;  // older nacre: one leg
  // (a programme that turned has no previous increment to extrapolate: have_previous 0 after a turn)
  if (c.run.step > 0 && !c.run.have_previous && c.run.leg == 0)
    bad("have_previous = 0 after " + std::to_string(c.run.step) + " steps");
  auto finite = [&](const char* name) {  // a load programme may take D through 0 or below
    const double v = n.real(name);
    if (!std::isfinite(v)) bad(std::string(name) + " = " + num(v) + " is not finite");
    return v;
  };
  c.displacement = finite("displacement");
  c.step_size = real("step_size", true);
  c.rot_step = real("rot_step", true);
  (void)finite("final_displacement");
  auto poses = [&](const char* name) {
    const auto& v = n.array(name);
    if (v.size() != 3 * n_bricks)
      bad(std::string(name) + " holds " + std::to_string(v.size()) + " values, expected 3 x " + std::to_string(n_bricks));
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        bad(std::string(name) + " of brick " + std::to_string(i / 3) + " is " + num(v[i]) + "; expected a finite pose");
    return v;
  };
  c.pose = poses("pose");
  c.previous_pose = poses("previous_pose");
  if (auto it = n.arrays.find("brick_step"); it != n.arrays.end()) {
    c.brick_step = poses("brick_step");
    for (std::size_t i = 0; i < n_bricks; ++i) {
      const double st = c.brick_step[3 * i], rot = c.brick_step[3 * i + 1], acc = c.brick_step[3 * i + 2];
      if (st < 0 || rot < 0 || acc < 0 || acc != std::floor(acc) || acc > 2e9)
        bad("brick_step of brick " + std::to_string(i) + " is out of range");
    }
  }
  if (auto it = n.arrays.find("history"); it != n.arrays.end()) {
    for (std::size_t i = 0; i < it->second.size(); ++i)
      if (!std::isfinite(it->second[i]) || it->second[i] < 0)
        bad("history value " + std::to_string(i) + " is " + num(it->second[i]) + "; expected a finite separation >= 0");
    c.history = it->second;
  }
  for (const auto& [name, v] : n.arrays)
    if (name != "pose" && name != "previous_pose" && name != "brick_step" && name != "history")
      bad("unexpected array '" + name + "'");
  return c;
}

}  // namespace nacre::mc
