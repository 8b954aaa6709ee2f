// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Quasi-static rigid-brick solver: load increments, each relaxed by colour-parallel
/// Metropolis sweeps until the sliding-window test converges (Chapter 2, MODEL.md §3), with the
/// adaptive step size, adaptive displacement and position predictor of §2.2.
#include <nacre/core/backend.hpp>
#include <nacre/deck/deck.hpp>
#include <nacre/mc/convergence.hpp>
#include <nacre/mc/kernels.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/mc/polish.hpp>
#include <nacre/par/comm.hpp>
#include <nacre/rng/uniform_source.hpp>

#include <functional>
#include <optional>
#include <iosfwd>
#include <string>
#include <memory>
#include <variant>

namespace nacre::mc {

/// \brief One row of the load-step table.
struct StepRecord {
  int step = 0;
  double displacement = 0, energy = 0, reaction = 0;
  long cycles = 0;
  double acceptance = 0;
  int ruptured = 0;
  bool converged = true;
  double step_size = 0, rot_step = 0, increment = 0;
  int reverts = 0;
  double seconds = 0;
  double residual = 0;        ///< largest generalised force on a free brick / its scale (gradient.hpp)
  long polish_iterations = 0;  ///< FIRE steps / Newton sweeps / trust-region Newton steps of the step
  long inner_iterations = 0;   ///< CG iterations of the trust-region Newton steps
  std::string method;          ///< what finished the step: monte-carlo, gradient, newton, newton+monte-carlo
  bool last = false;          ///< the step that reached the programme's last target: the run is done
};

/// \brief Where the loading programme stands between load steps (all a restart needs besides the
/// poses, the step sizes and the cycle counter).
struct RunState {
  int step = 0;                   ///< load steps done
  double increment = 0;           ///< next load increment (0: not started)
  double previous_increment = 0;  ///< increment of the last step (predictor ratio)
  bool have_previous = false;     ///< previous converged poses exist (predictor)
  double max_residual = 0;        ///< largest step residual so far (summary.json)
  long polish_iterations = 0;     ///< polish iterations so far (summary.json)
  long cg_iterations = 0;         ///< CG iterations of the trust-region Newton steps so far (summary.json)
  int leg = 0;                    ///< index of the programme target being approached (deck::Load::targets)
};

/// \brief Everything a checkpoint holds: restarting from it continues the run bit for bit.
struct Checkpoint {
  std::string colouring;
  std::string backend;  ///< where it was written (a restart may continue on any backend of the build: the same bits)
  RunState run;
  double displacement = 0, step_size = 0, rot_step = 0;
  std::uint64_t global_cycle = 0;
  long accepted_total = 0, trials_total = 0, window_accepted = 0, window_trials = 0;
  std::vector<double> pose, previous_pose;  ///< n x 3, original brick order
  std::vector<double> brick_step;           ///< step_mode per-brick: n x 3 (step, rot, accepted), original order; else empty
  /// damage = "irreversible": the damage history, n_interfaces x points (original interface
  /// order, a row per interface); else empty
  std::vector<double> history;
};

/// \brief The specimen-wide counts of a run (a rank's model holds only its part).
struct Sizes {
  std::size_t bricks = 0, free_bricks = 0, interfaces = 0;
  int colours = 0;
  int ranks = 1;  ///< processes the specimen is spread over
  /// how halo messages travel on several ranks: "host memory", "device memory, direct (GPU-aware
  /// MPI)" or "device memory, staged through host"; "" on one process
  std::string halo_messages;
};

/// \brief What a dump shows per brick and per interface, in the specimen's order: on one process,
/// or on rank 0 of several (the others get empty arrays: only rank 0 writes).
struct OutputFields {
  std::vector<double> x, y, theta;           ///< poses
  std::vector<double> brick_energy;          ///< half of each of the brick's interfaces' energies
  std::vector<double> interface_energy;      ///< cohesive energy of each interface
  std::vector<std::int8_t> interface_state;  ///< 0 elastic, 1 softening, 2 ruptured
};

/// \brief Wall time per phase (fenced), the split of Fig. 2.12.
struct PhaseTimes {
  double rng = 0, sweep = 0, energy = 0, other = 0, polish = 0;
};

template <class Exec>
class SolverOn;

namespace detail {
template <class Spaces>
struct SolverImpls;
template <class... Spaces>
struct SolverImpls<std::variant<Spaces...>> {
  using type = std::variant<std::unique_ptr<SolverOn<Spaces>>...>;
};
}  // namespace detail

/// \brief The Monte Carlo solver on a run's backend: the backend picks, once, the execution space
/// the whole solver is built for (SolverOn<Exec>, src/mc/solver_on.hpp), and every kernel,
/// allocation and copy of the run (the uniform source's batches, the polish) goes to its
/// instance. The same bits on every backend of a build (tests/test_backends.cpp).
class Solver {
public:
  /// \brief Colours the bricks (running the pre-simulation when colouring = "fastest") and uploads
  /// the model. `log` gets one line per decision (may be null).
  Solver(const Backend& backend, const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
         std::ostream* log = nullptr);
  /// \brief Spread over the ranks of `comm` (docs/scaling.md): each rank builds and relaxes its
  /// part of the specimen (owned bricks and a one-brick halo), every rank calls every member in
  /// the same order, and every result is the one-process result, bit for bit. Supported so far:
  /// every relaxation ("auto", "newton", "monte-carlo", "gradient") with the polishes "fire",
  /// "newton", "trust-region" and "none", colourings other than "fastest" (std::invalid_argument
  /// otherwise: ranks_refusal). The members that return specimen-wide arrays gather them from
  /// every rank, so each rank must call them: checkpoint(), interface_states() and output_fields()
  /// to rank 0 alone (the writer; the others get empty arrays), poses() to every rank.
  /// comm.size() == 1: the one-process solver.
  Solver(const Backend& backend, const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
         std::ostream* log, const par::Comm& comm);
  /// \brief The same on the default backend.
  Solver(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f, std::ostream* log = nullptr)
      : Solver(Backend{}, d, s, f, log) {}
  ~Solver();
  // the implementation calls back into on_progress / should_stop of this object: it stays put
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  /// \brief The backend the solver runs on.
  [[nodiscard]] Backend backend() const;

  /// \brief This process's model (on one of several ranks: its part of the specimen), when the
  /// backend keeps it in the default memory space (std::logic_error otherwise: a host backend of a
  /// CUDA build keeps it in host memory).
  [[nodiscard]] const Model<>& model() const;
  /// \brief The colouring the model was built with (its name: "tiles", "natural", ...).
  [[nodiscard]] const std::string& colouring_name() const;
  /// \brief The specimen-wide counts (the model's own on one process).
  [[nodiscard]] Sizes sizes() const;
  /// \brief Pre-simulation timings (candidate, seconds per cycle), in the order tried; empty
  /// unless the deck asked for colouring = "fastest".
  [[nodiscard]] const std::vector<std::pair<std::string, double>>& presim() const;

  /// \brief Move the driven bricks to load D (free bricks stay).
  void set_load(double D);
  [[nodiscard]] double load() const;
  /// \brief Exact total energy (a reduction over all interfaces).
  double energy();
  /// \brief Generalised reaction dE/dD at fixed free bricks (central difference).
  double reaction();
  /// \brief Interfaces at rupture (separated past x1 + x2 along the whole segment: cohesive::min_separation).
  int ruptured();
  /// \brief Per interface, in the geometry's order: 0 elastic, 1 softening, 2 ruptured (as the
  /// dumps' "state"; fracture::CrackTracker reads the crack from it).
  /// `energy` (optional) gets each interface's energy of fracture in the same order: what it
  /// dissipated with damage = "irreversible", its cohesive energy otherwise. On several ranks:
  /// gathered to rank 0 (the others get empty vectors).
  [[nodiscard]] std::vector<std::int8_t> interface_states(std::vector<double>* energy = nullptr);
  /// \brief Poses, brick energies, interface energies and states of the current state (a dump's
  /// fields), gathered to rank 0 (empty on the other ranks).
  [[nodiscard]] OutputFields output_fields();
  /// \brief Residual of the current state (exact gradient; see gradient.hpp for the scale).
  double residual();
  /// \brief Polish the current state with the deck's method and tolerance (or `method`, and
  /// `tolerance` when > 0); see polish.hpp. "anneal" is Monte Carlo cooled to T = 0 (anneal()).
  PolishResult polish(const std::string& method = "", double tolerance = 0);
  /// \brief Simulated annealing to a residual (the alternative to a gradient polish):
  /// Monte Carlo cycles at a temperature halved every `AdaptInter` cycles from the deck's TEMP
  /// (and 0 once it is below 1e-12 of it), with per-brick step sizes (whatever the run's
  /// step_mode) adapted by eq. 2.7's rule about an acceptance of 0.2 instead of 0.5, their floors
  /// lowered (MinStepSize and MinRotSize times 1e-6) so the trial moves can shrink to the distance
  /// from the minimum; the residual is checked after every block of `AdaptInter` cycles.
  /// Iterations are cycles; the run's own step sizes are untouched. `should_stop` is asked after
  /// every block: true ends the anneal unconverged with interrupted() set.
  PolishResult anneal(const PolishOptions& o);
  /// \brief The scales the residual is measured against.
  [[nodiscard]] const ResidualScale& residual_scale() const;
  /// \brief Exact gradient per free brick after residual() or polish() (sweep order), in the
  /// default memory space (as model()).
  [[nodiscard]] const GradientView<>& gradient() const;

  /// \brief One MC cycle (RNG batch + every colour once); returns accepted trials.
  long cycle();
  /// \brief Bytes one cycle must move at least (each array the sweep streams read once, the
  /// written ones twice: poses, slot records, energy cache, uniforms, per-brick steps, history),
  /// the numerator of `nacre bench`'s fraction of the triad bound.
  [[nodiscard]] std::size_t cycle_bytes() const;
  /// \brief Flops of one cycle's trials at the current state (mc/trial_flops.hpp: the trials'
  /// own code run on a counting scalar), the numerator of `nacre bench`'s fraction of the FMA
  /// bound; nullopt with a damage history (the irreversible law is not counted).
  [[nodiscard]] std::optional<double> cycle_flops() const;
  /// \brief Relax at the current load until converged or max_cycles; returns cycles done.
  long relax(bool& converged);
  /// \brief Apply the (rest of the) loading programme of the deck; calls on_step after each
  /// increment.
  void run(const std::function<void(const StepRecord&)>& on_step);

  /// \brief Snapshot for a restart (taken between load steps, e.g. from on_step). On several
  /// ranks its arrays are gathered to rank 0 (the others get the scalars and empty arrays).
  [[nodiscard]] Checkpoint checkpoint() const;
  /// \brief Continue from a checkpoint (the solver must have been built with its colouring).
  void restore(const Checkpoint& c);
  [[nodiscard]] const RunState& run_state() const;
  /// \brief The run has reached the programme's last target (nothing left for run()).
  [[nodiscard]] bool finished() const;
  /// \brief Fraction of the load path travelled (progress): 0 at the start, 1 at the end.
  [[nodiscard]] double path_fraction() const;
  /// \brief Energy dissipated by damage so far (0 with the reversible law; deterministic sum).
  double dissipated();

  /// \brief Called after every cycle inside a step with (cycles so far, energy), for progress
  /// (the caller throttles by time).
  std::function<void(long, double)> on_progress;
  /// \brief Asked after every cycle (e.g. a signal flag); true abandons the load step in
  /// progress and returns from run() with interrupted() set. The state is then mid-step: resume
  /// from a checkpoint taken after the last completed step.
  std::function<bool()> should_stop;
  [[nodiscard]] bool interrupted() const;
  /// \brief With convergence = "residual": a load step did not reach the tolerance within
  /// max_cycles (after any backtracking); run() returned without completing it, failed_step()
  /// describes it. The poses are mid-step; the last completed step's checkpoint is the good state.
  [[nodiscard]] bool failed() const;
  [[nodiscard]] const StepRecord& failed_step() const;
  /// \brief Largest step residual of the run (restarts included: kept in the checkpoint).
  [[nodiscard]] double max_step_residual() const { return run_state().max_residual; }
  /// \brief Polish iterations of the run's completed steps (restarts included).
  [[nodiscard]] long polish_iterations_total() const { return run_state().polish_iterations; }

  [[nodiscard]] const PhaseTimes& times() const;
  [[nodiscard]] double step_size() const;
  [[nodiscard]] double rot_step() const;
  [[nodiscard]] std::uint64_t global_cycle() const;
  [[nodiscard]] double tracked_energy() const;

  /// \brief Host copies of the poses, in original brick order (for output and tests).
  void poses(std::vector<double>& x, std::vector<double>& y, std::vector<double>& t) const;

private:
  /// f(the implementation): every member above forwards through here.
  template <class F>
  decltype(auto) on(F&& f) const;
  typename detail::SolverImpls<AnySpace>::type impl_;
};

/// \brief Why the deck's Monte Carlo run cannot be spread over `ranks` MPI ranks (naming the deck
/// key and what it expects), or "" when it can (the Solver constructor with a Comm throws
/// std::invalid_argument with this message; the app checks it before it writes anything).
[[nodiscard]] std::string ranks_refusal(const deck::Deck& d, int ranks);

/// \brief The colouring that colouring = "auto" stands for on a backend: "tiles" when it runs on
/// the host, "natural" (one brick per thread) on a device.
[[nodiscard]] std::string auto_colouring(const Backend& backend = Backend{});

}  // namespace nacre::mc
