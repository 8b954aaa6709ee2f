// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The Monte Carlo solver's side of the outputs: its CSV rows, its dump snapshot (named
/// brick / vertex / interface fields), its summary, and its checkpoint as named arrays with
/// range checks on the way back in. io stays solver-neutral; this file translates.
#include <nacre/fracture/crack.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/results.hpp>
#include <nacre/mc/solver.hpp>

#include <string>

namespace nacre::mc {

[[nodiscard]] std::string csv_header();
/// \brief The step's row; the crack reading of its state goes in the crack_* columns.
[[nodiscard]] std::string csv_row(const StepRecord& r, const fracture::CrackReading& crack);

/// \brief Poses, displaced polygon vertices, brick energies (half of each interface to each
/// side), interface ends, energies and states, in original order. Spread over ranks, every rank
/// calls it (the fields are gathered to rank 0, the writer); the others get a snapshot without fields.
[[nodiscard]] io::Snapshot snapshot(Solver& solver, const geometry::Specimen& s, const geometry::Interfaces& f,
                                    int step);

/// \brief summary.json: sizes, colouring (and the pick of colouring = "fastest" with its
/// timings), generator, seed, threads, backend, steps, cycles, times.
/// The crack of the final state (fracture/crack.hpp) goes in "crack", with the R-curve's
/// toughening ratio (null when NaN); the build (core/build_info.hpp) in "nacre", "kokkos", "libraries".
[[nodiscard]] std::string summary_json(const Solver& solver, const deck::Deck& d, int steps, double seconds,
                                       const fracture::CrackReading& crack, double notch_tip_x,
                                       double toughening_ratio);

/// \brief The checkpoint as named arrays (solver "mc"); `fingerprint` and `deck_text` identify
/// the deck that made it, `final_displacement` the end of its loading programme and `legs` the
/// programme's number of targets (the checkpoint is of a finished run when its leg reached it).
[[nodiscard]] io::Checkpoint to_named(const Checkpoint& c, const std::string& fingerprint, const std::string& deck_text,
                                      double final_displacement, int legs = 1);

/// \brief Back from named arrays, every value range-checked against a specimen of `n_bricks`
/// bricks of which `n_free` are free: poses finite, counts non-negative and consistent
/// (trials = cycles x free bricks, accepted <= trials), step sizes positive. Throws
/// io::CheckpointError naming the first offending entry.
[[nodiscard]] Checkpoint from_named(const io::Checkpoint& c, std::size_t n_bricks, std::size_t n_free);

}  // namespace nacre::mc
