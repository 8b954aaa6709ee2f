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

/// \brief A pose with its rotation evaluated once: sin t and cos t - 1 (the latter written as
/// -2 sin^2(t/2), so tiny rotations lose no digits). A Metropolis trial evaluates each pose's
/// trigonometry once instead of once per interface end.
struct Frame {
  double x, y, t, s, c1;
};

KOKKOS_INLINE_FUNCTION Frame make_frame(const Pose& p) {
  const double h = Kokkos::sin(0.5 * p.t);
  return Frame{p.x, p.y, p.t, Kokkos::sin(p.t), -2.0 * h * h};
}

/// \brief Displacement of the material point at r (relative to the centroid): u + (R(t) - I) r.
KOKKOS_INLINE_FUNCTION void point_displacement(const Frame& f, double rx, double ry, double& dx,
                                               double& dy) {
  dx = f.x + f.c1 * rx - f.s * ry;
  dy = f.y + f.s * rx + f.c1 * ry;
}

KOKKOS_INLINE_FUNCTION void point_displacement(const Pose& p, double rx, double ry, double& dx,
                                               double& dy) {
  point_displacement(make_frame(p), rx, ry, dx, dy);
}

/// \brief Geometry of one interface as seen by the energy: segment ends in both bricks' frames,
/// reference normal (a -> b) and length.
struct Segment {
  double ra0x, ra0y, ra1x, ra1y;
  double rb0x, rb0y, rb1x, rb1y;
  double nx, ny, length;
};

/// \brief Gap vectors (displacement of b minus displacement of a) at both segment ends and the
/// current normal direction. The normal turns with the mean rotation tm of the two bricks:
/// n + tm n_perp (a rotation by atan(tm) ~ tm, no trigonometry); it is left unnormalised
/// because only a penetrating point (dn < 0, rare) needs the normal opening itself.
struct Gap {
  double g0x, g0y, g1x, g1y, nx, ny;
};

/// \brief Energy density at gap (gx, gy) with unnormalised normal (nx, ny): f(|gap|) + g(dn).
KOKKOS_INLINE_FUNCTION double gap_density(const Law& m, double gx, double gy, double nx, double ny) {
  double e = f_energy_sq(m, gx * gx + gy * gy);
  const double dn_raw = gx * nx + gy * ny;  // same sign as dn
  if (dn_raw < 0.0) e += g_energy(m, dn_raw / Kokkos::sqrt(nx * nx + ny * ny));
  return e;
}

KOKKOS_INLINE_FUNCTION Gap interface_gap(const Segment& sg, const Frame& a, const Frame& b) {
  double a0x, a0y, a1x, a1y, b0x, b0y, b1x, b1y;
  point_displacement(a, sg.ra0x, sg.ra0y, a0x, a0y);
  point_displacement(a, sg.ra1x, sg.ra1y, a1x, a1y);
  point_displacement(b, sg.rb0x, sg.rb0y, b0x, b0y);
  point_displacement(b, sg.rb1x, sg.rb1y, b1x, b1y);
  const double tm = 0.5 * (a.t + b.t);
  return Gap{b0x - a0x, b0y - a0y, b1x - a1x, b1y - a1y, sg.nx - tm * sg.ny, sg.ny + tm * sg.nx};
}

/// \brief Integral of f(|gap|) + g(dn) along the segment (the gap is linear in s).
///
/// Most interfaces are elastic: when |gap| <= x1 at both ends (|gap| is convex along the
/// segment, so then everywhere) and dn >= 0 at both ends (dn is linear, so then everywhere), the
/// density is 0.5 k |gap(s)|^2 and the integral is exact in closed form,
/// 0.5 k L (|g0|^2 + g0.g1 + |g1|^2) / 3. Only the other interfaces use the quadrature rule.
KOKKOS_INLINE_FUNCTION double gap_energy(const Law& m, const Quadrature& q, const Gap& g,
                                         double length) {
  const double d0 = g.g0x * g.g0x + g.g0y * g.g0y, d1 = g.g1x * g.g1x + g.g1y * g.g1y;
  const double x1sq = m.x1 * m.x1;
  if (d0 <= x1sq && d1 <= x1sq && g.g0x * g.nx + g.g0y * g.ny >= 0.0 &&
      g.g1x * g.nx + g.g1y * g.ny >= 0.0)
    return length * m.k * (d0 + g.g0x * g.g1x + g.g0y * g.g1y + d1) * (1.0 / 6.0);
  double e = 0.0;
  for (int k = 0; k < q.n; ++k) {
    const double s = q.s[k];
    const double gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
    e += q.w[k] * gap_density(m, gx, gy, g.nx, g.ny);
  }
  return e * length;
}

KOKKOS_INLINE_FUNCTION Gap interface_gap(const Segment& sg, const Pose& a, const Pose& b) {
  return interface_gap(sg, make_frame(a), make_frame(b));
}

/// \brief Energy of one interface with bricks in frames a and b.
KOKKOS_INLINE_FUNCTION double interface_energy(const Law& m, const Quadrature& q,
                                               const Segment& sg, const Frame& a, const Frame& b) {
  return gap_energy(m, q, interface_gap(sg, a, b), sg.length);
}

/// \brief Energy of one interface with bricks in poses a and b.
KOKKOS_INLINE_FUNCTION double interface_energy(const Law& m, const Quadrature& q,
                                               const Segment& sg, const Pose& a, const Pose& b) {
  return interface_energy(m, q, sg, make_frame(a), make_frame(b));
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
