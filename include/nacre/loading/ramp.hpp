// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Time profile of the opening, D(t), for solvers that move through time (Chapter 4):
/// the opening rate ramps up from 0 over ramp_time, then stays constant; D stops growing at
/// final_displacement (held after) when that is > 0. (The quasi-static Monte Carlo solver steps
/// D directly and needs no ramp.)
#include <Kokkos_Core.hpp>

#include <cstdint>

namespace nacre::loading {

/// \brief How the rate ramps up: linear (rate ~ t, acceleration jumps to r / T at t = 0) or
/// smooth (rate ~ (1 - cos(pi t / T)) / 2, acceleration continuous, zero at t = 0).
enum class Profile : std::uint8_t { linear, smooth };

/// \brief Opening and its first two time derivatives.
struct Opening {
  double D = 0, rate = 0, accel = 0;
};

/// \brief Most targets of a load programme (deck [load] programme), held by value in the ramp.
inline constexpr int kMaxTargets = 16;

struct Ramp {
  Profile profile = Profile::linear;
  double rate = 0;                ///< dD/dt once ramped up (length / time)
  double ramp_time = 0;           ///< time over which the rate ramps from 0 (0: none)
  double final_displacement = 0;  ///< D held once |D| reaches it (0: no limit)
  /// A load programme (n_targets > 0): D travels from 0 through target[0..n) in order, at the
  /// ramped rate along the path, and is held at the last target; final_displacement is then not
  /// read. The turns are sharp (the rate changes sign within a step), as a testing machine's
  /// cross-head reversing.
  int n_targets = 0;
  double target[kMaxTargets] = {};

  /// \brief D(t), D'(t), D''(t).
  KOKKOS_INLINE_FUNCTION Opening operator()(double t) const {
    const double r = rate, T = ramp_time;
    Opening o;
    if (T > 0 && t < T) {
      if (profile == Profile::linear) {
        o.D = 0.5 * r * t * t / T, o.rate = r * t / T, o.accel = r / T;
      } else {
        const double w = Kokkos::numbers::pi / T;
        o.D = 0.5 * r * (t - Kokkos::sin(w * t) / w), o.rate = 0.5 * r * (1 - Kokkos::cos(w * t));
        o.accel = 0.5 * r * w * Kokkos::sin(w * t);
      }
    } else {
      o.D = r * (t - 0.5 * T), o.rate = r, o.accel = 0;
    }
    if (n_targets > 0) return along_programme(o);
    if (final_displacement > 0 && Kokkos::abs(o.D) >= final_displacement)
      o.D = Kokkos::copysign(final_displacement, o.D), o.rate = 0, o.accel = 0;
    return o;
  }

  /// \brief The programme's D for a path length s = o.D travelled (and its rates, turned with
  /// the leg's direction).
  KOKKOS_INLINE_FUNCTION Opening along_programme(Opening o) const {
    double prev = 0.0, left = o.D;
    for (int k = 0; k < n_targets; ++k) {
      const double len = Kokkos::abs(target[k] - prev), dir = target[k] >= prev ? 1.0 : -1.0;
      if (left < len) return Opening{prev + dir * left, dir * o.rate, dir * o.accel};
      left -= len, prev = target[k];
    }
    return Opening{prev, 0.0, 0.0};
  }

  /// \brief D(t) alone.
  KOKKOS_INLINE_FUNCTION double displacement(double t) const { return (*this)(t).D; }
};

}  // namespace nacre::loading
