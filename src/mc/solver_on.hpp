// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The Monte Carlo solver on one execution space: mc::Solver (include/nacre/mc/solver.hpp) is its
// face, picks the space once from the run's Backend and forwards every call here.
//
// Why a template to the top: every kernel, allocation and copy of a run (the sweep, the energy
// reductions, the uniform source's batches, the polish, the anneal) launches on `space_` with its
// own type, so a build with Serial and OpenMP (or CUDA) runs either from one binary and the
// loops carry no per-launch dispatch. The members mirror Solver's; solver.hpp documents them.
#include <nacre/mc/halo.hpp>
#include <nacre/mc/solver.hpp>

#include <optional>

namespace nacre::mc {

/// \brief How a load step is relaxed (deck key relaxation).
enum class Relaxation { monte_carlo, gradient, newton, automatic };

template <class Exec>
class SolverOn {
public:
  /// where the model, the state and every work array live: the execution space's own memory
  using Mem = MemOf<Exec>;

  /// `owner` (may be null: a pre-simulation candidate) is the face whose on_progress and
  /// should_stop hooks the loops call.
  SolverOn(const Exec& space, const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
           const Solver* owner, std::ostream* log, const par::Comm& comm = {});

  [[nodiscard]] const Exec& space() const { return space_; }
  [[nodiscard]] const Model<Mem>& model() const { return m_; }
  [[nodiscard]] Sizes sizes() const;
  [[nodiscard]] OutputFields output_fields();
  [[nodiscard]] const std::vector<std::pair<std::string, double>>& presim() const { return presim_; }
  void set_load(double D);
  [[nodiscard]] double load() const { return D_; }
  double energy();
  double reaction();
  int ruptured();
  [[nodiscard]] std::vector<std::int8_t> interface_states(std::vector<double>* energy = nullptr);
  double residual();
  PolishResult polish(const std::string& method = "", double tolerance = 0);
  PolishResult polish_with(PolishMethod method, double tolerance = 0);
  PolishResult anneal(const PolishOptions& o);
  [[nodiscard]] const ResidualScale& residual_scale() const { return scale_; }
  [[nodiscard]] const GradientView<Mem>& gradient() const { return polisher_.gradient(); }
  long cycle();
  [[nodiscard]] std::size_t cycle_bytes() const;
  [[nodiscard]] std::optional<double> cycle_flops() const;
  long relax(bool& converged);
  void run(const std::function<void(const StepRecord&)>& on_step);
  [[nodiscard]] Checkpoint checkpoint() const;
  void restore(const Checkpoint& c);
  [[nodiscard]] const RunState& run_state() const { return run_; }
  [[nodiscard]] bool finished() const;
  [[nodiscard]] double path_fraction() const;
  double dissipated();
  [[nodiscard]] bool interrupted() const { return interrupted_; }
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] const StepRecord& failed_step() const { return failed_step_; }
  [[nodiscard]] const PhaseTimes& times() const { return times_; }
  [[nodiscard]] double step_size() const { return step_; }
  [[nodiscard]] double rot_step() const { return rot_step_; }
  [[nodiscard]] std::uint64_t global_cycle() const { return global_cycle_; }
  [[nodiscard]] double tracked_energy() const { return E_; }
  void poses(std::vector<double>& x, std::vector<double>& y, std::vector<double>& t) const;

private:
  /// What both constructors start from: the deck's parameters, no model yet.
  SolverOn(const Exec& space, const deck::Deck& d, const Solver* owner, std::ostream* log);
  /// A solver on a given colouring (a pre-simulation candidate).
  SolverOn(const Exec& space, const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
           const geometry::Adjacency& adj, const Colouring& c);
  static std::string presimulate(const Exec& space, const deck::Deck& d, const geometry::Specimen& s,
                                 const geometry::Interfaces& f, const geometry::Adjacency& adj,
                                 std::vector<std::pair<std::string, double>>& presim, std::ostream* log);
  void setup(const geometry::Specimen& s, const geometry::Interfaces& f, const geometry::Adjacency& adj,
             const Colouring& c, const par::Comm& comm = {});
  /// deterministic_sum's combine for `owned` terms of this rank (every term in one process)
  [[nodiscard]] par::Reduce over(long long owned) const {
    return reduce_over(dist_.get(), owned);
  }
  /// after a move of every brick (load aside: apply_load leaves the halo alone): the halo's poses
  void refresh_halo() {
    if (dist_) dist_->refresh(space_, m_);
  }
  /// what is not yet spread over ranks says so
  void one_process_only(const char* what) const;
  /// the specimen's numbering of local brick k (sweep order) and model interface i, whether this
  /// rank owns them, and the specimen's counts (a rank's part, or everything in one process)
  [[nodiscard]] int global_brick(int k) const { return dist_ ? dist_->d.bricks[m_.perm[k]] : m_.perm[k]; }
  [[nodiscard]] int global_interface(int i) const {
    return dist_ ? dist_->d.interfaces[m_.iface_perm[i]] : m_.iface_perm[i];
  }
  [[nodiscard]] bool owned_brick(int k) const { return !dist_ || m_.perm[k] < dist_->d.n_owned; }
  [[nodiscard]] bool owned_interface(int i) const { return !dist_ || dist_->d.iface_owned[m_.iface_perm[i]]; }
  [[nodiscard]] std::size_t n_bricks_global() const { return dist_ ? dist_->d.owner.size() : m_.perm.size(); }
  [[nodiscard]] std::size_t n_interfaces_global() const { return dist_ ? dist_->n_interfaces : m_.iface_perm.size(); }
  /// the array of `width` values per item whose owned items' (index, values...) records `mine`
  /// holds on each rank: on every rank, in the specimen's order (zeros where no rank has an item)
  /// (to_root: rank 0 alone gets the array, the others an empty one; a dump needs no more)
  [[nodiscard]] std::vector<double> assemble(std::size_t n, int width, const std::vector<double>& mine,
                                             bool to_root = false) const;
  /// every brick's (x, y, theta), specimen order
  [[nodiscard]] std::vector<double> checkpoint_poses() const;
  void allocate_work();
  void predict(double ratio);
  long mc_phase(long budget, bool& window_converged);
  long relax_auto(bool& converged, long limit);
  /// The face's hooks (none for a pre-simulation candidate).
  [[nodiscard]] bool stop_requested() const { return owner_ && owner_->should_stop && owner_->should_stop(); }
  void report_progress(long cycles, double energy) const {
    if (owner_ && owner_->on_progress) owner_->on_progress(cycles, energy);
  }

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
    Relaxation relax = Relaxation::monte_carlo;
    PolishMethod polish = PolishMethod::fire;
    explicit Settings(const deck::Deck& d);
  };

  Exec space_;
  Settings cfg_;
  Model<Mem> m_;
  loading::Pattern pattern_;
  std::unique_ptr<rng::UniformSource> source_;
  rng::UniformTable<Mem> u_;
  SumWorkspace<Mem> sum_ws_;
  Field<double, Mem> de_;  ///< accepted energy change per free brick in the current cycle
  /// Each interface's energy at the current poses (the sweep's cache, kernels.hpp); valid only
  /// while cache_valid_: every pose change outside the sweep clears the flag, cycle() refills.
  Field<double, Mem> iface_energy_;
  bool cache_valid_ = false;
  BrickSteps<Mem> brick_steps_;                          ///< step_mode = "per-brick" only
  typename Model<Mem>::PoseView prev_pose_, save_pose_;  ///< previous converged step (predictor), step start (revert)
  Field<double, Mem> phi_;
  ConvergenceMonitor monitor_;
  std::vector<std::pair<std::string, double>> presim_;
  PhaseTimes times_;
  double D_ = 0, E_ = 0, step_, rot_step_;
  double temperature_;              ///< of the sweep: the deck's TEMP, lower while anneal() runs
  double step_floor_ = 1.0;         ///< factor on the per-brick steps' floors (1e-6 while anneal() runs)
  double acceptance_target_ = 0.5;  ///< of the per-brick step adaptation (eq. 2.7: 0.5; 0.2 while anneal() runs)
  long window_accepted_ = 0, window_trials_ = 0;  ///< since the last step-size adaptation
  long accepted_total_ = 0, trials_total_ = 0;
  long cycle_limit_ = 0;  ///< > 0: relax() gives up after this many cycles (backtracking)
  RunState run_;
  std::uint64_t global_cycle_ = 0;
  bool interrupted_ = false;
  Polisher<Exec> polisher_;
  ResidualScale scale_;
  PolishOptions polish_options_;
  double residual_ = 0;   ///< of the last relax()
  long step_polish_ = 0;  ///< polish iterations of the last relax()
  long step_inner_ = 0;   ///< CG iterations of the last relax() (trust region)
  std::string step_method_;       ///< what finished the last relax() (StepRecord::method)
  int step_ruptured0_ = 0;        ///< ruptured joints at the start of the load step (relaxation = "auto")
  typename Model<Mem>::PoseView
      burst_pose_;  ///< relaxation = "auto": Newton's state while a burst looks for a lower one
  bool failed_ = false;
  StepRecord failed_step_;
  const Solver* owner_ = nullptr;
  std::unique_ptr<Distribution<Mem>> dist_;  ///< this rank's part of a specimen spread over ranks (null: all here)
  std::ostream* log_;
};

}  // namespace nacre::mc
