// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Gauss-Legendre rules on [0, 1] for integrating the cohesive energy along an interface.
///
/// Why Gauss-Legendre: for rigid bricks the gap varies linearly along a straight interface, so
/// in the elastic range the density 0.5 k |gap|^2 is a quadratic in s (exact with 2 points) and
/// the interpenetration penalty is a degree-6 polynomial (exact with 4 points). Only where a
/// branch point (x1, x2, x1 + x2 or dn = 0) falls inside the segment is the density merely C1,
/// and there the error falls like n^-2 or faster; tests/test_cohesive.cpp measures it against a
/// 20000-panel composite reference. Default: 4 points.
#include <Kokkos_Core.hpp>

namespace nacre::cohesive {

/// \brief An n-point rule on [0, 1]; weights sum to 1. Trivially copyable so kernels capture it.
struct Quadrature {
  int n = 0;
  double s[8] = {};
  double w[8] = {};
};

/// \brief The n-point Gauss-Legendre rule (1 <= n <= 8), nodes by Newton on P_n.
Quadrature gauss_legendre(int n);

}  // namespace nacre::cohesive
