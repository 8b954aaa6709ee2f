// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/cohesive/quadrature.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace nacre::cohesive {

Quadrature gauss_legendre(int n) {
  if (n < 1 || n > 8) throw std::invalid_argument("gauss_legendre: n must be in [1, 8]");
  Quadrature q;
  q.n = n;
  for (int i = 0; i < n; ++i) {
    // Newton on the Legendre polynomial P_n from the Chebyshev-like initial guess.
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      if (n == 1) p0 = 1, p1 = x;
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    q.s[i] = 0.5 * (1 - x);                      // map [-1, 1] -> [0, 1], ascending
    q.w[i] = 1.0 / ((1 - x * x) * dp * dp);       // 2 / ((1-x^2) P'^2), halved for [0, 1]
  }
  return q;
}

}  // namespace nacre::cohesive
