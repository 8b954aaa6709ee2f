// SPDX-License-Identifier: BSD-3-Clause
// The nacre command line: validate everything (flags, deck, limits, checkpoint) before touching
// the output directory, run the MC solver, write outputs atomically, stop cleanly on SIGINT /
// SIGTERM with a checkpoint, and start the plotting script without a shell.
#include <nacre/app/restart.hpp>
#include <nacre/app/run.hpp>
#include <nacre/app/signals.hpp>
#include <nacre/core/build_info.hpp>
#include <nacre/core/format.hpp>
#include <nacre/deck/deck.hpp>
#include <nacre/fracture/crack.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/io/atomic_file.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/io/results.hpp>
#include <nacre/mc/output.hpp>
#include <nacre/mc/solver.hpp>
#include <nacre/par/comm.hpp>

#include "driver.hpp"
#include "run_log.hpp"
#include "dyn_fields.hpp"
#include "progress.hpp"
#include <nacre/app/run_dynamics.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>
#include <streambuf>
#include <string_view>
#include <unistd.h>

namespace nacre::app {

namespace {

/// \brief Integer-valued Kokkos flags are checked here: Kokkos aborts (exit 134, a backtrace)
/// on "--kokkos-num-threads=abc". Other --kokkos-* flags are left to Kokkos.
void check_kokkos_flags(const std::vector<char*>& args) {
  struct Rule {
    std::string_view flag;
    long lo;
  };
  static constexpr Rule rules[] = {{"--kokkos-num-threads", 1}, {"--kokkos-device-id", 0},
                                   {"--kokkos-num-devices", 1}, {"--kokkos-skip-device", 0}};
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string_view a(args[i]);
    for (const auto& r : rules) {
      if (!a.starts_with(r.flag)) continue;
      const std::string_view rest = a.substr(r.flag.size());
      if (!rest.empty() && rest[0] != '=') continue;  // another flag sharing the prefix
      if (rest.empty())
        throw UsageError(std::string(a) + ": expected " + std::string(r.flag) + "=N (an integer >= " +
                         std::to_string(r.lo) + ")");
      const std::string_view v = rest.substr(1);
      long n = 0;
      const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
      if (v.empty() || ec != std::errc() || p != v.data() + v.size() || n < r.lo || n > 1000000)
        throw UsageError(std::string(a) + ": \"" + std::string(v) + "\" is not valid; expected " +
                         std::string(r.flag) + "=N with N an integer in [" + std::to_string(r.lo) + ", 1000000]");
    }
  }
}

/// \brief `nacre --backend list` (or --backend=list) anywhere on the command line.
bool asks_backend_list(int argc, char* argv[]) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    if (a == "--backend=list" || (a == "--backend" && i + 1 < argc && std::string_view(argv[i + 1]) == "list"))
      return true;
  }
  return false;
}

struct RunOptions {
  bool quiet = false, tty = false, extend = false, overwrite = false;
  std::string restart;
  std::string backend;  ///< `--backend NAME` ("" = the default space)
  std::string gpu_aware_mpi = "auto";  ///< `--gpu-aware-mpi auto|on|off` (par::Comm::device_direct)
};

/// \brief The specimen of a deck, refused (DeckError) when no brick is free.
void build(const deck::Deck& d, geometry::Specimen& specimen, geometry::Interfaces& interfaces, std::size_t& n_free) {
  specimen = geometry::build_specimen(d.geometry);
  interfaces = geometry::find_interfaces(specimen, d.geometry);
  n_free = static_cast<std::size_t>(std::count(specimen.drive.begin(), specimen.drive.end(), geometry::Drive::free));
  if (n_free == 0)
    throw deck::DeckError(d.where("geometry") + ": the specimen has " + std::to_string(specimen.size()) +
                          " bricks and none is free (all driven or none left); expected a specimen "
                          "taller than 2 * driven_rows * brick_height, with bricks between the driven rows");
}

/// \brief Read and validate a checkpoint for this deck and specimen (checksum, fingerprint,
/// ranges, final displacement); throws io::CheckpointError. Touches no output.
mc::Checkpoint validated_checkpoint(const deck::Deck& d, const RunOptions& opt, std::size_t n_bricks,
                                    std::size_t n_free) {
  const std::string& restart = opt.restart;
  const io::Checkpoint named = io::read_checkpoint(restart);
  check_fingerprint(named, d, restart);
  mc::Checkpoint cp;
  try {
    cp = mc::from_named(named, n_bricks, n_free);
  } catch (const io::CheckpointError& e) {
    throw io::CheckpointError(restart + ": " + e.what());
  }
  check_restart_backend(restart, cp.backend, opt.backend.empty() ? Backend::names().front() : opt.backend);
  const double cp_final = named.real("final_displacement");
  if (d.load.programme.empty() && cp.displacement > d.load.final_displacement * (1 + 1e-12))
    throw io::CheckpointError(restart + ": the checkpoint is at D = " + std::to_string(cp.displacement) +
                              ", beyond this deck's final_displacement = " + std::to_string(d.load.final_displacement) +
                              " (" + d.where("load.final_displacement") + ")");
  if (cp.run.leg > static_cast<int>(d.load.targets().size()))
    throw io::CheckpointError(restart + ": the checkpoint is on leg " + std::to_string(cp.run.leg + 1) +
                              " of a load programme, this deck has " + std::to_string(d.load.targets().size()) + " (" +
                              d.where("load.programme") + ")");
  if (cp_final != d.load.final_displacement && !opt.extend)
    throw io::CheckpointError(restart + ": the checkpoint's run ends at final_displacement = " +
                              std::to_string(cp_final) + ", this deck at " + std::to_string(d.load.final_displacement) +
                              " (" + d.where("load.final_displacement") +
                              "); pass --extend to continue the run to the deck's final_displacement");
  return cp;
}

/// One Monte Carlo run, from the deck to the summary: the solver on the session's
/// execution-space instance (a restart's state validated before the output directory is
/// touched), the writer, the row / dump / checkpoint of every load step, and the ways a run ends
/// (complete, stopped by a signal, a step not converged). Each phase is one member.
///
/// Spread over the ranks of `comm` (`mpirun -np N nacre DECK`), every rank runs this same
/// sequence: each builds the specimen and its part of the solver, every gathering member
/// (checkpoint, snapshot, interface states) is called on all of them, and rank 0 alone logs and
/// writes. A signal counts once every rank has heard of it (a max over ranks after each cycle), so
/// all stop after the same cycle. The files are those of the one-process run (docs/scaling.md).
class MonteCarloRun {
public:
  MonteCarloRun(deck::Deck d, const RunOptions& opt, const par::Comm& comm)
      : d_(std::move(d)), opt_(opt), comm_(comm), root_(comm.rank() == 0),
        session_(d_, opt.quiet, opt.tty, opt.backend.empty() ? Backend{} : Backend::parse(opt.backend)),
        log_(session_.log()), text_(physics_text(d_)), print_(fingerprint(text_)) {
    Kokkos::Profiling::ScopedRegion region("nacre::geometry::build");
    build(d_, specimen_, interfaces_, n_free_);
  }

  int run() {
    session_.log_start(std::to_string(specimen_.size()) + " bricks, " + std::to_string(interfaces_.size()) +
                       " interfaces (" + format_real(session_.elapsed(), 4) + " s)" +
                       (comm_.size() > 1 ? ", " + std::to_string(comm_.size()) + " MPI ranks" : std::string()));
    make_solver();
    // every rank has read the checkpoint (restart) before rank 0 sets up the directory
    comm_.barrier();
    // Only now, with everything validated, is the output directory set up (a restart into
    // another directory writes its own mesh.h5 and receives the earlier rows).
    io::RunWriter::Options wo;
    wo.directory = d_.output.directory, wo.hdf5 = d_.output.hdf5, wo.csv_header = mc::csv_header();
    if (root_) writer_.emplace(session_.open_writer(wo, specimen_, interfaces_, opt_.restart, cp_ ? cp_->run.step : 0));
    crack_.emplace(specimen_, interfaces_, d_.geometry);  // the crack_* columns, the dumps' "crack"
    last_ = named_checkpoint();                            // state after the last completed step
    SignalGuard signals;
    solver_->should_stop = [this] { return agreed_signal() != 0; };
    t_run_ = session_.elapsed();
    if (session_.progress()) solver_->on_progress = [this](long c, double e) { progress_line(c, e); };
    else if (session_.heartbeat()) solver_->on_progress = [this](long c, double e) { heartbeat_line(c, e); };
    if (!cp_) dump(0);
    solver_->run([this](const mc::StepRecord& r) { step_done(r); });
    if (session_.progress()) std::fprintf(stderr, "\n");
    if (solver_->interrupted()) {
      // The write in progress finished before the flag was seen; the step in progress is dropped
      // and the checkpoint holds the last completed one (a restart reproduces the uninterrupted run).
      int rc = 128 + signal_;
      if (writer_) {
        writer_->checkpoint(last_);
        rc = session_.stopped_by_signal(signal_, "step " + std::to_string(last_.integer("step")), *writer_);
      }
      // rank 0 has written and said so before any rank exits non-zero (a launcher may then end
      // the others at once)
      comm_.barrier();
      return rc;
    }
    if (solver_->failed()) {
      const int rc = not_converged();
      comm_.barrier();  // (as above)
      return rc;
    }
    const fracture::CrackReading crack = read_crack();  // gathered to rank 0: every rank calls
    if (!writer_) return 0;
    // the R-curve (energies per unit depth: thickness 1) before the summary that quotes its ratio
    const double ratio = write_r_curve(*writer_, 1.0, d_.mortar.bed.k * d_.mortar.bed.x1 * d_.mortar.bed.x2, log_);
    writer_->summary(mc::summary_json(*solver_, d_, writer_->last_step(), session_.elapsed(), crack,
                                      crack_->notch_tip_x(), ratio));
    if (log_) {
      const auto& pt = solver_->times();
      *log_ << "nacre: done in " << session_.elapsed() << " s; " << solver_->global_cycle()
            << " cycles; time split: sweep " << pt.sweep << " s, energy " << pt.energy << " s, rng " << pt.rng
            << " s, polish " << pt.polish << " s; largest step residual " << solver_->max_step_residual() << "\n";
    }
    return session_.complete(*writer_, "steps.csv, nacre.xdmf, summary.json", "mc");
  }

private:
  /// Restart: read and validate everything (checksum, fingerprint, ranges, the solver's own
  /// checks) before the output directory is touched.
  void make_solver() {
    if (!opt_.restart.empty()) {
      cp_ = validated_checkpoint(d_, opt_, specimen_.size(), n_free_);
    }
    // a restart continues with the schedule it started with; the deck keeps its rule (summary.json's
    // colouring_rule: "auto" stays "auto", as in the uninterrupted run)
    deck::Deck solver_deck = d_;
    if (cp_) solver_deck.solver.colouring = cp_->colouring;
    solver_.emplace(session_.backend(), solver_deck, specimen_, interfaces_, log_, comm_);
    if (!cp_) return;
    try {
      solver_->restore(*cp_);
    } catch (const std::runtime_error& e) {
      throw io::CheckpointError(opt_.restart + ": " + e.what());
    }
    if (log_)
      *log_ << "nacre: restarting from " << opt_.restart << " at step " << cp_->run.step
            << ", D = " << cp_->displacement << ", cycle " << cp_->global_cycle
            << (!cp_->backend.empty() && cp_->backend != session_.backend().name()
                    ? " (written on " + cp_->backend + ", continued on " + session_.backend().name() +
                          ": the same bits)"
                    : std::string())
            << "\n";
  }

  io::Checkpoint named_checkpoint() const {
    const mc::Checkpoint c = solver_->checkpoint();  // (gathered to rank 0: every rank calls)
    if (!root_) return {};
    return mc::to_named(c, print_, text_, d_.load.final_displacement, static_cast<int>(d_.load.targets().size()));
  }

  fracture::CrackReading read_crack() {
    const auto st = solver_->interface_states(&iface_energy_);  // (gathered to rank 0: every rank calls)
    if (!root_) return {};
    return crack_->measure(st, iface_energy_);
  }

  void dump(int step) {
    io::Snapshot snap = mc::snapshot(*solver_, specimen_, interfaces_, step);  // (gathers: every rank)
    if (!writer_) return;                                                      // rank 0 writes
    // the crack from the states the snapshot holds (no second evaluation of the interfaces)
    const auto state = std::find_if(snap.fields.begin(), snap.fields.end(), [](const io::Field& f) {
      return f.centre == io::Centre::interface && f.name == "state";
    });
    if (state == snap.fields.end()) throw std::logic_error("mc::snapshot holds no interface state");
    snap.fields.push_back(
        {io::Centre::interface, "crack", crack_->crack_mask(std::get<std::vector<std::int8_t>>(state->data)), 1});
    writer_->dump(snap);
    writer_->checkpoint(last_);
  }

  /// The first SIGINT / SIGTERM any rank received (0: none). One process: its own flag; on
  /// several ranks a max over them, so every rank stops after the same cycle.
  int agreed_signal() {
    signal_ = comm_.size() > 1 ? static_cast<int>(comm_.max(pending_signal())) : pending_signal();
    return signal_;
  }

  /// The live line (the solver calls after every cycle; at most 4 lines a second, and one at the
  /// end of each step).
  void progress_line(long cycles, double energy) {
    if (!session_.progress_due(step_done_)) return;
    session_.line_written();
    const double frac = solver_->path_fraction();
    const double spent = session_.elapsed() - t_run_;
    const double left = frac > 0 ? spent / frac - spent : -1;
    std::fprintf(stderr, "\r  step %4d  D %.4g/%.4g  cycles %8ld  E %.6g  elapsed %s  left ~%s   ",
                 step_done_ ? current_step_ : current_step_ + 1, solver_->load(), d_.load.final_displacement, cycles,
                 energy, hms(spent).c_str(), hms(left).c_str());
    std::fflush(stderr);
  }
  /// Off a terminal: a plain log line at most every [output] heartbeat seconds within a step.
  void heartbeat_line(long cycles, double energy) {
    if (!session_.heartbeat_due()) return;
    session_.line_written();
    *log_ << "  step " << current_step_ + 1 << " in progress: D = " << solver_->load() << ", " << cycles
          << " cycles, E = " << energy << ", elapsed " << hms(session_.elapsed() - t_run_) << "\n";
  }

  /// A completed load step: its row, the dump and checkpoint where due, the log or progress line.
  void step_done(const mc::StepRecord& r) {
    current_step_ = r.step;
    const fracture::CrackReading crack = read_crack();
    if (writer_) writer_->row(r.step, mc::csv_row(r, crack));
    last_ = named_checkpoint();
    if ((d_.output.dump_interval > 0 && r.step % d_.output.dump_interval == 0) || r.last) dump(r.step);
    if (session_.progress()) {
      step_done_ = true;
      progress_line(r.cycles, r.energy);
      step_done_ = false;
    } else if (log_) {
      session_.line_written();
      *log_ << "  step " << r.step << ": D = " << r.displacement << ", E = " << r.energy << ", F = " << r.reaction
            << ", " << r.cycles << " cycles" << (r.converged ? "" : " (not converged)") << ", acceptance "
            << r.acceptance << ", ruptured " << r.ruptured << ", residual " << r.residual << " ("
            << r.polish_iterations << " polish iterations)\n";
    }
  }

  /// "not converged after N cycles": the rows of the completed steps stay in steps.csv, the
  /// checkpoint holds the last completed step; no summary (the run did not finish). Exit 4.
  int not_converged() {
    const auto& f = solver_->failed_step();
    if (!writer_) return 4;
    writer_->checkpoint(last_);
    std::cerr << "nacre: step " << f.step << " (D = " << f.displacement << ") not converged after " << f.cycles
              << " cycles"
              << (f.polish_iterations ? " and " + std::to_string(f.polish_iterations) + " polish iterations"
                                      : std::string())
              << ": residual " << f.residual << " > tolerance " << d_.solver.residual_tolerance << " ("
              << d_.where("solver.residual_tolerance") << ")"
              << (f.reverts ? " after " + std::to_string(f.reverts) + " smaller increments" : std::string())
              << "; steps.csv holds the " << last_.integer("step") << " completed steps and "
              << writer_->checkpoint_path().string() << " the last of them\n";
    return 4;
  }

  deck::Deck d_;
  const RunOptions& opt_;
  const par::Comm comm_;
  const bool root_;  ///< rank 0: logs and writes
  int signal_ = 0;   ///< agreed_signal()'s last answer
  RunSession session_;
  std::ostream* log_;
  const std::string text_, print_;  ///< the deck's physics text and its fingerprint (checkpoints)
  geometry::Specimen specimen_;
  geometry::Interfaces interfaces_;
  std::size_t n_free_ = 0;
  std::optional<mc::Checkpoint> cp_;
  std::optional<mc::Solver> solver_;
  std::optional<io::RunWriter> writer_;
  std::optional<fracture::CrackTracker> crack_;
  std::vector<double> iface_energy_;
  io::Checkpoint last_;
  int current_step_ = 0;
  bool step_done_ = false;  ///< the progress line names the step just finished (else the one in progress)
  double t_run_ = 0;
};

int run_deck(deck::Deck d, const RunOptions& opt, const par::Comm& comm) {
  return MonteCarloRun(std::move(d), opt, comm).run();
}

/// How many MPI ranks this process was started as one of (1: not under mpirun), from the
/// launchers' environment (Open MPI, MPICH / Intel MPI's PMI, MVAPICH).
int launched_ranks() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MV2_COMM_WORLD_SIZE"})
    if (const char* s = std::getenv(v)) {
      const int n = std::atoi(s);
      if (n > 1) return n;
    }
  return 1;
}

/// Standard output and error held back for the life of the object (the ranks other than 0 while
/// the command line, deck and checkpoint are validated: rank 0 prints the one message), kept in
/// text() for the case where this rank alone refused.
class Silence {
public:
  Silence() : out_(std::cout.rdbuf(held_.rdbuf())), err_(std::cerr.rdbuf(held_.rdbuf())) {}
  ~Silence() {
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
  }
  Silence(const Silence&) = delete;
  Silence& operator=(const Silence&) = delete;
  [[nodiscard]] std::string text() const { return held_.str(); }

private:
  std::ostringstream held_;
  std::streambuf *out_, *err_;
};

/// " on rank r of n" when the run has several ranks, else "".
std::string on_rank(const par::Comm& comm) {
  return comm.size() > 1 ? " on rank " + std::to_string(comm.rank()) + " of " + std::to_string(comm.size())
                         : std::string();
}

/// A run that failed with `code`: on several ranks the others may wait in a collective for this
/// one, so the whole run ends here (MPI_Abort); one process returns the code.
int failed(const par::Comm& comm, int code) {
  if (comm.size() > 1) comm.abort(code);
  return code;
}

}  // namespace

int main(int argc, char* argv[]) {
  // Log lines reach a file or a pipe as they are written (a batch job's output file, `| tee`),
  // not in 4 KiB blocks at the end: stdout line-buffered even when it is not a terminal
  // (std::cout writes through stdio, sync_with_stdio is left on).
  std::setvbuf(stdout, nullptr, _IOLBF, BUFSIZ);
  // A file-size limit (ulimit -f) makes a write fail with EFBIG, which the atomic writers report
  // by name and clean up, instead of killing the process silently with a temporary left behind.
  std::signal(SIGXFSZ, SIG_IGN);
  // Started as one of several MPI ranks (mpirun / mpiexec / srun): the Monte Carlo run is spread
  // over them (docs/scaling.md); a build without MPI, the sweep and the bench refuse before
  // anything is read or written (else every rank would run the whole deck into one directory).
  const int ranks = launched_ranks();
  const bool subcommand = argc > 1 && (std::string_view(argv[1]) == "sweep" || std::string_view(argv[1]) == "bench");
  if (ranks > 1 && (!par::has_mpi() || subcommand)) {
    // every rank says it (the launcher may end rank 0 as soon as another exits non-zero)
    std::cerr << "nacre: error: started as one of " << ranks << " MPI ranks; "
              << (subcommand ? "nacre " + std::string(argv[1]) + " runs on one rank"
                             : std::string("this nacre was built without MPI (configure with -DNACRE_ENABLE_MPI=ON)"))
              << ". Run it without mpirun / mpiexec.\n";
    return 2;
  }
  std::optional<par::Environment> mpi;  // outlives Kokkos (declared before its ScopeGuard)
  if (ranks > 1) mpi.emplace(argc, argv);
  par::Comm comm = par::Comm::world();
  // Every rank reads the same command line, deck and checkpoint: rank 0's messages say it all.
  // The others stay silent until the run (where a failure of one rank alone is printed by it).
  std::optional<Silence> silent;
  if (comm.rank() != 0) silent.emplace();
  // --kokkos-* flags go to Kokkos (ScopeGuard), the rest to CLI11. Both vectors end with the
  // argv[argc] == nullptr sentinel that Kokkos (and C convention) expect.
  if (argc > 1 && std::string_view(argv[1]) == "sweep") return sweep_main(argc, argv);
  if (argc > 1 && std::string_view(argv[1]) == "bench") return bench_main(argc, argv);
  if (asks_backend_list(argc, argv)) {  // the backends this build can run, the default first (no deck)
    const auto n = Backend::names();
    for (std::size_t k = 0; k < n.size(); ++k) std::cout << n[k] << (k == 0 ? " (default)" : "") << "\n";
    return 0;
  }
  // `nacre DECK ...` is `nacre run DECK ...`; `nacre check DECK ...` is `nacre run DECK --check ...`
  static char run_word[] = "run", check_flag[] = "--check";
  std::vector<char*> kokkos_args{argv[0]}, app_args{argv[0]};
  const std::string_view first = argc > 1 ? std::string_view(argv[1]) : std::string_view();
  const bool top_level = first.empty() || first == "-h" || first == "--help" || first == "--version";
  if (!top_level) app_args.push_back(run_word);
  for (int i = (first == "run" || first == "check") ? 2 : 1; i < argc; ++i)
    (std::string_view(argv[i]).starts_with("--kokkos-") ? kokkos_args : app_args).push_back(argv[i]);
  if (first == "check") app_args.push_back(check_flag);

  CLI::App cli{"nacre " + build_info().version +
               ": fracture of brick-and-mortar composites (rigid bricks by Monte Carlo; deformable bricks in time "
               "with a [dynamics] section)"};
  cli.set_version_flag("--version", version_text(), "print nacre's version and commit, the Kokkos version and "
                                                    "backends, and the optional libraries found, and exit");
  cli.require_subcommand(1);
  CLI::App* run_cmd = cli.add_subcommand("run", "run a deck (`nacre DECK` is the same)");
  cli.add_subcommand("check", "validate a deck, and with --restart its checkpoint, and exit (`nacre run DECK --check`)");
  cli.add_subcommand("sweep", "one run of a deck per combination of --set values (`nacre sweep --help`)");
  cli.add_subcommand("bench", "time a deck on each backend and check they agree (`nacre bench --help`)");
  std::string deck_path;
  std::string out_override;
  std::vector<std::string> sets;  // --set KEY=VALUE
  RunOptions opt;
  bool check_only = false, critical = false;
  deck::Deck d;
  // Everything is validated before Kokkos starts and before any output; on several ranks they
  // agree (the largest exit code) so that none goes on alone into the run's collectives.
  const auto prepare = [&]() -> int {
    run_cmd->add_option("deck", deck_path, "TOML input deck (see docs/decks.md)")->required();
    run_cmd->add_option("-o,--output", out_override, "output directory (overrides [output] directory)");
    run_cmd->add_option("--set", sets,
                        "SECTION.KEY=VALUE: set a deck key for this run (repeatable; validated as the deck is; "
                        "recorded in the run's deck.toml)");
    run_cmd->add_flag("-q,--quiet", opt.quiet, "no log lines or progress");
    run_cmd->add_flag("--check", check_only, "validate the deck and exit");
    run_cmd->add_option("--restart", opt.restart, "continue a run from its checkpoint.h5 (written at every dump)")
        ->check(CLI::ExistingFile);
    run_cmd->add_flag("--critical-step", critical,
                 "print the largest stable time step of a [dynamics] deck's method (bisection) and exit");
    run_cmd->add_flag("--overwrite", opt.overwrite,
                 "start afresh even where the output directory holds the checkpoint of an unfinished run");
    run_cmd->add_option("--backend", opt.backend,
                   "execution space the kernels run on: one of this build's backends (`nacre --backend list`); "
                   "default: Kokkos' default space")
        ->check([](const std::string& b) {
          return Backend::canonical(b).empty()
                     ? "\"" + b + "\" is not a backend of this build; expected one of: " + Backend::names_list()
                     : std::string();
        });
    run_cmd->add_option("--gpu-aware-mpi", opt.gpu_aware_mpi,
                   "on several MPI ranks with the data on a GPU: hand device buffers to MPI (on), stage them "
                   "through host memory (off), or on where the MPI reports GPU support (auto, the default)")
        ->check(CLI::IsMember({"auto", "on", "off"}));
    run_cmd->add_flag("--extend", opt.extend,
                 "with --restart: the deck's final_displacement may differ from the checkpoint's run "
                 "(continue a finished run further)");
    run_cmd->footer(
        "Kokkos flags such as --kokkos-num-threads=N are passed through to Kokkos.\n"
        "Exit codes: 0 done, 1 runtime failure (e.g. a write failed), 2 bad command line, deck or "
        "checkpoint, 3 dynamic run stopped unstable, 4 a load step not converged (residual above the tolerance "
        "after max_cycles; completed steps and their checkpoint kept), 130/143 stopped by SIGINT/SIGTERM (checkpoint written).");
    cli.footer("`nacre DECK` runs a deck (as `nacre run DECK`); `nacre COMMAND --help` shows a command's options.\n"
               "Kokkos flags such as --kokkos-num-threads=N are passed through to Kokkos.\n"
               "Exit codes: 0 done, 1 runtime failure, 2 bad command line, deck or checkpoint, 3 dynamic run "
               "stopped unstable, 4 a load step not converged, 130/143 stopped by SIGINT/SIGTERM.");
    if (const int rc = parse_command_line(cli, app_args, [&] { check_kokkos_flags(kokkos_args); }); rc >= 0) return rc;
    if (opt.extend && opt.restart.empty()) {
      std::cerr << "nacre: error: --extend needs --restart\n";
      return 2;
    }

    try {
      d = deck::parse_deck_file(deck_path);
      if (!sets.empty()) {
        const std::string path = d.path;
        d = deck::parse_deck_string(deck_with_sets(deck_path, d.text, sets), deck_path + " (with --set)");
        d.path = path;
      }
    } catch (const UsageError& e) {
      std::cerr << "nacre: error: " << e.what() << "\n";
      return 2;
    } catch (const deck::DeckError& e) {
      std::cerr << "nacre: error: " << e.what() << "\n";
      return 2;
    }
    if (!out_override.empty()) d.output.directory = out_override;
    if (!opt.backend.empty()) opt.backend = Backend::canonical(opt.backend);  // checked above: "Serial" -> "serial"
    if (critical && !d.dynamics.enabled) {
      std::cerr << "nacre: error: " << deck_path << ": --critical-step needs a [dynamics] section in the deck\n";
      return 2;
    }
    if (check_only) {
      std::cout << "nacre: " << deck_path << ": deck is valid\n";
      if (opt.restart.empty()) return 0;
      try {  // host-only: the specimen and the checkpoint, no Kokkos, no output
        geometry::Specimen specimen;
        geometry::Interfaces interfaces;
        std::size_t n_free = 0;
        if (d.dynamics.enabled) {  // the same validation as the run's (dyn_fields.hpp, run_dynamics)
          const DynCheckpoint cp = validated_dyn_checkpoint(d, opt.restart, opt.extend);
          check_restart_backend(opt.restart, cp.backend, opt.backend.empty() ? Backend::names().front() : opt.backend);
          std::cout << "nacre: " << opt.restart << ": checkpoint is valid for this deck (step " << cp.step
                    << ", t = " << cp.time << " s of " << d.dynamics.end_time << " s)\n";
          return 0;
        }
        build(d, specimen, interfaces, n_free);
        const mc::Checkpoint cp = validated_checkpoint(d, opt, specimen.size(), n_free);
        std::cout << "nacre: " << opt.restart << ": checkpoint is valid for this deck (step " << cp.run.step
                  << ", D = " << cp.displacement << ")\n";
        return 0;
      } catch (const deck::DeckError& e) {
        std::cerr << "nacre: error: " << e.what() << "\n";
      } catch (const io::CheckpointError& e) {
        std::cerr << "nacre: error: cannot restart: " << e.what() << "\n";
      }
      return 2;
    }
    if (comm.size() > 1) {  // what is not yet spread over ranks says so now
      std::string why = critical
                            ? d.path +
                                  ": --critical-step runs on one process (its trials are one-process runs); run it "
                                  "without mpirun"
                        : d.dynamics.enabled ? std::string()
                                             : mc::ranks_refusal(d, comm.size());
      if (!why.empty()) {
        std::cerr << "nacre: error: " << why << "\n";
        return 2;
      }
    }
    try {
      check_not_overwriting(d, opt.restart, opt.overwrite);
    } catch (const UsageError& e) {
      std::cerr << "nacre: error: " << e.what() << "\n";
      return 2;
    }
    return -1;
  };
  const int mine = prepare();
  int rc = mine;
  if (comm.size() > 1) {
    rc = static_cast<int>(comm.max(mine));
    // a refusal of another rank alone (a file it cannot read): it says why, rank 0 could not
    const int root_rc = static_cast<int>(comm.max(comm.rank() == 0 ? mine : -1));
    if (rc >= 0 && root_rc != rc && silent && mine == rc) {
      const std::string held = silent->text();
      silent.reset();
      std::cerr << "nacre: rank " << comm.rank() << " of " << comm.size() << ": " << held;
    }
    comm.barrier();  // printed before any rank exits
  }
  if (rc >= 0) return rc;
  silent.reset();
  if (comm.rank() != 0) opt.quiet = true;  // rank 0 logs
  std::optional<RunLog> run_log;  // rank 0's lines, also in the run directory's log.txt
  if (comm.rank() == 0 && !critical) run_log.emplace();
  if (comm.size() > 1) {
    const bool aware = par::mpi_device_aware();
    comm.set_device_direct(opt.gpu_aware_mpi == "on" || (opt.gpu_aware_mpi == "auto" && aware));
    if (opt.gpu_aware_mpi == "on" && !aware && comm.rank() == 0 &&
        !Kokkos::SpaceAccessibility<Kokkos::HostSpace, Kokkos::DefaultExecutionSpace::memory_space>::accessible)
      std::cerr << "nacre: warning: --gpu-aware-mpi on, but this MPI does not report GPU support; device "
                   "buffers are handed to it anyway\n";
  }
  // where the ranks sit, before Kokkos starts threads (an unbound launch put them on one core)
  const char* keep = std::getenv("NACRE_PLACEMENT");
  const par::Placement& placed = par::check_placement(comm, !(keep && std::string_view(keep) == "keep"));
  if (placed.shared && comm.rank() == 0)
    std::cerr << "nacre: warning: the " << placed.node_ranks << " ranks on this node could run on the same CPUs ("
              << "rank 0 on " << placed.cpus_at_start << "; an unbound launch such as mpirun --oversubscribe); "
              << (placed.rebound ? "nacre bound each rank to CPUs of its own (rank 0: " + placed.cpus +
                                       "; NACRE_PLACEMENT=keep leaves them as launched)"
                                 : std::string("launch with mpirun --bind-to core, or set OMP_PROC_BIND=false"))
              << "\n";
  kokkos_args.push_back(nullptr);
  int kargc = static_cast<int>(kokkos_args.size()) - 1;
  Kokkos::ScopeGuard guard(kargc, kokkos_args.data());
  if (const int t = Kokkos::DefaultHostExecutionSpace().concurrency(); par::oversubscribed(t) && comm.rank() == 0)
    std::cerr << "nacre: warning: " << placed.node_ranks << " rank(s) x " << t << " threads on " << placed.node_cpus
              << " CPUs: threads wait for each other; use --kokkos-num-threads="
              << std::max(1, placed.node_cpus / placed.node_ranks) << "\n";
  opt.tty = ::isatty(STDERR_FILENO) != 0;
  try {
    const Backend backend = opt.backend.empty() ? Backend{} : Backend::parse(opt.backend);
    if (critical) return print_critical_step(d, opt.quiet, backend);
    if (d.dynamics.enabled) return run_dynamics(d, {opt.quiet, opt.tty, opt.extend, opt.restart, backend, comm});
    return run_deck(d, opt, comm);
  } catch (const deck::DeckError& e) {  // (on several ranks each says it: an abort may end rank 0 first)
    std::cerr << "\nnacre: error" << on_rank(comm) << ": " << e.what() << "\n";
    return failed(comm, 2);
  } catch (const io::CheckpointError& e) {
    std::cerr << "\nnacre: error" << on_rank(comm) << ": cannot restart: " << e.what() << "\n";
    return failed(comm, 2);
  } catch (const std::bad_alloc&) {
    std::cerr << "\nnacre: error" << on_rank(comm)
              << ": out of memory (raise nothing: reduce the specimen, see [limits] in docs/decks.md)\n";
    return failed(comm, 1);
  } catch (const std::exception& e) {
    std::cerr << "\nnacre: error" << on_rank(comm) << ": " << e.what() << "\n";
    return failed(comm, 1);
  }
}

}  // namespace nacre::app
