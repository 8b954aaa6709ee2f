// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Irreversible damage: the cohesive law of law.hpp with a history variable, kappa, the
/// largest separation a point of the joint has seen, and the energy and end forces of a segment
/// integrated with one kappa per Gauss point.
///
/// Why a history: the law f(d) of law.hpp is elastic-plastic-softening but reversible: a joint
/// pulled past x1 and let go returns along f, so it gives back the energy of its plateau and
/// softening, and a ruptured joint that closes heals. Unloading needs the standard cohesive-zone
/// rule (Ortiz and Pandolfi 1999; Camacho and Ortiz 1996): below kappa the joint unloads towards
/// the origin along its damaged secant s(kappa) = f'(kappa) / kappa,
///   psi(d; kappa) = f(d)                              for d >= kappa (the envelope),
///   psi(d; kappa) = D(kappa) + s(kappa) d^2 / 2       for d <  kappa,
///   D(kappa)      = f(kappa) - f'(kappa) kappa / 2    (the area above the secant: dissipated).
/// psi is C1 in d (value f(kappa) and slope f'(kappa) at d = kappa on both sides), so it is an
/// energy to minimise at fixed kappa (the Monte Carlo rule: kappa held within a load step,
/// raised when the step converges) and a potential for the dynamics' forces. Raising kappa to the
/// current d changes no energy (psi = f(d) there on both sides), and D(kappa) is non-decreasing
/// in kappa: 0 in the elastic range, k x1 (kappa - x1) / 2 on the plateau, k x1 x2 at rupture,
/// where s = 0 (ruptured joints stay ruptured: no traction in tension, whatever the opening).
/// D summed over the joints is then exactly the energy dissipated by fracture, and psi - D the
/// elastic energy the joints would give back. The interpenetration penalty g(dn) is contact, not
/// damage: it stays reversible.
///
/// Why Gauss points: the exact piecewise integral of segment.hpp rests on |gap| being the only
/// variable along the segment; with a history kappa(s) it is not. So a segment whose history has
/// left the elastic range (some kappa > x1) or whose gap leaves it is integrated by the model's
/// Gauss-Legendre rule with one kappa per point (Quadrature, at least 2 points); a segment elastic
/// at both ends with an elastic history takes the closed form, which the rule reproduces to
/// rounding (a quadratic), and the penalty keeps its exact closed form. Energy and forces come
/// from the same points, so the forces are the exact gradient of the energy at fixed kappa.
#include <nacre/cohesive/quadrature.hpp>
#include <nacre/cohesive/segment.hpp>

namespace nacre::cohesive {

/// \brief Damage models of a run's joints (the deck's [mortar] damage).
enum class Damage : std::uint8_t { reversible, irreversible };

/// \brief Secant stiffness s(kappa) = f'(kappa) / kappa of a joint whose history is kappa
/// (k in the elastic range, 0 once ruptured).
KOKKOS_INLINE_FUNCTION double secant(const Law& m, double kappa) {
  return kappa <= m.x1 ? m.k : f_slope(m, kappa) / kappa;
}

/// \brief D(kappa) = f(kappa) - f'(kappa) kappa / 2: energy dissipated per unit length by a
/// joint point whose history is kappa (0 while kappa <= x1, k x1 x2 at rupture).
KOKKOS_INLINE_FUNCTION double dissipated(const Law& m, double kappa) {
  if (kappa <= m.x1) return 0.0;
  return f_energy(m, kappa) - 0.5 * f_slope(m, kappa) * kappa;
}

/// \brief psi(d; kappa), the energy density of separation d with history kappa.
KOKKOS_INLINE_FUNCTION double damaged_energy(const Law& m, double d, double kappa) {
  if (d >= kappa) return f_energy(m, d);
  return dissipated(m, kappa) + 0.5 * secant(m, kappa) * d * d;
}

/// \brief psi'(d; kappa) / d, the factor that turns the gap vector into the traction (k at d = 0
/// with an elastic history, as law.hpp's limit).
KOKKOS_INLINE_FUNCTION double damaged_ratio(const Law& m, double d, double kappa) {
  if (d >= kappa) return d > 0.0 ? f_slope(m, d) / d : m.k;
  return secant(m, kappa);
}

/// \brief Largest history value of a segment's n points.
KOKKOS_INLINE_FUNCTION double max_history(const double* kappa, int n) {
  double r = 0.0;
  for (int p = 0; p < n; ++p) r = Kokkos::fmax(r, kappa[p]);
  return r;
}

/// \brief True when the segment takes the closed form: elastic at both ends (hence everywhere)
/// with a history that never left the elastic range (then psi = f everywhere it is evaluated).
KOKKOS_INLINE_FUNCTION bool intact_elastic(const Law& m, const Gap& g, const double* kappa, int n) {
  const double d0 = g.g0x * g.g0x + g.g0y * g.g0y, d1 = g.g1x * g.g1x + g.g1y * g.g1y;
  const double x1sq = m.x1 * m.x1;
  return d0 <= x1sq && d1 <= x1sq && max_history(kappa, n) <= m.x1;
}

/// \brief Energy of a segment with history kappa[0..q.n) at the rule's points (see the file
/// comment); kappa null: the reversible law's exact integral (segment.hpp).
KOKKOS_INLINE_FUNCTION double integrate(EnergyTag, const Law& m, const Quadrature& q, const Gap& g, double length,
                                        const double* kappa) {
  // intact and elastic: the reversible closed form itself (the same bits as without a history)
  if (!kappa || intact_elastic(m, g, kappa, q.n)) return integrate(EnergyTag{}, m, g, length);
  double ef = 0.0;
  for (int p = 0; p < q.n; ++p) {
    const double s = q.s[p];
    const double gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
    ef += q.w[p] * damaged_energy(m, Kokkos::sqrt(gx * gx + gy * gy), kappa[p]);
  }
  return length * (ef + detail::penalty_integral(m, g));
}

/// \brief End forces (dE/dg0, dE/dg1) of integrate(EnergyTag, ..., kappa) at fixed kappa.
KOKKOS_INLINE_FUNCTION EndForces integrate(TractionTag, const Law& m, const Quadrature& q, const Gap& g, double length,
                                           const double* kappa) {
  if (!kappa || intact_elastic(m, g, kappa, q.n)) return integrate(TractionTag{}, m, g, length);
  EndForces f;
  for (int p = 0; p < q.n; ++p) {
    const double s = q.s[p];
    const double gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
    const double c = q.w[p] * damaged_ratio(m, Kokkos::sqrt(gx * gx + gy * gy), kappa[p]);
    f.f0x += c * (1.0 - s) * gx, f.f0y += c * (1.0 - s) * gy;
    f.f1x += c * s * gx, f.f1y += c * s * gy;
  }
  detail::penalty_forces(m, g, f);
  f.f0x *= length, f.f0y *= length, f.f1x *= length, f.f1y *= length;
  return f;
}

/// \brief Raise the history to the segment's current separations: kappa[p] = max(kappa[p],
/// |g(s_p)|). Returns true when any value grew.
KOKKOS_INLINE_FUNCTION bool update_history(const Quadrature& q, const Gap& g, double* kappa) {
  bool grew = false;
  for (int p = 0; p < q.n; ++p) {
    const double s = q.s[p];
    const double gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
    const double d = Kokkos::sqrt(gx * gx + gy * gy);
    if (d > kappa[p]) kappa[p] = d, grew = true;
  }
  return grew;
}

/// \brief Energy dissipated by a segment of the given length with history kappa (the rule's
/// weights times D(kappa)).
KOKKOS_INLINE_FUNCTION double dissipated(const Law& m, const Quadrature& q, const double* kappa, double length) {
  double e = 0.0;
  for (int p = 0; p < q.n; ++p) e += q.w[p] * dissipated(m, kappa[p]);
  return length * e;
}

/// \brief The smallest history value of a segment's points: the joint is ruptured for good
/// when this has reached x1 + x2.
KOKKOS_INLINE_FUNCTION double min_history(const double* kappa, int n) {
  double r = 1e300;
  for (int p = 0; p < n; ++p) r = Kokkos::fmin(r, kappa[p]);
  return r;
}

}  // namespace nacre::cohesive
