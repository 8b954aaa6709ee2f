// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/mc/convergence.hpp>

#include <cmath>

namespace nacre::mc {

WindowStats window_stats(const double* y, std::size_t n) {
  WindowStats s;
  if (n == 0) return s;
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += y[i];
  s.mean = sum / static_cast<double>(n);
  // second pass on deviations: no cancellation even when |mean| >> spread
  const double xm = 0.5 * static_cast<double>(n - 1);
  double syy = 0, sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dy = y[i] - s.mean, dx = static_cast<double>(i) - xm;
    syy += dy * dy;
    sxy += dx * dy;
    sxx += dx * dx;
  }
  s.variance = syy / static_cast<double>(n);
  s.r2 = (syy > 0 && sxx > 0) ? (sxy * sxy) / (sxx * syy) : 0.0;  // a flat window has no trend
  return s;
}

ConvergenceMonitor::ConvergenceMonitor(int window_size, int repetitions, double stol, double rtol,
                                       bool relative)
    : ring_(static_cast<std::size_t>(window_size)), scratch_(ring_.size()), rep_(repetitions),
      stol_(stol), rtol_(rtol), relative_(relative) {}

void ConvergenceMonitor::reset() {
  head_ = count_ = 0;
  passes_ = 0;
  last_ = {};
}

bool ConvergenceMonitor::push(double energy) {
  ring_[head_] = energy;
  head_ = (head_ + 1) % ring_.size();
  ++count_;
  if (!window_full()) return false;
  const std::size_t n = ring_.size();
  for (std::size_t i = 0; i < n; ++i) scratch_[i] = ring_[(head_ + i) % n];  // oldest first
  last_ = window_stats(scratch_.data(), n);
  const double scale = relative_ ? last_.mean * last_.mean : 1.0;
  const bool flat = relative_ && scale == 0 ? last_.variance == 0 : last_.variance < stol_ * scale;
  if (flat && last_.r2 < rtol_) ++passes_;
  else passes_ = 0;
  return converged();
}

}  // namespace nacre::mc
