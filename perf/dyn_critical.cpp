// SPDX-License-Identifier: BSD-3-Clause
// Critical step (largest stable explicit step, dyn::critical_step: bisection to a relative
// tolerance, blow-up criterion in docs/dynamics.md) against the stiffness ratio r for UE and BE
// (Fig. 4.6), with and without Table 4.2 damping. The UE/BE gap is compared with
// sqrt(internal joint stiffness / brick stiffness) = sqrt(internal_stiffness_factor) in the chart.
//
//   nacre_perf_dyn_critical --ratios 1,10,50,100,500 --bricks 1000 --csv FILE
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>

#include "specimen_size.hpp"

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

using namespace nacre;

int main(int argc, char* argv[]) {
  Kokkos::ScopeGuard guard(argc, argv);
  CLI::App cli{"nacre dynamics critical step vs stiffness ratio"};
  std::vector<double> ratios{1, 10, 50, 100, 500};
  std::vector<std::string> methods{"ue", "be"}, dampings{"none", "table"};
  long bricks = 1000, steps = 2000;
  double rtol = 0.01, factor = 50;
  std::string csv;
  cli.add_option("--ratios", ratios)->delimiter(',');
  cli.add_option("--methods", methods)->delimiter(',');
  cli.add_option("--damping", dampings, "none and/or table")->delimiter(',');
  cli.add_option("--bricks", bricks);
  cli.add_option("--steps", steps, "steps per bisection trial");
  cli.add_option("--rtol", rtol);
  cli.add_option("--internal-factor", factor, "UE internal joint stiffness / (E / brick_height)");
  cli.add_option("--csv", csv)->required();
  cli.allow_extras();
  CLI11_PARSE(cli, argc, argv);

  // ~`bricks` bricks of 0.105 x 0.03 mm (MODEL.md §5: L ~ 30 µm), notched, in bending
  deck::Deck d;
  size_dyn_specimen(d.geometry, bricks);
  const auto& g = d.geometry;
  geometry::Specimen s = geometry::build_specimen(g);
  const geometry::Interfaces f = geometry::find_interfaces(s, g);

  std::ofstream out(csv);
  out << "method,ratio,damping,bricks,youngs_modulus,alpha_d,beta_d,internal_factor,critical_step,rtol,trial_steps,"
         "seconds\n";
  for (double r : ratios) {
    // Table 4.1's k x1 grows slightly with r (49.99 .. 70.63 N/mm^2); k x1 x2 = 22 N/mm
    const double kx1 = r <= 1 ? 49.99 : r <= 10 ? 67.41 : r <= 50 ? 70.0 : r <= 100 ? 70.35 : 70.63;
    d.mortar.bed = d.mortar.head = {7000.0, kx1 / 7000.0, 22.0 / kx1};
    for (const auto& damp : dampings)
      for (const auto& m : methods) {
        dyn::Params p;
        p.method = m == "ue" ? dyn::Method::ue : dyn::Method::be;
        p.youngs_modulus = 214.99 * r;
        p.internal_stiffness_factor = factor;
        p.rate = 1000.0, p.final_displacement = 0.01, p.tension = 0, p.bending = 1;
        if (damp == "table") dyn::table_4_2_damping(s.size(), r, p.alpha_d, p.beta_d);
        const auto t0 = std::chrono::steady_clock::now();
        const double h = dyn::critical_step(p, s, f, d.mortar, steps, rtol);
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        out << m << "," << r << "," << damp << "," << s.size() << "," << p.youngs_modulus << "," << p.alpha_d << ","
            << p.beta_d << "," << factor << "," << h << "," << rtol << "," << steps << "," << sec << "\n";
        out.flush();
        std::cout << "[dyn_critical] r = " << r << ", " << m << ", damping " << damp << ": h_crit = " << h << " s ("
                  << sec << " s)\n";
      }
  }
  return 0;
}
