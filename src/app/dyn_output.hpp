#pragma once
// Outputs of a dynamic run (Chapter 4), each file written atomically into the output directory:
//   series.csv       one row every csv_interval steps: time, D, energies, balance, reaction, ruptured
//   mesh.h5          static: triangle connectivity, reference nodes, brick of each triangle,
//                    interface segments (connectivity, kind, reference points)
//   dump_NNNNNNNNN.h5  per dump (N = step): deformed nodes, displacement, velocity, stress per
//                    triangle, vertical stress per brick, interface damage/state
//   nacre.xdmf       ParaView (Xdmf3 reader) index of the dumps: "triangles" and "interfaces"
//   checkpoint.h5    the solver's named state arrays at the last dump (restart bit for bit)
//   summary.json     sizes, step, timings, status
// Why here and not in io: io depends on no solver, and this writer reads dyn::Snapshot; it uses
// only io's atomic files and HDF5 layer.
#include <nacre/deck/deck.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace nacre::app {

/// \brief One time-series row (all values finite when written).
struct SeriesRow {
  long step = 0;
  double time = 0, displacement = 0;
  dyn::Energies e;
  double reaction = 0;
  int ruptured = 0;
  double dt = 0;                 ///< step in use (the adaptive mode changes it)
  double critical_estimate = 0;  ///< the stability monitor's estimated critical step at the last check
  double seconds = 0;
};

/// \brief What a restart needs besides the solver's arrays.
struct DynCheckpoint {
  long step = 0;
  double time = 0, dt = 0;
  std::string method;
  dyn::StateArrays state;
};

class DynWriter {
public:
  /// \brief Creates the directory, removes a previous run's files (new run) or keeps the rows and
  /// dumps up to `resume_step` (restart), and writes mesh.h5 from the first snapshot.
  DynWriter(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
            const dyn::Snapshot& first, long resume_step = -1);

  /// \brief Append a row (kept in memory; flushed to series.csv by flush_series()).
  void row(const SeriesRow& r);
  /// \brief Rewrite series.csv atomically with every row so far.
  void flush_series();
  /// \brief Dump the snapshot (HDF5 + XDMF) and the checkpoint beside it.
  void dump(long step, const dyn::Snapshot& snap, const DynCheckpoint& cp);
  void summary(const std::string& json_body);

  [[nodiscard]] const std::filesystem::path& directory() const { return dir_; }
  [[nodiscard]] long last_dump_step() const { return dumps_.empty() ? -1 : dumps_.back().step; }
  [[nodiscard]] long rows() const { return rows_; }
  [[nodiscard]] static std::string csv_header();

  /// \brief checkpoint.h5 as an io::Checkpoint (named arrays, the deck's physics fingerprint,
  /// checksum); read_checkpoint refuses (io::CheckpointError) a corrupt one, one of a Monte Carlo
  /// run or of another deck, before anything in the output directory changes.
  void write_checkpoint(const std::filesystem::path& path, const DynCheckpoint& c) const;
  [[nodiscard]] static DynCheckpoint read_checkpoint(const std::filesystem::path& path, const deck::Deck& d);

private:
  void write_mesh(const dyn::Snapshot& first);
  void write_xdmf() const;

  const deck::Deck& deck_;
  const geometry::Specimen& s_;
  const geometry::Interfaces& f_;
  std::filesystem::path dir_;
  std::string csv_;
  long rows_ = 0;
  std::size_t n_nodes_ = 0, n_tri_ = 0;
  /// Each interface end lies on an edge (n0, n1) of a triangle of brick a: u = (1-w) u0 + w u1.
  std::vector<int> end_n0_, end_n1_;
  std::vector<double> end_w_, end_ref_;
  struct DumpInfo {
    long step;
    double time;
    std::string file;
  };
  std::vector<DumpInfo> dumps_;
};

/// \brief The first non-finite value of a snapshot ("ux of node 12"), or "" when all are finite.
[[nodiscard]] std::string first_non_finite(const dyn::Snapshot& s);

}  // namespace nacre::app
