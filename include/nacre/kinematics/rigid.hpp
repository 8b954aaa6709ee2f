// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Rigid-brick kinematics: a brick's pose, the displacement of its material points and
/// the gap (displacement jump) it opens across an interface with a neighbour.
///
/// Why a module of its own: the cohesive law does not care how a jump came about. Rigid bricks
/// (Monte Carlo, Chapters 2-3) produce it from two poses here; deformable bricks (Chapter 4)
/// from nodal displacements. Both hand the law the same cohesive::Gap.
#include <nacre/cohesive/damage.hpp>

#include <Kokkos_Core.hpp>

namespace nacre::kinematics {

/// \brief Rigid-body displacement of a brick: translation of its centroid and rotation about it.
struct Pose {
  double x, y, t;
};

/// \brief A pose with its rotation evaluated once: sin t and cos t - 1 (the latter written as
/// -2 sin^2(t/2), so tiny rotations lose no digits). A Metropolis trial evaluates each pose's
/// trigonometry once instead of once per interface end.
/// (T: double, or ad::Dual where the gradient is differentiated: mc/hessian.hpp)
template <class T>
struct BasicFrame {
  T x, y, t, s, c1;
};
using Frame = BasicFrame<double>;

template <class T>
KOKKOS_INLINE_FUNCTION BasicFrame<T> make_frame(const T& x, const T& y, const T& t) {
  const T h = sc::sin(0.5 * t);
  return BasicFrame<T>{x, y, t, sc::sin(t), -2.0 * h * h};
}

KOKKOS_INLINE_FUNCTION Frame make_frame(const Pose& p) { return make_frame(p.x, p.y, p.t); }

/// \brief Displacement of the material point at r (relative to the centroid): u + (R(t) - I) r.
template <class T>
KOKKOS_INLINE_FUNCTION void point_displacement(const BasicFrame<T>& f, double rx, double ry, T& dx, T& dy) {
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
template <class T>
KOKKOS_INLINE_FUNCTION cohesive::BasicGap<T> interface_gap(const Segment& sg, const BasicFrame<T>& a,
                                                           const BasicFrame<T>& b) {
  T a0x, a0y, a1x, a1y, b0x, b0y, b1x, b1y;
  point_displacement(a, sg.ra0x, sg.ra0y, a0x, a0y);
  point_displacement(a, sg.ra1x, sg.ra1y, a1x, a1y);
  point_displacement(b, sg.rb0x, sg.rb0y, b0x, b0y);
  point_displacement(b, sg.rb1x, sg.rb1y, b1x, b1y);
  const T tm = 0.5 * (a.t + b.t);
  return cohesive::BasicGap<T>{b0x - a0x, b0y - a0y, b1x - a1x, b1y - a1y, sg.nx - tm * sg.ny, sg.ny + tm * sg.nx};
}

KOKKOS_INLINE_FUNCTION cohesive::Gap interface_gap(const Segment& sg, const Pose& a, const Pose& b) {
  return interface_gap(sg, make_frame(a), make_frame(b));
}

/// \brief Energy of one interface between rigid bricks in frames a and b.
/// `kappa` (optional): the interface's history at q's points (cohesive/damage.hpp); null: the
/// reversible law.
KOKKOS_INLINE_FUNCTION double interface_energy(const cohesive::Law& m, const cohesive::Quadrature& q, const Segment& sg,
                                               const Frame& a, const Frame& b, const double* kappa = nullptr) {
  return cohesive::integrate(cohesive::EnergyTag{}, m, q, interface_gap(sg, a, b), sg.length, kappa);
}

/// \brief Gradient of one interface's energy with respect to both bricks' poses:
/// ga = dE/d(x_a, y_a, t_a), gb = dE/d(x_b, y_b, t_b), exactly that of interface_energy.
///
/// Chain rule through the gap: the segment's end forces fk = dE/dgk (cohesive::integrate with
/// TractionTag) times dgk/dpose (gk = u_b(rbk) - u_a(rak), du/dt = (-sin t rx - cos t ry,
/// cos t rx - sin t ry)), plus the turn of the normal with the mean rotation tm. That last term
/// needs no extra quadrature: the density depends on the gap only through |gap| and gap.n/|n|,
/// so turning n by an angle phi is turning every gap by -phi, and
/// dE/dphi = sum_k (fk_x gk_y - fk_y gk_x) (zero for the f(|gap|) part, exactly). The normal
/// n0 + tm n0_perp is n0 turned by phi = atan(tm), dphi/dtm = 1 / (1 + tm^2), and each brick
/// owns half of tm.
template <class T>
KOKKOS_INLINE_FUNCTION void gradient_of_forces(const Segment& sg, const BasicFrame<T>& a, const BasicFrame<T>& b,
                                               const cohesive::BasicGap<T>& g, const cohesive::BasicEndForces<T>& f,
                                               T ga[3], T gb[3]) {
  const T fx = f.f0x + f.f1x, fy = f.f0y + f.f1y;
  // d u(r) / dt = (-s rx - c ry, c rx - s ry), c = cos t = 1 + c1
  const T ca = 1.0 + a.c1, cb = 1.0 + b.c1;
  const T ta = f.f0x * (-a.s * sg.ra0x - ca * sg.ra0y) + f.f0y * (ca * sg.ra0x - a.s * sg.ra0y) +
               f.f1x * (-a.s * sg.ra1x - ca * sg.ra1y) + f.f1y * (ca * sg.ra1x - a.s * sg.ra1y);
  const T tb = f.f0x * (-b.s * sg.rb0x - cb * sg.rb0y) + f.f0y * (cb * sg.rb0x - b.s * sg.rb0y) +
               f.f1x * (-b.s * sg.rb1x - cb * sg.rb1y) + f.f1y * (cb * sg.rb1x - b.s * sg.rb1y);
  const T tm = 0.5 * (a.t + b.t);
  const T dphi = (f.f0x * g.g0y - f.f0y * g.g0x + f.f1x * g.g1y - f.f1y * g.g1x) / (1.0 + tm * tm);
  ga[0] = -fx, ga[1] = -fy, ga[2] = -ta + 0.5 * dphi;
  gb[0] = fx, gb[1] = fy, gb[2] = tb + 0.5 * dphi;
}

KOKKOS_INLINE_FUNCTION void interface_gradient(const cohesive::Law& m, const cohesive::Quadrature& q, const Segment& sg,
                                               const Frame& a, const Frame& b, double ga[3], double gb[3],
                                               const double* kappa = nullptr) {
  const cohesive::Gap g = interface_gap(sg, a, b);
  gradient_of_forces(sg, a, b, g, cohesive::integrate(cohesive::TractionTag{}, m, q, g, sg.length, kappa), ga, gb);
}

/// \brief The same with the reversible law on any scalar (ad::Dual: its derivative along the
/// frames' seeds is a column of the Hessian, mc/hessian.hpp).
template <class T>
KOKKOS_INLINE_FUNCTION void interface_gradient(const cohesive::Law& m, const Segment& sg, const BasicFrame<T>& a,
                                               const BasicFrame<T>& b, T ga[3], T gb[3]) {
  const cohesive::BasicGap<T> g = interface_gap(sg, a, b);
  gradient_of_forces(sg, a, b, g, cohesive::integrate(cohesive::TractionTag{}, m, g, sg.length), ga, gb);
}

/// \brief Energy of one interface between rigid bricks in poses a and b.
KOKKOS_INLINE_FUNCTION double interface_energy(const cohesive::Law& m, const cohesive::Quadrature& q,
                                               const Segment& sg, const Pose& a, const Pose& b) {
  return interface_energy(m, q, sg, make_frame(a), make_frame(b));
}

}  // namespace nacre::kinematics
