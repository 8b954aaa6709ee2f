// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Progress-line helpers shared by the Monte Carlo and the dynamics drivers.
#include <cstdio>
#include <string>

namespace nacre::app {

/// \brief Seconds as hh:mm:ss ("--:--" when unknown or beyond 100 h).
inline std::string hms(double s) {
  if (!(s >= 0) || s > 360000) return "--:--";
  const long t = static_cast<long>(s + 0.5);
  char b[32];
  std::snprintf(b, sizeof b, "%02ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return b;
}

}  // namespace nacre::app
