// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Deformable bricks in time (Chapter 4, MODEL.md §5): the public face of the dynamics
/// solver family. The driver (src/app), the outputs and the benchmarks see only this header; the
/// element library, the interface assembly and the integrators live behind it in src/dyn.
///
/// CONTRACT between the dynamics core (src/dyn, include/nacre/dyn) and its users (app, io, perf):
/// names and meanings below are fixed; the core may add members, never change these silently.
#include <nacre/core/backend.hpp>
#include <nacre/dyn/params.hpp>
#include <nacre/geometry/specimen.hpp>
#include <nacre/par/comm.hpp>

#include <Kokkos_Core.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace nacre::dyn {

/// \brief Everything that fixes a dynamic run, in one consistent unit system: N, mm, t (tonne), s.
/// Geometry and the bed/head laws come from the deck's [geometry] and [mortar] sections (mm, N/mm^3).
struct Params {
  Method method = Method::be;
  double youngs_modulus = 214.99 * 500;  ///< E, N/mm^2 (MODEL.md §5: 214.99 r for stiffness ratio r)
  double poisson = 0.35;                 ///< nu (plane stress)
  double density = 3.7e-9;               ///< rho, t/mm^3
  double thickness = 1.0;                ///< out-of-plane depth, mm
  double internal_stiffness_factor = 50; ///< UE internal joints: k_int = factor * E / brick_height
  double alpha_d = 0, beta_d = 0;        ///< Rayleigh damping C = alpha_d M + beta_d K (1/s, s)
  double dt = 0;                         ///< time step, s (> 0 when the Simulation is built)
  double rate = 0;                       ///< opening rate dD/dt once ramped up, mm/s
  double ramp_time = 0;                  ///< s over which the rate ramps from 0 (0: none)
  Ramp ramp = Ramp::linear;
  double final_displacement = 0;         ///< D at which the opening stops growing (held after), mm (0: no limit)
  /// Load programme: D travels through these targets in order at `rate` and is held at the last
  /// (empty: from 0 to final_displacement); at most loading::kMaxTargets.
  std::vector<double> programme;
  double tension = 0, bending = 1;       ///< load pattern weights, as in the rigid deck's [load]
  double thermal_strain = 0;             ///< uniform thermal load Theta (isotropic eigenstrain)
  double force_top = 0;                  ///< prescribed vertical force per unit length on the top edge, N/mm (0: none);
                                         ///< when non-zero the top bricks are force-loaded, not displacement-driven
  bool share_element_matrices = true;    ///< one matrix set per element type (false: per element)
  ElementApply element_apply = ElementApply::automatic;  ///< per-element terms: per element or tiled (same bits)
  BieSolve bie_solve = BieSolve::shared_gemm;  ///< BIE: implementation of the J^-1 apply
  int bie_block = 4;                     ///< BIE reordered matvec: rows per block NB (2, 4, 5, 10)
  int bie_iterations = 2;                ///< BIE: Newton iterations per step with the constant J (eq. 4.6: 2)
  BieScheme bie_scheme = BieScheme::iterate;  ///< BIE: eq. 4.6's iterations or the split step (bie_iterations unused)
  /// BIE: true = the interface force of the last iterate's predecessor is kept for a_{n+1} (one
  /// interface evaluation per iteration but none after the last: exact when C = 0, where the last
  /// iteration does not move p; O(h^3) otherwise); false = re-evaluated at x_{n+1}.
  bool bie_reuse_force = true;
  /// BIE, tiled J^-1 apply, by damping: C = 0 skips the exact zero block and identity of J^-1
  /// (the same bits); C = alpha M multiplies the first nd columns after scaling g; beta != 0 the
  /// velocity-first apply (one nd x 2nd matrix). Each halves the multiply-adds and equals the
  /// dense product to rounding; false = the dense product (benchmarks and tests compare them).
  bool bie_block_structure = true;
  /// Interfaces numbered in element order (true, src/dyn/model.cpp) or in the geometry's order
  /// (false: the comparison in tests/dyn); outputs are in the geometry's order either way.
  bool iface_element_order = true;
  int quadrature_points = 4;             ///< Gauss-Legendre points along each interface segment (1..8)

  // ---- stability monitor (checked after every step chunk; 0 / false: off, the library default;
  // the app turns every one on with the deck's values, docs/dynamics.md "Stability monitor")
  /// stop at the first check where |energy balance residual| exceeds this (0: not checked)
  double balance_tolerance = 0;
  /// stop when one element's share of the strain + kinetic energy grew by more than this factor
  /// per check in growth_checks consecutive checks (0: not checked)
  double growth_factor = 0;
  int growth_checks = 5;
  /// watch the tangent step bound (StepBound, monitor.hpp) at every check: fixed mode stops when
  /// the estimated critical step falls below dt, adaptive mode follows it
  bool step_check = false;
  DtMode dt_mode = DtMode::fixed;
  /// element types whose step bound is below this fraction of the median free element's get a
  /// selective mass scaling up to it (build_model, docs/dynamics.md "Slivers"; 0: none)
  double sliver_step_ratio = 0;
};

/// \brief Steps per check chunk of Simulation::advance (docs/dynamics.md "Stability monitor").
inline constexpr int kCheckEvery = 32;
/// \brief Whether the energy balance is checked at step n: from the first chunk's end on (the
/// first steps of a start carry an O((h omega)^2) error of the books relative to the little energy
/// put in yet, which is no instability).
constexpr bool balance_checked(long n) { return n >= kCheckEvery; }

/// \brief What the step monitor saw at the last check.
struct StepReport {
  double dt = 0;             ///< step in use
  double bound = 0;          ///< 2 / sqrt(StepBound of M^-1 K_t) now, s (the explicit part: BIE interfaces only)
  double bound_start = 0;    ///< the same at the start of the run
  double estimate = 0;       ///< estimated critical step now (= bound: the step the run compares dt with)
  int element = -1, brick = -1;  ///< where the bound is attained
  int iface = -1;            ///< bed/head interface (geometry index) adding most there (-1: an internal joint or none)
  double penetration = 0;    ///< its largest -dn / x1
  long dt_changes = 0;       ///< adaptive mode: how often the step was changed
  int growth_longest = 0;    ///< longest run of checks in which one element's energy share grew > growth_factor
};

/// \brief Energy bookkeeping at the current time (all in N*mm). The balance residual is
/// external_work - (strain + kinetic + cohesive + damping_dissipated), relative to max(|terms|).
struct Energies {
  double strain = 0, kinetic = 0, cohesive = 0, damping_dissipated = 0, external_work = 0;
  double balance_residual = 0;
};

/// \brief Host copy of everything an output needs (solver-neutral names are given by the writer).
/// Triangles are always reported (BE maps its bricks back onto their triangles).
struct Snapshot {
  double time = 0, displacement = 0;
  std::vector<double> node_x, node_y;        ///< reference positions of the output nodes
  std::vector<double> ux, uy, vx, vy;        ///< displacement and velocity per output node
  std::vector<int> tri;                      ///< 3 output-node indices per triangle
  std::vector<int> tri_brick;                ///< brick of each triangle
  std::vector<double> tri_sxx, tri_syy, tri_sxy;  ///< Cauchy stress per triangle, N/mm^2
  std::vector<double> brick_syy;             ///< area-weighted vertical stress per brick (Fig. 4.5)
  std::vector<double> iface_damage;          ///< per bed/head interface: 0 intact .. 1 ruptured (max over its quadrature points)
  std::vector<int> iface_state;              ///< 0 elastic, 1 softening/plastic, 2 ruptured
};

/// \brief Named arrays that restore a run bit for bit (the checkpoint writer stores them as-is).
using StateArrays = std::map<std::string, std::vector<double>>;

/// \brief The dynamic solver (pimpl: Kokkos views and the element tables stay in src/dyn).
class Simulation {
public:
  /// \brief Builds the model and the state at t = 0 on `space` (the instance every later call of
  /// this run uses unless advance names another). Spread over the ranks of `comm` (more than one:
  /// MPI) each rank holds its part (par::Decomposition: its bricks and a one-brick halo, halo.hpp)
  /// and every member below is collective: every rank calls it, in the same order. Results are the
  /// one-process bits on every rank; the whole-specimen arrays (snapshot, interface_damage,
  /// save_state) land on rank 0, the other ranks get them empty. restore_state takes the whole
  /// arrays on every rank, so a state saved on N ranks restores on M.
  Simulation(const Backend& backend, const Params& p, const geometry::Specimen& s, const geometry::Interfaces& f,
             const deck::Mortar& mortar, const par::Comm& comm = par::Comm{});
  /// \brief As above on `space` (an instance of the default execution space).
  Simulation(const Kokkos::DefaultExecutionSpace& space, const Params& p, const geometry::Specimen& s,
             const geometry::Interfaces& f, const deck::Mortar& mortar)
      : Simulation(Backend(space), p, s, f, mortar) {}
  /// \brief As above on a default-constructed instance (tests, benchmarks).
  Simulation(const Params& p, const geometry::Specimen& s, const geometry::Interfaces& f, const deck::Mortar& mortar)
      : Simulation(Kokkos::DefaultExecutionSpace{}, p, s, f, mortar) {}
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  /// \brief Advance n steps on the run's backend. Returns false (state left at the last finite
  /// step) if a non-finite value or a blow-up (see is_unstable) appeared; `why()` then names step,
  /// time, quantity.
  bool advance(long n);
  /// \brief As above, on `space` from now on (an instance of the default execution space).
  bool advance(const Kokkos::DefaultExecutionSpace& space, long n);
  [[nodiscard]] const std::string& why() const;

  [[nodiscard]] double time() const;
  [[nodiscard]] long steps() const;
  [[nodiscard]] double displacement() const;  ///< applied opening D(t)
  [[nodiscard]] Energies energies() const;
  [[nodiscard]] double reaction() const;       ///< vertical force on the top driven edge, N
  [[nodiscard]] int ruptured() const;          ///< bed/head interfaces ruptured
  /// \brief Largest interpenetration of the bed/head joints, max over quadrature points of -dn / x1
  /// (0: none); the penalty then stiffens a joint to k (1 + 1.875 (dn / x1)^4).
  [[nodiscard]] double max_penetration() const;
  [[nodiscard]] Snapshot snapshot() const;
  /// \brief Per bed/head interface, in the geometry's order: damage (0 intact .. 1 ruptured) and
  /// state (0 elastic, 1 softening, 2 ruptured), as in Snapshot; for the crack reading of each row
  /// without the snapshot's triangles. `energy` (optional): each joint's energy of fracture, N mm:
  /// what it dissipated with damage = "irreversible", its cohesive energy otherwise.
  void interface_damage(std::vector<double>& damage, std::vector<int>& state,
                        std::vector<double>* energy = nullptr) const;
  /// \brief The step monitor's last reading (refreshed by every check; step_check() reads now).
  [[nodiscard]] const StepReport& step_report() const;
  /// \brief Evaluate the tangent step bound at the current state (as a check does) and return it.
  StepReport step_check();
  /// \brief Current step (the adaptive mode changes it between chunks).
  [[nodiscard]] double dt() const;
  /// \brief Set the step before the first step (the app: dt_fraction x the estimated critical
  /// step read with step_check()); the run's start dt becomes h.
  void set_initial_dt(double h);

  [[nodiscard]] StateArrays save_state() const;
  /// \brief Names of the arrays save_state() writes and restore_state() needs (a reader can
  /// check a checkpoint for them before building a Simulation).
  [[nodiscard]] static const std::vector<std::string>& state_array_names();
  void restore_state(const StateArrays& a);    ///< throws std::runtime_error on a size/shape mismatch

  /// \brief Bytes of device memory held (model + state), and how many element types were shared.
  [[nodiscard]] std::size_t bytes() const;
  /// \brief Bytes one step must move at least (the memory-bandwidth bound's numerator): every
  /// model array read once (element types, connectivity, gather list, tiles, loads) and the state
  /// u, v, a and the per-element books read and written once. Not counted: what a step need not
  /// move through memory (the interface force rows, BIE's p_n, v_n and residual block: values
  /// a fused kernel could keep in registers) and the roll-back copy (touched once per check
  /// interval, not per step).
  [[nodiscard]] std::size_t step_bytes() const;
  /// \brief Flops of one step (the FMA bound's numerator), velocity Verlet (UE, BE): per element
  /// the dense K u (and K w, K v where beta_d > 0) and (M + h/2 C)^-1 r products, 2 nd^2 each (nd
  /// dofs), and the update's vector work; per interface the jump at the ends, the end forces
  /// (cohesive::integrate run on flops::Counted on the elastic branch, the state of almost every
  /// interface; a softening one costs more), their shape-function split and the gather. Counting
  /// convention: core/flop_count.hpp. BIE: the K applies, the J^-1 applies in the form the run
  /// takes (dense 2nd x 2nd, or the block forms' columns), the vector work and the interface force
  /// passes of the step's scheme (split: one of each; iterated: per iteration, with the kept force
  /// and the reduced last pass where the run takes them).
  [[nodiscard]] double step_flops() const;
  [[nodiscard]] int element_types() const;
  /// \brief Elements whose mass Params::sliver_step_ratio scaled, and the mass they gained
  /// relative to the specimen's.
  [[nodiscard]] int sliver_elements() const;
  [[nodiscard]] double sliver_mass_added() const;
  /// \brief The elements' part of the step bound with the scaling over without it (1: none).
  [[nodiscard]] double sliver_step_gain() const;
  [[nodiscard]] std::size_t bricks() const;
  /// \brief Spread over ranks (0 in one process): the bytes one halo exchange sends, all ranks
  /// together (collective), and the exchanges this run has made (UE, BE: one a step; BIE: one per
  /// interface evaluation and one after a step whose last update follows its last evaluation).
  [[nodiscard]] long long halo_bytes() const;
  [[nodiscard]] long long halo_exchanges() const;

  /// \brief BIE only (0 otherwise): largest 1-norm condition number of the per-type Jacobians
  /// J of eq. 4.7 in dimensionless form D J D^-1, D = diag(I, h I), checked at start-up.
  [[nodiscard]] double jacobian_condition() const;
  /// \brief BIE only (0 otherwise): relative residual of the last step after its last Newton
  /// iteration, sqrt(sum m |G_v|^2 / sum m |v_{n+1} - v_n|^2): what neglecting the interface
  /// Jacobian left unconverged (small when BIE is accurate). Needs bie_reuse_force = false (with the
  /// force kept from the previous iterate the last iteration is exact for it: 0 to rounding).
  [[nodiscard]] double bie_residual() const;

private:
  /// The state lives in the memory space of the backend it was built for (ImplIn<Mem>,
  /// simulation.cpp); on() hands every member its own.
  struct Impl;
  template <class F>
  decltype(auto) on(F&& f) const;
  std::unique_ptr<Impl> impl_;
};

/// \brief Largest stable step of p.method for this specimen: bisection over dt, each trial a
/// fresh Simulation advanced `steps` steps; stable = finite and kinetic energy below a bound from
/// the work done (stated in docs/dynamics.md). Relative tolerance `rtol`. Every trial runs on `space`.
[[nodiscard]] double critical_step(const Backend& space, const Params& p, const geometry::Specimen& s,
                                   const geometry::Interfaces& f, const deck::Mortar& mortar, long steps = 2000,
                                   double rtol = 0.01);
/// \brief As above on a default-constructed instance (tests).
[[nodiscard]] inline double critical_step(const Params& p, const geometry::Specimen& s, const geometry::Interfaces& f,
                                          const deck::Mortar& mortar, long steps = 2000, double rtol = 0.01) {
  return critical_step(Backend{}, p, s, f, mortar, steps, rtol);
}

/// \brief Rayleigh (alpha_d, beta_d) of Table 4.2 (MODEL.md §5 unit reading) for the nearest
/// tabulated brick count and stiffness ratio.
void table_4_2_damping(std::size_t bricks, double stiffness_ratio, double& alpha_d, double& beta_d);

}  // namespace nacre::dyn
