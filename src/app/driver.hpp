#pragma once
// What the Monte Carlo and the dynamics drivers share around their run loops: the overwrite
// guard of an unfinished run, the plotting scripts (spawned, never through a shell), and the
// messages of a stopped run. One rule in one place, so both families behave alike.
#include <nacre/deck/deck.hpp>

#include <filesystem>
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

/// \brief Run argv[0] with arguments, no shell (nothing in a path is ever interpreted);
/// returns the exit status, 128 + signal when it was killed, or kNotStarted.
int spawn_and_wait(const std::vector<std::string>& argv);

/// \brief A new run (or a restart into another directory) sets up its output directory afresh:
/// refuse (UsageError) when that would remove the checkpoint of an unfinished run of either
/// family, unless `overwrite`. A finished run, or a checkpoint that could not be restarted
/// anyway, is replaced.
void check_not_overwriting(const deck::Deck& d, const std::string& restart, bool overwrite);

/// \brief Runs the plotting script `script_name` (nacre_plot.py, nacre_dyn_plot.py; beside
/// NACRE_PLOT_SCRIPT) on `dir`. The scripts write each chart to a temporary and rename it, so a
/// failure leaves no truncated PNG. Returns false (message printed) when the script failed;
/// a missing script or python is a warning and returns true.
bool run_charts(const std::string& script_name, const std::filesystem::path& dir, std::ostream* log);

/// \brief `nacre sweep DECK --set KEY=V1,V2 ...` (argv[1] == "sweep"; src/app/sweep.cpp): one run
/// per combination of the values, resumable, then sweep.json, sweep.csv and sweep.png.
int sweep_main(int argc, char* argv[]);

}  // namespace nacre::app
