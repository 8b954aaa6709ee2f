// SPDX-License-Identifier: BSD-3-Clause
// Limits and estimates of a deck: an absurd deck (1e6 x 1e6 bricks, sizes of
// 1e300 or 1e-300, an increment that never reaches the final displacement) is refused from the
// deck alone, in milliseconds, with "file:line: key: ..." and how to raise the limit. Also the
// canonical physics text of a deck (checkpoint fingerprints) and the line of every key.
#include <nacre/deck/limits.hpp>
#include <nacre/core/format.hpp>

#include "toml_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <unistd.h>
#include <utility>
#include <vector>

namespace nacre::deck {

namespace {
std::string fmt(double v) { return format_real(v, 3); }

void walk(const toml::table& t, const std::string& prefix, std::map<std::string, int>& out) {
  for (auto&& [k, v] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    out[key] = static_cast<int>(v.source().begin.line);
    if (auto* sub = v.as_table()) walk(*sub, key, out);
  }
}

void value_text(const toml::node& v, std::ostringstream& os) {
  if (auto d = v.value_exact<double>()) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", *d);
    os << b;
  } else if (auto i = v.value_exact<std::int64_t>()) {
    os << *i;
  } else if (auto b = v.value_exact<bool>()) {
    os << (*b ? "true" : "false");
  } else if (auto s = v.value_exact<std::string>()) {
    os << '"';
    for (char c : *s) {
      if (c == '"' || c == '\\') os << '\\';
      if (c == '\n') os << "\\n";
      else os << c;
    }
    os << '"';
  } else if (auto* a = v.as_array()) {
    os << '[';
    bool first = true;
    for (auto&& e : *a) {
      os << (first ? "" : ", ");
      value_text(e, os);
      first = false;
    }
    os << ']';
  } else {
    os << "<other>";
  }
}

void canon(const toml::table& t, const std::string& prefix, std::ostringstream& os) {
  // toml::table iterates in key order: the text does not depend on how the deck was laid out
  for (auto&& [k, v] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    // not physics: where outputs go, the limits, and how far the run goes (a restart may extend
    // it: MC's final_displacement, the dynamics' end_time) or how often it writes
    if (key == "output" || key == "limits" || key == "load.final_displacement" || key == "dynamics.end_time" ||
        key == "dynamics.csv_interval" || key == "dynamics.dump_interval")
      continue;
    if (auto* sub = v.as_table()) {
      canon(*sub, key, os);
      continue;
    }
    os << key << " = ";
    value_text(v, os);
    os << '\n';
  }
}
}  // namespace

std::map<std::string, int> key_lines(const toml::table& root) {
  std::map<std::string, int> out;
  walk(root, "", out);
  return out;
}

std::string canonical_physics(const toml::table& root) {
  std::ostringstream os;
  canon(root, "", os);
  return os.str();
}

std::string Deck::where(const std::string& key) const {
  int line = 0;
  for (std::string k = key; !k.empty();) {  // the key's line, else its section's
    if (auto it = lines.find(k); it != lines.end()) {
      line = it->second;
      break;
    }
    const auto dot = k.rfind('.');
    k = dot == std::string::npos ? std::string() : k.substr(0, dot);
  }
  return path + ":" + std::to_string(line) + ": " + key;
}

double memory_limit_bytes(const Limits& l) {
  if (l.max_memory_gib > 0) return l.max_memory_gib * 1073741824.0;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 16.0 * 1073741824.0;
  return 0.8 * static_cast<double>(pages) * static_cast<double>(page);
}

Estimate estimate(const Deck& d) {
  const auto& G = d.geometry;
  Estimate e;
  // The wall grid that build_specimen walks: rows over the specimen's extent normal to the rows
  // and columns along them (the rotated bounding box), plus the margin it adds; a notch splits
  // at most one row of bricks in two.
  const double al = G.angle_deg * std::numbers::pi / 180.0;
  const double ca = std::abs(std::cos(al)), sa = std::abs(std::sin(al));
  const double extent_u = ca * G.width + sa * G.height, extent_v = sa * G.width + ca * G.height;
  const double rows = extent_v / G.brick_height + 4, cols = extent_u / G.brick_width + 6;
  e.bricks = rows * cols + (G.notch_length > 0 ? cols : 0);
  const auto& L = d.load;
  const double smallest = L.adaptive ? std::min(L.min_step, L.initial_step) : L.initial_step;
  e.load_steps = L.path_length() / smallest;  // the whole path (a programme unloads and reloads)
  e.bytes = e.bricks * (bytes_per_brick + (d.dynamics.enabled && !d.dynamics.share_element_matrices
                                                ? unshared_bytes_per_brick(d.dynamics)
                                                : 0.0));
  return e;
}

double unshared_bytes_per_brick(const Dynamics& D) {
  switch (D.method) {
    case Dynamics::Method::bie: return 12288;
    case Dynamics::Method::ue: return 8192;
    case Dynamics::Method::be: break;
  }
  return 4096;
}

void check_time_steps(const Deck& d, double dt, const std::string& key) {
  const double steps = d.dynamics.end_time / dt;
  if (!(steps <= d.limits.max_time_steps))
    throw DeckError(d.where(d.lines.count(key) ? key : std::string("dynamics.end_time")) + ": end_time / dt = " +
                    fmt(d.dynamics.end_time) + " s / " + fmt(dt) + " s = " + fmt(steps) +
                    " time steps, above the limit of " + fmt(d.limits.max_time_steps) +
                    "; expected a larger dt or a shorter end_time, or raise [limits] max_time_steps if intended");
}

void check_limits(const Deck& d) {
  // the key as the deck wrote it: its Table 2.1 alias, or for a law the [mortar.bed]/[mortar.head] override
  static const std::map<std::string, std::vector<std::string>> spelled = {
      {"load.initial_step", {"load.InitialLoadStepSize"}}, {"load.min_step", {"load.MinLoadStepSize"}},
      {"solver.step", {"solver.InitialStepSize"}},         {"solver.min_step", {"solver.MinStepSize"}},
      {"solver.rot_step", {"solver.InitialRotSize"}},      {"solver.min_rot_step", {"solver.MinRotSize"}}};
  auto as_written = [&](const std::string& key) {
    if (d.lines.count(key)) return key;
    if (auto it = spelled.find(key); it != spelled.end())
      for (const auto& alt : it->second)
        if (d.lines.count(alt)) return alt;
    return key;
  };
  auto fail = [&](const std::string& key, const std::string& what) {
    throw DeckError(d.where(as_written(key)) + ": " + what);
  };
  // Magnitudes: lengths, stiffnesses and displacements are squared and multiplied in the model;
  // outside [1e-100, 1e100] (denormals included) that overflows or underflows.
  auto magnitude = [&](const std::string& key, double v) {
    if (v != 0 && (std::abs(v) < 1e-100 || std::abs(v) > 1e100))
      fail(key, "value " + fmt(v) + " outside [1e-100, 1e100]; expected a magnitude the model can square "
                "(choose the length unit so that sizes are near 1)");
  };
  const auto& G = d.geometry;
  magnitude("geometry.width", G.width);
  magnitude("geometry.height", G.height);
  magnitude("geometry.brick_width", G.brick_width);
  magnitude("geometry.brick_height", G.brick_height);
  if (d.load.programme.empty())
    magnitude("load.final_displacement", d.load.final_displacement);
  else
    magnitude("load.programme", d.load.max_displacement());
  magnitude("load.initial_step", d.load.initial_step);
  magnitude("load.min_step", d.load.min_step);
  for (const auto& [name, law] : {std::pair{"bed", &d.mortar.bed}, std::pair{"head", &d.mortar.head}})
    for (const auto& [k, v] : {std::pair{"k", law->k}, std::pair{"x1", law->x1}, std::pair{"x2", law->x2}}) {
      const std::string own = std::string("mortar.") + name + "." + k;
      magnitude(d.lines.count(own) ? own : std::string("mortar.") + k, v);
    }
  magnitude("solver.step", d.solver.step);
  magnitude("solver.min_step", d.solver.min_step);
  magnitude("solver.rot_step", d.solver.rot_step);
  magnitude("solver.min_rot_step", d.solver.min_rot_step);

  const Estimate e = estimate(d);
  const auto& Li = d.limits;
  const std::string size_key = G.width / G.brick_width >= G.height / G.brick_height ? "geometry.brick_width"
                                                                                  : "geometry.brick_height";
  if (!(e.bricks <= Li.max_bricks))
    fail(size_key, "the specimen needs about " + fmt(e.bricks) + " bricks (width / brick_width x height / "
                   "brick_height), above the limit of " + fmt(Li.max_bricks) +
                   "; expected fewer bricks, or raise [limits] max_bricks if intended");
  const double mem = memory_limit_bytes(Li);
  if (!(e.bytes <= mem))
    fail(size_key, "about " + fmt(e.bricks) + " bricks need about " + fmt(e.bytes / 1073741824.0) +
                   " GiB, above the limit of " + fmt(mem / 1073741824.0) + " GiB" +
                   (Li.max_memory_gib > 0 ? " ([limits] max_memory_gib)" : " (80 % of this machine's memory)") +
                   "; expected fewer bricks, or raise [limits] max_memory_gib if the machine has the memory");
  const std::string step_key = d.load.adaptive && d.load.min_step < d.load.initial_step ? "load.min_step"
                                                                                       : "load.initial_step";
  if (d.dynamics.enabled && d.dynamics.dt > 0) check_time_steps(d, d.dynamics.dt, "dynamics.dt");
  if (!(e.load_steps <= Li.max_load_steps))
    fail(step_key, "final_displacement / increment = " + fmt(e.load_steps) + " load steps, above the limit of " +
                   fmt(Li.max_load_steps) + "; expected a larger increment, or raise [limits] max_load_steps "
                   "if intended");
}

}  // namespace nacre::deck
