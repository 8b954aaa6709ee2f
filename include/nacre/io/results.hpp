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
  /// \brief Creates the directory and writes mesh.h5 (call only after the deck validated). With
  /// `resume_step` >= 0 (a restart) the outputs of steps up to it are kept and later ones removed.
  RunWriter(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
            int resume_step = -1);

  void step(const mc::StepRecord& r);
  /// \brief HDF5 dump of the current state, and checkpoint.h5 beside it.
  void dump(int step, mc::Solver& solver);
  void summary(const mc::Solver& solver, double seconds, const std::string& extra_json);

  [[nodiscard]] const std::filesystem::path& directory() const { return dir_; }
  [[nodiscard]] static std::string csv_header();

  static void write_checkpoint(const std::filesystem::path& path, const mc::Checkpoint& c);
  [[nodiscard]] static mc::Checkpoint read_checkpoint(const std::filesystem::path& path);

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
  int last_step_ = 0;  ///< load steps in steps.csv (a restart continues the count)
};

}  // namespace nacre::io
