// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The dynamic run's stability monitor (docs/dynamics.md "Stability monitor"): kernels
/// that the check after every step chunk runs besides the energy books.
///
/// Why: a critical step bisected from rest holds for the elastic specimen only. A running crack
/// presses joints together, and the interpenetration penalty g = k dn^6 / (16 x1^4) stiffens a
/// joint to k (1 + 1.875 (dn / x1)^4); small clipped pieces put that stiffness on a small mass.
/// The explicit step then goes unstable in a few elements while the specimen's books still look
/// fine for hundreds of steps. Two kernels watch for it:
///  - StepBound: a Gershgorin bound of the largest eigenvalue of M^-1 K_t, K_t the current
///    tangent stiffness (element matrices + every interface at its current penetration), per
///    free element (the largest row sum over its lumped masses). 2 / sqrt(max) is a step the
///    linearised system is stable at; its trend against the start tells how far the current
///    state's critical step has fallen. Deterministic (a max), one gather pass, no atomics.
///  - ElementGrowth: per element E_e = strain + kinetic energy and its share of the total; a
///    share that grows by more than a factor per check for several checks in a row is the
///    signature of a local instability (a stable run's shares rise once, when a wave or the
///    crack arrives, and then oscillate).
#include <nacre/dyn/kernels.hpp>

namespace nacre::dyn {

/// \brief Step bound of M^-1 K_t per free element: the largest eigenvalue of M_e^-1 K_e (exact,
/// per type: the elements share no nodes) plus the Gershgorin bound of the interface part, the
/// largest interface tangent row sum over the node's mass. (Weyl: the global largest eigenvalue is
/// at most max_e of the first plus max of the second; the element-local sum is the estimate the
/// run tracks, and the bisected step calibrates it.) The interface tangent is bounded in the
/// Loewner order by k I + g''(dn) n n^T at each quadrature point (the cohesive part's positive
/// curvature never exceeds k; the penalty's is g'' = 1.875 k (dn / x1)^4), whose row sums in x
/// and y are k + g'' |n_x| (|n_x| + |n_y|) and k + g'' |n_y| (|n_x| + |n_y|). With the edge shape
/// functions N (|N_a0| + |N_a1| = |N_b0| + |N_b1| = 1 at every point) the row of edge node j of
/// one side is 2 sum_q w_q L t k_row(q) N_j(q). `with_elements` = false drops the element rows
/// (BIE: the bricks are integrated implicitly, only the interfaces are explicit).
template <class MemorySpace>
struct StepBound {
  InterfaceOp<MemorySpace> op;
  Kokkos::View<const int*, MemorySpace> type, goff;
  Kokkos::View<const GatherEntry*, MemorySpace> gent;
  Kokkos::View<const std::int8_t*, MemorySpace> drive;
  Kokkos::View<const double**, ElemLayout<MemorySpace>, MemorySpace> mass;
  Kokkos::View<const double*, MemorySpace> klam;
  int nd;
  bool with_elements;

  /// Interface i's tangent rows on its side's edge nodes n0, n1: (x, y) for n0 then n1.
  KOKKOS_INLINE_FUNCTION void iface_rows(int i, int side, double r[4]) const {
    double q[8];
    op.load(i, q);
    const int sh = op.ishape(i);
    const cohesive::Law& law = op.laws[op.ikind(sh)];
    const double lt = op.ilen(sh) * op.thickness, nx = Kokkos::abs(op.inx(sh)), ny = Kokkos::abs(op.iny(sh));
    r[0] = r[1] = r[2] = r[3] = 0;
    for (int p = 0; p < op.quad.n; ++p) {
      double dn, dt, xa, xb;
      op.jump(i, q, op.quad.s[p], dn, dt, xa, xb);
      double g2 = 0;
      if (dn < 0) {
        const double s = dn / law.x1, s2 = s * s;
        g2 = 1.875 * law.k * s2 * s2;
      }
      const double w = 2.0 * op.quad.w[p] * lt, kx = law.k + g2 * nx * (nx + ny), ky = law.k + g2 * ny * (nx + ny);
      const double x = side == 0 ? xa : xb;
      r[0] += w * (1 - x) * kx, r[1] += w * (1 - x) * ky, r[2] += w * x * kx, r[3] += w * x * ky;
    }
  }

  /// Largest eigenvalue bound of element e (0 for a driven element: its motion is prescribed).
  KOKKOS_INLINE_FUNCTION double operator()(int e) const {
    if (drive(e) != 0) return 0.0;
    const int t = type(e);
    double row[kMaxDof];
    for (int j = 0; j < nd; ++j) row[j] = 0.0;
    for (int k = goff(e); k < goff(e + 1); ++k) {
      const GatherFields g = gather_fields(gent(k));
      const int i = g.iface, side = g.side, n0 = g.n0, n1 = g.n1;
      double r[4];
      iface_rows(i, side, r);
      row[2 * n0] += r[0], row[2 * n0 + 1] += r[1], row[2 * n1] += r[2], row[2 * n1 + 1] += r[3];
    }
    double w2 = 0;
    for (int j = 0; j < nd; ++j)
      if (mass(t, j) > 0) w2 = Kokkos::max(w2, row[j] / mass(t, j));
    return (with_elements ? klam(t) : 0.0) + w2;
  }
};

/// \brief max over i in [0, n) of term(i) and the lowest i that attains it (deterministic for any
/// thread count); term returns a T.
template <class T, class ExecutionSpace, class Term>
typename Kokkos::MaxLoc<T, int>::value_type arg_max(const ExecutionSpace& space, const char* label, int n,
                                                    const Term& term) {
  using V = typename Kokkos::MaxLoc<T, int>::value_type;
  V r;
  Kokkos::parallel_reduce(
      label, Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
      KOKKOS_LAMBDA(const int i, V& acc) {
        const T x = term(i);
        if (x > acc.val || (x == acc.val && i < acc.loc)) acc.val = x, acc.loc = i;
      },
      Kokkos::MaxLoc<T, int>(r));
  return r;
}

/// \brief max over free elements of StepBound and the element that attains it (on ranks: over
/// the elements of `mask`, OwnedTerm; empty: all).
template <class ExecutionSpace>
Kokkos::MaxLoc<double, int>::value_type step_bound(const ExecutionSpace& space,
                                                  const StepBound<MemOf<ExecutionSpace>>& sb, int n_elem,
                                                  const Kokkos::View<std::uint8_t*, MemOf<ExecutionSpace>>& mask = {}) {
  return arg_max<double>(space, "nacre::dyn::monitor::step_bound", n_elem, owned_term(mask, sb));
}

/// \brief The interface that adds the most to element e's bound (its largest row), and the
/// largest penetration -dn / x1 over that interface's quadrature points: where a stop happened.
template <class ExecutionSpace>
void controlling_interface(const ExecutionSpace& space, const StepBound<MemOf<ExecutionSpace>>& sb, int e,
                           int& iface, double& penetration) {
  using V = Kokkos::MaxLoc<double, int>::value_type;
  V r;
  Kokkos::parallel_reduce(
      "nacre::dyn::monitor::controlling_interface", Kokkos::RangePolicy<ExecutionSpace>(space, 0, 1),
      KOKKOS_LAMBDA(const int, V& acc) {
        for (int k = sb.goff(e); k < sb.goff(e + 1); ++k) {
          const GatherFields g = gather_fields(sb.gent(k));
          const int i = g.iface, side = g.side;
          double rr[4];
          sb.iface_rows(i, side, rr);
          const double m = Kokkos::max(Kokkos::max(rr[0], rr[1]), Kokkos::max(rr[2], rr[3]));
          if (m > acc.val) acc.val = m, acc.loc = i;
        }
      },
      Kokkos::MaxLoc<double, int>(r));
  iface = r.loc;
  penetration = 0;
  if (iface < 0) return;
  double pen = 0;
  const auto op = sb.op;
  const int i = iface;
  Kokkos::parallel_reduce(
      "nacre::dyn::monitor::penetration", Kokkos::RangePolicy<ExecutionSpace>(space, 0, 1),
      KOKKOS_LAMBDA(const int, double& acc) { acc = Kokkos::max(acc, op.penetration(i)); }, Kokkos::Max<double>(pen));
  penetration = pen;
}

/// \brief Per element: E_e = strain + kinetic energy, its share s = E_e / total of the last
/// check, and the run of consecutive checks in which the share grew by more than `factor`
/// (elements below `floor` of the total reset their run). Returns through the reduction the
/// longest run and its element (lowest index among ties).
template <class MemorySpace>
struct ElementGrowth {
  StrainEnergy<MemorySpace> strain;
  KineticEnergy<MemorySpace> kinetic;
  Kokkos::View<double*, MemorySpace> share;   ///< share at the last check
  Kokkos::View<std::int16_t*, MemorySpace> run;
  double inv_total, factor, floor;
  KOKKOS_INLINE_FUNCTION int operator()(int e) const {
    const double s = (strain(e) + kinetic(e)) * inv_total, old = share(e);
    int n = run(e);
    if (s > floor && old > 0 && s > factor * old) n = n < 32000 ? n + 1 : n;
    else n = 0;
    share(e) = s, run(e) = static_cast<std::int16_t>(n);
    return n;
  }
};

/// \brief The longest growth run over the elements and its element (ElementGrowth updates every
/// element's share and run as it goes).
template <class ExecutionSpace>
Kokkos::MaxLoc<int, int>::value_type element_growth(const ExecutionSpace& space,
                                                   const ElementGrowth<MemOf<ExecutionSpace>>& g, int n_elem,
                                                   const Kokkos::View<std::uint8_t*, MemOf<ExecutionSpace>>& mask = {}) {
  return arg_max<int>(space, "nacre::dyn::monitor::element_growth", n_elem, owned_term(mask, g));
}

}  // namespace nacre::dyn
