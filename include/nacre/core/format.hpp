// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief A real as text with a given number of significant digits ("%.*g"): CSV rows (10, or 17
/// where a restarted run's rows must compare exactly), messages (3 to 6). One helper for every
/// writer and message, so no file keeps its own copy.
#include <cstdio>
#include <string>

namespace nacre {

[[nodiscard]] inline std::string format_real(double v, int digits = 10) {
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

}  // namespace nacre
