// SPDX-License-Identifier: BSD-3-Clause
// mc::Solver: the Monte Carlo solver's members on one execution space (SolverOn<Exec>,
// solver_on.hpp) and the face that picks the space from the run's Backend and forwards to them.
#include "solver_on.hpp"

#include <nacre/mc/trial_flops.hpp>
#include <nacre/rng/registry.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <stdexcept>

namespace nacre::mc {

namespace {
std::vector<bool> free_flags(const geometry::Specimen& s) {
  std::vector<bool> free(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) free[i] = s.drive[i] == geometry::Drive::free;
  return free;
}
}  // namespace

namespace {
/// The deck's relaxation; "auto" with the irreversible law (a path that turns back: the
/// Hessian needs the reversible law, hessian.hpp) is Monte Carlo with the polish.
Relaxation parse_relaxation(const deck::Deck& d) {
  const std::string& r = d.solver.relaxation;
  if (r == "gradient") return Relaxation::gradient;
  if (r == "newton") return Relaxation::newton;
  if (r == "auto")
    return d.mortar.damage == cohesive::Damage::irreversible ? Relaxation::monte_carlo : Relaxation::automatic;
  return Relaxation::monte_carlo;
}

Colouring make_colouring(const std::string& name, const geometry::Specimen& s, const geometry::Adjacency& adj,
                         const std::vector<bool>& free, std::uint64_t seed) {
  Colouring c = colour_graph(name, s, adj, free, seed);
  if (auto err = validate_colouring(c, adj, free); !err.empty())
    throw std::logic_error("colouring '" + name + "' is invalid: " + err);
  return c;
}
}  // namespace

template <class Exec>
SolverOn<Exec>::Settings::Settings(const deck::Deck& d)
    : load(d.load), mc(d.solver), mortar(d.mortar), brick_width(d.geometry.brick_width),
      brick_height(d.geometry.brick_height), seed(d.seed), by_residual(d.solver.convergence == "residual"),
      relax(parse_relaxation(d)), polish(parse_polish_method(d.solver.polish)) {}

template <class Exec>
SolverOn<Exec>::SolverOn(const Exec& space, const deck::Deck& d, const Solver* owner, std::ostream* log)
    : space_(space), cfg_(d), pattern_{d.load.tension, d.load.bending, d.geometry.width},
      monitor_(d.solver.window_size, d.solver.convergence_rep, d.solver.stol, d.solver.rtol, d.solver.stol_relative),
      step_(d.solver.step), rot_step_(d.solver.rot_step), temperature_(d.solver.temperature), owner_(owner), log_(log) {
}

template <class Exec>
SolverOn<Exec>::SolverOn(const Exec& space, const deck::Deck& d, const geometry::Specimen& s,
                         const geometry::Interfaces& f, const Solver* owner, std::ostream* log, const par::Comm& comm)
    : SolverOn(space, d, owner, log) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::setup");
  const auto adj = geometry::build_adjacency(s.size(), f);
  std::string chosen = d.solver.colouring;
  // "auto" is a fixed rule, so the same deck and seed give the same result on the same build:
  // tiles (cache-friendly, one thread per tile) where the run's backend runs on the host, the
  // per-brick natural colouring (one thread per brick) on devices. "fastest" times every
  // candidate (results may then differ between runs; the pick goes to summary.json).
  if (chosen == "auto") chosen = auto_colouring(Backend(space_));
  if (comm.size() > 1)  // what is not yet spread over ranks (docs/scaling.md) says so before any work
    if (const std::string why = ranks_refusal(d, comm.size()); !why.empty()) throw std::invalid_argument(why);
  if (chosen == "fastest") chosen = presimulate(space_, d, s, f, adj, presim_, log_);
  const Colouring c = make_colouring(chosen, s, adj, free_flags(s), d.seed);
  setup(s, f, adj, c, comm);
  const Sizes z = sizes();  // the specimen's (a rank's model holds its part)
  if (log_)
    *log_ << "  colouring: " << chosen << " (" << c.n_colours << " colours), " << z.free_bricks << " free and "
          << (z.bricks - z.free_bricks) << " driven bricks, " << z.interfaces << " interfaces"
          << (z.ranks > 1 ? ", spread over " + std::to_string(z.ranks) + " ranks" : "") << "\n";
}

std::string ranks_refusal(const deck::Deck& d, int ranks) {
  const std::string on = " on " + std::to_string(ranks) + " MPI ranks (docs/scaling.md); run it on one rank";
  // newton and auto relax with the trust region whatever the polish; the others polish with it
  const Relaxation r = parse_relaxation(d);
  const PolishMethod p = parse_polish_method(d.solver.polish);
  if ((r == Relaxation::monte_carlo || r == Relaxation::gradient) && p == PolishMethod::anneal)
    return d.where("solver.polish") + ": polish = \"" + d.solver.polish +
           "\" is not yet spread over ranks; expected \"fire\", \"newton\", \"trust-region\" or \"none\" for a run" +
           on;
  if (d.solver.colouring == "fastest")
    return d.where("solver.colouring") +
           ": colouring = \"fastest\" picks by timing, which ranks need not agree on; expected a named colouring "
           "(or \"auto\") for a run" +
           on;
  return "";
}

std::string auto_colouring(const Backend& backend) {
  return backend.reaches<Kokkos::HostSpace>() ? "tiles" : "natural";
}

template <class Exec>
SolverOn<Exec>::SolverOn(const Exec& space, const deck::Deck& d, const geometry::Specimen& s,
                         const geometry::Interfaces& f, const geometry::Adjacency& adj, const Colouring& c)
    : SolverOn(space, d, nullptr, nullptr) {
  setup(s, f, adj, c);
}

template <class Exec>
void SolverOn<Exec>::setup(const geometry::Specimen& s, const geometry::Interfaces& f, const geometry::Adjacency& adj,
                           const Colouring& c, const par::Comm& comm) {
  source_ = rng::make_uniform_source(cfg_.mc.rng, cfg_.seed);
  if (comm.size() > 1) {
    dist_ = distribute(space_, comm, s, f, adj, c, cfg_.mortar, cfg_.mc.quadrature_points, m_);
  } else {
    m_ = build_model(space_, s, f, adj, c, cfg_.mortar, cfg_.mc.quadrature_points);
  }
  allocate_work();
  const std::string& pc = cfg_.mc.newton_preconditioner;
  polisher_ = Polisher<Exec>(
      space_, m_,
      pc == "cholesky"       ? NewtonPreconditioner::cholesky
      : pc == "block-jacobi" ? NewtonPreconditioner::block_jacobi
                             : NewtonPreconditioner::automatic,
      cfg_.mc.factor_precision == "double" ? FactorPrecision::double_precision : FactorPrecision::single);
  polisher_.distribute(dist_.get());
  // Residual scales (docs/decks.md, "Convergence"): the largest elastic-limit traction k x1 over
  // a brick's length is the force an intact bed joint carries at its limit; a moment is that
  // force times the brick length.
  const auto& bed = cfg_.mortar.bed;
  const auto& head = cfg_.mortar.head;
  const double bw = cfg_.brick_width, bh = cfg_.brick_height;
  scale_.force = std::max(bed.k * bed.x1, head.k * head.x1) * bw;
  scale_.moment = scale_.force * bw;
  polish_options_.method = cfg_.polish;
  polish_options_.tolerance = cfg_.mc.residual_tolerance;
  polish_options_.max_iterations = cfg_.mc.polish_iterations;
  polish_options_.max_inner_iterations = cfg_.mc.cg_iterations;
  polish_options_.rotation_length = bw / std::sqrt(12.0);
  polish_options_.stiffness = 2.0 * bed.k * bw + 2.0 * head.k * bh;
  D_ = 0;
  set_load(0);
  E_ = energy();
}

template <class Exec>
std::string SolverOn<Exec>::presimulate(const Exec& space, const deck::Deck& d, const geometry::Specimen& s,
                                        const geometry::Interfaces& f, const geometry::Adjacency& adj,
                                        std::vector<std::pair<std::string, double>>& presim, std::ostream* log) {
  // Pre-simulation (§2.4, colouring = "fastest"): a few cycles at the first load increment with
  // each candidate; the fastest wins. The choice depends on timings, so results may differ
  // between runs; the pick is logged, written to summary.json and kept by the checkpoint. Each candidate is
  // a solver of its own, dropped after timing: the run itself starts untouched.
  Kokkos::Profiling::ScopedRegion pre("nacre::mc::presimulation");
  const auto free = free_flags(s);
  double best = std::numeric_limits<double>::max();
  for (const auto& name : colouring_strategies()) {
    const Colouring c = make_colouring(name, s, adj, free, d.seed);
    SolverOn candidate(space, d, s, f, adj, c);
    candidate.set_load(d.load.initial_step);
    candidate.cycle();  // warm-up (first touch, instantiation)
    space.fence("nacre::mc::presimulation");
    // best of three blocks: the minimum is robust to a busy machine's interruptions
    double per_cycle = std::numeric_limits<double>::max();
    for (int rep = 0; rep < 3; ++rep) {
      Kokkos::Timer timer;
      for (int k = 0; k < d.solver.presim_cycles; ++k) candidate.cycle();
      space.fence("nacre::mc::presimulation");
      per_cycle = std::min(per_cycle, timer.seconds() / d.solver.presim_cycles);
    }
    presim.emplace_back(name, per_cycle);
    if (log) *log << "  pre-simulation: colouring " << name << ", " << c.n_colours << " colours, "
                  << per_cycle * 1e3 << " ms/cycle\n";
    best = std::min(best, per_cycle);
  }
  // Timings within 15 % of the fastest count as a tie, won by the earliest candidate in the
  // fixed list: machine noise then rarely flips the choice (and with it the run's result).
  for (const auto& [name, sec] : presim)
    if (sec <= 1.15 * best) return name;
  return presim.front().first;
}

template <class Exec>
void SolverOn<Exec>::allocate_work() {
  using Kokkos::view_alloc;
  using Kokkos::WithoutInitializing;
  const auto n = static_cast<std::size_t>(m_.n_bricks), nf = static_cast<std::size_t>(m_.n_free);
  // Written before read each cycle / step: no initialisation pass.
  // The uniforms table only for sources that fill one (Philox is drawn inside the sweep).
  u_ = dynamic_cast<const rng::PhiloxSource*>(source_.get())
           ? rng::UniformTable<Mem>()
           : rng::UniformTable<Mem>(view_alloc(space_, WithoutInitializing, "nacre::mc::uniforms"), nf);
  save_pose_ = typename Model<Mem>::PoseView(view_alloc(space_, WithoutInitializing, "nacre::mc::save_pose"), n);
  phi_ = Field<double, Mem>(view_alloc(space_, WithoutInitializing, "nacre::mc::phi"), n);
  de_ = Field<double, Mem>(view_alloc(space_, WithoutInitializing, "nacre::mc::delta_energy"), nf);
  iface_energy_ = Field<double, Mem>(view_alloc(space_, WithoutInitializing, "nacre::mc::energy_cache"),
                                     static_cast<std::size_t>(m_.n_interfaces));
  cache_valid_ = false;
  // Read before first written (a checkpoint at step 0 stores the previous poses): zeroed.
  prev_pose_ = typename Model<Mem>::PoseView(view_alloc(space_, "nacre::mc::prev_pose"), n);
  brick_steps_ = {};
  if (cfg_.mc.per_brick_steps) {
    brick_steps_.step =
        decltype(brick_steps_.step)(view_alloc(space_, WithoutInitializing, "nacre::mc::brick_step"), nf);
    brick_steps_.accepted = decltype(brick_steps_.accepted)(view_alloc(space_, "nacre::mc::brick_accepted"), nf);
    auto h = Kokkos::create_mirror_view(WithoutInitializing, brick_steps_.step);
    for (int b = 0; b < m_.n_free; ++b) h(b, 0) = cfg_.mc.step, h(b, 1) = cfg_.mc.rot_step;
    Kokkos::deep_copy(space_, brick_steps_.step, h);
  }
  space_.fence("nacre::mc::allocate_work");
}

template <class Exec>
void SolverOn<Exec>::set_load(double D) {
  cache_valid_ = false;
  D_ = D;
  apply_load(space_, m_, pattern_, D);
}

template <class Exec>
double SolverOn<Exec>::energy() {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");  // PhaseTimes::energy
  Kokkos::Timer timer;
  // each interface summed by its owner (all here in one process: total_energy's terms)
  const InterfaceEvaluator<Mem> ev(m_);
  const auto own = owned_mask(dist_.get());
  const double e = deterministic_sum(
      space_, "nacre::mc::total_energy", sum_ws_, 0, m_.n_interfaces,
      KOKKOS_LAMBDA(const int i) { return own.data() && !own(i) ? 0.0 : ev.energy(i); },
      over(owned_interfaces(dist_.get(), m_)));
  times_.energy += timer.seconds();
  return e;
}

template <class Exec>
double SolverOn<Exec>::reaction() {
  const double D = D_;
  const double h = 1e-6 * std::max({std::abs(D), m_.laws[geometry::JointKind::bed].x1, m_.laws[geometry::JointKind::head].x1});
  set_load(D + h);
  const double ep = energy();
  set_load(D - h);
  const double em = energy();
  set_load(D);
  return (ep - em) / (2 * h);
}

template <class Exec>
int SolverOn<Exec>::ruptured() {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");  // PhaseTimes::energy
  Kokkos::Timer timer;
  int r = 0;
  if (dist_) {  // each interface counted by its owner
    Field<std::int8_t, Mem> st(Kokkos::view_alloc(space_, Kokkos::WithoutInitializing, "nacre::mc::iface_state"),
                               m_.n_interfaces);
    interface_state(space_, m_, Field<double, Mem>(), st);
    auto own = dist_->iface_owned;
    Kokkos::parallel_reduce(
        "nacre::mc::count_ruptured", Kokkos::RangePolicy<Exec>(space_, 0, m_.n_interfaces),
        KOKKOS_LAMBDA(const int i, int& acc) { acc += own(i) && st(i) == 2; }, r);
    r = static_cast<int>(dist_->comm.sum(static_cast<long long>(r)));
  } else {
    r = interface_state(space_, m_, Field<double, Mem>(), Field<std::int8_t, Mem>());
  }
  times_.energy += timer.seconds();
  return r;
}

template <class Exec>
std::vector<std::int8_t> SolverOn<Exec>::interface_states(std::vector<double>* energy) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::energy");  // PhaseTimes::energy
  Kokkos::Timer timer;
  using Kokkos::view_alloc, Kokkos::WithoutInitializing;
  Field<std::int8_t, Mem> st(view_alloc(space_, WithoutInitializing, "nacre::mc::iface_state"), m_.n_interfaces);
  Field<double, Mem> en;
  if (energy)
    en = Field<double, Mem>(view_alloc(space_, WithoutInitializing, "nacre::mc::iface_energy"), m_.n_interfaces);
  // with a history the energy of fracture is what each joint dissipated, not its cohesive energy
  interface_state(space_, m_, m_.hist.data() ? Field<double, Mem>() : en, st);
  if (energy && m_.hist.data()) interface_dissipation(space_, m_, en);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), st);
  auto he = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), en);
  std::vector<double> recs;  // (interface, state, energy) of each owned interface
  for (int i = 0; i < m_.n_interfaces; ++i)
    if (owned_interface(i))
      recs.insert(recs.end(),
                  {static_cast<double>(global_interface(i)), static_cast<double>(h(i)), energy ? he(i) : 0.0});
  // back to the geometry's order, on rank 0 (the crack and the files are its business)
  const std::vector<double> all = assemble(n_interfaces_global(), 2, recs, true);
  times_.energy += timer.seconds();
  if (all.empty()) {  // another rank
    if (energy) energy->clear();
    return {};
  }
  std::vector<std::int8_t> out(n_interfaces_global());
  if (energy) energy->assign(out.size(), 0.0);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<std::int8_t>(all[2 * i]);
    if (energy) (*energy)[i] = all[2 * i + 1];
  }
  return out;
}

template <class Exec>
Sizes SolverOn<Exec>::sizes() const {
  Sizes z;
  z.bricks = n_bricks_global();
  z.free_bricks = dist_ ? static_cast<std::size_t>(dist_->n_free) : static_cast<std::size_t>(m_.n_free);
  z.interfaces = n_interfaces_global();
  z.colours = dist_ ? dist_->n_colours : static_cast<int>(m_.colour_offset.size()) - 1;
  z.ranks = dist_ ? dist_->comm.size() : 1;
  if (dist_)
    z.halo_messages = Kokkos::SpaceAccessibility<Kokkos::HostSpace, Mem>::accessible ? "host memory"
                      : dist_->comm.device_direct() ? "device memory, direct (GPU-aware MPI)"
                                                    : "device memory, staged through host";
  return z;
}

template <class Exec>
OutputFields SolverOn<Exec>::output_fields() {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::output_fields");
  using Kokkos::view_alloc, Kokkos::WithoutInitializing;
  Field<double, Mem> be(view_alloc(space_, WithoutInitializing, "nacre::mc::brick_energy_out"), m_.n_bricks);
  Field<double, Mem> ie(view_alloc(space_, WithoutInitializing, "nacre::mc::iface_energy_out"), m_.n_interfaces);
  Field<std::int8_t, Mem> is(view_alloc(space_, WithoutInitializing, "nacre::mc::iface_state_out"), m_.n_interfaces);
  interface_state(space_, m_, ie, is);
  // an owned brick's interfaces are all on its rank (the halo); each evaluated once, above
  brick_energy(space_, m_, be, Kokkos::View<const double*, Mem>(ie));
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m_.pose);
  auto hbe = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), be);
  auto hie = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ie);
  auto his = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), is);
  std::vector<double> bricks, ifaces;  // (index, values...) of what this rank owns
  for (int k = 0; k < m_.n_bricks; ++k)
    if (owned_brick(k))
      bricks.insert(bricks.end(), {static_cast<double>(global_brick(k)), hp(k, 0), hp(k, 1), hp(k, 2), 0.5 * hbe(k)});
  for (int i = 0; i < m_.n_interfaces; ++i)
    if (owned_interface(i))
      ifaces.insert(ifaces.end(), {static_cast<double>(global_interface(i)), hie(i), static_cast<double>(his(i))});
  // to rank 0 only (the writer): an allgather of a 1M-brick dump's fields cost 0.6 s on 2 ranks
  const std::vector<double> b = assemble(n_bricks_global(), 4, bricks, true);
  const std::vector<double> f = assemble(n_interfaces_global(), 2, ifaces, true);
  OutputFields o;
  const std::size_t nb = b.size() / 4, ni = f.size() / 2;
  o.x.resize(nb), o.y.resize(nb), o.theta.resize(nb), o.brick_energy.resize(nb);
  for (std::size_t k = 0; k < nb; ++k)
    o.x[k] = b[4 * k], o.y[k] = b[4 * k + 1], o.theta[k] = b[4 * k + 2], o.brick_energy[k] = b[4 * k + 3];
  o.interface_energy.resize(ni), o.interface_state.resize(ni);
  for (std::size_t i = 0; i < ni; ++i)
    o.interface_energy[i] = f[2 * i], o.interface_state[i] = static_cast<std::int8_t>(f[2 * i + 1]);
  return o;
}

template <class Exec>
double SolverOn<Exec>::dissipated() {
  if (!m_.hist.data()) return 0.0;
  Field<double, Mem> en(Kokkos::view_alloc(space_, Kokkos::WithoutInitializing, "nacre::mc::iface_dissipation"),
                        m_.n_interfaces);
  interface_dissipation(space_, m_, en);
  const auto own = owned_mask(dist_.get());
  return deterministic_sum(
      space_, "nacre::mc::dissipated", sum_ws_, 0, m_.n_interfaces,
      KOKKOS_LAMBDA(const int i) { return own.data() && !own(i) ? 0.0 : en(i); },
      over(owned_interfaces(dist_.get(), m_)));
}

template <class Exec>
bool SolverOn<Exec>::finished() const {
  return run_.leg >= static_cast<int>(cfg_.load.targets().size());
}

template <class Exec>
double SolverOn<Exec>::path_fraction() const {
  const auto targets = cfg_.load.targets();
  double done = 0, prev = 0;
  for (int k = 0; k < static_cast<int>(targets.size()); ++k) {
    if (k < run_.leg)
      done += std::abs(targets[k] - prev);
    else if (k == run_.leg)
      done += std::abs(D_ - prev);
    prev = targets[k];
  }
  const double total = cfg_.load.path_length();
  return total > 0 ? std::min(1.0, done / total) : 1.0;
}

template <class Exec>
double SolverOn<Exec>::residual() {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::polish");  // PhaseTimes::polish
  Kokkos::Timer timer;
  const double r = polisher_.residual(space_, m_, scale_);
  space_.fence("nacre::mc::residual");
  times_.polish += timer.seconds();
  return r;
}

template <class Exec>
PolishResult SolverOn<Exec>::polish(const std::string& method, double tolerance) {
  PolishOptions o = polish_options_;
  if (!method.empty()) o.method = parse_polish_method(method);
  if (tolerance > 0) o.tolerance = tolerance;
  return polish_with(o.method, o.tolerance);
}

template <class Exec>
PolishResult SolverOn<Exec>::polish_with(PolishMethod method, double tolerance) {
  if (dist_ && method == PolishMethod::anneal) one_process_only(polish_method_name(method));
  Kokkos::Profiling::ScopedRegion region("nacre::mc::polish");  // PhaseTimes::polish
  Kokkos::Timer timer;
  PolishOptions o = polish_options_;
  o.method = method;
  if (tolerance > 0) o.tolerance = tolerance;
  cache_valid_ = false;
  const PolishResult r = o.method == PolishMethod::anneal ? anneal(o) : polisher_.run(space_, m_, scale_, o);
  times_.polish += timer.seconds();
  return r;
}

template <class Exec>
PolishResult SolverOn<Exec>::anneal(const PolishOptions& o) {
  one_process_only("anneal");
  Kokkos::Profiling::ScopedRegion region("nacre::mc::polish_anneal");
  const auto& S = cfg_.mc;
  const long block = S.adapt_interval > 0 ? S.adapt_interval : 50;
  const double T0 = S.temperature;
  // Per-brick step sizes while annealing, whatever the run's step_mode: with one global pair the
  // bricks already at their minimum (the majority) shrink everyone's step below what the last
  // far-off bricks need, and the residual (a maximum over bricks) stalls. The run's own steps
  // (global pair or per-brick table) are swapped out and come back untouched.
  const BrickSteps<Mem> run_steps = brick_steps_;
  BrickSteps<Mem> own;
  own.step = decltype(own.step)(Kokkos::view_alloc(space_, Kokkos::WithoutInitializing, "nacre::mc::anneal::step"),
                                m_.n_free);
  own.accepted = decltype(own.accepted)(Kokkos::view_alloc(space_, "nacre::mc::anneal::accepted"), m_.n_free);
  if (run_steps.active()) {
    Kokkos::deep_copy(space_, own.step, run_steps.step);
  } else {
    auto st = own.step;
    const double s0 = step_, r0 = rot_step_;
    Kokkos::parallel_for(
        "nacre::mc::anneal::initial_steps", Kokkos::RangePolicy<Exec>(space_, 0, m_.n_free),
        KOKKOS_LAMBDA(const int b) {
          st(b, 0) = s0;
          st(b, 1) = r0;
        });
  }
  brick_steps_ = own;
  const double E0 = energy();
  PolishResult r;
  r.residual = polisher_.residual(space_, m_, scale_);
  step_floor_ = 1e-6;
  // Measured on the default deck at D = 0.03 (docs/convergence.md): the run's target 0.5 stalls
  // (a descent-only chain accepts at most half of small trials, so the steps shrink far below the
  // distance to the minimum); 0.2 is the target used.
  acceptance_target_ = 0.2;
  double T = T0;
  while (r.residual > o.tolerance && r.iterations < o.max_iterations) {
    temperature_ = T > 1e-12 * T0 ? T : 0.0;
    for (long k = 0; k < block; ++k) cycle();
    r.iterations += static_cast<int>(block);
    T *= 0.5;
    r.residual = polisher_.residual(space_, m_, scale_);
    if (stop_requested()) {  // a long anneal must not hold off SIGINT / SIGTERM
      interrupted_ = true;
      break;
    }
  }
  temperature_ = T0;
  step_floor_ = 1.0;
  acceptance_target_ = 0.5;
  brick_steps_ = run_steps;
  window_accepted_ = window_trials_ = 0;
  E_ = energy();
  r.energy_change = E_ - E0;
  r.converged = r.residual <= o.tolerance;
  return r;
}

template <class Exec>
long SolverOn<Exec>::cycle() {
  Kokkos::Timer timer;
  // Philox (the default) is generated inside the sweep, brick by brick: the same numbers as its
  // table (rng::philox_uniforms), without the table pass. Other sources fill the table first.
  const auto* philox = dynamic_cast<const rng::PhiloxSource*>(source_.get());
  if (!philox) {
    Kokkos::Profiling::ScopedRegion region("nacre::mc::rng");
    auto streams = Kokkos::subview(m_.id, Kokkos::make_pair(0, m_.n_free));
    source_->fill(Backend(space_), global_cycle_, streams, u_);
    space_.fence("nacre::mc::rng");  // the phase is timed on its own
  }
  times_.rng += timer.seconds();
  timer.reset();
  long accepted = 0;
  double de = 0;
  {
    Kokkos::Profiling::ScopedRegion region("nacre::mc::sweep");
    const double T = temperature_;
    if (!cache_valid_) {  // poses changed outside the sweep since the last cycle
      interface_energies(space_, m_, iface_energy_);
      cache_valid_ = true;
    }
    auto sweep = [&](const auto& uniforms) {
      for (std::size_t c = 0; c + 1 < m_.colour_tiles.size(); ++c) {
        accepted += sweep_colour(space_, m_, m_.colour_tiles[c], m_.colour_tiles[c + 1], uniforms, iface_energy_,
                                 de_, step_, rot_step_, T, brick_steps_);
        // spread over ranks: this colour's moves to the ranks holding them in a halo
        if (dist_) dist_->halo->exchange(space_, dist_->comm, m_, static_cast<int>(c), iface_energy_);
      }
    };
    if (philox)
      sweep(PhiloxUniforms<Mem>{m_.id, philox->seed(), global_cycle_});
    else
      sweep(TableUniforms<Mem>{u_});
    auto d = de_;
    de = deterministic_sum(
        space_, "nacre::mc::sum_delta_energy", sum_ws_, 0, m_.n_free, KOKKOS_LAMBDA(const int b) { return d(b); },
        over(m_.n_free));
    if (dist_) accepted = dist_->comm.sum(static_cast<long long>(accepted));
  }
  times_.sweep += timer.seconds();
  E_ += de;
  ++global_cycle_;
  const long trials = dist_ ? static_cast<long>(dist_->n_free) : m_.n_free;
  window_accepted_ += accepted;
  window_trials_ += trials;
  accepted_total_ += accepted;
  trials_total_ += trials;
  const auto& S = cfg_.mc;
  // eq. 2.7, every AdaptInter cycles of the run (the global count, so the rhythm does not
  // restart with each load step), per brick or for the global pair
  if (S.adapt_interval > 0 && global_cycle_ % S.adapt_interval == 0) {
    if (brick_steps_.active()) {
      adapt_brick_steps(space_, brick_steps_, m_.n_free, S.adapt_interval, S.min_step * step_floor_, S.max_step,
                        S.min_rot_step * step_floor_, S.max_rot_step, acceptance_target_);
    } else if (window_trials_ > 0) {
      const double a = static_cast<double>(window_accepted_) / static_cast<double>(window_trials_);
      // (anneal() always runs per-brick steps: its lower target and floors never reach here)
      step_ = adapted_step(step_, a, S.min_step, S.max_step);
      rot_step_ = adapted_step(rot_step_, a, S.min_rot_step, S.max_rot_step);
    }
    window_accepted_ = window_trials_ = 0;
  }
  return accepted;
}

template <class Exec>
std::size_t SolverOn<Exec>::cycle_bytes() const {
  // the free bricks' slots: adj_offset(n_free) (one value from the device)
  int slots = 0;
  Kokkos::deep_copy(space_, Kokkos::View<int, Kokkos::HostSpace>(&slots), Kokkos::subview(m_.adj_offset, m_.n_free));
  space_.fence("nacre::mc::cycle_bytes");
  const std::size_t nf = static_cast<std::size_t>(m_.n_free), ns = static_cast<std::size_t>(slots);
  std::size_t b = nf * (2 * 5 * sizeof(double)                 // pose read and written
                        + sizeof(std::uint64_t) + sizeof(int)  // stream id, CSR offset
                        + sizeof(double));                     // energy change
  b += ns * (static_cast<std::size_t>(col(SlotCol::count)) * sizeof(double) + 2 * sizeof(int) + 1);  // slot records
  b += static_cast<std::size_t>(m_.n_interfaces) * 2 * sizeof(double);  // energy cache read and written
  if (u_.data()) b += nf * 4 * sizeof(double);                          // uniforms table
  if (brick_steps_.active()) b += nf * 2 * (2 * sizeof(double) + sizeof(int));
  if (m_.hist.data()) b += m_.hist.span() * sizeof(double);
  return b;
}

template <class Exec>
std::optional<double> SolverOn<Exec>::cycle_flops() const {
  const auto per_trial = trial_flops(m_, step_, rot_step_, temperature_);
  if (!per_trial) return std::nullopt;
  return *per_trial * static_cast<double>(m_.n_free);
}

template <class Exec>
long SolverOn<Exec>::mc_phase(long budget, bool& window_converged) {
  // Monte Carlo until the window test passes (or the budget / the backtracking limit is spent)
  const auto& S = cfg_.mc;
  monitor_.reset();
  E_ = energy();
  window_converged = false;
  long c = 0;
  while (c < budget) {
    cycle();
    ++c;
    // Exact resynchronisation: E_ accumulates accepted energy changes (cheap, exact up to
    // rounding); once per window it is replaced by a full reduction so rounding cannot build up.
    if (c % S.window_size == 0) E_ = energy();
    if (monitor_.push(E_)) {
      window_converged = true;
      break;
    }
    report_progress(c, E_);  // every cycle: the caller throttles by time
    if (cycle_limit_ > 0 && c >= cycle_limit_) break;
    if (stop_requested()) {
      interrupted_ = true;
      break;
    }
  }
  return c;
}

template <class Exec>
long SolverOn<Exec>::relax(bool& converged) {
  // convergence = "window": one Monte Carlo phase ended by the window test, then the polish (if
  // any); the residual is reported. convergence = "residual": Monte Carlo phase + polish until
  // the residual is below the tolerance; a polish that stalls (e.g. in a metastable state) gets
  // another Monte Carlo phase, until max_cycles (or the backtracking limit) is spent.
  const auto& S = cfg_.mc;
  const bool by_residual = cfg_.by_residual;
  const long limit = cycle_limit_ > 0 ? std::min(cycle_limit_, S.max_cycles) : S.max_cycles;
  converged = false;
  step_polish_ = step_inner_ = 0;
  long c = 0;
  if (cfg_.relax == Relaxation::gradient || cfg_.relax == Relaxation::newton) {
    // A pure gradient (or Newton) minimiser with the same load stepping: no Monte Carlo at all
    // (0 cycles); the step converges when the method reaches the tolerance within polish_iterations.
    const bool newton = cfg_.relax == Relaxation::newton;
    const PolishResult p = polish_with(newton ? PolishMethod::trust_region : polish_options_.method);
    step_polish_ = p.iterations, step_inner_ = p.inner_iterations;
    residual_ = p.residual;
    step_method_ = newton ? "newton" : "gradient";
    converged = p.converged || !by_residual;
    E_ = energy();
    return 0;
  }
  if (cfg_.relax == Relaxation::automatic) return relax_auto(converged, limit);
  step_method_ = "monte-carlo";
  for (;;) {
    bool window = false;
    c += mc_phase(limit - c, window);
    if (interrupted_) break;
    const PolishResult p = polish();
    step_polish_ += p.iterations, step_inner_ += p.inner_iterations;
    residual_ = p.residual;
    if (interrupted_) break;  // stopped inside the polish (anneal)
    if (!by_residual) {
      converged = window;
      break;
    }
    if (p.converged) {
      converged = true;
      break;
    }
    if (c >= limit) break;
  }
  E_ = energy();
  return c;
}

template <class Exec>
long SolverOn<Exec>::relax_auto(bool& converged, long limit) {
  // relaxation = "auto": trust-region Newton from the predicted poses. Where it stalls, or where
  // the step ruptured joints (a crack advanced: a lower state may lie across a flat plateau of
  // ruptured joints, where the gradient is zero and Newton stops, tests/test_polish.cpp), a
  // bounded Monte Carlo burst (burst_cycles, ended early by the window test) and Newton again;
  // of two converged states the lower is kept. Bursts repeat only while Newton has not converged.
  PolishResult p = polish_with(PolishMethod::trust_region);
  step_polish_ += p.iterations, step_inner_ += p.inner_iterations;
  step_method_ = "newton";
  long c = 0;
  bool burst = !p.converged || ruptured() > step_ruptured0_;
  while (burst && c < limit && !interrupted_) {
    const bool had = p.converged;
    const double e_had = had ? energy() : 0.0;
    if (had) {
      if (!burst_pose_.data())
        burst_pose_ = typename Model<Mem>::PoseView(
            Kokkos::view_alloc(space_, Kokkos::WithoutInitializing, "nacre::mc::burst_pose"), m_.n_bricks);
      Kokkos::deep_copy(space_, burst_pose_, m_.pose);
    }
    bool window = false;
    c += mc_phase(std::min(limit - c, cfg_.mc.burst_cycles), window);
    if (interrupted_) break;
    const PolishResult q = polish_with(PolishMethod::trust_region);
    step_polish_ += q.iterations, step_inner_ += q.inner_iterations;
    if (had && (!q.converged || energy() >= e_had)) {  // the burst found nothing lower: Newton's state
      Kokkos::deep_copy(space_, m_.pose, burst_pose_);
      cache_valid_ = false;
      break;
    }
    p = q;
    step_method_ = "newton+monte-carlo";
    burst = !p.converged;
  }
  residual_ = p.residual;
  converged = p.converged || !cfg_.by_residual;
  E_ = energy();
  return c;
}

template <class Exec>
void SolverOn<Exec>::predict(double ratio) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::predictor");
  cache_valid_ = false;
  // the secant where Newton relaxes (unless the deck asks for eq. 2.11's), eq. 2.11's elsewhere
  // (unless it asks for the secant): deck/deck.hpp Load::Predictor, mc/kernels.hpp
  using Kind = deck::Load::Predictor;
  const Kind kind = cfg_.load.predictor;
  const bool newton = cfg_.relax == Relaxation::newton || cfg_.relax == Relaxation::automatic;
  if (kind == Kind::secant || (kind == Kind::automatic && newton)) {
    predict_poses(space_, SecantPredictor{}, m_, prev_pose_, ratio);
  } else {
    brick_energy(space_, m_, phi_);
    predict_poses(space_, m_, prev_pose_, phi_, ratio);
  }
  refresh_halo();
}

template <class Exec>
void SolverOn<Exec>::run(const std::function<void(const StepRecord&)>& on_step) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::run");
  const auto& L = cfg_.load;
  const auto& S = cfg_.mc;
  // Target and upper cycle counts of the adaptive displacement (eq. 2.8, 2.9). The dissertation
  // names WindowMul and WindowUpperMul without the formula; nacre reads them as multiples of
  // ConvergenceRep (documented in docs/decks.md).
  const double c_t = S.window_mul * S.convergence_rep;
  const double c_u = S.window_upper_mul * S.convergence_rep;
  if (run_.step == 0 && run_.increment == 0) run_.increment = L.initial_step;
  double& inc = run_.increment;
  double& inc_prev = run_.previous_increment;
  bool& have_prev = run_.have_previous;
  int& step = run_.step;
  // the programme's targets in order (a monotonic deck: final_displacement alone); a leg is done
  // when D is within 1e-12 of the path's largest |D| of its target
  const std::vector<double> targets = L.targets();
  const int n_legs = static_cast<int>(targets.size());
  const double reached = 1e-12 * L.max_displacement();
  auto leg_done = [&] {
    const double t = targets[run_.leg];
    return (t >= D_ ? t - D_ : D_ - t) <= reached;
  };
  // past every target D has reached; where the path turns, the last increment predicts nothing
  auto direction = [&](int k) { return targets[k] >= (k > 0 ? targets[k - 1] : 0.0) ? 1 : -1; };
  auto next_legs = [&] {
    while (run_.leg < n_legs && leg_done()) {
      if (run_.leg + 1 < n_legs && direction(run_.leg + 1) != direction(run_.leg)) have_prev = false;
      ++run_.leg;
    }
  };
  // a monotonic deck has one leg whose target --extend may have moved: where it stands follows
  // from D alone (a programme's legs come from the checkpoint: its targets are in the fingerprint)
  if (L.programme.empty()) run_.leg = 0;
  next_legs();  // (a checkpoint taken on a target)
  while (run_.leg < n_legs) {
    if (stop_requested()) {
      interrupted_ = true;
      return;
    }
    Kokkos::Timer timer;
    const double target = targets[run_.leg];
    const double dir = target >= D_ ? 1.0 : -1.0;
    double inc_now = std::min(inc, dir * (target - D_));
    const double D0 = D_;
    Kokkos::deep_copy(space_, save_pose_, m_.pose);
    int reverts = 0;
    long cycles = 0;
    bool converged = false;
    const long acc0 = accepted_total_;
    const long trials0 = trials_total_;
    const int snap_limit = L.max_ruptures_per_step;
    const int ruptured0 = snap_limit > 0 || cfg_.relax == Relaxation::automatic ? ruptured() : 0;
    step_ruptured0_ = ruptured0;
    for (;;) {
      if (L.predictor != deck::Load::Predictor::none && have_prev) predict(inc_now / inc_prev);
      set_load(D0 + dir * inc_now);
      const bool may_revert = L.adaptive && inc_now > L.min_step * (1 + 1e-12) && c_u < S.max_cycles;
      cycle_limit_ = may_revert ? static_cast<long>(c_u) : 0;
      cycles = relax(converged);
      cycle_limit_ = 0;
      if (interrupted_) return;  // the step is abandoned; the caller keeps the last step's checkpoint
      if (may_revert && !converged && cycles >= static_cast<long>(c_u)) {
        // eq. 2.9: back to the last converged state, retry with a smaller increment
        Kokkos::deep_copy(space_, m_.pose, save_pose_);
        cache_valid_ = false;
        inc_now = std::max(L.min_step, inc_now * (2.0 / 3.0) * c_t / c_u);
        ++reverts;
        if (log_) *log_ << "  step " << step + 1 << ": no convergence in " << cycles
                        << " cycles, retrying with increment " << inc_now << "\n";
        continue;
      }
      if (converged && snap_limit > 0 && inc_now > L.min_step * (1 + 1e-12)) {
        // snap-back: many interfaces broke in one increment, so the path between the two states
        // was jumped over; undo and take half the increment
        const int broke = ruptured() - ruptured0;
        if (broke > snap_limit) {
          Kokkos::deep_copy(space_, m_.pose, save_pose_);
          cache_valid_ = false;
          inc_now = std::max(L.min_step, 0.5 * inc_now);
          ++reverts;
          if (log_) *log_ << "  step " << step + 1 << ": " << broke << " interfaces ruptured in one increment (limit "
                          << snap_limit << "), retrying with increment " << inc_now << "\n";
          continue;
        }
      }
      break;
    }
    // what a step record holds whether or not the step converged
    auto record = [&](int number) {
      StepRecord r;
      r.step = number;
      r.displacement = D_;
      r.energy = E_;
      r.cycles = cycles;
      r.converged = converged;
      r.increment = inc_now;
      r.reverts = reverts;
      r.residual = residual_;
      r.polish_iterations = step_polish_;
      r.inner_iterations = step_inner_;
      r.method = step_method_;
      r.seconds = timer.seconds();
      return r;
    };
    if (!converged && cfg_.by_residual) {
      // "not converged after N cycles": the step is not completed; the caller reports it and
      // keeps the last completed step's checkpoint and rows.
      failed_ = true;
      failed_step_ = record(step + 1);
      return;
    }
    Kokkos::deep_copy(space_, prev_pose_, save_pose_);
    have_prev = true;
    inc_prev = inc_now;
    if (L.adaptive) inc = std::clamp(inc_now * c_t / std::max<long>(cycles, 1), L.min_step, L.max_step);
    // irreversible damage: the converged state's separations become history (energies unchanged:
    // psi = f where the history grows, cohesive/damage.hpp; the sweep's cache is refilled anyway)
    if (update_history(space_, m_) > 0) cache_valid_ = false;
    next_legs();

    StepRecord r = record(++step);
    r.last = run_.leg >= n_legs;
    r.reaction = reaction();
    const long trials = trials_total_ - trials0;
    r.acceptance = trials > 0 ? static_cast<double>(accepted_total_ - acc0) / trials : 0.0;
    r.ruptured = ruptured();
    r.step_size = step_;
    r.rot_step = rot_step_;
    if (brick_steps_.active()) {  // per-brick steps: report their mean (exact sums, over ranks too)
      auto bs = brick_steps_.step;
      const double st = deterministic_sum(
          space_, "nacre::mc::mean_step", sum_ws_, 0, m_.n_free, KOKKOS_LAMBDA(const int b) { return bs(b, 0); },
          over(m_.n_free));
      const double sr = deterministic_sum(
          space_, "nacre::mc::mean_rot_step", sum_ws_, 0, m_.n_free, KOKKOS_LAMBDA(const int b) { return bs(b, 1); },
          over(m_.n_free));
      const double n = dist_ ? static_cast<double>(dist_->n_free) : m_.n_free;
      r.step_size = n > 0 ? st / n : 0.0;
      r.rot_step = n > 0 ? sr / n : 0.0;
    }
    run_.max_residual = std::max(run_.max_residual, residual_);
    run_.polish_iterations += step_polish_;
    run_.cg_iterations += step_inner_;
    r.seconds = timer.seconds();
    if (on_step) on_step(r);
  }
}

namespace {
/// v(k) = in[global(k)] (x, y, theta) for every local brick k
template <class PV>
void from_global_order(const std::vector<double>& in, const std::vector<int>& global, const PV& v) {
  auto h = Kokkos::create_mirror_view(v);
  Kokkos::deep_copy(h, 0.0);
  for (std::size_t k = 0; k < global.size(); ++k)
    for (int c = 0; c < 3; ++c) h(k, c) = in[3 * global[k] + c];
  Kokkos::deep_copy(v, h);  // the caller refreshes the cached rotation
}
}  // namespace

template <class Exec>
std::vector<double> SolverOn<Exec>::assemble(std::size_t n, int width, const std::vector<double>& mine,
                                             bool to_root) const {
  if (dist_ && to_root && dist_->comm.rank() != 0) {
    (void)dist_->comm.gather(mine);
    return {};
  }
  std::vector<double> out(n * static_cast<std::size_t>(width), 0.0);
  const auto place = [&](const std::vector<double>& recs) {
    for (std::size_t r = 0; r + width < recs.size(); r += static_cast<std::size_t>(width) + 1) {
      const auto i = static_cast<std::size_t>(recs[r]);
      for (int c = 0; c < width; ++c) out[i * width + c] = recs[r + 1 + c];
    }
  };
  if (!dist_) {
    place(mine);
    return out;
  }
  for (const auto& recs : to_root ? dist_->comm.gather(mine) : dist_->comm.allgather(mine)) place(recs);
  return out;
}

template <class Exec>
Checkpoint SolverOn<Exec>::checkpoint() const {
  Checkpoint c;
  c.colouring = m_.colouring_name;
  c.backend = Backend(space_).name();
  c.run = run_;
  c.displacement = D_;
  c.step_size = step_;
  c.rot_step = rot_step_;
  c.global_cycle = global_cycle_;
  c.accepted_total = accepted_total_;
  c.trials_total = trials_total_;
  c.window_accepted = window_accepted_;
  c.window_trials = window_trials_;
  // every array in the specimen's order, from each brick's / interface's owner (all here in one
  // process), on rank 0 (the writer; the others get the scalars): the same checkpoint on any rank
  // count, so a run restarts on any other
  const std::size_t nb = n_bricks_global(), ni = n_interfaces_global();
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m_.pose);
  auto hq = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), prev_pose_);
  std::vector<double> pose, prev;
  for (int k = 0; k < m_.n_bricks; ++k) {
    if (!owned_brick(k)) continue;
    const double g = static_cast<double>(global_brick(k));
    pose.insert(pose.end(), {g, hp(k, 0), hp(k, 1), hp(k, 2)});
    prev.insert(prev.end(), {g, hq(k, 0), hq(k, 1), hq(k, 2)});
  }
  c.pose = assemble(nb, 3, pose, true);
  c.previous_pose = assemble(nb, 3, prev, true);
  // (on ranks the deck decides, not the local arrays: a rank without free bricks or interfaces
  // must still take part in the gathers)
  if (brick_steps_.active() || (dist_ && cfg_.mc.per_brick_steps)) {
    auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), brick_steps_.step);
    auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), brick_steps_.accepted);
    std::vector<double> st;
    for (int k = 0; k < m_.n_free; ++k)  // a rank's free bricks are its own
      st.insert(st.end(), {static_cast<double>(global_brick(k)), hs(k, 0), hs(k, 1), static_cast<double>(ha(k))});
    c.brick_step = assemble(nb, 3, st, true);
  }
  if (m_.hist.data() || (dist_ && cfg_.mortar.damage == cohesive::Damage::irreversible)) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m_.hist);
    const int nq = m_.quad.n;
    std::vector<double> hist;
    for (int i = 0; i < m_.n_interfaces; ++i) {
      if (!owned_interface(i)) continue;
      hist.push_back(static_cast<double>(global_interface(i)));
      for (int q = 0; q < nq; ++q) hist.push_back(h(i, q));
    }
    c.history = assemble(ni, nq, hist, true);
  }
  return c;
}

template <class Exec>
void SolverOn<Exec>::restore(const Checkpoint& c) {
  if (c.colouring != m_.colouring_name)
    throw std::runtime_error("checkpoint was made with colouring '" + c.colouring + "', solver uses '" +
                             m_.colouring_name + "'");
  // every local brick and interface (a rank's halo too) from the specimen-wide arrays
  const std::size_t nb = n_bricks_global(), ni = n_interfaces_global();
  std::vector<int> gperm(m_.perm.size());
  for (int k = 0; k < m_.n_bricks; ++k) gperm[k] = global_brick(k);
  if (c.pose.size() != 3 * nb || c.previous_pose.size() != 3 * nb)
    throw std::runtime_error("checkpoint does not match the specimen");
  from_global_order(c.pose, gperm, m_.pose);
  cache_valid_ = false;
  from_global_order(c.previous_pose, gperm, prev_pose_);
  refresh_frames(space_, m_);
  if (brick_steps_.active() != !c.brick_step.empty())
    throw std::runtime_error("checkpoint and deck disagree on step_mode");
  if (brick_steps_.active()) {
    if (c.brick_step.size() != 3 * nb) throw std::runtime_error("checkpoint does not match the specimen");
    auto hs = Kokkos::create_mirror_view(brick_steps_.step);
    auto ha = Kokkos::create_mirror_view(brick_steps_.accepted);
    for (int k = 0; k < m_.n_free; ++k) {
      const int i = gperm[k];
      hs(k, 0) = c.brick_step[3 * i], hs(k, 1) = c.brick_step[3 * i + 1];
      ha(k) = static_cast<int>(c.brick_step[3 * i + 2]);
    }
    Kokkos::deep_copy(brick_steps_.step, hs);
    Kokkos::deep_copy(brick_steps_.accepted, ha);
  }
  if (m_.hist.data() != nullptr) {
    const int nq = m_.quad.n;
    if (c.history.size() != ni * nq)
      throw std::runtime_error(c.history.empty() ? "checkpoint has no damage history, the deck's damage is irreversible"
                                                 : "checkpoint's damage history does not match the specimen");
    auto h = Kokkos::create_mirror_view(m_.hist);
    for (int i = 0; i < m_.n_interfaces; ++i)
      for (int q = 0; q < nq; ++q) h(i, q) = c.history[static_cast<std::size_t>(global_interface(i)) * nq + q];
    Kokkos::deep_copy(space_, m_.hist, h);
  } else if (!c.history.empty()) {
    throw std::runtime_error("checkpoint has a damage history, the deck's damage is reversible");
  }
  run_ = c.run;
  D_ = c.displacement;
  step_ = c.step_size;
  rot_step_ = c.rot_step;
  global_cycle_ = c.global_cycle;
  accepted_total_ = c.accepted_total;
  trials_total_ = c.trials_total;
  window_accepted_ = c.window_accepted;
  window_trials_ = c.window_trials;
  set_load(D_);  // driven bricks exactly where the load puts them
  E_ = energy();
}

template <class Exec>
void SolverOn<Exec>::poses(std::vector<double>& x, std::vector<double>& y, std::vector<double>& t) const {
  const std::vector<double> p = checkpoint_poses();
  const std::size_t n = p.size() / 3;
  x.resize(n), y.resize(n), t.resize(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = p[3 * i], y[i] = p[3 * i + 1], t[i] = p[3 * i + 2];
}

template <class Exec>
std::vector<double> SolverOn<Exec>::checkpoint_poses() const {
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m_.pose);
  std::vector<double> pose;
  for (int k = 0; k < m_.n_bricks; ++k)
    if (owned_brick(k)) pose.insert(pose.end(), {static_cast<double>(global_brick(k)), hp(k, 0), hp(k, 1), hp(k, 2)});
  return assemble(n_bricks_global(), 3, pose);
}

template <class Exec>
void SolverOn<Exec>::one_process_only(const char* what) const {
  if (dist_)
    throw std::logic_error(std::string("mc::Solver: ") + what +
                           " is not yet spread over ranks (docs/scaling.md); this "
                           "run has " +
                           std::to_string(dist_->comm.size()));
}

// ---- the face: the backend picks the space once; every member forwards to SolverOn<space>

Solver::Solver(const Backend& backend, const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
               std::ostream* log)
    : Solver(backend, d, s, f, log, par::Comm{}) {}

Solver::Solver(const Backend& backend, const deck::Deck& d, const geometry::Specimen& s, const geometry::Interfaces& f,
               std::ostream* log, const par::Comm& comm) {
  backend.visit([&](const auto& space) {
    using Exec = std::decay_t<decltype(space)>;
    impl_ = std::make_unique<SolverOn<Exec>>(space, d, s, f, this, log, comm);
  });
}

Solver::~Solver() = default;

template <class F>
decltype(auto) Solver::on(F&& f) const {
  return std::visit([&](const auto& impl) -> decltype(auto) { return f(*impl); }, impl_);
}

Backend Solver::backend() const {
  return on([](const auto& s) { return Backend(s.space()); });
}
namespace {
/// What model() and gradient() say on a backend that keeps its model outside the default memory
/// space (a host backend of a CUDA build): they return default-memory views, and it has none.
[[noreturn, maybe_unused]] void not_in_default_memory(const std::string& space, const char* what) {
  throw std::logic_error(std::string("nacre::mc::Solver::") + what + ": this solver runs on " + space +
                         ", whose memory is not the default memory space");
}
}  // namespace

const Model<>& Solver::model() const {
  return on([](const auto& s) -> const Model<>& {
    if constexpr (std::is_same_v<typename std::decay_t<decltype(s)>::Mem, MemSpace>)
      return s.model();
    else
      not_in_default_memory(s.space().name(), "model");
  });
}
const std::string& Solver::colouring_name() const {
  return on([](const auto& s) -> const std::string& { return s.model().colouring_name; });
}
Sizes Solver::sizes() const {
  return on([](const auto& s) { return s.sizes(); });
}
OutputFields Solver::output_fields() {
  return on([](auto& s) { return s.output_fields(); });
}
const std::vector<std::pair<std::string, double>>& Solver::presim() const {
  return on([](const auto& s) -> const auto& { return s.presim(); });
}
void Solver::set_load(double D) {
  on([&](auto& s) { s.set_load(D); });
}
double Solver::load() const {
  return on([](const auto& s) { return s.load(); });
}
double Solver::energy() {
  return on([](auto& s) { return s.energy(); });
}
double Solver::reaction() {
  return on([](auto& s) { return s.reaction(); });
}
int Solver::ruptured() {
  return on([](auto& s) { return s.ruptured(); });
}
std::vector<std::int8_t> Solver::interface_states(std::vector<double>* energy) {
  return on([&](auto& s) { return s.interface_states(energy); });
}
double Solver::residual() {
  return on([](auto& s) { return s.residual(); });
}
PolishResult Solver::polish(const std::string& method, double tolerance) {
  return on([&](auto& s) { return s.polish(method, tolerance); });
}
PolishResult Solver::anneal(const PolishOptions& o) {
  return on([&](auto& s) { return s.anneal(o); });
}
const ResidualScale& Solver::residual_scale() const {
  return on([](const auto& s) -> const ResidualScale& { return s.residual_scale(); });
}
const GradientView<>& Solver::gradient() const {
  return on([](const auto& s) -> const GradientView<>& {
    if constexpr (std::is_same_v<typename std::decay_t<decltype(s)>::Mem, MemSpace>)
      return s.gradient();
    else
      not_in_default_memory(s.space().name(), "gradient");
  });
}
long Solver::cycle() {
  return on([](auto& s) { return s.cycle(); });
}
std::size_t Solver::cycle_bytes() const {
  return on([](const auto& s) { return s.cycle_bytes(); });
}
std::optional<double> Solver::cycle_flops() const {
  return on([](const auto& s) { return s.cycle_flops(); });
}
long Solver::relax(bool& converged) {
  return on([&](auto& s) { return s.relax(converged); });
}
void Solver::run(const std::function<void(const StepRecord&)>& on_step) {
  on([&](auto& s) { s.run(on_step); });
}
Checkpoint Solver::checkpoint() const {
  return on([](const auto& s) { return s.checkpoint(); });
}
void Solver::restore(const Checkpoint& c) {
  on([&](auto& s) { s.restore(c); });
}
const RunState& Solver::run_state() const {
  return on([](const auto& s) -> const RunState& { return s.run_state(); });
}
bool Solver::finished() const {
  return on([](const auto& s) { return s.finished(); });
}
double Solver::path_fraction() const {
  return on([](const auto& s) { return s.path_fraction(); });
}
double Solver::dissipated() {
  return on([](auto& s) { return s.dissipated(); });
}
bool Solver::interrupted() const {
  return on([](const auto& s) { return s.interrupted(); });
}
bool Solver::failed() const {
  return on([](const auto& s) { return s.failed(); });
}
const StepRecord& Solver::failed_step() const {
  return on([](const auto& s) -> const StepRecord& { return s.failed_step(); });
}
const PhaseTimes& Solver::times() const {
  return on([](const auto& s) -> const PhaseTimes& { return s.times(); });
}
double Solver::step_size() const {
  return on([](const auto& s) { return s.step_size(); });
}
double Solver::rot_step() const {
  return on([](const auto& s) { return s.rot_step(); });
}
std::uint64_t Solver::global_cycle() const {
  return on([](const auto& s) { return s.global_cycle(); });
}
double Solver::tracked_energy() const {
  return on([](const auto& s) { return s.tracked_energy(); });
}
void Solver::poses(std::vector<double>& x, std::vector<double>& y, std::vector<double>& t) const {
  on([&](const auto& s) { s.poses(x, y, t); });
}

}  // namespace nacre::mc
