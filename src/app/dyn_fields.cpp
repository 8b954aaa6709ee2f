// SPDX-License-Identifier: BSD-3-Clause
// The dynamic run's share of the outputs (see dyn_fields.hpp): the triangle mesh, the fields of a
// dump, the series row and the checkpoint; io::RunWriter writes them.
#include "dyn_fields.hpp"

#include <nacre/app/restart.hpp>
#include <nacre/core/format.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <tuple>

namespace nacre::app {

namespace {

std::string num(double v) { return format_real(v, 17); }

}  // namespace

std::string first_non_finite(const dyn::Snapshot& s) {
  auto scan = [](const std::vector<double>& v, const char* name, const char* what) -> std::string {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i])) return std::string(name) + " of " + what + " " + std::to_string(i);
    return "";
  };
  for (auto [v, name, what] : {std::tuple{&s.ux, "ux", "node"}, {&s.uy, "uy", "node"}, {&s.vx, "vx", "node"},
                               {&s.vy, "vy", "node"}, {&s.tri_sxx, "sxx", "triangle"}, {&s.tri_syy, "syy", "triangle"},
                               {&s.tri_sxy, "sxy", "triangle"}, {&s.brick_syy, "vertical stress", "brick"},
                               {&s.iface_damage, "damage", "interface"}})
    if (auto m = scan(*v, name, what); !m.empty()) return m;
  if (!std::isfinite(s.time)) return "time";
  if (!std::isfinite(s.displacement)) return "applied displacement";
  return "";
}

std::string series_header() {
  return "step,time,displacement,strain_energy,kinetic_energy,cohesive_energy,damping_dissipated,external_work,"
         "balance_residual,reaction,ruptured," +
         fracture::csv_header() + ",crack_speed,crack_speed_rayleigh,dt,critical_estimate,seconds\n";
}

std::string series_line(const SeriesRow& r) {
  const auto& e = r.e;
  return std::to_string(r.step) + "," + num(r.time) + "," + num(r.displacement) + "," + num(e.strain) + "," +
         num(e.kinetic) + "," + num(e.cohesive) + "," + num(e.damping_dissipated) + "," + num(e.external_work) + "," +
         num(e.balance_residual) + "," + num(r.reaction) + "," + std::to_string(r.ruptured) + "," +
         fracture::csv_columns(r.crack, 17) + "," + num(r.crack_speed) + "," + num(r.crack_speed_rayleigh) + "," +
         num(r.dt) + "," + num(r.critical_estimate) + "," + num(r.seconds) + "\n";
}

DynFields::DynFields(const geometry::Specimen& s, const geometry::Interfaces& f, const dyn::Snapshot& first)
    : n_interfaces_(f.size()) {
  const std::size_t nn = first.node_x.size(), nt = first.tri.size() / 3;
  if (first.iface_damage.size() != f.size() || first.tri_brick.size() != nt || first.brick_syy.size() != s.size())
    throw std::runtime_error("dynamics snapshot sizes do not match the specimen (" +
                             std::to_string(first.iface_damage.size()) + " interface values for " +
                             std::to_string(f.size()) + " interfaces, " + std::to_string(first.brick_syy.size()) +
                             " brick values for " + std::to_string(s.size()) + " bricks)");
  mesh_.reference.resize(2 * nn);
  for (std::size_t v = 0; v < nn; ++v) mesh_.reference[2 * v] = first.node_x[v], mesh_.reference[2 * v + 1] = first.node_y[v];
  mesh_.connectivity.assign(first.tri.begin(), first.tri.end());
  mesh_.brick.assign(first.tri_brick.begin(), first.tri_brick.end());

  // Interface ends onto triangle edges of brick a (static; used to draw the deformed interfaces).
  std::vector<std::vector<int>> tris_of(s.size());
  for (std::size_t t = 0; t < nt; ++t) tris_of[static_cast<std::size_t>(first.tri_brick[t])].push_back(static_cast<int>(t));
  end_n0_.resize(2 * f.size()), end_n1_.resize(2 * f.size()), end_w_.resize(2 * f.size()), end_ref_.resize(4 * f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const std::size_t a = static_cast<std::size_t>(f.a[i]);
    const double ends[2][2] = {{s.cx[a] + f.ra0x[i], s.cy[a] + f.ra0y[i]}, {s.cx[a] + f.ra1x[i], s.cy[a] + f.ra1y[i]}};
    for (int e = 0; e < 2; ++e) {
      const double px = ends[e][0], py = ends[e][1];
      double best = 1e300;
      int b0 = -1, b1 = -1;
      double bw = 0;
      for (int t : tris_of[a])
        for (int k = 0; k < 3; ++k) {
          const int n0 = first.tri[3 * t + k], n1 = first.tri[3 * t + (k + 1) % 3];
          const double x0 = first.node_x[n0], y0 = first.node_y[n0], dx = first.node_x[n1] - x0,
                       dy = first.node_y[n1] - y0;
          const double l2 = dx * dx + dy * dy;
          if (l2 <= 0) continue;
          const double w = std::clamp(((px - x0) * dx + (py - y0) * dy) / l2, 0.0, 1.0);
          const double ex = x0 + w * dx - px, ey = y0 + w * dy - py, dist = ex * ex + ey * ey;
          if (dist < best) best = dist, b0 = n0, b1 = n1, bw = w;
        }
      if (b0 < 0) throw std::runtime_error("dynamics snapshot: brick " + std::to_string(a) + " has no triangle");
      end_n0_[2 * i + e] = b0, end_n1_[2 * i + e] = b1, end_w_[2 * i + e] = bw;
      end_ref_[4 * i + 2 * e] = px, end_ref_[4 * i + 2 * e + 1] = py;
    }
  }
}

io::Snapshot DynFields::fields(long step, const dyn::Snapshot& snap) const {
  using io::Centre;
  const std::size_t nn = mesh_.nodes(), nt = mesh_.triangles(), ni = n_interfaces_;
  // vectors carry a zero z component: ParaView's Xdmf3 reader then offers them for warping
  std::vector<double> pts(2 * nn), u(3 * nn, 0.0), v(3 * nn, 0.0), ipts(4 * ni), tri_bs(nt);
  for (std::size_t i = 0; i < nn; ++i) {
    pts[2 * i] = snap.node_x[i] + snap.ux[i], pts[2 * i + 1] = snap.node_y[i] + snap.uy[i];
    u[3 * i] = snap.ux[i], u[3 * i + 1] = snap.uy[i];
    v[3 * i] = snap.vx[i], v[3 * i + 1] = snap.vy[i];
  }
  for (std::size_t k = 0; k < 2 * ni; ++k) {
    const int n0 = end_n0_[k], n1 = end_n1_[k];
    const double w = end_w_[k];
    ipts[2 * k] = end_ref_[2 * k] + (1 - w) * snap.ux[n0] + w * snap.ux[n1];
    ipts[2 * k + 1] = end_ref_[2 * k + 1] + (1 - w) * snap.uy[n0] + w * snap.uy[n1];
  }
  for (std::size_t t = 0; t < nt; ++t) tri_bs[t] = snap.brick_syy[static_cast<std::size_t>(snap.tri_brick[t])];
  io::Snapshot o;
  o.step = step;
  o.time = snap.time;
  o.reals["displacement"] = snap.displacement;
  o.fields.push_back({Centre::vertex, "points", std::move(pts), 2});
  o.fields.push_back({Centre::vertex, "displacement", std::move(u), 3});
  o.fields.push_back({Centre::vertex, "velocity", std::move(v), 3});
  o.fields.push_back({Centre::element, "sxx", snap.tri_sxx, 1});
  o.fields.push_back({Centre::element, "syy", snap.tri_syy, 1});
  o.fields.push_back({Centre::element, "sxy", snap.tri_sxy, 1});
  o.fields.push_back({Centre::element, "brick_syy", std::move(tri_bs), 1});
  o.fields.push_back({Centre::brick, "syy", snap.brick_syy, 1});
  o.fields.push_back({Centre::interface, "points", std::move(ipts), 2});
  o.fields.push_back({Centre::interface, "damage", snap.iface_damage, 1});
  o.fields.push_back({Centre::interface, "state", std::vector<std::int8_t>(snap.iface_state.begin(), snap.iface_state.end()), 1});
  return o;
}

io::Checkpoint to_named(const DynCheckpoint& c, const deck::Deck& d) {
  io::Checkpoint k;
  const std::string text = physics_text(d);
  k.fingerprint = fingerprint(text);
  k.strings["deck"] = text;
  k.strings["kind"] = "dynamics";
  k.strings["method"] = c.method;
  if (!c.backend.empty()) k.strings["backend"] = c.backend;
  k.integers["step"] = c.step;
  k.reals["time"] = c.time;
  k.reals["dt"] = c.dt;
  k.reals["end_time"] = c.end_time;
  k.reals["critical_step"] = c.critical_step;
  k.reals["worst_balance_residual"] = c.worst_balance;
  k.arrays = c.state;
  return k;
}

DynCheckpoint read_dyn_checkpoint(const std::filesystem::path& path, const deck::Deck& d) {
  const io::Checkpoint k = io::read_checkpoint(path);
  if (!k.strings.count("kind") || k.strings.at("kind") != "dynamics")
    throw io::CheckpointError(path.string() + ": not a checkpoint of a dynamic run (a Monte Carlo checkpoint?)");
  check_fingerprint(k, d, path.string());
  DynCheckpoint c;
  c.method = k.string("method");
  if (k.strings.count("backend")) c.backend = k.string("backend");
  c.step = static_cast<long>(k.integer("step"));
  c.time = k.real("time");
  c.dt = k.real("dt");
  c.end_time = k.reals.count("end_time") ? k.real("end_time") : 0.0;  // 0: an older nacre's checkpoint
  c.critical_step = k.reals.count("critical_step") ? k.real("critical_step") : 0.0;
  c.worst_balance = k.reals.count("worst_balance_residual") ? k.real("worst_balance_residual") : 0.0;
  char b[160];
  if (!(c.dt > 0) || !std::isfinite(c.dt) || c.step < 0 || !(c.time >= 0) || !std::isfinite(c.time)) {
    std::snprintf(b, sizeof b, ": dt = %.6g s, step = %ld, t = %.6g s out of range", c.dt, c.step, c.time);
    throw io::CheckpointError(path.string() + b + "; expected dt > 0, step >= 0 and t >= 0, all finite");
  }
  // Arrays a newer nacre added to the state are missing from a checkpoint an older build wrote:
  // say so here, before anything is built or written, rather than fail later in restore_state.
  check_state_arrays(k, dyn::Simulation::state_array_names(), path.string());
  for (const auto& [name, v] : k.arrays)
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        throw io::CheckpointError(path.string() + ": state array '" + name + "' holds a non-finite value at index " +
                                  std::to_string(i) + " (a checkpoint is written only from checked, finite states)");
  // the state's own clock against the checkpoint's books: a disagreement is a damaged or
  // hand-edited file, refused here by value (exit 2) rather than by the simulation mid-restore
  const std::vector<double>& clock = k.arrays.at("clock");
  if (clock.size() >= 2) {
    if (clock[0] != static_cast<double>(c.step)) {
      std::snprintf(b, sizeof b, ": the state's clock is at step %.17g, the checkpoint says step %ld", clock[0], c.step);
      throw io::CheckpointError(path.string() + b + "; expected the two to agree (a damaged or edited checkpoint)");
    }
    if (clock[1] != c.dt) {
      std::snprintf(b, sizeof b, ": the state was saved with dt = %.9g s, the checkpoint says dt = %.9g s", clock[1], c.dt);
      throw io::CheckpointError(path.string() + b + "; expected the two to agree (a damaged or edited checkpoint)");
    }
  }
  c.state = k.arrays;
  return c;
}

}  // namespace nacre::app
