// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief What identifies a run's physics in a checkpoint, and the checks a restart makes before
/// anything in the output directory is touched. Shared by the solver families: each stores its
/// state as io::Checkpoint named arrays with the fingerprint of its deck.
#include <nacre/core/backend.hpp>
#include <nacre/deck/deck.hpp>
#include <nacre/io/checkpoint.hpp>

#include <string>
#include <vector>

namespace nacre::app {

/// \brief The deck's canonical physics text (Deck::canonical) plus nacre's version and the
/// build's backend (Kokkos default execution space): everything that fixes the numbers.
[[nodiscard]] std::string physics_text(const deck::Deck& d);

/// \brief 16 hex digits (FNV-1a 64) of physics_text.
[[nodiscard]] std::string fingerprint(const std::string& physics_text);

/// \brief A checkpoint written on backend `written_on` ("": before backends were recorded, i.e. on
/// the build's default backend) may
/// continue on `here` only where the results are the same bits (Backend::bit_compatible: the same
/// backend, or both on the host); otherwise io::CheckpointError naming both and the way out.
/// `here` is the run's backend's name (no initialised Kokkos needed: `--check` validates first).
void check_restart_backend(const std::string& checkpoint_path, const std::string& written_on, const std::string& here);

/// \brief Refuses (io::CheckpointError) a checkpoint whose fingerprint differs from the deck's,
/// naming the first differing line of the physics text ("mortar.k = 100 in the checkpoint,
/// 120 in the deck"). The checkpoint must hold its text as strings["deck"].
void check_fingerprint(const io::Checkpoint& c, const deck::Deck& d, const std::string& checkpoint_path);

/// \brief Refuses (io::CheckpointError) a checkpoint that lacks one of the named state arrays:
/// a solver that added an array to its state cannot restart from a checkpoint an older nacre
/// wrote (same deck, same fingerprint, valid checksum), and says so before anything is built.
void check_state_arrays(const io::Checkpoint& c, const std::vector<std::string>& names,
                        const std::string& checkpoint_path);

}  // namespace nacre::app
