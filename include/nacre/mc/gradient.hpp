// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The exact gradient of the rigid-brick energy and the residual of a load step.
///
/// Why: "converged" must be a statement about the state, not about the Monte Carlo chain. The
/// generalised force on a free brick, -dE/d(x, y, theta), is computed exactly (the chain rule of
/// kinematics::interface_gradient over the brick's interfaces); the residual of a state is the
/// largest component over the free bricks, forces relative to F_s = max(k x1) x brick_width and
/// moments relative to F_s x brick_width (docs/decks.md, "Convergence").
///
/// One thread per free brick sums its own interfaces in adjacency order: no atomics, and the
/// same bits for any thread count (each interface is evaluated twice, once per brick; the
/// gradient is needed far less often than the sweep's energies).
#include <nacre/mc/kernels.hpp>

namespace nacre::mc {

/// \brief Gradient per free brick (sweep order), LayoutLeft: one column per component, so
/// consecutive bricks coalesce on GPUs and the polish's vector updates stream each column.
template <class MemorySpace = MemSpace>
using GradientView = Kokkos::View<double* [3], Kokkos::LayoutLeft, MemorySpace>;

/// \brief Scales of the residual: a force F_s and a moment M_s (see the file comment).
struct ResidualScale {
  double force = 1.0, moment = 1.0;
};

/// \brief Brick b in frame fb, its neighbours where they are: with g null, the energy of b's
/// interfaces; else their gradient dE/d(x_b, y_b, t_b) added to g (and 0 returned).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION double brick_local(const InterfaceEvaluator<MemorySpace>& ev,
                                          const Kokkos::View<int*, MemorySpace>& off,
                                          const Kokkos::View<int*, MemorySpace>& adj, int b,
                                          const kinematics::Frame& fb, double* g) {
  double e = 0.0;
  for (int j = off(b); j < off(b + 1); ++j) {
    const int i = adj(j);
    const int a = ev.ends(i, 0), c = ev.ends(i, 1);
    const kinematics::Segment sg = load_segment(ev.seg, i);
    const auto& law = ev.law(i);
    const kinematics::Frame fa = a == b ? fb : frame_of(ev.pose, a);
    const kinematics::Frame fc = c == b ? fb : frame_of(ev.pose, c);
    if (g) {
      double ga[3], gc[3];
      kinematics::interface_gradient(law, ev.quad, sg, fa, fc, ga, gc, ev.history(i));
      const double* mine = a == b ? ga : gc;
      g[0] += mine[0], g[1] += mine[1], g[2] += mine[2];
    } else {
      e += kinematics::interface_energy(law, ev.quad, sg, fa, fc, ev.history(i));
    }
  }
  return e;
}

/// \brief Energy change of brick b's interfaces when b moves from frame f0 to f1, summed
/// interface by interface as differences (a change far below the energy's rounding still has
/// its sign right).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION double brick_delta(const InterfaceEvaluator<MemorySpace>& ev,
                                          const Kokkos::View<int*, MemorySpace>& off,
                                          const Kokkos::View<int*, MemorySpace>& adj, int b,
                                          const kinematics::Frame& f0, const kinematics::Frame& f1) {
  double d = 0.0;
  for (int j = off(b); j < off(b + 1); ++j) {
    const int i = adj(j);
    const int a = ev.ends(i, 0), c = ev.ends(i, 1);
    const kinematics::Segment sg = load_segment(ev.seg, i);
    const auto& law = ev.law(i);
    const kinematics::Frame fo = frame_of(ev.pose, a == b ? c : a);
    const double* kappa = ev.history(i);
    d += a == b ? kinematics::interface_energy(law, ev.quad, sg, f1, fo, kappa) -
                      kinematics::interface_energy(law, ev.quad, sg, f0, fo, kappa)
                : kinematics::interface_energy(law, ev.quad, sg, fo, f1, kappa) -
                      kinematics::interface_energy(law, ev.quad, sg, fo, f0, kappa);
  }
  return d;
}

/// \brief grad(b, :) = dE/d(x, y, theta) of every free brick b at the current poses.
template <class ExecutionSpace, class MemorySpace>
void brick_gradient(const ExecutionSpace& space, const Model<MemorySpace>& m, const GradientView<MemorySpace>& grad) {
  check_access<ExecutionSpace, MemorySpace>();
  Kokkos::Profiling::ScopedRegion region("nacre::mc::gradient");
  const InterfaceEvaluator<MemorySpace> ev(m);
  auto off = m.adj_offset, adj = m.adj_iface;
  Kokkos::parallel_for(
      "nacre::mc::brick_gradient", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_free),
      KOKKOS_LAMBDA(const int b) {
        double g[3] = {0.0, 0.0, 0.0};
        brick_local(ev, off, adj, b, frame_of(ev.pose, b), g);
        grad(b, 0) = g[0], grad(b, 1) = g[1], grad(b, 2) = g[2];
      });
}

/// \brief The residual of a gradient: max over free bricks of |Fx| / F_s, |Fy| / F_s, |M| / M_s
/// (a max reduction: exact, the same for any thread count).
template <class ExecutionSpace, class MemorySpace>
double residual_of(const ExecutionSpace& space, const GradientView<MemorySpace>& grad, int n_free,
                   const ResidualScale& scale) {
  check_access<ExecutionSpace, MemorySpace>();
  const double inv_f = 1.0 / scale.force, inv_m = 1.0 / scale.moment;
  double r = 0.0;
  Kokkos::parallel_reduce(
      "nacre::mc::residual", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n_free),
      KOKKOS_LAMBDA(const int b, double& acc) {
        const double v = Kokkos::fmax(Kokkos::fmax(Kokkos::fabs(grad(b, 0)), Kokkos::fabs(grad(b, 1))) * inv_f,
                                      Kokkos::fabs(grad(b, 2)) * inv_m);
        acc = Kokkos::fmax(acc, v);
      },
      Kokkos::Max<double>(r));
  return r;
}

}  // namespace nacre::mc
