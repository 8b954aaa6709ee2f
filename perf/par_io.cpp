// SPDX-License-Identifier: BSD-3-Clause
// The outputs of a Monte Carlo run spread over MPI ranks (docs/scaling.md, "Outputs"): what the
// gather to rank 0 costs against the write itself and against a cycle. Per repetition: the
// dump's fields gathered (mc::snapshot: poses, brick and interface energies and states), the
// checkpoint gathered (Solver::checkpoint), and rank 0 writing both (io::RunWriter: HDF5 dump +
// checkpoint, atomically); with a Monte Carlo cycle for scale. Max over ranks, best of --repeat.
//
//   mpiexec -n P nacre_perf_par_io --bricks 1000000 --repeat 3 --csv out.csv [--dir DIR]
//
// Parallel HDF5 would replace the gather and rank 0's write by a collective write of each rank's
// part; this measures what there is to win (perf/run_par_scaling.sh runs it at 1M bricks).
#include <nacre/core/backend.hpp>
#include <nacre/fracture/crack.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/io/results.hpp>
#include <nacre/mc/output.hpp>
#include <nacre/mc/solver.hpp>
#include <nacre/par/comm.hpp>

#include "specimen_size.hpp"

#include <CLI/CLI.hpp>

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

using namespace nacre;

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }
}  // namespace

int main(int argc, char* argv[]) {
  par::Environment mpi(argc, argv);
  const par::Comm comm = par::Comm::world();
  long bricks = 1000000;
  int repeat = 3;
  std::string csv, dir = "par_io_out";
  CLI::App cli{"nacre_perf_par_io: the cost of gathering a spread run's outputs to rank 0"};
  cli.add_option("--bricks", bricks, "bricks in the specimen");
  cli.add_option("--repeat", repeat, "repetitions (the best is kept)");
  cli.add_option("--csv", csv, "append a row to this CSV (rank 0)");
  cli.add_option("--dir", dir, "scratch output directory (rank 0 writes here, removed at the end)");
  CLI11_PARSE(cli, argc, argv);
  Kokkos::ScopeGuard guard(argc, argv);
  {
    deck::Deck d = mc_bench_deck(bricks);
    d.load.tension = 1.0, d.load.bending = 0.5;
    d.solver.relaxation = "monte-carlo", d.solver.polish = "fire", d.solver.colouring = "natural";
    d.output.directory = dir + "_" + std::to_string(comm.size());
    auto t = Clock::now();
    geometry::Specimen s = geometry::build_specimen(d.geometry);
    const geometry::Interfaces f = geometry::find_interfaces(s, d.geometry);
    const double t_geometry = comm.max(since(t));
    t = Clock::now();
    mc::Solver solver(Backend{}, d, s, f, nullptr, comm);
    const double t_setup = comm.max(since(t));
    solver.set_load(1e-3);
    std::optional<io::RunWriter> writer;
    t = Clock::now();
    if (comm.rank() == 0) {
      io::RunWriter::Options wo;
      wo.directory = d.output.directory, wo.csv_header = mc::csv_header();
      writer.emplace(wo, s, f, std::nullopt);
    }
    const double t_mesh = comm.max(since(t));
    double best_cycle = 1e300, best_snap = 1e300, best_cp = 1e300, best_write = 1e300, best_poses = 1e300,
           best_fields = 1e300;
    for (int r = 0; r < repeat; ++r) {
      comm.barrier();
      t = Clock::now();
      (void)solver.cycle();
      best_cycle = std::min(best_cycle, comm.max(since(t)));
      comm.barrier();
      t = Clock::now();
      {  // the snapshot's two gathers alone
        std::vector<double> x, y, th;
        solver.poses(x, y, th);
        best_poses = std::min(best_poses, comm.max(since(t)));
        t = Clock::now();
        (void)solver.output_fields();
        best_fields = std::min(best_fields, comm.max(since(t)));
      }
      comm.barrier();
      t = Clock::now();
      io::Snapshot snap = mc::snapshot(solver, s, f, r);
      best_snap = std::min(best_snap, comm.max(since(t)));
      comm.barrier();
      t = Clock::now();
      const io::Checkpoint cp = mc::to_named(solver.checkpoint(), "perf", "perf", 1.0);
      best_cp = std::min(best_cp, comm.max(since(t)));
      comm.barrier();
      t = Clock::now();
      if (writer) writer->dump(snap), writer->checkpoint(cp);
      best_write = std::min(best_write, comm.max(since(t)));
    }
    std::uintmax_t bytes = 0;
    if (comm.rank() == 0) {
      for (const auto& e : std::filesystem::directory_iterator(d.output.directory))
        if (e.path().filename().string().starts_with("dump_00000") || e.path().filename() == "checkpoint.h5")
          bytes += e.file_size();
      writer.reset();
      std::filesystem::remove_all(d.output.directory);
      const mc::Sizes z = solver.sizes();
      std::cout << "nacre_perf_par_io: " << comm.size() << " ranks, " << z.bricks << " bricks: cycle " << best_cycle
                << " s, gather dump " << best_snap << " s (poses " << best_poses << " s, fields " << best_fields
                << " s), gather checkpoint " << best_cp << " s, write (rank 0) "
                << best_write << " s, " << bytes << " bytes\n";
      if (!csv.empty()) {
        const bool fresh = !std::filesystem::exists(csv);
        std::ofstream o(csv, std::ios::app);
        if (fresh)
          o << "ranks,bricks,interfaces,geometry_s,setup_s,mesh_write_s,cycle_s,gather_dump_s,poses_s,fields_s,"
               "gather_checkpoint_s,write_s,bytes\n";
        o << comm.size() << ',' << z.bricks << ',' << z.interfaces << ',' << t_geometry << ',' << t_setup << ','
          << t_mesh << ',' << best_cycle << ',' << best_snap << ',' << best_poses << ',' << best_fields << ',' << best_cp << ',' << best_write << ',' << bytes
          << '\n';
      }
    }
  }
  return 0;
}
