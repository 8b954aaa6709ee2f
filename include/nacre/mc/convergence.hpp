// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Sliding-window convergence test of a load step (§2.2, eq. 2.5-2.6).
///
/// The window holds the last WindowSize cycle energies. Each cycle, after the window is full,
/// the test computes the window variance and R^2 of energy against cycle index (how much of the
/// variation is a linear trend). A cycle "passes" when the variance test holds (relative mode:
/// var / mean^2 < STOL, dimensionless and independent of the energy scale; absolute mode:
/// var < STOL) and R^2 < RTOL. The step has converged after ConvergenceRep consecutive passes.
///
/// Exactness: the paper's running sums (eq. 2.6) drift and needed quad precision. Here every
/// statistic is recomputed from the stored window with shifted two-pass sums — O(WindowSize)
/// per cycle, which is noise next to a sweep over all bricks — so there is nothing to drift.
#include <cstddef>
#include <vector>

namespace nacre::mc {

/// \brief Statistics of one full window.
struct WindowStats {
  double mean = 0, variance = 0, r2 = 0;
};

/// \brief Exact statistics of a sequence y_0 .. y_{n-1} against index 0 .. n-1.
[[nodiscard]] WindowStats window_stats(const double* y, std::size_t n);

class ConvergenceMonitor {
public:
  ConvergenceMonitor(int window_size, int repetitions, double stol, double rtol, bool relative);

  /// \brief Record the energy after a cycle; returns true once converged.
  bool push(double energy);
  /// \brief Start a new load step.
  void reset();

  [[nodiscard]] bool converged() const { return passes_ >= rep_; }
  [[nodiscard]] int passes() const { return passes_; }
  [[nodiscard]] const WindowStats& last() const { return last_; }
  [[nodiscard]] bool window_full() const { return count_ >= ring_.size(); }

private:
  std::vector<double> ring_, scratch_;
  std::size_t head_ = 0, count_ = 0;
  int rep_;
  double stol_, rtol_;
  bool relative_;
  int passes_ = 0;
  WindowStats last_;
};

}  // namespace nacre::mc
