// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Kernels over the rigid-brick model: total / per-brick energy, rupture count, load
/// application and the colour sweep. Every kernel takes the execution-space instance it runs on
/// (f(space, ...), ArborX style); the model's Views must be accessible from it (checked at
/// compile time). The overloads without a space run on a default-constructed instance of the
/// default execution space.
#include <nacre/core/assert.hpp>
#include <nacre/core/deterministic_sum.hpp>
#include <nacre/kinematics/rigid.hpp>
#include <nacre/loading/pattern.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/rng/uniform_source.hpp>

#include <type_traits>

#if defined(__AVX512F__) && !defined(__CUDA_ARCH__)
#include <immintrin.h>  // the batched sweep's row transpose (detail::transpose_rows)
#endif

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
  decltype(Model<MemorySpace>::hist) hist;
  cohesive::LawTable laws;
  cohesive::Quadrature quad;

  explicit InterfaceEvaluator(const Model<MemorySpace>& m)
      : pose(m.pose), ends(m.ends), seg(m.seg), kind(m.kind), hist(m.hist), laws(m.laws), quad(m.quad) {}

  KOKKOS_INLINE_FUNCTION const cohesive::Law& law(int i) const { return laws[kind(i)]; }
  KOKKOS_INLINE_FUNCTION cohesive::Gap gap(int i) const {
    return kinematics::interface_gap(load_segment(seg, i), frame_of(pose, ends(i, 0)), frame_of(pose, ends(i, 1)));
  }
  /// Interface i's damage history, or null (the reversible law).
  KOKKOS_INLINE_FUNCTION const double* history(int i) const { return hist.data() ? &hist(i, 0) : nullptr; }
  KOKKOS_INLINE_FUNCTION double energy(int i) const {
    return cohesive::integrate(cohesive::EnergyTag{}, law(i), quad, gap(i), seg(i, col(SegCol::length)), history(i));
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
  NACRE_ASSERT(full.extent(0) >= std::size_t(m.n_bricks), "brick_energy: a value per brick");
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

/// \brief The same from each interface's energy already evaluated (`iface_energy`, e.g. by
/// interface_state): each brick adds its interfaces' values in the same order, so the bits are
/// brick_energy's, for one evaluation per interface instead of two.
template <class ExecutionSpace, class MemorySpace>
void brick_energy(const ExecutionSpace& space, const Model<MemorySpace>& m, Field<double, MemorySpace> full,
                  Kokkos::View<const double*, MemorySpace> iface_energy) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(full.extent(0) >= std::size_t(m.n_bricks), "brick_energy: a value per brick");
  NACRE_ASSERT(iface_energy.extent(0) >= std::size_t(m.n_interfaces), "brick_energy: a value per interface");
  auto off = m.adj_offset, adj = m.adj_iface;
  Kokkos::parallel_for(
      "nacre::mc::brick_energy_from_interfaces", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_bricks),
      KOKKOS_LAMBDA(const int b) {
        double e = 0;
        for (int j = off(b); j < off(b + 1); ++j) e += iface_energy(adj(j));
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
        const double* kappa = ev.history(i);
        if (energy.data())
          energy(i) =
              cohesive::integrate(cohesive::EnergyTag{}, law, ev.quad, g, ev.seg(i, col(SegCol::length)), kappa);
        // with a history, what the joint has been through counts: ruptured for good once every
        // point has seen x1 + x2, softening once any has passed x1
        const double kmin = kappa ? cohesive::min_history(kappa, ev.quad.n) : 0.0;
        const double kmax = kappa ? cohesive::max_history(kappa, ev.quad.n) : 0.0;
        std::int8_t s = 0;
        if (Kokkos::fmax(cohesive::min_separation(g), kmin) >= law.rupture_distance())
          s = 2;
        else if (Kokkos::fmax(cohesive::max_separation(g), kmax) > law.x1)
          s = 1;
        if (state.data()) state(i) = s;
        acc += (s == 2);
      },
      ruptured);
  return ruptured;
}

/// \brief Raise every interface's damage history to its separations at the current poses
/// (cohesive::update_history; nothing without a history). The Monte Carlo rule: called once a
/// load step has converged, so the energy minimised within a step is one function. Returns the
/// number of interfaces whose history grew (an integer reduction: exact).
template <class ExecutionSpace, class MemorySpace>
int update_history(const ExecutionSpace& space, const Model<MemorySpace>& m) {
  check_access<ExecutionSpace, MemorySpace>();
  if (!m.hist.data()) return 0;
  NACRE_ASSERT(m.hist.extent(0) == std::size_t(m.n_interfaces) && m.hist.extent(1) == std::size_t(m.quad.n),
               "update_history: a history row of quad.n values per interface");
  Kokkos::Profiling::ScopedRegion region("nacre::mc::history");
  const InterfaceEvaluator<MemorySpace> ev(m);
  auto hist = m.hist;
  int grew = 0;
  Kokkos::parallel_reduce(
      "nacre::mc::update_history", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_interfaces),
      KOKKOS_LAMBDA(const int i, int& acc) { acc += cohesive::update_history(ev.quad, ev.gap(i), &hist(i, 0)); }, grew);
  return grew;
}

/// \brief Energy each interface has dissipated by damage (cohesive::dissipated over its history)
/// into `out`; zero without a history.
template <class ExecutionSpace, class MemorySpace>
void interface_dissipation(const ExecutionSpace& space, const Model<MemorySpace>& m, Field<double, MemorySpace> out) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(out.extent(0) >= std::size_t(m.n_interfaces), "interface_dissipation: a value per interface");
  const InterfaceEvaluator<MemorySpace> ev(m);
  Kokkos::parallel_for(
      "nacre::mc::interface_dissipation", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_interfaces),
      KOKKOS_LAMBDA(const int i) {
        const double* kappa = ev.history(i);
        out(i) = kappa ? cohesive::dissipated(ev.law(i), ev.quad, kappa, ev.seg(i, col(SegCol::length))) : 0.0;
      });
}

/// \brief Move the driven bricks to the pose the load pattern gives them at opening D
/// (loading::rigid_pose; free bricks, a rank's free halo bricks among them, are untouched).
template <class ExecutionSpace, class MemorySpace>
void apply_load(const ExecutionSpace& space, const Model<MemorySpace>& m, const loading::Pattern& lp, double D) {
  check_access<ExecutionSpace, MemorySpace>();
  auto p = m.pose;
  auto cx = m.cx, cy = m.cy;
  auto drive = m.drive;
  Kokkos::parallel_for(
      "nacre::mc::apply_load", Kokkos::RangePolicy<ExecutionSpace>(space, m.n_free, m.n_bricks),
      KOKKOS_LAMBDA(const int b) {
        if (drive(b) == 0) return;  // a rank's halo brick that is free (mc/halo.hpp): its owner's pose
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

/// \brief interface_energies (below) for the interfaces list(0 .. n-1) only (an empty list:
/// interfaces 0 .. n-1): the entries a halo exchange made stale (mc/halo.hpp).
template <class ExecutionSpace, class MemorySpace>
void interface_energies(const ExecutionSpace& space, const Model<MemorySpace>& m, Field<double, MemorySpace> cache,
                        Kokkos::View<const int*, MemorySpace> list, int n) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(cache.extent(0) >= std::size_t(m.n_interfaces), "interface_energies: a cache entry per interface");
  NACRE_ASSERT(list.data() == nullptr || list.extent(0) >= std::size_t(n), "interface_energies: n entries in the list");
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");
  auto p = m.pose;
  auto ends = m.ends;
  auto seg = m.seg;
  auto kind = m.kind;
  auto hist = m.hist;
  const cohesive::LawTable laws = m.laws;
  const cohesive::Quadrature q = m.quad;
  Kokkos::parallel_for(
      "nacre::mc::interface_energies", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n), KOKKOS_LAMBDA(const int k) {
        const int i = list.data() ? list(k) : k;
        cache(i) = kinematics::interface_energy(laws[kind(i)], q, load_segment(seg, i), frame_of(p, ends(i, 0)),
                                                frame_of(p, ends(i, 1)), hist.data() ? &hist(i, 0) : nullptr);
      });
}

/// \brief Each interface's energy at the current poses into cache(i): what the sweep's cache
/// must hold before a cycle (after any pose change outside the sweep: load, predictor, polish,
/// restore). The same arithmetic as the sweep's trial evaluation, so the cached value has the
/// bits a recomputation would give.
template <class ExecutionSpace, class MemorySpace>
void interface_energies(const ExecutionSpace& space, const Model<MemorySpace>& m, Field<double, MemorySpace> cache) {
  interface_energies(space, m, cache, Kokkos::View<const int*, MemorySpace>{}, m.n_interfaces);
}

/// \brief Energy of the interface in adjacency slot j with its brick in frame f and the other
/// brick in frame fo (Model::slot: oriented from the brick's side; same bits as the interface's
/// own orientation, see there). `kappa`: the interface's damage history at q's points, or null
/// (the reversible law's exact integral; q is then not read).
/// (T: double, or flops::Counted where a trial's flops are counted, mc/trial_flops.hpp: the
/// reversible law only, kappa null)
template <class SlotView, class T>
KOKKOS_INLINE_FUNCTION T slot_energy(const SlotView& r, int j, const cohesive::Law& law,
                                     const kinematics::BasicFrame<T>& f, const kinematics::BasicFrame<T>& fo,
                                     const cohesive::Quadrature& q, const double* kappa) {
  using C = SlotCol;
  T a0x, a0y, a1x, a1y, b0x, b0y, b1x, b1y;
  kinematics::point_displacement(f, r(j, col(C::r0x)), r(j, col(C::r0y)), a0x, a0y);
  kinematics::point_displacement(f, r(j, col(C::r1x)), r(j, col(C::r1y)), a1x, a1y);
  kinematics::point_displacement(fo, r(j, col(C::o0x)), r(j, col(C::o0y)), b0x, b0y);
  kinematics::point_displacement(fo, r(j, col(C::o1x)), r(j, col(C::o1y)), b1x, b1y);
  const T tm = 0.5 * (f.t + fo.t);
  const double nx = r(j, col(C::nx)), ny = r(j, col(C::ny));
  const cohesive::BasicGap<T> g{b0x - a0x, b0y - a0y, b1x - a1x, b1y - a1y, nx - tm * ny, ny + tm * nx};
  if constexpr (std::is_same_v<T, double>) {
    return cohesive::integrate(cohesive::EnergyTag{}, law, q, g, r(j, col(C::length)), kappa);
  } else {
    return cohesive::integrate(cohesive::EnergyTag{}, law, g, r(j, col(C::length)));
  }
}

/// \brief The trial pose of a brick at frame f_old from its uniforms u[0..2] and the step sizes:
/// each coordinate moved by a uniform in [-step, step] (one definition for the sweep and the flop
/// count of a trial).
template <class T>
KOKKOS_INLINE_FUNCTION kinematics::BasicFrame<T> trial_frame(const kinematics::Frame& f_old, const double u[4],
                                                             double s, double sr) {
  return kinematics::make_frame<T>(T(f_old.x) + s * (2.0 * T(u[0]) - 1.0), T(f_old.y) + s * (2.0 * T(u[1]) - 1.0),
                                   T(f_old.t) + sr * (2.0 * T(u[2]) - 1.0));
}

namespace detail {
/// \brief Rows of N values stored row after row (what a LayoutRight View<T* [N]> holds when
/// unpadded), read as p[i N + c]: the sweep's hot loads without the View's index arithmetic,
/// which the compiler does not fold away in the trial loop (callgrind: ~90 instructions per trial
/// in extents and accessor code, perf/README.md). The same addresses, so the same values.
template <class T, int N>
struct Rows {
  T* p;
  KOKKOS_INLINE_FUNCTION T& operator()(int i, int c) const { return p[static_cast<std::size_t>(i) * N + c]; }
};
/// \brief Rows over a rank-2 View with N columns (host-side check that it is unpadded).
template <int N, class V>
Rows<typename V::value_type, N> rows_of(const V& v) {
  static_assert(V::rank == 2, "nacre::mc::detail::rows_of: a rank-2 View");
  NACRE_ASSERT(v.extent(0) == 0 || (v.extent(1) == std::size_t(N) && v.stride(0) == std::size_t(N) && v.stride(1) == 1),
               "rows_of: a View of N unpadded values per row");
  return {v.data()};
}
}  // namespace detail

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

/// \brief Trial evaluation of the sweep, one brick per thread at a time: the schedule of every
/// backend (a GPU thread's), and the reference the batched form is tested against.
struct ScalarTrials {};
/// \brief Trial evaluation of the sweep on a host: kSweepLanes same-colour work items in lockstep
/// (see sweep_colour(BatchedTrials, ...)). Same trials, same bits as ScalarTrials.
struct BatchedTrials {};

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
/// PerBrick (a variant, not a run-time flag inside the kernel): step sizes per brick
/// (BrickSteps active) or the global ones; sweep_colour(ScalarTrials, ...) picks it once.
template <bool PerBrick, class ExecutionSpace, class MemorySpace, class Uniforms>
long sweep_colour(ScalarTrials, std::bool_constant<PerBrick>, const ExecutionSpace& space, const Model<MemorySpace>& m,
                  int begin, int end, const Uniforms& uniforms, Field<double, MemorySpace> cache,
                  Field<double, MemorySpace> de, double step, double rot_step, double temperature,
                  const BrickSteps<MemorySpace>& brick_steps) {
  check_access<ExecutionSpace, MemorySpace>();
  NACRE_ASSERT(cache.extent(0) >= std::size_t(m.n_interfaces), "sweep_colour: an energy cache entry per interface");
  NACRE_ASSERT(de.extent(0) >= std::size_t(m.n_free), "sweep_colour: an energy change per free brick");
  NACRE_ASSERT(!m.hist.data() || m.hist.extent(1) == std::size_t(m.quad.n),
               "sweep_colour: a damage history of one value per quadrature point");
  NACRE_ASSERT(!brick_steps.active() || brick_steps.step.extent(0) >= std::size_t(m.n_free),
               "sweep_colour: per-brick steps for every free brick");
  const auto p = detail::rows_of<5>(m.pose);
  const int* const off = m.adj_offset.data();
  const auto slot = detail::rows_of<col(SlotCol::count)>(m.slot);
  const auto link = detail::rows_of<2>(m.slot_link);
  const std::uint8_t* const skind = m.slot_kind.data();
  const int* const tiles = m.tile_offset.data();
  double* const cached = cache.data();
  double* const dE = de.data();
  const cohesive::LawTable laws = m.laws;
  const cohesive::Quadrature quad = m.quad;
  double* const hist = m.hist.data();  // rows of quad.n values (LayoutRight), or null
  const int nq = m.quad.n;
  const double inv_t = temperature > 0 ? 1.0 / temperature : 0.0;
  auto bstep = brick_steps.step;
  auto bacc = brick_steps.accepted;
  long accepted = 0;
  Kokkos::parallel_reduce(
      "nacre::mc::sweep_colour", Kokkos::RangePolicy<ExecutionSpace>(space, begin, end),
      KOKKOS_LAMBDA(const int w, long& acc) {
       for (int b = tiles[w]; b < tiles[w + 1]; ++b) {
        const kinematics::Frame f_old = frame_of(p, b);
        double u[4];
        uniforms(b, u);
        const double s = PerBrick ? bstep(b, 0) : step, sr = PerBrick ? bstep(b, 1) : rot_step;
        const kinematics::Frame f_new = trial_frame<double>(f_old, u, s, sr);
        const int j0 = off[b], j1 = off[b + 1];
        double e_old = 0, e_new = 0;
        double keep[kTrialKeep];
        for (int j = j0; j < j1; ++j) {
          const double en = slot_energy(slot, j, laws[skind[j]], f_new, frame_of(p, link(j, 0)), quad,
                                        hist ? hist + static_cast<std::size_t>(link(j, 1)) * nq : nullptr);
          if (j - j0 < kTrialKeep) keep[j - j0] = en;
          e_old += cached[link(j, 1)];
          e_new += en;
        }
        const double d = e_new - e_old;
        const bool accept = d <= 0.0 || (inv_t > 0.0 && u[3] < Kokkos::exp(-d * inv_t));
        if (accept) {
          store_frame(p, b, f_new);
          for (int j = j0; j < j1; ++j)
            cached[link(j, 1)] = j - j0 < kTrialKeep
                                     ? keep[j - j0]
                                     : slot_energy(slot, j, laws[skind[j]], f_new, frame_of(p, link(j, 0)), quad,
                                                   hist ? hist + static_cast<std::size_t>(link(j, 1)) * nq : nullptr);
          acc += 1;
          // one thread per brick: no race (a plain if: nvcc's lambdas may not capture in an if constexpr)
          if (PerBrick) bacc(b) += 1;
        }
        dE[b] = accept ? d : 0.0;
       }
      },
      accepted);
  return accepted;
}


/// Marks a loop over the lanes of BatchedTrials for vectorisation (OpenMP's simd where the host
/// compiler has OpenMP; the loops are written to vectorise without it too).
#if defined(_OPENMP) && !defined(__CUDA_ARCH__)
#define NACRE_MC_LANES _Pragma("omp simd")
#else
#define NACRE_MC_LANES
#endif

/// \brief Work items a host thread sweeps in lockstep (BatchedTrials): 8 doubles fill an AVX-512
/// register (4 AVX2, 2 SSE2 registers: the same code, narrower instructions).
inline constexpr int kSweepLanes = 8;

namespace detail {
/// \brief A joint kind's law constants as the batched trial reads them (the scalar code's own
/// subexpressions, so the products round alike): indexed by kind byte.
struct LaneLaws {
  static_assert(geometry::kJointKinds == 3, "sweep_colour(BatchedTrials) selects among three joint kinds");
  double k[geometry::kJointKinds], x1sq[geometry::kJointKinds];
};
inline LaneLaws lane_laws(const cohesive::LawTable& t) {
  LaneLaws l{};
  for (int i = 0; i < geometry::kJointKinds; ++i) {
    l.k[i] = t.law[i].k, l.x1sq[i] = t.law[i].x1 * t.law[i].x1;
  }
  return l;
}

/// \brief rows[l] points to lane l's n consecutive doubles (n <= 8); out[c][l] = rows[l][c] for
/// c < n (out needs 8 rows). The lanes' interface records and neighbour poses sit at unrelated
/// addresses: read element by element they cost a load and an insert each (this CPU's gather
/// instructions are slower still, measured), read as rows and transposed in registers (AVX-512:
/// one masked load per lane, 24 shuffles per 8 x 8 block) they cost a few instructions per row.
/// Pure data movement: the values, hence the bits, are the same either way.
inline void transpose_rows(const double* const rows[kSweepLanes], int n, double (*out)[kSweepLanes]) {
#if defined(__AVX512F__) && !defined(__CUDA_ARCH__)
  static_assert(kSweepLanes == 8, "the AVX-512 transpose moves 8 x 8 blocks");
  const __mmask8 m = static_cast<__mmask8>((1u << n) - 1u);  // masked loads: no read past a row
  __m512d r[8], t[8], u[8];
  for (int l = 0; l < 8; ++l) r[l] = _mm512_maskz_loadu_pd(m, rows[l]);
  for (int l = 0; l < 8; l += 2) {  // [a0 b0 | a2 b2 | a4 b4 | a6 b6], [a1 b1 | a3 b3 | ...]
    t[l] = _mm512_unpacklo_pd(r[l], r[l + 1]);
    t[l + 1] = _mm512_unpackhi_pd(r[l], r[l + 1]);
  }
  for (int h = 0; h < 8; h += 4) {  // 128-bit quarters: columns {0,4}, {2,6}, {1,5}, {3,7} of 4 rows
    u[h + 0] = _mm512_shuffle_f64x2(t[h + 0], t[h + 2], 0x88);
    u[h + 1] = _mm512_shuffle_f64x2(t[h + 0], t[h + 2], 0xDD);
    u[h + 2] = _mm512_shuffle_f64x2(t[h + 1], t[h + 3], 0x88);
    u[h + 3] = _mm512_shuffle_f64x2(t[h + 1], t[h + 3], 0xDD);
  }
  _mm512_storeu_pd(out[0], _mm512_shuffle_f64x2(u[0], u[4], 0x88));
  _mm512_storeu_pd(out[4], _mm512_shuffle_f64x2(u[0], u[4], 0xDD));
  _mm512_storeu_pd(out[2], _mm512_shuffle_f64x2(u[1], u[5], 0x88));
  _mm512_storeu_pd(out[6], _mm512_shuffle_f64x2(u[1], u[5], 0xDD));
  _mm512_storeu_pd(out[1], _mm512_shuffle_f64x2(u[2], u[6], 0x88));
  _mm512_storeu_pd(out[5], _mm512_shuffle_f64x2(u[2], u[6], 0xDD));
  _mm512_storeu_pd(out[3], _mm512_shuffle_f64x2(u[3], u[7], 0x88));
  _mm512_storeu_pd(out[7], _mm512_shuffle_f64x2(u[3], u[7], 0xDD));
#else
  for (int c = 0; c < n; ++c)
    for (int l = 0; l < kSweepLanes; ++l) out[c][l] = rows[l][c];
#endif
}

/// \brief Ask for the cache line at p (a hint; nothing where the compiler has no builtin).
inline void prefetch(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(p, 0, 3);
#else
  (void)p;
#endif
}
}  // namespace detail

/// \brief sweep_colour on a host execution space with the trials of kSweepLanes work items
/// evaluated side by side (structure of arrays over the lanes, one lane per work item): lane l
/// takes work item begin + kSweepLanes g + l, and step k of the group tries the k-th brick of
/// every lane's work item (a tile's bricks stay in their order; single-brick work items are one
/// step). The lanes' bricks have one colour and sit in different work items, so they share no
/// interface and none is another's neighbour: evaluating them together changes no trial.
///
/// Per step, the lanes' slots j = 0, 1, ... are evaluated as one loop over the lanes without
/// branches, which the compiler turns into vector instructions (the records and the neighbours'
/// poses transposed from rows first, detail::transpose_rows; the elastic closed form and the
/// penalty's sixth power as selects); a lane whose interface is not elastic everywhere takes the
/// scalar cohesive::segment_energy for that slot. The proposal (Philox, two sines), the
/// Metropolis test and the writes stay per lane, in the scalar code's order. The lane arithmetic
/// is the scalar code's expression for expression, so the energies, acceptances and poses have
/// the scalar path's bits (tests/test_mc_batched.cpp checks this on damaged and penetrating
/// interfaces, three colourings, global and per-brick steps). Host only (a plain lambda and
/// host intrinsics); measured slower than ScalarTrials at 300k bricks on the CPU it was written
/// on, so the solver uses it only with NACRE_MC_BATCHED (perf/README.md, "Batched trials").
template <bool PerBrick, class ExecutionSpace, class MemorySpace, class Uniforms>
long sweep_colour(BatchedTrials, std::bool_constant<PerBrick>, const ExecutionSpace& space, const Model<MemorySpace>& m,
                  int begin, int end, const Uniforms& uniforms, Field<double, MemorySpace> cache,
                  Field<double, MemorySpace> de, double step, double rot_step, double temperature,
                  const BrickSteps<MemorySpace>& brick_steps) {
  check_access<ExecutionSpace, MemorySpace>();
  static_assert(Kokkos::SpaceAccessibility<ExecutionSpace, Kokkos::HostSpace>::accessible,
                "nacre::mc: the batched sweep is a host schedule (devices take ScalarTrials)");
  constexpr int W = kSweepLanes;
  auto p = m.pose;
  auto off = m.adj_offset;
  auto slot = m.slot;
  auto link = m.slot_link;
  auto skind = m.slot_kind;
  auto tiles = m.tile_offset;
  const cohesive::LawTable laws = m.laws;
  const cohesive::Quadrature quad = m.quad;
  const double* const hist = m.hist.data();  // rows of quad.n values, or null
  const int nq = m.quad.n;
  const detail::LaneLaws ll = detail::lane_laws(laws);
  const double inv_t = temperature > 0 ? 1.0 / temperature : 0.0;
  auto bstep = brick_steps.step;
  auto bacc = brick_steps.accepted;
  // raw pointers for the lane loops, with the unpadded LayoutRight row lengths as constants (a
  // slot's 11 numbers, a link's 2, a pose's 5): rows are then fixed-size blocks to transpose
  constexpr int rs = col(SlotCol::count), lsr = 2, ps = 5;
  static_assert(rs > 8 && rs <= 16 && ps <= 8, "transpose_rows moves a record in two blocks, a pose in one");
  const double* rec = detail::rows_of<rs>(slot).p;  // rows_of checks the rows are unpadded
  const int* lnk = detail::rows_of<lsr>(link).p;
  const std::uint8_t* kinds = skind.data();
  const double* pose = detail::rows_of<ps>(p).p;
  const double* cached = cache.data();
  const int groups = (end - begin + W - 1) / W;
  long accepted = 0;
  Kokkos::parallel_reduce(
      "nacre::mc::sweep_colour_batched", Kokkos::RangePolicy<ExecutionSpace>(space, 0, groups),
      [=](const int g, long& acc) {
        // pointers and the laws' constants as locals (registers), not loads from the closure
        // inside the lane loops (which the vectoriser cannot hoist)
        const double* const rec_l = rec;
        const int* const lnk_l = lnk;
        const std::uint8_t* const kinds_l = kinds;
        const double* const pose_l = pose;
        const double* const cached_l = cached;
        const Uniforms uni = uniforms;
        const double k0 = ll.k[0], k1 = ll.k[1], k2 = ll.k[2];
        const double xs0 = ll.x1sq[0], xs1 = ll.x1sq[1], xs2 = ll.x1sq[2];
        int first[W], last[W];
        int kmax = 0;
        for (int l = 0; l < W; ++l) {
          const int w = begin + g * W + l;
          first[l] = w < end ? tiles(w) : 0;
          last[l] = w < end ? tiles(w + 1) : 0;
          kmax = Kokkos::max(kmax, last[l] - first[l]);
        }
        for (int k = 0; k < kmax; ++k) {
          int act[W], bl[W], j0[W], deg[W];
          double fx[W], fy[W], ft[W], fs[W], fc[W], u3[W], uu[3][W];
          for (int l = 0; l < W; ++l) {
            act[l] = first[l] + k < last[l];
            bl[l] = act[l] ? first[l] + k : 0;  // idle lanes draw for brick 0 (it exists), unused
          }
          // Prefetch the records (and links) of the brick each lane tries next: the next brick of
          // its tile, or its work item in the next group. Slot jj of 8 lanes touches 8 records
          // 0.5-4 KB apart, a pattern the hardware prefetcher follows worse than the scalar
          // sweep's one stream; one step ahead (8 trials, ~1 us) covers the memory latency.
          for (int l = 0; l < W; ++l) {
            const int w_next = begin + (g + 1) * W + l;
            const int nb = first[l] + k + 1 < last[l] ? first[l] + k + 1 : (w_next < end ? tiles(w_next) : -1);
            if (nb < 0) continue;
            const int ja = off(nb), jb = off(nb + 1);
            for (const char* q = reinterpret_cast<const char*>(rec_l + ja * rs);
                 q < reinterpret_cast<const char*>(rec_l + jb * rs); q += 64)
              detail::prefetch(q);
            detail::prefetch(lnk_l + ja * lsr);
          }
          // the proposal: the uniforms of all lanes in one loop (Philox is integer arithmetic the
          // vector unit does lane by lane), the trial poses, then the two sines per lane (libm)
          NACRE_MC_LANES
          for (int l = 0; l < W; ++l) {
            double u[4];
            uni(bl[l], u);
            uu[0][l] = u[0], uu[1][l] = u[1], uu[2][l] = u[2], u3[l] = u[3];
          }
          int dmax = 0;
          for (int l = 0; l < W; ++l) {
            const int b = bl[l];
            const kinematics::Frame f_old = frame_of(p, b);
            const double s = PerBrick ? bstep(b, 0) : step, sr = PerBrick ? bstep(b, 1) : rot_step;
            const kinematics::Pose trial{f_old.x + s * (2.0 * uu[0][l] - 1.0), f_old.y + s * (2.0 * uu[1][l] - 1.0),
                                         f_old.t + sr * (2.0 * uu[2][l] - 1.0)};
            const kinematics::Frame f = kinematics::make_frame(trial);
            fx[l] = f.x, fy[l] = f.y, ft[l] = f.t, fs[l] = f.s, fc[l] = f.c1;
            j0[l] = off(b), deg[l] = act[l] ? off(b + 1) - j0[l] : 0;
            dmax = Kokkos::max(dmax, deg[l]);
          }
          double e_old[W], e_new[W], keep[kTrialKeep][W];
          for (int l = 0; l < W; ++l) e_old[l] = e_new[l] = 0.0;
          for (int jj = 0; jj < dmax; ++jj) {
            int js[W], on[W], general[W], kind[W];  // int, not bool / uint8: 32-bit lanes the vector unit gathers and masks
            double en[W], eo[W];
            for (int l = 0; l < W; ++l) {
              on[l] = jj < deg[l];
              js[l] = on[l] ? j0[l] + jj : 0;  // idle lanes read slot 0 (it exists)
              kind[l] = kinds_l[js[l]];          // bytes: no byte gathers, so loaded here
            }
            // the lanes' records and their neighbours' poses, transposed to one row per field
            double rc[16][W], po[8][W];
            {
              const double* rows[W];
              for (int l = 0; l < W; ++l) rows[l] = rec_l + js[l] * rs;
              detail::transpose_rows(rows, 8, rc);
              for (int l = 0; l < W; ++l) rows[l] += 8;
              detail::transpose_rows(rows, rs - 8, rc + 8);
              for (int l = 0; l < W; ++l) rows[l] = pose_l + lnk_l[js[l] * lsr] * ps;
              detail::transpose_rows(rows, ps, po);
            }
            // slot jj of every lane, branch-free (vectorised): slot_energy's arithmetic with the
            // elastic closed form and the penalty (cohesive::integrate, penalty_integral) as selects
            NACRE_MC_LANES
            for (int l = 0; l < W; ++l) {
              const int j = js[l];
              auto r = [&](SlotCol c) { return rc[col(c)][l]; };
              const int kd = kind[l];
              // the kind's constants by selects (3 kinds), not a gather from the closure
              const double lk = kd == 0 ? k0 : (kd == 1 ? k1 : k2);
              const double x1sq = kd == 0 ? xs0 : (kd == 1 ? xs1 : xs2);
              const kinematics::Frame f{fx[l], fy[l], ft[l], fs[l], fc[l]};
              const kinematics::Frame fo{po[0][l], po[1][l], po[2][l], po[3][l], po[4][l]};
              using C = SlotCol;
              double a0x, a0y, a1x, a1y, b0x, b0y, b1x, b1y;
              kinematics::point_displacement(f, r(C::r0x), r(C::r0y), a0x, a0y);
              kinematics::point_displacement(f, r(C::r1x), r(C::r1y), a1x, a1y);
              kinematics::point_displacement(fo, r(C::o0x), r(C::o0y), b0x, b0y);
              kinematics::point_displacement(fo, r(C::o1x), r(C::o1y), b1x, b1y);
              const double tm = 0.5 * (f.t + fo.t), rnx = r(C::nx), rny = r(C::ny);
              const double g0x = b0x - a0x, g0y = b0y - a0y, g1x = b1x - a1x, g1y = b1y - a1y;
              const double nx = rnx - tm * rny, ny = rny + tm * rnx;
              const double d0 = g0x * g0x + g0y * g0y, d1 = g1x * g1x + g1y * g1y;
              const double ef = lk * (d0 + g0x * g1x + g0y * g1y + d1) * (1.0 / 6.0);
              // cohesive::detail::penalty_integral expression for expression (one quotient), its
              // cases (no end penetrates, both do, one does) as selects
              const double q0 = g0x * nx + g0y * ny, q1 = g1x * nx + g1y * ny;
              const bool pen = !((q0 >= 0.0) & (q1 >= 0.0)), both = (q0 < 0.0) & (q1 < 0.0);  // & not &&: no branches
              const double n2 = nx * nx + ny * ny;
              const double den = 7.0 * (n2 * n2 * n2) * (x1sq * x1sq);
              const double a2 = q0 * q0, a3 = a2 * q0, b2 = q1 * q1, b3 = b2 * q1;
              const double num = a3 * a3 + a3 * a2 * q1 + a2 * a2 * b2 + a3 * b3 + a2 * b2 * b2 + q0 * b2 * b3 + b3 * b3;
              const double qa = q0 < 0.0 ? q0 : q1, qo = q0 < 0.0 ? q1 : q0;  // qa < 0 <= qo where one end penetrates
              const double qa2 = qa * qa, qa7 = qa2 * qa2 * qa2 * qa;
              // both forms computed, one selected (no conditional arithmetic: the loop stays one
              // block); the unselected form's divisors are kept non-zero, the selected one's are;
              // where qa^7 underflows (a subnormal gap) the energy is 0, as penalty_integral's
              const double dq = qa - qo, dd = den != 0.0 ? den : 1.0;
              const double e_both = 0.0625 * lk * num / dd;
              const double e_one = qa7 >= 0.0 ? 0.0 : 0.0625 * lk * qa7 / ((dq != 0.0 ? dq : 1.0) * dd);
              const double ep = pen ? (both ? e_both : e_one) : 0.0;
              en[l] = r(C::length) * (ef + ep);
              general[l] = on[l] & int(!((d0 <= x1sq) & (d1 <= x1sq)));
              eo[l] = cached_l[lnk_l[j * lsr + 1]];
            }
            for (int l = 0; l < W; ++l) {  // not elastic everywhere, or damaged: the general integral, per lane
              const double* kap = hist ? hist + static_cast<std::size_t>(link(js[l], 1)) * nq : nullptr;
              if (general[l] || (on[l] && kap && cohesive::max_history(kap, nq) > laws[skind(js[l])].x1))
                en[l] =
                    slot_energy(slot, js[l], laws[skind(js[l])], kinematics::Frame{fx[l], fy[l], ft[l], fs[l], fc[l]},
                                frame_of(p, link(js[l], 0)), quad, kap);
            }
            for (int l = 0; l < W; ++l) {
              e_old[l] = on[l] ? e_old[l] + eo[l] : e_old[l];
              e_new[l] = on[l] ? e_new[l] + en[l] : e_new[l];
            }
            if (jj < kTrialKeep)
              for (int l = 0; l < W; ++l) keep[jj][l] = en[l];
          }
          for (int l = 0; l < W; ++l) {  // Metropolis and the writes, per lane as in ScalarTrials
            if (!act[l]) continue;
            const int b = first[l] + k;
            const double d = e_new[l] - e_old[l];
            const bool accept = d <= 0.0 || (inv_t > 0.0 && u3[l] < Kokkos::exp(-d * inv_t));
            if (accept) {
              const kinematics::Frame f_new{fx[l], fy[l], ft[l], fs[l], fc[l]};
              store_frame(p, b, f_new);
              for (int j = j0[l]; j < j0[l] + deg[l]; ++j)
                cache(link(j, 1)) =
                    j - j0[l] < kTrialKeep
                        ? keep[j - j0[l]][l]
                        : slot_energy(slot, j, laws[skind(j)], f_new, frame_of(p, link(j, 0)), quad,
                                      hist ? hist + static_cast<std::size_t>(link(j, 1)) * nq : nullptr);
              acc += 1;
              if (PerBrick) bacc(b) += 1;
            }
            de(b) = accept ? d : 0.0;
          }
        }
      },
      accepted);
  return accepted;
}

/// \brief sweep_colour(ScalarTrials or BatchedTrials, ...): the per-brick-steps variant picked once,
/// from whether brick_steps holds steps.
template <class Trials, class ExecutionSpace, class MemorySpace, class Uniforms,
          std::enable_if_t<std::is_same_v<Trials, ScalarTrials> || std::is_same_v<Trials, BatchedTrials>, int> = 0>
long sweep_colour(Trials t, const ExecutionSpace& space, const Model<MemorySpace>& m, int begin, int end,
                  const Uniforms& uniforms, Field<double, MemorySpace> cache, Field<double, MemorySpace> de,
                  double step, double rot_step, double temperature, const BrickSteps<MemorySpace>& brick_steps = {}) {
  if (brick_steps.active())
    return sweep_colour(t, std::true_type{}, space, m, begin, end, uniforms, cache, de, step, rot_step, temperature,
                        brick_steps);
  return sweep_colour(t, std::false_type{}, space, m, begin, end, uniforms, cache, de, step, rot_step, temperature,
                      brick_steps);
}

/// \brief The sweep as the solver runs it: ScalarTrials, or with NACRE_MC_BATCHED=ON BatchedTrials
/// on a host execution space (a device always keeps its per-thread code). Batched is not the
/// default because it does not pay on the CPU it was measured on at 300k bricks
/// (perf/results/mc/sweep_simd/, perf/README.md); the two give the same bits.
template <class ExecutionSpace, class MemorySpace, class Uniforms>
long sweep_colour(const ExecutionSpace& space, const Model<MemorySpace>& m, int begin, int end,
                  const Uniforms& uniforms, Field<double, MemorySpace> cache, Field<double, MemorySpace> de,
                  double step, double rot_step, double temperature, const BrickSteps<MemorySpace>& brick_steps = {}) {
#ifdef NACRE_MC_BATCHED_SWEEP  // cmake -DNACRE_MC_BATCHED=ON (src/mc/mc.cmake); OFF by default
  if constexpr (Kokkos::SpaceAccessibility<ExecutionSpace, Kokkos::HostSpace>::accessible)
#else
  if constexpr (false)
#endif
    return sweep_colour(BatchedTrials{}, space, m, begin, end, uniforms, cache, de, step, rot_step, temperature,
                        brick_steps);
  else
    return sweep_colour(ScalarTrials{}, space, m, begin, end, uniforms, cache, de, step, rot_step, temperature,
                        brick_steps);
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

/// \brief The plain secant predictor for the free bricks: p += ratio (p - p_prev), every brick
/// alike (no energy damping). Where Newton relaxes (relaxation = "newton", "auto") it is the
/// default: eq. 2.11's damping holds back exactly the bricks of the process zone, which then start
/// each load step behind, and after the peak the trust region walked them into other (higher)
/// converged states. Measured on the 20k-brick reference path (docs/speed_accuracy.md): 603 -> 484
/// Newton steps, post-peak energies at or nearer FIRE's reference.
struct SecantPredictor {};

template <class ExecutionSpace, class MemorySpace>
void predict_poses(const ExecutionSpace& space, SecantPredictor, const Model<MemorySpace>& m,
                   typename Model<MemorySpace>::PoseView prev, double ratio) {
  check_access<ExecutionSpace, MemorySpace>();
  auto p = m.pose;
  Kokkos::parallel_for(
      "nacre::mc::predict_secant", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_free), KOKKOS_LAMBDA(const int b) {
        const kinematics::Pose q{p(b, 0) + ratio * (p(b, 0) - prev(b, 0)), p(b, 1) + ratio * (p(b, 1) - prev(b, 1)),
                                 p(b, 2) + ratio * (p(b, 2) - prev(b, 2))};
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
/// accepts at most half of small trials), so it aims lower (Solver::anneal). Target 0.5 is
/// eq. 2.7 itself, with its own expression (its bits).
KOKKOS_INLINE_FUNCTION double adapted_step(double s, double a, double lo, double hi, double target) {
  if (target == 0.5) return adapted_step(s, a, lo, hi);
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
        step(b, 0) = adapted_step(step(b, 0), a, min_step, max_step, target);
        step(b, 1) = adapted_step(step(b, 1), a, min_rot, max_rot, target);
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
