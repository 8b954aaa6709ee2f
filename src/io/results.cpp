// SPDX-License-Identifier: BSD-3-Clause
// The output directory of a run of either solver family: CSV rows, mesh, dumps of named fields,
// the XDMF index, the checkpoint and the summary, each written atomically and in the order a
// restart relies on. Knows geometry, not solvers; restarts keep or set up the directory only
// after the caller validated the checkpoint.
#include <nacre/io/atomic_file.hpp>
#include <nacre/core/format.hpp>
#include <nacre/io/hdf5_writer.hpp>
#include <nacre/io/results.hpp>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace nacre::io {

namespace {
std::string num(double v) { return format_real(v, 10); }

/// \brief Files a run owns in its directory (a new run removes them; others are left alone).
bool ours(const std::string& n) {
  if (dump_step(n).has_value()) return true;
  for (auto own : {names::mesh, names::xdmf, names::mc_table, names::dyn_table, names::summary, names::checkpoint})
    if (n == own) return true;
  return std::find(names::charts.begin(), names::charts.end(), n) != names::charts.end();
}

/// \brief The step of a CSV row ("12,0.3,..."), parsed strictly.
std::optional<long> row_step(const std::string& line) {
  const auto comma = line.find(',');
  if (comma == std::string::npos || comma == 0) return std::nullopt;
  long v = -1;
  const auto [p, ec] = std::from_chars(line.data(), line.data() + comma, v);
  if (ec != std::errc() || p != line.data() + comma || v < 0) return std::nullopt;
  return v;
}

/// \brief The HDF5 group of a field: with a triangle mesh vertex fields live on its nodes.
const char* group_of(Centre c, bool triangles) {
  switch (c) {
    case Centre::element: return triangles ? "/triangles" : "/elements";
    case Centre::interface: return "/interfaces";
    case Centre::vertex: return triangles ? "/nodes" : "/bricks";
    default: return "/bricks";
  }
}
}  // namespace

std::optional<long> dump_step(const std::string& n) {
  if (n.size() < 9 || !n.starts_with("dump_") || !n.ends_with(".h5")) return std::nullopt;
  const char* b = n.data() + 5;
  const char* e = n.data() + n.size() - 3;
  if (!std::all_of(b, e, [](char ch) { return ch >= '0' && ch <= '9'; })) return std::nullopt;
  long v = -1;
  const auto [p, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || p != e) return std::nullopt;
  return v;
}

RunWriter::RunWriter(Options o, const geometry::Specimen& s, const geometry::Interfaces& f,
                     const std::optional<Resume>& resume)
    : o_(std::move(o)), s_(s), f_(f), csv_(o_.csv_header) {
  const auto& dir = o_.directory;
  std::filesystem::create_directories(dir);
  stale_removed_ = remove_stale_temporaries(dir);
  std::error_code ec;
  const bool same_dir = resume && std::filesystem::equivalent(resume->source_directory, dir, ec) && !ec;
  if (resume && same_dir) {
    // A restart keeps the rows and dumps up to the checkpoint's step and drops later ones.
    keep_rows(dir / o_.csv_name, resume->step);
    std::vector<std::pair<long, std::filesystem::path>> files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (const auto step = dump_step(e.path().filename().string())) files.emplace_back(*step, e.path());
    std::sort(files.begin(), files.end());  // by step: names of other widths sort the same
    for (const auto& [step, p] : files) {  // not a dump of ours (dump_final.h5, backups): left alone
      if (step > resume->step) {
        std::filesystem::remove(p);
        continue;
      }
      const H5Reader h(p.string());
      const double t = h.attributes().count("time") ? h.attribute("time") : h.attribute("displacement");
      dumps_.push_back({step, t, p.filename().string()});
    }
    write_file_atomic(dir / o_.csv_name, csv_);
    // the mesh is a function of the geometry alone: rewritten when missing or from a version
    // without the interfaces' connectivity
    if (o_.hdf5 && (!std::filesystem::exists(dir / names::mesh) ||
                    !H5Reader((dir / names::mesh).string()).has("/interfaces/connectivity")))
      write_mesh();
    return;
  }
  // A new run (or a restart into another directory) owns the directory's nacre files: dumps of
  // an earlier run would otherwise sit beside the new ones (and be plotted). Other files stay.
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::error_code rec;
    if (ours(e.path().filename().string()) && e.is_regular_file(rec)) std::filesystem::remove(e.path());
  }
  // the source's history up to the checkpoint, so the table is complete here too
  if (resume) keep_rows(resume->source_directory / o_.csv_name, resume->step);
  // the table exists from the start (header only until a row comes), so a run that stops in
  // its first step still leaves it
  write_file_atomic(dir / o_.csv_name, csv_);
  if (o_.hdf5) write_mesh();
}

void RunWriter::keep_rows(const std::filesystem::path& table, long up_to) {
  std::ifstream in(table);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const auto st = row_step(line);
    if (!st || *st > up_to) break;
    csv_ += line + "\n";
    last_step_ = *st;
    ++rows_;
  }
}

void RunWriter::write_mesh() const {
  const auto& s = s_;
  const auto& f = f_;
  // Static mesh: XDMF "Mixed" topology, each polygon as [3 (polygon), n, v0 .. v(n-1)].
  AtomicPath ap(o_.directory / names::mesh);
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
    // Polyline connectivity of the interfaces grid: interface i joins points 2i and 2i + 1 of the
    // dumps' /interfaces/points (ParaView's Xdmf3 reader shows no cells without it)
    std::vector<std::int32_t> conn(2 * f.size());
    for (std::size_t i = 0; i < conn.size(); ++i) conn[i] = static_cast<std::int32_t>(i);
    h.write("/interfaces/connectivity", conn, 2);
    if (o_.elements) {  // deformable bricks: the triangle mesh the dumps' node fields live on
      const TriangleMesh& m = *o_.elements;
      h.group("/nodes");
      h.write("/nodes/reference", m.reference, 2);
      h.group("/triangles");
      h.write("/triangles/connectivity", m.connectivity, 3);
      h.write("/triangles/brick", m.brick);
    }
    h.attribute("width", s.width);
    h.attribute("height", s.height);
    h.close();
  }
  ap.commit();
}

void RunWriter::row(long step, const std::string& csv_line, bool durable) {
  last_step_ = step;
  csv_ += csv_line;
  ++rows_;
  pending_ = true;
  if (durable) flush_rows();
}

void RunWriter::flush_rows() {
  if (!pending_) return;
  write_file_atomic(o_.directory / o_.csv_name, csv_);
  pending_ = false;
}

void RunWriter::dump(const Snapshot& snap) {
  flush_rows();
  if (!o_.hdf5) return;
  const bool tri = o_.elements.has_value();
  char name[48];
  std::snprintf(name, sizeof name, "dump_%0*ld.h5", o_.dump_digits, snap.step);
  std::vector<Layout> layout;
  AtomicPath ap(o_.directory / name);
  {
    H5Writer h(ap.temp().string());
    h.attribute("step", static_cast<std::int64_t>(snap.step));
    h.attribute("time", snap.time);
    for (const auto& [n, v] : snap.reals) h.attribute(n, v);
    for (const auto& [n, v] : snap.integers) h.attribute(n, v);
    std::vector<std::string> made;
    for (const auto& fld : snap.fields) {
      const std::string g = group_of(fld.centre, tri);
      if (std::find(made.begin(), made.end(), g) == made.end()) h.group(g), made.push_back(g);
      std::size_t size = 0;
      std::visit(
          [&](const auto& v) {
            size = v.size();
            h.write(g + "/" + fld.name, v, fld.components);
          },
          fld.data);
      layout.push_back({fld.centre, fld.name, fld.data.index(), fld.components, size / fld.components});
    }
    h.close();
  }
  ap.commit();
  layout_ = std::move(layout);
  std::erase_if(dumps_, [&](const DumpInfo& d) { return d.step == snap.step; });
  dumps_.push_back({snap.step, snap.time, name});
  write_xdmf();
}

void RunWriter::checkpoint(const Checkpoint& c) {
  flush_rows();  // the rows up to the checkpoint's step are durable before it
  write_checkpoint(checkpoint_path(), c);
}

void RunWriter::write_xdmf() const {
  const std::size_t n = s_.size(), ni = f_.size();
  const bool tri = o_.elements.has_value();
  const std::size_t topo_len = 2 * n + s_.vx.size();
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n";
  auto item = [&](const std::string& dims, const char* type, int prec, const std::string& ref) {
    x << "   <DataItem Dimensions=\"" << dims << "\" NumberType=\"" << type << "\" Precision=\"" << prec
      << "\" Format=\"HDF\">" << ref << "</DataItem>\n";
  };
  auto field_item = [&](const Layout& l, const std::string& file) {
    static const char* types[] = {"Float", "Int", "Char"};
    static const int precs[] = {8, 4, 1};
    const std::string dims = std::to_string(l.rows) + (l.components > 1 ? " " + std::to_string(l.components) : "");
    item(dims, types[l.index], precs[l.index], file + ":" + group_of(l.centre, tri) + "/" + l.name);
  };
  auto find = [&](Centre c, const char* name) -> const Layout* {
    for (const auto& l : layout_)
      if (l.centre == c && l.name == name) return &l;
    return nullptr;
  };
  auto attributes = [&](Centre c, const char* centre_name, const std::string& file) {
    for (const auto& l : layout_) {
      if (l.centre != c || l.name == "points") continue;
      x << "   <Attribute Name=\"" << l.name << "\" AttributeType=\"" << (l.components == 1 ? "Scalar" : "Vector")
        << "\" Center=\"" << centre_name << "\">\n";
      field_item(l, file);
      x << "   </Attribute>\n";
    }
  };
  // One temporal collection per mesh: its topology, geometry (the dump's "points", else the
  // reference points), the dump's fields of the given centres and one static cell attribute.
  struct Attribute {
    Centre centre;
    const char* centre_name;
  };
  struct Grid {
    const char* name;
    std::string topology;  ///< the Topology element's attributes
    std::string connectivity_dims;
    const char* connectivity;
    const Layout* points;
    std::string reference_dims;
    const char* reference;
    std::vector<Attribute> fields;
    const char* static_name;
    const char* static_type;
    int static_prec;
    const char* static_path;
    std::size_t cells;
  };
  auto grid = [&](const Grid& g) {
    x << "<Grid Name=\"" << g.name << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& d : dumps_) {
      x << "  <Grid Name=\"" << g.name << "_" << d.step << "\" GridType=\"Uniform\">\n   <Time Value=\""
        << num(d.time) << "\"/>\n   <Topology " << g.topology << " NumberOfElements=\"" << g.cells << "\">\n";
      item(g.connectivity_dims, "Int", 4, g.connectivity);
      x << "   </Topology>\n   <Geometry GeometryType=\"XY\">\n";
      if (g.points) field_item(*g.points, d.file);
      else item(g.reference_dims, "Float", 8, g.reference);
      x << "   </Geometry>\n";
      for (const auto& a : g.fields) attributes(a.centre, a.centre_name, d.file);
      x << "   <Attribute Name=\"" << g.static_name << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
      item(std::to_string(g.cells), g.static_type, g.static_prec, g.static_path);
      x << "   </Attribute>\n  </Grid>\n";
    }
    x << "</Grid>\n";
  };
  const Layout* points = find(Centre::vertex, "points");
  if (tri) {  // deformable bricks are drawn by their triangles: node and element fields
    const std::size_t nn = o_.elements->nodes(), nt = o_.elements->triangles();
    grid({"triangles", "TopologyType=\"Triangle\"", std::to_string(nt) + " 3", "mesh.h5:/triangles/connectivity",
          points, std::to_string(nn) + " 2", "mesh.h5:/nodes/reference",
          {{Centre::vertex, "Node"}, {Centre::element, "Cell"}}, "brick", "Int", 4, "mesh.h5:/triangles/brick", nt});
  } else {  // rigid bricks: one polygon each (XDMF "Mixed")
    grid({"bricks", "TopologyType=\"Mixed\"", std::to_string(topo_len), "mesh.h5:/bricks/topology", points,
          std::to_string(s_.vx.size()) + " 2", "mesh.h5:/bricks/reference_points",
          {{Centre::brick, "Cell"}, {Centre::vertex, "Node"}}, "drive", "Char", 1, "mesh.h5:/bricks/drive", n});
  }
  if (const Layout* ip = find(Centre::interface, "points"))
    grid({"interfaces", "TopologyType=\"Polyline\" NodesPerElement=\"2\"", std::to_string(ni) + " 2",
          "mesh.h5:/interfaces/connectivity", ip, "", "", {{Centre::interface, "Cell"}}, "kind", "Char", 1,
          "mesh.h5:/interfaces/kind", ni});
  x << "</Domain>\n</Xdmf>\n";
  write_file_atomic(o_.directory / names::xdmf, x.str());
}

void RunWriter::summary(const std::string& json) { write_file_atomic(o_.directory / names::summary, json); }

}  // namespace nacre::io
