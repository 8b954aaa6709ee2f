#pragma once
/// \file
/// \brief Energy of one rigid-brick interface: the law integrated along the shared segment.
#include <nacre/cohesive/law.hpp>
#include <nacre/cohesive/quadrature.hpp>

namespace nacre::cohesive {

/// \brief Rigid-body displacement of a brick: translation of its centroid and rotation about it.
struct Pose {
  double x, y, t;
};

/// \brief Displacement of the material point at r (relative to the centroid) of a brick in pose p.
/// (R(t) - I) r is written with cos t - 1 = -2 sin^2(t/2) so tiny rotations lose no digits.
KOKKOS_INLINE_FUNCTION void point_displacement(const Pose& p, double rx, double ry, double& dx,
                                               double& dy) {
  const double s = Kokkos::sin(p.t), h = Kokkos::sin(0.5 * p.t), cm1 = -2.0 * h * h;
  dx = p.x + cm1 * rx - s * ry;
  dy = p.y + s * rx + cm1 * ry;
}

/// \brief Geometry of one interface as seen by the energy: segment ends in both bricks' frames,
/// reference normal (a -> b) and length.
struct Segment {
  double ra0x, ra0y, ra1x, ra1y;
  double rb0x, rb0y, rb1x, rb1y;
  double nx, ny, length;
};

/// \brief Gap vectors (displacement of b minus displacement of a) at both segment ends and the
/// current normal. The normal turns with the mean rotation tm of the two bricks: n + tm n_perp,
/// normalised (a rotation by atan(tm) ~ tm, with no trigonometry in the inner loop).
struct Gap {
  double g0x, g0y, g1x, g1y, nx, ny;
};

KOKKOS_INLINE_FUNCTION Gap interface_gap(const Segment& sg, const Pose& a, const Pose& b) {
  double a0x, a0y, a1x, a1y, b0x, b0y, b1x, b1y;
  point_displacement(a, sg.ra0x, sg.ra0y, a0x, a0y);
  point_displacement(a, sg.ra1x, sg.ra1y, a1x, a1y);
  point_displacement(b, sg.rb0x, sg.rb0y, b0x, b0y);
  point_displacement(b, sg.rb1x, sg.rb1y, b1x, b1y);
  const double tm = 0.5 * (a.t + b.t), inv = 1.0 / Kokkos::sqrt(1.0 + tm * tm);
  return Gap{b0x - a0x, b0y - a0y, b1x - a1x, b1y - a1y, (sg.nx - tm * sg.ny) * inv,
             (sg.ny + tm * sg.nx) * inv};
}

/// \brief Integral of f(|gap|) + g(dn) along the segment (the gap is linear in s).
KOKKOS_INLINE_FUNCTION double gap_energy(const Law& m, const Quadrature& q, const Gap& g,
                                         double length) {
  double e = 0.0;
  for (int k = 0; k < q.n; ++k) {
    const double s = q.s[k];
    const double gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
    const double dn = gx * g.nx + gy * g.ny, dt = gy * g.nx - gx * g.ny;
    e += q.w[k] * energy_density(m, dn, dt);
  }
  return e * length;
}

/// \brief Energy of one interface with bricks in poses a and b.
KOKKOS_INLINE_FUNCTION double interface_energy(const Law& m, const Quadrature& q,
                                               const Segment& sg, const Pose& a, const Pose& b) {
  return gap_energy(m, q, interface_gap(sg, a, b), sg.length);
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
