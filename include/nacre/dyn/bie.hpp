#pragma once
/// \file
/// \brief The bolted implicit-explicit method (BIE, eq. 4.6/4.7, issue 8): implicit midpoint for
/// the element terms (K, C), explicit Verlet for the interface forces, Newton iterations with the
/// constant Jacobian J of eq. 4.7 whose interface term is neglected, so every brick is solved on
/// its own with J^-1 of its element type (computed once at start-up, Eigen, condition checked).
///
/// Why written as it is (docs/methods.md):
/// - Unknowns x = (p_{n+1}, v_{n+1}) per element, start x^0 = (p_n, v_n). The residual of eq. 4.6,
///   with a(x) = M^-1 (F_i(p) + F_p + Theta - K p - C v) the acceleration of a state, is
///     G_p = h v_n + h^2/2 a_n - h^2/4 M^-1 (K dp + C dv) - dp,   G_v = h/2 (a_n + a(x)) - dv,
///   dp = p - p_n, dv = v - v_n (eq. 4.6 rewritten: Q = a_n - M^-1 (K dp + C dv)/2, R = (a_n +
///   a(x))/2). One iteration: x += J^-1 G(x). The element part is linear, so each iteration solves
///   it exactly for the interface force of the current iterate; two iterations (eq. 4.6) make the
///   interface force second-order consistent. a_{n+1} = a(x_{n+1}) closes the step, with the
///   interface force re-evaluated at x_{n+1} or (Params::bie_reuse_force, default) kept from the
///   previous iterate: with C = 0 the last iteration does not move p (J^-1's p-v block is zero),
///   so that is exact; with damping it differs by O(h^3) and saves one interface evaluation per
///   step. The state between steps is (p, v, a) as for UE/BE: outputs, checkpoints and the
///   blow-up check are shared unchanged.
/// - The residual block R is View<double**, LayoutLeft> [slot][2 nd]: slot index fastest
///   (coalesced on a GPU, contiguous SIMD runs on a CPU); slots are the elements sorted by element
///   type, so the shared-J^-1 variant multiplies one type's J^-1 with a contiguous 2nd x n block.
/// - The J^-1 apply is one interface with four variants (tags, one operator() each), all in place
///   (each work item copies its input to registers/stack before writing): row, reordered<NB>,
///   batched (KokkosBatched::SerialGemv), shared_gemm (tiles of kTile slots x kRowBlock rows of
///   accumulators, the matrix broadcast from L1).
#include <nacre/dyn/kernels.hpp>

#include <string>
#include <vector>

#if defined(NACRE_HAVE_KOKKOSKERNELS)
#include <KokkosBatched_Gemv_Decl.hpp>
#endif

namespace nacre::dyn {

inline constexpr int kMaxBie = 2 * kMaxDof;  ///< largest J: 2 x 16 dof
inline constexpr int kTile = 8;              ///< shared_gemm: slots per work item (one SIMD register pair of doubles)
inline constexpr int kRowBlock = 4;          ///< shared_gemm: rows of accumulators per pass

/// \brief J^-1 per element type and the slot ordering (elements sorted by type).
template <class MemorySpace = MemSpace>
struct BieTables {
  using TypeMat = typename Model<MemorySpace>::TypeMat;
  TypeMat Jinv;                                   ///< [type][2nd][2nd], LayoutLeft as K
  Kokkos::View<int*, MemorySpace> slot_of_elem;   ///< element -> slot
  Kokkos::View<int*, MemorySpace> slot_type;      ///< slot -> element type
  Kokkos::View<int*, MemorySpace> tile_start;     ///< shared_gemm work items: first slot of each tile
  Kokkos::View<int*, MemorySpace> tile_count;     ///< ... and its number of slots (<= kTile, one type)
  std::vector<int> type_offset;                   ///< host: slots of type t are [off[t], off[t+1])
  double max_condition = 0;      ///< max over types of cond_1(D J D^-1), D = diag(I, h I) (dimensionless J)
  double max_identity_error = 0; ///< max over types of max|J~ J~^-1 - I| of that dimensionless J~
  int n2 = 0;                                     ///< 2 * nd
};

/// \brief Build J (eq. 4.7) for every element type of a bolted model (host, Eigen), invert it,
/// check cond_1 of the dimensionless D J D^-1, D = diag(I, h I) (throws std::runtime_error above 1e12 or on a non-finite inverse), upload.
BieTables<> build_bie_tables(const Model<>& m);

/// \brief Host J of eq. 4.7 for type t of the model (2nd x 2nd; padded dof rows are identity).
std::vector<double> bie_jacobian_host(const Model<>& m, int t);

/// \brief Bytes held by the BIE tables.
std::size_t bie_bytes(const BieTables<>& b);

/// \brief Names and parsing of the solve variants (deck key `bie_solve`).
const char* bie_solve_name(BieSolve s);
bool parse_bie_solve(const std::string& name, BieSolve& out);
/// \brief True where the variant can run in this build (batched needs Kokkos Kernels).
bool bie_solve_available(BieSolve s);

struct BieStartTag {};
struct BieResidualTag {};
struct BieUpdateTag {};
struct BieFinalTag {};

/// \brief Per-element kernels of one BIE step. Driven elements use the explicit integrator's
/// prescribed motion and reaction bookkeeping (Integrator's InitialTag / FinalTag).
template <class MemorySpace>
struct BieIntegrator {
  Integrator<MemorySpace> ex;
  Kokkos::View<const int*, MemorySpace> slot_of_elem;
  DofView<MemorySpace> pn, vn, R;  ///< p_n, v_n per element; residual/correction per slot
  bool book = true;                ///< BieFinalTag: accumulate work and damping (false: a only)

  KOKKOS_INLINE_FUNCTION double minv(int t, int j) const {
    const double m = ex.mass(t, j);
    return m > 0 ? 1.0 / m : 0.0;
  }

  /// Driven: impose t_{n+1}. Free: keep (p_n, v_n), residual at x^0 = x_n: G = (h v_n + h^2/2 a_n, h a_n).
  KOKKOS_INLINE_FUNCTION void operator()(BieStartTag, int e) const {
    if (ex.drive(e) != 0) {
      ex(InitialTag{}, e);
      return;
    }
    const int s = slot_of_elem(e), nd = ex.nd;
    const double h = ex.h;
    for (int j = 0; j < nd; ++j) {
      const double p = ex.u(e, j), v = ex.v(e, j), a = ex.a(e, j);
      pn(e, j) = p, vn(e, j) = v;
      R(s, j) = h * v + 0.5 * h * h * a;
      R(s, nd + j) = h * a;
    }
  }

  /// a(x) of the current iterate (interface force gathered in a fixed order).
  KOKKOS_INLINE_FUNCTION void accel(int e, int t, double* ax) const {
    const int nd = ex.nd;
    double f[kMaxDof], w[kMaxDof];
    ex.gather(e, f);
    for (int j = 0; j < nd; ++j) {
      f[j] += ex.theta(t, j) + (ex.has_fp ? ex.fp(e, j) : 0.0);
      w[j] = ex.u(e, j) + ex.beta * ex.v(e, j);
    }
    for (int i = 0; i < nd; ++i) {
      double kw = 0;
      for (int j = 0; j < nd; ++j) kw += ex.K(t, i, j) * w[j];
      ax[i] = minv(t, i) * (f[i] - kw) - ex.alpha * ex.v(e, i);
    }
  }

  /// Residual G(x^k) of eq. 4.6 at the current iterate (u, v) with the current interface force.
  KOKKOS_INLINE_FUNCTION void operator()(BieResidualTag, int e) const {
    if (ex.drive(e) != 0) return;
    const int t = ex.type(e), s = slot_of_elem(e), nd = ex.nd;
    const double h = ex.h;
    double ax[kMaxDof], dp[kMaxDof], dv[kMaxDof], w[kMaxDof];
    accel(e, t, ax);
    for (int j = 0; j < nd; ++j) {
      dp[j] = ex.u(e, j) - pn(e, j), dv[j] = ex.v(e, j) - vn(e, j);
      w[j] = dp[j] + ex.beta * dv[j];
    }
    for (int i = 0; i < nd; ++i) {
      double kw = 0;
      for (int j = 0; j < nd; ++j) kw += ex.K(t, i, j) * w[j];
      const double kc = minv(t, i) * kw + ex.alpha * dv[i];  // M^-1 (K dp + C dv)
      const double an = ex.a(e, i);
      R(s, i) = h * vn(e, i) + 0.5 * h * h * an - 0.25 * h * h * kc - dp[i];
      R(s, nd + i) = 0.5 * h * (an + ax[i]) - dv[i];
    }
  }

  /// x += J^-1 G (R holds the correction after the solve).
  KOKKOS_INLINE_FUNCTION void operator()(BieUpdateTag, int e) const {
    if (ex.drive(e) != 0) return;
    const int s = slot_of_elem(e), nd = ex.nd;
    for (int j = 0; j < nd; ++j) ex.u(e, j) += R(s, j), ex.v(e, j) += R(s, nd + j);
  }

  /// End of step: a_{n+1} = a(x_{n+1}); work of F_p + Theta over dp, damping dp . C v_mid
  /// (implicit midpoint); R(s, 0..1) = m-weighted |G_v|^2 and |dv|^2 of the final state.
  /// Driven elements: reaction and work as in the explicit methods.
  KOKKOS_INLINE_FUNCTION void operator()(BieFinalTag, int e) const {
    if (ex.drive(e) != 0) {
      if (book) ex(FinalTag{}, e);
      return;
    }
    const int t = ex.type(e), s = slot_of_elem(e), nd = ex.nd;
    double ax[kMaxDof];
    accel(e, t, ax);
    if (!book) {
      for (int j = 0; j < nd; ++j) ex.a(e, j) = ax[j];
      return;
    }
    const double h = ex.h;
    double work = 0, pd = 0, g2 = 0, d2 = 0, dp[kMaxDof], vm[kMaxDof];
    for (int j = 0; j < nd; ++j) {
      dp[j] = ex.u(e, j) - pn(e, j);
      vm[j] = 0.5 * (ex.v(e, j) + vn(e, j));
      work += (ex.theta(t, j) + (ex.has_fp ? ex.fp(e, j) : 0.0)) * dp[j];
    }
    for (int i = 0; i < nd; ++i) {
      double kv = 0;
      for (int j = 0; j < nd; ++j) kv += ex.K(t, i, j) * vm[j];
      const double m = ex.mass(t, i);
      pd += dp[i] * (ex.alpha * m * vm[i] + ex.beta * kv);
      const double dv = ex.v(e, i) - vn(e, i);
      const double gv = 0.5 * h * (ex.a(e, i) + ax[i]) - dv;
      g2 += m * gv * gv, d2 += m * dv * dv;
      ex.a(e, i) = ax[i];
    }
    ex.acc(e, kWork) += work;
    ex.acc(e, kDamp) += pd;
    R(s, 0) = g2, R(s, 1) = d2;
  }
};

// ---- the J^-1 apply: R(s, :) <- J^-1(type(s)) R(s, :) for every slot, in place

struct SolveRowTag {};
template <int NB>
struct SolveReorderedTag {};
struct SolveBatchedTag {};
struct SolveTileTag {};

template <class MemorySpace>
struct BieSolveOp {
  Kokkos::View<const double***, Kokkos::LayoutLeft, MemorySpace> J;  ///< J^-1 [type][row][col]
  Kokkos::View<const int*, MemorySpace> slot_type, tile_start, tile_count;
  DofView<MemorySpace> R;
  int n;  ///< 2 nd

  /// (1) the CPU version of the dissertation: one row of J^-1 times the residual at a time.
  KOKKOS_INLINE_FUNCTION void operator()(SolveRowTag, int s) const {
    const int t = slot_type(s);
    double r[kMaxBie];
    for (int j = 0; j < n; ++j) r[j] = R(s, j);
    for (int i = 0; i < n; ++i) {
      double y = 0;
      for (int j = 0; j < n; ++j) y += J(t, i, j) * r[j];
      R(s, i) = y;
    }
  }

  /// (2) §4.3, Fig. 4.4: NB rows at a time, column by column, NB accumulators in registers; each
  /// residual entry is read once per block instead of once per row.
  template <int NB>
  KOKKOS_INLINE_FUNCTION void operator()(SolveReorderedTag<NB>, int s) const {
    const int t = slot_type(s);
    double r[kMaxBie];
    for (int j = 0; j < n; ++j) r[j] = R(s, j);
    for (int i0 = 0; i0 < n; i0 += NB) {
      double y[NB];
      for (int b = 0; b < NB; ++b) y[b] = 0;
      if (i0 + NB <= n) {
        for (int j = 0; j < n; ++j) {
          const double rj = r[j];
          for (int b = 0; b < NB; ++b) y[b] += J(t, i0 + b, j) * rj;
        }
        for (int b = 0; b < NB; ++b) R(s, i0 + b) = y[b];
      } else {  // tail block (n not a multiple of NB)
        for (int j = 0; j < n; ++j)
          for (int b = 0; i0 + b < n; ++b) y[b] += J(t, i0 + b, j) * r[j];
        for (int b = 0; i0 + b < n; ++b) R(s, i0 + b) = y[b];
      }
    }
  }

#if defined(NACRE_HAVE_KOKKOSKERNELS)
  /// (3) Kokkos Kernels: KokkosBatched::SerialGemv of the element's J^-1 and residual.
  KOKKOS_INLINE_FUNCTION void operator()(SolveBatchedTag, int s) const {
    const int t = slot_type(s);
    double r[kMaxBie];
    for (int j = 0; j < n; ++j) r[j] = R(s, j);
    auto A = Kokkos::subview(J, t, Kokkos::ALL, Kokkos::ALL);
    auto y = Kokkos::subview(R, s, Kokkos::ALL);
    Kokkos::View<const double*, Kokkos::LayoutRight, Kokkos::AnonymousSpace, Kokkos::MemoryUnmanaged> x(r, n);
    KokkosBatched::SerialGemv<KokkosBatched::Trans::NoTranspose, KokkosBatched::Algo::Gemv::Unblocked>::invoke(
        1.0, Kokkos::subview(A, Kokkos::make_pair(0, n), Kokkos::make_pair(0, n)), x, 0.0,
        Kokkos::subview(y, Kokkos::make_pair(0, n)));
  }
#endif

  /// (4) J^-1 shared by a type: Y = J^-1 [r_s0 .. r_s0+kTile-1], a 2nd x 2nd by 2nd x kTile
  /// product per work item; kRowBlock x kTile accumulators, the innermost loop over the tile's
  /// slots (contiguous: slot index fastest), each matrix entry loaded once per tile.
  KOKKOS_INLINE_FUNCTION void operator()(SolveTileTag, int w) const {
    const int s0 = tile_start(w), nb = tile_count(w), t = slot_type(s0);
    double x[kMaxBie][kTile];
    for (int j = 0; j < n; ++j)
      for (int b = 0; b < kTile; ++b) x[j][b] = b < nb ? R(s0 + b, j) : 0.0;
    for (int i0 = 0; i0 < n; i0 += kRowBlock) {
      double y[kRowBlock][kTile];
      for (int q = 0; q < kRowBlock; ++q)
        for (int b = 0; b < kTile; ++b) y[q][b] = 0;
      const int nq = n - i0 < kRowBlock ? n - i0 : kRowBlock;
      for (int j = 0; j < n; ++j)
        for (int q = 0; q < kRowBlock; ++q) {
          const double c = q < nq ? J(t, i0 + q, j) : 0.0;
          for (int b = 0; b < kTile; ++b) y[q][b] += c * x[j][b];
        }
      for (int q = 0; q < nq; ++q)
        for (int b = 0; b < nb; ++b) R(s0 + b, i0 + q) = y[q][b];
    }
  }
};

template <class ExecutionSpace>
void bie_solve(const ExecutionSpace& space, const BieSolveOp<MemOf<ExecutionSpace>>& op, BieSolve variant,
               int block, int n_slots, int n_tiles) {
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_solve");
  switch (variant) {
  case BieSolve::row:
    Kokkos::parallel_for("nacre::dyn::bie_solve_row", Kokkos::RangePolicy<ExecutionSpace, SolveRowTag>(space, 0, n_slots), op);
    return;
  case BieSolve::reordered:
    switch (block) {
#define NACRE_BIE_NB(NB)                                                                                   \
  case NB:                                                                                                 \
    Kokkos::parallel_for("nacre::dyn::bie_solve_reordered_" #NB,                                          \
                         Kokkos::RangePolicy<ExecutionSpace, SolveReorderedTag<NB>>(space, 0, n_slots), op); \
    return;
      NACRE_BIE_NB(2)
      NACRE_BIE_NB(4)
      NACRE_BIE_NB(5)
      NACRE_BIE_NB(10)
#undef NACRE_BIE_NB
    default:
      Kokkos::abort("nacre::dyn::bie_solve: reordered block NB must be 2, 4, 5 or 10");
    }
    return;
  case BieSolve::batched:
#if defined(NACRE_HAVE_KOKKOSKERNELS)
    Kokkos::parallel_for("nacre::dyn::bie_solve_batched", Kokkos::RangePolicy<ExecutionSpace, SolveBatchedTag>(space, 0, n_slots),
                         op);
#else
    Kokkos::abort("nacre::dyn::bie_solve: batched needs Kokkos Kernels (not in this build)");
#endif
    return;
  case BieSolve::shared_gemm:
    Kokkos::parallel_for("nacre::dyn::bie_solve_tile", Kokkos::RangePolicy<ExecutionSpace, SolveTileTag>(space, 0, n_tiles), op);
    return;
  }
}

/// \brief One BIE step: start, then per iteration (solve, update, interface force, residual),
/// the last interface force at x_{n+1}, and the final accelerations and books.
template <class ExecutionSpace>
void bie_step(const ExecutionSpace& space, const BieIntegrator<MemOf<ExecutionSpace>>& it,
              const InterfaceOp<MemOf<ExecutionSpace>>& op, const BieSolveOp<MemOf<ExecutionSpace>>& solve,
              BieSolve variant, int block, int iterations, bool reuse_force, int n_elem, int n_iface, int n_tiles) {
  using Exec = ExecutionSpace;
  {
    Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_start");
    Kokkos::parallel_for("nacre::dyn::bie_start", Kokkos::RangePolicy<Exec, BieStartTag>(space, 0, n_elem), it);
  }
  for (int k = 0; k < iterations; ++k) {
    if (k > 0) {
      Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_residual");
      Kokkos::parallel_for("nacre::dyn::bie_residual", Kokkos::RangePolicy<Exec, BieResidualTag>(space, 0, n_elem), it);
    }
    bie_solve(space, solve, variant, block, n_elem, n_tiles);
    {
      Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_update");
      Kokkos::parallel_for("nacre::dyn::bie_update", Kokkos::RangePolicy<Exec, BieUpdateTag>(space, 0, n_elem), it);
    }
    if (reuse_force && k == iterations - 1 && k > 0) break;  // a_{n+1} from the force at the previous iterate
    Kokkos::Profiling::ScopedRegion r("nacre::dyn::interface_force");
    Kokkos::parallel_for("nacre::dyn::interface_force", Kokkos::RangePolicy<Exec, ForceTag>(space, 0, n_iface), op);
  }
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_final");
  Kokkos::parallel_for("nacre::dyn::bie_final", Kokkos::RangePolicy<Exec, BieFinalTag>(space, 0, n_elem), it);
}

/// \brief Free elements' accelerations a(x) of the current state (start-up: a_0 consistent with
/// the initial loads); needs the interface force of the current state in op.out first.
template <class ExecutionSpace>
void bie_accelerations(const ExecutionSpace& space, BieIntegrator<MemOf<ExecutionSpace>> it,
                       const InterfaceOp<MemOf<ExecutionSpace>>& op, int n_elem, int n_iface) {
  interface_forces(space, op, n_iface);
  it.book = false;
  Kokkos::parallel_for("nacre::dyn::bie_accelerations", Kokkos::RangePolicy<ExecutionSpace, BieFinalTag>(space, 0, n_elem),
                       it);
}

/// \brief Relative residual of the last step (see Simulation::bie_residual), from R(s, 0..1).
template <class ExecutionSpace>
double bie_last_residual(const ExecutionSpace& space, const DofView<MemOf<ExecutionSpace>>& R,
                         const Kokkos::View<const std::int8_t*, MemOf<ExecutionSpace>>& drive,
                         const Kokkos::View<const int*, MemOf<ExecutionSpace>>& slot_of_elem, int n_elem) {
  double g = 0, d = 0;
  Kokkos::parallel_reduce(
      "nacre::dyn::bie_residual_norm", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n_elem),
      KOKKOS_LAMBDA(const int e, double& gs) {
        if (drive(e) == 0) gs += R(slot_of_elem(e), 0);
      },
      g);
  Kokkos::parallel_reduce(
      "nacre::dyn::bie_residual_norm", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n_elem),
      KOKKOS_LAMBDA(const int e, double& ds) {
        if (drive(e) == 0) ds += R(slot_of_elem(e), 1);
      },
      d);
  return d > 0 ? Kokkos::sqrt(g / d) : 0.0;
}

}  // namespace nacre::dyn
