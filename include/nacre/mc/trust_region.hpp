// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Trust-region Newton-CG (Steihaug) on the exact rigid-brick energy: the quasi-static
/// minimiser of relaxation = "newton" (and of polish = "trust-region").
///
/// Why this method: a load step's relaxation is a minimisation of a smooth-but-kinked energy
/// whose Hessian is indefinite on softening branches. Newton's direction with the exact H v
/// (hessian.hpp) converges in tens of iterations where FIRE takes thousands; the trust region
/// (in the block-Jacobi norm) makes it safe on negative curvature: Steihaug's CG stops at the
/// boundary along a direction of negative curvature or when the step leaves the region, and the
/// ratio of actual to predicted decrease (the energy change summed interface by interface, as
/// FIRE's test) grows or shrinks the region. Preconditioner (PolishOptions::preconditioner): on
/// host memory the sparse Cholesky factor of the whole exact Hessian, shifted where indefinite
/// (hessian_factor.hpp: a few CG iterations per Newton step); else (devices, or asked) the 3x3
/// diagonal block of each brick (exact, hessian_blocks), inverted where positive definite, else
/// its diagonal magnitudes with a floor (a brick whose joints are all ruptured has none).
/// Every sum is a deterministic_sum: the same bits on 1 and 2 threads and on every backend.
/// Spread over ranks (distribute(): a rank's model of its owned bricks and their halo) each rank
/// holds its free bricks' rows, sums its own terms and interfaces over the ranks, takes its
/// halo's poses after each move and its halo's rows of a vector before each H v from their
/// owners, and the Cholesky factor lives on rank 0 (hessian_factor.hpp): the bits of one process.
#include <nacre/core/deterministic_sum.hpp>
#include <nacre/mc/halo.hpp>
#include <nacre/mc/hessian.hpp>
#include <nacre/mc/hessian_factor.hpp>
#include <nacre/mc/polish_types.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

namespace nacre::mc {

namespace detail {
/// Block b of a BlockView as a symmetric 3x3 and its Cholesky-based inverse, or (not positive
/// definite) the inverse of max(|diagonal|, floor): written to inv as (xx, yy, tt, xy, xt, yt).
KOKKOS_INLINE_FUNCTION void block_inverse(const double h[6], const double floor[3], double inv[6]) {
  const double a = h[0], d = h[1], f = h[2], b = h[3], c = h[4], e = h[5];  // [[a b c][b d e][c e f]]
  const double c0 = d * f - e * e, c1 = c * e - b * f, c2 = b * e - c * d;  // cofactors of row 0
  const double det = a * c0 + b * c1 + c * c2;
  const bool spd = a > floor[0] && a * d - b * b > floor[0] * floor[1] && det > floor[0] * floor[1] * floor[2];
  if (spd) {
    const double r = 1.0 / det;
    inv[0] = c0 * r, inv[1] = (a * f - c * c) * r, inv[2] = (a * d - b * b) * r;
    inv[3] = c1 * r, inv[4] = c2 * r, inv[5] = (b * c - a * e) * r;
  } else {
    inv[0] = 1.0 / Kokkos::fmax(Kokkos::fabs(a), floor[0]);
    inv[1] = 1.0 / Kokkos::fmax(Kokkos::fabs(d), floor[1]);
    inv[2] = 1.0 / Kokkos::fmax(Kokkos::fabs(f), floor[2]);
    inv[3] = inv[4] = inv[5] = 0.0;
  }
}
}  // namespace detail

/// \brief The work vectors of the method and the method itself, on one execution space.
template <class ExecutionSpace>
class TrustRegion {
public:
  /// the model's and the work vectors' memory: the execution space's own
  using Mem = MemOf<ExecutionSpace>;
  TrustRegion() = default;
  TrustRegion(const ExecutionSpace& space, const Model<Mem>& m, NewtonPreconditioner pc,
              FactorPrecision precision = FactorPrecision::single) {
    const int n_free = m.n_free;
    using Kokkos::view_alloc, Kokkos::WithoutInitializing;
    const auto nf = static_cast<std::size_t>(n_free);
    auto vec = [&](const char* label) {
      return GradientView<Mem>(view_alloc(space, WithoutInitializing, std::string(label)), nf);
    };
    // the step and the CG direction get H v: a row per model brick (a rank's halo rows come
    // from their owners; one process reads only the free rows). Zeroed: the rows of driven
    // bricks are never written but travel in the halo messages (the receivers' mask skips them)
    const auto nb = static_cast<std::size_t>(m.n_bricks);
    step_ = GradientView<Mem>(view_alloc(space, std::string("nacre::mc::newton::step")), nb);
    d_ = GradientView<Mem>(view_alloc(space, std::string("nacre::mc::newton::direction")), nb);
    r_ = vec("nacre::mc::newton::residual"), y_ = vec("nacre::mc::newton::preconditioned");
    hd_ = vec("nacre::mc::newton::h_direction"), save_ = vec("nacre::mc::newton::save");
    minv_ = BlockView<Mem>(view_alloc(space, WithoutInitializing, "nacre::mc::newton::block_inverse"), nf);
    mblk_ = BlockView<Mem>(view_alloc(space, WithoutInitializing, "nacre::mc::newton::blocks"), nf);
    md_ = vec("nacre::mc::newton::m_direction");
    tangents_ = TangentView<Mem>(view_alloc(space, WithoutInitializing, "nacre::mc::newton::interface_tangents"),
                                 static_cast<std::size_t>(m.n_interfaces));
    trig_ = TrigView<Mem>(view_alloc(space, WithoutInitializing, std::string("nacre::mc::newton::brick_trig")), nb);
    constexpr bool host = std::is_same_v<Mem, Kokkos::HostSpace>;
    if (pc == NewtonPreconditioner::cholesky && !host)
      throw std::invalid_argument(
          "newton_preconditioner = \"cholesky\" needs host memory (this backend keeps its model "
          "on a device); expected \"block-jacobi\" or \"auto\"");
    if (pc == NewtonPreconditioner::cholesky || (pc == NewtonPreconditioner::automatic && host)) {
      const bool single = precision == FactorPrecision::single;
      factor_ = std::make_shared<HessianFactor>(single);
      ref_factor_ = std::make_shared<HessianFactor>(single);
      slots_ = SlotBlockView<Mem>(view_alloc(space, WithoutInitializing, std::string("nacre::mc::newton::slot_blocks")),
                                  static_cast<std::size_t>(m.adj_iface.extent(0)));
    }
  }

  /// \brief Minimise from the current poses until the residual (gradient.hpp) is below
  /// o.tolerance, o.max_iterations Newton steps are spent, or the trust radius collapses
  /// (a stall: result not converged). `grad` is the caller's gradient View (written: the final
  /// gradient), e / trial two per-interface energy Views, ws a sum workspace.
  PolishResult run(const ExecutionSpace& space, const Model<Mem>& m, const ResidualScale& scale, const PolishOptions& o,
                   const GradientView<Mem>& grad, Field<double, Mem>& e, Field<double, Mem>& trial,
                   SumWorkspace<Mem>& ws);

  /// \brief Work on a rank's part of a specimen (null: the whole one in this process); before
  /// the first run().
  void distribute(const Distribution<Mem>* d) {
    dist_ = d;
    if (d && factor_) factor_->distribute(d->comm, d->global_free), ref_factor_->distribute(d->comm, d->global_free);
  }

  // ---- the building blocks (public: nvcc needs the enclosing function of a device lambda public)
  /// a . b over the free bricks (deterministic)
  double dot(const ExecutionSpace& space, SumWorkspace<Mem>& ws, const GradientView<Mem>& a, const GradientView<Mem>& b,
             int nf) const;
  /// What Steihaug-CG returns besides the step s (step_).
  struct Steihaug {
    int iterations = 0;        ///< CG iterations (H v products)
    bool on_boundary = false;  ///< s ends on the trust region's boundary
    bool negative = false;     ///< it met a direction of negative (or no) curvature
    double snorm2 = 0.0;       ///< ||s||_M^2
    double model = 0.0;        ///< q(s) = g.s + s.H s / 2, the model's change (<= 0)
  };
  /// Steihaug-CG for H s = -g inside ||s||_M <= radius. ||s||_M and q(s) come from CG's own
  /// recurrences (Conn, Gould & Toint, Trust-Region Methods, 7.5.1: s.M d and d.M d from r.y
  /// and beta; q falls by alpha r.y / 2 a step), so neither an M product per iteration nor an H s
  /// after it is needed. minv_g: M^-1 g where the caller has it (minv_norm2 with the factor).
  Steihaug steihaug(const ExecutionSpace& space, const Model<Mem>& m, const GradientView<Mem>& g, double radius,
                    double eta, int max_cg, SumWorkspace<Mem>& ws, const GradientView<Mem>& minv_g = {});
  /// z += tau d
  void add_scaled(const ExecutionSpace& space, const GradientView<Mem>& z, const GradientView<Mem>& d, double tau,
                  int nf) const;
  /// ||g||_{M^-1}^2 with the current preconditioner (with the factor, M^-1 g is left in md_)
  double minv_norm2(const ExecutionSpace& space, SumWorkspace<Mem>& ws, const GradientView<Mem>& g, int nf) const;
  /// 4 eps sum |e(i)|: the rounding of an energy change summed as per-interface differences
  double rounding_of(const ExecutionSpace& space, SumWorkspace<Mem>& ws, const Field<double, Mem>& e, int ni) const;
  /// sum over interfaces of (energy at the poses now - e(i)), the energies now into trial
  double energy_change(const ExecutionSpace& space, SumWorkspace<Mem>& ws, const InterfaceEvaluator<Mem>& ev,
                       const Field<double, Mem>& e, const Field<double, Mem>& trial, int ni) const;
  /// the preconditioner from the Hessian at the current poses (floors: translation, rotation);
  /// `indefinite`: H is likely indefinite (the factor's shift search skips sigma = 0)
  void precondition(const ExecutionSpace& space, const Model<Mem>& m, double floor_t, double floor_r,
                    bool indefinite = false);
  /// y = M^-1 r
  void precondition_apply(const ExecutionSpace& space, const GradientView<Mem>& r, const GradientView<Mem>& y,
                          int nf) const;
  /// the residual of grad (the largest over the ranks)
  double residual_now(const ExecutionSpace& space, const GradientView<Mem>& grad, int nf,
                      const ResidualScale& scale) const;
  /// v's halo rows from their owners (v: a row per model brick); nothing on one process
  void halo_rows(const ExecutionSpace& space, const GradientView<Mem>& v) const;
  /// the poses of the halo from their owners after a move; nothing on one process
  void refresh(const ExecutionSpace& space, const Model<Mem>& m) const {
    if (dist_) dist_->refresh(space, m);
  }
  /// whether the preconditioner is a Cholesky factor (else block-Jacobi)
  [[nodiscard]] bool has_factor() const { return factor_ != nullptr; }
  /// the step of the last steihaug() (a row per model brick)
  [[nodiscard]] const GradientView<Mem>& step() const { return step_; }
  /// the relative shift of the last Cholesky factor (0: H was positive definite, or block-Jacobi)
  [[nodiscard]] double shift() const { return active_ ? active_->shift() : 0.0; }
  /// make the factor of the Hessian at zero poses (every joint elastic: the stiffness of the
  /// intact wall, state-independent) the active preconditioner, factorising it on first use
  void reference_factor(const ExecutionSpace& space, const Model<Mem>& m, double floor_t, double floor_r);

private:
  [[nodiscard]] par::Reduce over(long long owned) const { return reduce_over(dist_, owned); }
  [[nodiscard]] FreeMask<Mem> mask() const { return dist_ ? FreeMask<Mem>(dist_->brick_free) : FreeMask<Mem>(); }
  const Distribution<Mem>* dist_ = nullptr;
  GradientView<Mem> step_, r_, y_, d_, hd_, save_, md_;
  BlockView<Mem> minv_, mblk_;
  std::shared_ptr<HessianFactor> factor_;      ///< Cholesky of H at a current state (null: block-Jacobi)
  std::shared_ptr<HessianFactor> ref_factor_;  ///< Cholesky of H at zero poses (the intact wall)
  HessianFactor* active_ = nullptr;            ///< the one preconditioning now
  bool ref_ready_ = false;
  static constexpr int kRefactorCg = 8;  ///< CG iterations above which the factor is renewed
  /// fractions 1/2, 1/4, ..., 1/256 of a rejected step tried (one energy pass each). 3 (down to
  /// 1/8) until 2026-12-05: a step that failed there was rejected whole and the next Newton step
  /// ran the same CG to a quarter of the radius, mostly to be taken at a fraction of that
  /// (measured on the 20k-brick reference path: 21 rejections -> 1, 622 -> 603 Newton steps)
  static constexpr int kBacktracks = 8;
  static constexpr double kEtaMax = 0.05;  ///< loosest CG forcing term (the first Newton step)
  /// The region's first radius, in units of the preconditioned gradient's M-norm (the Newton
  /// step's length where M = H), and its growth where a step on the boundary met the model within
  /// 10 % (rho in 0.9..1.1; 2x elsewhere above 0.75). Before 2026-12-06 1 and 2: 126 of the 484
  /// Newton steps on the 20k-brick reference path were cut by the radius at rho within 10 % of 1
  /// (the first step of a load step with the stale factor, and each doubling after a rupture).
  /// With 2 and 4: 484 -> 407 Newton steps, 1,879 -> 1,724 CG iterations there, 251 -> 212 and
  /// 272 -> 225 on the adaptive "newton" and "auto" paths, the same end states (47 ruptures, the
  /// same energy); the default deck 707 -> 730 Newton steps with eq. 2.11's predictor, 687 with the
  /// secant it now names, its end state unchanged. Taken singly
  /// (measured): growth 4 alone sent the adaptive paths to a higher branch (48 ruptures, E 0.30858
  /// against 0.30808), start 2 alone ended the reference path in another state; 8x growth arrested
  /// the reference path at 35 ruptures (docs/speed_accuracy.md)
  static constexpr double kRadiusStart = 2.0;
  static constexpr double kGrowExact = 4.0;
  int last_cg_ = 0;                      ///< CG iterations of the last Newton step
  bool last_negative_ = false;           ///< the last Newton step's CG met negative curvature
  SlotBlockView<Mem> slots_;
  TangentView<Mem> tangents_;  ///< H v's per-interface pass
  TrigView<Mem> trig_;         ///< the poses' sines and cosines (brick_trig) for H v and the Hessian's blocks
};

// ---------------------------------------------------------------------------------- kernels

template <class ExecutionSpace>
double TrustRegion<ExecutionSpace>::dot(const ExecutionSpace& space, SumWorkspace<Mem>& ws, const GradientView<Mem>& a,
                                        const GradientView<Mem>& b, int nf) const {
  return deterministic_sum(
      space, "nacre::mc::newton::dot", ws, 0, nf,
      KOKKOS_LAMBDA(const int i) { return a(i, 0) * b(i, 0) + a(i, 1) * b(i, 1) + a(i, 2) * b(i, 2); }, over(nf));
}

template <class ExecutionSpace>
void TrustRegion<ExecutionSpace>::add_scaled(const ExecutionSpace& space, const GradientView<Mem>& z,
                                             const GradientView<Mem>& d, double tau, int nf) const {
  Kokkos::parallel_for(
      "nacre::mc::newton::add_scaled", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf), KOKKOS_LAMBDA(const int i) {
        for (int k = 0; k < 3; ++k) z(i, k) += tau * d(i, k);
      });
}

template <class ExecutionSpace>
double TrustRegion<ExecutionSpace>::minv_norm2(const ExecutionSpace& space, SumWorkspace<Mem>& ws,
                                               const GradientView<Mem>& g, int nf) const {
  if (factor_) {
    precondition_apply(space, g, md_, nf);
    return dot(space, ws, g, md_, nf);
  }
  auto Minv = minv_;
  return deterministic_sum(
      space, "nacre::mc::newton::gnorm", ws, 0, nf,
      KOKKOS_LAMBDA(const int i) {
        const double a = g(i, 0), b = g(i, 1), c = g(i, 2);
        return a * (Minv(i, 0) * a + Minv(i, 3) * b + Minv(i, 4) * c) +
               b * (Minv(i, 3) * a + Minv(i, 1) * b + Minv(i, 5) * c) +
               c * (Minv(i, 4) * a + Minv(i, 5) * b + Minv(i, 2) * c);
      },
      over(nf));
}

template <class ExecutionSpace>
double TrustRegion<ExecutionSpace>::rounding_of(const ExecutionSpace& space, SumWorkspace<Mem>& ws,
                                                const Field<double, Mem>& e, int ni) const {
  const auto own = owned_mask(dist_);  // interfaces summed by their owner only
  const long long owned = owned_interfaces(dist_, ni);
  return 4 * DBL_EPSILON *
         deterministic_sum(
             space, "nacre::mc::newton::energy_scale", ws, 0, ni,
             KOKKOS_LAMBDA(const int i) { return own.data() && !own(i) ? 0.0 : Kokkos::abs(e(i)); }, over(owned));
}

template <class ExecutionSpace>
double TrustRegion<ExecutionSpace>::energy_change(const ExecutionSpace& space, SumWorkspace<Mem>& ws,
                                                  const InterfaceEvaluator<Mem>& ev, const Field<double, Mem>& e,
                                                  const Field<double, Mem>& trial, int ni) const {
  const auto own = owned_mask(dist_);
  const long long owned = owned_interfaces(dist_, ni);
  return deterministic_sum(
      space, "nacre::mc::newton::energy_change", ws, 0, ni,
      KOKKOS_LAMBDA(const int i) {
        const double v = ev.energy(i);
        trial(i) = v;
        return own.data() && !own(i) ? 0.0 : v - e(i);
      },
      over(owned));
}

template <class ExecutionSpace>
void TrustRegion<ExecutionSpace>::precondition(const ExecutionSpace& space, const Model<Mem>& m, double floor_t,
                                               double floor_r, bool indefinite) {
  brick_trig(space, m, trig_);
  hessian_blocks(space, m, mblk_, trig_);
  if (factor_) {
    hessian_slots(space, m, slots_, mask(), trig_);
    space.fence("nacre::mc::newton::factor");
    factor_->factor(m, mblk_, slots_, floor_t, floor_r, indefinite);
    active_ = factor_.get();
    return;
  }
  auto M = mblk_, Minv = minv_;
  Kokkos::parallel_for(
      "nacre::mc::newton::block_inverse", Kokkos::RangePolicy<ExecutionSpace>(space, 0, m.n_free),
      KOKKOS_LAMBDA(const int i) {
        double h[6], inv[6];
        for (int k = 0; k < 6; ++k) h[k] = M(i, k);
        const double fl[3] = {floor_t, floor_t, floor_r};
        detail::block_inverse(h, fl, inv);
        // (the trust region's norm is this operator's: the block where Cholesky succeeded, the
        // floored diagonal otherwise; Steihaug's recurrences need only its inverse)
        for (int k = 0; k < 6; ++k) Minv(i, k) = inv[k];
      });
}

template <class ExecutionSpace>
double TrustRegion<ExecutionSpace>::residual_now(const ExecutionSpace& space, const GradientView<Mem>& grad, int nf,
                                                 const ResidualScale& scale) const {
  return max_over(dist_, residual_of(space, grad, nf, scale));
}

template <class ExecutionSpace>
void TrustRegion<ExecutionSpace>::halo_rows(const ExecutionSpace& space, const GradientView<Mem>& v) const {
  if (dist_) dist_->halo->exchange_rows(space, dist_->comm, v, 3);
}

template <class ExecutionSpace>
void TrustRegion<ExecutionSpace>::reference_factor(const ExecutionSpace& space, const Model<Mem>& m, double floor_t,
                                                   double floor_r) {
  if (!ref_ready_) {
    Model<Mem> m0 = m;  // the same interfaces, every brick at its reference pose
    m0.pose = typename Model<Mem>::PoseView(Kokkos::view_alloc(space, std::string("nacre::mc::newton::reference_pose")),
                                            static_cast<std::size_t>(m.n_bricks));
    const auto trig0 = brick_trig(space, m0);
    hessian_blocks(space, m0, mblk_, trig0);
    hessian_slots(space, m0, slots_, mask(), trig0);
    space.fence("nacre::mc::newton::reference_factor");
    ref_factor_->factor(m0, mblk_, slots_, floor_t, floor_r);
    ref_ready_ = true;
  }
  active_ = ref_factor_.get();
}

template <class ExecutionSpace>
void TrustRegion<ExecutionSpace>::precondition_apply(const ExecutionSpace& space, const GradientView<Mem>& r,
                                                     const GradientView<Mem>& y, int nf) const {
  if (factor_) {
    space.fence("nacre::mc::newton::solve");
    active_->solve(r, y);
    return;
  }
  auto Minv = minv_;
  Kokkos::parallel_for(
      "nacre::mc::newton::block_apply", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf), KOKKOS_LAMBDA(const int i) {
        const double r0 = r(i, 0), r1 = r(i, 1), r2 = r(i, 2);
        y(i, 0) = Minv(i, 0) * r0 + Minv(i, 3) * r1 + Minv(i, 4) * r2;
        y(i, 1) = Minv(i, 3) * r0 + Minv(i, 1) * r1 + Minv(i, 5) * r2;
        y(i, 2) = Minv(i, 4) * r0 + Minv(i, 5) * r1 + Minv(i, 2) * r2;
      });
}

namespace detail {
/// tau >= 0 with ||z + tau d||_M = radius, from zMz, zMd, dMd
inline double to_boundary(double zz, double zd, double dd, double radius) {
  if (!(dd > 0.0)) return 0.0;
  const double disc = std::max(0.0, zd * zd + dd * (radius * radius - zz));
  return (-zd + std::sqrt(disc)) / dd;
}
}  // namespace detail

template <class ExecutionSpace>
typename TrustRegion<ExecutionSpace>::Steihaug TrustRegion<ExecutionSpace>::steihaug(
    const ExecutionSpace& space, const Model<Mem>& m, const GradientView<Mem>& g, double radius, double eta, int max_cg,
    SumWorkspace<Mem>& ws, const GradientView<Mem>& minv_g) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::newton::cg");
  const int nf = m.n_free;
  auto z = step_, r = r_, y = y_, d = d_, hd = hd_;
  // z = 0, r = g, y = M^-1 r, d = -y
  Kokkos::parallel_for(
      "nacre::mc::newton::cg_start", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf), KOKKOS_LAMBDA(const int i) {
        z(i, 0) = z(i, 1) = z(i, 2) = 0.0;
        r(i, 0) = g(i, 0), r(i, 1) = g(i, 1), r(i, 2) = g(i, 2);
      });
  if (minv_g.data())  // the caller's M^-1 g: the same bits as solving again
    Kokkos::deep_copy(space, y, minv_g);
  else
    precondition_apply(space, r, y, nf);
  Kokkos::parallel_for(
      "nacre::mc::newton::cg_first_direction", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf),
      KOKKOS_LAMBDA(const int i) { d(i, 0) = -y(i, 0), d(i, 1) = -y(i, 1), d(i, 2) = -y(i, 2); });
  brick_trig(space, m, trig_);  // once for every product below (the poses hold still)
  Steihaug out;
  double ry = dot(space, ws, r, y, nf);
  const double stop = eta * eta * ry;  // ||r||_{M^-1}^2 <= eta^2 ||g||_{M^-1}^2
  // ||z||_M^2, z.M d, d.M d and q(z) by recurrence: r_k.d_j = 0 for j < k and r_k.d_k = -r_k.y_k,
  // so d.M d <- r.y + beta^2 d.M d, z.M d <- beta (z.M d + alpha d.M d), q <- q - alpha r.y / 2
  double zz = 0.0, zd = 0.0, dd = ry, q = 0.0;
  auto finish_on_boundary = [&](double dhd) {  // z + tau d on the boundary; q along d: -tau r.y + tau^2 dHd / 2
    const double tau = detail::to_boundary(zz, zd, dd, radius);
    add_scaled(space, z, d, tau, nf);
    zz += 2.0 * tau * zd + tau * tau * dd;
    q += -tau * ry + 0.5 * tau * tau * dhd;
    out.on_boundary = true;
  };
  while (out.iterations < max_cg && ry > stop) {
    ++out.iterations;
    halo_rows(space, d);
    hessian_vector(space, m, d, hd, mask(), tangents_, trig_);
    const double dhd = dot(space, ws, d, hd, nf);
    if (!(dhd > 0.0)) {  // negative (or no) curvature: follow d to the boundary
      out.negative = true;
      finish_on_boundary(dhd);
      break;
    }
    const double alpha = ry / dhd;
    const double zz_next = zz + 2.0 * alpha * zd + alpha * alpha * dd;
    if (zz_next >= radius * radius) {  // the step leaves the region: stop on its boundary
      finish_on_boundary(dhd);
      break;
    }
    Kokkos::parallel_for(
        "nacre::mc::newton::cg_update", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf), KOKKOS_LAMBDA(const int i) {
          for (int k = 0; k < 3; ++k) z(i, k) += alpha * d(i, k), r(i, k) += alpha * hd(i, k);
        });
    precondition_apply(space, r, y, nf);
    zz = zz_next;
    q -= 0.5 * alpha * ry;
    const double ry_next = dot(space, ws, r, y, nf);
    const double beta = ry_next / ry;
    zd = beta * (zd + alpha * dd);
    dd = ry_next + beta * beta * dd;
    ry = ry_next;
    Kokkos::parallel_for(
        "nacre::mc::newton::cg_direction", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf),
        KOKKOS_LAMBDA(const int i) {
          for (int k = 0; k < 3; ++k) d(i, k) = -y(i, k) + beta * d(i, k);
        });
  }
  out.snorm2 = zz;
  out.model = q;
  return out;
}

template <class ExecutionSpace>
PolishResult TrustRegion<ExecutionSpace>::run(const ExecutionSpace& space, const Model<Mem>& m,
                                              const ResidualScale& scale, const PolishOptions& o,
                                              const GradientView<Mem>& grad, Field<double, Mem>& e,
                                              Field<double, Mem>& trial, SumWorkspace<Mem>& ws) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::polish_trust_region");
  const int nf = m.n_free, ni = m.n_interfaces;
  const InterfaceEvaluator<Mem> ev(m);
  auto pose = m.pose;
  auto z = step_, save = save_;
  // floors of the preconditioner: a brick's stiffness K (translations) and K l^2 (rotation),
  // times 1e-8 (a floppy brick moves at most ~1e8 x its force / K per CG step; the trust region
  // bounds the step anyway)
  const double l = o.rotation_length;
  const double floor_t = 1e-8 * o.stiffness, floor_r = 1e-8 * o.stiffness * l * l;
  {
    auto en = e;
    Kokkos::parallel_for(
        "nacre::mc::newton::interface_energy", Kokkos::RangePolicy<ExecutionSpace>(space, 0, ni),
        KOKKOS_LAMBDA(const int i) { en(i) = ev.energy(i); });
  }
  double rounding = rounding_of(space, ws, e, ni);
  last_cg_ = 0;
  last_negative_ = false;
  if (factor_) {
    // the shift search's memory is the step's own: a run restarted between load steps
    // preconditions as the original did
    factor_->forget_shift();
    reference_factor(space, m, floor_t, floor_r);
  }
  PolishResult r;
  brick_gradient(space, m, grad);
  r.residual = residual_now(space, grad, nf, scale);
  double radius = -1.0;  // set from the first preconditioned gradient
  double g0 = 0.0;
  while (r.residual >= o.tolerance && r.iterations < o.max_iterations) {
    ++r.iterations;
    // the preconditioner: block-Jacobi at every Newton step (cheap); with Cholesky, the intact
    // wall's factor (made once per run, state-independent) until it serves CG badly (more than
    // kRefactorCg iterations: joints soften or rupture), then the factor of the current H for
    // the rest of the call. Every call starts from the intact wall's, so a run restarted between
    // load steps preconditions exactly as the original did.
    if (!factor_ || last_cg_ > kRefactorCg) precondition(space, m, floor_t, floor_r, last_negative_);
    const double gMg = minv_norm2(space, ws, grad, nf);
    if (radius < 0.0) radius = kRadiusStart * std::sqrt(gMg), g0 = std::sqrt(gMg);
    // forcing term (CG stops at eta |g|): the relative gradient (quadratic convergence), at most
    // kEtaMax, and no tighter than this step's tolerance needs (0.5 tolerance / residual). Measured
    // on a 5k-brick path at residual 1e-9 (80 steps, 41 ruptures): 892 Newton steps with the former
    // sqrt(relative) capped at 0.5, 781 with backtracking, 592 with this; the same final state
    const double eta =
        std::min(kEtaMax, std::max(std::sqrt(gMg) / std::max(g0, 1e-300), 0.5 * o.tolerance / r.residual));
    // (with the factor, minv_norm2 left M^-1 g in md_: CG's first solve)
    const Steihaug cg =
        steihaug(space, m, grad, radius, eta, o.max_inner_iterations, ws, factor_ ? md_ : GradientView<Mem>());
    last_cg_ = cg.iterations;
    last_negative_ = cg.negative;
    const bool boundary = cg.on_boundary;
    r.inner_iterations += last_cg_;
    // predicted decrease -(g.s + s.H s / 2): CG's model value (before 2026-12-05 one more H s
    // product and an M s, which gave the same numbers up to rounding)
    const double gs = dot(space, ws, grad, z, nf);
    const double pred = -cg.model, sHs = 2.0 * (cg.model - gs);
    const double snorm = std::sqrt(cg.snorm2);
    // the trial: poses moved by s, the energy change summed interface by interface
    Kokkos::parallel_for(
        "nacre::mc::newton::move", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf), KOKKOS_LAMBDA(const int b) {
          save(b, 0) = pose(b, 0), save(b, 1) = pose(b, 1), save(b, 2) = pose(b, 2);
          store_frame(pose, b,
                      kinematics::make_frame(
                          kinematics::Pose{pose(b, 0) + z(b, 0), pose(b, 1) + z(b, 1), pose(b, 2) + z(b, 2)}));
        });
    refresh(space, m);
    const double dE = energy_change(space, ws, ev, e, trial, ni);
    // below the rounding of the energy the ratio means nothing: the residual decides
    const double old_residual = r.residual;
    double rho;
    if (pred <= rounding) {
      brick_gradient(space, m, grad);
      const double res = residual_now(space, grad, nf, scale);
      rho = dE <= rounding && res < old_residual ? 1.0 : -1.0;
    } else {
      rho = -dE / pred;
    }
    bool taken = rho > 1e-4, partial = false;  // partial: rejected whole, taken in part
    double dE_taken = dE;
    if (!taken && pred > rounding && gs < 0.0) {
      // rejected: back along the step before giving it up. Where the model fails it is mostly a
      // joint's kink (contact penalty, the law's peak) crossed part-way along s; the energy at
      // save + alpha s for alpha = 1/2, 1/4, ..., 1/256 costs one energy pass each, against a new CG
      // solve (and often a refactorisation) for a rejected step. A fraction is taken when its
      // own ratio to the model's decrease along the line passes the acceptance test.
      double alpha = 1.0;
      for (int k = 0; k < kBacktracks && !taken; ++k) {
        alpha *= 0.5;
        const double al = alpha;
        Kokkos::parallel_for(
            "nacre::mc::newton::backtrack", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf),
            KOKKOS_LAMBDA(const int b) {
              store_frame(pose, b,
                          kinematics::make_frame(kinematics::Pose{save(b, 0) + al * z(b, 0), save(b, 1) + al * z(b, 1),
                                                                  save(b, 2) + al * z(b, 2)}));
            });
        refresh(space, m);
        dE_taken = energy_change(space, ws, ev, e, trial, ni);
        const double pred_a = -(al * gs + 0.5 * al * al * sHs);
        taken = pred_a > rounding && -dE_taken / pred_a > 1e-4;
      }
      // the model held up to alpha s: the region shrinks to it. (Keeping at least half the
      // radius saved 4 % of the Newton steps on the 20k reference path but sent "auto" onto an
      // arrested branch, 32 ruptures against 47, on the adaptive path: not taken, 2026-12-05.)
      if (taken) partial = true, radius = alpha * snorm;
    }
    if (taken) {
      std::swap(e, trial);
      r.energy_change += dE_taken;
      rounding = rounding_of(space, ws, e, ni);
      brick_gradient(space, m, grad);
      r.residual = residual_now(space, grad, nf, scale);
    } else {  // rejected: back to the saved poses
      ++r.rejected;
      Kokkos::parallel_for(
          "nacre::mc::newton::reject", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf), KOKKOS_LAMBDA(const int b) {
            store_frame(pose, b, kinematics::make_frame(kinematics::Pose{save(b, 0), save(b, 1), save(b, 2)}));
          });
      refresh(space, m);
      brick_gradient(space, m, grad);
    }
    if (rho < 0.25 && !partial)
      radius = 0.25 * snorm;
    else if (rho > 0.75 && boundary)
      radius = (std::abs(rho - 1.0) < 0.1 ? kGrowExact : 2.0) * radius;
    if (!(radius > 1e-14 * g0)) {  // the region collapsed: a stall (a kink or a flat plateau)
      r.stalled = true;
      break;
    }
  }
  r.converged = r.residual < o.tolerance;
  space.fence("nacre::mc::polish_trust_region");
  return r;
}

}  // namespace nacre::mc
