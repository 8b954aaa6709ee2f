// Outputs of a dynamic run: time series, per-dump HDF5 + XDMF of the deformed triangle mesh,
// named-array checkpoint, summary (see dyn_output.hpp for the file list). Every file is written
// to a temporary sibling and renamed, so an interrupted or unstable run leaves only whole files.
#include "dyn_output.hpp"

#include <nacre/app/restart.hpp>
#include <nacre/io/atomic_file.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/hdf5_writer.hpp>

#include <Kokkos_Core.hpp>
#include <Kokkos_Profiling_ScopedRegion.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace nacre::app {

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);  // round-trips: a restarted run's rows compare exactly
  return b;
}

std::string dump_name(long step) {
  char b[40];
  std::snprintf(b, sizeof b, "dump_%09ld.h5", step);
  return b;
}

bool is_dump(const std::string& n) { return n.starts_with("dump_") && n.ends_with(".h5"); }

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

std::string DynWriter::csv_header() {
  return "step,time,displacement,strain_energy,kinetic_energy,cohesive_energy,damping_dissipated,external_work,"
         "balance_residual,reaction,ruptured,dt,critical_estimate,seconds\n";
}

DynWriter::DynWriter(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
                     const dyn::Snapshot& first, long resume_step)
    : deck_(d), s_(s), f_(f), dir_(d.output.directory), csv_(csv_header()) {
  std::filesystem::create_directories(dir_);
  n_nodes_ = first.node_x.size();
  n_tri_ = first.tri.size() / 3;
  if (first.iface_damage.size() != f.size() || first.tri_brick.size() != n_tri_ || first.brick_syy.size() != s.size())
    throw std::runtime_error("dynamics snapshot sizes do not match the specimen (" +
                             std::to_string(first.iface_damage.size()) + " interface values for " +
                             std::to_string(f.size()) + " interfaces, " + std::to_string(first.brick_syy.size()) +
                             " brick values for " + std::to_string(s.size()) + " bricks)");

  // Interface ends onto triangle edges of brick a (static; used to draw the deformed interfaces).
  std::vector<std::vector<int>> tris_of(s.size());
  for (std::size_t t = 0; t < n_tri_; ++t) tris_of[static_cast<std::size_t>(first.tri_brick[t])].push_back(static_cast<int>(t));
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

  if (resume_step >= 0) {
    // A restart keeps the rows and dumps up to the checkpoint's step and drops later ones.
    std::ifstream in(dir_ / "series.csv");
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      if (line.empty() || std::stol(line.substr(0, line.find(','))) > resume_step) break;
      csv_ += line + "\n";
      ++rows_;
    }
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir_)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& p : files) {
      const std::string n = p.filename().string();
      if (!is_dump(n)) continue;
      const long step = std::stol(n.substr(5, n.size() - 8));
      if (step > resume_step) std::filesystem::remove(p);
      else dumps_.push_back({step, io::H5Reader(p.string()).attribute("time"), n});
    }
    flush_series();
    if (d.output.hdf5 && !std::filesystem::exists(dir_ / "mesh.h5")) write_mesh(first);  // restart into another directory
    write_xdmf();
    return;
  }
  // A new run owns the directory's nacre files (a previous run's dumps would sit beside the new).
  for (const auto& e : std::filesystem::directory_iterator(dir_)) {
    const std::string n = e.path().filename().string();
    const bool ours = is_dump(n) || n == "mesh.h5" || n == "nacre.xdmf" || n == "series.csv" || n == "steps.csv" ||
                      n == "summary.json" || n == "energy_force.png" || n == "crack.png" || n == "checkpoint.h5";
    if (ours && e.is_regular_file()) std::filesystem::remove(e.path());
  }
  flush_series();
  if (d.output.hdf5) write_mesh(first);
}

void DynWriter::write_mesh(const dyn::Snapshot& first) {
  io::AtomicPath ap(dir_ / "mesh.h5");
  {
    io::H5Writer h(ap.temp().string());
    std::vector<double> ref(2 * n_nodes_);
    for (std::size_t v = 0; v < n_nodes_; ++v) ref[2 * v] = first.node_x[v], ref[2 * v + 1] = first.node_y[v];
    h.group("/nodes");
    h.write("/nodes/reference", ref, 2);
    h.group("/triangles");
    h.write("/triangles/connectivity", std::vector<std::int32_t>(first.tri.begin(), first.tri.end()), 3);
    h.write("/triangles/brick", std::vector<std::int32_t>(first.tri_brick.begin(), first.tri_brick.end()));
    h.group("/bricks");
    h.write("/bricks/centroid_x", s_.cx);
    h.write("/bricks/centroid_y", s_.cy);
    h.write("/bricks/area", s_.area);
    std::vector<std::int8_t> drive(s_.size());
    for (std::size_t i = 0; i < s_.size(); ++i) drive[i] = static_cast<std::int8_t>(s_.drive[i]);
    h.write("/bricks/drive", drive);
    h.group("/interfaces");
    std::vector<std::int32_t> conn(2 * f_.size());
    for (std::size_t i = 0; i < conn.size(); ++i) conn[i] = static_cast<std::int32_t>(i);
    std::vector<std::int8_t> kind(f_.size());
    for (std::size_t i = 0; i < f_.size(); ++i) kind[i] = static_cast<std::int8_t>(f_.kind[i]);
    h.write("/interfaces/connectivity", conn, 2);
    h.write("/interfaces/kind", kind);
    h.write("/interfaces/reference_points", end_ref_, 2);
    h.attribute("width", s_.width);
    h.attribute("height", s_.height);
  }
  ap.commit();
}

void DynWriter::row(const SeriesRow& r) {
  const auto& e = r.e;
  csv_ += std::to_string(r.step) + "," + num(r.time) + "," + num(r.displacement) + "," + num(e.strain) + "," +
          num(e.kinetic) + "," + num(e.cohesive) + "," + num(e.damping_dissipated) + "," + num(e.external_work) + "," +
          num(e.balance_residual) + "," + num(r.reaction) + "," + std::to_string(r.ruptured) + "," + num(r.dt) + "," +
          num(r.critical_estimate) + "," + num(r.seconds) +
          "\n";
  ++rows_;
}

void DynWriter::flush_series() { io::write_file_atomic(dir_ / "series.csv", csv_); }

void DynWriter::dump(long step, const dyn::Snapshot& snap, const DynCheckpoint& cp) {
  if (deck_.output.hdf5) {
    Kokkos::Profiling::ScopedRegion region("nacre::app::dyn_dump");
    const std::size_t nn = n_nodes_, nt = n_tri_, ni = f_.size();
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
    std::vector<std::int8_t> state(snap.iface_state.begin(), snap.iface_state.end());
    const std::string name = dump_name(step);
    io::AtomicPath ap(dir_ / name);
    {
      io::H5Writer h(ap.temp().string());
      h.attribute("step", static_cast<std::int64_t>(step));
      h.attribute("time", snap.time);
      h.attribute("displacement", snap.displacement);
      h.group("/nodes");
      h.write("/nodes/points", pts, 2);
      h.write("/nodes/displacement", u, 3);
      h.write("/nodes/velocity", v, 3);
      h.group("/triangles");
      h.write("/triangles/sxx", snap.tri_sxx);
      h.write("/triangles/syy", snap.tri_syy);
      h.write("/triangles/sxy", snap.tri_sxy);
      h.write("/triangles/brick_syy", tri_bs);
      h.group("/bricks");
      h.write("/bricks/syy", snap.brick_syy);
      h.group("/interfaces");
      h.write("/interfaces/points", ipts, 2);
      h.write("/interfaces/damage", snap.iface_damage);
      h.write("/interfaces/state", state);
    }
    ap.commit();
    std::erase_if(dumps_, [&](const DumpInfo& d) { return d.step == step; });
    dumps_.push_back({step, snap.time, name});
    write_xdmf();
  }
  write_checkpoint(dir_ / "checkpoint.h5", cp);
  flush_series();
}

void DynWriter::write_checkpoint(const std::filesystem::path& path, const DynCheckpoint& c) const {
  io::Checkpoint k;
  const std::string text = physics_text(deck_);
  k.fingerprint = fingerprint(text);
  k.strings["deck"] = text;
  k.strings["kind"] = "dynamics";
  k.strings["method"] = c.method;
  k.integers["step"] = c.step;
  k.reals["time"] = c.time;
  k.reals["dt"] = c.dt;
  k.arrays = c.state;
  io::write_checkpoint(path, k);
}

DynCheckpoint DynWriter::read_checkpoint(const std::filesystem::path& path, const deck::Deck& d) {
  const io::Checkpoint k = io::read_checkpoint(path);
  if (!k.strings.count("kind") || k.strings.at("kind") != "dynamics")
    throw io::CheckpointError(path.string() + ": not a checkpoint of a dynamic run (a Monte Carlo checkpoint?)");
  check_fingerprint(k, d, path.string());
  DynCheckpoint c;
  c.method = k.string("method");
  c.step = static_cast<long>(k.integer("step"));
  c.time = k.real("time");
  c.dt = k.real("dt");
  if (!(c.dt > 0) || c.step < 0)
    throw io::CheckpointError(path.string() + ": dt = " + std::to_string(c.dt) + ", step = " + std::to_string(c.step) +
                              " out of range; expected dt > 0 and step >= 0");
  // Arrays a newer nacre added to the state (dacc: the driven elements' accumulators, 2026-11)
  // are missing from a checkpoint an older build wrote: say so here, before anything is built or
  // written, rather than fail later in restore_state.
  check_state_arrays(k, dyn::Simulation::state_array_names(), path.string());
  c.state = k.arrays;
  return c;
}

void DynWriter::write_xdmf() const {
  const std::size_t nn = n_nodes_, nt = n_tri_, ni = f_.size();
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n";
  auto item = [&](const std::string& dims, const char* type, int prec, const std::string& ref) {
    x << "    <DataItem Dimensions=\"" << dims << "\" NumberType=\"" << type << "\" Precision=\"" << prec
      << "\" Format=\"HDF\">" << ref << "</DataItem>\n";
  };
  auto attribute = [&](const char* name, const char* type, const char* center, const std::string& dims,
                       const char* ntype, int prec, const std::string& ref) {
    x << "   <Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"" << center << "\">\n";
    item(dims, ntype, prec, ref);
    x << "   </Attribute>\n";
  };
  x << "<Grid Name=\"triangles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& d : dumps_) {
    const std::string f = d.file + ":";
    x << "  <Grid Name=\"triangles_" << d.step << "\" GridType=\"Uniform\">\n   <Time Value=\"" << num(d.time)
      << "\"/>\n   <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << nt << "\">\n";
    item(std::to_string(nt) + " 3", "Int", 4, "mesh.h5:/triangles/connectivity");
    x << "   </Topology>\n   <Geometry GeometryType=\"XY\">\n";
    item(std::to_string(nn) + " 2", "Float", 8, f + "/nodes/points");
    x << "   </Geometry>\n";
    attribute("displacement", "Vector", "Node", std::to_string(nn) + " 3", "Float", 8, f + "/nodes/displacement");
    attribute("velocity", "Vector", "Node", std::to_string(nn) + " 3", "Float", 8, f + "/nodes/velocity");
    for (const char* a : {"sxx", "syy", "sxy", "brick_syy"})
      attribute(a, "Scalar", "Cell", std::to_string(nt), "Float", 8, f + "/triangles/" + a);
    attribute("brick", "Scalar", "Cell", std::to_string(nt), "Int", 4, "mesh.h5:/triangles/brick");
    x << "  </Grid>\n";
  }
  x << "</Grid>\n";
  if (ni > 0) {
    x << "<Grid Name=\"interfaces\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& d : dumps_) {
      const std::string f = d.file + ":";
      x << "  <Grid Name=\"interfaces_" << d.step << "\" GridType=\"Uniform\">\n   <Time Value=\"" << num(d.time)
        << "\"/>\n   <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" NumberOfElements=\"" << ni << "\">\n";
      item(std::to_string(ni) + " 2", "Int", 4, "mesh.h5:/interfaces/connectivity");
      x << "   </Topology>\n   <Geometry GeometryType=\"XY\">\n";
      item(std::to_string(2 * ni) + " 2", "Float", 8, f + "/interfaces/points");
      x << "   </Geometry>\n";
      attribute("damage", "Scalar", "Cell", std::to_string(ni), "Float", 8, f + "/interfaces/damage");
      attribute("state", "Scalar", "Cell", std::to_string(ni), "Char", 1, f + "/interfaces/state");
      attribute("kind", "Scalar", "Cell", std::to_string(ni), "Char", 1, "mesh.h5:/interfaces/kind");
      x << "  </Grid>\n";
    }
    x << "</Grid>\n";
  }
  x << "</Domain>\n</Xdmf>\n";
  io::write_file_atomic(dir_ / "nacre.xdmf", x.str());
}

void DynWriter::summary(const std::string& json_body) { io::write_file_atomic(dir_ / "summary.json", json_body); }

}  // namespace nacre::app
