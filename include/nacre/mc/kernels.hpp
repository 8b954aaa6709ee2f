#pragma once
/// \file
/// \brief Kernels over the rigid-brick model: total / per-brick energy, rupture count, load
/// application and the colour sweep. Every kernel takes the execution-space instance it runs on
/// (f(space, ...), ArborX style); the model's Views must be accessible from it (checked at
/// compile time). The overloads without a space run on a default-constructed instance of the
/// default execution space.
#include <nacre/core/deterministic_sum.hpp>
#include <nacre/kinematics/rigid.hpp>
#include <nacre/loading/pattern.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/rng/uniform_source.hpp>

namespace nacre::mc {

/// \brief Compile-time check that kernels on ExecutionSpace may touch MemorySpace's Views.
template <class ExecutionSpace, class MemorySpace>
constexpr void check_access() {
  static_assert(Kokkos::is_execution_space_v<ExecutionSpace>, "nacre::mc: not a Kokkos execution space");
  static_assert(Kokkos::SpaceAccessibility<ExecutionSpace, MemorySpace>::accessible,
                "nacre::mc: the model's memory space is not accessible from this execution space");
}

/// \brief Pose of brick b, with its cached rotation.
template <class PV>
KOKKOS_INLINE_FUNCTION kinematics::Frame frame_of(const PV& p, int b) {
  return kinematics::Frame{p(b, 0), p(b, 1), p(b, 2), p(b, 3), p(b, 4)};
}

/// \brief Set brick b's pose (and its cached rotation).
template <class PV>
KOKKOS_INLINE_FUNCTION void store_frame(const PV& p, int b, const kinematics::Frame& f) {
  p(b, 0) = f.x, p(b, 1) = f.y, p(b, 2) = f.t, p(b, 3) = f.s, p(b, 4) = f.c1;
}

/// \brief What the energy kernels read of the model, copied by value into a lambda (Views are
/// handles; the law table and the quadrature rule are a few doubles): one place that evaluates an
/// interface at the current poses.
template <class MemorySpace>
struct InterfaceEvaluator {
  typename Model<MemorySpace>::PoseView pose;
  decltype(Model<MemorySpace>::ends) ends;
  decltype(Model<MemorySpace>::seg) seg;
  decltype(Model<MemorySpace>::kind) kind;
  cohesive::LawTable laws;
  cohesive::Quadrature quad;

  explicit InterfaceEvaluator(const Model<MemorySpace>& m)
      : pose(m.pose), ends(m.ends), seg(m.seg), kind(m.kind), laws(m.laws), quad(m.quad) {}

  KOKKOS_INLINE_FUNCTION const cohesive::Law& law(int i) const { return laws[kind(i)]; }
  KOKKOS_INLINE_FUNCTION cohesive::Gap gap(int i) const {
    return kinematics::interface_gap(load_segment(seg, i), frame_of(pose, ends(i, 0)), frame_of(pose, ends(i, 1)));
  }
  KOKKOS_INLINE_FUNCTION double energy(int i) const {
    return cohesive::segment_energy(law(i), quad, gap(i), seg(i, col(SegCol::length)));
  }
};

/// \brief Total energy: sum over interfaces (deterministic: same bits for any thread count).
template <class ExecutionSpace, class MemorySpace>
double total_energy(const ExecutionSpace& space, const Model<MemorySpace>& m, SumWorkspace<MemorySpace>& ws) {
  check_access<ExecutionSpace, MemorySpace>();
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  const InterfaceEvaluator<MemorySpace> ev(m);
  return deterministic_sum(space, "nacre::mc::total_energy", ws, 0, m.n_interfaces,
                           KOKKOS_LAMBDA(const int i) { return ev.energy(i); });
}

/// \brief Energy of each brick's interfaces: full sum per brick into `full` (each interface
/// counted in both its bricks); half of it is the brick's share of the total.
template <class ExecutionSpace, class MemorySpace>
void brick_energy(const ExecutionSpace& space, const Model<MemorySpace>& m, Field<double, MemorySpace> full) {
  check_access<ExecutionSpace, MemorySpace>();
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  const InterfaceEvaluator<MemorySpace> ev(m);
  auto off = m.adj_offset, adj = m.adj_iface;
  Kokkos::parallel_for(
      "nacre::mc::brick_energy", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_bricks),
      KOKKOS_LAMBDA(const int b) {
        double e = 0;
        for (int j = off(b); j < off(b + 1); ++j) e += ev.energy(adj(j));
        full(b) = e;
      });
}

/// \brief Per-interface energy and state (0 elastic, 1 plastic/softening somewhere, 2 ruptured);
/// either output may be an empty View. Returns the number of ruptured interfaces.
template <class ExecutionSpace, class MemorySpace>
int interface_state(const ExecutionSpace& space, const Model<MemorySpace>& m, Field<double, MemorySpace> energy,
                    Field<std::int8_t, MemorySpace> state) {
  check_access<ExecutionSpace, MemorySpace>();
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  const InterfaceEvaluator<MemorySpace> ev(m);
  int ruptured = 0;
  Kokkos::parallel_reduce(
      "nacre::mc::interface_state", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_interfaces),
      KOKKOS_LAMBDA(const int i, int& acc) {
        const auto& law = ev.law(i);
        const cohesive::Gap g = ev.gap(i);
        if (energy.data()) energy(i) = cohesive::segment_energy(law, ev.quad, g, ev.seg(i, col(SegCol::length)));
        std::int8_t s = 0;
        if (cohesive::min_separation(ev.quad, g) >= law.rupture_distance()) s = 2;
        else if (cohesive::max_separation(g) > law.x1) s = 1;
        if (state.data()) state(i) = s;
        acc += (s == 2);
      },
      ruptured);
  return ruptured;
}

/// \brief Move the driven bricks to the pose the load pattern gives them at opening D
/// (loading::rigid_pose; free bricks are untouched).
template <class ExecutionSpace, class MemorySpace>
void apply_load(const ExecutionSpace& space, const Model<MemorySpace>& m, const loading::Pattern& lp, double D) {
  check_access<ExecutionSpace, MemorySpace>();
  auto p = m.pose;
  auto cx = m.cx, cy = m.cy;
  auto drive = m.drive;
  Kokkos::parallel_for(
      "nacre::mc::apply_load", Kokkos::RangePolicy<ExecutionSpace>(space, m.n_free, m.n_bricks),
      KOKKOS_LAMBDA(const int b) {
        const kinematics::Pose q = loading::rigid_pose(lp, drive(b), cx(b), cy(b), D);
        store_frame(p, b, kinematics::make_frame(q));
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

/// \brief Each interface's energy at the current poses into cache(i): what the sweep's cache
/// must hold before a cycle (after any pose change outside the sweep: load, predictor, polish,
/// restore). The same arithmetic as the sweep's trial evaluation, so the cached value has the
/// bits a recomputation would give.
template <class ExecutionSpace, class MemorySpace>
void interface_energies(const ExecutionSpace& space, const Model<MemorySpace>& m, Field<double, MemorySpace> cache) {
  check_access<ExecutionSpace, MemorySpace>();
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  auto p = m.pose;
  auto ends = m.ends;
  auto seg = m.seg;
  auto kind = m.kind;
  const cohesive::LawTable laws = m.laws;
  const cohesive::Quadrature q = m.quad;
  Kokkos::parallel_for(
      "nacre::mc::interface_energies", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_interfaces),
      KOKKOS_LAMBDA(const int i) {
        cache(i) = kinematics::interface_energy(laws[kind(i)], q, load_segment(seg, i), frame_of(p, ends(i, 0)),
                                                frame_of(p, ends(i, 1)));
      });
}

/// \brief Energy of the interface in adjacency slot j with its brick in frame f and the other
/// brick in frame fo (Model::slot: oriented from the brick's side; same bits as the interface's
/// own orientation, see there).
template <class SlotView>
KOKKOS_INLINE_FUNCTION double slot_energy(const SlotView& r, int j, const cohesive::Law& law,
                                          const kinematics::Frame& f, const kinematics::Frame& fo) {
  using C = SlotCol;
  double a0x, a0y, a1x, a1y, b0x, b0y, b1x, b1y;
  kinematics::point_displacement(f, r(j, col(C::r0x)), r(j, col(C::r0y)), a0x, a0y);
  kinematics::point_displacement(f, r(j, col(C::r1x)), r(j, col(C::r1y)), a1x, a1y);
  kinematics::point_displacement(fo, r(j, col(C::o0x)), r(j, col(C::o0y)), b0x, b0y);
  kinematics::point_displacement(fo, r(j, col(C::o1x)), r(j, col(C::o1y)), b1x, b1y);
  const double tm = 0.5 * (f.t + fo.t), nx = r(j, col(C::nx)), ny = r(j, col(C::ny));
  const cohesive::Gap g{b0x - a0x, b0y - a0y, b1x - a1x, b1y - a1y, nx - tm * ny, ny + tm * nx};
  return cohesive::segment_energy(law, g, r(j, col(C::length)));
}

/// \brief A trial's four uniforms read from a table filled beforehand (any UniformSource).
template <class MemorySpace>
struct TableUniforms {
  rng::UniformTable<MemorySpace> u;
  KOKKOS_INLINE_FUNCTION void operator()(int b, double r[4]) const {
    r[0] = u(b, 0), r[1] = u(b, 1), r[2] = u(b, 2), r[3] = u(b, 3);
  }
};

/// \brief A trial's four uniforms generated where they are used: Philox at the brick's stream
/// (its original id) and the cycle's draw index, the same numbers rng::PhiloxSource writes into
/// the table (one function, rng::philox_uniforms), so no table pass and no table traffic.
template <class MemorySpace>
struct PhiloxUniforms {
  Kokkos::View<const std::uint64_t*, MemorySpace> id;
  std::uint64_t seed, draw;
  KOKKOS_INLINE_FUNCTION void operator()(int b, double r[4]) const { rng::philox_uniforms(seed, id(b), draw, r); }
};

/// \brief Most interfaces of one brick whose trial energies a trial keeps in registers for the
/// cache update on acceptance; a brick with more (not produced by nacre's walls, which give 4-8)
/// recomputes the rest on acceptance: correct for any degree, fast for the usual one.
inline constexpr int kTrialKeep = 12;

/// \brief One Metropolis trial per brick of one colour (MODEL.md §3), work items [begin, end) in
/// parallel, the bricks of a work item (one brick, or a tile) in order. Same-colour work items
/// share no interface, so the trials are independent; uniforms(b, r) gives brick b's four
/// uniforms (TableUniforms or PhiloxUniforms).
/// cache(i) holds interface i's energy at the current poses (interface_energies): a trial
/// evaluates only the brick's own interfaces at the trial pose, the old energy is the sum of
/// their cached values, and an accepted trial writes its new values back. Same-colour bricks
/// share no interface, so no two threads write one entry; the neighbour's view of a shared
/// interface is the same entry, so it stays current. The sums run in the brick's adjacency
/// order, so e_old has the bits of a recomputation at the current poses.
/// de(b) receives the accepted energy change (0 when rejected); the count of accepted trials is
/// returned (an integer reduction, exact for any thread count).
template <class ExecutionSpace, class MemorySpace, class Uniforms>
long sweep_colour(const ExecutionSpace& space, const Model<MemorySpace>& m, int begin, int end,
                  const Uniforms& uniforms, Field<double, MemorySpace> cache, Field<double, MemorySpace> de,
                  double step, double rot_step, double temperature, const BrickSteps<MemorySpace>& brick_steps = {}) {
  check_access<ExecutionSpace, MemorySpace>();
  auto p = m.pose;
  auto off = m.adj_offset;
  auto slot = m.slot;
  auto link = m.slot_link;
  auto skind = m.slot_kind;
  auto tiles = m.tile_offset;
  const cohesive::LawTable laws = m.laws;
  const double inv_t = temperature > 0 ? 1.0 / temperature : 0.0;
  const bool per_brick = brick_steps.active();
  auto bstep = brick_steps.step;
  auto bacc = brick_steps.accepted;
  long accepted = 0;
  Kokkos::parallel_reduce(
      "nacre::mc::sweep_colour", Kokkos::RangePolicy<ExecutionSpace>(space, begin, end),
      KOKKOS_LAMBDA(const int w, long& acc) {
       for (int b = tiles(w); b < tiles(w + 1); ++b) {
        const kinematics::Frame f_old = frame_of(p, b);
        double u[4];
        uniforms(b, u);
        const double s = per_brick ? bstep(b, 0) : step, sr = per_brick ? bstep(b, 1) : rot_step;
        const kinematics::Pose trial{f_old.x + s * (2.0 * u[0] - 1.0), f_old.y + s * (2.0 * u[1] - 1.0),
                                     f_old.t + sr * (2.0 * u[2] - 1.0)};
        const kinematics::Frame f_new = kinematics::make_frame(trial);
        const int j0 = off(b), j1 = off(b + 1);
        double e_old = 0, e_new = 0;
        double keep[kTrialKeep];
        for (int j = j0; j < j1; ++j) {
          const double en = slot_energy(slot, j, laws[skind(j)], f_new, frame_of(p, link(j, 0)));
          if (j - j0 < kTrialKeep) keep[j - j0] = en;
          e_old += cache(link(j, 1));
          e_new += en;
        }
        const double d = e_new - e_old;
        const bool accept = d <= 0.0 || (inv_t > 0.0 && u[3] < Kokkos::exp(-d * inv_t));
        if (accept) {
          store_frame(p, b, f_new);
          for (int j = j0; j < j1; ++j)
            cache(link(j, 1)) =
                j - j0 < kTrialKeep ? keep[j - j0] : slot_energy(slot, j, laws[skind(j)], f_new, frame_of(p, link(j, 0)));
          acc += 1;
          if (per_brick) bacc(b) += 1;  // one thread per brick: no race
        }
        de(b) = accept ? d : 0.0;
       }
      },
      accepted);
  return accepted;
}

/// \brief The same without a caller-held cache (tests, one-off sweeps): fills a temporary one
/// at the current poses first.
template <class ExecutionSpace, class MemorySpace>
long sweep_colour(const ExecutionSpace& space, const Model<MemorySpace>& m, int begin, int end,
                  rng::UniformTable<MemorySpace> u, Field<double, MemorySpace> de, double step, double rot_step,
                  double temperature, const BrickSteps<MemorySpace>& brick_steps = {}) {
  Field<double, MemorySpace> cache(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::energy_cache"),
                                   m.n_interfaces);
  interface_energies(space, m, cache);
  return sweep_colour(space, m, begin, end, TableUniforms<MemorySpace>{u}, cache, de, step, rot_step, temperature, brick_steps);
}

/// \brief Position predictor (eq. 2.10, 2.11) for the free bricks: p += ratio (p - p_prev) m,
/// m = 1 - 1.8 (max(min(phi/phi0, 1), 0.5) - 0.5): linear extrapolation at low energy, fading
/// to constant prediction as the brick approaches its elastic limit. ratio = D_{n+1} / D_n.
template <class ExecutionSpace, class MemorySpace>
void predict_poses(const ExecutionSpace& space, const Model<MemorySpace>& m,
                   typename Model<MemorySpace>::PoseView prev, Field<double, MemorySpace> phi, double ratio) {
  check_access<ExecutionSpace, MemorySpace>();
  auto p = m.pose;
  auto phi0 = m.phi0;
  Kokkos::parallel_for(
      "nacre::mc::predict", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_free), KOKKOS_LAMBDA(const int b) {
        const double r = phi0(b) > 0 ? phi(b) / phi0(b) : 0.0;
        const double mfac = 1.0 - 1.8 * (Kokkos::fmax(Kokkos::fmin(r, 1.0), 0.5) - 0.5);
        kinematics::Pose q{p(b, 0), p(b, 1), p(b, 2)};
        q.x += ratio * (q.x - prev(b, 0)) * mfac;
        q.y += ratio * (q.y - prev(b, 1)) * mfac;
        q.t += ratio * (q.t - prev(b, 2)) * mfac;
        store_frame(p, b, kinematics::make_frame(q));
      });
}

/// \brief eq. 2.7: a step size s after a window with acceptance a: s (0.5 + a) clamped to
/// [lo, hi] when a is outside [0.4, 0.6], else unchanged.
KOKKOS_INLINE_FUNCTION double adapted_step(double s, double a, double lo, double hi) {
  return (a < 0.4 || a > 0.6) ? Kokkos::clamp(s * (0.5 + a), lo, hi) : s;
}

/// \brief The same rule about another acceptance target (band target +- 0.1, factor
/// 1 + a - target): annealing at T -> 0 cannot reach eq. 2.7's 0.5 (a descent-only chain
/// accepts at most half of small trials), so it aims lower (Solver::anneal).
KOKKOS_INLINE_FUNCTION double adapted_step(double s, double a, double lo, double hi, double target) {
  return (a < target - 0.1 || a > target + 0.1) ? Kokkos::clamp(s * (1.0 + (a - target)), lo, hi) : s;
}

/// \brief eq. 2.7 per brick: after `interval` trials, adapt each brick's steps to its own
/// acceptance (adapted_step) and restart its count.
template <class ExecutionSpace, class MemorySpace>
void adapt_brick_steps(const ExecutionSpace& space, const BrickSteps<MemorySpace>& bs, int n_free, int interval,
                       double min_step, double max_step, double min_rot, double max_rot, double target = 0.5) {
  check_access<ExecutionSpace, MemorySpace>();
  auto step = bs.step;
  auto acc = bs.accepted;
  Kokkos::parallel_for(
      "nacre::mc::adapt_brick_steps", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n_free),
      KOKKOS_LAMBDA(const int b) {
        const double a = static_cast<double>(acc(b)) / interval;
        step(b, 0) = target == 0.5 ? adapted_step(step(b, 0), a, min_step, max_step)
                                   : adapted_step(step(b, 0), a, min_step, max_step, target);
        step(b, 1) = target == 0.5 ? adapted_step(step(b, 1), a, min_rot, max_rot)
                                   : adapted_step(step(b, 1), a, min_rot, max_rot, target);
        acc(b) = 0;
      });
}

/// \brief Recompute the cached rotation of every brick from its angle (after poses were set from
/// outside, e.g. a checkpoint), with the same device sine the sweep uses.
template <class ExecutionSpace, class MemorySpace>
void refresh_frames(const ExecutionSpace& space, const Model<MemorySpace>& m) {
  check_access<ExecutionSpace, MemorySpace>();
  auto p = m.pose;
  Kokkos::parallel_for(
      "nacre::mc::refresh_frames", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_bricks),
      KOKKOS_LAMBDA(const int b) {
        store_frame(p, b, kinematics::make_frame(kinematics::Pose{p(b, 0), p(b, 1), p(b, 2)}));
      });
}

// ---- default-instance overloads (callers that do not manage instances, e.g. the writers)
template <class MemorySpace>
double total_energy(const Model<MemorySpace>& m, SumWorkspace<MemorySpace>& ws) {
  return total_energy(ExecSpace{}, m, ws);
}
template <class MemorySpace>
void brick_energy(const Model<MemorySpace>& m, Field<double, MemorySpace> full) {
  brick_energy(ExecSpace{}, m, full);
}
template <class MemorySpace>
int interface_state(const Model<MemorySpace>& m, Field<double, MemorySpace> energy,
                    Field<std::int8_t, MemorySpace> state) {
  return interface_state(ExecSpace{}, m, energy, state);
}

}  // namespace nacre::mc
