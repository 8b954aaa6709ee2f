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
/// deterministic_sum and every max a max: the same bits for any thread count.
#include <nacre/core/deterministic_sum.hpp>
#include <nacre/mc/gradient.hpp>

#include <string>

namespace nacre::mc {

/// \brief The polish methods (deck key `polish`): anneal is mc::Solver::anneal, the others Polisher's.
enum class PolishMethod { fire, newton, anneal, none };
/// \brief The method named `name` (the deck's spelling); std::invalid_argument for any other.
PolishMethod parse_polish_method(const std::string& name);
/// \brief The deck's spelling of `m`.
const char* polish_method_name(PolishMethod m);

/// \brief What a polish is asked to do.
struct PolishOptions {
  PolishMethod method = PolishMethod::fire;
  double tolerance = 1e-6;      ///< residual to reach
  int max_iterations = 5000;    ///< FIRE steps or Newton sweeps
  double rotation_length = 1.0; ///< l of the FIRE coordinates (x, y, l theta)
  double stiffness = 1.0;       ///< K of one brick (sets FIRE's time steps: dt_max = 1 / sqrt(K))
};

/// \brief What a polish did.
struct PolishResult {
  int iterations = 0;   ///< FIRE steps / Newton sweeps taken
  int rejected = 0;     ///< FIRE steps rejected by the energy test
  double residual = 0;  ///< residual at the end
  double energy_change = 0;  ///< sum of the accepted energy changes (<= 0)
  bool converged = false;
};

/// \brief Work arrays and the two methods, on one execution-space instance.
class Polisher {
public:
  Polisher() = default;
  Polisher(const ExecSpace& space, const Model<>& m);

  /// \brief The exact gradient at the current poses and its residual.
  double residual(const ExecSpace& space, const Model<>& m, const ResidualScale& scale);
  [[nodiscard]] const GradientView<>& gradient() const { return grad_; }

  PolishResult run(const ExecSpace& space, const Model<>& m, const ResidualScale& scale, const PolishOptions& o);
  PolishResult fire(const ExecSpace& space, const Model<>& m, const ResidualScale& scale, const PolishOptions& o);
  PolishResult newton(const ExecSpace& space, const Model<>& m, const ResidualScale& scale, const PolishOptions& o);

private:
  GradientView<> grad_, vel_;
  Kokkos::View<double* [3], Kokkos::LayoutLeft, MemSpace> save_;
  Field<double> iface_e_, iface_trial_;
  SumWorkspace<> ws_;
};

}  // namespace nacre::mc
