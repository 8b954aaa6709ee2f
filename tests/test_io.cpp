// SPDX-License-Identifier: BSD-3-Clause
// Outputs and checkpoints: atomic commits that keep the previous file on a failed write,
// checkpoints whose checksum catches any change, MC checkpoint range checks (with valid
// checksums, so only the range check can refuse them), restart fingerprints that name the
// differing key, strict dump names, stale temporaries, and the colouring rule.
#include <nacre/core/build_info.hpp>
#include <nacre/app/restart.hpp>
#include <nacre/app/run_dynamics.hpp>
#include <nacre/deck/limits.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/io/atomic_file.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/results.hpp>
#include <nacre/io/state_compare.hpp>
#include <nacre/mc/output.hpp>
#include <nacre/mc/solver.hpp>

#include "../src/app/dyn_fields.hpp"

#include <catch2/catch_test_macros.hpp>
#include <catch2/matchers/catch_matchers_string.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <unistd.h>

using namespace nacre;
using Catch::Matchers::ContainsSubstring;

namespace {

std::filesystem::path scratch(const std::string& name) {
  auto p = std::filesystem::temp_directory_path() / ("nacre_test_io_" + std::to_string(::getpid())) / name;
  std::filesystem::create_directories(p);
  return p;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool has_temporary(const std::filesystem::path& dir) {
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
  return false;
}

/// Sets NACRE_INJECT_WRITE_FAILURE for its lifetime.
struct Inject {
  explicit Inject(const char* names) { ::setenv("NACRE_INJECT_WRITE_FAILURE", names, 1); }
  ~Inject() { ::unsetenv("NACRE_INJECT_WRITE_FAILURE"); }
};

io::Checkpoint sample() {
  io::Checkpoint c;
  c.fingerprint = "0123456789abcdef";
  c.integers["step"] = 7;
  c.integers["big"] = (std::int64_t(1) << 60) + 3;  // not representable as a double: stored exactly
  c.reals["displacement"] = 0.125;
  c.strings["solver"] = "test";
  c.arrays["pose"] = {1.0, -2.5, 3e-300, 0.0};
  c.arrays["empty"] = {};
  return c;
}

deck::Deck mc_deck() {
  deck::Deck d;
  d.geometry.width = 21, d.geometry.height = 8, d.geometry.notch_length = 8, d.geometry.notch_y = 4;
  d.geometry.brick_width = 3.5, d.geometry.brick_height = 1.0;
  d.mortar.bed = {100.0, 0.002, 0.004};
  d.mortar.head = {100.0, 0.001, 0.002};
  d.load.bending = 1.0;
  d.load.final_displacement = 0.008;
  d.load.initial_step = d.load.min_step = d.load.max_step = 0.004;
  d.solver.temperature = 1e-7;
  d.solver.step = 1e-4, d.solver.min_step = 1e-7, d.solver.max_step = 1e-3;
  d.solver.rot_step = 1e-4, d.solver.min_rot_step = 1e-7, d.solver.max_rot_step = 1e-3;
  d.solver.adapt_interval = 20;
  d.solver.window_size = 60, d.solver.convergence_rep = 20;
  d.solver.colouring = "natural";
  d.output.hdf5 = false, d.output.charts = false;
  return d;
}

}  // namespace

TEST_CASE("a checkpoint of named arrays round-trips exactly", "[io][checkpoint]") {
  const auto dir = scratch("roundtrip");
  const io::Checkpoint c = sample();
  io::write_checkpoint(dir / "cp.h5", c);
  const io::Checkpoint back = io::read_checkpoint(dir / "cp.h5");
  CHECK(back.fingerprint == c.fingerprint);
  CHECK(back.integers == c.integers);
  CHECK(back.reals == c.reals);
  CHECK(back.strings == c.strings);
  CHECK(back.arrays == c.arrays);
  CHECK(io::checksum(back) == io::checksum(c));
  CHECK_FALSE(has_temporary(dir));
  std::filesystem::remove_all(dir);
}

TEST_CASE("the checksum changes with any entry", "[io][checkpoint]") {
  const io::Checkpoint c = sample();
  const auto h = io::checksum(c);
  std::vector<std::function<void(io::Checkpoint&)>> edits = {
      [](io::Checkpoint& x) { x.fingerprint[3] ^= 1; },
      [](io::Checkpoint& x) { x.integers["step"] ^= 1 << 30; },
      [](io::Checkpoint& x) { x.reals["displacement"] = std::nextafter(0.125, 1.0); },
      [](io::Checkpoint& x) { x.strings["solver"] = "tesT"; },
      [](io::Checkpoint& x) { x.arrays["pose"][2] = -x.arrays["pose"][2]; },
      [](io::Checkpoint& x) { x.arrays["pose"].push_back(0.0); },
      [](io::Checkpoint& x) { x.arrays["extra"] = {}; },
      [](io::Checkpoint& x) { x.arrays.erase("empty"); },
  };
  for (std::size_t i = 0; i < edits.size(); ++i) {
    CAPTURE(i);
    io::Checkpoint e = c;
    edits[i](e);
    CHECK(io::checksum(e) != h);
  }
}

TEST_CASE("a failed commit keeps the previous file, removes the temporary and names file and error",
          "[io][atomic]") {
  const auto dir = scratch("inject");
  io::write_checkpoint(dir / "checkpoint.h5", sample());
  const std::string before = slurp(dir / "checkpoint.h5");
  io::Checkpoint next = sample();
  next.integers["step"] = 8;
  {
    Inject inject("steps.csv,checkpoint.h5");
    try {
      io::write_checkpoint(dir / "checkpoint.h5", next);
      FAIL("the injected failure did not throw");
    } catch (const io::WriteError& e) {
      CHECK_THAT(e.what(), ContainsSubstring((dir / "checkpoint.h5").string()));
      CHECK_THAT(e.what(), ContainsSubstring("No space left on device"));
      CHECK_THAT(e.what(), ContainsSubstring("previous checkpoint.h5"));
    }
    CHECK_THROWS_AS(io::write_file_atomic(dir / "steps.csv", "x\n"), io::WriteError);
    io::write_file_atomic(dir / "other.txt", "y\n");  // names not listed are written
  }
  CHECK(slurp(dir / "checkpoint.h5") == before);
  CHECK(io::read_checkpoint(dir / "checkpoint.h5").integers.at("step") == 7);
  CHECK_FALSE(std::filesystem::exists(dir / "steps.csv"));
  CHECK(slurp(dir / "other.txt") == "y\n");
  CHECK_FALSE(has_temporary(dir));
  // a directory that does not exist: the OS error is named
  try {
    io::write_file_atomic(dir / "missing" / "f.txt", "z");
    FAIL("no error for a missing directory");
  } catch (const io::WriteError& e) {
    CHECK_THAT(e.what(), ContainsSubstring("No such file or directory"));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("stale temporaries of dead processes are removed, live ones and other files kept", "[io][atomic]") {
  const auto dir = scratch("stale");
  // pid 2^22 + 7 exceeds Linux's pid_max default; a live pid: this process's parent
  const std::string dead = ".steps.csv.tmp4194311", live = ".dump_00001.h5.tmp" + std::to_string(::getppid());
  for (const auto& n : {dead, live, std::string("keep.tmp12"), std::string(".x.tmp"), std::string(".y.tmp12a")})
    std::ofstream(dir / n) << "x";
  CHECK(io::remove_stale_temporaries(dir) == 1);
  CHECK_FALSE(std::filesystem::exists(dir / dead));
  CHECK(std::filesystem::exists(dir / live));
  CHECK(std::filesystem::exists(dir / "keep.tmp12"));
  CHECK(std::filesystem::exists(dir / ".x.tmp"));
  CHECK(std::filesystem::exists(dir / ".y.tmp12a"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("dump names are parsed strictly", "[io]") {
  CHECK(io::dump_step("dump_00012.h5") == 12);
  CHECK(io::dump_step("dump_0.h5") == 0);
  CHECK(io::dump_step("dump_000000012.h5") == 12);      // a dynamic run's 9 digits
  CHECK(io::dump_step("dump_99999999999.h5") == 99999999999L);  // time steps beyond int
  for (const char* n : {"dump_final.h5", "dump_-3.h5", "dump_.h5", "dump_1.h5.bak", "dump_+1.h5", "dump_1a.h5",
                        "dump_99999999999999999999.h5", "xdump_1.h5", "dump_1.H5"})
    CHECK_FALSE(io::dump_step(n).has_value());
}

TEST_CASE("MC checkpoints are range-checked on the way in (valid checksums)", "[io][checkpoint][mc]") {
  const auto d = mc_deck();
  auto s = geometry::build_specimen(d.geometry);
  auto f = geometry::find_interfaces(s, d.geometry);
  mc::Solver solver(d, s, f);
  mc::Checkpoint cp;
  solver.run([&](const mc::StepRecord& r) {
    if (r.step == 1) cp = solver.checkpoint();
  });
  const std::size_t n = s.size(), nf = static_cast<std::size_t>(solver.model().n_free);
  const io::Checkpoint good = mc::to_named(cp, "fp", "text", d.load.final_displacement);
  const auto dir = scratch("ranges");
  // through the file, as the app does: a valid checkpoint comes back equal
  io::write_checkpoint(dir / "good.h5", good);
  const mc::Checkpoint back = mc::from_named(io::read_checkpoint(dir / "good.h5"), n, nf);
  CHECK(back.pose == cp.pose);
  CHECK(back.global_cycle == cp.global_cycle);
  CHECK(back.run.step == 1);

  struct Case {
    const char* what;
    std::function<void(io::Checkpoint&)> edit;
    const char* message;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Case> cases = {
      {"NaN pose", [&](io::Checkpoint& c) { c.arrays["pose"][4] = nan; }, "expected a finite pose"},
      {"infinite previous pose", [](io::Checkpoint& c) { c.arrays["previous_pose"][0] = HUGE_VAL; }, "previous_pose"},
      {"negative step", [](io::Checkpoint& c) { c.integers["step"] = -2147483644; }, "step = -2147483644 is out of range"},
      {"cycles without trials", [](io::Checkpoint& c) { c.integers["global_cycle"] += 1; }, "is not global_cycle x free bricks"},
      {"accepted > trials", [](io::Checkpoint& c) { c.integers["accepted_total"] = c.integers["trials_total"] + 1; }, "accepted_total"},
      {"window accepted > window trials", [](io::Checkpoint& c) { c.integers["window_accepted"] = c.integers["window_trials"] + 1; }, "window_accepted"},
      {"zero step size", [](io::Checkpoint& c) { c.reals["step_size"] = 0; }, "step_size"},
      {"NaN displacement", [&](io::Checkpoint& c) { c.reals["displacement"] = nan; }, "displacement"},
      {"short pose", [](io::Checkpoint& c) { c.arrays["pose"].pop_back(); }, "expected 3 x"},
      {"missing pose", [](io::Checkpoint& c) { c.arrays.erase("pose"); }, "lacks the array 'pose'"},
      {"other brick count", [](io::Checkpoint& c) { c.integers["bricks"] += 1; }, "bricks"},
      {"other solver", [](io::Checkpoint& c) { c.strings["solver"] = "dyn"; }, "'dyn' solver"},
      {"unknown array", [](io::Checkpoint& c) { c.arrays["velocity"] = {}; }, "unexpected array"},
      {"have_previous 2", [](io::Checkpoint& c) { c.integers["have_previous"] = 2; }, "have_previous"},
  };
  for (const auto& k : cases) {
    CAPTURE(k.what);
    io::Checkpoint bad = good;
    k.edit(bad);
    io::write_checkpoint(dir / "bad.h5", bad);
    const io::Checkpoint read = io::read_checkpoint(dir / "bad.h5");  // checksum fine
    try {
      (void)mc::from_named(read, n, nf);
      FAIL("accepted: " << k.what);
    } catch (const io::CheckpointError& e) {
      CHECK_THAT(e.what(), ContainsSubstring(k.message));
    }
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("a dynamic checkpoint without an array the state now holds is refused as written by an older nacre",
          "[io][checkpoint][dyn]") {
  // A checkpoint an older nacre wrote for the same deck passes the fingerprint and the checksum;
  // the state it holds lacks what was added since (dacc: the driven elements' accumulators). It
  // must be refused by name (CheckpointError: exit 2, nothing built or written), not fail later.
  const auto& names = dyn::Simulation::state_array_names();
  REQUIRE(std::find(names.begin(), names.end(), std::string("dacc")) != names.end());
  io::Checkpoint c;
  for (const auto& n : names) c.arrays[n] = {0.0};
  CHECK_NOTHROW(app::check_state_arrays(c, names, "cp.h5"));
  c.arrays.erase("dacc");
  try {
    app::check_state_arrays(c, names, "cp.h5");
    FAIL("a state without dacc was accepted");
  } catch (const io::CheckpointError& e) {
    CHECK_THAT(e.what(), ContainsSubstring("cp.h5: array 'dacc' missing: the checkpoint was written by an older nacre"));
  }
}

namespace {
/// A dynamic checkpoint of tiny_dynamic.toml at step 100 and start step `dt`, its state arrays
/// placeholders but for the clock (step and dt as the books say), and a scratch path for it.
struct DynCheckpointCase {
  deck::Deck d = deck::parse_deck_file(NACRE_SOURCE_DIR "/tests/app/tiny_dynamic.toml");
  app::DynCheckpoint c;
  std::filesystem::path path;
  DynCheckpointCase(double dt, const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("nacre_" + name + "_" + std::to_string(::getpid()) + ".h5")) {
    c.method = "be", c.step = 100, c.time = 1e-6, c.dt = dt, c.end_time = d.dynamics.end_time;
    for (const auto& n : dyn::Simulation::state_array_names()) c.state[n] = {0.0, 1.0};
    c.state["clock"] = {100.0, dt};
  }
};
}  // namespace

TEST_CASE("a dynamic checkpoint with a valid checksum but a non-finite state value is refused by name",
          "[io][checkpoint][dyn]") {
  // A checkpoint is written only from checked, finite states; one holding a NaN (a bug, or an
  // edit that recomputed the checksum) must not seed a run.
  DynCheckpointCase k(1e-8, "nan_cp");
  auto& [d, c, path] = k;
  io::write_checkpoint(path, app::to_named(c, d));
  CHECK_NOTHROW(app::read_dyn_checkpoint(path, d));
  c.state.begin()->second[1] = std::numeric_limits<double>::quiet_NaN();
  io::write_checkpoint(path, app::to_named(c, d));  // a valid checksum over the NaN
  try {
    (void)app::read_dyn_checkpoint(path, d);
    FAIL("a checkpoint holding a NaN was accepted");
  } catch (const io::CheckpointError& e) {
    CHECK_THAT(e.what(), ContainsSubstring("state array '" + c.state.begin()->first +
                                           "' holds a non-finite value at index 1"));
  }
  std::filesystem::remove(path);
}

TEST_CASE("a dynamic checkpoint whose state clock disagrees with its books is refused with both values",
          "[io][checkpoint][dyn]") {
  // (exit 2 before anything is built: it used to be exit 1 from the simulation, "dt = 0.000000 s")
  DynCheckpointCase k(1.25e-8, "clock_cp");
  auto& [d, c, path] = k;
  const auto refused = [&](const std::vector<double>& clock) -> std::string {
    c.state["clock"] = clock;
    io::write_checkpoint(path, app::to_named(c, d));  // a valid checksum over the edit
    try {
      (void)app::read_dyn_checkpoint(path, d);
    } catch (const io::CheckpointError& e) {
      return e.what();
    }
    return "";
  };
  CHECK(refused({100.0, 1.25e-8}).empty());
  CHECK_THAT(refused({100.0, 1.5e-8}),
             ContainsSubstring("the state was saved with dt = 1.5e-08 s, the checkpoint says dt = 1.25e-08 s"));
  CHECK_THAT(refused({99.0, 1.25e-8}), ContainsSubstring("the state's clock is at step 99, the checkpoint says step 100"));
  std::filesystem::remove(path);
}

TEST_CASE("a restart fingerprint names the first differing key", "[io][checkpoint][deck]") {
  const std::string base = "[geometry]\nwidth = 21.0\nheight = 8.0\nbrick_width = 3.5\nbrick_height = 1.0\n"
                           "notch_length = 7.0\n[mortar]\nk = 100.0\nx1 = 0.002\nx2 = 0.004\n"
                           "[load]\nbending = 1.0\nfinal_displacement = 0.012\nInitialLoadStepSize = 0.004\n"
                           "[random]\nseed = 5\n[output]\ndirectory = \"a\"\n";
  const auto d = deck::parse_deck_string(base, "a.toml");
  io::Checkpoint c;
  c.strings["deck"] = app::physics_text(d);
  c.fingerprint = app::fingerprint(c.strings["deck"]);
  // the same physics: comments, layout, key order, [output], [limits], final_displacement
  const std::string same = "# comment\n[random]\nseed = 5 # same\n[load]\nInitialLoadStepSize = 0.004\n"
                           "final_displacement = 0.5\nbending = 1.0\n[geometry]\nnotch_length = 7.0\n"
                           "brick_height = 1.0\nbrick_width = 3.5\nheight = 8.0\nwidth = 21.0\n"
                           "[mortar]\nx2 = 0.004\nx1 = 0.002\nk = 100.0\n[output]\ndirectory = \"b\"\n"
                           "DumpInter = 3\n[limits]\nmax_bricks = 1e7\n";
  CHECK_NOTHROW(app::check_fingerprint(c, deck::parse_deck_string(same, "b.toml"), "cp.h5"));
  auto refused = [&](const std::string& text) {
    try {
      app::check_fingerprint(c, deck::parse_deck_string(text, "b.toml"), "cp.h5");
    } catch (const io::CheckpointError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = base;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  CHECK_THAT(refused(replaced("k = 100.0", "k = 120.0")), ContainsSubstring("mortar.k = 100 in the checkpoint, 120 in b.toml"));
  CHECK_THAT(refused(replaced("seed = 5", "seed = 6")), ContainsSubstring("random.seed = 5 in the checkpoint, 6 in b.toml"));
  CHECK_THAT(refused(base + "[solver]\nTEMP = 1e-7\n"), ContainsSubstring("solver.TEMP = 9.9999999999999995e-08 in b.toml, not set"));
  CHECK_THAT(refused(replaced("notch_length = 7.0\n", "")), ContainsSubstring("geometry.notch_length = 7 in the checkpoint, not set in b.toml"));
}

TEST_CASE("absurd decks are refused from estimates with file, line and key, limits are raisable", "[deck][limits]") {
  const std::string base = "[geometry]\nwidth = 40.0\nheight = 24.0\nbrick_width = 3.5\nbrick_height = 1.0\n"
                           "notch_length = 14.0\n[mortar]\nk = 100.0\nx1 = 0.002\nx2 = 0.004\n"
                           "[load]\nfinal_displacement = 0.05\n";
  auto error_of = [](const std::string& text) {
    try {
      (void)deck::parse_deck_string(text, "deck.toml");
    } catch (const deck::DeckError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = base;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  CHECK(error_of(base).empty());
  const std::string huge = with("width = 40.0\nheight = 24.0", "width = 1e6\nheight = 1e6");
  CHECK_THAT(error_of(huge), ContainsSubstring("deck.toml:5: geometry.brick_height: the specimen needs about 2.86e+11 bricks"));
  CHECK_THAT(error_of(huge), ContainsSubstring("[limits] max_bricks"));
  CHECK_THAT(error_of(huge + "[limits]\nmax_bricks = 1e12\nmax_memory_gib = 1e4\n"), ContainsSubstring("max_memory_gib"));
  CHECK(error_of(huge + "[limits]\nmax_bricks = 1e12\nmax_memory_gib = 1e7\n").empty());
  CHECK_THAT(error_of(with("width = 40.0", "width = 1e300")), ContainsSubstring("deck.toml:2: geometry.width: value 1e+300 outside"));
  CHECK_THAT(error_of(with("brick_height = 1.0", "brick_height = 5e-324")), ContainsSubstring("deck.toml:5: geometry.brick_height:"));
  CHECK_THAT(error_of(with("x1 = 0.002", "x1 = 1e-200")), ContainsSubstring("deck.toml:9: mortar.x1:"));
  CHECK_THAT(error_of(base + "InitialLoadStepSize = 1e-300\n"), ContainsSubstring("deck.toml:13: load.InitialLoadStepSize:"));
  CHECK_THAT(error_of(base + "InitialLoadStepSize = 1e-9\n"), ContainsSubstring("5e+07 load steps, above the limit of 1e+06"));
  CHECK(error_of(base + "InitialLoadStepSize = 1e-9\n[limits]\nmax_load_steps = 1e8\n").empty());
  CHECK_THAT(error_of(base + "[limits]\nmax_brick = 3\n"), ContainsSubstring("limits.max_brick: unknown key"));
}

TEST_CASE("the brick estimate bounds the specimen actually built", "[deck][limits]") {
  for (const double angle : {0.0, 30.0, 90.0, -45.0}) {
    CAPTURE(angle);
    deck::Deck d;
    d.geometry.width = 40, d.geometry.height = 24, d.geometry.notch_length = 14, d.geometry.notch_y = 12;
    d.geometry.angle_deg = angle;
    const auto s = geometry::build_specimen(d.geometry);
    const auto e = deck::estimate(d);
    CHECK(static_cast<double>(s.size()) <= e.bricks);
    CHECK(e.bricks < 3.0 * static_cast<double>(s.size()));  // and not absurdly loose
  }
}

namespace {
// every Kokkos allocation while a callback is set (Kokkos Tools): bytes held now and at most
std::int64_t g_held = 0, g_peak = 0;
void on_allocate(const Kokkos_Profiling_SpaceHandle, const char*, const void*, const std::uint64_t n) {
  g_held += static_cast<std::int64_t>(n);
  g_peak = std::max(g_peak, g_held);
}
void on_deallocate(const Kokkos_Profiling_SpaceHandle, const char*, const void*, const std::uint64_t n) {
  g_held -= static_cast<std::int64_t>(n);
}
}  // namespace

TEST_CASE("the memory estimate of a dynamic deck bounds what its simulation allocates (Kokkos Tools)",
          "[deck][limits][dyn]") {
  // The [limits] check refuses a deck from its estimate before anything is built; the estimate
  // must bound what the run then allocates, every element's own matrices included
  // (share_element_matrices = false), or a deck passes the check and fails at allocation.
  std::ifstream in(NACRE_SOURCE_DIR "/inputs/dynamic_bie.toml");
  std::stringstream text;
  text << in.rdbuf();
  for (const char* method : {"be", "bie", "ue"})
    for (const bool share : {true, false}) {
      CAPTURE(method, share);
      std::string t = text.str();
      t.replace(t.find("method = \"bie\""), 14, std::string("method = \"") + method + "\"");
      if (std::string(method) != "bie") {  // the BIE keys (one per line) go with it
        for (const char* k : {"bie_solve", "bie_block", "bie_iterations", "bie_scheme"})
          if (const auto at = t.find(std::string("\n") + k); at != std::string::npos)
            t.erase(at + 1, t.find('\n', at + 1) - at);
      }
      t.replace(t.find("[dynamics]"), 10, std::string("[dynamics]\nshare_element_matrices = ") + (share ? "true" : "false"));
      const deck::Deck d = deck::parse_deck_string(t, "dynamic_bie.toml");
      auto s = geometry::build_specimen(d.geometry);
      const auto f = geometry::find_interfaces(s, d.geometry);
      const dyn::Params p = app::dynamics_params(d, s.size());
      g_held = g_peak = 0;
      Kokkos::Tools::Experimental::set_allocate_data_callback(on_allocate);
      Kokkos::Tools::Experimental::set_deallocate_data_callback(on_deallocate);
      {
        dyn::Simulation sim(p, s, f, d.mortar);
        (void)sim.advance(1);
      }
      Kokkos::Tools::Experimental::set_allocate_data_callback(nullptr);
      Kokkos::Tools::Experimental::set_deallocate_data_callback(nullptr);
      const double estimate = deck::estimate(d).bytes;
      INFO("peak of Kokkos allocations " << g_peak << " bytes for " << s.size() << " bricks; estimate " << estimate);
      CHECK(g_peak > 0);
      CHECK(static_cast<double>(g_peak) <= estimate);
    }
}

TEST_CASE("colouring = auto is a fixed rule, fastest times the candidates and keeps its pick", "[mc][colouring]") {
  auto d = mc_deck();
  auto s = geometry::build_specimen(d.geometry);
  auto f = geometry::find_interfaces(s, d.geometry);
  d.solver.colouring = "auto";
  const mc::Solver a(d, s, f);
  CHECK(a.model().colouring_name == mc::auto_colouring());
  CHECK(a.presim().empty());
  if (Kokkos::SpaceAccessibility<Kokkos::HostSpace, Kokkos::DefaultExecutionSpace::memory_space>::accessible)
    CHECK(mc::auto_colouring() == "tiles");
  d.solver.colouring = "fastest";
  d.solver.presim_cycles = 2;
  const mc::Solver b(d, s, f);
  CHECK(b.presim().size() == mc::colouring_strategies().size());
  const std::string json = mc::summary_json(b, d, 0, 0.0, fracture::CrackReading{}, 0.0, 1.5);
  CHECK_THAT(json, ContainsSubstring("\"presimulation_pick\": \"" + b.model().colouring_name + "\""));
  CHECK_THAT(json, ContainsSubstring("\"colouring_rule\": \"fastest\""));
  CHECK_THAT(json, ContainsSubstring("\"toughening_ratio\": 1.5"));
  CHECK_THAT(json, ContainsSubstring("\"version\": \"" + build_info().version + "\""));
  CHECK_THAT(json, ContainsSubstring("\"commit\": \"" + build_info().commit + "\""));
}

TEST_CASE("two states are compared array by array, each at its own scale", "[io][bench]") {
  using io::NamedArrays;
  // a BIE state's shape: displacements near 1e-6 beside accelerations near 1e10
  const NamedArrays ref{{"u", {1e-6, -2e-6, 0.5e-6}}, {"a", {3e10, -1e10, 2e9}}, {"dacc", {0.0, 0.0}}};
  SECTION("the same state: bit-identical, no difference, no array named") {
    const auto d = io::compare_states(ref, ref);
    CHECK(d.same_layout);
    CHECK(d.bit_identical);
    CHECK(d.max_abs == 0);
    CHECK(d.relative == 0);
    CHECK(d.worst.empty());
  }
  SECTION("a displacement off by 1e-9 is 5e-4 of u's scale, not 3e-20 of the accelerations'") {
    NamedArrays o = ref;
    o[0].values[1] += 1e-9;  // u's scale: 2e-6
    o[1].values[0] += 1e-3;  // a's: 1e-3 / 3e10, far smaller
    const auto d = io::compare_states(ref, o);
    CHECK(d.same_layout);
    CHECK_FALSE(d.bit_identical);
    CHECK(std::abs(d.max_abs - 1e-3) < 1e-5);  // (3e10 + 1e-3 rounds to a multiple of 2^-18)
    CHECK(d.worst == "u");
    CHECK(d.worst_scale == 2e-6);
    CHECK(std::abs(d.relative - 1e-9 / 2e-6) < 1e-12);
  }
  SECTION("an array of zeros is measured against the whole state's largest value") {
    NamedArrays o = ref;
    o[2].values[0] = 6.0;
    const auto d = io::compare_states(ref, o);
    CHECK(d.worst == "dacc");
    CHECK(d.worst_scale == 3e10);
    CHECK(d.relative == 6.0 / 3e10);
  }
  SECTION("a NaN is an infinite difference") {
    NamedArrays o = ref;
    o[1].values[2] = std::nan("");
    const auto d = io::compare_states(ref, o);
    CHECK(std::isinf(d.relative));
    CHECK(d.worst == "a");
  }
  SECTION("another layout (a name or a length) is never within any tolerance") {
    NamedArrays renamed = ref, shorter = ref;
    renamed[0].name = "v";
    shorter[2].values.pop_back();
    for (const auto& o : {renamed, shorter}) {
      const auto d = io::compare_states(ref, o);
      CHECK_FALSE(d.same_layout);
      CHECK_FALSE(d.bit_identical);
      CHECK(std::isinf(d.relative));
    }
  }
  SECTION("a state file's values cut back into its arrays") {
    const auto flat = io::flatten(ref);
    REQUIRE(flat.size() == 8);
    NamedArrays back;
    REQUIRE(io::unflatten(flat, {{"u", 3}, {"a", 3}, {"dacc", 2}}, back));
    CHECK(io::compare_states(ref, back).bit_identical);
    CHECK_FALSE(io::unflatten(flat, {{"u", 3}, {"a", 3}}, back));
  }
}
