// SPDX-License-Identifier: BSD-3-Clause
// Shared pieces of the run drivers (driver.hpp).
#include "driver.hpp"
#include "run_log.hpp"

#include <nacre/app/signals.hpp>

#include <nacre/core/format.hpp>
#include <nacre/fracture/r_curve.hpp>
#include <nacre/io/atomic_file.hpp>
#include <nacre/io/csv.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/names.hpp>

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sched.h>
#include <spawn.h>
#include <unistd.h>
#include <string_view>
#include <sys/wait.h>

extern char** environ;

#ifndef NACRE_SOURCE_PYTHON_DIR
#define NACRE_SOURCE_PYTHON_DIR ""
#endif

namespace nacre::app {

RunSession::RunSession(const deck::Deck& d, bool quiet, bool tty, const Backend& backend)
    : d_(d), t0_(clock::now()), backend_(backend),
      log_(!quiet ? &std::cout : RunLog::active() ? &RunLog::active()->file_only() : nullptr),
      progress_(tty && d.output.progress && !quiet), heartbeat_(!tty && !quiet && d.output.heartbeat > 0) {}

double RunSession::elapsed() const { return std::chrono::duration<double>(clock::now() - t0_).count(); }

void RunSession::log_start(const std::string& what) const {
  if (log_)
    *log_ << "nacre: " << d_.path << ": " << what << ", " << backend_.kokkos_name() << " with "
          << backend_.concurrency() << " threads\n";
}

io::RunWriter RunSession::open_writer(const io::RunWriter::Options& o, const geometry::Specimen& s,
                                      const geometry::Interfaces& f, const std::string& restart,
                                      long restart_step) const {
  std::optional<io::RunWriter::Resume> resume;
  if (!restart.empty()) {
    resume = io::RunWriter::Resume{restart_step, std::filesystem::path(restart).parent_path()};
    if (resume->source_directory.empty()) resume->source_directory = ".";
  }
  io::RunWriter w(o, s, f, resume);
  io::write_file_atomic(w.directory() / io::names::deck_copy, d_.text);  // the deck this run ran
  if (RunLog* l = RunLog::active()) {  // and its log: a restart into another directory continues a copy
    namespace fs = std::filesystem;
    std::error_code ec;
    if (resume && !fs::exists(w.directory() / io::names::log) && fs::exists(resume->source_directory / io::names::log))
      fs::copy_file(resume->source_directory / io::names::log, w.directory() / io::names::log, ec);
    l->attach(w.directory(), resume.has_value());
  }
  if (log_ && w.stale_temporaries_removed() > 0)
    *log_ << "nacre: removed " << w.stale_temporaries_removed() << " stale temporary file(s) of a killed run in "
          << w.directory().string() << "/\n";
  return w;
}

int RunSession::stopped_by_signal(int sig, const std::string& after, const io::RunWriter& w) const {
  std::cerr << "nacre: " << signal_name(sig) << " received: stopped after " << after << "; checkpoint written to "
            << w.checkpoint_path().string() << "\nnacre: continue with: nacre " << d_.path << " -o "
            << w.directory().string() << " --restart " << w.checkpoint_path().string() << "\n";
  return 128 + sig;
}

int RunSession::complete(const io::RunWriter& w, const std::string& files, const std::string& script) const {
  if (log_) *log_ << "nacre: results in " << w.directory().string() << "/ (" << files << ")\n";
  if (const int sig = pending_signal()) {  // in the last stretch: the results are complete
    std::cerr << "nacre: " << signal_name(sig) << " received during the last stretch: results complete, charts skipped\n";
    return 128 + sig;
  }
  if (d_.output.charts) run_charts(script, w.directory(), log_);  // a missing chart is a warning
  return 0;
}

int parse_command_line(CLI::App& cli, std::vector<char*>& args, const std::function<void()>& then) {
  try {
    cli.parse(static_cast<int>(args.size()), args.data());
    then();
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? 0 : 2;
  } catch (const UsageError& e) {
    std::cerr << "nacre: error: " << e.what() << "\n";
    return 2;
  }
  return -1;
}

int spawn_start(const std::vector<std::string>& argv, const std::vector<std::string>& env_set,
                const std::vector<int>& cpus) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // this process's environment, with each "NAME=value" of env_set replacing its NAME
  std::vector<char*> env;
  for (char** e = environ; *e; ++e) {
    const std::string_view kv(*e);
    bool replaced = false;
    for (const auto& s : env_set) replaced = replaced || kv.substr(0, kv.find('=') + 1) == s.substr(0, s.find('=') + 1);
    if (!replaced) env.push_back(*e);
  }
  for (const auto& s : env_set) env.push_back(const_cast<char*>(s.c_str()));
  env.push_back(nullptr);
  if (cpus.empty()) {
    pid_t pid = 0;
    return posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), env.data()) == 0 ? static_cast<int>(pid)
                                                                                        : kNotStarted;
  }
  // on CPUs of its own: the mask is set between fork and exec (posix_spawn has no attribute for
  // it); only async-signal-safe calls in the child
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus) CPU_SET(c, &set);
  const pid_t pid = fork();
  if (pid < 0) return kNotStarted;
  if (pid == 0) {
    sched_setaffinity(0, sizeof set, &set);
    execvpe(args[0], args.data(), env.data());
    _exit(127);
  }
  return static_cast<int>(pid);
}

int exit_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 128;
}

int spawn_and_wait(const std::vector<std::string>& argv, const std::vector<std::string>& env_set) {
  const int pid = spawn_start(argv, env_set, {});
  if (pid == kNotStarted) return kNotStarted;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return kNotStarted;
  return exit_code(status);
}

namespace {
std::string g(double v) { return format_real(v, 6); }

/// \brief "step 12, D = 0.01 of 0.02" when the checkpoint is of an unfinished run, else "".
std::string unfinished(const io::Checkpoint& c) {
  const auto step = c.integers.find("step");
  const std::string at = "step " + (step == c.integers.end() ? std::string("?") : std::to_string(step->second));
  const auto kind = c.strings.find("kind");
  if (kind != c.strings.end() && kind->second == "dynamics") {
    const auto t = c.reals.find("time"), end = c.reals.find("end_time");
    if (t == c.reals.end()) return "";
    if (end == c.reals.end()) return at + ", t = " + g(t->second) + " s";  // an older nacre's: end unknown
    if (!(t->second < end->second * (1 - 1e-12))) return "";
    return at + ", t = " + g(t->second) + " s of " + g(end->second) + " s";
  }
  const auto D = c.reals.find("displacement"), F = c.reals.find("final_displacement");
  const auto leg = c.integers.find("leg"), legs = c.integers.find("legs");
  if (leg != c.integers.end() && legs != c.integers.end() && D != c.reals.end()) {  // a load programme's legs
    if (leg->second >= legs->second) return "";
    return at + ", D = " + g(D->second) + " on leg " + std::to_string(leg->second + 1) + " of " +
           std::to_string(legs->second);
  }
  if (D == c.reals.end() || F == c.reals.end() || !(D->second < F->second * (1 - 1e-12))) return "";
  return at + ", D = " + g(D->second) + " of " + g(F->second);
}
}  // namespace

void check_not_overwriting(const deck::Deck& d, const std::string& restart, bool overwrite) {
  if (overwrite) return;
  const std::filesystem::path dir(d.output.directory), cpath = dir / io::names::checkpoint;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(cpath, ec)) return;
  if (!restart.empty()) {
    std::filesystem::path src = std::filesystem::path(restart).parent_path();
    if (src.empty()) src = ".";
    if (std::filesystem::equivalent(src, dir, ec) && !ec) return;  // continuing in place
  }
  io::Checkpoint c;
  try {
    c = io::read_checkpoint(cpath);
  } catch (const io::CheckpointError&) {
    return;
  }
  const std::string where = unfinished(c);
  if (where.empty()) return;
  throw UsageError(cpath.string() + " holds the checkpoint of an unfinished run (" + where +
                   "), which this run would remove; continue it with --restart " + cpath.string() +
                   ", write elsewhere with -o, or pass --overwrite to start afresh");
}

double write_r_curve(const io::RunWriter& w, double thickness, double gc, std::ostream* log) {
  const io::CsvTable t = io::parse_csv(w.table(), (w.directory() / w.table_name()).string());
  const fracture::RCurve c =
      fracture::r_curve(t.numbers("crack_extension"), t.numbers("fracture_energy"), thickness, gc);
  io::write_file_atomic(w.directory() / io::names::r_curve, fracture::r_curve_csv(c));
  if (log)
    *log << "nacre: R-curve: " << c.points.size() << " points, toughening ratio "
         << (std::isfinite(c.toughening_ratio) ? format_real(c.toughening_ratio, 4)
                                               : std::string("n/a (the crack grew at fewer than 2 rows)"))
         << " (r_curve.csv)\n";
  return c.toughening_ratio;
}

std::filesystem::path python_dir() {
  std::error_code ec;
  const auto has_package = [&ec](const std::filesystem::path& p) {
    return !p.empty() && std::filesystem::is_regular_file(p / "nacre" / "__init__.py", ec);
  };
  if (const char* env = std::getenv("NACRE_PYTHON_DIR"); env && *env) return env;  // as asked, even if wrong
  // an installed nacre: PREFIX/bin/nacre beside PREFIX/share/nacre/python
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "nacre" / "python";
    if (has_package(installed)) return installed;
  }
  const std::filesystem::path source = NACRE_SOURCE_PYTHON_DIR;  // a build tree: the source's python/
  if (has_package(source)) return source;
  return {};
}

bool run_charts(const std::string& chart, const std::filesystem::path& dir, std::ostream* log) {
  const std::filesystem::path py = python_dir();
  std::error_code ec;
  if (py.empty() || !std::filesystem::is_regular_file(py / "nacre" / "charts" / (chart + ".py"), ec)) {
    std::cerr << "nacre: warning: the chart module nacre.charts." << chart << " was not found (set NACRE_PYTHON_DIR "
              << "to the directory that holds the nacre Python package); charts skipped, the results are complete\n";
    return false;
  }
  // an argument vector, no shell: the output path is never interpreted
  std::vector<std::string> cmd{"python3", "-m", "nacre.charts." + chart, dir.string()};
  if (log != &std::cout) cmd.emplace_back("--quiet");  // none, or a quiet run's log file: the module prints nothing
  const char* old = std::getenv("PYTHONPATH");
  const std::string path = "PYTHONPATH=" + py.string() + (old && *old ? ":" + std::string(old) : std::string());
  const int rc = spawn_and_wait(cmd, {path});
  if (rc == kNotStarted) {
    std::cerr << "nacre: warning: python3 not found; charts skipped, the results are complete\n";
    return false;
  }
  if (rc != 0) {
    std::cerr << "nacre: warning: the charts (python3 -m nacre.charts." << chart << ") failed with status " << rc
              << "; the results are complete, no chart was left half-written\n";
    return false;
  }
  if (log)
    *log << "nacre: charts: "
         << (chart == "sweep"   ? "sweep.png"
             : chart == "bench" ? "bench.png"
                               : "energy_force.png, crack.png, r_curve.png")
         << "\n";
  return true;
}

}  // namespace nacre::app
