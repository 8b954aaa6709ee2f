// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief What a polish is asked to do and what it did (the methods: polish.hpp, trust_region.hpp).
#include <string>

namespace nacre::mc {

/// \brief The polish methods (deck key `polish`): anneal is mc::Solver::anneal, the others Polisher's
/// ("newton": colour-swept 3x3 block Newton; "trust-region": Newton-CG, trust_region.hpp).
enum class PolishMethod { fire, newton, trust_region, anneal, none };
/// \brief The method named `name` (the deck's spelling); std::invalid_argument for any other.
PolishMethod parse_polish_method(const std::string& name);
/// \brief The deck's spelling of `m`.
const char* polish_method_name(PolishMethod m);

/// \brief The trust-region Newton method's preconditioner (deck key newton_preconditioner):
/// the sparse Cholesky factor of the (shifted) Hessian on host memory, else 3x3 block-Jacobi.
enum class NewtonPreconditioner { automatic, cholesky, block_jacobi };
/// \brief The Cholesky preconditioner's arithmetic (deck key factor_precision): float halves the
/// bytes its solves stream; CG, H v and the residual stay double. CHOLMOD only (Eigen: double).
enum class FactorPrecision { single, double_precision };

/// \brief What a polish is asked to do.
struct PolishOptions {
  PolishMethod method = PolishMethod::fire;
  double tolerance = 1e-6;         ///< residual to reach
  int max_iterations = 5000;       ///< FIRE steps, Newton sweeps or trust-region Newton steps
  int max_inner_iterations = 500;  ///< CG iterations per trust-region Newton step
  NewtonPreconditioner preconditioner = NewtonPreconditioner::automatic;
  double rotation_length = 1.0;    ///< l of the FIRE coordinates (x, y, l theta)
  double stiffness = 1.0;          ///< K of one brick (sets FIRE's time steps: dt_max = 1 / sqrt(K))
};

/// \brief What a polish did.
struct PolishResult {
  int iterations = 0;         ///< FIRE steps / Newton sweeps taken
  int rejected = 0;           ///< FIRE / trust-region steps rejected by the energy test
  long inner_iterations = 0;  ///< CG iterations (trust region)
  bool stalled = false;       ///< the trust region collapsed before the tolerance (trust region)
  double residual = 0;        ///< residual at the end
  double energy_change = 0;   ///< sum of the accepted energy changes (<= 0)
  bool converged = false;
};

}  // namespace nacre::mc
