// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the Monte Carlo and the dynamics drivers share around their run loops: the overwrite
// guard of an unfinished run, the plotting scripts (spawned, never through a shell), and the
// messages of a stopped run. One rule in one place, so both families behave alike.
#include <nacre/core/backend.hpp>
#include <nacre/deck/deck.hpp>
#include <nacre/io/results.hpp>

#include <Kokkos_Core.hpp>

#include <filesystem>
#include <chrono>
#include <functional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace nacre::app {

/// \brief A bad command line or a refused request before anything ran (exit 2).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// \brief Parse `args` (argv[0] first) into `cli`, then run `then` (further checks that throw
/// UsageError). Returns -1 when both passed, else the exit code with its message printed: 0 for
/// --help, 2 for a bad command line. Both `nacre DECK` and `nacre sweep` parse through it.
int parse_command_line(CLI::App& cli, std::vector<char*>& args, const std::function<void()>& then);

/// \brief spawn_and_wait's result when argv[0] could not be started (not found on PATH).
inline constexpr int kNotStarted = -1;

/// \brief Run argv[0] with arguments, no shell (nothing in a path is ever interpreted), in this
/// process's environment with each "NAME=value" of `env_set` set; returns the exit status,
/// 128 + signal when it was killed, or kNotStarted.
int spawn_and_wait(const std::vector<std::string>& argv, const std::vector<std::string>& env_set = {});

/// \brief spawn_and_wait without the wait: the child's pid, or kNotStarted; on the CPUs `cpus`
/// (its affinity mask, inherited by the threads it starts) when not empty.
int spawn_start(const std::vector<std::string>& argv, const std::vector<std::string>& env_set,
                const std::vector<int>& cpus);

/// \brief A waitpid status as an exit code: the child's, or 128 + the signal that killed it.
int exit_code(int status);

/// \brief The directory that holds the nacre Python package (nacre/__init__.py): NACRE_PYTHON_DIR
/// when set; else PREFIX/share/nacre/python beside an installed PREFIX/bin/nacre; else the source
/// tree's python/ (a build tree); empty when none is found.
[[nodiscard]] std::filesystem::path python_dir();

/// \brief A new run (or a restart into another directory) sets up its output directory afresh:
/// refuse (UsageError) when that would remove the checkpoint of an unfinished run of either
/// family, unless `overwrite`. A finished run, or a checkpoint that could not be restarted
/// anyway, is replaced.
void check_not_overwriting(const deck::Deck& d, const std::string& restart, bool overwrite);

/// \brief Draws the charts of `dir` with `python3 -m nacre.charts.CHART` (mc, dyn, sweep, bench;
/// the package found by python_dir()). Charts only draw: every data product is written before
/// (r_curve.csv, sweep.csv, summary.json). Each chart goes to a temporary and is renamed, so a
/// failure leaves no truncated PNG. A missing package or python3, or a failed chart, is a warning
/// naming what is missing (returns false); the caller's exit code stays 0.
bool run_charts(const std::string& chart, const std::filesystem::path& dir, std::ostream* log);

/// \brief The R-curve of the run's table so far (fracture/r_curve.hpp; the crack_extension and
/// fracture_energy columns of either family), written to r_curve.csv (atomically); `log` gets
/// one line with the toughening ratio. Returns the ratio: NaN with fewer than 2 points.
double write_r_curve(const io::RunWriter& w, double thickness, double gc, std::ostream* log);

/// \brief What every run's driver (Monte Carlo: run.cpp, dynamics: run_dynamics.cpp) shares around
/// its loop: the run's execution-space instance and clock, the log, whether a live progress line
/// (on a terminal) or a heartbeat line (off one, every [output] heartbeat s) is shown, the output
/// directory's opening (fresh or resumed, stale temporaries reported), and the two endings that
/// are not a failure: stopped by a signal (a checkpoint to continue from) and complete (charts).
class RunSession {
public:
  RunSession(const deck::Deck& d, bool quiet, bool tty, const Backend& backend = {});

  [[nodiscard]] double elapsed() const;
  [[nodiscard]] std::ostream* log() const { return log_; }
  /// \brief The run's backend (`--backend`; the default space unless asked).
  [[nodiscard]] const Backend& backend() const { return backend_; }
  [[nodiscard]] bool progress() const { return progress_; }    ///< a live line on stderr
  [[nodiscard]] bool heartbeat() const { return heartbeat_; }  ///< plain log lines within a long stretch
  /// \brief A heartbeat line is due (the last line is [output] heartbeat seconds old).
  [[nodiscard]] bool heartbeat_due() const { return heartbeat_ && elapsed() - last_line_ >= d_.output.heartbeat; }
  /// \brief A progress line is due (at most 4 per second, or `now` for the end of a step).
  [[nodiscard]] bool progress_due(bool now) const { return progress_ && (now || elapsed() - last_line_ >= 0.25); }
  /// \brief The time of the last log or progress line, for the two throttles above.
  void line_written() { last_line_ = elapsed(); }
  /// \brief "nacre: DECK: N bricks, M interfaces..., <space> with T threads" (what = the middle).
  void log_start(const std::string& what) const;

  /// \brief The output directory: set up afresh, or (restart non-empty) resumed after
  /// `restart_step` from the checkpoint's directory; stale temporaries of a killed run are reported.
  [[nodiscard]] io::RunWriter open_writer(const io::RunWriter::Options& o, const geometry::Specimen& s,
                                          const geometry::Interfaces& f, const std::string& restart,
                                          long restart_step) const;
  /// \brief A run stopped by signal `sig` after `after` ("step 12 (t = ...)"): the message with the
  /// command that continues it; returns 128 + sig.
  int stopped_by_signal(int sig, const std::string& after, const io::RunWriter& w) const;
  /// \brief A complete run: its results line, then the charts (skipped when a signal arrived in
  /// the last stretch: 128 + sig); 0, or 1 when the charts failed.
  int complete(const io::RunWriter& w, const std::string& files, const std::string& script) const;

private:
  using clock = std::chrono::steady_clock;
  const deck::Deck& d_;
  const clock::time_point t0_;
  const Backend backend_;  ///< every kernel of the run goes to this instance
  std::ostream* log_;
  bool progress_, heartbeat_;
  double last_line_ = 0;
};

/// \brief The deck `text` (read from `deck_path`) with each "SECTION.KEY=VALUE" of `sets` set
/// (`nacre run DECK --set ...`; the value typed as in a sweep: integer, real, boolean or string),
/// as TOML text whose first line records the settings. UsageError for a malformed setting,
/// deck::DeckError for a deck that is not TOML; the result is validated as any deck.
[[nodiscard]] std::string deck_with_sets(const std::string& deck_path, const std::string& text,
                                         const std::vector<std::string>& sets);

/// \brief `nacre sweep DECK --set KEY=V1,V2 ...` (argv[1] == "sweep"; src/app/sweep.cpp): one run
/// per combination of the values, resumable, then sweep.json, sweep.csv and sweep.png.
int sweep_main(int argc, char* argv[]);

/// \brief `nacre bench DECK [--backends a,b] [--steps N | --cycles N] [--repeat R] [-o OUT]`
/// (argv[1] == "bench"; src/app/bench.cpp): the deck on each backend, timed by phase, with the
/// backends' bounds and the agreement of their results; bench.csv, bench.json, bench.png.
int bench_main(int argc, char* argv[]);

}  // namespace nacre::app
