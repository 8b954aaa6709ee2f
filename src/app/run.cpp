#include <nacre/app/run.hpp>
#include <nacre/deck/deck.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/io/results.hpp>
#include <nacre/mc/solver.hpp>

#include "progress.hpp"
#include "run_dynamics.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string_view>
#include <unistd.h>

#ifndef NACRE_PLOT_SCRIPT
#define NACRE_PLOT_SCRIPT ""
#endif

namespace nacre::app {

namespace {

int run_deck(deck::Deck d, bool quiet, bool tty, const std::string& restart) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(clock::now() - t0).count(); };
  std::ostream* log = quiet ? nullptr : &std::cout;

  geometry::Specimen specimen;
  geometry::Interfaces interfaces;
  {
    Kokkos::Profiling::ScopedRegion region("nacre::geometry::build");
    specimen = geometry::build_specimen(d.geometry);
    interfaces = geometry::find_interfaces(specimen, d.geometry);
  }
  if (log)
    *log << "nacre: " << d.path << ": " << specimen.size() << " bricks, " << interfaces.size()
         << " interfaces (" << elapsed() << " s), " << Kokkos::DefaultExecutionSpace::name() << " with "
         << Kokkos::DefaultExecutionSpace().concurrency() << " threads\n";
  mc::Checkpoint cp;
  if (!restart.empty()) {
    cp = io::RunWriter::read_checkpoint(restart);
    d.solver.colouring = cp.colouring;  // the run continues with the schedule it started with
  }
  mc::Solver solver(d, specimen, interfaces, log);
  if (!restart.empty()) {
    solver.restore(cp);
    if (log) *log << "nacre: restarting from " << restart << " at step " << cp.run.step << ", D = " << cp.displacement
                  << ", cycle " << cp.global_cycle << "\n";
  }
  io::RunWriter writer(d, specimen, interfaces, restart.empty() ? -1 : cp.run.step);
  const bool progress = tty && d.output.progress && !quiet;
  int current_step = 0;
  const double t_run = elapsed();
  bool step_done = false;  // the line names the step in progress, or the one just finished
  auto progress_line = [&](long cycles, double energy) {
    const double frac = solver.load() / d.load.final_displacement;
    const double spent = elapsed() - t_run;
    const double left = frac > 0 ? spent / frac - spent : -1;
    std::fprintf(stderr, "\r  step %4d  D %.4g/%.4g  cycles %8ld  E %.6g  elapsed %s  left ~%s   ",
                 step_done ? current_step : current_step + 1,
                 solver.load(), d.load.final_displacement, cycles, energy, hms(spent).c_str(), hms(left).c_str());
    std::fflush(stderr);
  };
  if (progress) solver.on_progress = progress_line;
  if (restart.empty()) writer.dump(0, solver);
  solver.run([&](const mc::StepRecord& r) {
    current_step = r.step;
    writer.step(r);
    const bool last = r.displacement >= d.load.final_displacement * (1 - 1e-12);
    if ((d.output.dump_interval > 0 && r.step % d.output.dump_interval == 0) || last) writer.dump(r.step, solver);
    if (progress) {
      step_done = true;
      progress_line(r.cycles, r.energy);
      step_done = false;
    }
    else if (log)
      *log << "  step " << r.step << ": D = " << r.displacement << ", E = " << r.energy << ", F = " << r.reaction
           << ", " << r.cycles << " cycles" << (r.converged ? "" : " (not converged)") << ", acceptance "
           << r.acceptance << ", ruptured " << r.ruptured << "\n";
  });
  if (progress) std::fprintf(stderr, "\n");
  writer.summary(solver, elapsed(), "");
  if (log) {
    const auto& pt = solver.times();
    *log << "nacre: done in " << elapsed() << " s; " << solver.global_cycle() << " cycles; time split: sweep "
         << pt.sweep << " s, energy " << pt.energy << " s, rng " << pt.rng << " s\n";
    *log << "nacre: results in " << writer.directory().string() << "/ (steps.csv, nacre.xdmf, summary.json)\n";
  }
  if (d.output.charts) {
    const char* env = std::getenv("NACRE_PLOT_SCRIPT");
    const std::string script = env ? env : NACRE_PLOT_SCRIPT;
    if (script.empty() || !std::filesystem::exists(script)) {
      std::cerr << "nacre: warning: plotting script not found; charts skipped\n";
    } else {
      const std::string cmd = "python3 '" + script + "' '" + writer.directory().string() + "'";
      if (std::system(cmd.c_str()) != 0) std::cerr << "nacre: warning: chart script failed: " << cmd << "\n";
      else if (log) *log << "nacre: charts: energy_force.png, crack.png\n";
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char* argv[]) {
  // --kokkos-* flags go to Kokkos (ScopeGuard), the rest to CLI11.
  std::vector<char*> kokkos_args{argv[0]}, app_args{argv[0]};
  for (int i = 1; i < argc; ++i)
    (std::string_view(argv[i]).starts_with("--kokkos-") ? kokkos_args : app_args).push_back(argv[i]);

  CLI::App cli{"nacre: fracture of brick-and-mortar composites (rigid bricks by Monte Carlo; deformable bricks in time with a [dynamics] section)"};
  std::string deck_path;
  std::string out_override;
  bool quiet = false, check_only = false, critical = false;
  std::string restart;
  cli.add_option("deck", deck_path, "TOML input deck (see docs/decks.md)")->required();
  cli.add_option("-o,--output", out_override, "output directory (overrides [output] directory)");
  cli.add_flag("-q,--quiet", quiet, "no log lines or progress");
  cli.add_flag("--check", check_only, "validate the deck and exit");
  cli.add_option("--restart", restart, "continue a run from its checkpoint.h5 (written at every dump)")
      ->check(CLI::ExistingFile);
  cli.add_flag("--critical-step", critical,
               "print the largest stable time step of a [dynamics] deck's method (bisection) and exit");
  cli.footer("Kokkos flags such as --kokkos-num-threads=N are passed through to Kokkos.");
  try {
    cli.parse(static_cast<int>(app_args.size()), app_args.data());
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? 0 : 2;
  }

  deck::Deck d;
  try {
    d = deck::parse_deck_file(deck_path);
  } catch (const deck::DeckError& e) {
    std::cerr << "nacre: error: " << e.what() << "\n";
    return 2;
  }
  if (!out_override.empty()) d.output.directory = out_override;
  if (critical && !d.dynamics.enabled) {
    std::cerr << "nacre: error: " << deck_path << ": --critical-step needs a [dynamics] section in the deck\n";
    return 2;
  }
  if (check_only) {
    std::cout << "nacre: " << deck_path << ": deck is valid\n";
    return 0;
  }
  int kargc = static_cast<int>(kokkos_args.size());
  Kokkos::ScopeGuard guard(kargc, kokkos_args.data());
  try {
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    if (critical) return print_critical_step(d, quiet);
    if (d.dynamics.enabled) return run_dynamics(d, quiet, tty, restart);
    return run_deck(d, quiet, tty, restart);
  } catch (const std::exception& e) {
    std::cerr << "\nnacre: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace nacre::app
