// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief A scalar that counts the floating-point operations done on it (host only), for the
/// flops of one unit of work: the fraction of a backend's FMA bound that `nacre bench` reports.
///
/// Why count by running the code, not by hand: a Monte Carlo trial's arithmetic depends on the
/// state (the elastic fast path of a segment, or up to 7 pieces with square roots and asinh; the
/// penalty only where an end penetrates), so a hand count is right for one state at most and
/// drifts when the code changes. The cohesive energy and the rigid kinematics are templated on
/// the scalar (for the Newton method's dual numbers, core/dual.hpp); run on `Counted`, the same
/// source counts its own operations on the state it is given.
///
/// Convention (docs/design.md "Backends"): + - * / and sqrt are one flop each (an FMA is two, as
/// the bench's FMA loop counts it), a transcendental function (exp, asinh, sin, cos)
/// kTranscendentalFlops; comparisons, fabs, fmin / fmax, copysign and clamps none. Products of
/// constants that are plain `double`s (law constants) are not counted: a compiler hoists them.
/// On the device `Counted` is never used (the counting operators only count on the host).
#include <Kokkos_Core.hpp>

namespace nacre::flops {

/// Flops charged to one transcendental function call (exp, asinh, sin, cos): about what a
/// vectorised libm spends in polynomial and range-reduction arithmetic.
inline constexpr double kTranscendentalFlops = 20.0;

/// \brief Operations counted by kind.
struct Counts {
  double add = 0, mul = 0, div = 0, sqrt = 0, transcendental = 0;
  [[nodiscard]] double flops() const { return add + mul + div + sqrt + kTranscendentalFlops * transcendental; }
};

/// \brief The running tally `Counted` adds to (host; one thread counts at a time).
inline Counts& tally() {
  static Counts c;
  return c;
}

/// \brief Counts `f()`'s operations on `Counted`: the tally before and after.
template <class F>
Counts count(F&& f) {
  const Counts before = tally();
  f();
  const Counts& after = tally();
  return {after.add - before.add, after.mul - before.mul, after.div - before.div, after.sqrt - before.sqrt,
          after.transcendental - before.transcendental};
}

// On the device the counting branch is compiled out (Counted never runs there; the operators are
// annotated only so that templated host-device code can be instantiated with it without warnings).
#define NACRE_FLOPS_COUNT(field) KOKKOS_IF_ON_HOST((::nacre::flops::tally().field += 1.0;))

/// \brief A double that counts the operations done on it.
struct Counted {
  double v = 0.0;
  constexpr Counted() = default;  // (no annotation: nvcc ignores one on a defaulted constructor)
  KOKKOS_INLINE_FUNCTION constexpr Counted(double x) : v(x) {}  // NOLINT: constants promote
  KOKKOS_INLINE_FUNCTION Counted& operator+=(const Counted& o) {
    NACRE_FLOPS_COUNT(add)
    v += o.v;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Counted& operator-=(const Counted& o) {
    NACRE_FLOPS_COUNT(add)
    v -= o.v;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Counted& operator*=(const Counted& o) {
    NACRE_FLOPS_COUNT(mul)
    v *= o.v;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Counted& operator/=(const Counted& o) {
    NACRE_FLOPS_COUNT(div)
    v /= o.v;
    return *this;
  }
};

KOKKOS_INLINE_FUNCTION Counted operator-(const Counted& a) { return {-a.v}; }
KOKKOS_INLINE_FUNCTION Counted operator+(Counted a, const Counted& b) { return a += b; }
KOKKOS_INLINE_FUNCTION Counted operator-(Counted a, const Counted& b) { return a -= b; }
KOKKOS_INLINE_FUNCTION Counted operator*(Counted a, const Counted& b) { return a *= b; }
KOKKOS_INLINE_FUNCTION Counted operator/(Counted a, const Counted& b) { return a /= b; }
KOKKOS_INLINE_FUNCTION Counted operator+(Counted a, double b) { return a += Counted(b); }
KOKKOS_INLINE_FUNCTION Counted operator+(double a, Counted b) { return b += Counted(a); }
KOKKOS_INLINE_FUNCTION Counted operator-(Counted a, double b) { return a -= Counted(b); }
KOKKOS_INLINE_FUNCTION Counted operator-(double a, const Counted& b) { return Counted(a) -= b; }
KOKKOS_INLINE_FUNCTION Counted operator*(Counted a, double b) { return a *= Counted(b); }
KOKKOS_INLINE_FUNCTION Counted operator*(double a, Counted b) { return b *= Counted(a); }
KOKKOS_INLINE_FUNCTION Counted operator/(Counted a, double b) { return a /= Counted(b); }
KOKKOS_INLINE_FUNCTION Counted operator/(double a, const Counted& b) { return Counted(a) /= b; }
KOKKOS_INLINE_FUNCTION bool operator<(const Counted& a, const Counted& b) { return a.v < b.v; }
KOKKOS_INLINE_FUNCTION bool operator<=(const Counted& a, const Counted& b) { return a.v <= b.v; }
KOKKOS_INLINE_FUNCTION bool operator>(const Counted& a, const Counted& b) { return a.v > b.v; }
KOKKOS_INLINE_FUNCTION bool operator>=(const Counted& a, const Counted& b) { return a.v >= b.v; }
KOKKOS_INLINE_FUNCTION bool operator==(const Counted& a, const Counted& b) { return a.v == b.v; }
KOKKOS_INLINE_FUNCTION bool operator!=(const Counted& a, const Counted& b) { return a.v != b.v; }

}  // namespace nacre::flops

namespace nacre::sc {

using flops::Counted;

// The scalar functions of core/dual.hpp for Counted: the value is the double function's.
KOKKOS_INLINE_FUNCTION double value(const Counted& x) { return x.v; }
KOKKOS_INLINE_FUNCTION Counted sqrt(const Counted& x) {
  NACRE_FLOPS_COUNT(sqrt)
  return {Kokkos::sqrt(x.v)};
}
KOKKOS_INLINE_FUNCTION Counted exp(const Counted& x) {
  NACRE_FLOPS_COUNT(transcendental)
  return {Kokkos::exp(x.v)};
}
KOKKOS_INLINE_FUNCTION Counted asinh(const Counted& x) {
  NACRE_FLOPS_COUNT(transcendental)
  return {Kokkos::asinh(x.v)};
}
KOKKOS_INLINE_FUNCTION Counted sin(const Counted& x) {
  NACRE_FLOPS_COUNT(transcendental)
  return {Kokkos::sin(x.v)};
}
KOKKOS_INLINE_FUNCTION Counted cos(const Counted& x) {
  NACRE_FLOPS_COUNT(transcendental)
  return {Kokkos::cos(x.v)};
}
KOKKOS_INLINE_FUNCTION Counted fabs(const Counted& x) { return {Kokkos::fabs(x.v)}; }
KOKKOS_INLINE_FUNCTION Counted fmin(const Counted& a, const Counted& b) { return {Kokkos::fmin(a.v, b.v)}; }
KOKKOS_INLINE_FUNCTION Counted fmax(const Counted& a, const Counted& b) { return {Kokkos::fmax(a.v, b.v)}; }
KOKKOS_INLINE_FUNCTION Counted clamp(const Counted& x, double lo, double hi) { return {Kokkos::clamp(x.v, lo, hi)}; }
KOKKOS_INLINE_FUNCTION Counted copysign(const Counted& mag, const Counted& sgn) {
  return {Kokkos::copysign(mag.v, sgn.v)};
}

}  // namespace nacre::sc

#undef NACRE_FLOPS_COUNT
