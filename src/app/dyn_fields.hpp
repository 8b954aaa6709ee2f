// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What a dynamic run hands to io::RunWriter, the writer both solver families share: the triangle
// mesh (mesh.h5), each dump's named fields (deformed nodes, displacement, velocity, stresses per
// triangle and brick, interface damage and state, interface polylines), the series.csv row and
// the checkpoint as io::Checkpoint named arrays. Why here and not in io: io depends on no
// solver, and these read dyn::Snapshot.
#include <nacre/deck/deck.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/fracture/crack.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/results.hpp>

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
  fracture::CrackReading crack;     ///< the crack from the notch (fracture/crack.hpp)
  double crack_speed = 0;           ///< d(crack extension)/dt since the previous row, mm/s (0 on the first row)
  double crack_speed_rayleigh = 0;  ///< crack_speed over the bricks' Rayleigh wave speed
  double dt = 0;                 ///< step in use (the adaptive mode changes it)
  double critical_estimate = 0;  ///< the stability monitor's estimated critical step at the last check
  double seconds = 0;
};

[[nodiscard]] std::string series_header();
/// \brief The row as CSV, every real to 17 digits (a restarted run's rows compare exactly).
[[nodiscard]] std::string series_line(const SeriesRow& r);

/// \brief What a restart needs besides the solver's arrays.
struct DynCheckpoint {
  long step = 0;
  double time = 0, dt = 0, end_time = 0;
  std::string method;
  /// The backend the run was on (`--backend`): recorded, not compared. A restart may take another
  /// backend of the same build (they give the same bits); another build's default space changes
  /// the fingerprint (nacre.backend), which refuses the restart by name.
  std::string backend;
  dyn::StateArrays state;
  /// The run's books a restart carries into its summary.json (0: an older checkpoint): the
  /// critical step a dt_fraction deck took its dt from, the largest balance residual of the rows
  /// so far.
  double critical_step = 0, worst_balance = 0;
};

/// \brief The checkpoint as named arrays with the deck's physics fingerprint.
[[nodiscard]] io::Checkpoint to_named(const DynCheckpoint& c, const deck::Deck& d);
/// \brief Reads and validates a dynamic checkpoint (io::CheckpointError: corrupt, of a Monte Carlo
/// run or of another deck, out-of-range step, time or dt, a missing or non-finite state array),
/// before anything in the output directory changes.
[[nodiscard]] DynCheckpoint read_dyn_checkpoint(const std::filesystem::path& path, const deck::Deck& d);

/// \brief read_dyn_checkpoint, and refused where it cannot continue this deck: another method,
/// another end_time without `extend`, a run at or past the deck's end_time (run_dynamics.cpp).
[[nodiscard]] DynCheckpoint validated_dyn_checkpoint(const deck::Deck& d, const std::string& restart, bool extend);

/// \brief The static mesh and the per-dump fields of a dynamic run.
class DynFields {
public:
  /// \brief Maps each interface end onto a triangle edge of its brick (from the first snapshot).
  DynFields(const geometry::Specimen& s, const geometry::Interfaces& f, const dyn::Snapshot& first);
  [[nodiscard]] const io::TriangleMesh& mesh() const { return mesh_; }
  [[nodiscard]] io::Snapshot fields(long step, const dyn::Snapshot& snap) const;

private:
  io::TriangleMesh mesh_;
  std::size_t n_interfaces_ = 0;
  /// Each interface end lies on an edge (n0, n1) of a triangle of brick a: u = (1-w) u0 + w u1.
  std::vector<int> end_n0_, end_n1_;
  std::vector<double> end_w_, end_ref_;
};

/// \brief The first non-finite value of a snapshot ("ux of node 12"), or "".
[[nodiscard]] std::string first_non_finite(const dyn::Snapshot& s);

}  // namespace nacre::app
