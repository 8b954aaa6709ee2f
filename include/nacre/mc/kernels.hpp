#pragma once
/// \file
/// \brief Kernels over the rigid-brick model: total / per-brick energy, rupture count, load
/// application and the colour sweep. Templated on the execution space; the model's Views must
/// be accessible from it.
#include <nacre/core/deterministic_sum.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/rng/uniform_source.hpp>

namespace nacre::mc {

/// \brief Pose of brick b, with its cached rotation.
template <class PV>
KOKKOS_INLINE_FUNCTION cohesive::Frame frame_of(const PV& p, int b) {
  return cohesive::Frame{p(b, 0), p(b, 1), p(b, 2), p(b, 3), p(b, 4)};
}

/// \brief Set brick b's pose (and its cached rotation).
template <class PV>
KOKKOS_INLINE_FUNCTION void store_frame(const PV& p, int b, const cohesive::Frame& f) {
  p(b, 0) = f.x, p(b, 1) = f.y, p(b, 2) = f.t, p(b, 3) = f.s, p(b, 4) = f.c1;
}

/// \brief What the energy kernels read of the model, copied by value into a lambda (Views are
/// handles; the two laws and the quadrature rule are a few doubles): one place that evaluates an
/// interface at the current poses.
template <class MemorySpace>
struct InterfaceEvaluator {
  typename Model<MemorySpace>::PoseView pose;
  decltype(Model<MemorySpace>::ends) ends;
  decltype(Model<MemorySpace>::seg) seg;
  decltype(Model<MemorySpace>::kind) kind;
  cohesive::Law law0, law1;
  cohesive::Quadrature quad;

  explicit InterfaceEvaluator(const Model<MemorySpace>& m)
      : pose(m.pose), ends(m.ends), seg(m.seg), kind(m.kind), law0(m.law[0]), law1(m.law[1]), quad(m.quad) {}

  KOKKOS_INLINE_FUNCTION const cohesive::Law& law(int i) const { return kind(i) ? law1 : law0; }
  KOKKOS_INLINE_FUNCTION cohesive::Gap gap(int i) const {
    return cohesive::interface_gap(load_segment(seg, i), frame_of(pose, ends(i, 0)), frame_of(pose, ends(i, 1)));
  }
  KOKKOS_INLINE_FUNCTION double energy(int i) const {
    return cohesive::gap_energy(law(i), quad, gap(i), seg(i, col(SegCol::length)));
  }
};

/// \brief Total energy: sum over interfaces (deterministic: same bits for any thread count).
template <class ExecutionSpace = ExecSpace>
double total_energy(const Model<typename ExecutionSpace::memory_space>& m,
                    SumWorkspace<typename ExecutionSpace::memory_space>& ws) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  const InterfaceEvaluator<typename ExecutionSpace::memory_space> ev(m);
  return deterministic_sum<ExecutionSpace>("nacre::mc::total_energy", ws, 0, m.n_interfaces,
                                           KOKKOS_LAMBDA(const int i) { return ev.energy(i); });
}

/// \brief Energy of each brick's interfaces: full sum per brick into `full` (each interface
/// counted in both its bricks); half of it is the brick's share of the total.
template <class ExecutionSpace = ExecSpace>
void brick_energy(const Model<typename ExecutionSpace::memory_space>& m,
                  Field<double, typename ExecutionSpace::memory_space> full) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  const InterfaceEvaluator<typename ExecutionSpace::memory_space> ev(m);
  auto off = m.adj_offset, adj = m.adj_iface;
  Kokkos::parallel_for(
      "nacre::mc::brick_energy", Kokkos::RangePolicy<ExecutionSpace>(0, m.n_bricks),
      KOKKOS_LAMBDA(const int b) {
        double e = 0;
        for (int j = off(b); j < off(b + 1); ++j) e += ev.energy(adj(j));
        full(b) = e;
      });
}

/// \brief Per-interface energy and state (0 elastic, 1 plastic/softening somewhere, 2 ruptured).
template <class ExecutionSpace = ExecSpace>
int interface_state(const Model<typename ExecutionSpace::memory_space>& m,
                    Field<double, typename ExecutionSpace::memory_space> energy,
                    Field<std::int8_t, typename ExecutionSpace::memory_space> state) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  const InterfaceEvaluator<typename ExecutionSpace::memory_space> ev(m);
  int ruptured = 0;
  Kokkos::parallel_reduce(
      "nacre::mc::interface_state", Kokkos::RangePolicy<ExecutionSpace>(0, m.n_interfaces),
      KOKKOS_LAMBDA(const int i, int& acc) {
        const auto& law = ev.law(i);
        const cohesive::Gap g = ev.gap(i);
        if (energy.data()) energy(i) = cohesive::gap_energy(law, ev.quad, g, ev.seg(i, col(SegCol::length)));
        std::int8_t s = 0;
        if (cohesive::min_separation(ev.quad, g) >= law.x1 + law.x2) s = 2;
        else if (cohesive::max_separation(g) > law.x1) s = 1;
        if (state.data()) state(i) = s;
        acc += (s == 2);
      },
      ruptured);
  return ruptured;
}

/// \brief Prescribed pose of a driven brick at load D: opening of the top edge
/// u_y = +D/2 [tension + bending (1 - x / width)] and its mirror at the bottom; the edge turns
/// by the slope of that profile. (Free bricks are untouched.)
struct LoadPattern {
  double tension, bending, width;
  KOKKOS_INLINE_FUNCTION cohesive::Pose pose(int side, double cx, double D) const {
    const double lever = 1.0 - cx / width;  // 1 at the notch mouth, 0 at the far edge
    const double uy = 0.5 * D * (tension + bending * lever) * side;
    const double slope = -0.5 * D * bending / width * side;
    return cohesive::Pose{0.0, uy, Kokkos::atan(slope)};
  }
};

template <class ExecutionSpace = ExecSpace>
void apply_load(const Model<typename ExecutionSpace::memory_space>& m, const LoadPattern& lp, double D) {
  auto p = m.pose;
  auto cx = m.cx;
  auto drive = m.drive;
  Kokkos::parallel_for(
      "nacre::mc::apply_load", Kokkos::RangePolicy<ExecutionSpace>(m.n_free, m.n_bricks),
      KOKKOS_LAMBDA(const int b) {
        const cohesive::Pose q = lp.pose(drive(b), cx(b), D);
        store_frame(p, b, cohesive::make_frame(q));
      });
}

/// \brief Per-brick trial step sizes (eq. 2.7 applied brick by brick): step(b, 0) translation,
/// step(b, 1) rotation, accepted(b) trials accepted since the last adaptation. Empty views mean
/// the global step sizes are used.
template <class MemorySpace = MemSpace>
struct BrickSteps {
  Kokkos::View<double* [2], Kokkos::LayoutRight, MemorySpace> step;
  Kokkos::View<int*, MemorySpace> accepted;
  [[nodiscard]] bool active() const { return step.extent(0) > 0; }
};

/// \brief One Metropolis trial per brick of one colour (MODEL.md §3), work items [begin, end) in
/// parallel, the bricks of a work item (one brick, or a tile) in order. Same-colour work items
/// share no interface, so the trials are independent; u(b, 0..3) holds brick b's uniforms.
/// de(b) receives the accepted energy change (0 when rejected); the count of accepted trials is
/// returned (an integer reduction, exact for any thread count).
template <class ExecutionSpace = ExecSpace>
long sweep_colour(const Model<typename ExecutionSpace::memory_space>& m, int begin, int end,
                  rng::UniformTable<typename ExecutionSpace::memory_space> u,
                  Field<double, typename ExecutionSpace::memory_space> de, double step,
                  double rot_step, double temperature,
                  const BrickSteps<typename ExecutionSpace::memory_space>& brick_steps = {}) {
  auto p = m.pose;
  auto ends = m.ends;
  auto seg = m.seg;
  auto kind = m.kind;
  auto off = m.adj_offset, adj = m.adj_iface;
  auto tiles = m.tile_offset;
  const cohesive::Law l0 = m.law[0], l1 = m.law[1];
  const cohesive::Quadrature q = m.quad;
  const double inv_t = temperature > 0 ? 1.0 / temperature : 0.0;
  const bool per_brick = brick_steps.active();
  auto bstep = brick_steps.step;
  auto bacc = brick_steps.accepted;
  long accepted = 0;
  Kokkos::parallel_reduce(
      "nacre::mc::sweep_colour", Kokkos::RangePolicy<ExecutionSpace>(begin, end),
      KOKKOS_LAMBDA(const int w, long& acc) {
       for (int b = tiles(w); b < tiles(w + 1); ++b) {
        const cohesive::Frame f_old = frame_of(p, b);
        const cohesive::Pose old{f_old.x, f_old.y, f_old.t};
        const double s = per_brick ? bstep(b, 0) : step, sr = per_brick ? bstep(b, 1) : rot_step;
        const cohesive::Pose trial{old.x + s * (2.0 * u(b, 0) - 1.0), old.y + s * (2.0 * u(b, 1) - 1.0),
                                   old.t + sr * (2.0 * u(b, 2) - 1.0)};
        const cohesive::Frame f_new = cohesive::make_frame(trial);
        double e_old = 0, e_new = 0;
        for (int j = off(b); j < off(b + 1); ++j) {
          const int i = adj(j);
          const int a = ends(i, 0), c = ends(i, 1);
          const int o = (a == b) ? c : a;
          const cohesive::Frame fo = frame_of(p, o);
          const cohesive::Segment sg = load_segment(seg, i);
          const auto& law = kind(i) ? l1 : l0;
          if (a == b) {
            e_old += cohesive::interface_energy(law, q, sg, f_old, fo);
            e_new += cohesive::interface_energy(law, q, sg, f_new, fo);
          } else {
            e_old += cohesive::interface_energy(law, q, sg, fo, f_old);
            e_new += cohesive::interface_energy(law, q, sg, fo, f_new);
          }
        }
        const double d = e_new - e_old;
        const bool accept = d <= 0.0 || (inv_t > 0.0 && u(b, 3) < Kokkos::exp(-d * inv_t));
        if (accept) {
          store_frame(p, b, f_new);
          acc += 1;
          if (per_brick) bacc(b) += 1;  // one thread per brick: no race
        }
        de(b) = accept ? d : 0.0;
       }
      },
      accepted);
  return accepted;
}

/// \brief Position predictor (eq. 2.10, 2.11) for the free bricks: p += ratio (p - p_prev) m,
/// m = 1 - 1.8 (max(min(phi/phi0, 1), 0.5) - 0.5): linear extrapolation at low energy, fading
/// to constant prediction as the brick approaches its elastic limit. ratio = D_{n+1} / D_n.
template <class ExecutionSpace = ExecSpace>
void predict_poses(const Model<typename ExecutionSpace::memory_space>& m,
                   typename Model<typename ExecutionSpace::memory_space>::PoseView prev,
                   Field<double, typename ExecutionSpace::memory_space> phi, double ratio) {
  auto p = m.pose;
  auto phi0 = m.phi0;
  Kokkos::parallel_for(
      "nacre::mc::predict", Kokkos::RangePolicy<ExecutionSpace>(0, m.n_free), KOKKOS_LAMBDA(const int b) {
        const double r = phi0(b) > 0 ? phi(b) / phi0(b) : 0.0;
        const double mfac = 1.0 - 1.8 * (Kokkos::fmax(Kokkos::fmin(r, 1.0), 0.5) - 0.5);
        cohesive::Pose q{p(b, 0), p(b, 1), p(b, 2)};
        q.x += ratio * (q.x - prev(b, 0)) * mfac;
        q.y += ratio * (q.y - prev(b, 1)) * mfac;
        q.t += ratio * (q.t - prev(b, 2)) * mfac;
        store_frame(p, b, cohesive::make_frame(q));
      });
}

/// \brief eq. 2.7: a step size s after a window with acceptance a: s (0.5 + a) clamped to
/// [lo, hi] when a is outside [0.4, 0.6], else unchanged.
KOKKOS_INLINE_FUNCTION double adapted_step(double s, double a, double lo, double hi) {
  return (a < 0.4 || a > 0.6) ? Kokkos::clamp(s * (0.5 + a), lo, hi) : s;
}

/// \brief eq. 2.7 per brick: after `interval` trials, adapt each brick's steps to its own
/// acceptance (adapted_step) and restart its count.
template <class ExecutionSpace = ExecSpace>
void adapt_brick_steps(const BrickSteps<typename ExecutionSpace::memory_space>& bs, int n_free, int interval,
                       double min_step, double max_step, double min_rot, double max_rot) {
  auto step = bs.step;
  auto acc = bs.accepted;
  Kokkos::parallel_for(
      "nacre::mc::adapt_brick_steps", Kokkos::RangePolicy<ExecutionSpace>(0, n_free), KOKKOS_LAMBDA(const int b) {
        const double a = static_cast<double>(acc(b)) / interval;
        step(b, 0) = adapted_step(step(b, 0), a, min_step, max_step);
        step(b, 1) = adapted_step(step(b, 1), a, min_rot, max_rot);
        acc(b) = 0;
      });
}

/// \brief Recompute the cached rotation of every brick from its angle (after poses were set from
/// outside, e.g. a checkpoint), with the same device sine the sweep uses.
template <class ExecutionSpace = ExecSpace>
void refresh_frames(const Model<typename ExecutionSpace::memory_space>& m) {
  auto p = m.pose;
  Kokkos::parallel_for(
      "nacre::mc::refresh_frames", Kokkos::RangePolicy<ExecutionSpace>(0, m.n_bricks), KOKKOS_LAMBDA(const int b) {
        store_frame(p, b, cohesive::make_frame(cohesive::Pose{p(b, 0), p(b, 1), p(b, 2)}));
      });
}

}  // namespace nacre::mc
