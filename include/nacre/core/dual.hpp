// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Forward-mode dual numbers (value + one directional derivative) for device code, and
/// the scalar functions the templated cohesive code calls on `double` or `Dual` alike.
///
/// Why: the quasi-static Newton method needs Hessian-vector products of the exact energy. The
/// gradient (kinematics::interface_gradient over cohesive::integrate's end forces) is a
/// piecewise-analytic function of the poses with data-dependent pieces (where |gap| crosses
/// x1, x2, x1 + x2) and adaptive sub-intervals; differentiating that code itself, with the
/// derivative carried beside each value, gives H v exact to rounding along the branch the
/// values take, without a second hand-derived formula to keep in step. At a kink of the law the
/// branch is the one the double code's comparison picks (the comparisons read the value only).
///
/// `sc::` (scalar) holds one spelling per function for both types: for `double` it is exactly the
/// Kokkos function (so code templated on the scalar gives the same bits as before), for `Dual`
/// the value is that same function and the derivative its chain rule.
#include <Kokkos_Core.hpp>
// the scalar functions for flops::Counted first: templated code's qualified sc:: calls bind to the
// overloads declared before it
#include <nacre/core/flop_count.hpp>

namespace nacre::ad {

struct Dual {
  double v = 0.0;  ///< value
  double d = 0.0;  ///< derivative along the seeded direction
  constexpr Dual() = default;  // (no annotation: nvcc ignores one on a defaulted constructor)
  KOKKOS_INLINE_FUNCTION constexpr Dual(double value) : v(value) {}  // NOLINT: constants promote
  KOKKOS_INLINE_FUNCTION constexpr Dual(double value, double derivative) : v(value), d(derivative) {}
  KOKKOS_INLINE_FUNCTION Dual& operator+=(const Dual& o) {
    v += o.v, d += o.d;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Dual& operator-=(const Dual& o) {
    v -= o.v, d -= o.d;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Dual& operator*=(const Dual& o) {
    d = d * o.v + v * o.d, v *= o.v;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Dual& operator/=(const Dual& o) {
    const double q = v / o.v;
    d = (d - q * o.d) / o.v, v = q;
    return *this;
  }
};

KOKKOS_INLINE_FUNCTION Dual operator-(const Dual& a) { return {-a.v, -a.d}; }
KOKKOS_INLINE_FUNCTION Dual operator+(Dual a, const Dual& b) { return a += b; }
KOKKOS_INLINE_FUNCTION Dual operator-(Dual a, const Dual& b) { return a -= b; }
KOKKOS_INLINE_FUNCTION Dual operator*(Dual a, const Dual& b) { return a *= b; }
KOKKOS_INLINE_FUNCTION Dual operator/(Dual a, const Dual& b) { return a /= b; }
KOKKOS_INLINE_FUNCTION Dual operator+(Dual a, double b) { return {a.v + b, a.d}; }
KOKKOS_INLINE_FUNCTION Dual operator+(double a, const Dual& b) { return {a + b.v, b.d}; }
KOKKOS_INLINE_FUNCTION Dual operator-(Dual a, double b) { return {a.v - b, a.d}; }
KOKKOS_INLINE_FUNCTION Dual operator-(double a, const Dual& b) { return {a - b.v, -b.d}; }
KOKKOS_INLINE_FUNCTION Dual operator*(const Dual& a, double b) { return {a.v * b, a.d * b}; }
KOKKOS_INLINE_FUNCTION Dual operator*(double a, const Dual& b) { return {a * b.v, a * b.d}; }
KOKKOS_INLINE_FUNCTION Dual operator/(const Dual& a, double b) { return {a.v / b, a.d / b}; }
KOKKOS_INLINE_FUNCTION Dual operator/(double a, const Dual& b) {
  const double q = a / b.v;
  return {q, -q * b.d / b.v};
}
// comparisons read the value: the derivative follows the branch the value takes
KOKKOS_INLINE_FUNCTION bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
KOKKOS_INLINE_FUNCTION bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
KOKKOS_INLINE_FUNCTION bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
KOKKOS_INLINE_FUNCTION bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
KOKKOS_INLINE_FUNCTION bool operator==(const Dual& a, const Dual& b) { return a.v == b.v; }
KOKKOS_INLINE_FUNCTION bool operator!=(const Dual& a, const Dual& b) { return a.v != b.v; }

}  // namespace nacre::ad

namespace nacre::sc {

using ad::Dual;

/// \brief The value of a scalar (itself for double).
KOKKOS_INLINE_FUNCTION double value(double x) { return x; }
KOKKOS_INLINE_FUNCTION double value(const Dual& x) { return x.v; }

KOKKOS_INLINE_FUNCTION double sqrt(double x) { return Kokkos::sqrt(x); }
KOKKOS_INLINE_FUNCTION Dual sqrt(const Dual& x) {
  const double r = Kokkos::sqrt(x.v);
  return {r, r > 0.0 ? 0.5 * x.d / r : 0.0};  // (at 0 the one-sided derivative of a clamped 0 is 0)
}
KOKKOS_INLINE_FUNCTION double exp(double x) { return Kokkos::exp(x); }
KOKKOS_INLINE_FUNCTION double asinh(double x) { return Kokkos::asinh(x); }
KOKKOS_INLINE_FUNCTION double fabs(double x) { return Kokkos::fabs(x); }
KOKKOS_INLINE_FUNCTION Dual fabs(const Dual& x) { return x.v < 0.0 ? -x : x; }
KOKKOS_INLINE_FUNCTION double sin(double x) { return Kokkos::sin(x); }
KOKKOS_INLINE_FUNCTION Dual sin(const Dual& x) { return {Kokkos::sin(x.v), Kokkos::cos(x.v) * x.d}; }
KOKKOS_INLINE_FUNCTION double fmin(double a, double b) { return Kokkos::fmin(a, b); }
KOKKOS_INLINE_FUNCTION Dual fmin(const Dual& a, const Dual& b) { return b.v < a.v ? b : a; }
KOKKOS_INLINE_FUNCTION double fmax(double a, double b) { return Kokkos::fmax(a, b); }
KOKKOS_INLINE_FUNCTION Dual fmax(const Dual& a, const Dual& b) { return b.v > a.v ? b : a; }
KOKKOS_INLINE_FUNCTION double clamp(double x, double lo, double hi) { return Kokkos::clamp(x, lo, hi); }
KOKKOS_INLINE_FUNCTION Dual clamp(const Dual& x, double lo, double hi) {
  return x.v < lo ? Dual(lo) : x.v > hi ? Dual(hi) : x;
}
KOKKOS_INLINE_FUNCTION double copysign(double mag, double sgn) { return Kokkos::copysign(mag, sgn); }
KOKKOS_INLINE_FUNCTION Dual copysign(const Dual& mag, const Dual& sgn) {
  const double r = Kokkos::copysign(mag.v, sgn.v);
  const double s = (r < 0.0) == (mag.v < 0.0) ? 1.0 : -1.0;  // the sign flip applied to mag
  return {r, s * mag.d};
}

}  // namespace nacre::sc
