// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The cohesive law of MODEL.md §2: energy density f(d) + g(dn) and its gradient, the
/// traction, from one object (CabanaPD style: law(EnergyTag{}, ...) and law(TractionTag{}, ...)
/// over the same parameters and the same branches).
///
/// f: elastic up to x1, plastic plateau to x2, linear softening to rupture at x1 + x2, constant
/// k x1 x2 after. g penalises interpenetration (dn < 0). Both are C1; the traction magnitude
/// f'(d) is k d, k x1, k (x1 + x2 - d), 0.
///
/// Two ways to give the jump, same numbers:
///  - local frame: (dn, dt), normal and tangential opening (a deformable edge's natural frame);
///  - Cartesian: gap (gx, gy) with the interface normal (nx, ny), which need not be unit length
///    (rigid bricks turn the normal without renormalising it; see kinematics/rigid.hpp).
///    The local form is the Cartesian one with n = (1, 0).
/// The traction is the gradient of the energy density with respect to the gap at a fixed normal:
/// the force per unit length that the joint exerts on side a is +T, on side b is -T.
#include <Kokkos_Core.hpp>

namespace nacre::cohesive {

/// \brief Selects the energy density of a law or of a segment integral.
struct EnergyTag {};
/// \brief Selects the traction (energy gradient) of a law or of a segment integral.
struct TractionTag {};

/// \brief Parameters of one joint kind (bed, head or internal joint), and the law they define.
struct Law {
  double k;   ///< stiffness per unit length (energy / length^3 in 2-D per unit depth)
  double x1;  ///< end of the elastic range
  double x2;  ///< end of the plateau; rupture at x1 + x2, work to failure k x1 x2

  /// \brief Separation at which the joint is fully broken.
  KOKKOS_INLINE_FUNCTION double rupture_distance() const { return x1 + x2; }

  /// \brief Energy density at gap (gx, gy) across normal (nx, ny): f(|gap|) + g(gap.n/|n|).
  KOKKOS_INLINE_FUNCTION double operator()(EnergyTag, double gx, double gy, double nx, double ny) const;
  /// \brief Traction (tx, ty) = d/dgap [f(|gap|) + g(gap.n/|n|)] at a fixed normal.
  KOKKOS_INLINE_FUNCTION void operator()(TractionTag, double gx, double gy, double nx, double ny,
                                         double& tx, double& ty) const;
  /// \brief Energy density at normal / tangential opening (dn, dt).
  KOKKOS_INLINE_FUNCTION double operator()(EnergyTag, double dn, double dt) const {
    return (*this)(EnergyTag{}, dn, dt, 1.0, 0.0);
  }
  /// \brief Normal / tangential traction (fn, ft) at opening (dn, dt).
  KOKKOS_INLINE_FUNCTION void operator()(TractionTag, double dn, double dt, double& fn, double& ft) const {
    (*this)(TractionTag{}, dn, dt, 1.0, 0.0, fn, ft);
  }
};

/// \brief A law for a joint kind a model does not have: zero stiffness, so no energy and no
/// traction (x1, x2 > 0 keep every branch finite).
inline constexpr Law kNoJoint{0.0, 1.0, 1.0};

/// \brief f(x), the energy density of separation magnitude x >= 0.
KOKKOS_INLINE_FUNCTION double f_energy(const Law& m, double x) {
  if (x <= m.x1) return 0.5 * m.k * x * x;
  if (x <= m.x2) return m.k * m.x1 * (x - 0.5 * m.x1);
  if (x < m.x1 + m.x2)
    return -0.5 * m.k * (m.x1 * m.x1 + m.x2 * m.x2 + x * x - 2.0 * x * (m.x1 + m.x2));
  return m.k * m.x1 * m.x2;
}

/// \brief f'(x), the traction magnitude.
KOKKOS_INLINE_FUNCTION double f_slope(const Law& m, double x) {
  if (x <= m.x1) return m.k * x;
  if (x <= m.x2) return m.k * m.x1;
  if (x < m.x1 + m.x2) return m.k * (m.x1 + m.x2 - x);
  return 0.0;
}

/// \brief g(x), the interpenetration penalty for normal opening x (zero for x >= 0).
KOKKOS_INLINE_FUNCTION double g_energy(const Law& m, double x) {
  if (x >= 0.0) return 0.0;
  const double r = x / m.x1, r2 = r * r;
  return 0.0625 * m.k * x * x * r2 * r2;
}

/// \brief g'(x).
KOKKOS_INLINE_FUNCTION double g_slope(const Law& m, double x) {
  if (x >= 0.0) return 0.0;
  const double r = x / m.x1, r2 = r * r;
  return 0.375 * m.k * x * r2 * r2;  // d/dx (k x^6 / (16 x1^4)) = 6 k x^5 / (16 x1^4)
}

/// \brief f from the squared separation: the elastic branch (the common case) needs no sqrt.
KOKKOS_INLINE_FUNCTION double f_energy_sq(const Law& m, double d2) {
  if (d2 <= m.x1 * m.x1) return 0.5 * m.k * d2;
  return f_energy(m, Kokkos::sqrt(d2));
}

KOKKOS_INLINE_FUNCTION double Law::operator()(EnergyTag, double gx, double gy, double nx, double ny) const {
  double e = f_energy_sq(*this, gx * gx + gy * gy);
  const double dn_raw = gx * nx + gy * ny;  // same sign as dn; the sqrt only where it penetrates
  if (dn_raw < 0.0) e += g_energy(*this, dn_raw / Kokkos::sqrt(nx * nx + ny * ny));
  return e;
}

/// At gap 0 the limit of f'(d)/d, k, is used (the traction is then 0).
KOKKOS_INLINE_FUNCTION void Law::operator()(TractionTag, double gx, double gy, double nx, double ny,
                                            double& tx, double& ty) const {
  const double d = Kokkos::sqrt(gx * gx + gy * gy);
  const double s = d > 0.0 ? f_slope(*this, d) / d : k;
  tx = s * gx;
  ty = s * gy;
  const double dn_raw = gx * nx + gy * ny;
  if (dn_raw < 0.0) {
    const double inv = 1.0 / Kokkos::sqrt(nx * nx + ny * ny);
    const double gs = g_slope(*this, dn_raw * inv);
    tx += gs * nx * inv;
    ty += gs * ny * inv;
  }
}

/// \brief Energy density at relative displacement (dn, dt): f(|d|) + g(dn).
KOKKOS_INLINE_FUNCTION double energy_density(const Law& m, double dn, double dt) {
  return m(EnergyTag{}, dn, dt);
}

/// \brief Traction (gradient of energy_density): (Fn, Ft) = f'(d) (dn, dt)/d + (g'(dn), 0).
KOKKOS_INLINE_FUNCTION void traction(const Law& m, double dn, double dt, double& fn, double& ft) {
  m(TractionTag{}, dn, dt, fn, ft);
}

/// \brief True once the separation has reached the rupture distance x1 + x2.
KOKKOS_INLINE_FUNCTION bool ruptured(const Law& m, double d) { return d >= m.rupture_distance(); }

}  // namespace nacre::cohesive
