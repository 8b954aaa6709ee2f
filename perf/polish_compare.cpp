// SPDX-License-Identifier: BSD-3-Clause
// Which polish reaches a residual faster: from one Monte Carlo state of a deck's
// specimen at a load D (same seed, so the same state for every method), FIRE and colour-swept
// block Newton are run to decreasing tolerances; each row is the cumulative wall time and
// iterations to reach the tolerance, and the energy there. Writes CSV to stdout.
//   nacre_perf_polish DECK [--load D] [--cycles N] [--tolerances 1e-3,1e-4,...] [--max-iterations N]
#include <nacre/deck/deck.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/mc/solver.hpp>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

using namespace nacre;

int main(int argc, char* argv[]) {
  Kokkos::ScopeGuard guard(argc, argv);
  CLI::App app{"FIRE against block-Newton polish: time to a residual"};
  std::string deck_path;
  double D = 0.03;
  long cycles = 2000;
  int max_iterations = 200000;
  std::vector<double> tolerances{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  std::vector<std::string> methods{"fire", "newton"};
  app.add_option("deck", deck_path)->required();
  app.add_option("--load", D, "opening D of the state");
  app.add_option("--cycles", cycles, "Monte Carlo cycles before the polish");
  app.add_option("--tolerances", tolerances)->delimiter(',');
  app.add_option("--methods", methods)->delimiter(',');
  app.add_option("--max-iterations", max_iterations);
  app.allow_extras();
  CLI11_PARSE(app, argc, argv);
  deck::Deck d = deck::parse_deck_file(deck_path);
  auto s = geometry::build_specimen(d.geometry);
  const auto f = geometry::find_interfaces(s, d.geometry);
  std::printf("method,load,mc_cycles,tolerance,residual,iterations,seconds,energy,threads\n");
  for (const auto& method : methods) {
    d.solver.polish = method;
    d.solver.polish_iterations = max_iterations;
    mc::Solver solver(d, s, f);
    solver.set_load(D);
    for (long c = 0; c < cycles; ++c) solver.cycle();
    int total = 0;
    double seconds = 0;
    std::printf("%s,%g,%ld,%g,%.6e,%d,%.6f,%.12e,%d\n", method.c_str(), D, cycles, 0.0, solver.residual(), 0, 0.0,
                solver.energy(), Kokkos::DefaultExecutionSpace().concurrency());
    for (double tol : tolerances) {
      Kokkos::Timer timer;
      const auto r = solver.polish(method, tol);  // continues from the previous tolerance's state
      seconds += timer.seconds();
      total += r.iterations;
      std::printf("%s,%g,%ld,%g,%.6e,%d,%.6f,%.12e,%d\n", method.c_str(), D, cycles, tol, r.residual, total, seconds,
                  solver.energy(), Kokkos::DefaultExecutionSpace().concurrency());
      std::fflush(stdout);
      if (!r.converged) break;
    }
  }
  return 0;
}
