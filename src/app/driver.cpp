// Shared pieces of the run drivers (driver.hpp).
#include "driver.hpp"

#include <nacre/app/signals.hpp>

#include <nacre/core/format.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/names.hpp>

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

#ifndef NACRE_PLOT_SCRIPT
#define NACRE_PLOT_SCRIPT ""
#endif

namespace nacre::app {

RunSession::RunSession(const deck::Deck& d, bool quiet, bool tty, const Backend& backend)
    : d_(d), t0_(clock::now()), backend_(backend), log_(quiet ? nullptr : &std::cout),
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
  if (d_.output.charts && !run_charts(script, w.directory(), log_)) return 1;
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

int spawn_and_wait(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return kNotStarted;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return kNotStarted;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 128;
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

bool run_charts(const std::string& script_name, const std::filesystem::path& dir, std::ostream* log) {
  const char* env = std::getenv("NACRE_PLOT_SCRIPT");
  const std::filesystem::path mc_script = env ? env : NACRE_PLOT_SCRIPT;
  const std::filesystem::path script = mc_script.parent_path() / script_name;
  std::error_code ec;
  if (mc_script.empty() || !std::filesystem::exists(script, ec)) {
    std::cerr << "nacre: warning: plotting script " << script_name << " not found; charts skipped\n";
    return true;
  }
  // an argument vector, no shell: the output path is never interpreted
  std::vector<std::string> cmd{"python3", script.string(), dir.string()};
  if (!log) cmd.emplace_back("--quiet");  // the scripts print their findings (toughening ratio) unless quiet
  const int rc = spawn_and_wait(cmd);
  if (rc == kNotStarted) {
    std::cerr << "nacre: warning: python3 not found; charts skipped\n";
    return true;
  }
  if (rc != 0) {
    std::cerr << "nacre: error: chart script " << script.string() << " failed (status " << rc
              << "); the run's results are complete, no chart was left half-written\n";
    return false;
  }
  if (log)
    *log << "nacre: charts: "
         << (script_name == "nacre_sweep_plot.py"   ? "sweep.csv, sweep.png"
             : script_name == "nacre_bench_plot.py" ? "bench.png"
                                                    : "energy_force.png, crack.png, r_curve.png")
         << "\n";
  return true;
}

}  // namespace nacre::app
