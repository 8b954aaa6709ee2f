#pragma once
/// \file
/// \brief The cohesive law of MODEL.md §2: energy density f(d) + g(dn) and its derivatives.
///
/// f: elastic up to x1, plastic plateau to x2, linear softening to rupture at x1 + x2, constant
/// k x1 x2 after. g penalises interpenetration (dn < 0). Both are C1; the traction magnitude
/// f'(d) is k d, k x1, k (x1 + x2 - d), 0.
#include <Kokkos_Core.hpp>

namespace nacre::cohesive {

/// \brief Parameters of one interface kind (bed or head joint).
struct Law {
  double k;   ///< stiffness per unit length (energy / length^3 in 2-D per unit depth)
  double x1;  ///< end of the elastic range
  double x2;  ///< end of the plateau; rupture at x1 + x2, work to failure k x1 x2
};

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

/// \brief Energy density at relative displacement (dn, dt): f(|d|) + g(dn).
KOKKOS_INLINE_FUNCTION double energy_density(const Law& m, double dn, double dt) {
  return f_energy(m, Kokkos::sqrt(dn * dn + dt * dt)) + g_energy(m, dn);
}

/// \brief Traction (gradient of energy_density): (Fn, Ft) = f'(d) (dn, dt)/d + (g'(dn), 0).
/// At d = 0 the limit k (dn, dt) = (0, 0) is used.
KOKKOS_INLINE_FUNCTION void traction(const Law& m, double dn, double dt, double& fn, double& ft) {
  const double d = Kokkos::sqrt(dn * dn + dt * dt);
  const double s = d > 0.0 ? f_slope(m, d) / d : m.k;
  fn = s * dn + g_slope(m, dn);
  ft = s * dt;
}

/// \brief True once the separation has reached the rupture distance x1 + x2.
KOKKOS_INLINE_FUNCTION bool ruptured(const Law& m, double d) { return d >= m.x1 + m.x2; }

}  // namespace nacre::cohesive
