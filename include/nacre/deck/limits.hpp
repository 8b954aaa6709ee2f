// SPDX-License-Identifier: BSD-3-Clause
#pragma once
#include <string>
/// \file
/// \brief What a deck may ask for: sizes, memory and load steps estimated from the deck alone,
/// before anything is built, so an absurd deck is refused in milliseconds with
/// "file:line: key: ..." instead of running out of memory, overflowing or never ending.
#include <nacre/deck/deck.hpp>

namespace nacre::deck {

/// \brief Estimates of a deck's run (upper bounds, as documented in docs/decks.md [limits]).
struct Estimate {
  double bricks = 0;      ///< wall-grid cells covering the specimen's bounding box (x2 near the notch)
  double load_steps = 0;  ///< final_displacement / smallest increment
  double bytes = 0;       ///< bricks x bytes_per_brick
};

/// \brief Bytes per brick of a run (host specimen + interfaces + device model + work arrays +
/// the output copies), measured and rounded up (docs/decks.md).
inline constexpr double bytes_per_brick = 4096;

/// \brief What a dynamic run with share_element_matrices = false adds per brick: every element
/// its own type, so its matrices (K and (M + h/2 C)^-1; for BIE also J^-1 and its velocity rows)
/// are stored per element on the device and built through host copies. Measured on the 2,100-brick
/// dynamic_bie deck (device bytes per type: be 1,899, bie 5,093, ue 814 with 4 elements per brick),
/// doubled for the host copies at build time and rounded up.
[[nodiscard]] double unshared_bytes_per_brick(const Dynamics& D);

[[nodiscard]] Estimate estimate(const Deck& d);

/// \brief The [limits] memory bound in bytes (max_memory_gib, or 80 % of physical memory).
[[nodiscard]] double memory_limit_bytes(const Limits& l);

/// \brief Throws DeckError ("file:line: key: ...") when a value is outside what doubles can
/// carry through the model, or an estimate exceeds [limits].
void check_limits(const Deck& d);

/// \brief Refuses (DeckError at `key`, else dynamics.end_time) a dynamic run of more than
/// [limits] max_time_steps steps of dt; called for a deck's dt and again for the step a
/// dt_fraction deck takes from the estimated critical step.
void check_time_steps(const Deck& d, double dt, const std::string& key);

}  // namespace nacre::deck
