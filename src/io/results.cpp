#include <nacre/io/atomic_file.hpp>
#include <nacre/io/hdf5_writer.hpp>
#include <nacre/io/results.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <cstdio>
#include <sstream>

namespace nacre::io {

namespace {
std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}
}  // namespace

std::string RunWriter::csv_header() {
  return "step,displacement,energy,reaction,cycles,acceptance,ruptured,converged,step_size,"
         "rot_step,increment,reverts,seconds\n";
}

RunWriter::RunWriter(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
                     int resume_step)
    : deck_(d), s_(s), f_(f), dir_(d.output.directory), csv_(csv_header()) {
  std::filesystem::create_directories(dir_);
  if (resume_step >= 0) {
    // A restart keeps the rows and dumps up to the checkpoint's step and drops later ones.
    std::ifstream in(dir_ / "steps.csv");
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      if (line.empty() || std::stoi(line.substr(0, line.find(','))) > resume_step) break;
      csv_ += line + "\n";
      last_step_ = std::stoi(line.substr(0, line.find(',')));
    }
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir_)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& p : files) {
      const std::string n = p.filename().string();
      if (!(n.starts_with("dump_") && n.ends_with(".h5"))) continue;
      const int step = std::stoi(n.substr(5, n.size() - 8));
      if (step > resume_step) std::filesystem::remove(p);
      else dumps_.push_back({step, H5Reader(p.string()).attribute("displacement"), n});
    }
    write_file_atomic(dir_ / "steps.csv", csv_);
    return;
  }
  // A new run owns the directory's nacre files: dumps of an earlier run would otherwise sit
  // beside the new ones (and be plotted). Other files are left alone.
  for (const auto& e : std::filesystem::directory_iterator(dir_)) {
    const std::string n = e.path().filename().string();
    const bool ours = (n.starts_with("dump_") && n.ends_with(".h5")) || n == "mesh.h5" || n == "nacre.xdmf" ||
                      n == "steps.csv" || n == "summary.json" || n == "energy_force.png" || n == "crack.png" ||
                      n == "checkpoint.h5";
    if (ours && e.is_regular_file()) std::filesystem::remove(e.path());
  }
  if (!d.output.hdf5) return;
  // Static mesh: XDMF "Mixed" topology, each polygon as [3 (polygon), n, v0 .. v(n-1)].
  AtomicPath ap(dir_ / "mesh.h5");
  {
    H5Writer h(ap.temp().string());
    std::vector<std::int32_t> topo;
    topo.reserve(s.size() * 6 + s.vx.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      topo.push_back(3);
      topo.push_back(s.vertex_count(i));
      for (int v = s.poly_offset[i]; v < s.poly_offset[i + 1]; ++v) topo.push_back(v);
    }
    std::vector<double> ref(2 * s.vx.size());
    for (std::size_t v = 0; v < s.vx.size(); ++v) ref[2 * v] = s.vx[v], ref[2 * v + 1] = s.vy[v];
    std::vector<std::int8_t> drive(s.size()), kind(f.size());
    for (std::size_t i = 0; i < s.size(); ++i) drive[i] = static_cast<std::int8_t>(s.drive[i]);
    for (std::size_t i = 0; i < f.size(); ++i) kind[i] = static_cast<std::int8_t>(f.kind[i]);
    std::vector<std::int32_t> ends(2 * f.size());
    for (std::size_t i = 0; i < f.size(); ++i) ends[2 * i] = f.a[i], ends[2 * i + 1] = f.b[i];
    h.group("/bricks");
    h.write("/bricks/topology", topo);
    h.write("/bricks/reference_points", ref, 2);
    h.write("/bricks/centroid_x", s.cx);
    h.write("/bricks/centroid_y", s.cy);
    h.write("/bricks/area", s.area);
    h.write("/bricks/drive", drive);
    h.group("/interfaces");
    h.write("/interfaces/bricks", ends, 2);
    h.write("/interfaces/kind", kind);
    h.write("/interfaces/length", f.length);
    std::vector<double> iref(4 * f.size());
    for (std::size_t i = 0; i < f.size(); ++i) {
      const double cx = s.cx[f.a[i]], cy = s.cy[f.a[i]];
      iref[4 * i] = cx + f.ra0x[i], iref[4 * i + 1] = cy + f.ra0y[i];
      iref[4 * i + 2] = cx + f.ra1x[i], iref[4 * i + 3] = cy + f.ra1y[i];
    }
    h.write("/interfaces/reference_points", iref, 2);
    h.attribute("width", s.width);
    h.attribute("height", s.height);
  }
  ap.commit();
}

void RunWriter::step(const mc::StepRecord& r) {
  last_step_ = r.step;
  csv_ += std::to_string(r.step) + "," + num(r.displacement) + "," + num(r.energy) + "," + num(r.reaction) + "," +
          std::to_string(r.cycles) + "," + num(r.acceptance) + "," + std::to_string(r.ruptured) + "," +
          (r.converged ? "1" : "0") + "," + num(r.step_size) + "," + num(r.rot_step) + "," + num(r.increment) +
          "," + std::to_string(r.reverts) + "," + num(r.seconds) + "\n";
  write_file_atomic(dir_ / "steps.csv", csv_);
}

void RunWriter::dump(int step, mc::Solver& solver) {
  if (!deck_.output.hdf5) return;
  Kokkos::Profiling::ScopedRegion region("nacre::io::dump");
  const auto& m = solver.model();
  std::vector<double> x, y, t;
  solver.poses(x, y, t);
  // brick energy (half of each interface to each side) and interface state, original order
  Field<double> be("nacre::io::brick_energy", m.n_bricks), ie("nacre::io::iface_energy", m.n_interfaces);
  Field<std::int8_t> is("nacre::io::iface_state", m.n_interfaces);
  mc::brick_energy(m, be);
  mc::interface_state(m, ie, is);
  auto hbe = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), be);
  auto hie = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ie);
  auto his = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), is);
  const std::size_t n = s_.size(), ni = f_.size();
  std::vector<double> energy(n), pts(2 * s_.vx.size()), ipts(4 * ni), ienergy(ni);
  std::vector<std::int8_t> istate(ni);
  for (int k = 0; k < m.n_bricks; ++k) energy[m.perm[k]] = 0.5 * hbe(k);
  for (std::size_t i = 0; i < ni; ++i) ienergy[m.iface_perm[i]] = hie(i), istate[m.iface_perm[i]] = his(i);
  auto moved = [&](std::size_t b, double px, double py, double& ox, double& oy) {
    double dx, dy;
    cohesive::point_displacement(cohesive::Pose{x[b], y[b], t[b]}, px - s_.cx[b], py - s_.cy[b], dx, dy);
    ox = px + dx, oy = py + dy;
  };
  for (std::size_t b = 0; b < n; ++b)
    for (int v = s_.poly_offset[b]; v < s_.poly_offset[b + 1]; ++v)
      moved(b, s_.vx[v], s_.vy[v], pts[2 * v], pts[2 * v + 1]);
  for (std::size_t i = 0; i < ni; ++i) {  // interface drawn on brick a's face
    const std::size_t a = f_.a[i];
    moved(a, s_.cx[a] + f_.ra0x[i], s_.cy[a] + f_.ra0y[i], ipts[4 * i], ipts[4 * i + 1]);
    moved(a, s_.cx[a] + f_.ra1x[i], s_.cy[a] + f_.ra1y[i], ipts[4 * i + 2], ipts[4 * i + 3]);
  }
  char name[32];
  std::snprintf(name, sizeof name, "dump_%05d.h5", step);
  AtomicPath ap(dir_ / name);
  {
    H5Writer h(ap.temp().string());
    h.attribute("step", static_cast<std::int64_t>(step));
    h.attribute("displacement", solver.load());
    h.attribute("energy", solver.tracked_energy());
    h.attribute("cycle", static_cast<std::int64_t>(solver.global_cycle()));
    h.group("/bricks");
    h.write("/bricks/x", x);
    h.write("/bricks/y", y);
    h.write("/bricks/theta", t);
    h.write("/bricks/energy", energy);
    h.write("/bricks/points", pts, 2);
    h.group("/interfaces");
    h.write("/interfaces/points", ipts, 2);
    h.write("/interfaces/energy", ienergy);
    h.write("/interfaces/state", istate);
  }
  ap.commit();
  dumps_.push_back({step, solver.load(), name});
  write_xdmf();
  write_checkpoint(dir_ / "checkpoint.h5", solver.checkpoint());
}

void RunWriter::write_checkpoint(const std::filesystem::path& path, const mc::Checkpoint& c) {
  AtomicPath ap(path);
  {
    H5Writer h(ap.temp().string());
    h.attribute("colouring", c.colouring);
    h.attribute("step", static_cast<std::int64_t>(c.run.step));
    h.attribute("increment", c.run.increment);
    h.attribute("previous_increment", c.run.previous_increment);
    h.attribute("have_previous", static_cast<std::int64_t>(c.run.have_previous));
    h.attribute("displacement", c.displacement);
    h.attribute("step_size", c.step_size);
    h.attribute("rot_step", c.rot_step);
    h.attribute("global_cycle", static_cast<std::int64_t>(c.global_cycle));
    h.attribute("accepted_total", static_cast<std::int64_t>(c.accepted_total));
    h.attribute("trials_total", static_cast<std::int64_t>(c.trials_total));
    h.attribute("window_accepted", static_cast<std::int64_t>(c.window_accepted));
    h.attribute("window_trials", static_cast<std::int64_t>(c.window_trials));
    h.write("/pose", c.pose, 3);
    h.write("/previous_pose", c.previous_pose, 3);
    if (!c.brick_step.empty()) h.write("/brick_step", c.brick_step, 3);
  }
  ap.commit();
}

mc::Checkpoint RunWriter::read_checkpoint(const std::filesystem::path& path) {
  const H5Reader h(path.string());
  auto i64 = [&](const char* n) { return static_cast<long>(h.attribute(n)); };
  mc::Checkpoint c;
  c.colouring = h.string_attribute("colouring");
  c.run.step = static_cast<int>(i64("step"));
  c.run.increment = h.attribute("increment");
  c.run.previous_increment = h.attribute("previous_increment");
  c.run.have_previous = i64("have_previous") != 0;
  c.displacement = h.attribute("displacement");
  c.step_size = h.attribute("step_size");
  c.rot_step = h.attribute("rot_step");
  c.global_cycle = static_cast<std::uint64_t>(i64("global_cycle"));
  c.accepted_total = i64("accepted_total");
  c.trials_total = i64("trials_total");
  c.window_accepted = i64("window_accepted");
  c.window_trials = i64("window_trials");
  c.pose = h.doubles("/pose");
  c.previous_pose = h.doubles("/previous_pose");
  if (h.has("/brick_step")) c.brick_step = h.doubles("/brick_step");
  return c;
}

void RunWriter::write_xdmf() const {
  const std::size_t n = s_.size(), ni = f_.size();
  const std::size_t topo_len = 2 * n + s_.vx.size();
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n";
  auto item = [&](const std::string& dims, const char* type, int prec, const std::string& ref) {
    x << "   <DataItem Dimensions=\"" << dims << "\" NumberType=\"" << type << "\" Precision=\"" << prec
      << "\" Format=\"HDF\">" << ref << "</DataItem>\n";
  };
  x << "<Grid Name=\"bricks\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& d : dumps_) {
    x << "  <Grid Name=\"bricks_" << d.step << "\" GridType=\"Uniform\">\n   <Time Value=\"" << num(d.displacement)
      << "\"/>\n   <Topology TopologyType=\"Mixed\" NumberOfElements=\"" << n << "\">\n";
    item(std::to_string(topo_len), "Int", 4, "mesh.h5:/bricks/topology");
    x << "   </Topology>\n   <Geometry GeometryType=\"XY\">\n";
    item(std::to_string(s_.vx.size()) + " 2", "Float", 8, d.file + ":/bricks/points");
    x << "   </Geometry>\n";
    for (const char* a : {"energy", "x", "y", "theta"}) {
      x << "   <Attribute Name=\"" << a << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
      item(std::to_string(n), "Float", 8, d.file + ":/bricks/" + a);
      x << "   </Attribute>\n";
    }
    x << "   <Attribute Name=\"drive\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
    item(std::to_string(n), "Char", 1, "mesh.h5:/bricks/drive");
    x << "   </Attribute>\n  </Grid>\n";
  }
  x << "</Grid>\n<Grid Name=\"interfaces\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& d : dumps_) {
    x << "  <Grid Name=\"interfaces_" << d.step << "\" GridType=\"Uniform\">\n   <Time Value=\"" << num(d.displacement)
      << "\"/>\n   <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" NumberOfElements=\"" << ni
      << "\"/>\n   <Geometry GeometryType=\"XY\">\n";
    item(std::to_string(2 * ni) + " 2", "Float", 8, d.file + ":/interfaces/points");
    x << "   </Geometry>\n   <Attribute Name=\"state\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
    item(std::to_string(ni), "Char", 1, d.file + ":/interfaces/state");
    x << "   </Attribute>\n   <Attribute Name=\"energy\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
    item(std::to_string(ni), "Float", 8, d.file + ":/interfaces/energy");
    x << "   </Attribute>\n  </Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  write_file_atomic(dir_ / "nacre.xdmf", x.str());
}

void RunWriter::summary(const mc::Solver& solver, double seconds, const std::string& extra_json) {
  const auto& m = solver.model();
  const auto& pt = solver.times();
  std::ostringstream j;
  j << "{\n  \"deck\": \"" << deck_.path << "\",\n  \"bricks\": " << m.n_bricks << ",\n  \"free_bricks\": " << m.n_free
    << ",\n  \"interfaces\": " << m.n_interfaces << ",\n  \"colouring\": \"" << m.colouring_name
    << "\",\n  \"colours\": " << (m.colour_offset.size() - 1) << ",\n  \"rng\": \"" << deck_.solver.rng
    << "\",\n  \"seed\": " << deck_.seed << ",\n  \"threads\": " << Kokkos::DefaultExecutionSpace().concurrency()
    << ",\n  \"execution_space\": \"" << Kokkos::DefaultExecutionSpace::name() << "\",\n  \"steps\": " << last_step_
    << ",\n  \"cycles\": " << solver.global_cycle() << ",\n  \"seconds\": " << num(seconds)
    << ",\n  \"phase_seconds\": {\"rng\": " << num(pt.rng) << ", \"sweep\": " << num(pt.sweep) << ", \"energy\": "
    << num(pt.energy) << "},\n  \"presimulation_seconds_per_cycle\": {";
  bool first = true;
  for (const auto& [name, sec] : solver.presim()) {
    j << (first ? "" : ", ") << "\"" << name << "\": " << num(sec);
    first = false;
  }
  j << "}" << extra_json << "\n}\n";
  write_file_atomic(dir_ / "summary.json", j.str());
}

}  // namespace nacre::io
