// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Device kernels of the explicit integrators (eq. 4.4, UE and BE share them): the
/// cohesive interface operator (energy, forces and damage from the cohesive integral) and the
/// integrator (initial_integrate / final_integrate; the interface force sits between them).
///
/// Why no atomics: the interface kernel writes the 8 nodal force components of each interface
/// into its own row of `iforce`; final_integrate then gathers, per element, the rows of its
/// interfaces from a CSR list in increasing interface order. Every sum has a fixed order, so
/// the result is bit-identical for any thread count or backend schedule.
///
/// Why one law integral: the jump is linear along the shared segment (each side is a straight
/// edge), exactly as between rigid bricks, so the interface calls the cohesive folder's integral
/// (cohesive::integrate: exact piece by piece for the law, segment.hpp; Gauss-Legendre with a
/// history per point once a joint is damaged, damage.hpp) that the Monte Carlo solver uses: one
/// integral of one law, its energy and forces from the same pieces (force = -dE/dp to rounding).
#include <nacre/cohesive/damage.hpp>
#include <nacre/core/assert.hpp>
#include <nacre/core/deterministic_sum.hpp>
#include <nacre/dyn/halo.hpp>  // MPI runs refresh the halo's u before every interface force pass
#include <nacre/dyn/model.hpp>

#include <type_traits>

// Loop shapes of the device's per-element step (Integrator::final_one): an array stays in
// registers only when every index into it is a compile-time constant, so the inner (column)
// loops unroll fully; the outer (row) loops stay rolled, or the unrolled product would hold
// every matrix entry at once (measured with ptxas -v, sm_90: 255 registers and 1 KB of spills).
// Host passes get no pragma (nvcc's host front end rejects "GCC unroll", g++ ignores "unroll").
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#define NACRE_DYN_UNROLL _Pragma("unroll")
#define NACRE_DYN_ROLLED _Pragma("unroll 1")
#else
#define NACRE_DYN_UNROLL
#define NACRE_DYN_ROLLED
#endif

namespace nacre::dyn {

/// \brief f(std::integral_constant<int, ND>{}) for the model's dof count nd (6, 8, ..., 16: 2 x the
/// largest element's nodes), false for any other: the device kernels' per-element steps with the
/// count fixed at compile time (final_one, BieIntegrator's split_*_one). One nd per model, so the
/// switch never diverges.
template <class F>
KOKKOS_INLINE_FUNCTION bool dispatch_nd(int nd, const F& f) {
  switch (nd) {
  case 6: f(std::integral_constant<int, 6>{}); return true;
  case 8: f(std::integral_constant<int, 8>{}); return true;
  case 10: f(std::integral_constant<int, 10>{}); return true;
  case 12: f(std::integral_constant<int, 12>{}); return true;
  case 14: f(std::integral_constant<int, 14>{}); return true;
  case 16: f(std::integral_constant<int, 16>{}); return true;
  default: return false;
  }
}

struct ForceTag {};
struct InitialTag {};
/// How final_integrate applies (M + h/2 C)^-1: the dense product, or its diagonal where every
/// off-diagonal entry is an exact zero (Model::ainv_diagonal, beta_d = 0: the same bits, the
/// zeros skipped). A type, chosen once per run with the element walk.
struct AinvDense {};
struct AinvDiagonal {};
template <class AinvForm>
struct FinalTag {};
template <class AinvForm>
struct FinalTileTag {};

/// Column of the per-element accumulators (every element): work done on it and energy its
/// damping dissipated. BIE adds two columns: the m-weighted |G_v|^2 and |v_{n+1} - v_n|^2 of the
/// last step (Simulation::bie_residual); UE and BE allocate only the first two.
enum AccCol : int { kWork = 0, kDamp = 1, kBieG2 = 2, kBieD2 = 3 };
inline constexpr int kAccColsExplicit = 2, kAccColsBie = 4;
/// Column of the driven elements' books (row driven_index(e)): the reaction, and from the
/// previous step kinetic + strain energy, F_i . pattern (the interface force along the
/// prescribed motion) and v^T C v. Only driven elements need them, so only they store them
/// (a row per element cost 32 B per brick, twice with the roll-back copy).
enum DrivenCol : int { kReact = 0, kEnergyPrev = 1, kGPrev = 2, kDampPowPrev = 3, kDrivenCols = 4 };

template <class MemorySpace>
using DofView = typename Model<MemorySpace>::Dof;
/// \brief A rank's rows of a sum (MPI runs): term(i) where mask(i), 0 elsewhere; an empty mask
/// (one process) counts every row. The rows a rank does not own are never evaluated.
template <class MemorySpace, class Term>
struct OwnedTerm {
  Kokkos::View<const std::uint8_t*, MemorySpace> mask;
  Term term;
  KOKKOS_INLINE_FUNCTION auto operator()(int i) const -> decltype(term(i)) {
    if (mask.data() && mask(i) == 0) return decltype(term(i))(0);
    return term(i);
  }
};
template <class MemorySpace, class Term>
OwnedTerm<MemorySpace, Term> owned_term(const Kokkos::View<std::uint8_t*, MemorySpace>& mask, const Term& t) {
  return OwnedTerm<MemorySpace, Term>{mask, t};
}
/// [element][column]; the column count is the method's (kAccColsExplicit or kAccColsBie).
template <class MemorySpace>
using AccView = Kokkos::View<double**, ElemLayout<MemorySpace>, MemorySpace>;
/// [driven element][DrivenCol]
template <class MemorySpace>
using DrivenAccView = Kokkos::View<double* [kDrivenCols], ElemLayout<MemorySpace>, MemorySpace>;
template <class MemorySpace>
using IforceView = Kokkos::View<double* [8], ElemLayout<MemorySpace>, MemorySpace>;

/// \brief Cohesive interfaces acting on the jump of the element displacements `u`.
template <class MemorySpace>
struct InterfaceOp {
  Kokkos::View<const int* [2], ElemLayout<MemorySpace>, MemorySpace> ielem;
  Kokkos::View<const int*, MemorySpace> ishape;
  Kokkos::View<const std::int8_t* [4], ElemLayout<MemorySpace>, MemorySpace> inode;
  Kokkos::View<const double* [4], ElemLayout<MemorySpace>, MemorySpace> ixi;
  Kokkos::View<const double*, MemorySpace> inx, iny, ilen;
  Kokkos::View<const std::uint8_t*, MemorySpace> ikind;
  Kokkos::View<const double**, ElemLayout<MemorySpace>, MemorySpace> u;
  IforceView<MemorySpace> out;
  Kokkos::View<double**, Kokkos::LayoutRight, MemorySpace> hist;  ///< Model::hist (empty: reversible)
  cohesive::LawTable laws;
  cohesive::Quadrature quad;
  double thickness;
  /// MPI runs: the exchange force() runs first, so the halo ends read their owners' u (host
  /// only, never read in a kernel; null in one process)
  const ElementHalo<MemorySpace>* halo = nullptr;

  InterfaceOp(const Model<MemorySpace>& m, const DofView<MemorySpace>& u_, const IforceView<MemorySpace>& out_,
              const ElementHalo<MemorySpace>* halo_ = nullptr)
      : ielem(m.ielem), ishape(m.ishape), inode(m.inode), ixi(m.ixi), inx(m.inx), iny(m.iny), ilen(m.ilen),
        ikind(m.ikind), u(u_), out(out_), hist(m.hist), laws(m.laws), quad(m.quad), thickness(m.thickness),
        halo(halo_) {}

  /// Interface i's damage history (one value per quadrature point), or null: the reversible law
  /// (no history in the run, or an internal joint).
  KOKKOS_INLINE_FUNCTION double* history(int i) const {
    return hist.data() && i < static_cast<int>(hist.extent(0)) ? &hist(i, 0) : nullptr;
  }

  /// Nodal displacements of the two edges: q = (a0x a0y a1x a1y b0x b0y b1x b1y).
  KOKKOS_INLINE_FUNCTION void load(int i, double q[8]) const {
    const int ea = ielem(i, 0), eb = ielem(i, 1), sh = ishape(i);
    for (int k = 0; k < 4; ++k) {
      const int e = k < 2 ? ea : eb, n = inode(sh, k);
      q[2 * k] = u(e, 2 * n);
      q[2 * k + 1] = u(e, 2 * n + 1);
    }
  }

  /// Jump (normal, tangential) at segment parameter s and the two sides' edge parameters.
  KOKKOS_INLINE_FUNCTION void jump(int i, const double q[8], double s, double& dn, double& dt, double& xa,
                                   double& xb) const {
    xa = ixi(ishape(i), 0) + s * (ixi(ishape(i), 1) - ixi(ishape(i), 0));
    xb = ixi(ishape(i), 2) + s * (ixi(ishape(i), 3) - ixi(ishape(i), 2));
    const double dx = (1 - xb) * q[4] + xb * q[6] - (1 - xa) * q[0] - xa * q[2];
    const double dy = (1 - xb) * q[5] + xb * q[7] - (1 - xa) * q[1] - xa * q[3];
    const double nx = inx(ishape(i)), ny = iny(ishape(i));
    dn = dx * nx + dy * ny;
    dt = -dx * ny + dy * nx;  // tangent (-ny, nx)
  }

  /// The jump at the segment's two ends (side b minus side a, global frame) and the interface's
  /// unit normal: the gap cohesive::integrate takes. The jump is linear along the segment (each
  /// side is a straight edge with linear shape functions), so these two ends define it.
  KOKKOS_INLINE_FUNCTION cohesive::Gap gap(int i, const double q[8]) const {
    const int sh = ishape(i);
    const double xa0 = ixi(sh, 0), xa1 = ixi(sh, 1), xb0 = ixi(sh, 2), xb1 = ixi(sh, 3);
    return cohesive::Gap{(1 - xb0) * q[4] + xb0 * q[6] - (1 - xa0) * q[0] - xa0 * q[2],
                         (1 - xb0) * q[5] + xb0 * q[7] - (1 - xa0) * q[1] - xa0 * q[3],
                         (1 - xb1) * q[4] + xb1 * q[6] - (1 - xa1) * q[0] - xa1 * q[2],
                         (1 - xb1) * q[5] + xb1 * q[7] - (1 - xa1) * q[1] - xa1 * q[3],
                         inx(sh),
                         iny(sh)};
  }

  /// Energy of interface i (kEnergy) and/or the nodal forces f = -dE/dq (kForce): the law's one
  /// integral along the segment, cohesive::integrate (exact for the law alone, segment.hpp; the
  /// Gauss rule with one history value per point for a damaged joint, damage.hpp), the same the
  /// rigid-brick solver uses. Forces: the end forces dE/dg0, dE/dg1 taken by each edge node with
  /// its shape function's values at the two segment ends (the consistent nodal forces of a
  /// linear jump); the time step needs only the forces, the books only the energy.
  template <bool kEnergy, bool kForce>
  KOKKOS_INLINE_FUNCTION double integrate(int i, double* f) const {
    double q[8];
    load(i, q);
    const int sh = ishape(i);
    const cohesive::Law& m = laws[ikind(sh)];
    const double lt = ilen(sh) * thickness;
    const cohesive::Gap g = gap(i, q);
    const double* kappa = history(i);
    double e = 0;
    if constexpr (kEnergy) e = cohesive::integrate(cohesive::EnergyTag{}, m, quad, g, lt, kappa);
    if constexpr (kForce) {
      const cohesive::EndForces F = cohesive::integrate(cohesive::TractionTag{}, m, quad, g, lt, kappa);
      const double xa0 = ixi(sh, 0), xa1 = ixi(sh, 1), xb0 = ixi(sh, 2), xb1 = ixi(sh, 3);
      f[0] = (1 - xa0) * F.f0x + (1 - xa1) * F.f1x, f[1] = (1 - xa0) * F.f0y + (1 - xa1) * F.f1y;
      f[2] = xa0 * F.f0x + xa1 * F.f1x, f[3] = xa0 * F.f0y + xa1 * F.f1y;
      f[4] = -((1 - xb0) * F.f0x + (1 - xb1) * F.f1x), f[5] = -((1 - xb0) * F.f0y + (1 - xb1) * F.f1y);
      f[6] = -(xb0 * F.f0x + xb1 * F.f1x), f[7] = -(xb0 * F.f0y + xb1 * F.f1y);
    }
    return e;
  }

  KOKKOS_INLINE_FUNCTION double energy(int i) const { return integrate<true, false>(i, nullptr); }

  KOKKOS_INLINE_FUNCTION void operator()(ForceTag, int i) const {
    double f[8];
    integrate<false, true>(i, f);
    for (int k = 0; k < 8; ++k) out(i, k) = f[k];
  }

  /// Largest -dn / x1 of interface i over its quadrature points (its interpenetration).
  KOKKOS_INLINE_FUNCTION double penetration(int i) const {
    double q[8];
    load(i, q);
    const double x1 = laws[ikind(ishape(i))].x1;
    double r = -1e300;
    for (int p = 0; p < quad.n; ++p) {
      double dn, dt, xa, xb;
      jump(i, q, quad.s[p], dn, dt, xa, xb);
      r = Kokkos::max(r, -dn / x1);
    }
    return r;
  }

  /// Raise interface i's history to its separations now (no-op without a history).
  KOKKOS_INLINE_FUNCTION void update_history(int i) const {
    double* kappa = history(i);
    if (!kappa) return;
    double q[8];
    load(i, q);
    cohesive::update_history(quad, gap(i, q), kappa);
  }

  /// Energy interface i has dissipated by damage (0 without a history).
  KOKKOS_INLINE_FUNCTION double dissipated(int i) const {
    const double* kappa = history(i);
    if (!kappa) return 0.0;
    return cohesive::dissipated(laws[ikind(ishape(i))], quad, kappa, ilen(ishape(i)) * thickness);
  }

  /// Damage 0 (elastic) .. 1 (ruptured) = clamp((d_max - x1) / x2); state 0 elastic,
  /// 1 beyond x1 somewhere, 2 ruptured along the whole segment (with a history: or at every one
  /// of its points, which have seen their largest separation).
  KOKKOS_INLINE_FUNCTION void damage(int i, double& dmg, int& state) const {
    double q[8];
    load(i, q);
    const cohesive::Law& m = laws[ikind(ishape(i))];
    const double* kappa = history(i);
    // exact along the segment (cohesive::min_separation / max_separation, as the rigid solver);
    // with a history, what the joint's points have been through
    const cohesive::Gap g = gap(i, q);
    double dmax = cohesive::max_separation(g), dmin = cohesive::min_separation(g);
    if (kappa)
      dmax = Kokkos::max(dmax, cohesive::max_history(kappa, quad.n)),
      dmin = Kokkos::max(dmin, cohesive::min_history(kappa, quad.n));
    dmg = Kokkos::min(1.0, Kokkos::max(0.0, (dmax - m.x1) / m.x2));
    state = dmin >= m.rupture_distance() ? 2 : (dmax > m.x1 ? 1 : 0);
  }
};

/// \brief Velocity Verlet with velocity-dependent acceleration (eq. 4.4), per element.
/// Driven elements follow u = D(t) * pattern, v = D'(t) * pattern, a = D''(t) * pattern and
/// report the force needed to move them (reaction, external work).
template <class MemorySpace>
struct Integrator {
  using CDof = Kokkos::View<const double**, ElemLayout<MemorySpace>, MemorySpace>;
  using CMat = Kokkos::View<const double***, ElemLayout<MemorySpace>, MemorySpace>;
  Kokkos::View<const int*, MemorySpace> type, type_nodes, goff, tile_start, tile_elem, driven, driven_index;
  Kokkos::View<const GatherEntry*, MemorySpace> gent;
  Kokkos::View<const std::int8_t*, MemorySpace> drive;
  Kokkos::View<const double*, MemorySpace> cx, cy;
  CMat K, Ainv;
  CDof mass, theta, fp, node_x, node_y;
  Kokkos::View<const double* [8], ElemLayout<MemorySpace>, MemorySpace> iforce;
  DofView<MemorySpace> u, v, a;
  AccView<MemorySpace> acc;
  DrivenAccView<MemorySpace> dacc;
  int nd, n_tiles, n_driven;
  bool has_fp;
  double h, alpha, beta;
  loading::Pattern load;
  double D = 0, Dd = 0, Ddd = 0;  ///< opening and its rates at the new time
  double D_prev = 0;              ///< opening at the old time

  Integrator(const Model<MemorySpace>& m, const DofView<MemorySpace>& u_, const DofView<MemorySpace>& v_,
             const DofView<MemorySpace>& a_, const AccView<MemorySpace>& acc_, const DrivenAccView<MemorySpace>& dacc_,
             const IforceView<MemorySpace>& f_)
      : type(m.type), type_nodes(m.type_nodes), goff(m.goff), tile_start(m.tile_start), tile_elem(m.tile_elem),
        driven(m.driven), driven_index(m.driven_index), gent(m.gent), drive(m.drive), cx(m.cx), cy(m.cy), K(m.K),
        Ainv(m.Ainv), mass(m.mass), theta(m.theta), fp(m.fp), node_x(m.node_x), node_y(m.node_y), iforce(f_), u(u_),
        v(v_), a(a_), acc(acc_), dacc(dacc_), nd(m.nd), n_tiles(m.n_tiles), n_driven(m.n_driven),
        has_fp(m.fp.extent(0) > 0), h(m.h), alpha(m.alpha), beta(m.beta), load(m.pattern) {}

  /// Prescribed displacement per unit opening of node j of element e: the loading pattern's
  /// displacement at the node (u_y = side/2 [tension + bending (1 - x/W)]) plus the small
  /// rotation of the brick about its centroid that matches the pattern's slope,
  /// u_x = -slope (y - cy): driven bricks move rigidly (as the rigid deck's pose).
  KOKKOS_INLINE_FUNCTION void pattern(int e, int t, int j, double& px, double& py) const {
    const int side = drive(e);
    const double ry = node_y(t, j);
    const int d = driven_index(e);
    load.displacement(side, cx(d) + node_x(t, j), cy(d) + ry, 1.0, px, py);
    px -= load.slope(side, 1.0) * ry;
  }

  KOKKOS_INLINE_FUNCTION void operator()(InitialTag, int e) const {
    if (drive(e) == 0) {
      for (int j = 0; j < nd; ++j) u(e, j) += h * v(e, j) + 0.5 * h * h * a(e, j);
      return;
    }
    const int t = type(e), nn = type_nodes(t);
    for (int j = 0; j < nn; ++j) {
      double px, py;
      pattern(e, t, j, px, py);
      u(e, 2 * j) = D * px, u(e, 2 * j + 1) = D * py;
      v(e, 2 * j) = Dd * px, v(e, 2 * j + 1) = Dd * py;
      a(e, 2 * j) = Ddd * px, a(e, 2 * j + 1) = Ddd * py;
    }
  }

  /// Interface forces on element e, gathered in a fixed order. ND > 0: the element has ND dofs
  /// known at compile time, and each entry's two nodes are matched against every node in an
  /// unrolled loop instead of indexing fi with them, so fi stays in registers on a device; the
  /// same additions in the same order, so the same bits as ND = 0 (the run-time dof count).
  template <int ND = 0>
  KOKKOS_INLINE_FUNCTION void gather(int e, double* fi) const {
    if constexpr (ND > 0) {
      NACRE_DYN_UNROLL
      for (int j = 0; j < ND; ++j) fi[j] = 0;
      for (int k = goff(e); k < goff(e + 1); ++k) {
        const GatherFields g = gather_fields(gent(k));
        const int i = g.iface, side = g.side, n0 = g.n0, n1 = g.n1;
        const double f0x = iforce(i, 4 * side), f0y = iforce(i, 4 * side + 1);
        const double f1x = iforce(i, 4 * side + 2), f1y = iforce(i, 4 * side + 3);
        NACRE_DYN_UNROLL
        for (int n = 0; n < ND / 2; ++n)
          if (n == n0) fi[2 * n] += f0x, fi[2 * n + 1] += f0y;
        NACRE_DYN_UNROLL
        for (int n = 0; n < ND / 2; ++n)
          if (n == n1) fi[2 * n] += f1x, fi[2 * n + 1] += f1y;
      }
    } else {
      for (int j = 0; j < nd; ++j) fi[j] = 0;
      for (int k = goff(e); k < goff(e + 1); ++k) {
        const GatherFields g = gather_fields(gent(k));
        const int i = g.iface, side = g.side, n0 = g.n0, n1 = g.n1;
        fi[2 * n0] += iforce(i, 4 * side), fi[2 * n0 + 1] += iforce(i, 4 * side + 1);
        fi[2 * n1] += iforce(i, 4 * side + 2), fi[2 * n1 + 1] += iforce(i, 4 * side + 3);
      }
    }
  }

  /// End of step of element e: a free element as a lane of final_free (a tile of width 1), a
  /// driven one booked by final_driven.
  /// A free element takes final_one with its dof count fixed at compile time (dispatch_nd), on
  /// every backend: the per-element walk is the GPU's, and on the host (UE, or element_apply =
  /// "per-element") the tests compare it bit for bit with the tiled walk's final_free.
  template <class AinvForm>
  KOKKOS_INLINE_FUNCTION void operator()(FinalTag<AinvForm>, int e) const {
    if (drive(e) != 0) {
      final_driven(e);
      return;
    }
    if (dispatch_nd(nd, [&](auto N) { final_one<AinvForm, decltype(N)::value>(e); })) return;
    final_free<1, AinvForm>(type(e), &e, 1);
  }

  /// final_free of one free element with ND dofs, written for a GPU thread: u and the
  /// half-step velocity w = v + h/2 a are held in registers (every index into them a compile-time
  /// constant), the force / residual and the mid-step velocity are the only rows indexed by the
  /// rolled row loop, and v, a are re-read where a row needs them (coalesced, cached). The same
  /// operations in the same order as final_free, so the same bits. Measured with ptxas -v on
  /// sm_90: final_free<1> with a run-time dof count kept seven dof arrays in a 1 KB stack frame
  /// per thread, beyond L1 at a GPU's occupancy.
  template <class AinvForm, int ND>
  KOKKOS_INLINE_FUNCTION void final_one(int e) const {
    const int t = type(e);
    double f[ND], x[ND], w[ND];
    gather<ND>(e, f);
    double work = 0;
    NACRE_DYN_UNROLL
    for (int j = 0; j < ND; ++j) {
      const double fi = f[j];
      const double fj = fi + theta(t, j) + (has_fp ? fp(e, j) : 0.0);
      x[j] = u(e, j);
      w[j] = v(e, j) + 0.5 * h * a(e, j);
      work += (fj - fi) * w[j];
      f[j] = fj;
    }
    // r = f - K u - alpha M w - beta K w, row by row into f
    NACRE_DYN_ROLLED
    for (int i = 0; i < ND; ++i) {
      double ku = 0, kw = 0;
      NACRE_DYN_UNROLL
      for (int j = 0; j < ND; ++j) ku += K(t, i, j) * x[j];
      if (beta != 0.0) {
        NACRE_DYN_UNROLL
        for (int j = 0; j < ND; ++j) kw += K(t, i, j) * w[j];
      }
      const double am = alpha * mass(t, i);
      f[i] = f[i] - ku - am * (v(e, i) + 0.5 * h * a(e, i)) - beta * kw;
    }
    double vb[ND], pd = 0;
    NACRE_DYN_ROLLED
    for (int i = 0; i < ND; ++i) {
      double an;
      if constexpr (std::is_same_v<AinvForm, AinvDiagonal>) {
        an = Ainv(t, i, i) * f[i];
      } else {
        an = 0;
        NACRE_DYN_UNROLL
        for (int j = 0; j < ND; ++j) an += Ainv(t, i, j) * f[j];
      }
      const double am = alpha * mass(t, i), vo = v(e, i);
      const double vn = vo + 0.5 * h * (a(e, i) + an);
      vb[i] = 0.5 * (vo + vn);
      pd += am * vb[i] * vb[i];
      v(e, i) = vn, a(e, i) = an;  // row i is not read again
    }
    if (beta != 0.0) {
      NACRE_DYN_ROLLED
      for (int i = 0; i < ND; ++i) {
        double kv = 0;
        NACRE_DYN_UNROLL
        for (int j = 0; j < ND; ++j) kv += K(t, i, j) * vb[j];
        pd += beta * vb[i] * kv;
      }
    }
    acc(e, kWork) += h * work;
    acc(e, kDamp) += h * pd;
  }

  /// End of step over the element tiles of Model (work items w >= n_tiles: the driven elements).
  template <class AinvForm>
  KOKKOS_INLINE_FUNCTION void operator()(FinalTileTag<AinvForm>, int w) const {
    if (w >= n_tiles) {
      final_driven(driven(w - n_tiles));
      return;
    }
    const int k0 = tile_start(w);
    final_free<kTile, AinvForm>(type(tile_elem(k0)), tile_elem.data() + k0, tile_start(w + 1) - k0);
  }

  /// The reaction and the work of driven element e.
  KOKKOS_INLINE_FUNCTION void final_driven(int e) const {
    const int t = type(e);
    double f[kMaxDof], fi[kMaxDof];
    gather(e, fi);
    for (int j = 0; j < nd; ++j) f[j] = fi[j] + theta(t, j) + (has_fp ? fp(e, j) : 0.0);
    // Driven: the machine applies M a + C v + K u - F_i - F_p - Theta; with the prescribed loads
    // the external work on the element is int (M a + C v + K u - F_i) . v dt
    //   = change of its kinetic + strain energy + int v^T C v dt - int F_i . du.
    // The first part is booked exactly (an impulsive start or stop of the opening included), the
    // damping part by the trapezoidal rule in time, the interface part by the trapezoidal rule in
    // the opening: du = pattern dD, so int F_i . du = 1/2 (G_n + G_{n+1}) (D_{n+1} - D_n) with
    // G = F_i . pattern.
    double pd = 0, react = 0, en = 0, G = 0;
    for (int i = 0; i < nd; ++i) {
      double ku = 0, kv = 0;
      for (int j = 0; j < nd; ++j) {
        const double k = K(t, i, j);
        ku += k * u(e, j), kv += k * v(e, j);
      }
      const double vi = v(e, i);
      const double cv = alpha * mass(t, i) * vi + beta * kv;
      pd += vi * cv;
      en += 0.5 * (mass(t, i) * vi * vi + u(e, i) * ku);
      if (i % 2 == 1) react += mass(t, i) * a(e, i) + cv + ku - f[i];
    }
    const int nn = type_nodes(t);
    for (int j = 0; j < nn; ++j) {
      double px, py;
      pattern(e, t, j, px, py);
      G += fi[2 * j] * px + fi[2 * j + 1] * py;
    }
    const int d = driven_index(e);
    const double damp = 0.5 * h * (dacc(d, kDampPowPrev) + pd);
    acc(e, kWork) += (en - dacc(d, kEnergyPrev)) + damp - 0.5 * (dacc(d, kGPrev) + G) * (D - D_prev);
    acc(e, kDamp) += damp;
    dacc(d, kEnergyPrev) = en;
    dacc(d, kGPrev) = G;
    dacc(d, kDampPowPrev) = pd;
    dacc(d, kReact) = drive(e) > 0 ? react : 0.0;
  }

  /// final_integrate of the free elements elem[0, nb) of type t, W lanes (lanes >= nb padded:
  /// computed on zeros, never stored). The per-element kernel is the width-1 case, the tiled one
  /// width kTile: one code, so the two are the same bits by construction. The matrix entry is
  /// loaded once per tile and the innermost loops run over the lanes (independent accumulators:
  /// SIMD lanes and no add-latency chain).
  template <int W, class AinvForm>
  KOKKOS_INLINE_FUNCTION void final_free(int t, const int* elem, int nb) const {
    double x[kMaxDof][W], wv[kMaxDof][W], f[kMaxDof][W], r[kMaxDof][W], vo[kMaxDof][W], ao[kMaxDof][W];
    double work[W], pd[W];
    for (int b = 0; b < W; ++b) {
      work[b] = 0, pd[b] = 0;
      if (b >= nb) {
        for (int j = 0; j < nd; ++j) x[j][b] = wv[j][b] = f[j][b] = vo[j][b] = ao[j][b] = 0;
        continue;
      }
      const int e = elem[b];
      double fi[kMaxDof];
      gather(e, fi);
      double wk = 0;
      for (int j = 0; j < nd; ++j) {
        const double fj = fi[j] + theta(t, j) + (has_fp ? fp(e, j) : 0.0);
        x[j][b] = u(e, j);
        vo[j][b] = v(e, j), ao[j][b] = a(e, j);
        wv[j][b] = vo[j][b] + 0.5 * h * ao[j][b];
        wk += (fj - fi[j]) * wv[j][b];
        f[j][b] = fj;
      }
      work[b] = wk;
    }
    for (int i = 0; i < nd; ++i) {
      double ku[W], kw[W];
      for (int b = 0; b < W; ++b) ku[b] = 0, kw[b] = 0;
      for (int j = 0; j < nd; ++j) {
        const double k = K(t, i, j);
        for (int b = 0; b < W; ++b) ku[b] += k * x[j][b];
      }
      if (beta != 0.0)  // else beta * kw = 0 adds nothing
        for (int j = 0; j < nd; ++j) {
          const double k = K(t, i, j);
          for (int b = 0; b < W; ++b) kw[b] += k * wv[j][b];
        }
      const double am = alpha * mass(t, i);
      for (int b = 0; b < W; ++b) r[i][b] = f[i][b] - ku[b] - am * wv[i][b] - beta * kw[b];
    }
    double vb[kMaxDof][W];
    for (int i = 0; i < nd; ++i) {
      double an[W];
      if constexpr (std::is_same_v<
                        AinvForm,
                        AinvDiagonal>) {  // the off-diagonal terms are exact zeros: the sum is this one product
        const double c = Ainv(t, i, i);
        for (int b = 0; b < W; ++b) an[b] = c * r[i][b];
      } else {
        for (int b = 0; b < W; ++b) an[b] = 0;
        for (int j = 0; j < nd; ++j) {
          const double c = Ainv(t, i, j);
          for (int b = 0; b < W; ++b) an[b] += c * r[j][b];
        }
      }
      const double am = alpha * mass(t, i);
      for (int b = 0; b < W; ++b) {
        const double vn = vo[i][b] + 0.5 * h * (ao[i][b] + an[b]);
        vb[i][b] = 0.5 * (vo[i][b] + vn);
        pd[b] += am * vb[i][b] * vb[i][b];
        vo[i][b] = vn, ao[i][b] = an[b];
      }
    }
    if (beta != 0.0)
      for (int i = 0; i < nd; ++i) {
        double kv[W];
        for (int b = 0; b < W; ++b) kv[b] = 0;
        for (int j = 0; j < nd; ++j) {
          const double k = K(t, i, j);
          for (int b = 0; b < W; ++b) kv[b] += k * vb[j][b];
        }
        for (int b = 0; b < W; ++b) pd[b] += beta * vb[i][b] * kv[b];
      }
    for (int b = 0; b < nb; ++b) {
      const int e = elem[b];
      for (int j = 0; j < nd; ++j) v(e, j) = vo[j][b], a(e, j) = ao[j][b];
      acc(e, kWork) += h * work[b];
      acc(e, kDamp) += h * pd[b];
    }
  }
};

/// \brief 1/2 u^T K u of element e.
template <class MemorySpace>
struct StrainEnergy {
  Kokkos::View<const int*, MemorySpace> type;
  Kokkos::View<const double***, ElemLayout<MemorySpace>, MemorySpace> K;
  Kokkos::View<const double**, ElemLayout<MemorySpace>, MemorySpace> u;
  int nd;
  KOKKOS_INLINE_FUNCTION double operator()(int e) const {
    const int t = type(e);
    double s = 0;
    for (int i = 0; i < nd; ++i) {
      double ku = 0;
      for (int j = 0; j < nd; ++j) ku += K(t, i, j) * u(e, j);
      s += u(e, i) * ku;
    }
    return 0.5 * s;
  }
};

/// \brief 1/2 v^T M v of element e (optionally free elements only), and, for the blow-up
/// check, 0 * sum(u^2 + a^2): NaN if any displacement or acceleration is not finite.
template <class MemorySpace>
struct KineticEnergy {
  Kokkos::View<const int*, MemorySpace> type;
  Kokkos::View<const std::int8_t*, MemorySpace> drive;
  Kokkos::View<const double**, ElemLayout<MemorySpace>, MemorySpace> mass, u, v, a;
  int nd;
  bool free_only, poison;
  KOKKOS_INLINE_FUNCTION double operator()(int e) const {
    const int t = type(e);
    double s = 0, z = 0;
    for (int j = 0; j < nd; ++j) {
      s += mass(t, j) * v(e, j) * v(e, j);
      if (poison) z += u(e, j) * u(e, j) + a(e, j) * a(e, j);
    }
    if (free_only && drive(e) != 0) s = 0;
    return 0.5 * s + (poison ? 0.0 * z : 0.0);
  }
};

// ---- launchers: every one takes the execution-space instance it runs on (free functions, so
// CUDA's extended-lambda rules hold: no lambda inside a private member).

template <class ExecutionSpace>
using MemOf = typename ExecutionSpace::memory_space;

/// \brief Driven elements to their prescribed u, v, a (it.D, it.Dd, it.Ddd); free ones untouched.
template <class ExecutionSpace>
void impose_drive(const ExecutionSpace& space, const Integrator<MemOf<ExecutionSpace>>& it, int n_elem) {
  auto drive = it.drive;
  Kokkos::parallel_for("nacre::dyn::impose_drive", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n_elem),
                       KOKKOS_LAMBDA(const int e) {
                         if (drive(e) != 0) it(InitialTag{}, e);
                       });
}

/// \brief How final_integrate walks the free elements: per element (false) or over the element
/// tiles of Model (true; the same bits, Integrator::final_free). A type, chosen once per run.
template <bool Tiled>
using ElementTiles = std::bool_constant<Tiled>;

/// \brief initial_integrate: u_{n+1} of the free elements, the prescribed motion of the driven ones.
template <class ExecutionSpace>
void initial_integrate(const ExecutionSpace& space, const Integrator<MemOf<ExecutionSpace>>& it, int n_elem) {
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::initial_integrate");
  Kokkos::parallel_for("nacre::dyn::initial_integrate",
                       Kokkos::RangePolicy<ExecutionSpace, InitialTag>(space, 0, n_elem), it);
}

/// \brief The interface force at u_{n+1} (one row of op.out per interface); on ranks, after the
/// halo's u came from its owners (halo.hpp).
template <class ExecutionSpace>
void force(const ExecutionSpace& space, const InterfaceOp<MemOf<ExecutionSpace>>& op, int n_iface) {
  NACRE_ASSERT(op.out.extent(0) >= std::size_t(n_iface), "force: a force row per interface");
  if (op.halo) op.halo->exchange(space);
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::interface_force");
  Kokkos::parallel_for("nacre::dyn::interface_force", Kokkos::RangePolicy<ExecutionSpace, ForceTag>(space, 0, n_iface),
                       op);
}

/// \brief final_integrate: v_{n+1}, a_{n+1} and the books, per element or over the tiles.
template <class ExecutionSpace, bool Tiled, class AinvForm>
void final_integrate(const ExecutionSpace& space, ElementTiles<Tiled>, AinvForm,
                     const Integrator<MemOf<ExecutionSpace>>& it, int n_elem) {
  Kokkos::Profiling::ScopedRegion r("nacre::dyn::final_integrate");
  if constexpr (Tiled)
    Kokkos::parallel_for(
        "nacre::dyn::final_integrate_tiled",
        Kokkos::RangePolicy<ExecutionSpace, FinalTileTag<AinvForm>>(space, 0, it.n_tiles + it.n_driven), it);
  else
    Kokkos::parallel_for("nacre::dyn::final_integrate",
                         Kokkos::RangePolicy<ExecutionSpace, FinalTag<AinvForm>>(space, 0, n_elem), it);
}

/// \brief One velocity-Verlet step (UE, BE): initial_integrate, force, final_integrate.
template <class ExecutionSpace, bool Tiled, class AinvForm>
void verlet_step(const ExecutionSpace& space, ElementTiles<Tiled> tiles, AinvForm ainv,
                 const Integrator<MemOf<ExecutionSpace>>& it, const InterfaceOp<MemOf<ExecutionSpace>>& op, int n_elem,
                 int n_iface) {
  initial_integrate(space, it, n_elem);
  force(space, op, n_iface);
  final_integrate(space, tiles, ainv, it, n_elem);
}

/// \brief Sum of one accumulator column over the first n rows (deterministic): AccView over
/// the elements or DrivenAccView over the driven elements; on ranks the rows of `mask` (empty:
/// all), combined by `combine` (par::Reduce: the one-process bits).
template <class ExecutionSpace, class View, class Combine = sum::Local>
double column_sum(const ExecutionSpace& space, SumWorkspace<MemOf<ExecutionSpace>>& ws, const View& acc, int col, int n,
                  const Kokkos::View<std::uint8_t*, MemOf<ExecutionSpace>>& mask = {}, const Combine& combine = {}) {
  static_assert(Kokkos::SpaceAccessibility<ExecutionSpace, typename View::memory_space>::accessible);
  const auto term = KOKKOS_LAMBDA(const int e) { return acc(e, col); };
  return deterministic_sum(space, "nacre::dyn::sum_acc", ws, 0, n, owned_term(mask, term), combine);
}

/// \brief Total cohesive energy (deterministic; mask and combine as column_sum's).
template <class ExecutionSpace, class Combine = sum::Local>
double cohesive_energy(const ExecutionSpace& space, SumWorkspace<MemOf<ExecutionSpace>>& ws,
                       const InterfaceOp<MemOf<ExecutionSpace>>& op, int n_iface,
                       const Kokkos::View<std::uint8_t*, MemOf<ExecutionSpace>>& mask = {},
                       const Combine& combine = {}) {
  const auto term = KOKKOS_LAMBDA(const int i) { return op.energy(i); };
  return deterministic_sum(space, "nacre::dyn::cohesive_energy", ws, 0, n_iface, owned_term(mask, term), combine);
}

/// \brief Sum of a per-element term functor (strain or kinetic energy), deterministic (mask and
/// combine as column_sum's).
template <class ExecutionSpace, class Term, class Combine = sum::Local>
double element_sum(const ExecutionSpace& space, SumWorkspace<MemOf<ExecutionSpace>>& ws, const Term& term, int n_elem,
                   const Kokkos::View<std::uint8_t*, MemOf<ExecutionSpace>>& mask = {}, const Combine& combine = {}) {
  return deterministic_sum(space, "nacre::dyn::element_sum", ws, 0, n_elem, owned_term(mask, term), combine);
}

/// \brief acc(e, kWork) = term(e) and, for a driven element, its kEnergyPrev = term(e): the
/// energy the start gives an element (the kinetic energy of driven elements set moving at t = 0)
/// is booked as work.
template <class ExecutionSpace, class Term>
void set_initial_work(const ExecutionSpace& space, const Integrator<MemOf<ExecutionSpace>>& it, const Term& term,
                      int n_elem) {
  const auto acc = it.acc;
  const auto dacc = it.dacc;
  const auto drive = it.drive;
  const auto driven_index = it.driven_index;
  Kokkos::parallel_for("nacre::dyn::initial_work", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n_elem),
                       KOKKOS_LAMBDA(const int e) {
                         const double w = term(e);
                         acc(e, kWork) = w;
                         if (drive(e) != 0) dacc(driven_index(e), kEnergyPrev) = w;
                       });
}

/// \brief Number of ruptured interfaces among [0, n) (integer reduction: exact), those of `mask`
/// where it is not empty.
template <class ExecutionSpace>
int count_ruptured(const ExecutionSpace& space, const InterfaceOp<MemOf<ExecutionSpace>>& op, int n,
                   const Kokkos::View<std::uint8_t*, MemOf<ExecutionSpace>>& mask = {}) {
  int c = 0;
  Kokkos::parallel_reduce(
      "nacre::dyn::count_ruptured", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
      KOKKOS_LAMBDA(const int i, int& acc) {
        if (mask.data() && mask(i) == 0) return;
        double d;
        int st;
        op.damage(i, d, st);
        acc += st == 2;
      },
      c);
  return c;
}

/// \brief Largest penetration of interfaces [0, n) relative to their law's x1, max over the
/// quadrature points of -dn / x1 (0 when nothing penetrates): the interpenetration penalty
/// g(dn) = k dn^6 / (16 x1^4) stiffens the joint to k (1 + 1.875 (dn / x1)^4), which lowers the
/// explicit interface part's stable step like 1 / sqrt of that (docs/methods.md).
template <class ExecutionSpace>
double max_penetration(const ExecutionSpace& space, const InterfaceOp<MemOf<ExecutionSpace>>& op, int n) {
  double r = 0;
  Kokkos::parallel_reduce(
      "nacre::dyn::max_penetration", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
      KOKKOS_LAMBDA(const int i, double& acc) { acc = Kokkos::max(acc, op.penetration(i)); }, Kokkos::Max<double>(r));
  return r;
}

/// \brief Raise the damage history of interfaces [0, n) to their separations now (after every
/// step; nothing without a history).
template <class ExecutionSpace>
void update_history(const ExecutionSpace& space, const InterfaceOp<MemOf<ExecutionSpace>>& op, int n) {
  if (!op.hist.data()) return;
  NACRE_ASSERT(op.hist.extent(0) >= std::size_t(n) && op.hist.extent(1) == std::size_t(op.quad.n),
               "update_history: a history row of quad.n values per bed/head interface");
  Kokkos::parallel_for(
      "nacre::dyn::update_history", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
      KOKKOS_LAMBDA(const int i) { op.update_history(i); });
}

/// \brief Damage and state of interfaces [0, n), and where `energy` is allocated (an empty
/// View: not computed) their energy of fracture: the energy dissipated by damage with a history,
/// else the cohesive energy (the reversible law's stand-in).
template <class ExecutionSpace>
void interface_damage(const ExecutionSpace& space, const InterfaceOp<MemOf<ExecutionSpace>>& op, int n,
                      const Kokkos::View<double*, MemOf<ExecutionSpace>>& dmg,
                      const Kokkos::View<int*, MemOf<ExecutionSpace>>& state,
                      const Kokkos::View<double*, MemOf<ExecutionSpace>>& energy = {}) {
  NACRE_ASSERT(dmg.extent(0) >= std::size_t(n) && state.extent(0) >= std::size_t(n) &&
                   (!energy.data() || energy.extent(0) >= std::size_t(n)),
               "interface_damage: a value per interface in every output");
  Kokkos::parallel_for("nacre::dyn::damage", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
                       KOKKOS_LAMBDA(const int i) {
                         double d;
                         int q;
                         op.damage(i, d, q);
                         dmg(i) = d, state(i) = q;
                         if (energy.data()) energy(i) = op.history(i) ? op.dissipated(i) : op.energy(i);
                       });
}

}  // namespace nacre::dyn
