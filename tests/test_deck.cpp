// SPDX-License-Identifier: BSD-3-Clause
// Deck parsing: every error class names file, line, key and what was expected.
#include <nacre/deck/deck.hpp>

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_string.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

using namespace nacre::deck;
using Catch::Matchers::ContainsSubstring;
using Catch::Matchers::StartsWith;

namespace {
const std::string base = R"([geometry]
width = 40.0
height = 24.0
brick_width = 3.5
brick_height = 1.0
notch_length = 14.0

[mortar]
k = 100.0
x1 = 0.002
x2 = 0.004

[load]
final_displacement = 0.05
)";

std::string error_of(const std::string& text) {
  try {
    (void)parse_deck_string(text, "deck.toml");
  } catch (const DeckError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("a minimal deck parses with defaults", "[deck]") {
  const Deck d = parse_deck_string(base, "deck.toml");
  CHECK(d.geometry.width == 40.0);
  CHECK(d.geometry.notch_y == 12.0);  // default: mid-height
  CHECK(d.mortar.head.k == 100.0);
  CHECK(d.solver.stol == 0.002);
  CHECK(d.solver.rng == "philox");
}

TEST_CASE("the paper's Table 2.1 names are accepted as written", "[deck]") {
  const Deck d = parse_deck_string(base + R"(InitialLoadStepSize = 0.01
MinLoadStepSize = 0.005
MaxLoadStepSize = 0.02
[solver]
STOL = 0.002
RTOL = 0.03
ConvergenceRep = 1500
WindowSize = 3500
TEMP = 0.00075
AdaptInter = 5e3
InitialStepSize = 0.001
MinStepSize = 0.0001
MaxStepSize = 0.02
InitialRotSize = 0.001
MinRotSize = 0.0001
MaxRotSize = 0.02
AmpFactor = 1
StructSteps = 1
WindowMul = 20
WindowUpperMul = 50000
[output]
DumpInter = 10e0
)",
                                   "deck.toml");
  CHECK(d.solver.window_size == 3500);
  CHECK(d.solver.adapt_interval == 5000);
  CHECK(d.solver.temperature == 0.00075);
  CHECK(d.load.min_step == 0.005);
  CHECK(d.output.dump_interval == 10);
}

TEST_CASE("unknown keys are errors with line and the list of valid keys", "[deck]") {
  const auto e = error_of(base + "widht = 3\n");
  CHECK_THAT(e, StartsWith("deck.toml:15: load.widht: unknown key"));
  CHECK_THAT(e, ContainsSubstring("final_displacement"));
  CHECK_THAT(error_of(base + "[solvr]\nx = 1\n"), StartsWith("deck.toml:15: solvr: unknown key"));
}

TEST_CASE("wrong types are errors", "[deck]") {
  CHECK_THAT(error_of(base + "tension = \"a lot\"\n"),
             StartsWith("deck.toml:15: load.tension: wrong type (a string); expected a number"));
  CHECK_THAT(error_of(base + "[solver]\nWindowSize = 12.5\n"), StartsWith("deck.toml:16: solver.WindowSize: wrong type"));
}

TEST_CASE("missing required values are errors", "[deck]") {
  std::string text = base;
  text.replace(text.find("height = 24.0\n"), 14, "");
  CHECK_THAT(error_of(text), StartsWith("deck.toml:1: geometry.height: missing; expected a positive length"));
  CHECK_THAT(error_of("[geometry]\nwidth = 1\n"), ContainsSubstring("missing"));
}

TEST_CASE("predictor: true, false, \"damped\" or \"secant\"", "[deck]") {
  using Kind = Load::Predictor;
  auto with = [&](const std::string& v) {
    return parse_deck_string(base + "predictor = " + v + "\n", "deck.toml").load.predictor;
  };
  CHECK(parse_deck_string(base, "deck.toml").load.predictor == Kind::none);
  CHECK(with("true") == Kind::automatic);
  CHECK(with("false") == Kind::none);
  CHECK(with("\"damped\"") == Kind::damped);
  CHECK(with("\"secant\"") == Kind::secant);
  CHECK_THAT(error_of(base + "predictor = \"linear\"\n"),
             StartsWith("deck.toml:15: load.predictor: unknown value \"linear\"; expected true, false, \"damped\" "
                        "(eq. 2.11) or \"secant\""));
  CHECK_THAT(error_of(base + "predictor = 1\n"),
             StartsWith("deck.toml:15: load.predictor: wrong type (an integer); expected true, false, \"damped\""));
}

TEST_CASE("out-of-range values are errors", "[deck]") {
  CHECK_THAT(error_of(base + "[solver]\nRTOL = 3\n"), StartsWith("deck.toml:16: solver.RTOL: value 3 out of range"));
  CHECK_THAT(error_of(base + "[solver]\nTEMP = -1\n"), ContainsSubstring("solver.TEMP: value -1 out of range"));
  CHECK_THAT(error_of(base + "[solver]\nAmpFactor = 2\n"), ContainsSubstring("1 (the only value the paper uses)"));
  CHECK_THAT(error_of(base + "[output]\nheartbeat = -1\n"),
             StartsWith("deck.toml:16: output.heartbeat: value -1 out of range; expected seconds >= 0 (0: none)"));
}

TEST_CASE("output.heartbeat: default 60 s, 0 switches it off", "[deck]") {
  CHECK(parse_deck_string(base, "deck.toml").output.heartbeat == 60.0);
  CHECK(parse_deck_string(base + "[output]\nheartbeat = 0\n", "deck.toml").output.heartbeat == 0.0);
  CHECK(parse_deck_string(base + "[output]\nheartbeat = 5\n", "deck.toml").output.heartbeat == 5.0);
}

TEST_CASE("inconsistent values are errors", "[deck]") {
  std::string text = base;
  text.replace(text.find("notch_length = 14.0"), 19, "notch_length = 50.0");
  CHECK_THAT(error_of(text), StartsWith("deck.toml:6: geometry.notch_length: notch longer than the specimen"));
  CHECK_THAT(error_of(base + "[mortar.bed]\nx1 = 0.01\nx2 = 0.005\n"),
             StartsWith("deck.toml:17: mortar.bed.x2: x2 = 0.005"));
  CHECK_THAT(error_of(base + "[solver]\nMinStepSize = 0.1\nMaxStepSize = 0.01\n"), ContainsSubstring("minimum exceeds the maximum"));
  CHECK_THAT(error_of(base + "initial_step = 1.0\n"), ContainsSubstring("exceeds final_displacement"));
}

TEST_CASE("duplicates and syntax errors are errors", "[deck]") {
  CHECK_THAT(error_of(base + "[solver]\nTEMP = 1\ntemperature = 2\n"), ContainsSubstring("given twice"));
  CHECK_THAT(error_of(base + "[solver\n"), StartsWith("deck.toml:15: (syntax)"));
  CHECK_THAT(error_of(base + "[random]\ngenerator = \"rand\"\n"), ContainsSubstring("random.generator: expected one of"));
  CHECK_THAT(error_of(base + "[solver]\nstep_mode = \"each\"\n"),
             StartsWith("deck.toml:16: solver.step_mode: unknown value \"each\"; expected \"global\" or \"per-brick\""));
  CHECK(parse_deck_string(base + "[solver]\nstep_mode = \"per-brick\"\n", "deck.toml").solver.per_brick_steps);
}

TEST_CASE("the app exits with 2 and creates no output for a bad deck", "[deck][app]") {
  const char* exe = NACRE_EXE_PATH;
  const auto dir = std::filesystem::temp_directory_path() / "nacre_bad_deck_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto deck = dir / "bad.toml";
  std::string text = base + "[output]\ndirectory = \"" + (dir / "out").string() + "\"\n[solver]\nRTOL = 7\n";
  FILE* f = std::fopen(deck.c_str(), "w");
  std::fputs(text.c_str(), f);
  std::fclose(f);
  const std::string cmd = std::string(exe) + " " + deck.string() + " > " + (dir / "log").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  CHECK(WEXITSTATUS(rc) == 2);
  CHECK_FALSE(std::filesystem::exists(dir / "out"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("convergence keys: defaults, choices and ranges with file:line", "[deck]") {
  const Deck d = parse_deck_string(base, "deck.toml");
  CHECK(d.solver.convergence == "residual");
  CHECK(d.solver.residual_tolerance == 1e-6);
  CHECK(d.solver.polish == "fire");
  const Deck w = parse_deck_string(base + "[solver]\nconvergence = \"window\"\npolish = \"newton\"\n"
                                          "residual_tolerance = 1e-8\npolish_iterations = 10\n", "deck.toml");
  CHECK(w.solver.convergence == "window");
  CHECK(w.solver.polish == "newton");
  CHECK(w.solver.residual_tolerance == 1e-8);
  CHECK(w.solver.polish_iterations == 10);
  CHECK_THAT(error_of(base + "[solver]\nconvergence = \"energy\"\n"),
             StartsWith("deck.toml:16: solver.convergence:"));
  CHECK_THAT(error_of(base + "[solver]\nconvergence = \"energy\"\n"), ContainsSubstring("\"residual\" or \"window\""));
  CHECK_THAT(error_of(base + "[solver]\nresidual_tolerance = 0\n"),
             StartsWith("deck.toml:16: solver.residual_tolerance: value 0 out of range"));
  CHECK_THAT(error_of(base + "[solver]\nresidual_tolerance = 2\n"), ContainsSubstring("a tolerance in (0, 1)"));
  CHECK_THAT(error_of(base + "[solver]\npolish = \"lbfgs\"\n"), ContainsSubstring("solver.polish:"));
  CHECK_THAT(error_of(base + "[solver]\npolish_iterations = 0\n"), ContainsSubstring("solver.polish_iterations:"));
  CHECK(d.solver.relaxation == "monte-carlo");
  CHECK(parse_deck_string(base + "[solver]\nrelaxation = \"gradient\"\n", "deck.toml").solver.relaxation == "gradient");
  CHECK_THAT(error_of(base + "[solver]\nrelaxation = \"lbfgs\"\n"),
             StartsWith("deck.toml:16: solver.relaxation:"));
  CHECK_THAT(error_of(base + "[solver]\nrelaxation = \"gradient\"\npolish = \"none\"\n"),
             ContainsSubstring("expected polish = \"fire\", \"newton\" or \"trust-region\""));
  // the trust-region Newton method: relaxation newton / auto, its caps, the reversible law only
  CHECK(parse_deck_string(base + "[solver]\nrelaxation = \"newton\"\n", "deck.toml").solver.relaxation == "newton");
  CHECK(parse_deck_string(base + "[solver]\nrelaxation = \"auto\"\n", "deck.toml").solver.relaxation == "auto");
  CHECK(d.solver.cg_iterations == 500);
  CHECK(d.solver.burst_cycles == 200);
  CHECK_THAT(error_of(base + "[solver]\ncg_iterations = 0\n"), StartsWith("deck.toml:16: solver.cg_iterations:"));
  CHECK_THAT(error_of(base + "[solver]\nburst_cycles = -1\n"), StartsWith("deck.toml:16: solver.burst_cycles:"));
  // a key of a method the deck does not use is an error, not ignored (one rule for both families)
  CHECK_THAT(error_of(base + "[solver]\nburst_cycles = 100\n"),
             StartsWith("deck.toml:16: solver.burst_cycles: sets the Monte Carlo bursts of relaxation = \"auto\" only"));
  CHECK(error_of(base + "[solver]\nrelaxation = \"auto\"\nburst_cycles = 100\n").empty());
  CHECK_THAT(error_of(base + "[solver]\npresim_cycles = 5\n"),
             StartsWith("deck.toml:16: solver.presim_cycles: times the candidates of colouring = \"fastest\" only"));
  CHECK(error_of(base + "[solver]\ncolouring = \"fastest\"\npresim_cycles = 5\n").empty());
  for (const char* k : {"cg_iterations = 50", "newton_preconditioner = \"block-jacobi\"", "factor_precision = \"double\""}) {
    INFO(k);
    CHECK_THAT(error_of(base + "[solver]\n" + k + "\n"), ContainsSubstring("sets the Newton method, which this deck does not use"));
    CHECK(error_of(base + "[solver]\nrelaxation = \"newton\"\n" + k + "\n").empty());
    CHECK(error_of(base + "[solver]\npolish = \"trust-region\"\n" + k + "\n").empty());
  }
  std::string cyclic = base;  // a programme that turns back: damage "auto" is irreversible
  const std::string fin = "final_displacement = 0.05";
  cyclic.replace(cyclic.find(fin), fin.size(), "programme = [0.02, 0.01, 0.05]");
  CHECK_THAT(error_of(cyclic + "[solver]\nrelaxation = \"newton\"\n"),
             ContainsSubstring("solver.relaxation: the trust-region Newton method needs the reversible law"));
  CHECK_THAT(error_of(cyclic + "[solver]\npolish = \"trust-region\"\n"),
             ContainsSubstring("solver.polish: the trust-region"));
  CHECK(parse_deck_string(cyclic + "[solver]\nrelaxation = \"auto\"\n", "deck.toml").solver.relaxation == "auto");
  CHECK(parse_deck_string(base + "[solver]\npolish = \"anneal\"\n", "deck.toml").solver.polish == "anneal");
  CHECK_THAT(error_of(base + "[solver]\nrelaxation = \"gradient\"\npolish = \"anneal\"\n"),
             ContainsSubstring("not \"anneal\""));
}
