#pragma once
/// \file
/// \brief Rigid-brick kinematics: a brick's pose, the displacement of its material points and
/// the gap (displacement jump) it opens across an interface with a neighbour.
///
/// Why a module of its own: the cohesive law does not care how a jump came about. Rigid bricks
/// (Monte Carlo, Chapters 2-3) produce it from two poses here; deformable bricks (Chapter 4)
/// from nodal displacements. Both hand the law the same cohesive::Gap.
#include <nacre/cohesive/segment.hpp>

#include <Kokkos_Core.hpp>

namespace nacre::kinematics {

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

/// \brief Geometry of one interface between two rigid bricks: segment ends in both bricks' frames
/// (relative to their reference centroids), reference normal (a -> b) and length.
struct Segment {
  double ra0x, ra0y, ra1x, ra1y;
  double rb0x, rb0y, rb1x, rb1y;
  double nx, ny, length;
};

/// \brief Gap (displacement of b minus displacement of a) at both segment ends and the current
/// normal direction. The normal turns with the mean rotation tm of the two bricks:
/// n + tm n_perp (a rotation by atan(tm) ~ tm, no trigonometry); it is left unnormalised
/// because only a penetrating point (dn < 0, rare) needs the normal opening itself.
KOKKOS_INLINE_FUNCTION cohesive::Gap interface_gap(const Segment& sg, const Frame& a, const Frame& b) {
  double a0x, a0y, a1x, a1y, b0x, b0y, b1x, b1y;
  point_displacement(a, sg.ra0x, sg.ra0y, a0x, a0y);
  point_displacement(a, sg.ra1x, sg.ra1y, a1x, a1y);
  point_displacement(b, sg.rb0x, sg.rb0y, b0x, b0y);
  point_displacement(b, sg.rb1x, sg.rb1y, b1x, b1y);
  const double tm = 0.5 * (a.t + b.t);
  return cohesive::Gap{b0x - a0x, b0y - a0y, b1x - a1x, b1y - a1y, sg.nx - tm * sg.ny, sg.ny + tm * sg.nx};
}

KOKKOS_INLINE_FUNCTION cohesive::Gap interface_gap(const Segment& sg, const Pose& a, const Pose& b) {
  return interface_gap(sg, make_frame(a), make_frame(b));
}

/// \brief Energy of one interface between rigid bricks in frames a and b.
KOKKOS_INLINE_FUNCTION double interface_energy(const cohesive::Law& m, const cohesive::Quadrature& q,
                                               const Segment& sg, const Frame& a, const Frame& b) {
  return cohesive::segment_energy(m, q, interface_gap(sg, a, b), sg.length);
}

/// \brief Energy of one interface between rigid bricks in poses a and b.
KOKKOS_INLINE_FUNCTION double interface_energy(const cohesive::Law& m, const cohesive::Quadrature& q,
                                               const Segment& sg, const Pose& a, const Pose& b) {
  return interface_energy(m, q, sg, make_frame(a), make_frame(b));
}

}  // namespace nacre::kinematics
