// SPDX-License-Identifier: BSD-3-Clause
// The dynamic solver behind include/nacre/dyn/simulation.hpp: owns the model and the state (ImplIn<Mem>,
// in the memory space of the backend the run is built for: one binary runs on a CUDA build's
// device and its host backends), runs initial_integrate / interface force / final_integrate per
// step, keeps the energy books, and catches blow-ups.
//
// Checks (advance, critical_step; docs/dynamics.md "Stability monitor"): after every kCheckEvery
// steps (and after every step while locating a failure) the state is unstable when
//  - any displacement, velocity or acceleration is not finite, or the kinetic energy of the free
//    elements exceeds 10 * (|external work| + |E_ref|) + 1e-20 N mm (E_ref: the mechanical
//    energy at the start, 0 from rest): a stable run cannot reach it, damping only removes energy;
//  - Params::balance_tolerance > 0 and |energy balance residual| exceeds it: the physical
//    invariant, which a local instability breaks long before the kinetic bound;
//  - (chunk checks only) Params::growth_factor > 0 and one element's share of the energy grew by
//    more than that factor per check in growth_checks consecutive checks (monitor.hpp);
//  - (chunk checks only) Params::step_check, fixed dt, and the estimated critical step of the
//    current tangent stiffness (monitor.hpp StepBound) fell below dt.
// On failure the chunk is replayed step by step from a copy, so the state is left at the last
// step that passes the per-step checks (the run is deterministic, the replay takes the same
// path); a failure only the chunk checks see leaves the state at the chunk's start.
#include <nacre/dyn/bie.hpp>
#include <nacre/dyn/halo.hpp>
#include <nacre/dyn/kernels.hpp>
#include <nacre/dyn/model.hpp>
#include <nacre/dyn/monitor.hpp>
#include <nacre/dyn/simulation.hpp>
#include <nacre/core/backend.hpp>
#include <nacre/core/flop_count.hpp>

#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace nacre::dyn {

namespace {
constexpr double kBlowUpFactor = 10.0;
constexpr double kTinyEnergy = 1e-20;
/// elements below this share of the energy are not watched for growth (rounding-level shares
/// jump by any factor)
constexpr double kGrowthFloor = 1e-6;
/// Outcome of a check: passed, failed one the per-step replay also runs (finite, kinetic bound,
/// balance), or failed one of the chunk checks only (growth, step bound).
enum class Health { ok, step_failure, chunk_failure };
}  // namespace

template <class M>
struct ImplIn {
  using Mem = M;  ///< where the model and the state live: the run's backend's memory
  Params p;
  Model<Mem> m;
  HostMap map;
  std::size_t n_bricks = 0;
  // MPI runs (halo.hpp): the ranks, the exchange of the halo's u, the rows this rank owns of
  // each sum (elements, interfaces, driven rows); one process: Comm{}, no halo, every row
  par::Comm comm;
  std::unique_ptr<ElementHalo<Mem>> halo;
  long long own_elem = 0, own_iface = 0, own_driven = 0;
  [[nodiscard]] par::Reduce reduce(long long owned) const { return par::Reduce{&comm, owned}; }
  [[nodiscard]] InterfaceOp<Mem> iop() const { return InterfaceOp<Mem>(m, u, iforce, halo.get()); }
  DofView<Mem> u, v, a, u0, v0, a0;
  decltype(Model<Mem>::hist) hist0;  ///< the damage history's roll-back copy (irreversible damage only)
  AccView<Mem> acc, acc0;
  DrivenAccView<Mem> dacc, dacc0;
  IforceView<Mem> iforce;
  SumWorkspace<Mem> ws;
  loading::Ramp ramp;
  Backend backend;  ///< the instance the run's kernels go to (every launch: backend.visit_in<Mem>)
  long step = 0;
  /// time of step n: t_base + (n - step_base) dt, exactly n dt while dt never changed (the
  /// adaptive mode moves the base to the step of each change)
  double t_base = 0;
  long step_base = 0;
  [[nodiscard]] double now(long n) const { return t_base + static_cast<double>(n - step_base) * p.dt; }
  double dt0 = 0;       ///< the step the run started with (Params::dt)
  double e_ref = 0;
  double e_in = 0;      ///< energy of a state set by hand that no work accounts for (restore_state)
  std::string why;
  // stability monitor (monitor.hpp): energy shares and growth runs per element, the step bound
  Kokkos::View<double*, Mem> share;
  Kokkos::View<std::int16_t*, Mem> run;
  StepReport report;
  // BIE (bie.hpp): J^-1 per type, slot order, p_n / v_n and the residual block
  BieTables<Mem> bie;
  DofView<Mem> pn, vn, R;
  int n_tiles = 0;
  /// BIE's step, chosen once (choose_bie_step) from the scheme and whether the shared J^-1 is
  /// fused over the tiles: one of bie_step's overloads, and what it needs besides the functors.
  using BieStepFn = void (*)(const Backend&, const BieIntegrator<Mem>&, const InterfaceOp<Mem>&, const BieSolveOp<Mem>&,
                             const BieStepPlan&);
  BieStepFn bie_step_fn = nullptr;
  BieStepPlan bie_plan;
  [[nodiscard]] bool is_bie() const { return p.method == Method::bie; }
  /// The step's last update of u follows its last interface-force pass (bie_step: the iterated
  /// scheme keeping the force of the previous iterate for its last iteration).
  [[nodiscard]] bool moves_after_force() const {
    return is_bie() && p.bie_scheme == BieScheme::iterate && p.bie_reuse_force && p.bie_iterations >= 2;
  }

  template <class V>
  static V make(const std::string& l, std::size_t n0, std::size_t n1 = KOKKOS_IMPL_CTOR_DEFAULT_ARG) {
    return V(Kokkos::view_alloc("nacre::dyn::" + l), n0, n1);
  }

  void allocate() {
    const int ne = m.n_elem, nd = m.nd;
    u = make<DofView<Mem>>("u", ne, nd), v = make<DofView<Mem>>("v", ne, nd), a = make<DofView<Mem>>("a", ne, nd);
    u0 = make<DofView<Mem>>("u0", ne, nd), v0 = make<DofView<Mem>>("v0", ne, nd), a0 = make<DofView<Mem>>("a0", ne, nd);
    const int nc = is_bie() ? kAccColsBie : kAccColsExplicit, ndr = std::max(m.n_driven, 1);
    acc = make<AccView<Mem>>("acc", ne, nc), acc0 = make<AccView<Mem>>("acc0", ne, nc);
    dacc = make<DrivenAccView<Mem>>("dacc", ndr), dacc0 = make<DrivenAccView<Mem>>("dacc0", ndr);
    iforce = make<IforceView<Mem>>("iforce", std::max(m.n_iface, 1));
    if (m.hist.data()) hist0 = decltype(hist0)("nacre::dyn::history0", m.hist.extent(0), m.hist.extent(1));
    ws.reserve_terms(std::max(ne, m.n_iface));
    if (p.growth_factor > 0) {
      share = Kokkos::View<double*, Mem>("nacre::dyn::monitor::share", ne);
      run = Kokkos::View<std::int16_t*, Mem>("nacre::dyn::monitor::run", ne);
    }
    if (is_bie()) {
      pn = make<DofView<Mem>>("bie_pn", ne, nd), vn = make<DofView<Mem>>("bie_vn", ne, nd);
      if (!bie_fused()) R = make<DofView<Mem>>("bie_R", std::max(ne, 1), 2 * nd);
    }
  }

  BieIntegrator<Mem> bie_integrator() const {
    return BieIntegrator<Mem>{integrator(), bie.slot_of_elem, pn, vn, R, bie.Jinv, bie.jq, bie.jr, bie.Jv};
  }
  /// Picks BIE's step overload and fills its plan (after the tables and n_tiles are set): the
  /// scheme, whether the tiles are fused, and (fused) the form of the J^-1 apply the tables allow
  /// (Params::bie_block_structure = false keeps the dense form).
  void choose_bie_step() {
    if (!is_bie()) return;
    bie_plan = BieStepPlan{p.bie_solve, p.bie_block, p.bie_iterations, p.bie_reuse_force, m.n_elem, m.n_iface, n_tiles};
    if (p.bie_scheme == BieScheme::split)
      bie_step_fn = pick_bie_step<BieSplitScheme>();
    else
      bie_step_fn = pick_bie_step<BieIterateScheme>();
  }
  template <class Scheme>
  BieStepFn pick_bie_step() const {
    if (!bie_fused()) return &bie_step_of<Scheme, false, JinvDense>;
    if (p.bie_block_structure && bie.vfirst) return &bie_step_of<Scheme, true, JinvVelocityFirst>;
    if (p.bie_block_structure && bie.block_lower) return &bie_step_of<Scheme, true, JinvBlockLower>;
    return &bie_step_of<Scheme, true, JinvDense>;
  }
  /// bie_step's overload for (Scheme, Fused, Jinv) behind one function-pointer type.
  template <class Scheme, bool Fused, class Jinv>
  static void bie_step_of(const Backend& b, const BieIntegrator<Mem>& it, const InterfaceOp<Mem>& op,
                          const BieSolveOp<Mem>& so, const BieStepPlan& pl) {
    b.visit_in<Mem>([&](const auto& s) { bie_step(s, Scheme{}, std::bool_constant<Fused>{}, Jinv{}, it, op, so, pl); });
  }

  /// BIE's shared_gemm over the element tiles, fused with the residual and the update (no R).
  [[nodiscard]] bool bie_fused() const { return is_bie() && p.bie_solve == BieSolve::shared_gemm && tiled(); }
  BieSolveOp<Mem> bie_solver() const {
    return BieSolveOp<Mem>{bie.Jinv, bie.slot_type, bie.tile_start, bie.tile_count, R, bie.n2};
  }

  /// The state at t = 0: driven elements at their prescribed values, BIE's a_0, the start's work
  /// books, and the step bound's reference.
  void start() {
    impose(0.0);
    // BIE carries a_n into the step (eq. 4.6; the split step M^-1 F instead): start from the
    // initial state's.
    backend.visit_in<Mem>([&](const auto& space) {
      if (is_bie())
        bie_accelerations(space, bie_integrator(), iop(), m.n_elem, m.n_iface, p.bie_scheme == BieScheme::split);
      // An impulsive start (rate without ramp) gives the driven bricks velocity at t = 0: that
      // kinetic energy is counted as work done by the machine, so the balance starts closed.
      set_initial_work(space, integrator(), KineticEnergy<Mem>{m.type, m.drive, m.mass, u, v, a, m.nd, false, false},
                       m.n_elem);
      space.fence();
    });
    read_bound(false);
    report.bound_start = report.bound;
  }

  /// The tangent step bound (monitor.hpp) of the current state; BIE: interfaces only.
  StepBound<Mem> step_bound_op() const {
    return StepBound<Mem>{iop(), m.type, m.goff, m.gent, m.drive, m.mass, m.klam, m.nd, !is_bie()};
  }
  /// Evaluate the bound now into `report` (the controlling interface only when asked: a stop).
  void read_bound(bool where) {
    const auto sb = step_bound_op();
    const auto [val, loc] = over_ranks(
        backend.visit_in<Mem>([&](const auto& space) { return dyn::step_bound(space, sb, m.n_elem, m.elem_owned); }),
        true);
    report.dt = p.dt;
    report.bound = val > 0 ? 2.0 / std::sqrt(val) : 0.0;
    report.element = val > 0 ? loc : -1;
    report.brick = report.element >= 0 ? map.elem_brick[report.element] : -1;
    report.estimate = report.bound;
    report.iface = -1, report.penetration = 0;
    if (where && report.element >= 0) {  // on the rank that owns the element, then to every rank
      int i = -1;
      double pen = -std::numeric_limits<double>::infinity();
      const int e = local_element(report.element);
      if (e >= 0 && map.elem_owned[e]) {
        backend.visit_in<Mem>([&](const auto& space) { dyn::controlling_interface(space, sb, e, i, pen); });
        i = i >= 0 && i < m.n_mortar ? map.iface_geom[map.iface_global[i]] : -1;
      }
      report.iface = static_cast<int>(comm.max(e >= 0 && map.elem_owned[e] ? i : -2));
      report.penetration = comm.max(pen);
    }
  }

  Integrator<Mem> integrator() const { return Integrator<Mem>(m, u, v, a, acc, dacc, iforce); }

  /// A local arg-max over the owned elements as the whole run's: the largest value over the ranks
  /// and its whole-model element, the smallest among ties (one process's arg-max); a rank
  /// without an element (or, `positive`, without a positive value) offers (0, INT_MAX).
  template <class R>
  [[nodiscard]] std::pair<double, int> over_ranks(const R& r, bool positive) const {
    const bool found = (!positive || r.val > 0) && r.loc >= 0 && r.loc < m.n_elem;
    double val = found ? static_cast<double>(r.val) : 0.0;
    int loc = found ? map.elem_global[r.loc] : INT_MAX;
    comm.max_loc(val, loc);
    return {val, loc};
  }
  /// This rank's model element of whole-model element g, or -1.
  [[nodiscard]] int local_element(int g) const {
    const auto it = std::lower_bound(map.elem_global.begin(), map.elem_global.end(), g);
    return it != map.elem_global.end() && *it == g ? static_cast<int>(it - map.elem_global.begin()) : -1;
  }

  /// final_integrate over the element tiles (ElementTiles<true>) or per element: automatic =
  /// tiled on a CPU for the bolted methods (measured 1.5x faster final_integrate at 50k bricks);
  /// UE's 6-dof triangles gain nothing from it (measured), they stay per element.
  [[nodiscard]] bool tiled() const {
    return p.element_apply == ElementApply::tiled ||
           (p.element_apply == ElementApply::automatic && std::is_same_v<ElemLayout<Mem>, Kokkos::LayoutRight> &&
            p.method != Method::ue);
  }

  /// One step of the run's integrator (u, v, a from t_n to t_{n+1}; `it` carries the opening),
  /// chosen once (choose_step): velocity Verlet per element or tiled, or BIE's chosen step.
  using StepFn = void (*)(const ImplIn&, const Integrator<Mem>&);
  StepFn step_fn = nullptr;
  template <bool Tiled, class Ainv>
  static void verlet_of(const ImplIn& I, const Integrator<Mem>& it) {
    I.backend.visit_in<Mem>(
        [&](const auto& s) { verlet_step(s, ElementTiles<Tiled>{}, Ainv{}, it, I.iop(), I.m.n_elem, I.m.n_iface); });
  }
  static void bie_of(const ImplIn& I, const Integrator<Mem>& it) {
    auto bi = I.bie_integrator();
    bi.ex = it;
    I.bie_step_fn(I.backend, bi, I.iop(), I.bie_solver(), I.bie_plan);
  }
  void choose_step() {
    choose_bie_step();
    if (is_bie())
      step_fn = &bie_of;
    else if (m.ainv_diagonal)
      step_fn = tiled() ? &verlet_of<true, AinvDiagonal> : &verlet_of<false, AinvDiagonal>;
    else
      step_fn = tiled() ? &verlet_of<true, AinvDense> : &verlet_of<false, AinvDense>;
  }

  /// Driven elements at their prescribed values for time t (no step taken).
  void impose(double t) {
    auto it = integrator();
    const loading::Opening o = ramp(t);
    it.D = o.D, it.Dd = o.rate, it.Ddd = o.accel;
    backend.visit_in<Mem>([&](const auto& space) {
      impose_drive(space, it, m.n_elem);
      space.fence();
    });
  }

  void step_once() {
    const loading::Opening o = ramp(now(step + 1));
    auto it = integrator();
    it.D = o.D, it.Dd = o.rate, it.Ddd = o.accel;
    it.D_prev = ramp.displacement(now(step));
    step_fn(*this, it);
    backend.visit_in<Mem>([&](const auto& space) {
      // the iterated BIE step with the kept force moves u after its last force pass: the halo's u
      // from its owners again (every later reading of an interface needs both ends); Verlet's
      // and the split step's force pass left it current
      if (halo && moves_after_force()) halo->exchange(space);
      update_history(space, iop(), m.n_mortar);  // irreversible damage: after every step
    });
    ++step;
  }

  /// Adaptive mode: a new step h for every type table that depends on it ((M + h/2 C)^-1; BIE's
  /// J^-1), between two steps (velocity Verlet and the implicit midpoint take a new h per step).
  void change_dt(double h) {
    t_base = now(step), step_base = step;
    p.dt = h;
    set_model_step(m, h);
    if (is_bie()) {
      bie = build_bie_tables(m);
      n_tiles = static_cast<int>(bie.tile_start.extent(0));
      if (bie_fused()) bie.slot_of_elem = {}, bie.slot_type = {}, bie.tile_start = {}, bie.tile_count = {}, n_tiles = 0;
      choose_bie_step();
    }
    ++report.dt_changes;
  }

  void save_copy() {
    backend.visit_in<Mem>([&](const auto& space) {
      Kokkos::deep_copy(space, u0, u), Kokkos::deep_copy(space, v0, v), Kokkos::deep_copy(space, a0, a);
      Kokkos::deep_copy(space, acc0, acc), Kokkos::deep_copy(space, dacc0, dacc);
      if (m.hist.data()) Kokkos::deep_copy(space, hist0, m.hist);
    });
  }
  void load_copy() {
    backend.visit_in<Mem>([&](const auto& space) {
      Kokkos::deep_copy(space, u, u0), Kokkos::deep_copy(space, v, v0), Kokkos::deep_copy(space, a, a0);
      Kokkos::deep_copy(space, acc, acc0), Kokkos::deep_copy(space, dacc, dacc0);
      if (m.hist.data()) Kokkos::deep_copy(space, m.hist, hist0);
    });
  }

  // The books: every sum over this rank's owned rows, combined over the ranks (par::Reduce):
  // the bits of the one-process sum.
  double sum_acc(AccCol col) {
    return backend.visit_in<Mem>(
        [&](const auto& space) { return column_sum(space, ws, acc, col, m.n_elem, m.elem_owned, reduce(own_elem)); });
  }
  double sum_driven(DrivenCol col) {
    return backend.visit_in<Mem>([&](const auto& space) {
      return column_sum(space, ws, dacc, col, m.n_driven, m.driven_owned, reduce(own_driven));
    });
  }
  double kinetic(bool free_only, bool poison) {
    const KineticEnergy<Mem> k{m.type, m.drive, m.mass, u, v, a, m.nd, free_only, poison};
    return backend.visit_in<Mem>(
        [&](const auto& space) { return element_sum(space, ws, k, m.n_elem, m.elem_owned, reduce(own_elem)); });
  }
  double strain() {
    const StrainEnergy<Mem> se{m.type, m.K, u, m.nd};
    return backend.visit_in<Mem>(
        [&](const auto& space) { return element_sum(space, ws, se, m.n_elem, m.elem_owned, reduce(own_elem)); });
  }
  double cohesive() {
    const InterfaceOp<Mem> op = iop();
    return backend.visit_in<Mem>(
        [&](const auto& space) { return cohesive_energy(space, ws, op, m.n_iface, m.iface_owned, reduce(own_iface)); });
  }

  /// The energy books now; the balance residual is (W + E_in - (S + K + C + D)) / max|term|.
  Energies energies() {
    Energies e;
    e.strain = strain();
    e.kinetic = kinetic(false, false);
    e.cohesive = cohesive();
    e.damping_dissipated = sum_acc(kDamp);
    e.external_work = sum_acc(kWork);
    const double scale = std::max({std::abs(e.strain), std::abs(e.kinetic), std::abs(e.cohesive),
                                   std::abs(e.damping_dissipated), std::abs(e.external_work), std::abs(e_in)});
    const double res = e.external_work + e_in - (e.strain + e.kinetic + e.cohesive + e.damping_dissipated);
    e.balance_residual = scale > 0 ? res / scale : 0.0;
    return e;
  }
  /// Mechanical energy plus dissipation the books do not account for (0 for a state the run made).
  double unaccounted(const Energies& e) const {
    return e.strain + e.kinetic + e.cohesive + e.damping_dissipated - e.external_work - e_in;
  }

  /// The checks of the header on the current state; a failure fills `why`. `chunk`: the end of a
  /// step chunk (the growth and step-bound checks run there only).
  Health healthy(bool chunk) {
    Kokkos::Profiling::ScopedRegion r("nacre::dyn::check");
    const double ke = kinetic(true, true);
    const double w = sum_acc(kWork);
    const double bound = kBlowUpFactor * (std::abs(w) + std::abs(e_ref)) + kTinyEnergy;
    std::ostringstream o;
    o.precision(6);
    o << "step " << step << " (t = " << now(step) << " s): ";
    if (!std::isfinite(ke) || !std::isfinite(w)) {
      o << "non-finite " << (std::isfinite(ke) ? "external work" : "displacement, velocity or acceleration");
      why = o.str();
      return Health::step_failure;
    }
    if (ke > bound) {
      o << "kinetic energy " << ke << " N mm exceeds the bound 10 (|external work| + |E_ref|) = " << bound << " N mm";
      why = o.str();
      return Health::step_failure;
    }
    Energies e;
    if (p.balance_tolerance > 0 || p.growth_factor > 0) {
      e = energies();
      // from the first chunk's end on (balance_checked): the first steps of a start carry an
      // O((h omega)^2) error of the books relative to the little energy put in yet (BIE at 40 ns:
      // 2.2e-3 at step 2), not an instability
      if (p.balance_tolerance > 0 && balance_checked(step) && !(std::abs(e.balance_residual) <= p.balance_tolerance)) {
        o << "energy balance residual " << e.balance_residual << " exceeds balance_tolerance " << p.balance_tolerance
          << " (work " << e.external_work << ", strain " << e.strain << ", kinetic " << e.kinetic << ", cohesive "
          << e.cohesive << ", damping " << e.damping_dissipated << " N mm)";
        why = o.str();
        return Health::step_failure;
      }
    }
    if (!chunk) return Health::ok;
    if (p.growth_factor > 0 && e.strain + e.kinetic > 0) {
      const ElementGrowth<Mem> g{StrainEnergy<Mem>{m.type, m.K, u, m.nd},
                                 KineticEnergy<Mem>{m.type, m.drive, m.mass, u, v, a, m.nd, false, false},
                                 share, run, 1.0 / (e.strain + e.kinetic), p.growth_factor, kGrowthFloor};
      const auto [runs, where] = over_ranks(
          backend.visit_in<Mem>([&](const auto& space) { return element_growth(space, g, m.n_elem, m.elem_owned); }),
          false);
      const int longest = static_cast<int>(runs);
      report.growth_longest = std::max(report.growth_longest, longest);
      if (longest >= p.growth_checks) {
        const int el = local_element(where);
        double now = -std::numeric_limits<double>::infinity();
        if (el >= 0 && map.elem_owned[el]) {
          auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, Kokkos::subview(share, el));
          now = hs();
        }
        now = comm.max(now);
        o << "element " << where << " (brick " << map.elem_brick[where] << ") energy share grew by more than "
          << p.growth_factor << "x per " << kCheckEvery << "-step check in " << longest << " checks in a row (now "
          << now << " of the specimen's strain + kinetic energy): a local instability";
        why = o.str();
        return Health::chunk_failure;
      }
    }
    if (p.step_check) {
      read_bound(false);
      if (p.dt_mode == DtMode::fixed && p.dt > report.estimate) {
        read_bound(true);
        o << "the estimated critical step " << report.estimate << " s fell below dt = " << p.dt
          << " s (" << report.bound / report.bound_start << " of its start value) at element " << report.element << " (brick " << report.brick << ")";
        if (report.iface >= 0)
          o << ", interface " << report.iface << " penetrating " << report.penetration << " x1";
        o << "; use a smaller dt or dt_mode = \"adaptive\"";
        why = o.str();
        return Health::chunk_failure;
      }
    }
    return Health::ok;
  }

  /// Adaptive mode, after a passed chunk check: the step follows the bound, dt = dt0 * min(1,
  /// bound / bound_start), changed when it moved by more than 2 % (down) or 10 % (up).
  void adapt() {
    if (!(p.step_check && p.dt_mode == DtMode::adaptive) || !(report.bound_start > 0) || !(report.bound > 0)) return;
    const double want = dt0 * std::min(1.0, report.bound / report.bound_start);
    if (want < 0.98 * p.dt || want > 1.1 * p.dt || (want == dt0 && p.dt != dt0 && want > p.dt)) change_dt(want);
  }
};

template <class M>
using ImplPtr = std::unique_ptr<ImplIn<M>>;
/// The run's ImplIn, in its backend's memory space (one alternative in a host build).
struct Simulation::Impl {
  PerMemorySpace<ImplPtr> in;
};

/// f(the run's ImplIn): every member below goes through here.
template <class F>
decltype(auto) Simulation::on(F&& f) const {
  return std::visit([&](const auto& p) -> decltype(auto) { return f(*p); }, impl_->in);
}

Simulation::Simulation(const Backend& backend, const Params& p, const geometry::Specimen& s,
                       const geometry::Interfaces& f, const deck::Mortar& mortar, const par::Comm& comm)
    : impl_(std::make_unique<Impl>()) {
  Kokkos::Profiling::ScopedRegion region("nacre::dyn::setup");
  // the model and the state in the memory of the backend the run's kernels go to
  backend.visit([&](const auto& space) {
    using M = MemOf<std::decay_t<decltype(space)>>;
    impl_->in = std::make_unique<ImplIn<M>>();
  });
  on([&](auto& I) {
    using Mem = typename std::decay_t<decltype(I)>::Mem;
    I.p = p;
    I.ramp = loading::Ramp{p.ramp == Ramp::linear ? loading::Profile::linear : loading::Profile::smooth, p.rate,
                           p.ramp_time, p.final_displacement};
    if (p.programme.size() > static_cast<std::size_t>(loading::kMaxTargets))
      throw std::invalid_argument("dyn: a load programme has at most " + std::to_string(loading::kMaxTargets) +
                                  " targets");
    I.ramp.n_targets = static_cast<int>(p.programme.size());
    for (std::size_t k = 0; k < p.programme.size(); ++k) I.ramp.target[k] = p.programme[k];
    I.n_bricks = s.size();
    I.comm = comm;
    std::unique_ptr<par::Decomposition> part;
    if (comm.size() > 1)  // this rank's bricks and halo (the Monte Carlo solver's decomposition, one brick a work item)
      part = std::make_unique<par::Decomposition>(
          par::decompose(comm.rank(), comm.size(), s, f, geometry::build_adjacency(s.size(), f), {}));
    I.m = build_model<Mem>(p, s, f, mortar, I.map, part.get());
    for (char c : I.map.elem_owned) I.own_elem += c;
    for (char c : I.map.iface_owned) I.own_iface += c;
    for (char c : I.map.driven_owned) I.own_driven += c;
    if (I.is_bie()) {
      if (!bie_solve_available(p.bie_solve))
        throw std::invalid_argument(std::string("dyn: bie_solve = \"") + bie_solve_name(p.bie_solve) +
                                    "\" needs Kokkos Kernels, which this build does not have");
      if (p.bie_solve == BieSolve::reordered && !valid_bie_block(p.bie_block))
        throw std::invalid_argument(std::string("dyn: bie_block must be ") + kBieBlockExpected + " (got " +
                                    std::to_string(p.bie_block) + ")");
      if (p.bie_iterations < 1) throw std::invalid_argument("dyn: bie_iterations must be >= 1");
      I.bie = build_bie_tables(I.m);
      I.n_tiles = static_cast<int>(I.bie.tile_start.extent(0));
      if (I.bie_fused()) {  // the slot order serves only the unfused variants: keep nothing of it
        I.bie.slot_of_elem = {}, I.bie.slot_type = {}, I.bie.tile_start = {}, I.bie.tile_count = {};
        I.n_tiles = 0;
      }
    }
    I.choose_step();
    I.dt0 = p.dt;
    I.allocate();
    if (part) I.halo = std::make_unique<ElementHalo<Mem>>(comm, *part, I.map, I.u);
    I.backend = backend;
    I.start();
  });
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

bool Simulation::advance(const Kokkos::DefaultExecutionSpace& space, long n) {
  on([&](auto& I) {
    using Mem = typename std::decay_t<decltype(I)>::Mem;
    if (!Backend(space).reaches<Mem>())
      throw std::logic_error("dyn::Simulation::advance: the default space cannot reach this run's memory");
    I.backend = Backend(space);
  });
  return advance(n);
}

bool Simulation::advance(long n) {
  return on([&](auto& I) -> bool {
    Kokkos::Profiling::ScopedRegion region("nacre::dyn::advance");
    const Backend& backend = I.backend;
    long done = 0;
    while (done < n) {
      const long chunk = std::min<long>(kCheckEvery, n - done);
      I.save_copy();
      const long start = I.step;
      for (long k = 0; k < chunk; ++k) I.step_once();
      backend.fence();
      if (const auto h = I.healthy(true); h != Health::ok) {
        if (h == Health::chunk_failure) {  // only a chunk check (growth, step bound) saw it:
          I.load_copy();  // back to the chunk's start, which passed every check
          I.step = start;
          backend.fence();
          return false;
        }
        // replay the chunk step by step to stop at the last good step
        I.load_copy();
        I.step = start;
        for (long k = 0; k < chunk; ++k) {
          I.save_copy();
          I.step_once();
          backend.fence();
          if (I.healthy(false) != Health::ok) {
            I.load_copy();
            --I.step;
            backend.fence();
            return false;
          }
        }
        // (the replay found no failure: impossible for a deterministic run; report the chunk)
        I.why = "blow-up at the end of a step chunk that the replay did not reproduce";
        return false;
      }
      I.adapt();
      done += chunk;
    }
    return true;
  });
}

const std::string& Simulation::why() const {
  return on([&](auto& I) -> const std::string& { return I.why; });
}
double Simulation::time() const {
  return on([&](auto& I) -> double { return I.now(I.step); });
}
double Simulation::dt() const {
  return on([&](auto& I) -> double { return I.p.dt; });
}
const StepReport& Simulation::step_report() const {
  return on([&](auto& I) -> const StepReport& { return I.report; });
}
void Simulation::set_initial_dt(double h) {
  return on([&](auto& I) -> void {
    if (I.step != 0) throw std::logic_error("dyn::Simulation::set_initial_dt: the run has started");
    I.change_dt(h);
    I.dt0 = h;
    I.report.dt_changes = 0;
    I.start();  // a_0 and the start's books at the new step
  });
}
StepReport Simulation::step_check() {
  return on([&](auto& I) -> StepReport {
    I.read_bound(true);
    return I.report;
  });
}
long Simulation::steps() const {
  return on([&](auto& I) -> long { return I.step; });
}
double Simulation::displacement() const {
  return on([&](auto& I) -> double { return I.ramp.displacement(time()); });
}

Energies Simulation::energies() const {
  return on([&](auto& I) -> Energies {
    Kokkos::Profiling::ScopedRegion region("nacre::dyn::energies");
    return I.energies();
  });
}

double Simulation::reaction() const {
  return on([&](auto& I) -> double { return I.sum_driven(kReact); });
}

int Simulation::ruptured() const {
  return on([&](auto& I) -> int {
    using Mem = typename std::decay_t<decltype(I)>::Mem;
    const InterfaceOp<Mem> op = I.iop();
    const int mine = I.backend.template visit_in<Mem>(
        [&](const auto& space) { return count_ruptured(space, op, I.m.n_mortar, I.m.iface_owned); });
    return static_cast<int>(I.comm.sum(static_cast<long long>(mine)));
  });
}

double Simulation::max_penetration() const {
  return on([&](auto& I) -> double {
    using Mem = typename std::decay_t<decltype(I)>::Mem;
    const InterfaceOp<Mem> op = I.iop();
    return I.comm.max(I.backend.template visit_in<Mem>(
        [&](const auto& space) { return dyn::max_penetration(space, op, I.m.n_mortar); }));
  });
}

namespace {
// State arrays go to and from checkpoints in LayoutLeft order (element index fastest) whatever
// the backend's layout (ElemLayout), so a checkpoint and the tests' flat indexing are the same
// on every backend.
template <class V>
std::vector<double> to_vector(const V& d) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, d);
  const std::size_t n0 = h.extent(0), n1 = h.extent(1);
  std::vector<double> x(n0 * n1);
  for (std::size_t j = 0; j < n1; ++j)
    for (std::size_t i = 0; i < n0; ++i) x[i + n0 * j] = h(i, j);
  return x;
}
template <class V>
void from_vector(const V& d, const std::vector<double>& x, const char* name) {
  auto h = Kokkos::create_mirror_view(d);
  const std::size_t n0 = h.extent(0), n1 = h.extent(1);
  if (x.size() != n0 * n1)
    throw std::runtime_error(std::string("dyn::restore_state: array '") + name + "' has " + std::to_string(x.size()) +
                             " values, the model needs " + std::to_string(n0 * n1));
  for (std::size_t j = 0; j < n1; ++j)
    for (std::size_t i = 0; i < n0; ++i) h(i, j) = x[i + n0 * j];
  Kokkos::deep_copy(d, h);
}

/// Rank 0: the whole model's n rows of a [row][col] View the ranks hold in parts (row r here is
/// the whole model's global[r], sent where owned[r]), in to_vector's order; empty on the other
/// ranks. One process: to_vector.
template <class V>
std::vector<double> gather_rows(const par::Comm& comm, const V& d, const std::vector<int>& global,
                                const std::vector<char>& owned, std::size_t n) {
  if (comm.size() == 1) return to_vector(d);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, d);
  const std::size_t nc = h.extent(1);
  std::vector<double> mine;
  for (std::size_t r = 0; r < global.size(); ++r) {
    if (!owned[r]) continue;
    mine.push_back(global[r]);
    for (std::size_t c = 0; c < nc; ++c) mine.push_back(h(r, c));
  }
  const auto parts = comm.gather(std::move(mine));
  if (comm.rank() != 0) return {};
  std::vector<double> x(n * nc, 0.0);
  for (const auto& part : parts)
    for (std::size_t k = 0; k + nc < part.size() + 1; k += nc + 1) {
      const auto g = static_cast<std::size_t>(part[k]);
      for (std::size_t c = 0; c < nc; ++c) x[g + n * c] = part[k + 1 + c];
    }
  return x;
}

/// The reverse on every rank: its rows (global[r] of the whole model's n) from the whole array x
/// (every rank reads the checkpoint). One process: from_vector.
template <class V>
void scatter_rows(const par::Comm& comm, const V& d, const std::vector<double>& x, const std::vector<int>& global,
                  std::size_t n, const char* name) {
  if (comm.size() == 1) return from_vector(d, x, name);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, d);
  const std::size_t nc = h.extent(1);
  if (x.size() != n * nc)
    throw std::runtime_error(std::string("dyn::restore_state: array '") + name + "' has " + std::to_string(x.size()) +
                             " values, the model needs " + std::to_string(n * nc));
  for (std::size_t r = 0; r < global.size(); ++r)
    for (std::size_t c = 0; c < nc; ++c) h(r, c) = x[static_cast<std::size_t>(global[r]) + n * c];
  Kokkos::deep_copy(d, h);
}
}  // namespace

Snapshot Simulation::snapshot() const {
  return on([&](auto& I) -> Snapshot {
    Kokkos::Profiling::ScopedRegion region("nacre::dyn::snapshot");
    Snapshot s;
    s.time = time();
    s.displacement = displacement();
    const auto& M = I.map;
    const auto ne = static_cast<std::size_t>(M.n_elem);  // the whole model's, on rank 0
    const std::vector<double> gu = gather_rows(I.comm, I.u, M.elem_global, M.elem_owned, ne);
    const std::vector<double> gv = gather_rows(I.comm, I.v, M.elem_global, M.elem_owned, ne);
    std::vector<double> damage;
    std::vector<int> state;
    interface_damage(damage, state);  // (every rank: a gather)
    if (I.comm.rank() != 0) return s;
    auto hu = [&](std::size_t e, int j) { return gu[e + ne * static_cast<std::size_t>(j)]; };
    auto hv = [&](std::size_t e, int j) { return gv[e + ne * static_cast<std::size_t>(j)]; };
    std::vector<int> node0(ne + 1, 0);
    for (std::size_t e = 0; e < ne; ++e) node0[e + 1] = node0[e] + M.type_nodes[M.elem_type[e]];
    const int nn = node0[ne];
    s.node_x.resize(nn), s.node_y.resize(nn), s.ux.resize(nn), s.uy.resize(nn), s.vx.resize(nn), s.vy.resize(nn);
    for (std::size_t e = 0; e < ne; ++e) {
      const int t = M.elem_type[e], b = M.elem_brick[e];
      for (int j = 0; j < M.type_nodes[t]; ++j) {
        const int k = node0[e] + j;
        s.node_x[k] = M.cx[b] + M.type_x[t * kMaxNodes + j];
        s.node_y[k] = M.cy[b] + M.type_y[t * kMaxNodes + j];
        s.ux[k] = hu(e, 2 * j), s.uy[k] = hu(e, 2 * j + 1), s.vx[k] = hv(e, 2 * j), s.vy[k] = hv(e, 2 * j + 1);
      }
    }
    const std::size_t ntri = M.tri_elem.size();
    s.tri.resize(3 * ntri), s.tri_brick.resize(ntri);
    s.tri_sxx.resize(ntri), s.tri_syy.resize(ntri), s.tri_sxy.resize(ntri);
    s.brick_syy.assign(I.n_bricks, 0.0);
    std::vector<double> barea(I.n_bricks, 0.0);
    for (std::size_t k = 0; k < ntri; ++k) {
      const int e = M.tri_elem[k], t = M.elem_type[e], b = M.tri_brick[k];
      double x[3], y[3], ue[6], sig[3], area;
      for (int c = 0; c < 3; ++c) {
        const int j = M.tri_local[k][c];
        s.tri[3 * k + c] = node0[e] + j;
        x[c] = M.type_x[t * kMaxNodes + j], y[c] = M.type_y[t * kMaxNodes + j];
        ue[2 * c] = hu(e, 2 * j), ue[2 * c + 1] = hu(e, 2 * j + 1);
      }
      triangle_stress(x, y, ue, I.p.youngs_modulus, I.p.poisson, I.p.thermal_strain, sig, area);
      s.tri_brick[k] = b;
      s.tri_sxx[k] = sig[0], s.tri_syy[k] = sig[1], s.tri_sxy[k] = sig[2];
      s.brick_syy[b] += sig[1] * area, barea[b] += area;
    }
    for (std::size_t b = 0; b < I.n_bricks; ++b) s.brick_syy[b] /= barea[b] > 0 ? barea[b] : 1.0;
    s.iface_damage = std::move(damage), s.iface_state = std::move(state);
    return s;
  });
}

void Simulation::interface_damage(std::vector<double>& damage, std::vector<int>& state,
                                  std::vector<double>* energy) const {
  return on([&](auto& I) -> void {
    using Mem = typename std::decay_t<decltype(I)>::Mem;
    Kokkos::Profiling::ScopedRegion region("nacre::dyn::interface_damage");
    const int nm = I.m.n_mortar;  // bed/head only
    Kokkos::View<double*, Mem> dmg(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::damage"),
                                   std::max(nm, 1));
    Kokkos::View<int*, Mem> st(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::damage_state"),
                               std::max(nm, 1));
    Kokkos::View<double*, Mem> en;
    if (energy)
      en = Kokkos::View<double*, Mem>(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::iface_energy"),
                                      std::max(nm, 1));
    const InterfaceOp<Mem> op(I.m, I.u, I.iforce);
    I.backend.template visit_in<Mem>([&](const auto& space) { dyn::interface_damage(space, op, nm, dmg, st, en); });
    auto hd = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, dmg);
    auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, st);
    auto he = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, en);
    const auto& M = I.map;
    // (geometry index, damage, state, energy) of this rank's owned rows; on ranks gathered to rank 0
    std::vector<double> mine;
    mine.reserve(static_cast<std::size_t>(nm) * 4);
    for (int i = 0; i < nm; ++i)
      if (M.iface_owned[i])
        mine.insert(mine.end(), {static_cast<double>(M.iface_geom[M.iface_global[i]]), hd(i),
                                 static_cast<double>(hs(i)), energy ? he(i) : 0.0});
    const auto parts = I.comm.gather(std::move(mine));
    damage.clear(), state.clear();
    if (energy) energy->clear();
    if (I.comm.rank() != 0) return;
    const auto n = static_cast<std::size_t>(M.n_mortar);
    damage.assign(n, 0.0);
    state.assign(n, 0);
    if (energy) energy->assign(n, 0.0);
    for (const auto& part : parts)
      for (std::size_t k = 0; k + 4 <= part.size(); k += 4) {  // back to the geometry's interface order
        const auto g = static_cast<std::size_t>(part[k]);
        damage[g] = part[k + 1], state[g] = static_cast<int>(part[k + 2]);
        if (energy) (*energy)[g] = part[k + 3];
      }
  });
}

StateArrays Simulation::save_state() const {
  return on([&](auto& I) -> StateArrays {
    StateArrays s;
    const auto& M = I.map;
    const auto ne = static_cast<std::size_t>(M.n_elem);
    // on ranks the whole model's rows on rank 0 (the others: empty arrays), in the one-process layout
    s["u"] = gather_rows(I.comm, I.u, M.elem_global, M.elem_owned, ne);
    s["v"] = gather_rows(I.comm, I.v, M.elem_global, M.elem_owned, ne);
    s["a"] = gather_rows(I.comm, I.a, M.elem_global, M.elem_owned, ne);
    s["acc"] = gather_rows(I.comm, I.acc, M.elem_global, M.elem_owned, ne);
    s["dacc"] = gather_rows(I.comm, I.dacc, M.driven_global, M.driven_owned, std::max<std::size_t>(M.n_driven, 1));
    if (I.m.irreversible) {  // irreversible damage (optional array): the bed/head rows (a collective: the deck decides)
      const std::vector<int> rows(M.iface_global.begin(), M.iface_global.begin() + I.m.n_mortar);
      s["history"] = gather_rows(I.comm, I.m.hist, rows, M.iface_owned, static_cast<std::size_t>(M.n_mortar));
    }
    // step, start dt, E_ref, then the time base, current dt, the bound at the start, E_in, dt
    // changes, the step of the time base, the energy the books do not account for (a restore
    // that finds another value was set by hand), and the growth monitor's longest run so far
    const double unaccounted = I.unaccounted(I.energies());
    s["clock"] = {static_cast<double>(I.step),
                  I.dt0,
                  I.e_ref,
                  I.t_base,
                  I.p.dt,
                  I.report.bound_start,
                  I.e_in,
                  static_cast<double>(I.report.dt_changes),
                  static_cast<double>(I.step_base),
                  unaccounted,
                  static_cast<double>(I.report.growth_longest)};
    s["shape"] = {static_cast<double>(I.map.n_elem), static_cast<double>(I.m.nd), static_cast<double>(I.p.method),
                  static_cast<double>(I.map.n_iface)};
    return s;
  });
}

const std::vector<std::string>& Simulation::state_array_names() {
  static const std::vector<std::string> names{"u", "v", "a", "acc", "dacc", "clock", "shape"};
  return names;
}

void Simulation::restore_state(const StateArrays& a) {
  return on([&](auto& I) -> void {
    for (const auto& k : state_array_names())
      if (!a.count(k)) throw std::runtime_error("dyn::restore_state: array '" + k + "' missing");
    const auto& shape = a.at("shape");
    if (shape.size() != 4 || shape[0] != I.map.n_elem || shape[1] != I.m.nd ||
        shape[2] != static_cast<double>(I.p.method) || shape[3] != I.map.n_iface)
      throw std::runtime_error(
          "dyn::restore_state: saved state is for another model (elements, dof, method or interfaces differ)");
    const auto& clock = a.at("clock");
    if (clock.size() != 3 && clock.size() != 10 && clock.size() != 11)
      throw std::runtime_error("dyn::restore_state: 'clock' needs 3 or 10 (older nacre) or 11 values");
    if (clock[1] != I.dt0) {
      char b[160];
      std::snprintf(b, sizeof b, "dyn::restore_state: saved with dt = %.9g s, this run has dt = %.9g s", clock[1], I.dt0);
      throw std::runtime_error(b);
    }
    const auto& M = I.map;
    const auto ne = static_cast<std::size_t>(M.n_elem);
    scatter_rows(I.comm, I.u, a.at("u"), M.elem_global, ne, "u");
    scatter_rows(I.comm, I.v, a.at("v"), M.elem_global, ne, "v");
    scatter_rows(I.comm, I.a, a.at("a"), M.elem_global, ne, "a");
    scatter_rows(I.comm, I.acc, a.at("acc"), M.elem_global, ne, "acc");
    scatter_rows(I.comm, I.dacc, a.at("dacc"), M.driven_global, std::max<std::size_t>(M.n_driven, 1), "dacc");
    if (I.m.irreversible) {
      if (!a.count("history"))
        throw std::runtime_error(
            "dyn::restore_state: this run keeps a damage history (damage = \"irreversible\"), the "
            "saved state has none");
      const std::vector<int> rows(M.iface_global.begin(), M.iface_global.begin() + I.m.n_mortar);
      scatter_rows(I.comm, I.m.hist, a.at("history"), rows, static_cast<std::size_t>(M.n_mortar), "history");
    } else if (a.count("history")) {
      throw std::runtime_error(
          "dyn::restore_state: the saved state has a damage history, this run's law is reversible");
    }
    I.step = static_cast<long>(clock[0]);
    const bool v8 = clock.size() >= 10;  // nacre >= the stability monitor: time base, dt, bound, E_in
    if (v8 && clock[4] != I.p.dt) I.change_dt(clock[4]);
    I.t_base = v8 ? clock[3] : 0.0;
    I.step_base = v8 ? static_cast<long>(clock[8]) : 0;
    if (v8) I.report.bound_start = clock[5], I.report.dt_changes = static_cast<long>(clock[7]);
    if (clock.size() == 11)
      I.report.growth_longest = static_cast<int>(clock[10]);  // (a restart's summary: the whole run's)
    const double e_in_saved = v8 ? clock[6] : 0.0;
    // E_ref: the saved reference, unless the state was set by hand (e.g. initial velocities):
    // then the mechanical energy not accounted for by work and dissipation becomes the reference,
    // and E_in, which the balance counts as energy put in.
    I.e_in = e_in_saved;
    const Energies e = I.energies();
    const double emech = e.strain + e.kinetic + e.cohesive, w = e.external_work;
    const double unaccounted = I.unaccounted(e);
    I.e_ref = clock[2];
    // a state saved by save_state has the same unaccounted energy as at its save (older
    // checkpoints: none beyond 1e-3 of the energies); anything else was set by hand
    const double expected = v8 ? clock[9] : 0.0;
    if (std::abs(unaccounted - expected) > 1e-3 * std::max({emech, std::abs(w), kTinyEnergy})) {
      I.e_ref = std::max(std::abs(clock[2]), std::abs(unaccounted));
      I.e_in = e_in_saved + unaccounted - expected;
    }
    I.why.clear();
  });
}

std::size_t Simulation::bytes() const {
  return on([&](auto& I) -> std::size_t {
    std::size_t b = model_bytes(I.m);
    for (const auto* d : {&I.u, &I.v, &I.a, &I.u0, &I.v0, &I.a0}) b += d->span() * sizeof(double);
    b += (I.m.hist.span() + I.hist0.span()) * sizeof(double);
    b += (I.acc.span() + I.acc0.span() + I.dacc.span() + I.dacc0.span() + I.iforce.span()) * sizeof(double);
    if (I.is_bie()) b += bie_bytes(I.bie) + (I.pn.span() + I.vn.span() + I.R.span()) * sizeof(double);
    return b;
  });
}
std::size_t Simulation::step_bytes() const {
  return on([&](auto& I) -> std::size_t {
    std::size_t st = (I.u.span() + I.v.span() + I.a.span() + I.acc.span() + I.dacc.span()) * sizeof(double);
    std::size_t b = model_bytes(I.m) + 2 * st;
    if (I.is_bie()) b += I.bie.Jinv.span() * sizeof(double);  // the shared J^-1 (a few KB)
    return b;
  });
}
double Simulation::step_flops() const {
  return on([&](auto& I) -> double {
    const auto& m = I.m;
    const double nd = m.nd, mat = 2.0 * nd * nd;  // one dense nd x nd product
    const bool damped_k = m.beta != 0.0, has_fp = m.fp.extent(0) > 0;
    double per_elem = 0, forces = 1;  // per element; interface force passes per step
    if (I.is_bie()) {
      // bie.hpp's lane code, term by term; M^-1 and alpha M are per type and row, hoisted out of the
      // lanes (not counted, as constants); the per-element GPU kernels recompute a few sums (v+,
      // dp, v_mid: a few nd more)
      const bool fused = I.bie_fused(), vfirst = fused && I.p.bie_block_structure && I.bie.vfirst;
      const bool block = fused && !vfirst && I.p.bie_block_structure && I.bie.block_lower;
      // the J^-1 apply (tile_correction): unfused solves (row, reordered, batched, shared_gemm)
      // and the fused dense form a 2nd x 2nd product; velocity-first g_p -= h/2 g_v, Jv (nd x
      // 2nd), y_p = g_p + h/2 y_v; block-lower 2nd x nd, jr g_v (and g_p -= jq g_v)
      const double apply = vfirst  ? 2.0 * mat + 4.0 * nd
                           : block ? 2.0 * mat + 2.0 * nd + (I.bie.jq != 0.0 ? 2.0 * nd : 0.0)
                                   : 4.0 * mat;
      const double update = 2.0 * nd;                             // p += y_p, v += y_v
      const double load = nd + (has_fp ? nd : 0.0);               // f = F_i + (Theta + F_p)
      const double acc = mat + 6.0 * nd;                          // a = M^-1 (f - K (u + beta v)) - alpha v
      const double beta_books = damped_k ? mat + 2.0 * nd : 0.0;  // beta dp . K v_mid
      const double fp_books = has_fp ? nd : 0.0;                  // the work's Theta + F_p
      if (I.p.bie_scheme == BieScheme::split) {
        per_elem += mat + nd * (4.0 + 7.0);  // v+ = v + h/2 phi, w = p + beta v+; K w; -M^-1 K w - alpha v+, G
        per_elem += apply + update;
        per_elem += nd * (5.0 + 7.0) + fp_books + beta_books + 2.0;  // books (no residual): work, damping, |dv|^2
        per_elem += nd * (1.0 + 3.0) + fp_books;                     // kick: M^-1 (F + Theta + F_p), v
      } else {  // eq. 4.6's iterations (bie_step, BieIterateScheme)
        const int iters = I.p.bie_iterations;
        const bool reuse = I.p.bie_reuse_force && iters >= 2;
        // C = 0 in the block form: the last pass on the kept force is the reduced one at any
        // iteration count (BieIterFinalLinearTileTag), the start positions-only with two
        // (BieStartTileTag<Jinv, true>): bie_step's reduced_end
        const bool reduced_end = block && I.bie.jq == 0.0 && reuse, reduced_start = reduced_end && iters == 2;
        const double residual = mat + 16.0 * nd;                               // dp, dv, K (dp + beta dv), G_p, G_v
        const double books = nd * (5.0 + 13.0) + fp_books + beta_books + 2.0;  // + the |G_v|^2 book
        per_elem += 4.0 * nd + (reduced_start ? mat + nd : apply + update);    // G at x_n; the first apply
        for (int k = 1; k < iters; ++k) {
          if (reuse && k == iters - 1) break;
          per_elem += load + acc + residual + apply + update;
        }
        if (reuse)  // the last iteration on the kept force, then a_{n+1} and the books
          per_elem += reduced_end ? load + acc + 3.0 * nd + books
                                  : load + acc + residual + apply + update + (fused ? acc : load + acc) + books;
        else
          per_elem += load + acc + books;
        forces = reuse ? iters - 1 : iters;
      }
    } else {
      per_elem += 4.0 * nd;                                               // initial: u += h v + h^2/2 a
      per_elem += nd * (1.0 + (has_fp ? 1.0 : 0.0) + 2.0 + 3.0);          // f, w = v + h/2 a, the work
      per_elem += mat + (damped_k ? mat : 0.0) + nd * 6.0;                // r = f - K u - alpha M w - beta K w
      per_elem += (m.ainv_diagonal ? nd : mat) + nd * (3.0 + 2.0 + 3.0);  // a = A^-1 r; v, mid v, damping power
      per_elem += (damped_k ? mat + 3.0 * nd : 0.0) + 4.0;                // beta v K v; the books
    }
    // an interface: the jump at both ends (4 components of 2 shape-weighted differences), the end
    // forces, their split onto the 8 edge dofs ((1 - x) F0 + (1 - x') F1) and the gather (8 adds)
    const cohesive::Law& law = m.laws.law[0];
    const double e = 0.5 * law.x1;  // an elastic gap (below x1), opening
    const cohesive::BasicGap<flops::Counted> g{0.6 * e, 0.8 * e, 0.5 * e, 0.7 * e, 0.0, 1.0};
    const double ends = flops::count([&] { (void)cohesive::integrate(cohesive::TractionTag{}, law, g, 1.0); }).flops();
    const double per_iface = 4.0 * 9.0 + ends + 8.0 * 5.0 + 8.0;
    return per_elem * static_cast<double>(m.n_elem) + forces * per_iface * static_cast<double>(m.n_iface);
  });
}
double Simulation::jacobian_condition() const {
  return on([&](auto& I) -> double { return I.is_bie() ? I.bie.max_condition : 0.0; });
}
double Simulation::bie_residual() const {
  return on([&](auto& I) -> double {
    using Mem = typename std::decay_t<decltype(I)>::Mem;
    if (!I.is_bie() || I.step == 0) return 0.0;
    return I.backend.template visit_in<Mem>([&](const auto& space) {
      return bie_last_residual(space, I.ws, I.acc, I.m.drive, I.m.n_elem, I.m.elem_owned, I.reduce(I.own_elem));
    });
  });
}
int Simulation::element_types() const {
  return on([&](auto& I) -> int { return I.m.n_types; });
}
int Simulation::sliver_elements() const {
  return on([&](auto& I) -> int { return I.m.sliver_elements; });
}
double Simulation::sliver_mass_added() const {
  return on([&](auto& I) -> double { return I.m.sliver_mass_added; });
}
double Simulation::sliver_step_gain() const {
  return on([&](auto& I) -> double { return I.m.sliver_step_gain; });
}
std::size_t Simulation::bricks() const {
  return on([&](auto& I) -> std::size_t { return I.n_bricks; });
}
long long Simulation::halo_bytes() const {
  return on([&](auto& I) -> long long { return I.comm.sum(I.halo ? I.halo->bytes() : 0LL); });
}
long long Simulation::halo_exchanges() const {
  return on([&](auto& I) -> long long { return I.halo ? I.halo->exchanges() : 0; });
}

double critical_step(const Backend& space, const Params& p, const geometry::Specimen& s, const geometry::Interfaces& f,
                     const deck::Mortar& mortar, long steps, double rtol) {
  Kokkos::Profiling::ScopedRegion region("nacre::dyn::critical_step");
  auto stable = [&](double dt) {
    Params q = p;
    q.dt = dt;
    // a trial is stable when finite, below the kinetic bound and (balance_tolerance > 0) with
    // closed books; the growth and step-bound checks watch a run, not a trial
    q.growth_factor = 0, q.step_check = false, q.dt_mode = DtMode::fixed;
    Simulation sim(space, q, s, f, mortar);
    return sim.advance(steps);
  };
  double h = p.dt;
  if (!(h > 0)) {
    Params q = p;
    q.dt = 1.0;
    HostMap map;
    h = build_model(q, s, f, mortar, map).step_estimate;
  }
  double lo = 0, hi = 0;
  if (stable(h)) {
    lo = h;
    for (int k = 0; k < 60 && hi == 0; ++k) {
      const double t = lo * 2;
      if (stable(t)) lo = t;
      else hi = t;
    }
  } else {
    hi = h;
    for (int k = 0; k < 60 && lo == 0; ++k) {
      const double t = hi / 2;
      if (stable(t)) lo = t;
      else hi = t;
    }
  }
  if (lo == 0 || hi == 0) throw std::runtime_error("dyn::critical_step: no stable/unstable bracket found");
  while (hi - lo > rtol * lo) {
    const double mid = 0.5 * (lo + hi);
    if (stable(mid)) lo = mid;
    else hi = mid;
  }
  return lo;
}

void table_4_2_damping(std::size_t bricks, double stiffness_ratio, double& alpha_d, double& beta_d) {
  // Table 4.2 (MODEL.md §5): alpha_d in 1/Ms read as 1e6 / s, beta_d in microseconds.
  static constexpr double counts[4] = {10206, 50400, 101150, 201600};
  static constexpr double ratios[5] = {1, 10, 50, 100, 500};
  static constexpr double tab[4][5][2] = {
      {{0.07492, 0.8342}, {0.1010, 0.6187}, {0.1049, 0.5958}, {0.1054, 0.5928}, {0.1058, 0.5905}},
      {{0.03388, 1.8445}, {0.04569, 1.3679}, {0.04745, 1.3172}, {0.04768, 1.3108}, {0.04787, 1.3056}},
      {{0.02395, 2.6098}, {0.03229, 1.9355}, {0.03353, 1.8638}, {0.03370, 1.8546}, {0.03383, 1.8473}},
      {{0.01698, 3.6813}, {0.02289, 2.7302}, {0.02377, 2.6290}, {0.02389, 2.6161}, {0.02399, 2.6057}}};
  auto nearest = [](const double* xs, int n, double x) {  // nearest on a log scale
    int best = 0;
    const double lx = std::log(std::max(x, 1e-300));
    for (int i = 1; i < n; ++i)
      if (std::abs(std::log(xs[i]) - lx) < std::abs(std::log(xs[best]) - lx)) best = i;
    return best;
  };
  const int i = nearest(counts, 4, static_cast<double>(bricks)), j = nearest(ratios, 5, stiffness_ratio);
  alpha_d = tab[i][j][0] * 1e6;
  beta_d = tab[i][j][1] * 1e-6;
}

}  // namespace nacre::dyn
