// SPDX-License-Identifier: BSD-3-Clause
// Initialisation time against specimen size (Fig. 2.9's O(N) claim): wall construction,
// interface search, colouring and model upload, for 10k .. 1M bricks; and the dynamics model
// (dyn::build_model: element types, tiles, interfaces, gather list) for BE and UE, with shared
// element matrices and with one per element (--dyn 0 skips it). The tile build was once
// quadratic in the number of types (one per element unshared: 11+ minutes at 1M BE bricks):
// this is the check that it stays O(N).
//   nacre_perf_init --bricks 10000,100000,1000000 --csv FILE
#include <nacre/dyn/model.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/mc/model.hpp>

#include "specimen_size.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

using namespace nacre;

int main(int argc, char* argv[]) {
  std::vector<char*> kargs{argv[0]}, aargs{argv[0]};
  for (int i = 1; i < argc; ++i) (std::string_view(argv[i]).starts_with("--kokkos-") ? kargs : aargs).push_back(argv[i]);
  CLI::App cli{"nacre initialisation scaling"};
  std::vector<long> sizes{10000, 30000, 100000, 300000, 1000000};
  std::string csv = "init_scaling.csv";
  cli.add_option("--bricks", sizes)->delimiter(',');
  cli.add_option("--csv", csv);
  bool dyn_models = true;
  cli.add_option("--dyn", dyn_models, "also time dyn::build_model (BE, UE; shared and per-element matrices)");
  CLI11_PARSE(cli, static_cast<int>(aargs.size()), aargs.data());
  int kargc = static_cast<int>(kargs.size());
  Kokkos::ScopeGuard guard(kargc, kargs.data());
  std::ofstream out(csv);
  out << "bricks,interfaces,specimen_s,interfaces_s,colouring_s,model_s,total_s,dyn_be_s,dyn_be_own_s,dyn_ue_s,"
         "dyn_ue_own_s\n";
  using clk = std::chrono::steady_clock;
  auto since = [](clk::time_point t) { return std::chrono::duration<double>(clk::now() - t).count(); };
  for (long n : sizes) {
    deck::Deck d;
    size_specimen(d.geometry, n);
    d.geometry.angle_deg = 30.0;  // rotated: every boundary brick is clipped
    d.geometry.notch_y = 0.5 * d.geometry.height;
    auto t = clk::now();
    auto s = geometry::build_specimen(d.geometry);
    const double ts = since(t);
    t = clk::now();
    auto f = geometry::find_interfaces(s, d.geometry);
    const double ti = since(t);
    t = clk::now();
    auto adj = geometry::build_adjacency(s.size(), f);
    std::vector<bool> free(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) free[i] = s.drive[i] == geometry::Drive::free;
    auto c = mc::colour_graph("natural", s, adj, free, 1);
    const double tc = since(t);
    t = clk::now();
    auto m = mc::build_model(ExecSpace{}, s, f, adj, c, d.mortar, 4);
    Kokkos::fence();
    const double tm = since(t);
    out << s.size() << "," << f.size() << "," << ts << "," << ti << "," << tc << "," << tm << "," << ts + ti + tc + tm;
    std::cout << s.size() << " bricks, " << f.size() << " interfaces: " << ts + ti + tc + tm << " s (specimen " << ts
              << ", interfaces " << ti << ", colouring " << tc << ", model " << tm << ")";
    if (dyn_models) {
      std::cout << "; dyn::build_model";
      for (auto method : {dyn::Method::be, dyn::Method::ue})
        for (bool share : {true, false}) {
          dyn::Params p;
          p.method = method;
          p.dt = 1e-9;
          p.share_element_matrices = share;
          dyn::HostMap map;
          t = clk::now();
          auto dm = dyn::build_model(p, s, f, d.mortar, map);
          Kokkos::fence();
          const double td = since(t);
          out << "," << td;
          std::cout << " " << (method == dyn::Method::be ? "BE" : "UE") << (share ? "" : " own") << " " << td << " s";
        }
    } else {
      out << ",,,,";
    }
    out << "\n";
    std::cout << "\n";
  }
  return 0;
}
