// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Deterministic polish of a load step with the exact gradient: after the
/// Monte Carlo relaxation, drive the residual (gradient.hpp) below the deck's tolerance.
///
/// Why here and not Monte Carlo alone: a Metropolis chain at temperature T samples a state whose
/// energy sits ~(3/2) N T above the minimum and whose forces are thermal noise, so no window
/// statistic makes it a minimum. The energy is C1 and its gradient costs about two energy
/// evaluations per interface, so a gradient method finishes the job. Two methods:
///  - FIRE (Bitzek et al. 2006): damped dynamics of all free bricks at once, unit masses in the
///    coordinates (x, y, l theta), l = brick_width / sqrt(12) (a bed-jointed brick's rotation
///    stiffness over its translation stiffness is l^2); the step dt adapts as in the paper.
///  - "newton": colour-swept Newton on each brick's 3x3 block (block Gauss-Seidel), the Hessian
///    by forward differences of the exact gradient, the neighbours held.
/// Both never increase the energy: FIRE rejects a step whose energy change (summed interface by
/// interface as differences, see brick_delta) is positive, restoring the poses, zeroing the
/// velocities and halving dt; Newton halves its step until the brick's energy decreases (bricks
/// of one colour share no interface, so each brick's decrease is the total's). Every sum is a
/// deterministic_sum and every max a max: the same bits for any thread count. Spread over ranks
/// (distribute(); FIRE, Newton, the trust region of trust_region.hpp and the residual) each rank
/// moves its own free bricks (Newton: after each colour, that colour's poses go to the halos), sums its own
/// terms and interfaces over the ranks, and takes its halo's poses from their owners after each
/// move: the bits of one process.
#include <nacre/core/deterministic_sum.hpp>
#include <nacre/mc/gradient.hpp>
#include <nacre/mc/halo.hpp>
#include <nacre/mc/polish_types.hpp>
#include <nacre/mc/trust_region.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace nacre::mc {

/// \brief Work arrays and the two methods, on one execution space (the solver's: a template to
/// the top, so the loops below launch on a typed instance).
template <class ExecutionSpace = ExecSpace>
class Polisher {
public:
  /// the model's and the work arrays' memory: the execution space's own
  using Mem = MemOf<ExecutionSpace>;
  Polisher() = default;
  Polisher(const ExecutionSpace& space, const Model<Mem>& m, NewtonPreconditioner pc = NewtonPreconditioner::automatic,
           FactorPrecision precision = FactorPrecision::single);

  /// \brief The exact gradient at the current poses and its residual.
  double residual(const ExecutionSpace& space, const Model<Mem>& m, const ResidualScale& scale);
  [[nodiscard]] const GradientView<Mem>& gradient() const { return grad_; }

  PolishResult run(const ExecutionSpace& space, const Model<Mem>& m, const ResidualScale& scale,
                   const PolishOptions& o);
  PolishResult fire(const ExecutionSpace& space, const Model<Mem>& m, const ResidualScale& scale,
                    const PolishOptions& o);
  PolishResult newton(const ExecutionSpace& space, const Model<Mem>& m, const ResidualScale& scale,
                      const PolishOptions& o);
  /// \brief Work on a rank's part of a specimen (null: the whole one in this process).
  void distribute(const Distribution<Mem>* d) {
    dist_ = d;
    tr_.distribute(d);
  }

private:
  /// deterministic_sum's combine for `owned` terms of this rank (all of them in one process)
  [[nodiscard]] par::Reduce over(long long owned) const { return reduce_over(dist_, owned); }
  const Distribution<Mem>* dist_ = nullptr;
  GradientView<Mem> grad_, vel_;
  Kokkos::View<double* [3], Kokkos::LayoutLeft, Mem> save_;
  Field<double, Mem> iface_e_, iface_trial_;
  SumWorkspace<Mem> ws_;
  TrustRegion<ExecutionSpace> tr_;
};

template <class ExecutionSpace>
Polisher<ExecutionSpace>::Polisher(const ExecutionSpace& space, const Model<Mem>& m, NewtonPreconditioner pc,
                                   FactorPrecision precision) {
  using Kokkos::view_alloc, Kokkos::WithoutInitializing;
  const auto nf = static_cast<std::size_t>(m.n_free), ni = static_cast<std::size_t>(m.n_interfaces);
  grad_ = GradientView<Mem>(view_alloc(space, WithoutInitializing, "nacre::mc::polish::gradient"), nf);
  vel_ = GradientView<Mem>(view_alloc(space, WithoutInitializing, "nacre::mc::polish::velocity"), nf);
  save_ = decltype(save_)(view_alloc(space, WithoutInitializing, "nacre::mc::polish::save"), nf);
  iface_e_ = Field<double, Mem>(view_alloc(space, WithoutInitializing, "nacre::mc::polish::energy"), ni);
  iface_trial_ = Field<double, Mem>(view_alloc(space, WithoutInitializing, "nacre::mc::polish::trial_energy"), ni);
  tr_ = TrustRegion<ExecutionSpace>(space, m, pc, precision);
}

template <class ExecutionSpace>
double Polisher<ExecutionSpace>::residual(const ExecutionSpace& space, const Model<Mem>& m,
                                          const ResidualScale& scale) {
  brick_gradient(space, m, grad_);
  return max_over(dist_, residual_of(space, grad_, m.n_free, scale));
}

template <class ExecutionSpace>
PolishResult Polisher<ExecutionSpace>::run(const ExecutionSpace& space, const Model<Mem>& m, const ResidualScale& scale,
                                           const PolishOptions& o) {
  if (o.method == PolishMethod::fire) return fire(space, m, scale, o);
  if (o.method == PolishMethod::newton) return newton(space, m, scale, o);
  if (o.method == PolishMethod::trust_region) return tr_.run(space, m, scale, o, grad_, iface_e_, iface_trial_, ws_);
  if (o.method == PolishMethod::anneal) throw std::logic_error("Polisher::run: anneal is mc::Solver::anneal");
  PolishResult r;
  r.residual = residual(space, m, scale);
  r.converged = r.residual < o.tolerance;
  return r;
}

template <class ExecutionSpace>
PolishResult Polisher<ExecutionSpace>::fire(const ExecutionSpace& space, const Model<Mem>& m,
                                            const ResidualScale& scale, const PolishOptions& o) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::polish_fire");
  // Bitzek et al. 2006, Table 1: N_min 5, f_inc 1.1, f_dec 0.5, alpha_start 0.1, f_alpha 0.99.
  constexpr int n_min = 5;
  constexpr double f_inc = 1.1, f_dec = 0.5, alpha0 = 0.1, f_alpha = 0.99;
  const double dt_max = 1.0 / std::sqrt(o.stiffness);
  double dt = 0.25 * dt_max, alpha = alpha0;
  int n_pos = 0;
  const int nf = m.n_free, ni = m.n_interfaces;
  const double l = o.rotation_length, inv_l = 1.0 / l;
  const InterfaceEvaluator<Mem> ev(m);
  auto grad = grad_, vel = vel_, save = save_;
  auto pose = m.pose;
  // spread over ranks: interfaces summed by their owner only (an empty view: every one here)
  const auto own = owned_mask(dist_);
  const long long ni_owned = owned_interfaces(dist_, m);
  Kokkos::deep_copy(space, vel, 0.0);
  {
    auto e = iface_e_;
    Kokkos::parallel_for(
        "nacre::mc::polish::interface_energy", Kokkos::RangePolicy<ExecutionSpace>(space, 0, ni),
        KOKKOS_LAMBDA(const int i) { e(i) = ev.energy(i); });
  }
  // Rounding floor of the energy test: each per-interface difference v - e(i) is exact to about
  // eps |v|, so near the minimum a true decrease below ~eps E can come out positive; rejecting
  // such steps halves dt for ever and FIRE stalls (seen at residuals ~1e-8). Steps within this
  // floor count as level, not uphill.
  double rounding_floor = 0;
  {
    auto e = iface_e_;
    rounding_floor =
        4 * DBL_EPSILON *
        deterministic_sum(
            space, "nacre::mc::polish::energy_scale", ws_, 0, ni,
            KOKKOS_LAMBDA(const int i) { return own.data() && !own(i) ? 0.0 : Kokkos::abs(e(i)); }, over(ni_owned));
  }
  PolishResult r;
  r.residual = residual(space, m, scale);
  while (r.residual >= o.tolerance && r.iterations < o.max_iterations) {
    ++r.iterations;
    // forces in the coordinates (x, y, l theta): F = -(gx, gy, gt / l)
    const double P = -deterministic_sum(
        space, "nacre::mc::polish::power", ws_, 0, nf,
        KOKKOS_LAMBDA(const int b) {
          return grad(b, 0) * vel(b, 0) + grad(b, 1) * vel(b, 1) + grad(b, 2) * inv_l * vel(b, 2);
        },
        over(nf));
    const double FF = deterministic_sum(
        space, "nacre::mc::polish::force_norm", ws_, 0, nf,
        KOKKOS_LAMBDA(const int b) {
          return grad(b, 0) * grad(b, 0) + grad(b, 1) * grad(b, 1) + grad(b, 2) * grad(b, 2) * inv_l * inv_l;
        },
        over(nf));
    const double VV = deterministic_sum(
        space, "nacre::mc::polish::velocity_norm", ws_, 0, nf,
        KOKKOS_LAMBDA(const int b) { return vel(b, 0) * vel(b, 0) + vel(b, 1) * vel(b, 1) + vel(b, 2) * vel(b, 2); },
        over(nf));
    const bool downhill = P > 0.0;
    if (downhill) {
      if (++n_pos > n_min) dt = std::min(dt * f_inc, dt_max), alpha *= f_alpha;
    } else {
      n_pos = 0, dt *= f_dec, alpha = alpha0;
    }
    const double mix = FF > 0.0 ? alpha * std::sqrt(VV / FF) : 0.0, keep = 1.0 - alpha, h = dt;
    Kokkos::parallel_for(
        "nacre::mc::polish::fire_step", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf), KOKKOS_LAMBDA(const int b) {
          const double F[3] = {-grad(b, 0), -grad(b, 1), -grad(b, 2) * inv_l};
          for (int c = 0; c < 3; ++c) {
            const double v = downhill ? keep * vel(b, c) + mix * F[c] : 0.0;  // FIRE mixing, or stop
            vel(b, c) = v + h * F[c];                                         // semi-implicit Euler, unit masses
          }
          save(b, 0) = pose(b, 0), save(b, 1) = pose(b, 1), save(b, 2) = pose(b, 2);
          const kinematics::Pose q{pose(b, 0) + h * vel(b, 0), pose(b, 1) + h * vel(b, 1),
                                   pose(b, 2) + h * vel(b, 2) * inv_l};
          store_frame(pose, b, kinematics::make_frame(q));
        });
    if (dist_) dist_->refresh(space, m);
    // energy test: the change summed as per-interface differences
    auto e = iface_e_, et = iface_trial_;
    const double dE = deterministic_sum(
        space, "nacre::mc::polish::energy_change", ws_, 0, ni,
        KOKKOS_LAMBDA(const int i) {
          const double v = ev.energy(i);
          et(i) = v;
          return own.data() && !own(i) ? 0.0 : v - e(i);
        },
        over(ni_owned));
    if (dE <= rounding_floor) {
      std::swap(iface_e_, iface_trial_);
      r.energy_change += dE;
    } else {  // rejected: back to the saved poses, at rest, with a smaller step
      ++r.rejected;
      Kokkos::parallel_for(
          "nacre::mc::polish::fire_reject", Kokkos::RangePolicy<ExecutionSpace>(space, 0, nf),
          KOKKOS_LAMBDA(const int b) {
            store_frame(pose, b, kinematics::make_frame(kinematics::Pose{save(b, 0), save(b, 1), save(b, 2)}));
            vel(b, 0) = vel(b, 1) = vel(b, 2) = 0.0;
          });
      if (dist_) dist_->refresh(space, m);
      n_pos = 0, dt *= f_dec, alpha = alpha0;
    }
    r.residual = residual(space, m, scale);
  }
  r.converged = r.residual < o.tolerance;
  space.fence("nacre::mc::polish_fire");
  return r;
}

namespace detail {
/// Solve the symmetric 3x3 system H d = -g by Cholesky; false when H is not positive definite.
KOKKOS_INLINE_FUNCTION bool solve_spd3(const double H[3][3], const double g[3], double d[3]) {
  const double l00 = H[0][0];
  if (!(l00 > 0.0)) return false;
  const double L00 = Kokkos::sqrt(l00), L10 = H[1][0] / L00, L20 = H[2][0] / L00;
  const double l11 = H[1][1] - L10 * L10;
  if (!(l11 > 0.0)) return false;
  const double L11 = Kokkos::sqrt(l11), L21 = (H[2][1] - L20 * L10) / L11;
  const double l22 = H[2][2] - L20 * L20 - L21 * L21;
  if (!(l22 > 0.0)) return false;
  const double L22 = Kokkos::sqrt(l22);
  const double y0 = -g[0] / L00, y1 = (-g[1] - L10 * y0) / L11, y2 = (-g[2] - L20 * y0 - L21 * y1) / L22;
  d[2] = y2 / L22;
  d[1] = (y1 - L21 * d[2]) / L11;
  d[0] = (y0 - L10 * d[1] - L20 * d[2]) / L00;
  return true;
}
}  // namespace detail

template <class ExecutionSpace>
PolishResult Polisher<ExecutionSpace>::newton(const ExecutionSpace& space, const Model<Mem>& m,
                                              const ResidualScale& scale, const PolishOptions& o) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::polish_newton");
  const InterfaceEvaluator<Mem> ev(m);
  auto off = m.adj_offset, adj = m.adj_iface, tiles = m.tile_offset;
  auto pose = m.pose;
  // forward-difference steps of the Hessian and the largest move per Newton step
  const double x1 = std::min(m.laws[geometry::JointKind::bed].x1 > 0 ? m.laws[geometry::JointKind::bed].x1 : 1e300,
                             m.laws[geometry::JointKind::head].x1 > 0 ? m.laws[geometry::JointKind::head].x1 : 1e300);
  const double l = o.rotation_length;
  const double h[3] = {1e-6 * x1, 1e-6 * x1, 1e-6 * x1 / l};
  const double cap[3] = {x1, x1, x1 / l};
  const double inv_f = 1.0 / scale.force, inv_m = 1.0 / scale.moment, skip = 1e-2 * o.tolerance;
  PolishResult r;
  Field<double, Mem> de(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::polish::newton_de"),
                        m.n_free);
  r.residual = residual(space, m, scale);
  while (r.residual >= o.tolerance && r.iterations < o.max_iterations) {
    ++r.iterations;
    for (std::size_t c = 0; c + 1 < m.colour_tiles.size(); ++c) {
      Kokkos::parallel_for(
          "nacre::mc::polish::newton_colour",
          Kokkos::RangePolicy<ExecutionSpace>(space, m.colour_tiles[c], m.colour_tiles[c + 1]),
          KOKKOS_LAMBDA(const int w) {
            for (int b = tiles(w); b < tiles(w + 1); ++b) {
              de(b) = 0.0;
              const kinematics::Frame f0 = frame_of(pose, b);
              double g[3] = {0.0, 0.0, 0.0};
              brick_local(ev, off, adj, b, f0, g);
              if (Kokkos::fmax(Kokkos::fmax(Kokkos::fabs(g[0]), Kokkos::fabs(g[1])) * inv_f,
                               Kokkos::fabs(g[2]) * inv_m) < skip)
                continue;
              double H[3][3];
              for (int j = 0; j < 3; ++j) {
                double p[3] = {f0.x, f0.y, f0.t};
                p[j] += h[j];
                double gj[3] = {0.0, 0.0, 0.0};
                brick_local(ev, off, adj, b, kinematics::make_frame(kinematics::Pose{p[0], p[1], p[2]}), gj);
                for (int i = 0; i < 3; ++i) H[i][j] = (gj[i] - g[i]) / h[j];
              }
              for (int i = 0; i < 3; ++i)
                for (int j = 0; j < i; ++j) H[i][j] = H[j][i] = 0.5 * (H[i][j] + H[j][i]);
              double d[3];
              if (!detail::solve_spd3(H, g, d))  // not convex here: a diagonally scaled descent step
                for (int i = 0; i < 3; ++i) d[i] = -g[i] / Kokkos::fmax(Kokkos::fabs(H[i][i]), 1e-300);
              double t = 1.0;
              for (int i = 0; i < 3; ++i)
                if (Kokkos::fabs(d[i]) * t > cap[i]) t = cap[i] / Kokkos::fabs(d[i]);
              for (int k = 0; k < 30; ++k, t *= 0.5) {  // backtracking on the brick's energy
                const kinematics::Frame f1 =
                    kinematics::make_frame(kinematics::Pose{f0.x + t * d[0], f0.y + t * d[1], f0.t + t * d[2]});
                const double dE = brick_delta(ev, off, adj, b, f0, f1);
                if (dE < 0.0) {
                  store_frame(pose, b, f1);
                  de(b) = dE;
                  break;
                }
              }
            }
          });
      // spread over ranks: this colour's moves to the ranks holding them in a halo
      if (dist_) dist_->halo->exchange(space, dist_->comm, m, static_cast<int>(c));
    }
    r.energy_change += deterministic_sum(
        space, "nacre::mc::polish::newton_sum", ws_, 0, m.n_free, KOKKOS_LAMBDA(const int b) { return de(b); },
        over(m.n_free));
    r.residual = residual(space, m, scale);
  }
  r.converged = r.residual < o.tolerance;
  space.fence("nacre::mc::polish_newton");
  return r;
}

}  // namespace nacre::mc
