#pragma once
/// \file
/// \brief Everything a run writes into its output directory, each file atomically:
///  steps.csv          one row per load step (rewritten after each step)
///  mesh.h5            static data: polygon topology, reference geometry, ids (written once)
///  dump_NNNNN.h5      brick poses, displaced points, energies; interface states (per dump)
///  nacre.xdmf         ParaView index of all dumps (rewritten after each dump)
///  summary.json       parameters, colouring, phase times, totals (at the end)
#include <nacre/mc/solver.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace nacre::io {

class RunWriter {
public:
  /// \brief Creates the directory and writes mesh.h5 (call only after the deck validated).
  RunWriter(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
            const mc::Model<>& m);

  void step(const mc::StepRecord& r);
  void dump(int step, mc::Solver& solver);
  void summary(const mc::Solver& solver, double seconds, const std::string& extra_json);

  [[nodiscard]] const std::filesystem::path& directory() const { return dir_; }
  [[nodiscard]] static std::string csv_header();

private:
  void write_xdmf() const;

  const deck::Deck& deck_;
  const geometry::Specimen& s_;
  const geometry::Interfaces& f_;
  std::filesystem::path dir_;
  std::string csv_;
  struct DumpInfo {
    int step;
    double displacement;
    std::string file;
  };
  std::vector<DumpInfo> dumps_;
  std::vector<mc::StepRecord> rows_;
};

}  // namespace nacre::io
