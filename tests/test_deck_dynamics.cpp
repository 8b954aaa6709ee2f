// SPDX-License-Identifier: BSD-3-Clause
// The [dynamics] section: defaults, every key read, and every error naming file, line and key.
#include <nacre/app/run_dynamics.hpp>
#include <nacre/deck/deck.hpp>

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_string.hpp>

#include <string>

using namespace nacre::deck;
using Catch::Matchers::ContainsSubstring;
using Catch::Matchers::StartsWith;

namespace {
// line 15 is [dynamics], line 16 its first key
const std::string dyn_base = R"([geometry]
width = 0.63
height = 0.3
brick_width = 0.105
brick_height = 0.03
notch_length = 0.21

[mortar]
k = 7000.0
x1 = 0.002
x2 = 0.002

[load]
final_displacement = 0.001
[dynamics]
end_time = 1e-5
rate = 100.0
)";

std::string dyn_error_of(const std::string& text) {
  try {
    (void)parse_deck_string(text, "dyn.toml");
  } catch (const DeckError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("a [dynamics] section selects the dynamic solver, with documented defaults", "[deck][dyn]") {
  const Deck d = parse_deck_string(dyn_base, "dyn.toml");
  const auto& D = d.dynamics;
  CHECK(D.enabled);
  CHECK(D.method == Dynamics::Method::be);
  CHECK(D.modulus() == 214.99 * 500);
  CHECK(D.ratio() == 500);
  CHECK(D.poisson == 0.35);
  CHECK(D.density == 3.7e-9);
  CHECK(D.damping == Dynamics::Damping::table);
  CHECK(D.dt == 0);
  CHECK(D.dt_fraction == 0.5);
  CHECK(D.end_time == 1e-5);
  CHECK(D.rate == 100.0);
  CHECK(D.csv_interval == 100);
  CHECK(D.dump_interval == 10000);
  CHECK_FALSE(parse_deck_string(R"([geometry]
width = 40.0
height = 24.0
brick_width = 3.5
brick_height = 1.0
[mortar]
[load]
final_displacement = 0.05
)", "mc.toml").dynamics.enabled);
}

TEST_CASE("every [dynamics] key is read", "[deck][dyn]") {
  const Deck d = parse_deck_string(dyn_base + R"(method = "ue"
youngs_modulus = 2149.9
poisson = 0.3
density = 2e-9
thickness = 0.5
internal_stiffness_factor = 40
alpha_d = 1000.0
beta_d = 1e-8
dt = 1e-9
ramp = "smooth"
ramp_time = 1e-6
thermal_strain = 1e-4
force_top = 2.5
share_element_matrices = false
csv_interval = 10
dump_interval = 0
)", "dyn.toml");
  const auto& D = d.dynamics;
  CHECK(D.method == Dynamics::Method::ue);
  CHECK(D.modulus() == 2149.9);
  CHECK(D.ratio() == 10.0);
  CHECK(D.poisson == 0.3);
  CHECK(D.density == 2e-9);
  CHECK(D.thickness == 0.5);
  CHECK(D.internal_stiffness_factor == 40);
  CHECK(D.damping == Dynamics::Damping::explicit_values);
  CHECK(D.alpha_d == 1000.0);
  CHECK(D.beta_d == 1e-8);
  CHECK(D.dt == 1e-9);
  CHECK(D.dt_fraction == 0);
  CHECK(D.ramp == Dynamics::Ramp::smooth);
  CHECK(D.ramp_time == 1e-6);
  CHECK(D.thermal_strain == 1e-4);
  CHECK(D.force_top == 2.5);
  CHECK_FALSE(D.share_element_matrices);
  CHECK(D.csv_interval == 10);
  CHECK(D.dump_interval == 0);
  CHECK(parse_deck_string(dyn_base + "damping = \"none\"\n", "dyn.toml").dynamics.damping == Dynamics::Damping::none);
}

TEST_CASE("bad [dynamics] values are errors with file, line and key", "[deck][dyn]") {
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"biec\"\n"), StartsWith("dyn.toml:18: dynamics.method: unknown value \"biec\""));
  CHECK(dyn_error_of(dyn_base + "method = \"bie\"\n").empty());
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_solve = \"lu\"\n"), StartsWith("dyn.toml:19: dynamics.bie_solve: unknown value \"lu\""));
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_block = 3\n"), StartsWith("dyn.toml:19: dynamics.bie_block:"));
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_iterations = 0\n"), StartsWith("dyn.toml:19: dynamics.bie_iterations:"));
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_iterations = 17\n"), StartsWith("dyn.toml:19: dynamics.bie_iterations:"));
  CHECK(parse_deck_string(dyn_base + "method = \"bie\"\nbie_iterations = 3\n", "dyn.toml").dynamics.bie_iterations == 3);
  CHECK(parse_deck_string(dyn_base, "dyn.toml").dynamics.bie_iterations == 2);
  CHECK(parse_deck_string(dyn_base, "dyn.toml").dynamics.bie_scheme == "auto");
  CHECK(parse_deck_string(dyn_base + "method = \"bie\"\nbie_iterations = 3\n", "dyn.toml").dynamics.bie_scheme == "iterate");
  CHECK(parse_deck_string(dyn_base + "method = \"bie\"\nbie_scheme = \"split\"\n", "dyn.toml").dynamics.bie_scheme == "split");
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_scheme = \"splitt\"\n"), StartsWith("dyn.toml:19: dynamics.bie_scheme:"));
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_scheme = \"split\"\nbie_iterations = 3\n"),
             StartsWith("dyn.toml:20: dynamics.bie_iterations:"));
  CHECK_THAT(dyn_error_of(dyn_base + "method = 1\n"), StartsWith("dyn.toml:18: dynamics.method: wrong type"));
  CHECK_THAT(dyn_error_of(dyn_base + "stiffness_ratio = -1\n"), StartsWith("dyn.toml:18: dynamics.stiffness_ratio: value -1 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "stiffness_ratio = 10\nyoungs_modulus = 2000\n"),
             StartsWith("dyn.toml:19: dynamics.youngs_modulus: given together with stiffness_ratio"));
  CHECK_THAT(dyn_error_of(dyn_base + "poisson = 0.5\n"), StartsWith("dyn.toml:18: dynamics.poisson: value 0.5 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "dt = 1e-9\ndt_fraction = 0.5\n"), StartsWith("dyn.toml:19: dynamics.dt_fraction: given together with dt"));
  CHECK_THAT(dyn_error_of(dyn_base + "dt_fraction = 1.5\n"), StartsWith("dyn.toml:18: dynamics.dt_fraction: value 1.5 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "dt = 0\n"), StartsWith("dyn.toml:18: dynamics.dt: value 0 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "damping = \"table\"\nalpha_d = 1.0\n"),
             StartsWith("dyn.toml:19: dynamics.alpha_d: given together with damping"));
  CHECK_THAT(dyn_error_of(dyn_base + "damping = \"rayleigh\"\n"), StartsWith("dyn.toml:18: dynamics.damping: unknown value"));
  CHECK_THAT(dyn_error_of(dyn_base + "ramp = \"cosine\"\n"), StartsWith("dyn.toml:18: dynamics.ramp: unknown value"));
  // the stability monitor's keys (docs/dynamics.md "Stability monitor")
  CHECK(parse_deck_string(dyn_base, "dyn.toml").dynamics.balance_tolerance == 1e-3);
  CHECK(parse_deck_string(dyn_base, "dyn.toml").dynamics.dt_mode == "fixed");
  CHECK(parse_deck_string(dyn_base, "dyn.toml").dynamics.sliver_step_ratio == 0.5);
  CHECK(parse_deck_string(dyn_base + "dt_mode = \"adaptive\"\nbalance_tolerance = 0.0\nsliver_step_ratio = 0.0\n",
                          "dyn.toml").dynamics.dt_mode == "adaptive");
  CHECK_THAT(dyn_error_of(dyn_base + "balance_tolerance = -1e-3\n"),
             StartsWith("dyn.toml:18: dynamics.balance_tolerance: value -0.001 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "balance_tolerance = 1.0\n"), StartsWith("dyn.toml:18: dynamics.balance_tolerance: value 1 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "dt_mode = \"auto\"\n"), StartsWith("dyn.toml:18: dynamics.dt_mode: unknown value"));
  CHECK_THAT(dyn_error_of(dyn_base + "sliver_step_ratio = 1.5\n"), StartsWith("dyn.toml:18: dynamics.sliver_step_ratio: value 1.5 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "ramp_time = 1.0\n"), StartsWith("dyn.toml:18: dynamics.ramp_time: ramp longer than the run"));
  CHECK_THAT(dyn_error_of(dyn_base + "csv_interval = 0\n"), StartsWith("dyn.toml:18: dynamics.csv_interval: value 0 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "share_element_matrices = 1\n"), StartsWith("dyn.toml:18: dynamics.share_element_matrices: wrong type"));
  CHECK_THAT(dyn_error_of(dyn_base + "rate = 0\n"), StartsWith("dyn.toml:18: (syntax)"));
  std::string no_load = dyn_base;
  no_load.replace(no_load.find("rate = 100.0"), 12, "rate = 0.0");
  CHECK_THAT(dyn_error_of(no_load), StartsWith("dyn.toml:17: dynamics.rate: no load"));
  std::string no_end = dyn_base;
  no_end.replace(no_end.find("end_time = 1e-5"), 15, "");
  CHECK_THAT(dyn_error_of(no_end), ContainsSubstring("dynamics.end_time: missing"));
  CHECK_THAT(dyn_error_of(dyn_base + "stifness_ratio = 10\n"), StartsWith("dyn.toml:18: dynamics.stifness_ratio: unknown key"));
}

TEST_CASE("Monte Carlo keys in a dynamic deck are errors, not silently ignored", "[deck][dyn]") {
  CHECK_THAT(dyn_error_of(dyn_base + "[solver]\nTEMP = 1e-7\n"), StartsWith("dyn.toml:18: solver: the Monte Carlo [solver] section"));
  std::string load_step = dyn_base;
  load_step.replace(load_step.find("final_displacement = 0.001"), 26, "final_displacement = 0.001\nadaptive = true");
  CHECK_THAT(dyn_error_of(load_step), StartsWith("dyn.toml:15: load.adaptive: a Monte Carlo load-step key"));
  CHECK_THAT(dyn_error_of(dyn_base + "[output]\nDumpInter = 5\n"), StartsWith("dyn.toml:19: output.DumpInter: counts Monte Carlo load steps"));
  // the Monte Carlo check initial_step <= final_displacement does not apply to a dynamic deck
  CHECK(dyn_error_of(dyn_base).empty());
}

TEST_CASE("deck dynamics: bie_scheme = \"auto\" takes the split step where C != 0, eq. 4.6's iterations otherwise",
          "[deck][dynamics]") {
  auto scheme = [](const std::string& keys) {
    const auto d = parse_deck_string(dyn_base + "method = \"bie\"\n" + keys, "dyn.toml");
    return nacre::app::dynamics_params(d, 10000).bie_scheme;
  };
  using nacre::dyn::BieScheme;
  CHECK(scheme("damping = \"none\"\n") == BieScheme::iterate);
  CHECK(scheme("damping = \"table\"\n") == BieScheme::split);
  CHECK(scheme("alpha_d = 1e5\nbeta_d = 0.0\n") == BieScheme::split);
  CHECK(scheme("alpha_d = 0.0\nbeta_d = 1e-7\n") == BieScheme::split);
  CHECK(scheme("alpha_d = 0.0\nbeta_d = 0.0\n") == BieScheme::iterate);
  // an iteration count asks for the iterated step; an explicit scheme is kept as given
  CHECK(scheme("damping = \"table\"\nbie_iterations = 2\n") == BieScheme::iterate);
  CHECK(scheme("damping = \"table\"\nbie_scheme = \"iterate\"\n") == BieScheme::iterate);
  CHECK(scheme("damping = \"none\"\nbie_scheme = \"split\"\n") == BieScheme::split);
}

TEST_CASE("deck dynamics: quadrature_points reaches the solver, BIE keys with another method and misspelt keys are named",
          "[deck][dyn]") {
  const Deck d = parse_deck_string(dyn_base + "quadrature_points = 2\n", "dyn.toml");
  CHECK(d.dynamics.quadrature_points == 2);
  CHECK(nacre::app::dynamics_params(d, 65).quadrature_points == 2);
  CHECK(nacre::app::dynamics_params(parse_deck_string(dyn_base, "dyn.toml"), 65).quadrature_points == 4);
  CHECK_THAT(dyn_error_of(dyn_base + "quadrature_points = 9\n"), StartsWith("dyn.toml:18: dynamics.quadrature_points"));
  // the Monte Carlo solver integrates exactly: [solver] has no such key
  std::string mc = dyn_base.substr(0, dyn_base.find("[dynamics]")) + "initial_step = 0.0001\n[solver]\nquadrature_points = 4\n";
  CHECK_THAT(dyn_error_of(mc), ContainsSubstring("solver.quadrature_points: unknown key"));
  CHECK_THAT(dyn_error_of(dyn_base + "bie_iterations = 2\n"),
             StartsWith("dyn.toml:18: dynamics.bie_iterations: applies to method = \"bie\" only"));
  CHECK(dyn_error_of(dyn_base + "method = \"bie\"\nbie_iterations = 2\n").empty());
  std::string typo = dyn_base;
  typo.replace(typo.find("final_displacement = 0.001"), 26, "final_displacement = 0.001\nbendng = 1.0");
  CHECK_THAT(dyn_error_of(typo), StartsWith("dyn.toml:15: load.bendng: unknown key"));
}

TEST_CASE("deck dynamics: a key the method ignores is an error, and every physical value has a range", "[deck][dyn]") {
  // keys of one method or one solve variant, given with another: refused, not ignored
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"be\"\ninternal_stiffness_factor = 2.0\n"),
             StartsWith("dyn.toml:19: dynamics.internal_stiffness_factor: sets the internal joints of method = \"ue\" only"));
  CHECK_THAT(dyn_error_of(dyn_base + "internal_stiffness_factor = 2.0\n"),  // the default method, be
             StartsWith("dyn.toml:18: dynamics.internal_stiffness_factor:"));
  CHECK(dyn_error_of(dyn_base + "method = \"ue\"\ninternal_stiffness_factor = 2.0\n").empty());
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_block = 4\n"),
             StartsWith("dyn.toml:19: dynamics.bie_block: sets the block rows of bie_solve = \"reordered\" only"));
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"bie\"\nbie_solve = \"row\"\nbie_block = 4\n"),
             StartsWith("dyn.toml:20: dynamics.bie_block:"));
  CHECK(parse_deck_string(dyn_base + "method = \"bie\"\nbie_solve = \"reordered\"\nbie_block = 5\n", "dyn.toml")
            .dynamics.bie_block == 5);
  // values that would reach the first step only to stop as unstable (or overflow): deck errors
  for (const char* bad : {"youngs_modulus = 1e300", "youngs_modulus = 1e-300", "stiffness_ratio = 1e300",
                          "stiffness_ratio = 1e-300", "density = 1e300", "density = 1e-300", "thickness = 1e300",
                          "force_top = 1e300", "force_top = -1e300"}) {
    INFO(bad);
    const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
    CHECK_THAT(dyn_error_of(dyn_base + bad + "\n"), StartsWith("dyn.toml:18: dynamics." + key + ": value"));
    CHECK_THAT(dyn_error_of(dyn_base + bad + "\n"), ContainsSubstring("out of range"));
  }
  std::string fast = dyn_base;
  fast.replace(fast.find("rate = 100.0"), 12, "rate = 1e300");
  CHECK_THAT(dyn_error_of(fast), StartsWith("dyn.toml:17: dynamics.rate: value 1e+300 out of range"));
  CHECK_THAT(dyn_error_of(dyn_base + "method = \"ue\"\ninternal_stiffness_factor = 1e300\n"),
             StartsWith("dyn.toml:19: dynamics.internal_stiffness_factor: value"));
  // the ends of the ranges are real materials: a gel, diamond, an aerogel, osmium
  CHECK(dyn_error_of(dyn_base + "youngs_modulus = 1e-3\ndensity = 1e-12\n").empty());
  CHECK(dyn_error_of(dyn_base + "youngs_modulus = 1.2e6\ndensity = 2.26e-8\n").empty());
  CHECK(dyn_error_of(dyn_base + "force_top = -1e5\n").empty());
}
