// SPDX-License-Identifier: BSD-3-Clause
// Sweep schedules compared on the quantities that decide between them: number of colours (one
// parallel launch and one barrier each per cycle), balance (largest colour / mean colour: the
// largest colour bounds a cycle's critical path when colours are small), and the time to colour
// the wall (paid once per run, in the pre-simulation for every candidate). Sweep speed with each
// schedule comes from nacre_perf_mc --colouring ... (perf/run_colouring_bench.sh runs both).
//
//   nacre_perf_colouring --bricks 10000,100000,1000000 --repeats 3 --csv FILE
// Besides the strategies, "kokkos-d1-default" times Kokkos Kernels' default (non-deterministic)
// algorithm for the backend, to show what determinism costs.
#include <nacre/geometry/specimen.hpp>
#include <nacre/mc/colouring.hpp>

#include "specimen_size.hpp"

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iostream>

using namespace nacre;

int main(int argc, char* argv[]) {
  std::vector<char*> kargs{argv[0]}, aargs{argv[0]};
  for (int i = 1; i < argc; ++i) (std::string_view(argv[i]).starts_with("--kokkos-") ? kargs : aargs).push_back(argv[i]);
  CLI::App cli{"nacre colouring comparison"};
  std::vector<long> sizes{10000, 100000, 1000000};
  std::vector<std::string> strategies = mc::colouring_strategies();
  int repeats = 3;
  std::string csv = "colouring.csv";
  cli.add_option("--bricks", sizes, "specimen sizes (bricks)")->delimiter(',');
  cli.add_option("--colouring", strategies, "strategies to compare")->delimiter(',');
  cli.add_option("--repeats", repeats, "timed colourings per strategy; the fastest counts");
  cli.add_option("--csv", csv, "append results to this CSV");
  CLI11_PARSE(cli, static_cast<int>(aargs.size()), aargs.data());
  int kargc = static_cast<int>(kargs.size());
  Kokkos::ScopeGuard guard(kargc, kargs.data());
  const int threads = Kokkos::DefaultExecutionSpace().concurrency();
  const bool header = !std::ifstream(csv).good();
  std::ofstream out(csv, std::ios::app);
  if (header) out << "bricks,free_bricks,strategy,threads,backend,colours,largest,smallest,mean,balance,seconds,cpu_seconds\n";
  for (long n : sizes) {
    deck::Geometry g;
    size_specimen(g, n);
    g.notch_y = std::floor(0.5 * g.height);
    g.angle_deg = 30;  // clipped boundary bricks: irregular degrees, as in init_scaling
    auto s = geometry::build_specimen(g);
    auto f = geometry::find_interfaces(s, g);
    const auto adj = geometry::build_adjacency(s.size(), f);
    std::vector<bool> free;
    for (auto d : s.drive) free.push_back(d == geometry::Drive::free);
    const long n_free = std::count(free.begin(), free.end(), true);
    for (const auto& name : strategies) {
      mc::Colouring c;
      double sec = 1e300, cpu = 1e300;  // wall and process CPU seconds (all threads), fastest of repeats
      for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
#ifdef NACRE_HAVE_KOKKOSKERNELS
        if (name == "kokkos-d1-default")  // the library's fast, non-deterministic variant (not a strategy)
          c = mc::colour_kokkos_d1(adj, free, false);
        else
#endif
          c = mc::colour_graph(name, s, adj, free, 1);
        sec = std::min(sec, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        cpu = std::min(cpu, static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
      }
      if (auto err = mc::validate_colouring(c, adj, free); !err.empty()) {
        std::cerr << name << ": invalid colouring: " << err << "\n";
        return 1;
      }
      // balance over parallel work items: bricks per colour (tiles: bricks per colour too, the
      // work items being tiles of ~256 bricks)
      std::vector<long> size(c.n_colours, 0);
      for (int col : c.colour)
        if (col >= 0) ++size[col];
      const long largest = *std::max_element(size.begin(), size.end());
      const long smallest = *std::min_element(size.begin(), size.end());
      const double mean = static_cast<double>(n_free) / c.n_colours;
      out << s.size() << "," << n_free << "," << name << "," << threads << "," << Kokkos::DefaultExecutionSpace::name() << ","
          << c.n_colours << "," << largest << "," << smallest << "," << mean << "," << largest / mean << "," << sec << "," << cpu << "\n";
      std::cout << name << " " << s.size() << " bricks: " << c.n_colours << " colours, balance " << largest / mean << ", "
                << sec << " s (" << cpu << " CPU s)" << std::endl;
    }
  }
  return 0;
}
