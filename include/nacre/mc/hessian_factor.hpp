// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The factorised preconditioner of the trust-region Newton method on host backends: the
/// exact sparse Hessian (hessian_blocks + hessian_slots), shifted until positive definite, by
/// sparse Cholesky, its ordering analysed once per run: CHOLMOD's supernodal factor in a METIS
/// order where the build found CHOLMOD (1.55x faster on a 20k-brick path), in float by default
/// (deck key factor_precision: half the bytes a triangular solve streams, the same Newton and CG
/// counts), else Eigen's SimplicialLLT in an AMD order, double. Each gives its own bits (each
/// deterministic).
///
/// Why: block-Jacobi leaves CG the long waves of the brick wall (hundreds to thousands of CG
/// iterations per Newton step at 20k bricks, measured: docs/speed_accuracy.md); with the factor
/// of H itself (shifted only where H is indefinite, on softening branches) CG needs a few. The
/// shift is relative to the diagonal, M = H + sigma diag(|H_ii|) (floored), sigma = 0 first, then
/// 1e-4, 1e-3, ... (from a decade below the last positive shift that worked since forget_shift())
/// until Cholesky succeeds: scale-free between translations and rotations.
/// Host memory only (Eigen): a build whose models live on a device uses block-Jacobi.
///
/// Spread over ranks (distribute()): the factor must be the one-process factor, bit for bit, and
/// its bits depend on the matrix's numbering, so rank 0 holds it. Each factor() gathers every
/// rank's rows (its free bricks' diagonal and slot blocks, the other brick named by its
/// one-process free index) to rank 0, which assembles them in the one-process order and
/// factorises; each solve() gathers the vector to rank 0 and scatters the result. One
/// process is the case of one rank. Correct and bit-identical, but serial on rank 0.
#include <nacre/mc/hessian.hpp>
#include <nacre/par/comm.hpp>

#include <memory>
#include <stdexcept>
#include <vector>

namespace nacre::mc {

class HessianFactor {
public:
  /// \brief `single`: factor and solve in float where CHOLMOD factorises (Eigen's factor: double).
  explicit HessianFactor(bool single = false);
  ~HessianFactor();
  HessianFactor(HessianFactor&&) noexcept;
  HessianFactor& operator=(HessianFactor&&) noexcept;

  /// \brief Spread over the ranks of `comm`: global_free[k] is the one-process free index (the
  /// unknowns' numbering of one process) of brick k of this rank's model, -1 where the brick is
  /// held (driven); every rank calls every member below (collectives).
  void distribute(const par::Comm& comm, std::vector<int> global_free);
  /// \brief Assemble M from the model's adjacency (host copies taken on the first call: the
  /// pattern never changes), the diagonal blocks (xx, yy, tt, xy, xt, yt) and the slot blocks,
  /// and factorise it; `floor_t` / `floor_r` bound the diagonal scaling of the shift.
  /// `indefinite`: the caller saw negative curvature, so sigma = 0 is not tried.
  void factor(const Model<Kokkos::HostSpace>& m, const BlockView<Kokkos::HostSpace>& diag,
              const SlotBlockView<Kokkos::HostSpace>& slots, double floor_t, double floor_r, bool indefinite = false);
  /// \brief (A model in device memory: std::logic_error. The factor reads its arrays on the host;
  /// a solver on a device uses block-Jacobi and never makes one.)
  template <class Mem>
  void factor(const Model<Mem>&, const BlockView<Mem>&, const SlotBlockView<Mem>&, double, double, bool = false) {
    throw std::logic_error("nacre::mc::HessianFactor: host memory only (device models use block-Jacobi)");
  }
  /// \brief y = M^-1 r (free bricks, x / y / theta columns).
  void solve(const GradientView<Kokkos::HostSpace>& r, const GradientView<Kokkos::HostSpace>& y) const;
  template <class Mem>
  void solve(const GradientView<Mem>&, const GradientView<Mem>&) const {
    throw std::logic_error("nacre::mc::HessianFactor: host memory only (device models use block-Jacobi)");
  }
  /// \brief Start the shift search afresh (its memory of the last positive shift dropped).
  void forget_shift();
  /// \brief The relative shift the last factorisation needed (0: H itself was positive definite).
  [[nodiscard]] double shift() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nacre::mc
