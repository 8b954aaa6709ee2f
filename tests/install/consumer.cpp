// SPDX-License-Identifier: BSD-3-Clause
// Links nacre::nacre from an install prefix: the build's identity and an exact R-curve through
// the installed headers and library (tests/install/run_install_check.sh).
#include <nacre/core/build_info.hpp>
#include <nacre/fracture/r_curve.hpp>

#include <cstdio>

int main() {
  const nacre::fracture::RCurve c = nacre::fracture::r_curve({0, 1, 2}, {0, 1, 3}, 1.0, 2.0);
  // points at 1 (G_R = 1) and 2 (G_R = 2); the second half from extension 1: (3 - 1) / 1 / 1 / 2
  if (c.points.size() != 2 || c.points[1].G_R != 2.0 || c.toughening_ratio != 1.0) {
    std::printf("consumer: wrong R-curve\n");
    return 1;
  }
  std::printf("%s", nacre::version_text().c_str());
  return 0;
}
