// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The bolted implicit-explicit method (BIE, eq. 4.6/4.7): implicit midpoint for
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
/// - The residual block R is View<double**, ElemLayout> [slot][2 nd]: slot index fastest on a GPU
///   (coalesced), a slot's 2 nd entries contiguous on a CPU (one stream per pass); slots are the elements sorted by element
///   type, so the shared-J^-1 variant multiplies one type's J^-1 with a contiguous 2nd x n block.
/// - The J^-1 apply is one interface with four variants (tags, one operator() each), all in place
///   (each work item copies its input to registers/stack before writing): row, reordered<NB>,
///   batched (KokkosBatched::SerialGemv), shared_gemm (tiles of kTile slots x kRowBlock rows of
///   accumulators, the matrix broadcast from L1).
/// - The fused tiled step (shared_gemm with the tiled element apply) is three passes per step with
///   the defaults (two iterations, force kept): start + first J^-1 apply, the interface force at
///   x_1, then the second iteration and the end of the step in one pass (BieIterFinalTileTag: both
///   use the force at x_1, so one gather and one load/store of the state serve both).
/// - Without stiffness damping (beta_d = 0, BieTables::block_lower) J^-1 is determined by its
///   first nd columns and two numbers (jq = b/c, jr = 1/c of J's diagonal v-columns): it is built
///   blockwise, and the tiled apply scales g_p -= jq g_v, multiplies the first nd columns and adds
///   jr g_v (half the work of the dense apply). Without any damping (C = 0: jq = 0, jr = 1, exact
///   zeros and identity) the last iteration also takes its reduced form (BieIterFinalLinearTileTag):
///   G_p does not involve the interface force, so the first iteration already zeroed it and the
///   second only sets v = v_n + h/2 (a_n + a(x_1)), one nd x nd apply instead of the three K
///   applies and the 2nd x 2nd J^-1 apply. With stiffness damping (beta_d != 0, BieTables::vfirst)
///   J's rows still give J_p - h/2 J_v = [I, -h/2 I] on every dof with mass, so the tiled apply
///   scales g_p -= h/2 g_v, forms the velocity correction with one nd x 2nd matrix (Jv) and the
///   position correction as g~_p + h/2 y_v: half the dense apply (1.34x BIE's step at 50k bricks,
///   Table 4.2's damping). Params::bie_block_structure = false keeps the dense form.
#include <nacre/dyn/kernels.hpp>

#include <type_traits>

#include <string>
#include <vector>

#if defined(NACRE_HAVE_KOKKOSKERNELS)
#include <KokkosBlas2_serial_gemv.hpp>  // KokkosBatched::SerialGemv aborts in Kokkos Kernels >= 4.7.99
#endif

namespace nacre::dyn {

inline constexpr int kMaxBie = 2 * kMaxDof;  ///< largest J: 2 x 16 dof
inline constexpr int kRowBlock = 4;          ///< shared_gemm: rows of accumulators per pass

/// \brief J^-1 per element type and the slot ordering (elements sorted by type).
template <class MemorySpace = MemSpace>
struct BieTables {
  using TypeMat = typename Model<MemorySpace>::TypeMat;
  TypeMat Jinv;                                   ///< [type][2nd][2nd], layout as K
  Kokkos::View<int*, MemorySpace> slot_of_elem;   ///< element -> slot
  Kokkos::View<int*, MemorySpace> slot_type;      ///< slot -> element type
  Kokkos::View<int*, MemorySpace> tile_start;     ///< shared_gemm work items: first slot of each tile
  Kokkos::View<int*, MemorySpace> tile_count;     ///< ... and its number of slots (<= kTile, one type)
  std::vector<int> type_offset;                   ///< host: slots of type t are [off[t], off[t+1])
  double max_condition = 0;      ///< max over types of cond_1(D J D^-1), D = diag(I, h I) (dimensionless J)
  double max_identity_error = 0; ///< max over types of max|J~ J~^-1 - I| of that dimensionless J~
  int n2 = 0;                                     ///< 2 * nd
  /// No stiffness damping (beta_d = 0, C = alpha_d M): J = [[A, b I], [P, c I]] (b = h^2 alpha/4,
  /// c = 1 + h alpha/2 on every dof with mass), so J^-1 g = [S^-1 g~; L g~ + g_v / c] with
  /// g~ = g_p - (b/c) g_v, S = A - (b/c) P, L = -P S^-1 / c: the tiled apply multiplies the first
  /// nd columns only (half the work) after the scaling of g. C = 0: b = 0, c = 1 and the last nd
  /// columns are exactly [[0], [I]]. Built blockwise (exact zeros and ones).
  bool block_lower = false;
  double jq = 0.0;  ///< b / c (0 without damping)
  double jr = 1.0;  ///< 1 / c (1 without damping)
  /// Stiffness damping (beta_d != 0): J's rows give J_p - h/2 J_v = [I, -h/2 I] on every dof with
  /// mass (eq. 4.7 for any C), so with g~_p = g_p - h/2 g_v the correction is y_v = Jv [g~_p; g_v],
  /// y_p = g~_p + h/2 y_v: one nd x 2nd product (half the dense apply). Jv = [type][nd][2nd],
  /// the velocity rows of J^-1 times [[I, h/2 I], [0, I]] (padded dofs: identity).
  bool vfirst = false;
  TypeMat Jv;
};

/// \brief Build J (eq. 4.7) for every element type of a bolted model (host, Eigen), invert it,
/// check cond_1 of the dimensionless D J D^-1, D = diag(I, h I) (throws std::runtime_error above 1e12 or on a non-finite inverse), upload.
template <class Mem>
BieTables<Mem> build_bie_tables(const Model<Mem>& m);

/// \brief Host J of eq. 4.7 for type t of the model (2nd x 2nd; padded dof rows are identity).
template <class Mem>
std::vector<double> bie_jacobian_host(const Model<Mem>& m, int t);

/// \brief Bytes held by the BIE tables.
template <class Mem>
std::size_t bie_bytes(const BieTables<Mem>& b);

/// \brief Names and parsing of the solve variants (deck key `bie_solve`).
const char* bie_solve_name(BieSolve s);
bool parse_bie_solve(const std::string& name, BieSolve& out);
/// \brief True where the variant can run in this build (batched needs Kokkos Kernels).
bool bie_solve_available(BieSolve s);

struct BieStartTag {};
struct BieResidualTag {};
struct BieUpdateTag {};
struct BieFinalTag {};
struct BieAccelTag {};  ///< a = a(x) of the current state only (start-up: no books)
// fused, tiled (shared_gemm with the tiled element apply): one kernel per phase over the element
// tiles of Model (kTile free elements of one type), the residual kept in registers / L1 and
// J^-1 applied to it in place: no residual block R in memory, no slot order
// How the fused tiles apply J^-1, a type chosen once per run (BieTables says which applies):
struct JinvDense {};          ///< the dense 2nd x 2nd product
struct JinvBlockLower {};     ///< C = alpha M (BieTables::block_lower): first nd columns and (jq, jr)
struct JinvVelocityFirst {};  ///< beta_d != 0 (BieTables::vfirst): y_v = Jv g~, y_p = g~_p + h/2 y_v
/// PositionsOnly: the start applies only the position rows of J^-1 and leaves v at v_n, for the
/// reduced last pass (BieIterFinalLinearTileTag, C = 0, two iterations), which takes
/// v_{n+1} = v_n + h/2 (a_n + a(x_1)) and never reads the first iterate's velocity (the interface
/// force between reads u only): half of the start's J^-1 apply and its v stores skipped; u_1 and
/// every end-of-step value keep their bits (rows are summed independently).
template <class Jinv, bool PositionsOnly = false>
struct BieStartTileTag {};
template <class Jinv>
struct BieIterTileTag {};
struct BieFinalTileTag {};
template <class Jinv>
struct BieIterFinalTileTag {};        ///< the last iteration fused with the end of the step (bie_reuse_force)
struct BieIterFinalLinearTileTag {};  ///< ... when C = 0 (BieTables::block_lower): the reduced form
// the split step (BieScheme::split): start = half kick + the linear midpoint's residual, one J^-1
// apply, the interface force at p_{n+1}, final = books + half kick + a_{n+1}
struct BieSplitInitTag {};  ///< start-up: a = phi = M^-1 F of the initial state
struct BieSplitStartTag {};
struct BieSplitFinalTag {};
template <class Jinv>
struct BieSplitStartTileTag {};
struct BieSplitFinalTileTag {};

/// \brief Per-element kernels of one BIE step. Driven elements use the explicit integrator's
/// prescribed motion and reaction bookkeeping (Integrator's InitialTag / final_driven).
template <class MemorySpace>
struct BieIntegrator {
  Integrator<MemorySpace> ex;
  Kokkos::View<const int*, MemorySpace> slot_of_elem;
  DofView<MemorySpace> pn, vn, R;  ///< p_n, v_n per element; residual/correction per slot (unfused path)
  Kokkos::View<const double***, ElemLayout<MemorySpace>, MemorySpace> J;  ///< J^-1 per type (fused path)
  /// JinvBlockLower: J^-1 determined by its first nd columns and (jq, jr): the tiled apply scales
  /// g_p -= jq g_v (dofs with mass; skipped when jq = 0), sums the first nd columns and adds jr g_v
  /// on the velocity rows (C = 0: the identity), skipping the rest (JinvDense on such a matrix:
  /// without damping the same bits up to the sign of a zero).
  double jq = 0.0, jr = 1.0;  ///< BieTables::jq, jr
  /// JinvVelocityFirst (beta_d != 0): y_v = Jv [g~_p; g_v], y_p = g~_p + h/2 y_v.
  Kokkos::View<const double***, ElemLayout<MemorySpace>, MemorySpace> Jv;

  /// The J^-1 apply's input: g~_p = g_p - h/2 g_v (velocity-first) or g_p - jq g_v (block form;
  /// nothing when jq = 0) on the dofs with mass; the dense form takes g as it is.
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void tile_block_scale(int t, double (*KOKKOS_RESTRICT g)[kTile]) const {
    if constexpr (!std::is_same_v<Jinv, JinvDense>) {
      const int nd = ex.nd;
      const double c = std::is_same_v<Jinv, JinvVelocityFirst> ? 0.5 * ex.h : jq;
      if (c == 0.0) return;  // (the block form without damping: jq = 0)
      for (int j = 0; j < nd; ++j)
        if (ex.mass(t, j) > 0)
          for (int b = 0; b < kTile; ++b) g[j][b] -= c * g[nd + j][b];
    } else {
      (void)t, (void)g;
    }
  }

  /// y[q] = sum_{j < n} A(t, i0 + q, j) g[j] for the rows [i0, i0 + nq) of a per-type matrix:
  /// kRowBlock accumulator rows, each matrix entry loaded once and broadcast over the tile.
  template <class Mat>
  KOKKOS_INLINE_FUNCTION static void tile_rows(const Mat& A, int t, int i0, int nq, int n,
                                               const double (*KOKKOS_RESTRICT g)[kTile],
                                               double (*KOKKOS_RESTRICT y)[kTile]) {
    for (int q = 0; q < kRowBlock; ++q)
      for (int b = 0; b < kTile; ++b) y[q][b] = 0;
    for (int j = 0; j < n; ++j)
      for (int q = 0; q < kRowBlock; ++q) {
        const double c = q < nq ? A(t, i0 + q, j) : 0.0;
        for (int b = 0; b < kTile; ++b) y[q][b] += c * g[j][b];
      }
  }

  /// y[q] = sum_j J(t, i0 + q, j) g[j] for the rows [i0, i0 + nq) of J^-1 (dense, or the block
  /// structure: the same terms in the same order less the exact zeros).
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void tile_jinv_rows(int t, int i0, int nq, const double (*KOKKOS_RESTRICT g)[kTile],
                                             double (*KOKKOS_RESTRICT y)[kTile]) const {
    constexpr bool block_lower = std::is_same_v<Jinv, JinvBlockLower>;
    const int nd = ex.nd, n = block_lower ? nd : 2 * nd;
    tile_rows(J, t, i0, nq, n, g, y);
    if constexpr (
        block_lower)  // the v-v block's diagonal: row r >= nd gets jr g[r] (1 g[r] without damping, or no mass)
      for (int q = 0; q < nq; ++q)
        if (i0 + q >= nd) {
          const double r = ex.mass(t, i0 + q - nd) > 0 ? jr : 1.0;
          for (int b = 0; b < kTile; ++b) y[q][b] += r * g[i0 + q][b];
        }
  }

  /// The velocity-first correction of a tile (vfirst; g already scaled by tile_block_scale):
  /// y_v = Jv g in row blocks of kRowBlock accumulators, then y_p = g~_p + h/2 y_v on dofs with
  /// mass (y_p = g_p on padded ones).
  KOKKOS_INLINE_FUNCTION void tile_vfirst(int t, const double (*KOKKOS_RESTRICT g)[kTile],
                                          double (*KOKKOS_RESTRICT y)[kTile]) const {
    const int nd = ex.nd, n = 2 * nd;
    for (int i0 = 0; i0 < nd; i0 += kRowBlock) {
      const int nq = nd - i0 < kRowBlock ? nd - i0 : kRowBlock;
      double s[kRowBlock][kTile];
      tile_rows(Jv, t, i0, nq, n, g, s);
      for (int q = 0; q < nq; ++q)
        for (int b = 0; b < kTile; ++b) y[nd + i0 + q][b] = s[q][b];
    }
    const double hh = 0.5 * ex.h;
    for (int i = 0; i < nd; ++i) {
      const double c = ex.mass(t, i) > 0 ? hh : 0.0;
      for (int b = 0; b < kTile; ++b) y[i][b] = g[i][b] + c * y[nd + i][b];
    }
  }

  KOKKOS_INLINE_FUNCTION double minv(int t, int j) const {
    const double m = ex.mass(t, j);
    return m > 0 ? 1.0 / m : 0.0;
  }

  // ---- per element (the unfused path: the residual goes to R for a separate J^-1 apply). Each
  // kernel is the lane code below at width 1 on one element; the fused tile kernels run the same
  // code at width kTile: one code, so the two paths give the same bits by construction.

  /// Driven: impose t_{n+1}. Free: keep (p_n, v_n), residual at x^0 = x_n: G = (h v_n + h^2/2 a_n, h a_n).
  KOKKOS_INLINE_FUNCTION void operator()(BieStartTag, int e) const {
    if (ex.drive(e) != 0) {
      ex(InitialTag{}, e);
      return;
    }
    double g[kMaxBie][1];
    start_lanes<1>(&e, 1, g);
    store_residual(e, g);
  }

  /// Residual G(x^k) of eq. 4.6 at the current iterate (u, v) with the current interface force.
  KOKKOS_INLINE_FUNCTION void operator()(BieResidualTag, int e) const {
    if (ex.drive(e) != 0) return;
    const int t = ex.type(e);
    double u[kMaxDof][1], v[kMaxDof][1], ax[kMaxDof][1], p0[kMaxDof][1], v0[kMaxDof][1], a0[kMaxDof][1], g[kMaxBie][1];
    tile_accel<1>(t, &e, 1, u, v, ax);
    tile_residual<1>(t, &e, 1, u, v, ax, p0, v0, a0, g);
    store_residual(e, g);
  }

  /// x += J^-1 G (R holds the correction after the solve).
  KOKKOS_INLINE_FUNCTION void operator()(BieUpdateTag, int e) const {
    if (ex.drive(e) != 0) return;
    const int s = slot_of_elem(e), nd = ex.nd;
    for (int j = 0; j < nd; ++j) ex.u(e, j) += R(s, j), ex.v(e, j) += R(s, nd + j);
  }

  /// End of step: a_{n+1} = a(x_{n+1}); work of F_p + Theta over dp, damping dp . C v_mid
  /// (implicit midpoint); acc(e, kBieG2 / kBieD2) = m-weighted |G_v|^2 and |dv|^2 of the final state.
  /// Driven elements: reaction and work as in the explicit methods.
  KOKKOS_INLINE_FUNCTION void operator()(BieFinalTag, int e) const {
    if (ex.drive(e) != 0) {
      ex.final_driven(e);
      return;
    }
    final_lanes<1, true>(ex.type(e), &e, 1);
  }

  /// a = a(x) of the current state (free elements; the start-up's a_0): no books.
  KOKKOS_INLINE_FUNCTION void operator()(BieAccelTag, int e) const {
    if (ex.drive(e) == 0) final_lanes<1, false>(ex.type(e), &e, 1);
  }

  /// The residual of element e into its slot's row of R.
  KOKKOS_INLINE_FUNCTION void store_residual(int e, const double (*g)[1]) const {
    const int s = slot_of_elem(e);
    for (int j = 0; j < 2 * ex.nd; ++j) R(s, j) = g[j][0];
  }
  // ---- the split step (BieScheme::split, docs/methods.md "The split step"). F = interface force
  // + Theta + F_p (explicit). Between split steps the state is (p, v, phi) with phi = M^-1 F held
  // in a (not the acceleration: the step needs only phi, and storing it saves the K applies that
  // would recover it; restart and roll-back copy a as they do for every method).
  //   start: v+ = v_n + h/2 phi_n (half kick), and the linear midpoint from (p_n, v+): at x^0 =
  //          (p_n, v+) its residual is G = (h v+ + h^2/2 a_L, h a_L), a_L = -M^-1 K (p_n + beta
  //          v+) - alpha v+, and J of eq. 4.7 is its exact Jacobian: one apply solves it
  //          (p_{n+1}, v-). Per element (unfused) pn, vn keep p_n and v+ for the final's
  //          books; the fused tile start computes the books itself, from the same rounded values,
  //          while p_n, v+, p_{n+1}, v- are in registers, and stores neither.
  //   then the interface force at p_{n+1};
  //   final: the books where the start did not take them (work of Theta + F_p over dp; damping
  //          dp . C (v+ + v-)/2, the midpoint's exact dissipation), phi_{n+1} = M^-1 F_{n+1},
  //          v_{n+1} = v- + h/2 phi_{n+1} (half kick).
  // One K apply per step (two with beta_d: the damping book), as the iterated step's reduced form.
  // The per-element and tiled kernels do the same operations in the same order (the same bits).

  KOKKOS_INLINE_FUNCTION void operator()(BieSplitInitTag, int e) const {
    if (ex.drive(e) != 0) return;
    const int t = ex.type(e);
    double f[kMaxDof][1], v[kMaxDof][1];
    tile_load<1>(t, &e, 1, f, nullptr, v);
    for (int j = 0; j < ex.nd; ++j) ex.a(e, j) = minv(t, j) * f[j][0];
  }

  KOKKOS_INLINE_FUNCTION void operator()(BieSplitStartTag, int e) const {
    if (ex.drive(e) != 0) {
      ex(InitialTag{}, e);
      return;
    }
    if (dispatch_nd(ex.nd, [&](auto N) { split_start_one<decltype(N)::value>(e); })) return;
    double p[kMaxDof][1], v[kMaxDof][1], g[kMaxBie][1];
    split_start_lanes<1>(ex.type(e), &e, 1, p, v, g);
    store_residual(e, g);
    for (int j = 0; j < ex.nd; ++j) pn(e, j) = p[j][0], vn(e, j) = v[j][0], ex.v(e, j) = v[j][0];
  }

  KOKKOS_INLINE_FUNCTION void operator()(BieSplitFinalTag, int e) const {
    if (ex.drive(e) != 0) {
      ex.final_driven(e);
      return;
    }
    if (dispatch_nd(ex.nd, [&](auto N) { split_final_one<decltype(N)::value>(e); })) return;
    const int t = ex.type(e);
    {  // the books from the stored p_n, v+ and this p_{n+1}, v-
      double u[kMaxDof][1], v[kMaxDof][1], p0[kMaxDof][1], v0[kMaxDof][1];
      for (int j = 0; j < ex.nd; ++j)
        u[j][0] = ex.u(e, j), v[j][0] = ex.v(e, j), p0[j][0] = pn(e, j), v0[j][0] = vn(e, j);
      double work[1], pd[1], g2[1], d2[1];
      tile_books<1>(t, &e, 1, u, v, nullptr, p0, v0, nullptr, work, pd, g2, d2);
      store_books(e, work[0], pd[0], g2[0], d2[0]);  // g2 = 0: no iteration, nothing left unconverged
    }
    split_kick_lanes<1>(t, &e, 1);
  }

  // The split step's two per-element kernels for a GPU thread, the dof count ND fixed at compile
  // time (as Integrator::final_one): the arrays a row loop indexes are not kept (their entries
  // are re-read from the state, or written as soon as they are made), the rest stays in registers;
  // the same operations in the same order as split_start_lanes<1> / tile_books<1> +
  // split_kick_lanes<1>, so the same bits (ptxas -v, sm_90: the lane code at width 1 kept its
  // arrays in a 768 B / 1 KB stack frame per thread).

  template <int ND>
  KOKKOS_INLINE_FUNCTION void split_start_one(int e) const {
    const int t = ex.type(e), s = slot_of_elem(e);
    const double h = ex.h;
    double wv[ND];
    NACRE_DYN_UNROLL
    for (int j = 0; j < ND; ++j) wv[j] = ex.u(e, j) + ex.beta * (ex.v(e, j) + 0.5 * h * ex.a(e, j));
    NACRE_DYN_ROLLED
    for (int i = 0; i < ND; ++i) {
      double kw = 0;
      NACRE_DYN_UNROLL
      for (int j = 0; j < ND; ++j) kw += ex.K(t, i, j) * wv[j];
      const double mi = minv(t, i), p = ex.u(e, i), vi = ex.v(e, i) + 0.5 * h * ex.a(e, i);
      const double al = -mi * kw - ex.alpha * vi;
      R(s, i) = h * vi + 0.5 * h * h * al;
      R(s, ND + i) = h * al;
      pn(e, i) = p, vn(e, i) = vi, ex.v(e, i) = vi;  // row i is not read again
    }
  }

  template <int ND>
  KOKKOS_INLINE_FUNCTION void split_final_one(int e) const {
    const int t = ex.type(e);
    const double h = ex.h;
    {  // the books from the stored p_n, v+ and this p_{n+1}, v- (tile_books with ax = nullptr)
      double vm[ND], work = 0;
      NACRE_DYN_UNROLL
      for (int j = 0; j < ND; ++j) {
        vm[j] = 0.5 * (ex.v(e, j) + vn(e, j));
        work += (ex.theta(t, j) + (ex.has_fp ? ex.fp(e, j) : 0.0)) * (ex.u(e, j) - pn(e, j));
      }
      double pd = 0, d2 = 0;
      NACRE_DYN_ROLLED
      for (int i = 0; i < ND; ++i) {
        double kv = 0;
        if (ex.beta != 0.0) {
          NACRE_DYN_UNROLL
          for (int j = 0; j < ND; ++j) kv += ex.K(t, i, j) * vm[j];
        }
        const double m = ex.mass(t, i), dp = ex.u(e, i) - pn(e, i), v = ex.v(e, i), v0 = vn(e, i);
        pd += dp * (ex.alpha * m * (0.5 * (v + v0)) + (ex.beta != 0.0 ? ex.beta * kv : 0.0));
        const double dvi = v - v0;
        d2 += m * dvi * dvi;
      }
      store_books(e, work, pd, 0.0, d2);  // g2 = 0: no iteration, nothing left unconverged
    }
    // the end kick (split_kick_lanes): phi_{n+1} = M^-1 F, v_{n+1} = v- + h/2 phi_{n+1}
    double f[ND];
    ex.template gather<ND>(e, f);
    NACRE_DYN_UNROLL
    for (int i = 0; i < ND; ++i) {
      const double ax = minv(t, i) * (f[i] + (ex.theta(t, i) + (ex.has_fp ? ex.fp(e, i) : 0.0)));
      ex.v(e, i) = ex.v(e, i) + 0.5 * h * ax, ex.a(e, i) = ax;
    }
  }

  /// End-of-step work item w beyond the tiles: a driven element, booked as the explicit methods
  /// (Integrator::final_driven). True when w was such an item (nothing else to do).
  KOKKOS_INLINE_FUNCTION bool driven_final(int w) const {
    if (w < ex.n_tiles) return false;
    ex.final_driven(ex.driven(w - ex.n_tiles));
    return true;
  }

  /// The end-of-step books of element e: work and damping added, the residual norms set.
  KOKKOS_INLINE_FUNCTION void store_books(int e, double work, double pd, double g2, double d2) const {
    ex.acc(e, kWork) += work;
    ex.acc(e, kDamp) += pd;
    ex.acc(e, kBieG2) = g2, ex.acc(e, kBieD2) = d2;
  }

  // ---- lanes: W elements of one type side by side (W = 1: the per-element kernels above; W =
  // kTile: the fused tile kernels below, J^-1 applied in shared_gemm's order). Padded lanes
  // compute on zeros and are never stored.

  /// out[i][b] = sum_j K(t, i, j) in[j][b] for the tile's lanes.
  /// (Restrict and a local accumulator: the stores cannot alias the matrix or the functor, so
  /// the accumulators stay in registers.)
  template <int W>
  KOKKOS_INLINE_FUNCTION void tile_K(int t, const double (*KOKKOS_RESTRICT in)[W],
                                     double (*KOKKOS_RESTRICT out)[W]) const {
    const int nd = ex.nd;
    for (int i = 0; i < nd; ++i) {
      double y[W];
      for (int b = 0; b < W; ++b) y[b] = 0;
      for (int j = 0; j < nd; ++j) {
        const double k = ex.K(t, i, j);
        for (int b = 0; b < W; ++b) y[b] += k * in[j][b];
      }
      for (int b = 0; b < W; ++b) out[i][b] = y[b];
    }
  }

  /// Loads of a tile: f = gathered interface force + Theta + F_p, u (unless nullptr) and v
  /// (padded lanes zero).
  template <int W>
  KOKKOS_INLINE_FUNCTION void tile_load(int t, const int* el, int nb, double (*KOKKOS_RESTRICT f)[W],
                                        double (*KOKKOS_RESTRICT u)[W], double (*KOKKOS_RESTRICT v)[W]) const {
    const int nd = ex.nd;
    for (int b = 0; b < W; ++b) {
      if (b >= nb) {
        for (int j = 0; j < nd; ++j) v[j][b] = f[j][b] = 0;
        if (u)
          for (int j = 0; j < nd; ++j) u[j][b] = 0;
        continue;
      }
      const int e = el[b];
      double fi[kMaxDof];
      ex.gather(e, fi);
      for (int j = 0; j < nd; ++j) {
        f[j][b] = fi[j] + (ex.theta(t, j) + (ex.has_fp ? ex.fp(e, j) : 0.0));
        v[j][b] = ex.v(e, j);
      }
      if (u)
        for (int j = 0; j < nd; ++j) u[j][b] = ex.u(e, j);
    }
  }

  /// a(x) = M^-1 (f - K (u + beta v)) - alpha v for the lanes, from f, u, v of tile_load.
  template <int W>
  KOKKOS_INLINE_FUNCTION void tile_acc(int t, const double (*KOKKOS_RESTRICT f)[W],
                                       const double (*KOKKOS_RESTRICT u)[W], const double (*KOKKOS_RESTRICT v)[W],
                                       double (*KOKKOS_RESTRICT ax)[W]) const {
    const int nd = ex.nd;
    double w[kMaxDof][W], kw[kMaxDof][W];
    for (int j = 0; j < nd; ++j)
      for (int b = 0; b < W; ++b) w[j][b] = u[j][b] + ex.beta * v[j][b];
    tile_K(t, w, kw);
    for (int i = 0; i < nd; ++i) {
      const double mi = minv(t, i);
      for (int b = 0; b < W; ++b) ax[i][b] = mi * (f[i][b] - kw[i][b]) - ex.alpha * v[i][b];
    }
  }

  /// a(x) of the current iterate for the lanes; also loads u and v.
  template <int W>
  KOKKOS_INLINE_FUNCTION void tile_accel(int t, const int* el, int nb, double (*KOKKOS_RESTRICT u)[W],
                                         double (*KOKKOS_RESTRICT v)[W], double (*KOKKOS_RESTRICT ax)[W]) const {
    double f[kMaxDof][W];
    tile_load(t, el, nb, f, u, v);
    tile_acc(t, f, u, v, ax);
  }

  /// Residual G(x) of eq. 4.6 for the lanes from the iterate u, v, its a(x)
  /// ax, and p_n, v_n, a_n (loaded here into pn0, vn0, an0 for the caller; padded lanes zero).
  template <int W>
  KOKKOS_INLINE_FUNCTION void tile_residual(int t, const int* el, int nb, const double (*KOKKOS_RESTRICT u)[W],
                                            const double (*KOKKOS_RESTRICT v)[W], const double (*KOKKOS_RESTRICT ax)[W],
                                            double (*KOKKOS_RESTRICT pn0)[W], double (*KOKKOS_RESTRICT vn0)[W],
                                            double (*KOKKOS_RESTRICT an0)[W], double (*KOKKOS_RESTRICT g)[W]) const {
    const int nd = ex.nd;
    const double h = ex.h;
    double dp[kMaxDof][W], dv[kMaxDof][W], wv[kMaxDof][W], kw[kMaxDof][W];
    for (int b = 0; b < W; ++b) {
      const int e = el[b < nb ? b : 0];
      for (int j = 0; j < nd; ++j) {
        const double p0 = b < nb ? pn(e, j) : 0.0, v0 = b < nb ? vn(e, j) : 0.0;
        pn0[j][b] = p0, vn0[j][b] = v0, an0[j][b] = b < nb ? ex.a(e, j) : 0.0;
        dp[j][b] = u[j][b] - p0, dv[j][b] = v[j][b] - v0;
        wv[j][b] = dp[j][b] + ex.beta * dv[j][b];
      }
    }
    tile_K(t, wv, kw);
    for (int i = 0; i < nd; ++i) {
      const double mi = minv(t, i);
      for (int b = 0; b < W; ++b) {
        const double kc = mi * kw[i][b] + ex.alpha * dv[i][b];
        g[i][b] = h * vn0[i][b] + 0.5 * h * h * an0[i][b] - 0.25 * h * h * kc - dp[i][b];
        g[nd + i][b] = 0.5 * h * (an0[i][b] + ax[i][b]) - dv[i][b];
      }
    }
  }

  /// The books of the end of the step (as BieFinalTag) for the tile: work, damping, residual norms.
  template <int W>
  KOKKOS_INLINE_FUNCTION void tile_books(int t, const int* el, int nb, const double (*KOKKOS_RESTRICT u)[W],
                                         const double (*KOKKOS_RESTRICT v)[W], const double (*KOKKOS_RESTRICT ax)[W],
                                         const double (*KOKKOS_RESTRICT pn0)[W], const double (*KOKKOS_RESTRICT v0)[W],
                                         const double (*KOKKOS_RESTRICT a0)[W], double* work, double* pd, double* g2,
                                         double* d2) const {
    const int nd = ex.nd;
    const double h = ex.h;
    double dp[kMaxDof][W], vm[kMaxDof][W], kv[kMaxDof][W];
    for (int b = 0; b < W; ++b) {
      work[b] = 0;
      const bool live = b < nb;
      const int e = el[live ? b : 0];
      for (int j = 0; j < nd; ++j) {
        dp[j][b] = u[j][b] - pn0[j][b];
        vm[j][b] = 0.5 * (v[j][b] + v0[j][b]);
        work[b] += (ex.theta(t, j) + (ex.has_fp && live ? ex.fp(e, j) : 0.0)) * dp[j][b];
      }
    }
    if (ex.beta != 0.0) tile_K(t, vm, kv);  // else beta K vm adds nothing
    for (int b = 0; b < W; ++b) pd[b] = g2[b] = d2[b] = 0;
    for (int i = 0; i < nd; ++i) {
      const double m = ex.mass(t, i);
      for (int b = 0; b < W; ++b) {
        pd[b] += dp[i][b] * (ex.alpha * m * vm[i][b] + (ex.beta != 0.0 ? ex.beta * kv[i][b] : 0.0));
        const double dvi = v[i][b] - v0[i][b];
        const double gv = ax ? 0.5 * h * (a0[i][b] + ax[i][b]) - dvi : 0.0;  // ax = nullptr: the split, no residual
        g2[b] += m * gv * gv, d2[b] += m * dvi * dvi;
      }
    }
  }

  /// y = J^-1 G for the tile (G in g, rows [0, nd) positions, [nd, 2 nd) velocities; g is
  /// scaled in place for the block forms): the velocity-first form, or the rows of J^-1 (dense or
  /// block structure) in blocks of kRowBlock accumulators. Every tiled J^-1 apply goes through here.
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void tile_correction(int t, double (*KOKKOS_RESTRICT g)[kTile],
                                              double (*KOKKOS_RESTRICT y)[kTile]) const {
    const int n = 2 * ex.nd;
    tile_block_scale<Jinv>(t, g);
    if constexpr (std::is_same_v<Jinv, JinvVelocityFirst>) {
      tile_vfirst(t, g, y);
    } else {
      for (int i0 = 0; i0 < n; i0 += kRowBlock) {
        const int nq = n - i0 < kRowBlock ? n - i0 : kRowBlock;
        tile_jinv_rows<Jinv>(t, i0, nq, g, y + i0);
      }
    }
  }

  /// x += J^-1 G for the tile's elements.
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void tile_solve_update(int t, const int* el, int nb,
                                                double (*KOKKOS_RESTRICT g)[kTile]) const {
    const int nd = ex.nd;
    double y[kMaxBie][kTile];
    tile_correction<Jinv>(t, g, y);
    for (int b = 0; b < nb; ++b) {
      const int e = el[b];
      for (int j = 0; j < nd; ++j) ex.u(e, j) += y[j][b], ex.v(e, j) += y[nd + j][b];
    }
  }

  /// u += (J^-1 G)_p for the tile's elements, v untouched (start_positions_only; the block form
  /// without damping: g_p needs no scaling, and the first nd rows are those of tile_correction).
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void tile_solve_update_positions(int t, const int* el, int nb,
                                                          const double (*KOKKOS_RESTRICT g)[kTile]) const {
    const int nd = ex.nd;
    double y[kMaxBie][kTile];
    for (int i0 = 0; i0 < nd; i0 += kRowBlock)
      tile_jinv_rows<Jinv>(t, i0, nd - i0 < kRowBlock ? nd - i0 : kRowBlock, g, y + i0);
    for (int b = 0; b < nb; ++b) {
      const int e = el[b];
      for (int j = 0; j < nd; ++j) ex.u(e, j) += y[j][b];
    }
  }

  /// p_n, v_n stored; G at x^0 = x_n: (h v_n + h^2/2 a_n, h a_n) (padded lanes zero).
  template <int W>
  KOKKOS_INLINE_FUNCTION void start_lanes(const int* el, int nb, double (*KOKKOS_RESTRICT g)[W]) const {
    const int nd = ex.nd;
    const double h = ex.h;
    for (int b = 0; b < W; ++b) {
      if (b >= nb) {
        for (int j = 0; j < 2 * nd; ++j) g[j][b] = 0;
        continue;
      }
      const int e = el[b];
      for (int j = 0; j < nd; ++j) {
        const double p = ex.u(e, j), v = ex.v(e, j), a = ex.a(e, j);
        pn(e, j) = p, vn(e, j) = v;
        g[j][b] = h * v + 0.5 * h * h * a;
        g[nd + j][b] = h * a;
      }
    }
  }

  /// p_n, v_n, a_n of the lanes (padded lanes zero).
  template <int W>
  KOKKOS_INLINE_FUNCTION void load_step_start(const int* el, int nb, double (*KOKKOS_RESTRICT p0)[W],
                                              double (*KOKKOS_RESTRICT v0)[W], double (*KOKKOS_RESTRICT a0)[W]) const {
    for (int b = 0; b < W; ++b) {
      const bool live = b < nb;
      const int e = el[live ? b : 0];
      for (int j = 0; j < ex.nd; ++j)
        p0[j][b] = live ? pn(e, j) : 0.0, v0[j][b] = live ? vn(e, j) : 0.0, a0[j][b] = live ? ex.a(e, j) : 0.0;
    }
  }

  /// End of step of the lanes (BieFinalTag): a_{n+1} = a(x_{n+1}) and, when Book, the books.
  template <int W, bool Book>
  KOKKOS_INLINE_FUNCTION void final_lanes(int t, const int* el, int nb) const {
    const int nd = ex.nd;
    double u[kMaxDof][W], v[kMaxDof][W], ax[kMaxDof][W];
    tile_accel<W>(t, el, nb, u, v, ax);
    if constexpr (!Book) {
      for (int b = 0; b < nb; ++b)
        for (int j = 0; j < nd; ++j) ex.a(el[b], j) = ax[j][b];
      return;
    }
    double p0[kMaxDof][W], v0[kMaxDof][W], a0[kMaxDof][W];
    load_step_start<W>(el, nb, p0, v0, a0);
    double work[W], pd[W], g2[W], d2[W];
    tile_books<W>(t, el, nb, u, v, ax, p0, v0, a0, work, pd, g2, d2);
    for (int b = 0; b < nb; ++b) {
      const int e = el[b];
      for (int j = 0; j < nd; ++j) ex.a(e, j) = ax[j][b];
      store_books(e, work[b], pd[b], g2[b], d2[b]);
    }
  }

  /// The split step's start for the lanes: p = p_n, v = v+ = v_n + h/2 phi_n (a holds phi) and
  /// the linear midpoint's residual g at (p_n, v+) (padded lanes zero).
  template <int W>
  KOKKOS_INLINE_FUNCTION void split_start_lanes(int t, const int* el, int nb, double (*KOKKOS_RESTRICT p)[W],
                                                double (*KOKKOS_RESTRICT v)[W], double (*KOKKOS_RESTRICT g)[W]) const {
    const int nd = ex.nd;
    const double h = ex.h;
    double wv[kMaxDof][W], kw[kMaxDof][W];
    for (int b = 0; b < W; ++b) {
      const bool live = b < nb;
      const int e = el[live ? b : 0];
      for (int j = 0; j < nd; ++j) {
        p[j][b] = live ? ex.u(e, j) : 0.0;
        v[j][b] = live ? ex.v(e, j) + 0.5 * h * ex.a(e, j) : 0.0;
        wv[j][b] = p[j][b] + ex.beta * v[j][b];
      }
    }
    tile_K<W>(t, wv, kw);
    for (int i = 0; i < nd; ++i) {
      const double mi = minv(t, i);
      for (int b = 0; b < W; ++b) {
        const double al = -mi * kw[i][b] - ex.alpha * v[i][b];
        g[i][b] = h * v[i][b] + 0.5 * h * h * al;
        g[nd + i][b] = h * al;
      }
    }
  }

  /// The split step's end kick for the lanes: phi_{n+1} = M^-1 F (what a holds between split
  /// steps), v_{n+1} = v- + h/2 phi_{n+1}.
  template <int W>
  KOKKOS_INLINE_FUNCTION void split_kick_lanes(int t, const int* el, int nb) const {
    const int nd = ex.nd;
    const double h = ex.h;
    double f[kMaxDof][W], v[kMaxDof][W], ax[kMaxDof][W];
    tile_load<W>(t, el, nb, f, nullptr, v);
    for (int i = 0; i < nd; ++i) {
      const double mi = minv(t, i);
      for (int b = 0; b < W; ++b) {
        ax[i][b] = mi * f[i][b];
        v[i][b] += 0.5 * h * ax[i][b];
      }
    }
    for (int b = 0; b < nb; ++b) {
      const int e = el[b];
      for (int j = 0; j < nd; ++j) ex.v(e, j) = v[j][b], ex.a(e, j) = ax[j][b];
    }
  }

  /// The elements (el[0, nb)) and the type of the tile of work item w < n_tiles.
  struct Tile {
    const int* el;
    int nb, t;
  };
  KOKKOS_INLINE_FUNCTION Tile tile(int w) const {
    const int k0 = ex.tile_start(w);
    return Tile{ex.tile_elem.data() + k0, ex.tile_start(w + 1) - k0, ex.type(ex.tile_elem(k0))};
  }

  /// Start (BieStartTag) and the first J^-1 apply and update, per tile; driven elements impose t_{n+1}.
  template <class Jinv, bool PositionsOnly>
  KOKKOS_INLINE_FUNCTION void operator()(BieStartTileTag<Jinv, PositionsOnly>, int w) const {
    if (w >= ex.n_tiles) {
      ex(InitialTag{}, ex.driven(w - ex.n_tiles));
      return;
    }
    const Tile T = tile(w);
    double g[kMaxBie][kTile];
    start_lanes<kTile>(T.el, T.nb, g);
    if constexpr (PositionsOnly)
      tile_solve_update_positions<Jinv>(T.t, T.el, T.nb, g);
    else
      tile_solve_update<Jinv>(T.t, T.el, T.nb, g);
  }

  /// Residual (BieResidualTag), J^-1 apply and update, per tile; driven elements untouched.
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void operator()(BieIterTileTag<Jinv>, int w) const {
    if (w >= ex.n_tiles) return;
    const Tile T = tile(w);
    double u[kMaxDof][kTile], v[kMaxDof][kTile], ax[kMaxDof][kTile], p0[kMaxDof][kTile], v0[kMaxDof][kTile],
        a0[kMaxDof][kTile], g[kMaxBie][kTile];
    tile_accel<kTile>(T.t, T.el, T.nb, u, v, ax);
    tile_residual<kTile>(T.t, T.el, T.nb, u, v, ax, p0, v0, a0, g);
    tile_solve_update<Jinv>(T.t, T.el, T.nb, g);
  }

  /// End of step (BieFinalTag) per tile; driven elements as the explicit methods.
  KOKKOS_INLINE_FUNCTION void operator()(BieFinalTileTag, int w) const {
    if (driven_final(w)) return;
    const Tile T = tile(w);
    final_lanes<kTile, true>(T.t, T.el, T.nb);
  }

  /// The last iteration and the end of the step in one pass, where the end keeps the interface
  /// force of the previous iterate (Params::bie_reuse_force): that is the force the iteration
  /// gathers, so BieIterTileTag followed by BieFinalTileTag is this one kernel with one gather,
  /// one load of u, v, p_n, v_n, a_n and one store of u, v, a per element instead of two of each.
  /// The same operations on the same values in the same order: the same bits.
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void operator()(BieIterFinalTileTag<Jinv>, int w) const {
    if (driven_final(w)) return;
    const Tile T = tile(w);
    const int nd = ex.nd;
    double f[kMaxDof][kTile], u[kMaxDof][kTile], v[kMaxDof][kTile], ax[kMaxDof][kTile], p0[kMaxDof][kTile],
        v0[kMaxDof][kTile], a0[kMaxDof][kTile], g[kMaxBie][kTile];
    tile_load<kTile>(T.t, T.el, T.nb, f, u, v);
    tile_acc<kTile>(T.t, f, u, v, ax);
    tile_residual<kTile>(T.t, T.el, T.nb, u, v, ax, p0, v0, a0, g);
    {  // x += J^-1 G in registers (tile_solve_update's sums; its stores u += y are these adds)
      double y[kMaxBie][kTile];
      tile_correction<Jinv>(T.t, g, y);
      for (int j = 0; j < nd; ++j)
        for (int b = 0; b < kTile; ++b) u[j][b] += y[j][b], v[j][b] += y[nd + j][b];
    }
    // a_{n+1} = a(x_{n+1}) with the same interface force f, then the books
    tile_acc<kTile>(T.t, f, u, v, ax);
    double work[kTile], pd[kTile], g2[kTile], d2[kTile];
    tile_books<kTile>(T.t, T.el, T.nb, u, v, ax, p0, v0, a0, work, pd, g2, d2);
    for (int b = 0; b < T.nb; ++b) {
      const int e = T.el[b];
      for (int j = 0; j < nd; ++j) ex.u(e, j) = u[j][b], ex.v(e, j) = v[j][b], ex.a(e, j) = ax[j][b];
      store_books(e, work[b], pd[b], g2[b], d2[b]);
    }
  }

  /// BieIterFinalTileTag when C = 0 (block_lower), in its reduced form. The position residual
  /// G_p = h v_n + h^2/2 a_n - (I + h^2/4 M^-1 K) dp does not involve the interface force, and
  /// the first iteration solved it exactly (dp_1 = A^-1 (h v_n + h^2/2 a_n), A = I + h^2/4 M^-1 K),
  /// so G_p(x_1) = 0 and J^-1 = [[A^-1, 0], [B, I]] leaves y_p = 0, y_v = G_v: the last iteration
  /// is p_{n+1} = p_1, v_{n+1} = v_n + h/2 (a_n + a(x_1)), and a_{n+1} = a(x_1) (a depends on p
  /// only, the force is kept). The full form computes the same values plus the rounding of
  /// G_p ~ 0 times J^-1: equal to rounding (tests/dyn), at one K apply instead of three K applies
  /// and the J^-1 apply, and no store of u.
  KOKKOS_INLINE_FUNCTION void operator()(BieIterFinalLinearTileTag, int w) const {
    if (driven_final(w)) return;
    const Tile T = tile(w);
    const int nd = ex.nd;
    const double h = ex.h;
    double f[kMaxDof][kTile], u[kMaxDof][kTile], v[kMaxDof][kTile], ax[kMaxDof][kTile], p0[kMaxDof][kTile],
        v0[kMaxDof][kTile], a0[kMaxDof][kTile];
    tile_load<kTile>(T.t, T.el, T.nb, f, u, v);
    tile_acc<kTile>(T.t, f, u, v, ax);
    load_step_start<kTile>(T.el, T.nb, p0, v0, a0);
    for (int j = 0; j < nd; ++j)
      for (int b = 0; b < kTile; ++b) v[j][b] = v0[j][b] + 0.5 * h * (a0[j][b] + ax[j][b]);
    double work[kTile], pd[kTile], g2[kTile], d2[kTile];
    tile_books<kTile>(T.t, T.el, T.nb, u, v, ax, p0, v0, a0, work, pd, g2, d2);
    for (int b = 0; b < T.nb; ++b) {
      const int e = T.el[b];
      for (int j = 0; j < nd; ++j) ex.v(e, j) = v[j][b], ex.a(e, j) = ax[j][b];
      store_books(e, work[b], pd[b], g2[b], d2[b]);
    }
  }

  /// The split step's start (BieSplitStartTag) and its one J^-1 apply and update, per tile.
  template <class Jinv>
  KOKKOS_INLINE_FUNCTION void operator()(BieSplitStartTileTag<Jinv>, int w) const {
    if (w >= ex.n_tiles) {
      ex(InitialTag{}, ex.driven(w - ex.n_tiles));
      return;
    }
    const Tile T = tile(w);
    const int nd = ex.nd;
    double p[kMaxDof][kTile], v[kMaxDof][kTile], g[kMaxBie][kTile], y[kMaxBie][kTile];
    split_start_lanes<kTile>(T.t, T.el, T.nb, p, v, g);
    tile_correction<Jinv>(T.t, g, y);
    // p_{n+1} and v-; the step's books are complete here: they need p_n, v+, p_{n+1} and v-, not
    // the end's kick (BieSplitFinalTag books them from the stored p_n, v+ and the same rounded
    // p_{n+1}, v-: the same bits), so p_n, v+ are never stored nor reloaded
    double p1[kMaxDof][kTile], v1[kMaxDof][kTile];
    for (int j = 0; j < nd; ++j)
      for (int b = 0; b < kTile; ++b) p1[j][b] = p[j][b] + y[j][b], v1[j][b] = v[j][b] + y[nd + j][b];
    double work[kTile], pd[kTile], g2[kTile], d2[kTile];
    tile_books<kTile>(T.t, T.el, T.nb, p1, v1, nullptr, p, v, nullptr, work, pd, g2, d2);  // no residual
    for (int b = 0; b < T.nb; ++b) {
      const int e = T.el[b];
      for (int j = 0; j < nd; ++j) ex.u(e, j) = p1[j][b], ex.v(e, j) = v1[j][b];
      store_books(e, work[b], pd[b], 0.0, d2[b]);  // g2 = 0: no iteration
    }
  }

  /// The split step's end (BieSplitFinalTag) per tile; driven elements as the explicit methods.
  KOKKOS_INLINE_FUNCTION void operator()(BieSplitFinalTileTag, int w) const {
    if (driven_final(w)) return;
    const Tile T = tile(w);
    split_kick_lanes<kTile>(T.t, T.el, T.nb);  // the books were kept by the start (BieSplitStartTileTag)
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
  Kokkos::View<const double***, ElemLayout<MemorySpace>, MemorySpace> J;  ///< J^-1 [type][row][col]
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
  /// (3) Kokkos Kernels: KokkosBlas::SerialGemv (the per-thread batched GEMV; KokkosBatched's
  /// name for it is deprecated and aborts in the develop snapshot) of J^-1 and the residual.
  KOKKOS_INLINE_FUNCTION void operator()(SolveBatchedTag, int s) const {
    const int t = slot_type(s);
    double r[kMaxBie];
    for (int j = 0; j < n; ++j) r[j] = R(s, j);
    auto A = Kokkos::subview(J, t, Kokkos::ALL, Kokkos::ALL);
    auto y = Kokkos::subview(R, s, Kokkos::ALL);
    Kokkos::View<const double*, Kokkos::LayoutRight, Kokkos::AnonymousSpace, Kokkos::MemoryUnmanaged> x(r, n);
    KokkosBlas::SerialGemv<KokkosBlas::Trans::NoTranspose, KokkosBlas::Algo::Gemv::Unblocked>::invoke(
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

/// \brief What a BIE step needs besides the kernels' functors: the J^-1 apply and its block, the
/// iterations of eq. 4.6 (iterated scheme) and whether the last one keeps its force, and the
/// extents. Chosen once when the simulation is built.
struct BieStepPlan {
  BieSolve variant = BieSolve::shared_gemm;
  int block = 4, iterations = 2;
  bool reuse_force = true;
  int n_elem = 0, n_iface = 0, n_tiles = 0;
};

/// \brief The scheme of a BIE step as a type (BieScheme::iterate, BieScheme::split); with
/// std::bool_constant<Fused> (shared J^-1 over the element tiles, residual never stored: the
/// BieIntegrator's *TileTag kernels) they pick one of bie_step's overloads at compile time.
struct BieIterateScheme {};
struct BieSplitScheme {};

/// \brief One split BIE step (docs/methods.md "The split step"): start (half kick, residual) + one
/// J^-1 apply, the interface force at p_{n+1}, end.
template <class ExecutionSpace, bool Fused, class Jinv>
void bie_step(const ExecutionSpace& space, BieSplitScheme, std::bool_constant<Fused>, Jinv,
              const BieIntegrator<MemOf<ExecutionSpace>>& it, const InterfaceOp<MemOf<ExecutionSpace>>& op,
              const BieSolveOp<MemOf<ExecutionSpace>>& solve, const BieStepPlan& plan) {
  using Exec = ExecutionSpace;
  const int nw = it.ex.n_tiles + it.ex.n_driven;  // work items of the fused (tiled) kernels
  (void)nw, (void)solve;                          // (each is read by one of the two variants only)
  {
    Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_start");
    if constexpr (Fused)
      Kokkos::parallel_for("nacre::dyn::bie_split_start_tiled",
                           Kokkos::RangePolicy<Exec, BieSplitStartTileTag<Jinv>>(space, 0, nw), it);
    else {
      Kokkos::parallel_for("nacre::dyn::bie_split_start",
                           Kokkos::RangePolicy<Exec, BieSplitStartTag>(space, 0, plan.n_elem), it);
      bie_solve(space, solve, plan.variant, plan.block, plan.n_elem, plan.n_tiles);
      Kokkos::parallel_for("nacre::dyn::bie_update", Kokkos::RangePolicy<Exec, BieUpdateTag>(space, 0, plan.n_elem),
                           it);
    }
  }
  force(space, op, plan.n_iface);
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_final");
  if constexpr (Fused)
    Kokkos::parallel_for("nacre::dyn::bie_split_final_tiled",
                         Kokkos::RangePolicy<Exec, BieSplitFinalTileTag>(space, 0, nw), it);
  else
    Kokkos::parallel_for("nacre::dyn::bie_split_final",
                         Kokkos::RangePolicy<Exec, BieSplitFinalTag>(space, 0, plan.n_elem), it);
}

/// \brief One iterated BIE step (eq. 4.6), fused over the element tiles: start, then per
/// iteration the interface force and the tiled iterate; the last iteration and the end in one
/// pass where the force is kept.
template <class ExecutionSpace, class Jinv>
void bie_step(const ExecutionSpace& space, BieIterateScheme, std::true_type /*fused*/, Jinv,
              const BieIntegrator<MemOf<ExecutionSpace>>& it, const InterfaceOp<MemOf<ExecutionSpace>>& op,
              const BieSolveOp<MemOf<ExecutionSpace>>& /*solve: inside the tiles*/, const BieStepPlan& plan) {
  using Exec = ExecutionSpace;
  const int nw = it.ex.n_tiles + it.ex.n_driven;
  // C = 0 (the block form with jq = 0): with the force kept the last pass is the reduced one, and
  // with two iterations the start needs only u_1 (BieStartTileTag's PositionsOnly)
  const bool reduced_end = std::is_same_v<Jinv, JinvBlockLower> && it.jq == 0.0;
  {
    Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_start");
    if (reduced_end && plan.iterations == 2 && plan.reuse_force)
      Kokkos::parallel_for("nacre::dyn::bie_start_tiled",
                           Kokkos::RangePolicy<Exec, BieStartTileTag<Jinv, true>>(space, 0, nw), it);
    else
      Kokkos::parallel_for("nacre::dyn::bie_start_tiled",
                           Kokkos::RangePolicy<Exec, BieStartTileTag<Jinv, false>>(space, 0, nw), it);
  }
  for (int k = 0; k < plan.iterations; ++k) {
    if (k > 0 && plan.reuse_force && k == plan.iterations - 1) {  // the last iteration and the end in one pass
      Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_iterate_final");
      if (reduced_end)  // C = 0 only: with alpha_d M, G_p(x_1) = 0 still, but y_p != 0
        Kokkos::parallel_for("nacre::dyn::bie_iterate_final_linear",
                             Kokkos::RangePolicy<Exec, BieIterFinalLinearTileTag>(space, 0, nw), it);
      else
        Kokkos::parallel_for("nacre::dyn::bie_iterate_final_tiled",
                             Kokkos::RangePolicy<Exec, BieIterFinalTileTag<Jinv>>(space, 0, nw), it);
      return;
    }
    if (k > 0) {
      Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_iterate");
      Kokkos::parallel_for("nacre::dyn::bie_iterate_tiled",
                           Kokkos::RangePolicy<Exec, BieIterTileTag<Jinv>>(space, 0, nw), it);
    }
    force(space, op, plan.n_iface);
  }
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_final");
  Kokkos::parallel_for("nacre::dyn::bie_final_tiled", Kokkos::RangePolicy<Exec, BieFinalTileTag>(space, 0, nw), it);
}

/// \brief One iterated BIE step (eq. 4.6), unfused: start, then per iteration (solve, update,
/// interface force, residual), the last interface force at x_{n+1}, and the final accelerations
/// and books.
template <class ExecutionSpace, class Jinv>
void bie_step(const ExecutionSpace& space, BieIterateScheme, std::false_type /*fused*/, Jinv /*the solve applies J^-1*/,
              const BieIntegrator<MemOf<ExecutionSpace>>& it, const InterfaceOp<MemOf<ExecutionSpace>>& op,
              const BieSolveOp<MemOf<ExecutionSpace>>& solve, const BieStepPlan& plan) {
  using Exec = ExecutionSpace;
  {
    Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_start");
    Kokkos::parallel_for("nacre::dyn::bie_start", Kokkos::RangePolicy<Exec, BieStartTag>(space, 0, plan.n_elem), it);
  }
  for (int k = 0; k < plan.iterations; ++k) {
    if (k > 0) {
      Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_residual");
      Kokkos::parallel_for("nacre::dyn::bie_residual", Kokkos::RangePolicy<Exec, BieResidualTag>(space, 0, plan.n_elem),
                           it);
    }
    bie_solve(space, solve, plan.variant, plan.block, plan.n_elem, plan.n_tiles);
    {
      Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_update");
      Kokkos::parallel_for("nacre::dyn::bie_update", Kokkos::RangePolicy<Exec, BieUpdateTag>(space, 0, plan.n_elem),
                           it);
    }
    if (plan.reuse_force && k == plan.iterations - 1 && k > 0) break;  // a_{n+1} from the force at the previous iterate
    force(space, op, plan.n_iface);
  }
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::bie_final");
  Kokkos::parallel_for("nacre::dyn::bie_final", Kokkos::RangePolicy<Exec, BieFinalTag>(space, 0, plan.n_elem), it);
}

/// \brief Free elements' a of the current state (start-up): the acceleration a(x) for the
/// iterated step, phi = M^-1 F for the split step (what each carries between steps); computes the
/// interface force of the current state first.
template <class ExecutionSpace>
void bie_accelerations(const ExecutionSpace& space, BieIntegrator<MemOf<ExecutionSpace>> it,
                       const InterfaceOp<MemOf<ExecutionSpace>>& op, int n_elem, int n_iface, bool split = false) {
  force(space, op, n_iface);
  if (split)
    Kokkos::parallel_for("nacre::dyn::bie_split_init", Kokkos::RangePolicy<ExecutionSpace, BieSplitInitTag>(space, 0, n_elem),
                         it);
  else
    Kokkos::parallel_for("nacre::dyn::bie_accelerations",
                         Kokkos::RangePolicy<ExecutionSpace, BieAccelTag>(space, 0, n_elem), it);
}

/// \brief Relative residual of the last step (see Simulation::bie_residual), from the free
/// elements' acc(e, kBieG2), acc(e, kBieD2).
/// Deterministic sums over the rows of `mask` (empty: all) combined by `combine` (column_sum's):
/// the same bits on any thread or rank count.
template <class ExecutionSpace, class Combine = sum::Local>
double bie_last_residual(const ExecutionSpace& space, SumWorkspace<MemOf<ExecutionSpace>>& ws,
                         const AccView<MemOf<ExecutionSpace>>& acc,
                         const Kokkos::View<const std::int8_t*, MemOf<ExecutionSpace>>& drive, int n_elem,
                         const Kokkos::View<std::uint8_t*, MemOf<ExecutionSpace>>& mask = {},
                         const Combine& combine = {}) {
  const auto g2 = KOKKOS_LAMBDA(const int e) { return drive(e) == 0 ? acc(e, kBieG2) : 0.0; };
  const auto d2 = KOKKOS_LAMBDA(const int e) { return drive(e) == 0 ? acc(e, kBieD2) : 0.0; };
  const double g = deterministic_sum(space, "nacre::dyn::bie_residual_g", ws, 0, n_elem, owned_term(mask, g2), combine);
  const double d = deterministic_sum(space, "nacre::dyn::bie_residual_d", ws, 0, n_elem, owned_term(mask, d2), combine);
  return d > 0 ? Kokkos::sqrt(g / d) : 0.0;
}

}  // namespace nacre::dyn
