// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The cohesive law integrated exactly along one straight interface segment whose gap
/// varies linearly from one end to the other: energy and end forces from one piece loop.
///
/// Why exact, not a fixed Gauss rule: the density f(|g|) + g(dn) is only C1 where |g| crosses
/// x1, x2 or x1 + x2, or dn crosses 0, and a fixed rule is only algebraically accurate across such
/// a point (up to 2e-3 relative per interface with 4 points). Along a linear gap the branch
/// points are known in closed form: |g(s)|^2 = a s^2 + 2 b s + c is a convex quadratic, so
/// {s : |g(s)| <= r} is one interval (a quadratic's roots) and the intervals for r = x1, x2,
/// x1 + x2 are nested: the segment splits into at most 7 pieces whose branch is known from their
/// position (ruptured, softening, plateau, elastic, plateau, softening, ruptured), no sorting.
/// The penalty g(dn) has its own split: dn(s) is linear, so it is negative on one interval.
///
/// Per piece (rules and accuracy; tests/test_cohesive.cpp proves each against an independent
/// long-double reference):
///  - energy: closed form on every piece. Elastic: 0.5 k mean|g|^2, the mean of a quadratic
///    (exact); plateau / softening: polynomials in |g| and |g|^2, with the mean of |g| =
///    sqrt(p^2 + q^2) (p linear) in a cancellation-free form of its asinh antiderivative
///    (mean_norm); ruptured: constant; penalty: c dn^6 with dn linear, the mean of a sixth power
///    as a sum of same-sign terms. Relative error: a few ulps per piece.
///  - end forces: elastic and penalty pieces in closed form (polynomials), plateau and softening
///    pieces by 8-point Gauss-Legendre on sub-pieces graded away from the point nearest to zero
///    gap, each sub-piece no longer in gap than half the smallest |g| on it: the integrand's
///    singularities (|g| = 0, complex) then lie outside the Bernstein ellipse rho >= 8.1, so the
///    error is below rho^-16 ~ 3e-15 relative per sub-piece.
/// Forces are the integrals of the traction against the shape functions 1 - s and s; since the
/// density is continuous at every branch point, moving a branch point changes no integral to
/// first order, so these are the exact gradient of the energy (checked by finite differences).
///
/// Fast paths: a segment elastic along its whole length (|g| <= x1 at both ends; |g| is convex,
/// so then everywhere) takes 0.5 k L (|g0|^2 + g0.g1 + |g1|^2) / 3, and the penalty costs only a
/// sign test where dn >= 0 at both ends; where thermal jitter makes dn slightly negative at one
/// end (the common case) the penalty is one sixth power. No recursion; the only loop of variable
/// length is the graded sub-piece march of the forces (at most kMaxSubpieces).
#include <nacre/cohesive/law.hpp>
#include <nacre/core/dual.hpp>
#include <nacre/cohesive/quadrature.hpp>

namespace nacre::cohesive {

/// \brief Gap vectors at both segment ends (g0 at s = 0, g1 at s = 1; side b minus side a) and the
/// normal (a -> b), possibly unnormalised (see Law).
/// (T: double, or ad::Dual where the traction is differentiated: mc/hessian.hpp)
template <class T>
struct BasicGap {
  T g0x, g0y, g1x, g1y, nx, ny;
};
using Gap = BasicGap<double>;

/// \brief Generalised forces conjugate to the end gaps: f0 = dE/dg0, f1 = dE/dg1 at a fixed
/// normal, E the segment's energy. With g = u_b - u_a and a gap linear between the ends, the
/// joint pushes side b's end k with -fk and side a's end k with +fk (consistent nodal forces of
/// the linear shape functions 1 - s and s).
template <class T>
struct BasicEndForces {
  T f0x = 0.0, f0y = 0.0, f1x = 0.0, f1y = 0.0;
};
using EndForces = BasicEndForces<double>;

/// \brief True when the whole segment is in the elastic range of f (|gap| <= x1 at both ends,
/// hence everywhere) and does not penetrate (dn >= 0 at both ends, hence everywhere).
KOKKOS_INLINE_FUNCTION bool elastic_segment(const Law& m, const Gap& g) {
  const double d0 = g.g0x * g.g0x + g.g0y * g.g0y, d1 = g.g1x * g.g1x + g.g1y * g.g1y;
  const double x1sq = m.x1 * m.x1;
  return d0 <= x1sq && d1 <= x1sq && g.g0x * g.nx + g.g0y * g.ny >= 0.0 &&
         g.g1x * g.nx + g.g1y * g.ny >= 0.0;
}

namespace detail {

/// Most sub-pieces a plateau / softening piece is cut into for the forces (the graded march
/// needs about 3 + log_1.5((x1 + x2) / x1), 8 for x2 = 5 x1); the last one takes what is left.
inline constexpr int kMaxSubpieces = 64;

/// \brief The segment's |g(s)|^2 = a s^2 + 2 b s + c and its minimum over [0, 1].
template <class T>
struct Line {
  T dx, dy;       ///< g1 - g0
  T a, b, c, c1;  ///< coefficients; c1 = |g1|^2
  T cross;        ///< g0 x (g1 - g0): the line passes |cross| / sqrt(a) from zero gap
  T smin, r2min;  ///< argmin and minimum of |g(s)|^2 over [0, 1]
};

template <class T>
KOKKOS_INLINE_FUNCTION Line<T> make_line(const BasicGap<T>& g) {
  Line<T> l;
  l.dx = g.g1x - g.g0x, l.dy = g.g1y - g.g0y;
  l.a = l.dx * l.dx + l.dy * l.dy;
  l.b = g.g0x * l.dx + g.g0y * l.dy;
  l.c = g.g0x * g.g0x + g.g0y * g.g0y;
  l.c1 = g.g1x * g.g1x + g.g1y * g.g1y;
  l.cross = g.g0x * l.dy - g.g0y * l.dx;
  if (l.b >= 0.0) {  // |g| grows from s = 0 on (also a constant gap, a = 0)
    l.smin = 0.0, l.r2min = l.c;
  } else if (-l.b >= l.a) {  // still falling at s = 1
    l.smin = 1.0, l.r2min = l.c1;
  } else {  // the foot of the perpendicular from zero gap lies inside
    l.smin = -l.b / l.a;
    l.r2min = sc::fmin(l.cross * l.cross / l.a, sc::fmin(l.c, l.c1));
  }
  return l;
}

/// \brief {s in [0, 1] : |g(s)|^2 <= r2} = [lo, hi]. An empty set collapses onto smin, so the
/// intervals of increasing r2 are nested.
template <class T>
KOKKOS_INLINE_FUNCTION void sublevel(const Line<T>& l, double r2, T& lo, T& hi) {
  if (r2 <= l.r2min) {
    lo = hi = l.smin;
    return;
  }
  const bool in0 = l.c <= r2, in1 = l.c1 <= r2;
  if (in0 && in1) {  // convex: inside at both ends, inside everywhere
    lo = 0.0, hi = 1.0;
    return;
  }
  // roots of a s^2 + 2 b s + (c - r2) = 0 (a > 0 here); b^2 - a (c - r2) = a r2 - cross^2;
  // the stable pair q / a, (c - r2) / q avoids cancelling -b against the root of the discriminant
  const T disc = sc::sqrt(sc::fmax(l.a * r2 - l.cross * l.cross, 0.0));
  const T q = -(l.b + sc::copysign(disc, l.b));
  const T s1 = q / l.a, s2 = q != 0.0 ? (l.c - r2) / q : s1;
  lo = in0 ? 0.0 : sc::clamp(sc::fmin(s1, s2), 0.0, 1.0);
  hi = in1 ? 1.0 : sc::clamp(sc::fmax(s1, s2), 0.0, 1.0);
}

/// \brief Boundaries of the 7 pieces of f: piece j = [s[j], s[j+1]] has branch
/// branch_of(j) = 3 2 1 0 1 2 3 (0 elastic, 1 plateau, 2 softening, 3 ruptured).
template <class T>
struct Pieces {
  T s[8];
};
KOKKOS_INLINE_FUNCTION constexpr int branch_of(int j) { return j < 4 ? 3 - j : j - 3; }

template <class T>
KOKKOS_INLINE_FUNCTION Pieces<T> f_pieces(const Law& m, const Line<T>& l) {
  T lo1, hi1, lo2, hi2, lo3, hi3;
  const double x12 = m.x1 + m.x2;
  sublevel(l, m.x1 * m.x1, lo1, hi1);
  sublevel(l, m.x2 * m.x2, lo2, hi2);
  sublevel(l, x12 * x12, lo3, hi3);
  Pieces<T> p;  // nested by construction; the max() only keeps rounding from reordering them
  p.s[0] = 0.0;
  p.s[1] = lo3;
  p.s[2] = sc::fmax(lo2, p.s[1]);
  p.s[3] = sc::fmax(lo1, p.s[2]);
  p.s[4] = sc::fmax(hi1, p.s[3]);
  p.s[5] = sc::fmax(hi2, p.s[4]);
  p.s[6] = sc::fmax(hi3, p.s[5]);
  p.s[7] = 1.0;
  return p;
}

/// \brief asinh(x) / x, 1 at 0.
template <class T>
KOKKOS_INLINE_FUNCTION T asinhc(const T& x) {
  return x != 0.0 ? sc::asinh(x) / x : T(1.0);
}

/// \brief Twice the antiderivative of sqrt(p^2 + q^2) (q2 = q^2, r = sqrt(p^2 + q^2)): odd in p.
template <class T>
KOKKOS_INLINE_FUNCTION T norm_antiderivative2(const T& p, const T& r, const T& q, const T& q2) {
  return p * r + (q2 > 0.0 ? q2 * sc::asinh(p / q) : T(0.0));
}

/// \brief Mean of sqrt(p^2 + q^2) for p linear from pa to pb = pa + dl (dl >= 0), ra and rb its
/// values at the ends. The textbook difference of antiderivatives cancels when dl is small
/// against |p|; rewritten with
///   (pb rb - pa ra) / dl = (pa + pb)(pa^2 + pb^2 + q^2) / (pb rb + pa ra),
///   asinh(pb / q) - asinh(pa / q) = asinh(dl (pa + pb) / (pb ra + pa rb))
/// (pa, pb of one sign), every sum is of same-sign terms; of opposite signs the antiderivative
/// is odd, so its difference is a sum too.
template <class T>
KOKKOS_INLINE_FUNCTION T mean_norm(const T& pa, const T& pb, const T& q, const T& ra, const T& rb, const T& dl) {
  if (!(dl > 0.0)) return 0.5 * (ra + rb);
  const T q2 = q * q;
  if (pa * pb >= 0.0) {
    if (!(q2 > 0.0)) return 0.5 * sc::fabs(pa + pb);
    const T z = (pa + pb) / (pb * ra + pa * rb);
    return 0.5 * ((pa + pb) * (pa * pa + pb * pb + q2) / (pb * rb + pa * ra) + q2 * z * asinhc(dl * z));
  }
  return 0.5 * (norm_antiderivative2(pb, rb, q, q2) + norm_antiderivative2(-pa, ra, q, q2)) / dl;
}

/// \brief Integral over [0, 1] of f(|g(s)|) along a segment that is not elastic everywhere:
/// the closed form of each piece.
template <class T>
KOKKOS_INLINE_FUNCTION T f_integral(const Law& m, const BasicGap<T>& g) {
  const Line<T> l = make_line(g);
  const Pieces<T> p = f_pieces(m, l);
  const double x12 = m.x1 + m.x2;
  const T len = sc::sqrt(l.a), inv = len > 0.0 ? 1.0 / len : T(0.0);
  const T q = sc::fabs(l.cross) * inv;
  T e = 0.0;
  for (int j = 0; j < 7; ++j) {
    const T sa = p.s[j], sb = p.s[j + 1], ds = sb - sa;
    if (!(ds > 0.0)) continue;
    const int br = branch_of(j);
    if (br == 3) {
      e += ds * m.k * m.x1 * m.x2;
      continue;
    }
    const T gax = g.g0x + sa * l.dx, gay = g.g0y + sa * l.dy;
    const T gbx = g.g0x + sb * l.dx, gby = g.g0y + sb * l.dy;
    const T da = gax * gax + gay * gay, db = gbx * gbx + gby * gby;
    const T mean_sq = (da + gax * gbx + gay * gby + db) * (1.0 / 3.0);  // exact for a quadratic
    if (br == 0) {
      e += ds * 0.5 * m.k * mean_sq;
      continue;
    }
    const T pa = (gax * l.dx + gay * l.dy) * inv, pb = (gbx * l.dx + gby * l.dy) * inv;
    const T mean = mean_norm(pa, pb, q, sc::sqrt(da), sc::sqrt(db), ds * len);
    if (br == 1) e += ds * m.k * m.x1 * (mean - 0.5 * m.x1);
    else e += ds * m.k * (m.x1 * m.x2 - 0.5 * (x12 * x12 - 2.0 * x12 * mean + mean_sq));  // k x1 x2 - k (x12 - |g|)^2 / 2
  }
  return e;
}

/// \brief Where the normal opening is negative: s in [sa, sb], dn(sa) = da, dn(sb) = db (unit
/// normal). False when it is >= 0 everywhere.
template <class T>
KOKKOS_INLINE_FUNCTION bool penetration(const BasicGap<T>& g, T& sa, T& sb, T& da, T& db) {
  const T a0 = g.g0x * g.nx + g.g0y * g.ny, a1 = g.g1x * g.nx + g.g1y * g.ny;
  if (a0 >= 0.0 && a1 >= 0.0) return false;
  sa = 0.0, sb = 1.0, da = a0, db = a1;
  if (a0 >= 0.0) sa = a0 / (a0 - a1), da = 0.0;       // enters at the root of the linear dn
  else if (a1 >= 0.0) sb = a0 / (a0 - a1), db = 0.0;  // leaves at it
  const T inv = 1.0 / sc::sqrt(g.nx * g.nx + g.ny * g.ny);
  da *= inv, db *= inv;
  return true;
}

/// \brief Integral over [0, 1] of the penalty g(dn(s)) = k dn^6 / (16 x1^4): the mean of the sixth
/// power of a linear function is (sum_i da^(6-i) db^i) / 7, a sum of non-negative terms.
/// With dn = a / |n| (a the unnormalised opening, linear from a0 to a1) every factor is folded
/// into one quotient, so the integral costs one division and no square root:
///  - both ends penetrate: (sum_i a0^(6-i) a1^i) / (7 n2^3) (n2 = |n|^2; the terms of two
///    negative numbers of even total degree are non-negative);
///  - one end a < 0, the other a' >= 0: dn < 0 on the fraction a / (a - a') of the segment, where
///    the mean of dn^6 is a^6 / (7 n2^3): a^7 / ((a - a') 7 n2^3).
/// Thermal jitter puts most elastic interfaces in the second case, so this is on the sweep's
/// hot path (before: a division for the root, a square root and a division for 1 / |n|, and
/// 1 / x1: three divisions and a root per interface).
/// Precondition: the normal is near unit length (every caller's is: a unit normal turned by a
/// small angle, or unit): 7 n2^3 x1^4 must not underflow, or a penetrating end gives 0 / 0.
template <class T>
KOKKOS_INLINE_FUNCTION T penalty_integral(const Law& m, const BasicGap<T>& g) {
  const T a0 = g.g0x * g.nx + g.g0y * g.ny, a1 = g.g1x * g.nx + g.g1y * g.ny;
  if (a0 >= 0.0 && a1 >= 0.0) return T(0.0);
  const T n2 = g.nx * g.nx + g.ny * g.ny;
  const double x1sq = m.x1 * m.x1;
  const T den = 7.0 * (n2 * n2 * n2) * (x1sq * x1sq);
  if (a0 < 0.0 && a1 < 0.0) {
    const T a2 = a0 * a0, a3 = a2 * a0, b2 = a1 * a1, b3 = b2 * a1;
    const T num = a3 * a3 + a3 * a2 * a1 + a2 * a2 * b2 + a3 * b3 + a2 * b2 * b2 + a0 * b2 * b3 + b3 * b3;
    return 0.0625 * m.k * num / den;
  }
  const T a = a0 < 0.0 ? a0 : a1, other = a0 < 0.0 ? a1 : a0;  // a < 0 <= other
  const T a2 = a * a, a7 = a2 * a2 * a2 * a;
  // a^7 underflows to zero for |a| below ~1e-44 (the gaps ahead of an elastic wave's front are
  // subnormal), and (a - other) den can with it: 0 / 0 made the energy NaN (a 98,603-brick BE
  // run stopped at step 72, forces finite). The energy there is zero to 1e-290 of k.
  if (a7 >= 0.0) return T(0.0);  // (a NaN gap still gives NaN)
  return 0.0625 * m.k * a7 / ((a - other) * den);
}

/// \brief End forces of the penalty (unit segment length): the traction g'(dn) n / |n| against
/// 1 - s and s; with dn linear from da to db on [sa, sb] (t the local parameter),
/// int dn^5 (1 - t) dt = sum_i (6 - i) da^(5-i) db^i / 42 and int dn^5 t dt = sum_i (i + 1) da^(5-i) db^i / 42.
template <class T>
KOKKOS_INLINE_FUNCTION void penalty_forces(const Law& m, const BasicGap<T>& g, BasicEndForces<T>& f) {
  T sa, sb, da, db;
  if (!penetration(g, sa, sb, da, db)) return;
  T ia, ib;  // int dn^5 (1 - t) dt, int dn^5 t dt
  if (db == 0.0) {
    const T a2 = da * da, a5 = a2 * a2 * da;
    ia = a5 * (6.0 / 42.0), ib = a5 * (1.0 / 42.0);
  } else if (da == 0.0) {
    const T b2 = db * db, b5 = b2 * b2 * db;
    ia = b5 * (1.0 / 42.0), ib = b5 * (6.0 / 42.0);
  } else {
    const T a2 = da * da, a3 = a2 * da, a4 = a2 * a2, a5 = a4 * da;
    const T b2 = db * db, b3 = b2 * db, b4 = b2 * b2, b5 = b4 * db;
    ia = (6.0 * a5 + 5.0 * a4 * db + 4.0 * a3 * b2 + 3.0 * a2 * b3 + 2.0 * da * b4 + b5) * (1.0 / 42.0);
    ib = (a5 + 2.0 * a4 * db + 3.0 * a3 * b2 + 4.0 * a2 * b3 + 5.0 * da * b4 + 6.0 * b5) * (1.0 / 42.0);
  }
  const double r = 1.0 / m.x1, r2 = r * r;
  const T c = (sb - sa) * 0.375 * m.k * r2 * r2;  // g'(x) = 0.375 k x^5 / x1^4
  const T inv = 1.0 / sc::sqrt(g.nx * g.nx + g.ny * g.ny);
  const T w0 = c * ((1.0 - sa) * ia + (1.0 - sb) * ib) * inv, w1 = c * (sa * ia + sb * ib) * inv;
  f.f0x += w0 * g.nx, f.f0y += w0 * g.ny;
  f.f1x += w1 * g.nx, f.f1y += w1 * g.ny;
}

/// \brief 8-point Gauss-Legendre on [u, v] of the plateau (br = 1) or softening (br = 2) traction
/// f'(|g|) g / |g| against 1 - s and s.
template <class T>
KOKKOS_INLINE_FUNCTION void gauss8_traction(const Law& m, int br, const BasicGap<T>& g, const Line<T>& l, const T& u,
                                            const T& v, BasicEndForces<T>& f) {
  // nodes +-x_i and weights w_i on [-1, 1]
  const double x[4] = {0.18343464249564980494, 0.52553240991632898582, 0.79666647741362673959,
                       0.96028985649753623168};
  const double w[4] = {0.36268378337836198297, 0.31370664587788728734, 0.22238103445337447054,
                       0.10122853629037625915};
  const T mid = 0.5 * (u + v), half = 0.5 * (v - u);
  const double x12 = m.x1 + m.x2;
  for (int i = 0; i < 8; ++i) {
    const T s = mid + (i < 4 ? -half * x[i] : half * x[i - 4]);
    const T gx = g.g0x + s * l.dx, gy = g.g0y + s * l.dy;
    const T r = sc::sqrt(gx * gx + gy * gy);
    const T slope = br == 1 ? T(m.k * m.x1) : m.k * (x12 - r);  // f'(|g|)
    const T c = w[i & 3] * half * slope / r;
    const T c0 = c * (1.0 - s), c1 = c * s;
    f.f0x += c0 * gx, f.f0y += c0 * gy;
    f.f1x += c1 * gx, f.f1y += c1 * gy;
  }
}

/// \brief Forces of a plateau / softening stretch [from, to] along which |g| grows from `from`
/// (the end nearest the foot of the perpendicular from zero gap): sub-pieces no longer in gap
/// than half of |g| at their start, so each is far from the complex zeros of |g|.
template <class T>
KOKKOS_INLINE_FUNCTION void graded_traction(const Law& m, int br, const BasicGap<T>& g, const Line<T>& l, const T& from,
                                            const T& to, BasicEndForces<T>& f) {
  const T len = sc::sqrt(l.a);
  T s = from, left = sc::fabs(to - from);
  const double dir = to >= from ? 1.0 : -1.0;
  for (int it = 0; it < kMaxSubpieces && left > 0.0; ++it) {
    const T gx = g.g0x + s * l.dx, gy = g.g0y + s * l.dy;
    const T h =
        (it == kMaxSubpieces - 1 || !(len > 0.0)) ? left : sc::fmin(left, 0.5 * sc::sqrt(gx * gx + gy * gy) / len);
    const T next = h >= left ? to : s + dir * h;
    gauss8_traction(m, br, g, l, sc::fmin(s, next), sc::fmax(s, next), f);
    s = next, left -= h;
  }
}

/// \brief End forces of f along a segment that is not elastic everywhere (unit length).
template <class T>
KOKKOS_INLINE_FUNCTION void f_forces(const Law& m, const BasicGap<T>& g, BasicEndForces<T>& f) {
  const Line<T> l = make_line(g);
  const Pieces<T> p = f_pieces(m, l);
  // foot of the perpendicular from zero gap (|g| is smallest there along the whole line)
  const T foot = l.a > 0.0 ? -l.b / l.a : T(0.0);
  for (int j = 0; j < 7; ++j) {
    const T sa = p.s[j], sb = p.s[j + 1], ds = sb - sa;
    if (!(ds > 0.0)) continue;
    const int br = branch_of(j);
    if (br == 3) continue;  // ruptured: no traction
    if (br == 0) {  // k g(s) against 1 - s and s: exact for the quadratic integrands
      const T gax = g.g0x + sa * l.dx, gay = g.g0y + sa * l.dy;
      const T gbx = g.g0x + sb * l.dx, gby = g.g0y + sb * l.dy;
      const T c = ds * m.k * (1.0 / 6.0);
      // int (ga (1-t) + gb t)(pa (1-t) + pb t) dt = (2 ga pa + ga pb + gb pa + 2 gb pb) / 6
      const T a0 = 2.0 * (1.0 - sa) + (1.0 - sb), b0 = (1.0 - sa) + 2.0 * (1.0 - sb);
      const T a1 = 2.0 * sa + sb, b1 = sa + 2.0 * sb;
      f.f0x += c * (a0 * gax + b0 * gbx), f.f0y += c * (a0 * gay + b0 * gby);
      f.f1x += c * (a1 * gax + b1 * gbx), f.f1y += c * (a1 * gay + b1 * gby);
      continue;
    }
    if (foot > sa && foot < sb) {  // |g| falls then rises: march outwards from the foot
      graded_traction(m, br, g, l, foot, sa, f);
      graded_traction(m, br, g, l, foot, sb, f);
    } else if (foot <= sa) {
      graded_traction(m, br, g, l, sa, sb, f);
    } else {
      graded_traction(m, br, g, l, sb, sa, f);
    }
  }
}

}  // namespace detail

/// \brief Energy of a segment of the given length: the exact integral of the density along it.
/// (T: double, or flops::Counted where a trial's flops are counted: mc/trial_flops.hpp)
template <class T>
KOKKOS_INLINE_FUNCTION T integrate(EnergyTag, const Law& m, const BasicGap<T>& g, double length) {
  const T d0 = g.g0x * g.g0x + g.g0y * g.g0y, d1 = g.g1x * g.g1x + g.g1y * g.g1y;
  const double x1sq = m.x1 * m.x1;
  const T ef = (d0 <= x1sq && d1 <= x1sq) ? m.k * (d0 + g.g0x * g.g1x + g.g0y * g.g1y + d1) * (1.0 / 6.0)
                                          : detail::f_integral(m, g);
  return length * (ef + detail::penalty_integral(m, g));
}

/// \brief End forces of a segment of the given length: the gradient of integrate(EnergyTag, ...)
/// with respect to the end gaps (the traction integrated against 1 - s and s over the same pieces).
template <class T>
KOKKOS_INLINE_FUNCTION BasicEndForces<T> integrate(TractionTag, const Law& m, const BasicGap<T>& g, double length) {
  BasicEndForces<T> f;
  const T d0 = g.g0x * g.g0x + g.g0y * g.g0y, d1 = g.g1x * g.g1x + g.g1y * g.g1y;
  const double x1sq = m.x1 * m.x1;
  if (d0 <= x1sq && d1 <= x1sq) {  // traction k g(s): integrals of (1 - s) and s against a linear g
    const double c = m.k * (1.0 / 6.0);
    f.f0x = c * (2.0 * g.g0x + g.g1x), f.f0y = c * (2.0 * g.g0y + g.g1y);
    f.f1x = c * (g.g0x + 2.0 * g.g1x), f.f1y = c * (g.g0y + 2.0 * g.g1y);
  } else {
    detail::f_forces(m, g, f);
  }
  detail::penalty_forces(m, g, f);
  f.f0x *= length, f.f0y *= length, f.f1x *= length, f.f1y *= length;
  return f;
}

/// \brief Energy of a segment (integrate(EnergyTag{}, ...)).
KOKKOS_INLINE_FUNCTION double segment_energy(const Law& m, const Gap& g, double length) {
  return integrate(EnergyTag{}, m, g, length);
}

/// \brief Smallest separation over the whole segment, exactly: |g(s)| at the foot of the
/// perpendicular from zero gap, or at the nearer end. The interface is ruptured when even this
/// has reached x1 + x2.
KOKKOS_INLINE_FUNCTION double min_separation(const Gap& g) {
  return Kokkos::sqrt(detail::make_line(g).r2min);
}

/// \brief Largest separation at the segment ends (|gap| is convex, so the max is at an end).
KOKKOS_INLINE_FUNCTION double max_separation(const Gap& g) {
  return Kokkos::fmax(Kokkos::sqrt(g.g0x * g.g0x + g.g0y * g.g0y),
                      Kokkos::sqrt(g.g1x * g.g1x + g.g1y * g.g1y));
}

// ---- The signatures with a quadrature rule, from before integration was exact: the rule is no
// longer used along a linear gap; kept so that callers written against them still compile.
KOKKOS_INLINE_FUNCTION double integrate(EnergyTag t, const Law& m, const Quadrature&, const Gap& g, double length) {
  return integrate(t, m, g, length);
}
KOKKOS_INLINE_FUNCTION EndForces integrate(TractionTag t, const Law& m, const Quadrature&, const Gap& g,
                                           double length) {
  return integrate(t, m, g, length);
}
KOKKOS_INLINE_FUNCTION double segment_energy(const Law& m, const Quadrature&, const Gap& g, double length) {
  return integrate(EnergyTag{}, m, g, length);
}
KOKKOS_INLINE_FUNCTION double min_separation(const Quadrature&, const Gap& g) { return min_separation(g); }

}  // namespace nacre::cohesive
