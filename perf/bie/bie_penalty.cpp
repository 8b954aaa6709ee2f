// SPDX-License-Identifier: BSD-3-Clause
// Why a cracking BIE deck blows up at a step its intact specimen takes (issue 8): runs a deck
// (default inputs/dynamic_bie.toml) with BIE at several steps and records, every few steps, the
// largest interpenetration of the bed/head joints relative to x1 (Simulation::max_penetration),
// the stiffness the penalty g(dn) = k dn^6 / (16 x1^4) then gives a joint,
// k_eff / k = 1 + 1.875 (dn / x1)^4, the ruptured joints and the kinetic energy, until the end or
// the blow-up. The explicit interface part of BIE is stable below ~2 / omega of a brick mass on its
// joints, omega ~ sqrt(k_eff): its step limit falls like 1 / sqrt(k_eff / k) once the crack lets
// bricks slam into each other. Also the deck's critical step from rest (intact).
//
//   nacre_perf_bie_penalty --deck inputs/dynamic_bie.toml --dts 3e-8,4.5e-8,6e-8 --out FILE.csv
#include <nacre/app/run_dynamics.hpp>

#include <nacre/deck/deck.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>

#include <cmath>
#include <fstream>
#include <iostream>

using namespace nacre;

int main(int argc, char* argv[]) {
  Kokkos::ScopeGuard guard(argc, argv);
  CLI::App cli{"BIE step limit after cracking: penetration and penalty stiffness vs time"};
  std::string deck_path = "inputs/dynamic_bie.toml", out;
  std::vector<double> dts{3e-8, 4.5e-8, 6e-8};
  long every = 5, max_steps = 2000;
  bool critical = true;
  cli.add_option("--deck", deck_path);
  cli.add_option("--dts", dts)->delimiter(',');
  cli.add_option("--every", every, "steps between records");
  cli.add_option("--max-steps", max_steps);
  cli.add_option("--critical", critical, "also bisect the deck's critical step from rest");
  cli.add_option("--out", out)->required();
  cli.allow_extras();
  CLI11_PARSE(cli, argc, argv);

  const deck::Deck d = deck::parse_deck_file(deck_path);
  geometry::Specimen s = geometry::build_specimen(d.geometry);  // find_interfaces may tag it
  const geometry::Interfaces f = geometry::find_interfaces(s, d.geometry);
  const Kokkos::DefaultExecutionSpace space;
  std::ofstream o(out);
  o << "dt,step,time,displacement,ruptured,max_penetration,k_eff_over_k,kinetic,status\n";
  if (critical) {
    dyn::Params p = app::dynamics_params(d, s.size());
    p.dt = 0;
    const double hc = dyn::critical_step(p, s, f, d.mortar, 1000, 0.02);
    std::cout << "[penalty] critical step from rest (intact, 1000 steps, 2 %): " << hc << " s\n";
    o << "# critical_step_from_rest," << hc << "\n";
  }
  for (double dt : dts) {
    dyn::Params p = app::dynamics_params(d, s.size());
    p.dt = dt;
    dyn::Simulation sim(p, s, f, d.mortar);
    double worst = 0;
    bool ok = true;
    for (long n = 0; n < max_steps && ok; n += every) {
      ok = sim.advance(space, every);
      const double r = sim.max_penetration();
      worst = std::max(worst, r);
      const double keff = 1.0 + 1.875 * std::pow(r, 4);
      o << dt << "," << sim.steps() << "," << sim.time() << "," << sim.displacement() << "," << sim.ruptured() << ","
        << r << "," << keff << "," << sim.energies().kinetic << "," << (ok ? "ok" : "unstable") << "\n";
    }
    std::cout << "[penalty] dt " << dt << ": " << (ok ? "stable" : "unstable: " + sim.why()) << "; max penetration "
              << worst << " x1 (k_eff/k " << 1.0 + 1.875 * std::pow(worst, 4) << "), ruptured " << sim.ruptured()
              << " at step " << sim.steps() << "\n";
  }
  return 0;
}
