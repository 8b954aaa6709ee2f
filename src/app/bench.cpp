// SPDX-License-Identifier: BSD-3-Clause
// `nacre bench DECK [--backends a,b] [--steps N | --cycles N] [--repeat R] [-o OUT] [--compare DIR]`:
// the deck's kernels on each backend of this build in one process, in turn and repeated, timed by
// phase, against the backend's own bounds measured in the same run, with the agreement of the
// results (bit for bit across the backends of a build; within a stated tolerance against another
// build's bench, e.g. a CUDA one, with --compare).
//
// Why Kokkos' region callbacks: every phase of both solver families is already a labelled
// Kokkos::Profiling::ScopedRegion ("nacre::dyn::interface_force", "nacre::mc::sweep_colour"...),
// so the bench installs a push / pop region callback pair and reads the phases the solvers
// declare, inclusive times per region name. Kokkos fences before each callback (a tool's default
// requirement), so the times hold on an asynchronous device too.
//
// Writes OUT/bench.csv (one row per backend, repeat and phase), OUT/bench.json (the machine, the
// bounds, the best repeat per backend, the agreement), OUT/state.bin (the first backend's result,
// what another bench's --compare reads) and OUT/bench.png (python -m nacre.charts.bench).
#include "driver.hpp"

#include <nacre/app/run_dynamics.hpp>
#include <nacre/core/backend.hpp>
#include <nacre/core/flop_count.hpp>
#include <nacre/core/format.hpp>
#include <nacre/deck/deck.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/io/atomic_file.hpp>
#include <nacre/io/state_compare.hpp>
#include <nacre/perf/bounds.hpp>
#include <nacre/perf/tool_timer.hpp>
#include <nacre/mc/solver.hpp>

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>
#include <nlohmann/json.hpp>
#ifdef KOKKOS_ENABLE_CUDA
#include <cuda_runtime.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <string>
#include <thread>
#include <vector>

namespace nacre::app {

namespace {

using clock_type = std::chrono::steady_clock;

/// Seconds per profiling region of what a timer saw (inclusive per region name).
std::map<std::string, double> region_seconds(const perf::ToolTimer& t) {
  std::map<std::string, double> out;
  for (const auto& [name, e] : t.clock().regions()) out[name] = e.seconds;
  return out;
}

/// The backend's bounds (perf/bounds.hpp): triad over 3 x 64 MiB, beyond the caches of the
/// machines nacre meets, best of 5; FMA chains, best of 3.
struct Bounds {
  double triad_gbs = 0;   ///< a = b + s c, GB/s
  double fma_gflops = 0;  ///< independent FMA chains per work item, GFLOP/s
};
template <class ExecutionSpace>
Bounds measure_bounds(const ExecutionSpace& space) {
  return {perf::triad(space, std::size_t(1) << 23, 5).bytes_per_s / 1e9, perf::fma_flops(space, 3) / 1e9};
}

}  // namespace

namespace {

std::string machine_cpu() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

/// The GPU the run used (a CUDA build): name, driver, memory, multiprocessors; null otherwise.
nlohmann::ordered_json machine_gpu() {
#ifdef KOKKOS_ENABLE_CUDA
  int dev = 0, driver = 0, runtime = 0;
  cudaDeviceProp p{};
  if (cudaGetDevice(&dev) != cudaSuccess || cudaGetDeviceProperties(&p, dev) != cudaSuccess) return nullptr;
  cudaDriverGetVersion(&driver);
  cudaRuntimeGetVersion(&runtime);
  return {{"name", p.name},
          {"driver_version", driver},
          {"runtime_version", runtime},
          {"memory_bytes", p.totalGlobalMem},
          {"multiprocessors", p.multiProcessorCount}};
#else
  return nullptr;
#endif
}

// ---- one timed run of the deck on one backend
struct Sample {
  std::string backend;
  int repeat = 0;
  double seconds = 0;                   ///< the timed stretch
  long units = 0;                       ///< time steps (dynamics), Monte Carlo cycles or load steps
  double work = 0;                      ///< brick-steps (dynamics) or brick trials (Monte Carlo)
  double random_bits = 0;               ///< bits the uniform source drew (Monte Carlo: 256 per trial)
  std::map<std::string, double> phase;  ///< region -> seconds
  io::NamedArrays state;                ///< what the agreement check compares, array by array
  double bytes_per_unit = 0;            ///< Simulation::step_bytes, Solver::cycle_bytes x cycles per unit
  double flops_per_unit = NAN;          ///< Simulation::step_flops, Solver::cycle_flops x cycles per unit
  double dt = 0;                        ///< dynamics: the time step (s)
};

Sample run_dynamics_on(const Backend& b, const deck::Deck& d, const geometry::Specimen& s,
                       const geometry::Interfaces& f, long steps) {
  dyn::Params p = dynamics_params(d, s.size());
  const bool from_fraction = d.dynamics.dt <= 0;
  if (from_fraction) p.dt = 1e-9;  // replaced before the first step: the run's own rule
  dyn::Simulation sim(b, p, s, f, d.mortar);
  if (from_fraction) take_initial_step(sim, p, d, b, s, f, nullptr);
  Sample r;
  r.backend = b.name();
  r.units = steps;
  r.work = static_cast<double>(s.size()) * static_cast<double>(steps);
  r.dt = p.dt;
  r.bytes_per_unit = static_cast<double>(sim.step_bytes());
  r.flops_per_unit = sim.step_flops();
  {
    const perf::ToolTimer timer(perf::ToolTimer::regions);
    const auto t0 = clock_type::now();
    if (!sim.advance(steps)) throw std::runtime_error("the run stopped: " + sim.why());
    b.fence();
    r.seconds = std::chrono::duration<double>(clock_type::now() - t0).count();
    r.phase = region_seconds(timer);
  }
  for (auto& [name, x] : sim.save_state()) r.state.push_back({name, std::move(x)});
  return r;
}

/// Monte Carlo: `cycles` cycles at the first load increment, or (load_steps > 0) the first
/// `load_steps` load steps of the deck's path, each relaxed and polished as in a run.
Sample run_mc_on(const Backend& b, const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
                 long cycles, long load_steps) {
  mc::Solver solver(b, d, s, f);
  Sample r;
  r.backend = b.name();
  {
    const perf::ToolTimer timer(perf::ToolTimer::regions);
    const auto t0 = clock_type::now();
    if (load_steps > 0) {
      long done = 0;
      solver.should_stop = [&] { return done >= load_steps; };
      solver.run([&](const mc::StepRecord&) { ++done; });
      if (solver.failed())
        throw std::runtime_error("load step " + std::to_string(solver.failed_step().step) + " did not converge");
      r.units = done;
    } else {
      solver.set_load(d.load.initial_step);
      for (long c = 0; c < cycles; ++c) solver.cycle();
      r.units = cycles;
    }
    b.fence();
    r.seconds = std::chrono::duration<double>(clock_type::now() - t0).count();
    r.phase = region_seconds(timer);
  }
  const double trials = static_cast<double>(solver.sizes().free_bricks) * static_cast<double>(solver.global_cycle());
  r.work = trials;
  if (solver.times().rng > 0) r.random_bits = 256.0 * trials;  // a table filled by the source (not Philox in place)
  r.bytes_per_unit = static_cast<double>(solver.cycle_bytes()) * static_cast<double>(solver.global_cycle()) /
                     static_cast<double>(std::max(1L, r.units));
  // flops of the sweeps alone (counted at the state reached, after the timed stretch: a host
  // copy of the model); load steps also run Newton / FIRE, whose flops are not counted: none given
  if (const auto fc = load_steps > 0 ? std::nullopt : solver.cycle_flops())
    r.flops_per_unit = *fc * static_cast<double>(solver.global_cycle()) / static_cast<double>(std::max(1L, r.units));
  std::vector<double> x, y, t;
  solver.poses(x, y, t);
  r.state = {{"x", std::move(x)}, {"y", std::move(y)}, {"theta", std::move(t)}};
  return r;
}

struct BenchOptions {
  std::string deck, out = "bench", backends;
  std::string compare;         ///< another bench's output directory (another build, e.g. a GPU one)
  double tolerance = 1e-6;     ///< per array: largest |difference| / the array's largest |value|
  long steps = 0, cycles = 0;  ///< 0: not given (dynamics: 200 steps; Monte Carlo: 20 cycles)
  int repeat = 3;
};

/// The unit a bench times (bench.json "unit"): a time step, a load step (--steps on a Monte Carlo
/// deck) or a Monte Carlo cycle.
const char* bench_unit(const BenchOptions& o, bool dynamic) {
  return dynamic ? "step" : o.steps > 0 ? "load_step" : "cycle";
}

/// The state a bench leaves (the first backend's first repeat), raw doubles: what --compare reads.
std::vector<double> read_state(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path.string() + ": cannot be read (a `nacre bench -o DIR` writes it)");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() % sizeof(double) != 0) throw std::invalid_argument(path.string() + ": not a state file");
  std::vector<double> v(bytes.size() / sizeof(double));
  std::memcpy(v.data(), bytes.data(), bytes.size());
  return v;
}

/// --compare DIR's bench.json, refused (std::invalid_argument) unless each key of `mine` (bricks,
/// unit; after the runs also the units per repeat, which a path shorter than --steps load steps
/// sets) has this bench's value: checked before the timed runs, and again after them.
nlohmann::ordered_json compare_reference(const BenchOptions& o, const nlohmann::ordered_json& mine) {
  std::ifstream jin(std::filesystem::path(o.compare) / "bench.json");
  if (!jin)
    throw std::invalid_argument(o.compare + "/bench.json: cannot be read (--compare takes a bench's output directory)");
  const auto other = nlohmann::ordered_json::parse(jin);
  for (const auto& [key, value] : mine.items())
    if (other.at(key) != value)
      throw std::invalid_argument("--compare " + o.compare + ": its " + key + " is " + other.at(key).dump() +
                                  ", this bench's " + value.dump() + " (compare the same deck and units)");
  return other;
}

/// --compare DIR: each backend's state against another bench's (another build: a GPU, another
/// compiler), within a relative tolerance; the bench must be the same deck and units.
nlohmann::ordered_json compare_with(const BenchOptions& o, const nlohmann::ordered_json& mine,
                                    const std::vector<std::pair<std::string, const Sample*>>& firsts, bool& within) {
  namespace fs = std::filesystem;
  const auto other = compare_reference(o, mine);
  // the arrays the state file holds (bench.json "state_file"."arrays"); a bench written before
  // the arrays were recorded holds one array, compared at one scale as it was then
  const std::vector<double> flat = read_state(fs::path(o.compare) / "state.bin");
  std::vector<std::pair<std::string, std::size_t>> layout;
  const auto sf = other.value("state_file", nlohmann::ordered_json::object());
  const bool recorded = sf.contains("arrays");
  if (recorded)
    for (const auto& a : sf.at("arrays"))
      layout.emplace_back(a.at("name").get<std::string>(), a.at("values").get<std::size_t>());
  else
    layout.emplace_back("state", flat.size());
  io::NamedArrays ref;
  if (!io::unflatten(flat, layout, ref))
    throw std::invalid_argument(o.compare + "/state.bin: " + std::to_string(flat.size()) +
                                " values, not what its bench.json \"state_file\" lists");
  nlohmann::ordered_json c;
  c["directory"] = o.compare;
  c["machine"] = other.at("machine");
  c["reference_backend"] = other.at("backends").begin().key();
  c["tolerance"] = o.tolerance;
  c["per_array"] = recorded;
  within = true;
  const auto describe = [](const io::NamedArrays& st) {
    std::string t;
    for (const auto& a : st) t += (t.empty() ? "" : ", ") + a.name + " " + std::to_string(a.values.size());
    return t;
  };
  for (const auto& [name, s] : firsts) {
    const io::NamedArrays mine_state = recorded ? s->state : io::NamedArrays{{"state", io::flatten(s->state)}};
    const auto d = io::compare_states(ref, mine_state);
    if (!d.same_layout)  // another deck, or a state saved by another version of nacre
      throw std::invalid_argument("--compare " + o.compare + ": its state holds " + describe(ref) +
                                  " values, this bench's " + describe(mine_state) +
                                  " (compare the same deck, with benches of the same nacre version)");
    const bool ok = d.relative <= o.tolerance;
    within = within && ok;
    c["backends"][name] = {{"max_difference", d.max_abs},
                           {"relative", d.relative},
                           {"largest_relative_in", d.worst},
                           {"bit_identical", d.bit_identical},
                           {"within", ok}};
  }
  return c;
}

/// The files and the printed table: per backend its best repeat, phases, throughput, speed-up
/// over the reference (serial where listed, else the first), fraction of its bounds, agreement.
int write_bench(const BenchOptions& o, const deck::Deck& d, std::size_t bricks, bool dynamic,
                const std::vector<Backend>& backends, const std::vector<Bounds>& bounds,
                const std::vector<Sample>& samples) {
  namespace fs = std::filesystem;
  const std::string unit = bench_unit(o, dynamic);
  auto first = [&](std::size_t k) {  // backend k's first repeat
    for (const auto& s : samples)
      if (s.backend == backends[k].name()) return &s;
    return static_cast<const Sample*>(nullptr);
  };
  // --compare first: a reference that does not fit (another deck, units or layout) is refused
  // before any file is written
  bool within = true;
  nlohmann::ordered_json compared;
  if (!o.compare.empty()) {
    std::vector<std::pair<std::string, const Sample*>> firsts;
    for (std::size_t k = 0; k < backends.size(); ++k) firsts.emplace_back(backends[k].name(), first(k));
    compared = compare_with(o, {{"bricks", bricks}, {"unit", unit}, {"units_per_repeat", samples.front().units}},
                            firsts, within);
  }
  fs::create_directories(o.out);
  const char* work = dynamic ? "brick-steps/s" : "trials/s";
  std::ostringstream csv;
  csv.precision(9);
  csv << "backend,repeat,phase,seconds,seconds_per_" << unit << ",share\n";
  for (const auto& s : samples) {
    csv << s.backend << "," << s.repeat << ",total," << s.seconds << "," << s.seconds / s.units << ",1\n";
    for (const auto& [name, t] : s.phase)
      csv << s.backend << "," << s.repeat << "," << name << "," << t << "," << t / s.units << "," << t / s.seconds
          << "\n";
  }
  io::write_file_atomic(fs::path(o.out) / "bench.csv", csv.str());

  std::size_t ref = 0;
  for (std::size_t k = 0; k < backends.size(); ++k)
    if (backends[k].name() == "serial") ref = k;
  auto best = [&](std::size_t k) {
    const Sample* b = nullptr;
    for (const auto& s : samples)
      if (s.backend == backends[k].name() && (!b || s.seconds < b->seconds)) b = &s;
    return b;
  };
  nlohmann::ordered_json j;
  j["deck"] = d.path;
  j["solver"] = dynamic ? "dynamics" : "monte-carlo";
  j["bricks"] = bricks;
  j["unit"] = unit;
  j["flop_convention"] = "+ - * / sqrt: 1 flop, an FMA 2, exp / asinh / sin / cos: " +
                         std::to_string(static_cast<int>(flops::kTranscendentalFlops)) + " (core/flop_count.hpp)";
  j["units_per_repeat"] = samples.front().units;
  j["repeats"] = o.repeat;
  j["time_step"] = dynamic ? nlohmann::ordered_json(samples.front().dt) : nlohmann::ordered_json(nullptr);
  j["machine"] = {
      {"cpu", machine_cpu()},
      {"kokkos_version", std::to_string(KOKKOS_VERSION / 10000) + "." + std::to_string(KOKKOS_VERSION / 100 % 100) +
                             "." + std::to_string(KOKKOS_VERSION % 100)},
      {"cores", std::thread::hardware_concurrency()},
      {"gpu", machine_gpu()}};
  j["reference_backend"] = backends[ref].name();
  std::printf("%-8s %8s %14s %16s %9s %10s %10s  %s\n", "backend", "threads", ("s/" + unit).c_str(), work, "speed-up",
              "of triad", "of FMA", "agreement");
  const Sample* r0 = first(0);
  for (std::size_t k = 0; k < backends.size(); ++k) {
    const Sample* b = best(k);
    const Sample* f = first(k);
    const double per = b->seconds / b->units, thr = b->work / b->seconds;
    const double speedup = best(ref)->seconds / b->seconds;
    // fraction of the bandwidth bound: the bytes a unit must move at least (Simulation::step_bytes,
    // Solver::cycle_bytes) at the backend's triad rate; of the FMA bound: the flops a unit does
    // (Simulation::step_flops, Solver::cycle_flops; core/flop_count.hpp's convention) at the
    // backend's FMA-loop rate
    const double of_triad = bounds[k].triad_gbs > 0 && b->bytes_per_unit > 0 ? b->bytes_per_unit / per / (bounds[k].triad_gbs * 1e9) : NAN;
    const double of_fma = bounds[k].fma_gflops > 0 && b->flops_per_unit > 0
                              ? b->flops_per_unit / per / (bounds[k].fma_gflops * 1e9)
                              : NAN;
    // the uniform source's rate where it fills a table (aes-ctr, mt-aes; Philox is drawn inside the sweep)
    const auto rng_phase = b->phase.find("nacre::mc::rng");
    const double rng_gbits = b->random_bits > 0 && rng_phase != b->phase.end() && rng_phase->second > 0
                                 ? b->random_bits / rng_phase->second / 1e9
                                 : NAN;
    const auto vs0 = io::compare_states(r0->state, f->state);
    const double diff = vs0.max_abs;
    const bool same = vs0.bit_identical;
    // bit for bit where nacre promises it: against the first listed backend of the same kind of
    // arithmetic (host backends among themselves, whatever the order); a backend of another kind
    // than the first within --tolerance, array by array (a device against the host)
    std::size_t kin = 0;
    while (!backends[kin].bit_compatible(backends[k].name())) ++kin;
    const bool bits_promised = kin < k || k == 0;
    const bool same_as_kin = io::compare_states(first(kin)->state, f->state).bit_identical;
    // array by array, each against its own largest |value| (io/state_compare.hpp)
    const double rel = vs0.relative;
    // raw Monte Carlo cycles on another kind of arithmetic take another path (the first
    // differently rounded acceptance branches it): reported, not judged; converged load steps
    // (--steps) and dynamics are judged against --tolerance (docs/gpu.md gives each deck's)
    const bool judged = bits_promised || unit != "cycle";
    const bool agrees = bits_promised ? same_as_kin : !judged || rel <= o.tolerance;
    bool repeats_same = true;
    for (const auto& s : samples)
      if (s.backend == backends[k].name())
        repeats_same = repeats_same && io::compare_states(f->state, s.state).bit_identical;
    auto& e = j["backends"][backends[k].name()];
    e["execution_space"] = backends[k].kokkos_name();
    e["threads"] = backends[k].concurrency();
    e["best_seconds"] = b->seconds;
    e["seconds_per_unit"] = per;
    e[dynamic ? "brick_steps_per_second" : "trials_per_second"] = thr;
    e["rng_gbit_per_s"] = std::isnan(rng_gbits) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(rng_gbits);
    e["speedup_over_reference"] = speedup;
    e["triad_gb_per_s"] = bounds[k].triad_gbs;
    e["fma_gflop_per_s"] = bounds[k].fma_gflops;
    e["fraction_of_triad"] = std::isnan(of_triad) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(of_triad);
    e["bytes_per_unit"] = b->bytes_per_unit;
    e["fraction_of_fma"] = std::isnan(of_fma) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(of_fma);
    e["flops_per_unit"] =
        std::isnan(b->flops_per_unit) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(b->flops_per_unit);
    e["max_difference_to_" + backends[0].name()] = diff;
    e["bit_identical_to_" + backends[0].name()] = same;
    e["bit_identity_promised"] = bits_promised;
    e["bit_identical_to"] = backends[kin].name();  // the first listed backend of its kind of arithmetic
    e["relative_difference"] = rel;
    e["largest_relative_in"] = vs0.worst;
    e["agreement_judged"] = judged;
    e["agrees"] = agrees;
    e["repeats_bit_identical"] = repeats_same;
    for (const auto& [name, t] : b->phase) e["phases"][name] = t / b->units;
    const std::string verdict =
        k == 0                         ? std::string("reference")
        : bits_promised && same_as_kin ? "bit-identical" + (kin ? " to " + backends[kin].name() : "")
        : bits_promised                ? std::string("DIFFERS")
        : !judged ? std::string("another path (Monte Carlo cycles on other arithmetic: not judged)")
        : agrees  ? std::string("within tolerance")
                  : std::string("DIFFERS");
    const std::string where = vs0.worst.empty() ? "" : ", relative " + format_real(rel, 3) + " in " + vs0.worst;
    std::printf("%-8s %8d %14.6g %16.4g %9.3f %9.1f%% %9.1f%%  %s (max |diff| %.3g%s)%s\n", backends[k].name().c_str(),
                backends[k].concurrency(), per, thr, speedup, 100 * of_triad, 100 * of_fma, verdict.c_str(), diff,
                where.c_str(), repeats_same ? "" : "; repeats differ");
    if (!std::isnan(rng_gbits))
      std::printf("%-8s uniform source (%s): %.3g Gbit/s\n", "", d.solver.rng.c_str(), rng_gbits);
  }
  bool all_same = true;
  bool all_bits = true, all_judged = true;
  for (std::size_t k = 0; k < backends.size(); ++k) {
    const auto& e = j["backends"][backends[k].name()];
    all_same = all_same && e["agrees"].get<bool>() && e["repeats_bit_identical"].get<bool>();
    all_bits = all_bits && e["bit_identical_to_" + backends[0].name()].get<bool>();
    all_judged = all_judged && e["agreement_judged"].get<bool>();
  }
  j["agreement"] = !all_same     ? "differs"
                   : all_bits    ? "bit-identical"
                   : !all_judged ? "not judged across arithmetic (Monte Carlo cycles)"
                                 : "within tolerance";
  j["tolerance"] = o.tolerance;
  const auto state = io::flatten(first(0)->state);
  io::write_file_atomic(fs::path(o.out) / "state.bin",
                        std::string(reinterpret_cast<const char*>(state.data()), state.size() * sizeof(double)));
  j["state_file"] = {{"name", "state.bin"}, {"values", state.size()}, {"backend", backends[0].name()}};
  for (const auto& a : first(0)->state)
    j["state_file"]["arrays"].push_back({{"name", a.name}, {"values", a.values.size()}});
  if (!o.compare.empty()) {
    j["compared_to"] = compared;
    for (const auto& [name, c] : compared.at("backends").items()) {
      const std::string in = c.at("largest_relative_in").get<std::string>();
      std::printf("%-8s against %s (%s): max |diff| %.3g, relative %.3g%s: %s\n", name.c_str(), o.compare.c_str(),
                  compared.at("reference_backend").get<std::string>().c_str(), c.at("max_difference").get<double>(),
                  c.at("relative").get<double>(), in.empty() ? "" : (" (in " + in + ")").c_str(),
                  c.at("bit_identical").get<bool>() ? "bit-identical"
                  : c.at("within").get<bool>()      ? "within the tolerance"
                                                    : "BEYOND the tolerance");
    }
  }
  io::write_file_atomic(fs::path(o.out) / "bench.json", j.dump(2) + "\n");
  std::cout << "nacre bench: results in " << o.out << "/ (bench.csv, bench.json, bench.png)\n";
  run_charts("bench", o.out, &std::cout);  // a missing chart is a warning: bench.csv / bench.json are written
  // nacre promises the same bits on every host backend and every repeat, and a device within the
  // tolerance: anything else is a failure
  if (!all_same) {
    std::cerr << "nacre bench: error: the backends' results differ (bench.json \"agreement\")\n";
    return 1;
  }
  if (!within) {
    std::cerr << "nacre bench: error: the results differ from " << o.compare << "'s beyond the tolerance "
              << o.tolerance << " (bench.json \"compared_to\")\n";
    return 1;
  }
  return 0;
}

int bench(const BenchOptions& o) {
  const deck::Deck d = deck::parse_deck_file(o.deck);
  const bool dynamic = d.dynamics.enabled;
  std::vector<std::string> names = Backend::names();
  if (!o.backends.empty()) {
    names.clear();
    std::stringstream in(o.backends);
    for (std::string name; std::getline(in, name, ',');) names.push_back(name);
  }
  std::vector<Backend> backends;
  for (const auto& name : names) {
    backends.push_back(Backend::parse(name));
    // bench.json keys its results by backend: a backend listed twice (openmp,OpenMP too) would
    // overwrite its own entry and the agreement check would compare it with itself
    for (std::size_t k = 0; k + 1 < backends.size(); ++k)
      if (backends[k].name() == backends.back().name())
        throw std::invalid_argument("--backends lists " + backends.back().name() + " twice (\"" + o.backends + "\")");
  }
  auto specimen = geometry::build_specimen(d.geometry);
  const auto interfaces = geometry::find_interfaces(specimen, d.geometry);
  if (dynamic && o.cycles > 0) throw std::invalid_argument("--cycles applies to Monte Carlo decks; use --steps");
  if (!dynamic && o.steps > 0 && o.cycles > 0)
    throw std::invalid_argument("--steps (load steps) and --cycles (at the first load step) exclude each other");
  const long units = dynamic ? (o.steps > 0 ? o.steps : 200) : o.steps > 0 ? o.steps : o.cycles > 0 ? o.cycles : 20;
  std::cout << "nacre bench: " << o.deck << ": " << specimen.size() << " bricks, "
            << (dynamic ? "dynamics, " : "Monte Carlo, ") << units
            << (dynamic       ? " steps"
                : o.steps > 0 ? " load steps"
                              : " cycles at the first load step")
            << " x " << o.repeat << " repeats on";
  for (const auto& b : backends) std::cout << " " << b.name() << " (" << b.concurrency() << " threads)";
  std::cout << "\n";

  if (!o.compare.empty())  // a reference of another deck or units: refused before anything is timed
    (void)compare_reference(o, {{"bricks", specimen.size()}, {"unit", bench_unit(o, dynamic)}});
  std::vector<Bounds> bounds;
  for (const auto& b : backends) bounds.push_back(b.visit([](const auto& s) { return measure_bounds(s); }));
  std::vector<Sample> samples;
  for (int rep = 0; rep < o.repeat; ++rep)
    for (const auto& b : backends) {
      samples.push_back(dynamic ? run_dynamics_on(b, d, specimen, interfaces, units)
                                : run_mc_on(b, d, specimen, interfaces, units, o.steps));
      samples.back().repeat = rep;
    }
  return write_bench(o, d, specimen.size(), dynamic, backends, bounds, samples);
}

}  // namespace

int bench_main(int argc, char* argv[]) {
  std::vector<char*> kokkos_args{argv[0]}, app_args{argv[0]};
  for (int i = 2; i < argc; ++i)
    (std::string_view(argv[i]).starts_with("--kokkos-") ? kokkos_args : app_args).push_back(argv[i]);
  CLI::App cli{
      "nacre bench: the deck's kernels on each backend of this build, timed by phase, with the "
      "backends' bounds and the agreement of their results"};
  BenchOptions o;
  cli.add_option("deck", o.deck, "TOML input deck")->required()->check(CLI::ExistingFile);
  cli.add_option("--backends", o.backends, "comma-separated backends (default: all of `nacre --backend list`)");
  cli.add_option("--steps", o.steps,
                 "time steps per repeat (dynamic decks; default 200), or load steps of the path (Monte Carlo decks)")
      ->check(CLI::Range(1L, 100000000L));
  cli.add_option("--cycles", o.cycles, "Monte Carlo cycles per repeat at the first load step (rigid decks; default 20)")
      ->check(CLI::Range(1L, 100000000L));
  cli.add_option("--repeat", o.repeat, "repeats (each backend in turn)")->check(CLI::Range(1, 1000));
  cli.add_option("-o,--output", o.out, "output directory (bench.csv, bench.json, bench.png, state.bin)");
  cli.add_option("--compare", o.compare,
                 "another bench's output directory (e.g. a CUDA build's): each backend's result against its state.bin")
      ->check(CLI::ExistingDirectory);
  cli.add_option("--tolerance", o.tolerance,
                 "between a device and the host, and of --compare: per state array (u, v, a... or x, y, theta), its "
                 "largest |difference| over its largest |value| (default 1e-6)")
      ->check(CLI::PositiveNumber);
  if (const int rc = parse_command_line(cli, app_args, [] {}); rc >= 0) return rc;
  // (CLI11's PositiveNumber lets NaN through: every comparison with it is false)
  if (!std::isfinite(o.tolerance)) {
    std::cerr << "nacre bench: error: --tolerance: expected a positive finite number, got " << o.tolerance << "\n";
    return 2;
  }
  if (cli.count("--backends") > 0 && o.backends.empty()) {
    std::cerr << "nacre bench: error: --backends: expected a comma-separated list of backends (`nacre --backend "
                 "list`), got an empty one\n";
    return 2;
  }
  kokkos_args.push_back(nullptr);
  int kargc = static_cast<int>(kokkos_args.size()) - 1;
  Kokkos::ScopeGuard guard(kargc, kokkos_args.data());
  try {
    return bench(o);
  } catch (const deck::DeckError& e) {
    std::cerr << "nacre bench: error: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "nacre bench: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "nacre bench: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace nacre::app
