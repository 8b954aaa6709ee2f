#pragma once
/// \file
/// \brief Quasi-static rigid-brick solver: load increments, each relaxed by colour-parallel
/// Metropolis sweeps until the sliding-window test converges (Chapter 2, MODEL.md §3), with the
/// adaptive step size, adaptive displacement and position predictor of §2.2.
#include <nacre/deck/deck.hpp>
#include <nacre/mc/convergence.hpp>
#include <nacre/mc/kernels.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/mc/polish.hpp>
#include <nacre/rng/uniform_source.hpp>

#include <functional>
#include <iosfwd>
#include <memory>

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
  long polish_iterations = 0; ///< FIRE steps / Newton sweeps of the step
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
  int leg = 0;                    ///< index of the programme target being approached (deck::Load::targets)
};

/// \brief Everything a checkpoint holds: restarting from it continues the run bit for bit.
struct Checkpoint {
  std::string colouring;
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

/// \brief Wall time per phase (fenced), the split of Fig. 2.12.
struct PhaseTimes {
  double rng = 0, sweep = 0, energy = 0, other = 0, polish = 0;
};

/// \brief The Monte Carlo solver on one execution-space instance: every kernel, allocation and
/// copy of the run goes through `space()`, the uniform source's batches included.
class Solver {
public:
  /// \brief Colours the bricks (running the pre-simulation when colouring = "fastest") and uploads
  /// the model. `log` gets one line per decision (may be null).
  Solver(const ExecSpace& space, const deck::Deck& d, const geometry::Specimen& s,
         const geometry::Interfaces& f, std::ostream* log = nullptr);
  /// \brief The same on a default instance of the default execution space.
  Solver(const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
         std::ostream* log = nullptr)
      : Solver(ExecSpace{}, d, s, f, log) {}

  [[nodiscard]] const ExecSpace& space() const { return space_; }

  [[nodiscard]] const Model<>& model() const { return m_; }
  /// \brief Pre-simulation timings (candidate, seconds per cycle), in the order tried; empty
  /// unless the deck asked for colouring = "fastest".
  [[nodiscard]] const std::vector<std::pair<std::string, double>>& presim() const { return presim_; }

  /// \brief Move the driven bricks to load D (free bricks stay).
  void set_load(double D);
  [[nodiscard]] double load() const { return D_; }
  /// \brief Exact total energy (a reduction over all interfaces).
  double energy();
  /// \brief Generalised reaction dE/dD at fixed free bricks (central difference).
  double reaction();
  /// \brief Interfaces at rupture (separated past x1 + x2 along the whole segment: cohesive::min_separation).
  int ruptured();
  /// \brief Per interface, in the geometry's order: 0 elastic, 1 softening, 2 ruptured (as the
  /// dumps' "state"; fracture::CrackTracker reads the crack from it).
  /// `energy` (optional) gets each interface's energy of fracture in the same order: what it
  /// dissipated with damage = "irreversible", its cohesive energy otherwise.
  [[nodiscard]] std::vector<std::int8_t> interface_states(std::vector<double>* energy = nullptr);
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
  [[nodiscard]] const ResidualScale& residual_scale() const { return scale_; }
  /// \brief Exact gradient per free brick after residual() or polish() (sweep order).
  [[nodiscard]] const GradientView<>& gradient() const { return polisher_.gradient(); }

  /// \brief One MC cycle (RNG batch + every colour once); returns accepted trials.
  long cycle();
  /// \brief Relax at the current load until converged or max_cycles; returns cycles done.
  long relax(bool& converged);
  /// \brief Apply the (rest of the) loading programme of the deck; calls on_step after each
  /// increment.
  void run(const std::function<void(const StepRecord&)>& on_step);

  /// \brief Snapshot for a restart (taken between load steps, e.g. from on_step).
  [[nodiscard]] Checkpoint checkpoint() const;
  /// \brief Continue from a checkpoint (the solver must have been built with its colouring).
  void restore(const Checkpoint& c);
  [[nodiscard]] const RunState& run_state() const { return run_; }
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
  [[nodiscard]] bool interrupted() const { return interrupted_; }
  /// \brief With convergence = "residual": a load step did not reach the tolerance within
  /// max_cycles (after any backtracking); run() returned without completing it, failed_step()
  /// describes it. The poses are mid-step; the last completed step's checkpoint is the good state.
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] const StepRecord& failed_step() const { return failed_step_; }
  /// \brief Largest step residual of the run (restarts included: kept in the checkpoint).
  [[nodiscard]] double max_step_residual() const { return run_.max_residual; }
  /// \brief Polish iterations of the run's completed steps (restarts included).
  [[nodiscard]] long polish_iterations_total() const { return run_.polish_iterations; }

  [[nodiscard]] const PhaseTimes& times() const { return times_; }
  [[nodiscard]] double step_size() const { return step_; }
  [[nodiscard]] double rot_step() const { return rot_step_; }
  [[nodiscard]] std::uint64_t global_cycle() const { return global_cycle_; }
  [[nodiscard]] double tracked_energy() const { return E_; }

  /// \brief Host copies of the poses, in original brick order (for output and tests).
  void poses(std::vector<double>& x, std::vector<double>& y, std::vector<double>& t) const;

private:
  /// What both public constructors start from: the deck's parameters, no model yet.
  Solver(const ExecSpace& space, const deck::Deck& d, std::ostream* log);
  /// \brief A solver on a given colouring (a pre-simulation candidate).
  Solver(const ExecSpace& space, const deck::Deck& d, const geometry::Specimen& s,
         const geometry::Interfaces& f, const geometry::Adjacency& adj, const Colouring& c);
  /// \brief The pre-simulation (§2.4): each candidate colouring gets a fresh solver, timed for a
  /// few cycles and thrown away; returns the colouring to use, appends timings to `presim`.
  static std::string presimulate(const ExecSpace& space, const deck::Deck& d, const geometry::Specimen& s,
                                 const geometry::Interfaces& f, const geometry::Adjacency& adj,
                                 std::vector<std::pair<std::string, double>>& presim, std::ostream* log);
  void setup(const geometry::Specimen& s, const geometry::Interfaces& f, const geometry::Adjacency& adj,
             const Colouring& c);
  void allocate_work();
  void predict(double ratio);
  long mc_phase(long budget, bool& window_converged);

  /// What the solver reads of the deck, kept from construction (the sections it needs, not the
  /// deck's text and key table), with the run-time choices parsed once: no string compares in
  /// the loops.
  struct Settings {
    deck::Load load;
    deck::MonteCarlo mc;
    deck::Mortar mortar;
    double brick_width = 0, brick_height = 0;
    std::uint64_t seed = 1;
    bool by_residual = true;     ///< convergence = "residual" (else "window")
    bool gradient_only = false;  ///< relaxation = "gradient"
    PolishMethod polish = PolishMethod::fire;
    explicit Settings(const deck::Deck& d);
  };

  ExecSpace space_;
  Settings cfg_;
  Model<> m_;
  loading::Pattern pattern_;
  std::unique_ptr<rng::UniformSource> source_;
  rng::UniformTable<> u_;
  SumWorkspace<> sum_ws_;
  Field<double> de_;  ///< accepted energy change per free brick in the current cycle
  /// Each interface's energy at the current poses (the sweep's cache, kernels.hpp); valid only
  /// while cache_valid_: every pose change outside the sweep clears the flag, cycle() refills.
  Field<double> iface_energy_;
  bool cache_valid_ = false;
  BrickSteps<> brick_steps_;  ///< step_mode = "per-brick" only
  Model<>::PoseView prev_pose_, save_pose_;  ///< previous converged step (predictor), step start (revert)
  Field<double> phi_;
  ConvergenceMonitor monitor_;
  std::vector<std::pair<std::string, double>> presim_;
  PhaseTimes times_;
  double D_ = 0, E_ = 0, step_, rot_step_;
  double temperature_;        ///< of the sweep: the deck's TEMP, lower while anneal() runs
  double step_floor_ = 1.0;   ///< factor on the per-brick steps' floors (1e-6 while anneal() runs)
  double acceptance_target_ = 0.5;  ///< of the per-brick step adaptation (eq. 2.7: 0.5; 0.2 while anneal() runs)
  long window_accepted_ = 0, window_trials_ = 0;  ///< since the last step-size adaptation
  long accepted_total_ = 0, trials_total_ = 0;
  long cycle_limit_ = 0;
  RunState run_;  ///< > 0: relax() gives up after this many cycles (backtracking)
  std::uint64_t global_cycle_ = 0;
  bool interrupted_ = false;
  Polisher polisher_;
  ResidualScale scale_;
  PolishOptions polish_options_;
  double residual_ = 0;   ///< of the last relax()
  long step_polish_ = 0;  ///< polish iterations of the last relax()
  bool failed_ = false;
  StepRecord failed_step_;
  std::ostream* log_;
};

/// \brief The colouring that colouring = "auto" stands for on this build: "tiles" when the
/// default execution space runs on the host, "natural" (one brick per thread) on a device.
[[nodiscard]] std::string auto_colouring();

}  // namespace nacre::mc
