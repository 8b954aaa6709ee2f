// SPDX-License-Identifier: BSD-3-Clause
// [dynamics]: its presence selects the dynamic solver (Chapter 4). The reader also rejects the
// Monte Carlo keys a dynamic run would silently ignore ([solver], the load-step keys of [load],
// [output] DumpInter), so a deck never means something it does not do.
#include <nacre/deck/deck.hpp>

#include "../section.hpp"

namespace nacre::deck::detail {

namespace {

/// \brief Fail at the first of `keys` present in table `name` of the root (a key that does not
/// apply to a dynamic run).
void reject_mc_keys(const Section& top, const toml::table& root, const char* name,
                    std::initializer_list<const char*> keys, const std::string& why) {
  const toml::table* t = root.get_as<toml::table>(name);
  if (!t) return;
  const Section s(top.file(), name, t, static_cast<int>(t->source().begin.line));
  for (const char* k : keys)
    if (t->contains(k)) s.fail(k, why);
}

}  // namespace

void read_dynamics(Section& top, Deck& d) {
  Section s = top.sub("dynamics");
  if (!s.present()) return;
  const toml::table& root = *top.table();
  auto& D = d.dynamics;
  D.enabled = true;

  if (root.contains("solver"))
    top.fail("solver", "the Monte Carlo [solver] section does not apply to a [dynamics] deck; remove one of the two");
  reject_mc_keys(top, root, "load",
                 {"initial_step", "InitialLoadStepSize", "min_step", "MinLoadStepSize", "max_step", "MaxLoadStepSize",
                  "adaptive", "predictor"},
                 "a Monte Carlo load-step key; a [dynamics] run loads at [dynamics] rate (remove it)");
  reject_mc_keys(top, root, "output", {"dump_interval", "DumpInter"},
                 "counts Monte Carlo load steps; a [dynamics] deck sets [dynamics] dump_interval (time steps)");

  std::string method = D.method == Dynamics::Method::ue ? "ue" : (D.method == Dynamics::Method::bie ? "bie" : "be");
  s.string("method", method, {"ue", "be", "bie"},
           "\"ue\" (unbolted explicit, eq. 4.4), \"be\" (bolted explicit, eq. 4.5) or \"bie\" (bolted implicit-explicit, eq. 4.6)");
  D.method = method == "ue" ? Dynamics::Method::ue : (method == "bie" ? Dynamics::Method::bie : Dynamics::Method::be);
  if (D.method != Dynamics::Method::bie)  // keys of BIE alone would be ignored silently
    for (const char* k : {"bie_solve", "bie_block", "bie_iterations", "bie_scheme"})
      reject_if_given(s, k, "applies to method = \"bie\" only", "method is \"" + method + "\"", "method = \"bie\"");
#if defined(NACRE_HAVE_KOKKOSKERNELS)
  s.string("bie_solve", D.bie_solve, {"row", "reordered", "batched", "shared_gemm"},
           "\"row\", \"reordered\", \"batched\" or \"shared_gemm\" (docs/methods.md)");
#else
  s.string("bie_solve", D.bie_solve, {"row", "reordered", "shared_gemm"},
           "\"row\", \"reordered\" or \"shared_gemm\" (\"batched\" needs Kokkos Kernels, not in this build)");
#endif
  {
    long nb = D.bie_block;
    s.integer("bie_block", {}, nb, 2, 10, dyn::kBieBlockExpected);
    if (!dyn::valid_bie_block(nb)) s.fail("bie_block", std::string("expected ") + dyn::kBieBlockExpected);
    D.bie_block = static_cast<int>(nb);
  }
  {
    long ni = D.bie_iterations;
    s.integer("bie_iterations", {}, ni, 1, 16, "1 to 16 (iterations with the constant Jacobian per step)");
    D.bie_iterations = static_cast<int>(ni);
  }
  if (D.bie_solve != "reordered")
    reject_if_given(s, "bie_block", "sets the block rows of bie_solve = \"reordered\" only",
                    "bie_solve is \"" + D.bie_solve + "\"", "bie_solve = \"reordered\"");
  s.string("bie_scheme", D.bie_scheme, {"auto", "iterate", "split"},
           "\"auto\", \"iterate\" (eq. 4.6: bie_iterations iterations with the constant Jacobian) or \"split\" (half "
           "kicks around one implicit-midpoint solve of the bricks: docs/methods.md)");
  if (s.find("bie_iterations", {}) != nullptr) {
    if (D.bie_scheme == "split")
      s.fail("bie_iterations", "given with bie_scheme = \"split\", which solves each step with one J^-1 apply; expected "
                               "no bie_iterations (or bie_scheme = \"iterate\")");
    D.bie_scheme = "iterate";  // "auto" with an iteration count: the iterated step was asked for
  }

  // Physical values in ranges that say why: beyond them a run reaches its first step only to stop
  // as unstable (or overflow), so the deck refuses them with the key's line instead.
  const bool has_ratio = s.find("stiffness_ratio", {}) != nullptr;
  const bool has_e = s.find("youngs_modulus", {}) != nullptr;
  if (has_ratio && has_e)
    s.fail("youngs_modulus", "given together with stiffness_ratio; expected one of the two (E = 214.99 r N/mm^2)");
  s.number("stiffness_ratio", {}, D.stiffness_ratio, within(1e-3 / 214.99, 1e7 / 214.99),
           "a ratio r in [4.7e-6, 4.7e4] (E = 214.99 r N/mm^2, from a soft gel's 1e-3 to 1e7 N/mm^2, above "
           "diamond's 1.2e6)");
  s.number("youngs_modulus", {}, D.youngs_modulus, within(1e-3, 1e7),
           "a modulus in [1e-3, 1e7] N/mm^2 (from a soft gel's to above diamond's 1.2e6)");
  s.number("poisson", {}, D.poisson, [](double v) { return v > -1 && v < 0.5; }, "a Poisson ratio in (-1, 0.5)");
  s.number("density", {}, D.density, within(1e-12, 1e-7),
           "a density in [1e-12, 1e-7] t/mm^3 (from an aerogel's 1 kg/m^3 to above osmium's 22.6 g/cm^3; "
           "3.7 g/cm^3 = 3.7e-9)");
  s.number("thickness", {}, D.thickness, within(1e-6, 1e6), "an out-of-plane depth in [1e-6, 1e6] mm (1 nm to 1 km)");
  if (D.method != Dynamics::Method::ue)
    reject_if_given(s, "internal_stiffness_factor", "sets the internal joints of method = \"ue\" only (bolted methods have none)",
                    "method is \"" + method + "\"", "method = \"ue\"");
  s.number("internal_stiffness_factor", {}, D.internal_stiffness_factor, within(1, 1e4),
           "a factor in [1, 1e4] (internal joint stiffness = factor * E / brick_height: stiffer than the brick, "
           "about 50 in the dissertation; beyond 1e4 it only shrinks the stable step)");

  // damping: "table" | "none", or explicit alpha_d / beta_d (then no damping key)
  const bool has_alpha = s.find("alpha_d", {}) != nullptr, has_beta = s.find("beta_d", {}) != nullptr;
  std::string damping;
  s.string("damping", damping, {"table", "none"},
           "\"table\" (Table 4.2 by brick count and ratio) or \"none\"; or give alpha_d and beta_d instead");
  if ((has_alpha || has_beta) && !damping.empty())
    s.fail(has_alpha ? "alpha_d" : "beta_d",
           "given together with damping = \"" + damping + "\"; expected either damping or alpha_d/beta_d");
  if (has_alpha || has_beta) {
    D.damping = Dynamics::Damping::explicit_values;
    s.number("alpha_d", {}, D.alpha_d, non_negative, "a non-negative mass-proportional damping in 1/s");
    s.number("beta_d", {}, D.beta_d, non_negative, "a non-negative stiffness-proportional damping in s");
  } else {
    D.damping = damping == "none" ? Dynamics::Damping::none : Dynamics::Damping::table;
  }

  // time step: dt, or a fraction of the critical step (default 0.5)
  const bool has_dt = s.find("dt", {}) != nullptr, has_frac = s.find("dt_fraction", {}) != nullptr;
  if (has_dt && has_frac) s.fail("dt_fraction", "given together with dt; expected one of the two");
  s.number("dt", {}, D.dt, positive, "a positive time step in s");
  s.number("dt_fraction", {}, D.dt_fraction, [](double v) { return v > 0 && v <= 1; },
           "a fraction of the critical step in (0, 1]");
  if (has_dt) D.dt_fraction = 0;

  s.number("end_time", {}, D.end_time, positive, "a positive end time in s", true);
  s.number("rate", {}, D.rate, within(0, 1e7),
           "an opening rate dD/dt in [0, 1e7] mm/s (10 km/s, faster than any solid's waves: the opening of a "
           "quasi-static or impact test is far below)");
  std::string ramp = D.ramp == Dynamics::Ramp::smooth ? "smooth" : "linear";
  s.string("ramp", ramp, {"linear", "smooth"},
           "\"linear\" (rate grows linearly over ramp_time) or \"smooth\" (rate ramps as (1 - cos(pi t / ramp_time)) / 2)");
  D.ramp = ramp == "smooth" ? Dynamics::Ramp::smooth : Dynamics::Ramp::linear;
  s.number("ramp_time", {}, D.ramp_time, non_negative, "a non-negative time in s");
  s.number("thermal_strain", {}, D.thermal_strain, [](double v) { return std::abs(v) < 0.1; },
           "an eigenstrain with |Theta| < 0.1 (small strain)");
  s.number("force_top", {}, D.force_top, within(-1e6, 1e6),
           "a force per unit length in [-1e6, 1e6] N/mm (a line load that crushes any solid long before: 1e6 N/mm "
           "over a 1 mm-deep specimen is 1e6 N/mm^2 on a 1 mm face)");
  s.boolean("share_element_matrices", D.share_element_matrices);
  s.number("balance_tolerance", {}, D.balance_tolerance, [](double v) { return v >= 0 && v < 1; },
           "a relative residual in [0, 1) (0: not checked)");
  s.string("dt_mode", D.dt_mode, {"fixed", "adaptive"},
           "\"fixed\" (stop when the estimated critical step falls below dt) or \"adaptive\" (dt follows it)");
  s.number("sliver_step_ratio", {}, D.sliver_step_ratio, within(0, 1),
           "a fraction of the median element's step bound in [0, 1] (0: no mass scaling of slivers)");
  {
    long nq = D.quadrature_points;
    s.integer("quadrature_points", {}, nq, 1, 8, "an integer in [1, 8] (Gauss-Legendre points per interface)");
    D.quadrature_points = static_cast<int>(nq);
  }
  s.integer("csv_interval", {}, D.csv_interval, 1, 1000000000000L, "a step count >= 1");
  s.integer("dump_interval", {}, D.dump_interval, 0, 1000000000000L, "a step count >= 0 (0: first and last only)");

  // unknown keys before the checks that combine keys: a misspelt key is named as such
  s.reject_unknown({"method", "bie_solve", "bie_block", "bie_iterations", "bie_scheme", "stiffness_ratio", "youngs_modulus", "poisson", "density", "thickness",
                    "internal_stiffness_factor", "damping", "alpha_d", "beta_d", "dt", "dt_fraction", "end_time",
                    "rate", "ramp", "ramp_time", "thermal_strain", "force_top", "share_element_matrices",
                    "csv_interval", "dump_interval", "balance_tolerance", "dt_mode", "sliver_step_ratio", "quadrature_points"});
  if (D.rate == 0 && D.force_top == 0 && D.thermal_strain == 0)
    s.fail("rate", "no load: rate, force_top and thermal_strain are all zero; expected at least one non-zero");
  if (D.ramp_time > D.end_time)
    s.fail("ramp_time", "ramp longer than the run; expected ramp_time <= end_time");
  // (the step count end_time / dt is checked against [limits] max_time_steps by check_limits)

}

}  // namespace nacre::deck::detail
