// SPDX-License-Identifier: BSD-3-Clause
// `nacre sweep DECK --set KEY=V1,V2 [--set KEY=...] [-o OUT] [-j N]`: one run of the deck per
// combination of the values, each in OUT/<leaf>=<value>[_<leaf>=<value>...]/ from a deck written
// beside it (the deck with the keys set, OUT/<name>.toml), as a child nacre process (a crash or a
// bad value stops that run, not the sweep); with -j N, N children at once, each bound to a slice
// of the CPUs (an unbound child would share CPU 0 with the others under OMP_PROC_BIND).
// Resumable: a finished run is kept, an interrupted one restarted from its checkpoint. Then sweep.json (the runs and their outcomes) and the combined table and
// sweep.csv (one row per run, computed here), and the overlay charts (python -m nacre.charts.sweep:
// sweep.png; docs/fracture.md "Sweeps").
#include "driver.hpp"

#include <nacre/app/signals.hpp>
#include <nacre/core/format.hpp>
#include <nacre/deck/deck.hpp>
#include <nacre/fracture/r_curve.hpp>
#include <nacre/io/csv.hpp>
#include <nacre/io/atomic_file.hpp>
#include <nacre/io/names.hpp>
#include <nacre/par/comm.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <toml++/toml.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <sys/wait.h>
#include <charconv>
#include <cmath>
#include <limits>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace nacre::app {

namespace {

namespace fs = std::filesystem;

struct Axis {
  std::vector<std::string> path;    // dotted key split: {"geometry", "angle"}
  std::string key, leaf;            // "geometry.angle", "angle"
  std::vector<std::string> values;  // as typed
};

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

/// "geometry.angle=0,30,60" -> an axis; UsageError naming what is wrong.
Axis parse_set(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == arg.size())
    throw UsageError("--set " + arg + ": expected SECTION.KEY=V1,V2,... (e.g. geometry.angle=0,30,60,90)");
  Axis a;
  a.key = arg.substr(0, eq);
  a.path = split(a.key, '.');
  if (a.path.size() < 2)
    throw UsageError("--set " + arg + ": the key needs its section, e.g. geometry.angle or mortar.head.x2");
  for (const auto& p : a.path)
    if (p.empty()) throw UsageError("--set " + arg + ": an empty part in the key " + a.key);
  a.leaf = a.path.back();
  a.values = split(arg.substr(eq + 1), ',');
  for (const auto& v : a.values)
    if (v.empty()) throw UsageError("--set " + arg + ": an empty value in the list");
  return a;
}

/// The TOML value a typed text stands for: an integer, a real, a boolean or else a string.
void assign(toml::table& t, const std::string& key, const std::string& v) {
  std::int64_t i = 0;
  if (auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), i); ec == std::errc() && p == v.data() + v.size()) {
    t.insert_or_assign(key, i);
    return;
  }
  double x = 0;
  if (auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x); ec == std::errc() && p == v.data() + v.size()) {
    t.insert_or_assign(key, x);
    return;
  }
  if (v == "true" || v == "false") {
    t.insert_or_assign(key, v == "true");
    return;
  }
  t.insert_or_assign(key, v);
}

/// Set the dotted key in the deck (sections created where missing); UsageError if a part of the
/// path is a value, not a section.
void set_key(toml::table& deck, const Axis& a, const std::string& v) {
  toml::table* t = &deck;
  for (std::size_t k = 0; k + 1 < a.path.size(); ++k) {
    toml::node* n = t->get(a.path[k]);
    if (!n) {
      t->insert_or_assign(a.path[k], toml::table{});
      n = t->get(a.path[k]);
    }
    if (!n->is_table())
      throw UsageError("--set " + a.key + ": " + a.path[k] + " is a value in the deck, not a section");
    t = n->as_table();
  }
  assign(*t, a.path.back(), v);
}

}  // namespace

std::string deck_with_sets(const std::string& deck_path, const std::string& text, const std::vector<std::string>& sets) {
  toml::table t;
  try {
    t = toml::parse(text, deck_path);
  } catch (const toml::parse_error& e) {
    throw deck::DeckError(deck_path + ":" + std::to_string(e.source().begin.line) + ": (syntax): " +
                          std::string(e.description()));
  }
  std::string said;
  for (const auto& kv : sets) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == kv.size())
      throw UsageError("--set " + kv + ": expected SECTION.KEY=VALUE (e.g. geometry.angle=30)");
    Axis a = parse_set(kv.substr(0, eq + 1) + "x");  // the key's checks; the value is taken whole
    set_key(t, a, kv.substr(eq + 1));
    said += " " + kv;
  }
  std::ostringstream out;
  out << "# nacre: " << deck_path << " with --set" << said << "\n" << t << "\n";
  return out.str();
}

namespace {

/// A directory-name-safe form of a value (path separators and the like replaced).
std::string safe(const std::string& v) {
  std::string s;
  for (char c : v) s += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+') ? c : '_';
  return s;
}

/// What a run directory holds: "done" (summary.json exists: Monte Carlo writes it only at the
/// end; a dynamic run's status says done), "unstable" (a dynamic run that stopped at a failed
/// check: deterministic, so running it again would stop there again), else "" (to run or restart).
std::string outcome(const fs::path& dir) {
  std::ifstream in(dir / io::names::summary);
  if (!in) return "";
  try {
    const auto j = nlohmann::json::parse(in);
    if (!j.contains("status")) return "done";
    const auto s = j["status"].get<std::string>();
    return s == "done" || s == "unstable" ? s : "";
  } catch (const nlohmann::json::exception&) {
    return "";
  }
}

/// \brief A number as sweep.csv spells it: the shortest text that reads back to the same double.
std::string shortest(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[32];
  const auto [p, ec] = std::to_chars(b, b + sizeof b, v);
  return ec == std::errc() ? std::string(b, p) : format_real(v, 17);
}

/// \brief One row of sweep.csv (name -> text, in column order) for one child run of sweep.json:
/// its name, exit code and swept values; then, when it wrote a summary, its solver, status and
/// size, the peak reaction and where it fell, the final ruptured count, for Monte Carlo the
/// final energy, the quadratic E = c D^2 fitted through the first fifth of the steps (at least 2)
/// and the critical displacement D_c (the first step whose energy falls 5 % below it; the
/// dissertation's Fig. 2.8b), the R-curve's toughening ratio, and the crack's reading.
std::vector<std::pair<std::string, std::string>> sweep_row(const nlohmann::ordered_json& run) {
  std::vector<std::pair<std::string, std::string>> r;
  const auto text = [](const nlohmann::ordered_json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_number_float()) return shortest(v.get<double>());
    if (v.is_null()) return std::string("nan");
    return v.dump();
  };
  r.emplace_back("name", run["name"].get<std::string>());
  r.emplace_back("exit", std::to_string(run["exit"].get<int>()));
  for (const auto& [k, v] : run["values"].items()) r.emplace_back(k, text(v));
  const fs::path dir = run["directory"].get<std::string>();
  nlohmann::ordered_json s;
  {
    std::ifstream in(dir / io::names::summary);
    if (!in) return r;
    s = nlohmann::ordered_json::parse(in, nullptr, false);
    if (s.is_discarded()) return r;
  }
  const nlohmann::ordered_json c = s.value("crack", nlohmann::ordered_json::object());
  r.emplace_back("solver", s.value("solver", std::string()));
  r.emplace_back("status", s.value("status", std::string("done")));
  r.emplace_back("bricks", s.contains("bricks") ? text(s["bricks"]) : std::string());
  const fs::path table = dir / (s.value("solver", std::string()) == "dynamics" ? io::names::dyn_table : io::names::mc_table);
  std::ifstream in(table);
  std::stringstream ss;
  ss << in.rdbuf();
  const io::CsvTable t = io::parse_csv(ss.str(), table.string());
  if (!t.rows.empty()) {
    const std::vector<double> D = t.numbers("displacement"), F = t.numbers("reaction");
    std::size_t k = 0;
    for (std::size_t i = 1; i < F.size(); ++i)
      if (F[i] > F[k]) k = i;
    r.emplace_back("peak_reaction", shortest(F[k]));
    r.emplace_back("displacement_at_peak", shortest(D[k]));
    r.emplace_back("ruptured", t.rows.back()[*t.column("ruptured")]);
    if (t.column("energy")) {  // Monte Carlo: the total energy and Fig. 2.8b's critical displacement
      const std::vector<double> E = t.numbers("energy");
      const std::size_t n0 = std::min(E.size(), std::max<std::size_t>(2, E.size() / 5));
      double num = 0, den = 0;
      for (std::size_t i = 0; i < n0; ++i) num += D[i] * D[i] * E[i], den += D[i] * D[i] * D[i] * D[i];
      const double q = num / std::max(den, 1e-300);
      double Dc = std::numeric_limits<double>::quiet_NaN();
      for (std::size_t i = 0; i < E.size(); ++i)
        if (E[i] < 0.95 * q * D[i] * D[i]) {
          Dc = D[i];
          break;
        }
      r.emplace_back("final_energy", shortest(E.back()));
      r.emplace_back("quadratic_coefficient", shortest(q));
      r.emplace_back("critical_displacement", shortest(Dc));
    }
    if (c.contains("toughening_ratio")) {  // written by the run (null: fewer than 2 R-curve points)
      r.emplace_back("toughening_ratio", text(c["toughening_ratio"]));
    } else if (c.contains("bed_work_of_fracture") && t.column("crack_extension") && t.column("fracture_energy")) {
      // a run of a nacre before 1.0 kept by the sweep: its R-curve from its table
      const auto rc = fracture::r_curve(t.numbers("crack_extension"), t.numbers("fracture_energy"),
                                        c["thickness"].get<double>(), c["bed_work_of_fracture"].get<double>());
      r.emplace_back("toughening_ratio", shortest(rc.toughening_ratio));
    }
  }
  for (const char* k : {"extension", "path_length", "deflection", "interfaces", "bed", "head"})
    if (c.contains(k)) r.emplace_back(std::string("crack_") + k, text(c[k]));
  if (c.contains("fracture_energy")) r.emplace_back("fracture_energy", text(c["fracture_energy"]));
  return r;
}

/// \brief sweep.csv: one row per run of sweep.json, the columns the union of the rows' in order
/// of first appearance (a run that wrote no summary leaves its later columns empty).
std::string sweep_csv(const nlohmann::ordered_json& sweep) {
  std::vector<std::vector<std::pair<std::string, std::string>>> rows;
  std::vector<std::string> columns;
  for (const auto& run : sweep["runs"]) {
    rows.push_back(sweep_row(run));
    for (const auto& [k, v] : rows.back())
      if (std::find(columns.begin(), columns.end(), k) == columns.end()) columns.push_back(k);
  }
  std::string out;
  for (std::size_t k = 0; k < columns.size(); ++k) out += (k ? "," : "") + columns[k];
  out += "\n";
  for (const auto& r : rows) {
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const auto it = std::find_if(r.begin(), r.end(), [&](const auto& p) { return p.first == columns[k]; });
      out += (k ? "," : "") + (it == r.end() ? std::string() : it->second);
    }
    out += "\n";
  }
  return out;
}

/// \brief The node's CPUs (par::node_cpu_ids) in `n` slices, one per run at once: contiguous
/// slices of at least one CPU; with more runs than CPUs, the CPUs are dealt round. Every child gets
/// its slice explicitly: it would otherwise inherit this process's mask, which an OpenMP runtime
/// with OMP_PLACES or OMP_PROC_BIND set has narrowed to one CPU as the program started.
std::vector<std::vector<int>> cpu_slots(std::size_t n) {
  const std::vector<int> cpus = par::node_cpu_ids();
  if (cpus.empty()) return std::vector<std::vector<int>>(n);  // unknown: no binding
  std::vector<std::vector<int>> slots(n);
  if (cpus.size() >= n) {
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t c = k * cpus.size() / n; c < (k + 1) * cpus.size() / n; ++c) slots[k].push_back(cpus[c]);
  } else {
    for (std::size_t k = 0; k < n; ++k) slots[k].push_back(cpus[k % cpus.size()]);
  }
  return slots;
}

/// \brief CPUs as a list with ranges: "0-3,8".
std::string cpu_text(const std::vector<int>& cpus) {
  std::string t;
  for (std::size_t k = 0; k < cpus.size();) {
    std::size_t e = k;
    while (e + 1 < cpus.size() && cpus[e + 1] == cpus[e] + 1) ++e;
    t += (t.empty() ? "" : ",") + std::to_string(cpus[k]) + (e > k ? "-" + std::to_string(cpus[e]) : "");
    k = e + 1;
  }
  return t;
}

}  // namespace

int sweep_main(int argc, char* argv[]) {
  std::vector<std::string> sets, pass;  // pass: --kokkos-* flags for every run
  bool list_only = false;
  std::vector<char*> app_args{argv[0]};
  for (int i = 2; i < argc; ++i) {  // argv[1] is "sweep"
    if (std::string_view(argv[i]).starts_with("--kokkos-"))
      pass.emplace_back(argv[i]);
    else
      app_args.push_back(argv[i]);
  }
  CLI::App cli{"nacre sweep: one run of a deck per combination of --set values (docs/fracture.md \"Sweeps\")",
               "nacre sweep"};
  std::string deck_path, out;
  bool quiet = false;
  std::size_t jobs = 1;
  cli.add_option("deck", deck_path, "TOML input deck")->required()->check(CLI::ExistingFile);
  cli.add_option("--set", sets, "SECTION.KEY=V1,V2,... (repeatable: every combination is run)")->required();
  cli.add_option("-o,--output", out, "sweep directory (default: the deck's [output] directory + \"_sweep\")");
  cli.add_flag("-q,--quiet", quiet, "no log lines from the runs");
  cli.add_option("-j,--jobs", jobs,
                 "runs at once (default 1), each on a slice of the CPUs with as many threads, its log lines in "
                 "its log.txt")
      ->check(CLI::Range(std::size_t(1), std::size_t(65536)));
  cli.add_flag("--list", list_only,
               "write each run's deck and print one command per run that is still to do (for a "
               "scheduler's job array), then exit; run the sweep again afterwards for sweep.csv");
  std::vector<Axis> axes;
  if (const int rc = parse_command_line(cli, app_args,
                                        [&] {
                                          for (const auto& s : sets) axes.push_back(parse_set(s));
                                        });
      rc >= 0)
    return rc;
  toml::table base;
  try {
    base = toml::parse_file(deck_path);
  } catch (const toml::parse_error& e) {
    std::cerr << "nacre: error: " << deck_path << ":" << e.source().begin.line << ": " << e.description() << "\n";
    return 2;
  }
  if (out.empty()) {
    const auto* dir = base.at_path("output.directory").as_string();
    out = (dir ? dir->get() : std::string("out/" + fs::path(deck_path).stem().string())) + "_sweep";
  }
  // the combinations, the first axis slowest
  std::size_t total = 1;
  for (const auto& a : axes) total *= a.values.size();
  struct Run {
    std::vector<std::string> values;
    std::string name;
  };
  std::vector<Run> runs;
  for (std::size_t c = 0; c < total; ++c) {
    Run r;
    std::size_t rest = c;
    std::vector<std::size_t> idx(axes.size());
    for (std::size_t k = axes.size(); k-- > 0;) idx[k] = rest % axes[k].values.size(), rest /= axes[k].values.size();
    for (std::size_t k = 0; k < axes.size(); ++k) {
      // a leaf name shared by two axes (mortar.x2, mortar.head.x2) is written in full
      bool shared = false;
      for (std::size_t o = 0; o < axes.size(); ++o) shared |= o != k && axes[o].leaf == axes[k].leaf;
      r.values.push_back(axes[k].values[idx[k]]);
      r.name += (k ? "_" : "") + (shared ? axes[k].key : axes[k].leaf) + "=" + safe(axes[k].values[idx[k]]);
    }
    runs.push_back(r);
  }
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    std::cerr << "nacre: error: cannot create " << out << ": " << ec.message() << "\n";
    return 1;
  }
  const std::string self = fs::read_symlink("/proc/self/exe", ec).string();
  const std::string exe = ec || self.empty() ? std::string(argv[0]) : self;
  if (!quiet && !list_only)
    std::cout << "nacre: sweep of " << deck_path << ": " << runs.size() << " runs into " << out << "/\n";
  nlohmann::ordered_json summary;
  summary["deck"] = deck_path;
  for (const auto& a : axes) summary["keys"].push_back(a.key);
  if (jobs > 1) summary["jobs"] = jobs;
  // the runs in order: each one's deck written, finished ones kept, the others' commands made
  struct Job {
    std::size_t run;
    std::vector<std::string> cmd;
  };
  std::vector<Job> todo;
  std::vector<int> exits(runs.size(), 0);
  std::vector<std::string> hows(runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto& r = runs[i];
    const fs::path dir = fs::path(out) / r.name, deck = fs::path(out) / (r.name + ".toml");
    toml::table t = base;
    try {
      for (std::size_t k = 0; k < axes.size(); ++k) set_key(t, axes[k], r.values[k]);
    } catch (const UsageError& e) {
      std::cerr << "nacre: error: " << e.what() << "\n";
      return 2;
    }
    std::ostringstream text;
    text << "# nacre sweep: " << deck_path << " with " << r.name << "\n" << t << "\n";
    try {
      io::write_file_atomic(deck, text.str());
    } catch (const io::WriteError& e) {
      std::cerr << "nacre: error: " << e.what() << "\n";
      return 1;
    }
    if (const std::string o = outcome(dir); o == "done" || o == "unstable") {
      hows[i] = o == "done" ? "kept (finished before)" : "kept (stopped unstable before: exit 3)";
      exits[i] = o == "done" ? 0 : 3;
      if (!quiet && !list_only)
        std::cout << "nacre: sweep " << r.name << ": " << hows[i] << (exits[i] ? ", exit 3" : "") << "\n";
      continue;
    }
    std::vector<std::string> cmd{exe, deck.string(), "-o", dir.string()};
    if (const fs::path cp = dir / io::names::checkpoint; fs::exists(cp)) {
      cmd.insert(cmd.end(), {"--restart", cp.string()});
      hows[i] = "restarted from its checkpoint";
    } else {
      cmd.emplace_back("--overwrite");
      hows[i] = "run";
    }
    // several at once: each run's log lines go to its log.txt alone (warnings and errors still here)
    if (quiet || jobs > 1) cmd.emplace_back("-q");
    cmd.insert(cmd.end(), pass.begin(), pass.end());
    if (list_only) {  // one shell-quoted command line per run still to do
      for (std::size_t k = 0; k < cmd.size(); ++k) {
        std::string q = "'";
        for (char c : cmd[k]) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
        std::cout << (k ? " " : "") << q << "'";
      }
      std::cout << "\n";
      continue;
    }
    todo.push_back({i, cmd});
  }
  if (list_only) return 0;
  // --jobs N: N runs at once, each on CPUs of its own (a slice of the node's CPUs, its threads as
  // many unless --kokkos-num-threads was given): runs that shared CPUs would wait for each other
  const std::vector<std::vector<int>> slots = cpu_slots(jobs);
  const bool threads_given = std::any_of(pass.begin(), pass.end(), [](const std::string& a) {
    return a.starts_with("--kokkos-num-threads") || a.starts_with("--kokkos-threads");
  });
  int failed = 0;
  // Ctrl-C reaches the runs in progress too (they checkpoint and exit 130); a SIGTERM sent to the
  // sweep alone lets the runs in progress finish; either way no further run starts
  SignalGuard signals;
  struct Running {
    int pid;
    std::size_t slot, job;  // slots[slot] holds its CPUs, todo[job] its run
  };
  std::vector<Running> running;
  int stop_rc = 0;
  std::string stopped_in;
  const auto stopping = [&] { return stop_rc != 0 || pending_signal() != 0; };
  const auto finish = [&](std::size_t j, int rc) {
    const std::size_t i = todo[j].run;
    exits[i] = rc;
    if (rc == 130 || rc == 143 || pending_signal() != 0) {
      if (!stop_rc) stop_rc = rc == 130 || rc == 143 ? rc : 128 + pending_signal();
      stopped_in += (stopped_in.empty() ? "" : ", ") + runs[i].name;
    }
    if (!quiet && stop_rc == 0)
      std::cout << "nacre: sweep " << runs[i].name << ": " << hows[i] << (rc ? ", exit " + std::to_string(rc) : std::string())
                << "\n" << std::flush;
  };
  for (std::size_t next = 0; (next < todo.size() && !stopping()) || !running.empty();) {
    while (next < todo.size() && running.size() < slots.size() && !stopping()) {
      std::size_t slot = 0;  // the first slot no run holds
      while (std::any_of(running.begin(), running.end(), [&](const Running& r) { return r.slot == slot; })) ++slot;
      std::vector<std::string> cmd = todo[next].cmd;
      const std::vector<int>& cpus = slots[slot];
      if (jobs > 1 && !threads_given)
        cmd.push_back("--kokkos-num-threads=" + std::to_string(std::max<std::size_t>(1, cpus.size())));
      const std::size_t i = todo[next].run;
      if (!quiet) {
        std::cout << "nacre: sweep run " << i + 1 << "/" << runs.size() << ": " << runs[i].name;
        if (jobs > 1 && !cpus.empty()) std::cout << " (CPUs " << cpu_text(cpus) << ", log in " << runs[i].name << "/log.txt)";
        std::cout << "\n" << std::flush;
      }
      const int pid = spawn_start(cmd, {}, cpus);
      if (pid == kNotStarted)
        finish(next, kNotStarted);
      else
        running.push_back({pid, slot, next});
      ++next;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      std::cerr << "nacre: error: waiting for the sweep's runs: " << std::strerror(errno) << "\n";
      return 1;
    }
    const auto r = std::find_if(running.begin(), running.end(), [&](const Running& x) { return x.pid == pid; });
    if (r == running.end()) continue;
    finish(r->job, exit_code(status));
    running.erase(r);
  }
  if (stopping()) {
    std::cerr << "nacre: sweep stopped by a signal" << (stopped_in.empty() ? "" : " during " + stopped_in)
              << "; run the same command again to resume\n";
    return stop_rc ? stop_rc : 128 + pending_signal();
  }
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto& r = runs[i];
    if (exits[i] != 0) ++failed;
    nlohmann::ordered_json e;
    e["name"] = r.name;
    e["directory"] = (fs::path(out) / r.name).string();
    for (std::size_t k = 0; k < axes.size(); ++k) e["values"][axes[k].key] = r.values[k];
    e["exit"] = exits[i];
    e["how"] = hows[i];
    list.push_back(e);
  }
  summary["runs"] = list;
  try {
    io::write_file_atomic(fs::path(out) / "sweep.json", summary.dump(2) + "\n");
    io::write_file_atomic(fs::path(out) / "sweep.csv", sweep_csv(summary));
  } catch (const io::WriteError& e) {
    std::cerr << "nacre: error: " << e.what() << "\n";
    return 1;
  } catch (const std::runtime_error& e) {  // a child's table that does not read back
    std::cerr << "nacre: error: sweep.csv: " << e.what() << "\n";
    return 1;
  }
  if (!quiet) std::cout << "nacre: sweep: " << out << "/sweep.json, " << out << "/sweep.csv\n";
  run_charts("sweep", out, quiet ? nullptr : &std::cout);  // a missing chart is a warning: sweep.csv is written
  if (failed) {
    std::cerr << "nacre: sweep: " << failed << " of " << runs.size() << " runs failed (sweep.json names them)\n";
    return 1;
  }
  return 0;
}

}  // namespace nacre::app
