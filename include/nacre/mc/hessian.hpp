// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Exact Hessian-vector products and 3x3 diagonal blocks of the rigid-brick energy.
///
/// Why matrix-free: the Hessian has the brick graph's sparsity (a 3x3 block per brick and per
/// neighbour, ~7 blocks a row), but Newton-CG only needs H v, and H v is the directional
/// derivative of the exact gradient: the gradient code (kinematics::interface_gradient over
/// cohesive::integrate's end forces) run on dual numbers (core/dual.hpp) with every brick's pose
/// seeded with its component of v. Nothing is assembled or stored (a CrsMatrix would be ~60
/// doubles a brick, rebuilt at every Newton step); each product costs about one dual-number
/// gradient: each interface's tangent once, then one thread per free brick sums its own
/// interfaces' in adjacency order (as brick_gradient): no atomics, the same bits for any thread
/// count.
///
/// Kinks: the law's tangent jumps where |gap| crosses x1 (k -> 0 across the gap), x2 and x1 + x2,
/// and where the normal opening changes sign (the penalty's start). The product uses the branch
/// the value is on, and at a kink exactly the branch the double code's comparison selects: the
/// elastic side at |gap| = x1 (`<=`), the plateau at x2, the rupture side at x1 + x2, no penalty
/// at dn = 0. The reversible law only (a damage history makes the energy path-dependent).
#include <nacre/core/dual.hpp>
#include <nacre/mc/gradient.hpp>

#include <string>

namespace nacre::mc {

namespace detail {
/// Whether brick j's pose is an unknown: the first n_free bricks of one process, or (spread over
/// ranks) where `mask` says so, which includes the halo's free bricks.
template <class Mask>
KOKKOS_INLINE_FUNCTION bool is_free(const Mask& mask, int j, int n_free) {
  return mask.data() ? mask(j) != 0 : j < n_free;
}

/// Brick j's frame on dual numbers with its pose seeded by (dx, dy, dt): exactly
/// kinematics::make_frame on duals, with the sines and cosines read from the pose's cache
/// (sin t) and from `trig` (brick_trig) instead of evaluated: the same operations on the same
/// values, so the same bits.
template <class PV, class TV>
KOKKOS_INLINE_FUNCTION kinematics::BasicFrame<ad::Dual> dual_frame(const PV& pose, const TV& trig, int j, double dx,
                                                                   double dy, double dt) {
  const ad::Dual t{pose(j, 2), dt};
  const ad::Dual half = 0.5 * t;
  const ad::Dual h{trig(j, 1), trig(j, 2) * half.d};  // sc::sin(0.5 t)
  const ad::Dual s{pose(j, 3), trig(j, 0) * t.d};     // sc::sin(t)
  return kinematics::BasicFrame<ad::Dual>{ad::Dual{pose(j, 0), dx}, ad::Dual{pose(j, 1), dy}, t, s, -2.0 * h * h};
}

/// Brick j's frame seeded with the unit direction k of its pose (0: x, 1: y, 2: theta; any
/// other k: no seed, a frame held fixed).
template <class PV, class TV>
KOKKOS_INLINE_FUNCTION kinematics::BasicFrame<ad::Dual> unit_seeded(const PV& pose, const TV& trig, int j, int k) {
  return dual_frame(pose, trig, j, k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0);
}

/// Brick j's frame with its pose seeded by v (free bricks; driven ones stay put).
template <class PV, class TV, class V, class Mask>
KOKKOS_INLINE_FUNCTION kinematics::BasicFrame<ad::Dual> seeded_frame(const PV& pose, const TV& trig, const V& v, int j,
                                                                     int n_free, const Mask& mask) {
  const bool free = is_free(mask, j, n_free);
  return dual_frame(pose, trig, j, free ? v(j, 0) : 0.0, free ? v(j, 1) : 0.0, free ? v(j, 2) : 0.0);
}

/// d/de of brick b's gradient with b's neighbours in frames `other` (a functor j -> dual frame)
/// and b in `own`: adds the derivative to hv[3].
template <class MemorySpace, class OtherFrame>
KOKKOS_INLINE_FUNCTION void brick_tangent(const InterfaceEvaluator<MemorySpace>& ev,
                                          const Kokkos::View<int*, MemorySpace>& off,
                                          const Kokkos::View<int*, MemorySpace>& adj, int b,
                                          const kinematics::BasicFrame<ad::Dual>& own, const OtherFrame& other,
                                          double hv[3]) {
  for (int j = off(b); j < off(b + 1); ++j) {
    const int i = adj(j);
    const int a = ev.ends(i, 0), c = ev.ends(i, 1);
    const kinematics::Segment sg = load_segment(ev.seg, i);
    const auto fa = a == b ? own : other(a);
    const auto fc = c == b ? own : other(c);
    ad::Dual ga[3], gc[3];
    kinematics::interface_gradient(ev.law(i), sg, fa, fc, ga, gc);
    const ad::Dual* mine = a == b ? ga : gc;
    hv[0] += mine[0].d, hv[1] += mine[1].d, hv[2] += mine[2].d;
  }
}
}  // namespace detail

/// \brief Per brick of a model, 1 where its pose is an unknown. Empty (one process): the first
/// n_free. On a rank's model (mc/halo.hpp) it also marks the halo's free bricks, whose entries
/// of a vector the halo exchange brings.
template <class MemorySpace = MemSpace>
using FreeMask = Kokkos::View<const std::uint8_t*, MemorySpace>;

/// \brief Per interface, the directional derivatives of its two end forces (a: 0-2, c: 3-5) along
/// a vector: hessian_vector's first pass. LayoutLeft: the pass writes, and the brick pass reads,
/// one component of consecutive interfaces together (coalesced on a GPU).
template <class MemorySpace = MemSpace>
using TangentView = Kokkos::View<double* [6], Kokkos::LayoutLeft, MemorySpace>;

/// \brief Per brick, cos t, sin(t / 2) and cos(t / 2) of its pose: what the dual-number frames
/// of H v and of the Hessian's blocks need besides the pose and its cached sin t (Model::pose).
/// They depend on the poses only, so a Newton step evaluates them once for all its products
/// (brick_trig) instead of once per interface end and product: 8 sines and cosines an
/// interface were 40 % of a product's time (measured: docs/speed_accuracy.md). LayoutLeft: a
/// kernel reads one component of consecutive bricks.
template <class MemorySpace = MemSpace>
using TrigView = Kokkos::View<double* [3], Kokkos::LayoutLeft, MemorySpace>;

/// \brief trig = the sines and cosines of every model brick's pose (TrigView), at the poses now.
template <class ExecutionSpace, class MemorySpace>
void brick_trig(const ExecutionSpace& space, const Model<MemorySpace>& m, const TrigView<MemorySpace>& trig) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(trig.extent(0) >= static_cast<std::size_t>(m.n_bricks), "brick_trig: a row per model brick");
  auto pose = m.pose;
  Kokkos::parallel_for(
      "nacre::mc::newton::brick_trig", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_bricks),
      KOKKOS_LAMBDA(const int j) {
        const double t = pose(j, 2), h = 0.5 * t;
        trig(j, 0) = Kokkos::cos(t), trig(j, 1) = Kokkos::sin(h), trig(j, 2) = Kokkos::cos(h);
      });
}

/// \brief brick_trig into a View of its own.
template <class ExecutionSpace, class MemorySpace>
TrigView<MemorySpace> brick_trig(const ExecutionSpace& space, const Model<MemorySpace>& m) {
  TrigView<MemorySpace> trig(
      Kokkos::view_alloc(space, Kokkos::WithoutInitializing, std::string("nacre::mc::newton::brick_trig")),
      static_cast<std::size_t>(m.n_bricks));
  brick_trig(space, m, trig);
  return trig;
}

/// \brief hv = H v over the free bricks (sweep order): the exact second derivative of the total
/// energy in the free bricks' (x, y, theta), applied to v (see the file comment). With a mask,
/// v has a row per model brick and its halo rows are current. Two passes: each interface's
/// tangent once (both ends from one dual-number gradient), then each free brick sums its
/// interfaces' rows in adjacency order. Before 2026-12-05 each brick evaluated its interfaces
/// itself, so every interface twice; the per-interface values and the sums' order are the same,
/// so are the bits, at half the dual-number work (measured: docs/speed_accuracy.md). `work`: a
/// TangentView of m.n_interfaces rows (empty: allocated here). `trig`: brick_trig at the poses
/// now (empty: evaluated here; a caller with several products at one state passes its own).
template <class ExecutionSpace, class MemorySpace>
void hessian_vector(const ExecutionSpace& space, const Model<MemorySpace>& m, const GradientView<MemorySpace>& v,
                    const GradientView<MemorySpace>& hv, const FreeMask<MemorySpace>& mask = {},
                    TangentView<MemorySpace> work = {}, TrigView<MemorySpace> trig = {}) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(!m.hist.data(), "hessian_vector: the reversible law only");
  const InterfaceEvaluator<MemorySpace> ev(m);
  auto off = m.adj_offset, adj = m.adj_iface;
  const int nf = m.n_free;
  if (work.extent(0) < static_cast<std::size_t>(m.n_interfaces))
    work = TangentView<MemorySpace>(
        Kokkos::view_alloc(space, Kokkos::WithoutInitializing, std::string("nacre::mc::newton::interface_tangents")),
        static_cast<std::size_t>(m.n_interfaces));
  if (!trig.data()) trig = brick_trig(space, m);
  auto t = work;
  Kokkos::parallel_for(
      "nacre::mc::newton::interface_tangent", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_interfaces),
      KOKKOS_LAMBDA(const int i) {
        const int a = ev.ends(i, 0), c = ev.ends(i, 1);
        const kinematics::Segment sg = load_segment(ev.seg, i);
        ad::Dual ga[3], gc[3];
        kinematics::interface_gradient(ev.law(i), sg, detail::seeded_frame(ev.pose, trig, v, a, nf, mask),
                                       detail::seeded_frame(ev.pose, trig, v, c, nf, mask), ga, gc);
        for (int k = 0; k < 3; ++k) t(i, k) = ga[k].d, t(i, 3 + k) = gc[k].d;
      });
  Kokkos::parallel_for(
      "nacre::mc::newton::hessian_vector", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf),
      KOKKOS_LAMBDA(const int b) {
        double h[3] = {0.0, 0.0, 0.0};
        for (int j = off(b); j < off(b + 1); ++j) {
          const int i = adj(j);
          const int s = ev.ends(i, 0) == b ? 0 : 3;
          h[0] += t(i, s), h[1] += t(i, s + 1), h[2] += t(i, s + 2);
        }
        hv(b, 0) = h[0], hv(b, 1) = h[1], hv(b, 2) = h[2];
      });
}

/// \brief The 3x3 diagonal block of the Hessian per free brick (its own pose, neighbours held),
/// symmetric, stored as (xx, yy, tt, xy, xt, yt).
template <class MemorySpace = MemSpace>
using BlockView = Kokkos::View<double* [6], Kokkos::LayoutLeft, MemorySpace>;

/// `trig`: brick_trig at the poses now (empty: evaluated here).
template <class ExecutionSpace, class MemorySpace>
void hessian_blocks(const ExecutionSpace& space, const Model<MemorySpace>& m, const BlockView<MemorySpace>& blocks,
                    TrigView<MemorySpace> trig = {}) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(!m.hist.data(), "hessian_blocks: the reversible law only");
  if (!trig.data()) trig = brick_trig(space, m);
  const InterfaceEvaluator<MemorySpace> ev(m);
  auto off = m.adj_offset, adj = m.adj_iface;
  Kokkos::parallel_for(
      "nacre::mc::newton::hessian_blocks", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_free),
      KOKKOS_LAMBDA(const int b) {
        double H[3][3];
        auto held = [&](int j) { return detail::unit_seeded(ev.pose, trig, j, -1); };
        for (int k = 0; k < 3; ++k) {
          double col[3] = {0.0, 0.0, 0.0};
          detail::brick_tangent(ev, off, adj, b, detail::unit_seeded(ev.pose, trig, b, k), held, col);
          H[0][k] = col[0], H[1][k] = col[1], H[2][k] = col[2];
        }
        // symmetric by construction up to rounding: store the mean of the two triangles
        blocks(b, 0) = H[0][0], blocks(b, 1) = H[1][1], blocks(b, 2) = H[2][2];
        blocks(b, 3) = 0.5 * (H[0][1] + H[1][0]), blocks(b, 4) = 0.5 * (H[0][2] + H[2][0]);
        blocks(b, 5) = 0.5 * (H[1][2] + H[2][1]);
      });
}

/// \brief Off-diagonal blocks per adjacency slot: slots(j, 3 r + k) = d g_b(r) / d x_c(k) for slot
/// j of free brick b whose other brick c is free (zero where c is driven); LayoutRight: a
/// slot's 9 values together. With hessian_blocks, the whole sparse Hessian (the brick graph's
/// pattern), for a factorised preconditioner (hessian_factor.hpp).
template <class MemorySpace = MemSpace>
using SlotBlockView = Kokkos::View<double* [9], Kokkos::LayoutRight, MemorySpace>;

template <class ExecutionSpace, class MemorySpace>
void hessian_slots(const ExecutionSpace& space, const Model<MemorySpace>& m, const SlotBlockView<MemorySpace>& slots,
                   const FreeMask<MemorySpace>& mask = {}, TrigView<MemorySpace> trig = {}) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(!m.hist.data(), "hessian_slots: the reversible law only");
  if (!trig.data()) trig = brick_trig(space, m);
  const InterfaceEvaluator<MemorySpace> ev(m);
  auto off = m.adj_offset, adj = m.adj_iface;
  const int nf = m.n_free;
  Kokkos::parallel_for(
      "nacre::mc::newton::hessian_slots", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf),
      KOKKOS_LAMBDA(const int b) {
        for (int j = off(b); j < off(b + 1); ++j) {
          const int i = adj(j);
          const int a = ev.ends(i, 0), c = ev.ends(i, 1);
          const int other = a == b ? c : a;
          for (int q = 0; q < 9; ++q) slots(j, q) = 0.0;
          if (!detail::is_free(mask, other, nf)) continue;  // a driven neighbour: no unknowns
          const kinematics::Segment sg = load_segment(ev.seg, i);
          const auto mine = detail::unit_seeded(ev.pose, trig, b, -1);
          for (int k = 0; k < 3; ++k) {
            const auto seeded = detail::unit_seeded(ev.pose, trig, other, k);
            ad::Dual ga[3], gc[3];
            if (a == b)
              kinematics::interface_gradient(ev.law(i), sg, mine, seeded, ga, gc);
            else
              kinematics::interface_gradient(ev.law(i), sg, seeded, mine, ga, gc);
            const ad::Dual* g = a == b ? ga : gc;
            for (int r = 0; r < 3; ++r) slots(j, 3 * r + k) = g[r].d;
          }
        }
      });
}

}  // namespace nacre::mc
