// SPDX-License-Identifier: BSD-3-Clause
// [solver]: the Monte Carlo solver (deck::MonteCarlo; the TOML section keeps its name).
#include "../section.hpp"

namespace nacre::deck::detail {

void read_solver(Section& top, Deck& d) {
  Section s = top.sub("solver");
  auto& S = d.solver;
  s.number("temperature", {"TEMP"}, S.temperature, non_negative, "a non-negative temperature (energy units)");
  s.number("step", {"InitialStepSize"}, S.step, positive, "a positive length");
  S.min_step = S.max_step = S.step;
  s.number("min_step", {"MinStepSize"}, S.min_step, positive, "a positive length");
  s.number("max_step", {"MaxStepSize"}, S.max_step, positive, "a positive length");
  s.number("rot_step", {"InitialRotSize"}, S.rot_step, positive, "a positive angle (radians)");
  S.min_rot_step = S.max_rot_step = S.rot_step;
  s.number("min_rot_step", {"MinRotSize"}, S.min_rot_step, positive, "a positive angle (radians)");
  s.number("max_rot_step", {"MaxRotSize"}, S.max_rot_step, positive, "a positive angle (radians)");
  s.integer("adapt_interval", {"AdaptInter"}, S.adapt_interval, 0, 1000000000, "a cycle count >= 0 (0: fixed steps)");
  std::string step_mode = S.per_brick_steps ? "per-brick" : "global";
  s.string("step_mode", step_mode, {"global", "per-brick"}, "\"global\" or \"per-brick\"");
  S.per_brick_steps = step_mode == "per-brick";
  s.number("stol", {"STOL"}, S.stol, positive, "a positive tolerance");
  s.number("rtol", {"RTOL"}, S.rtol, [](double v) { return v > 0 && v <= 1; }, "R^2 tolerance in (0, 1]");
  std::string stol_mode = S.stol_relative ? "relative" : "absolute";
  s.string("stol_mode", stol_mode, {"relative", "absolute"}, "\"relative\" or \"absolute\"");
  S.stol_relative = stol_mode == "relative";
  s.integer("window_size", {"WindowSize"}, S.window_size, 3, 100000000, "an integer >= 3");
  s.integer("convergence_rep", {"ConvergenceRep"}, S.convergence_rep, 1, 100000000, "an integer >= 1");
  s.number("window_mul", {"WindowMul"}, S.window_mul, positive, "a positive factor");
  s.number("window_upper_mul", {"WindowUpperMul"}, S.window_upper_mul, positive, "a positive factor");
  s.integer("max_cycles", {}, S.max_cycles, 1, 1000000000000L, "a cycle count >= 1");
#ifdef NACRE_HAVE_KOKKOSKERNELS
  s.string("colouring", S.colouring,
           {"auto", "fastest", "natural", "largest-first", "random", "balanced", "tiles", "kokkos-d1"},
           "one of \"auto\", \"fastest\", \"natural\", \"largest-first\", \"random\", \"balanced\", \"tiles\", "
           "\"kokkos-d1\"");
#else
  s.string("colouring", S.colouring,
           {"auto", "fastest", "natural", "largest-first", "random", "balanced", "tiles"},
           "one of \"auto\", \"fastest\", \"natural\", \"largest-first\", \"random\", \"balanced\", \"tiles\" "
           "(\"kokkos-d1\" needs nacre built with Kokkos Kernels)");
#endif
  s.integer("presim_cycles", {}, S.presim_cycles, 1, 100000, "an integer in [1, 100000]");
  s.string("convergence", S.convergence, {"residual", "window"}, "\"residual\" or \"window\"");
  s.number("residual_tolerance", {}, S.residual_tolerance, [](double v) { return v > 0 && v < 1; },
           "a tolerance in (0, 1) (the residual is relative to k x1 brick_width)");
  s.string("polish", S.polish, {"fire", "newton", "trust-region", "anneal", "none"},
           "one of \"fire\", \"newton\", \"trust-region\", \"anneal\", \"none\"");
  s.integer("polish_iterations", {}, S.polish_iterations, 1, 100000000, "an integer >= 1");
  s.integer("cg_iterations", {}, S.cg_iterations, 1, 100000000, "an integer >= 1 (CG iterations per Newton step)");
  s.integer("burst_cycles", {}, S.burst_cycles, 1, 1000000000, "a cycle count >= 1");
  s.string("newton_preconditioner", S.newton_preconditioner, {"auto", "cholesky", "block-jacobi"},
           "one of \"auto\", \"cholesky\", \"block-jacobi\"");
  s.string("factor_precision", S.factor_precision, {"single", "double"}, "one of \"single\", \"double\"");
  s.string("relaxation", S.relaxation, {"monte-carlo", "gradient", "newton", "auto"},
           "one of \"monte-carlo\", \"gradient\", \"newton\", \"auto\"");
  if (S.relaxation == "gradient" && S.polish != "fire" && S.polish != "newton" && S.polish != "trust-region")
    s.fail("relaxation",
           "relaxation = \"gradient\" minimises with the polish method; expected polish = \"fire\", "
           "\"newton\" or \"trust-region\", not \"" +
               S.polish + "\"");
  // keys of one method given where the deck's method never reads them: refused, not ignored
  if (S.colouring != "fastest")
    reject_if_given(s, "presim_cycles", "times the candidates of colouring = \"fastest\" only",
                    "colouring is \"" + S.colouring + "\"", "colouring = \"fastest\"");
  if (S.relaxation != "auto")
    reject_if_given(s, "burst_cycles", "sets the Monte Carlo bursts of relaxation = \"auto\" only",
                    "relaxation is \"" + S.relaxation + "\"", "relaxation = \"auto\"");
  const bool newton = S.relaxation == "newton" || S.relaxation == "auto" || S.polish == "newton" || S.polish == "trust-region";
  for (const char* k : {"cg_iterations", "newton_preconditioner", "factor_precision"})
    if (!newton && s.find(k, {}) != nullptr)
      s.fail(k, std::string("sets the Newton method, which this deck does not use (relaxation = \"") + S.relaxation +
                    "\", polish = \"" + S.polish + "\"); expected relaxation = \"newton\" or \"auto\", or polish = "
                    "\"newton\" or \"trust-region\", or no " + k);
  // the trust region needs the Hessian of the reversible law (mc/hessian.hpp); "auto" falls back
  // to Monte Carlo with the polish there (docs/decks.md)
  if (d.mortar.damage == cohesive::Damage::irreversible && (S.relaxation == "newton" || S.polish == "trust-region"))
    s.fail(S.relaxation == "newton" ? "relaxation" : "polish",
           "the trust-region Newton method needs the reversible law, and this deck's damage is irreversible (set, "
           "or a load programme that turns back); expected relaxation = \"auto\", \"monte-carlo\" or "
           "\"gradient\" with polish = \"fire\"");
  // The paper's AmpFactor and StructSteps are 1 in every run it reports; nacre implements that
  // case only and says so instead of silently ignoring another value.
  double amp = 1, structs = 1;
  s.number("AmpFactor", {}, amp, [](double v) { return v == 1; }, "1 (the only value the paper uses)");
  s.number("StructSteps", {}, structs, [](double v) { return v == 1; }, "1 (the only value the paper uses)");
  check_bracket(s, "step", S.step, S.min_step, S.max_step, "min_step");
  check_bracket(s, "rot_step", S.rot_step, S.min_rot_step, S.max_rot_step, "min_rot_step");
  if (S.window_upper_mul < S.window_mul)
    s.fail("window_upper_mul", "upper cycle bound below the target; expected WindowUpperMul >= WindowMul");
  s.reject_unknown({"temperature (TEMP)",
                    "step (InitialStepSize)",
                    "min_step (MinStepSize)",
                    "max_step (MaxStepSize)",
                    "rot_step (InitialRotSize)",
                    "min_rot_step (MinRotSize)",
                    "max_rot_step (MaxRotSize)",
                    "adapt_interval (AdaptInter)",
                    "step_mode",
                    "stol (STOL)",
                    "rtol (RTOL)",
                    "stol_mode",
                    "window_size (WindowSize)",
                    "convergence_rep (ConvergenceRep)",
                    "window_mul (WindowMul)",
                    "window_upper_mul (WindowUpperMul)",
                    "max_cycles",
                    "colouring",
                    "presim_cycles",
                    "convergence",
                    "residual_tolerance",
                    "polish",
                    "polish_iterations",
                    "cg_iterations",
                    "burst_cycles",
                    "newton_preconditioner",
                    "factor_precision",
                    "relaxation",
                    "AmpFactor",
                    "StructSteps"});
}

}  // namespace nacre::deck::detail
