#pragma once
/// \file
/// \brief The cohesive law integrated along one straight interface segment whose gap varies
/// linearly from one end to the other: energy and end forces from one quadrature loop.
///
/// The gap is linear along the segment for rigid bricks (kinematics/rigid.hpp) and along the
/// shared edge of two constant-strain triangles, so both solver families integrate here.
/// Most segments are elastic: when |gap| <= x1 at both ends (|gap| is convex along the segment,
/// so then everywhere) and the normal opening is >= 0 at both ends (it is linear, so then
/// everywhere), the density is k |gap(s)|^2 / 2 and both integrals are exact in closed form.
/// Only the other segments use the quadrature rule (see quadrature.hpp for its accuracy).
#include <nacre/cohesive/law.hpp>
#include <nacre/cohesive/quadrature.hpp>

namespace nacre::cohesive {

/// \brief Gap vectors at both segment ends (g0 at s = 0, g1 at s = 1; side b minus side a) and the
/// normal (a -> b), possibly unnormalised (see Law).
struct Gap {
  double g0x, g0y, g1x, g1y, nx, ny;
};

/// \brief Generalised forces conjugate to the end gaps: f0 = dE/dg0, f1 = dE/dg1 at a fixed
/// normal, E the segment's energy. With g = u_b - u_a and a gap linear between the ends, the
/// joint pushes side b's end k with -fk and side a's end k with +fk (consistent nodal forces of
/// the linear shape functions 1 - s and s).
struct EndForces {
  double f0x = 0, f0y = 0, f1x = 0, f1y = 0;
};

/// \brief True when the whole segment is in the elastic range, not penetrating (closed form).
KOKKOS_INLINE_FUNCTION bool elastic_segment(const Law& m, const Gap& g) {
  const double d0 = g.g0x * g.g0x + g.g0y * g.g0y, d1 = g.g1x * g.g1x + g.g1y * g.g1y;
  const double x1sq = m.x1 * m.x1;
  return d0 <= x1sq && d1 <= x1sq && g.g0x * g.nx + g.g0y * g.ny >= 0.0 &&
         g.g1x * g.nx + g.g1y * g.ny >= 0.0;
}

namespace detail {
/// Energy accumulator of the quadrature loop.
struct EnergySum {
  double e = 0.0;
  KOKKOS_INLINE_FUNCTION void add(const Law& m, double w, double, double gx, double gy, double nx, double ny) {
    e += w * m(EnergyTag{}, gx, gy, nx, ny);
  }
};
/// End-force accumulator of the quadrature loop (shape functions 1 - s and s).
struct ForceSum {
  EndForces f;
  KOKKOS_INLINE_FUNCTION void add(const Law& m, double w, double s, double gx, double gy, double nx, double ny) {
    double tx, ty;
    m(TractionTag{}, gx, gy, nx, ny, tx, ty);
    const double w0 = w * (1.0 - s), w1 = w * s;
    f.f0x += w0 * tx, f.f0y += w0 * ty;
    f.f1x += w1 * tx, f.f1y += w1 * ty;
  }
};
}  // namespace detail

/// \brief The one quadrature loop: acc.add(law, weight, s, gap(s), normal) at each point.
template <class Accumulator>
KOKKOS_INLINE_FUNCTION void quadrature_loop(const Law& m, const Quadrature& q, const Gap& g, Accumulator& acc) {
  for (int k = 0; k < q.n; ++k) {
    const double s = q.s[k];
    const double gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
    acc.add(m, q.w[k], s, gx, gy, g.nx, g.ny);
  }
}

/// \brief Energy of a segment of the given length: the integral of the density along it.
KOKKOS_INLINE_FUNCTION double integrate(EnergyTag, const Law& m, const Quadrature& q, const Gap& g, double length) {
  if (elastic_segment(m, g)) {
    const double d0 = g.g0x * g.g0x + g.g0y * g.g0y, d1 = g.g1x * g.g1x + g.g1y * g.g1y;
    return length * m.k * (d0 + g.g0x * g.g1x + g.g0y * g.g1y + d1) * (1.0 / 6.0);
  }
  detail::EnergySum acc;
  quadrature_loop(m, q, g, acc);
  return acc.e * length;
}

/// \brief End forces of a segment of the given length (the gradient of integrate(EnergyTag, ...)
/// with respect to the end gaps, exactly that of the same rule).
KOKKOS_INLINE_FUNCTION EndForces integrate(TractionTag, const Law& m, const Quadrature& q, const Gap& g,
                                           double length) {
  EndForces f;
  if (elastic_segment(m, g)) {  // traction k g(s): integrals of (1 - s) and s against a linear g
    const double c = length * m.k * (1.0 / 6.0);
    f.f0x = c * (2.0 * g.g0x + g.g1x), f.f0y = c * (2.0 * g.g0y + g.g1y);
    f.f1x = c * (g.g0x + 2.0 * g.g1x), f.f1y = c * (g.g0y + 2.0 * g.g1y);
    return f;
  }
  detail::ForceSum acc;
  quadrature_loop(m, q, g, acc);
  f = acc.f;
  f.f0x *= length, f.f0y *= length, f.f1x *= length, f.f1y *= length;
  return f;
}

/// \brief Energy of a segment (integrate(EnergyTag{}, ...)).
KOKKOS_INLINE_FUNCTION double segment_energy(const Law& m, const Quadrature& q, const Gap& g, double length) {
  return integrate(EnergyTag{}, m, q, g, length);
}

/// \brief Smallest separation over the quadrature points: the interface is ruptured when even
/// this has reached x1 + x2 (|gap| is convex along the segment, so this is a fair minimum).
KOKKOS_INLINE_FUNCTION double min_separation(const Quadrature& q, const Gap& g) {
  double dmin = 1e300;
  for (int k = 0; k < q.n; ++k) {
    const double s = q.s[k];
    const double gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
    dmin = Kokkos::fmin(dmin, Kokkos::sqrt(gx * gx + gy * gy));
  }
  return dmin;
}

/// \brief Largest separation at the segment ends (|gap| is convex, so the max is at an end).
KOKKOS_INLINE_FUNCTION double max_separation(const Gap& g) {
  return Kokkos::fmax(Kokkos::sqrt(g.g0x * g.g0x + g.g0y * g.g0y),
                      Kokkos::sqrt(g.g1x * g.g1x + g.g1y * g.g1y));
}

}  // namespace nacre::cohesive
