// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The deck's [dynamics] section (Chapter 4: deformable bricks in time). Its presence
/// selects the dynamic solver instead of Monte Carlo. Units: one consistent system, N, mm, t
/// (tonne), s; the deck's lengths are then mm and the mortar's k is N/mm^3. docs/decks.md lists
/// every key with unit and default; docs/dynamics.md explains methods and outputs.
///
/// The deck knows nothing of the solver but the choices it offers (dyn/params.hpp, enums defined
/// once); src/app maps this struct onto dyn::Params.
#include <nacre/dyn/params.hpp>

#include <cstdint>
#include <string>

namespace nacre::deck {

struct Dynamics {
  /// \brief Integrator: UE unbolted explicit (eq. 4.4), BE bolted explicit (eq. 4.5), BIE bolted
  /// implicit-explicit (eq. 4.6/4.7, docs/methods.md).
  using Method = dyn::Method;
  /// \brief Rayleigh damping source: Table 4.2 preset, none, or alpha_d/beta_d as given.
  enum class Damping : std::uint8_t { table, none, explicit_values };
  /// \brief Time profile of the opening rate over ramp_time.
  using Ramp = dyn::Ramp;

  bool enabled = false;            ///< the deck has a [dynamics] section
  Method method = Method::be;
  double stiffness_ratio = 500;    ///< r: E = 214.99 r N/mm^2 (MODEL.md §5), unless youngs_modulus is given
  double youngs_modulus = 0;       ///< E, N/mm^2; 0: from stiffness_ratio
  double poisson = 0.35;           ///< nu (plane stress)
  double density = 3.7e-9;         ///< rho, t/mm^3
  double thickness = 1.0;          ///< out-of-plane depth, mm
  double internal_stiffness_factor = 50;  ///< UE diagonal joints: k_int = factor * E / brick_height
  Damping damping = Damping::table;
  double alpha_d = 0, beta_d = 0;  ///< 1/s, s (explicit_values only)
  double dt = 0;                   ///< time step, s; 0: dt_fraction of the critical step
  double dt_fraction = 0.5;        ///< fraction of the critical step (when dt is 0)
  double end_time = 0;             ///< s, required
  double rate = 0;                 ///< opening rate dD/dt after the ramp, mm/s
  Ramp ramp = Ramp::linear;
  double ramp_time = 0;            ///< s; 0: full rate from t = 0
  double thermal_strain = 0;       ///< uniform isotropic eigenstrain Theta
  double force_top = 0;            ///< vertical force per unit length on the top edge, N/mm
  bool share_element_matrices = true;  ///< one matrix set per element type (false: per element)
  std::string bie_solve = "shared_gemm";  ///< BIE J^-1 apply: row | reordered | batched | shared_gemm
  int bie_block = 4;               ///< BIE reordered matvec: rows per block (2, 4, 5, 10)
  int bie_iterations = 2;          ///< BIE: iterations with the constant J per step (eq. 4.6: 2)
  /// BIE: "iterate" (eq. 4.6), "split" (docs/methods.md) or "auto": split when damped (C != 0),
  /// iterate otherwise (the same step to rounding there, at the same cost: the dissertation's step kept);
  /// the reader turns "auto" with bie_iterations into "iterate".
  std::string bie_scheme = "auto";
  /// stop at the first check (every 32 steps) where |energy balance residual| exceeds this
  /// (0: not checked; docs/dynamics.md "Stability monitor")
  double balance_tolerance = 1e-3;
  /// "fixed": dt for the whole run, stop when the estimated critical step falls below it;
  /// "adaptive": dt follows the estimated critical step (docs/dynamics.md)
  std::string dt_mode = "fixed";
  /// elements whose step bound is below this fraction of the median element's get a selective
  /// mass scaling up to it (0: none; docs/dynamics.md "Slivers")
  double sliver_step_ratio = 0.5;
  int quadrature_points = 4;       ///< Gauss-Legendre points along each interface segment (1..8)
  long csv_interval = 100;         ///< time-series row every this many steps
  long dump_interval = 10000;      ///< HDF5 dump + checkpoint every this many steps (0: first and last only)

  /// \brief Young's modulus in N/mm^2 and the stiffness ratio it corresponds to.
  [[nodiscard]] double modulus() const { return youngs_modulus > 0 ? youngs_modulus : 214.99 * stiffness_ratio; }
  [[nodiscard]] double ratio() const { return modulus() / 214.99; }
};

}  // namespace nacre::deck
