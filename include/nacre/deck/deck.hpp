// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Input deck: every parameter of a run, parsed from TOML and validated up front.
///
/// docs/decks.md documents every key with unit and default. Any error (unknown key, wrong type,
/// missing value, out-of-range or inconsistent value) throws DeckError carrying
/// "file:line: key: what was expected" before any computation starts.
#include <nacre/cohesive/damage.hpp>
#include <nacre/deck/dynamics.hpp>

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace nacre::deck {

/// \brief A deck error; what() is "file:line: key: message".
class DeckError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// \brief Specimen and wall geometry (lengths in the deck's length unit).
struct Geometry {
  double width = 40.0;          ///< specimen size along x
  double height = 40.0;         ///< specimen size along y
  double brick_width = 3.5;     ///< brick length along the wall's rows
  double brick_height = 1.0;    ///< brick height (row spacing)
  double overlap = 0.5;         ///< running-bond stagger as a fraction of brick_width
  double angle_deg = 0.0;       ///< wall orientation relative to the specimen x axis
  double notch_length = 20.0;   ///< notch from the left edge along y = notch_y
  double notch_y = -1.0;        ///< notch height; < 0 means mid-height
  double min_piece_fraction = 0.02;  ///< partial bricks smaller than this (area fraction) are dropped
  int driven_rows = 1;          ///< bricks within this many brick heights of top/bottom are driven
};

/// \brief Mortar: cohesive law per interface kind.
struct Mortar {
  cohesive::Law bed{100.0, 0.01, 0.02};   ///< joints parallel to the rows
  cohesive::Law head{100.0, 0.01, 0.02};  ///< joints between bricks of one row
  /// damage: "reversible" (the law alone), "irreversible" (a history per Gauss point, unloading
  /// along the damaged secant: cohesive/damage.hpp) or "auto" (the default): irreversible exactly
  /// when [load] programme unloads, since monotonic loading never reads a history.
  cohesive::Damage damage = cohesive::Damage::reversible;
  bool damage_auto = true;  ///< damage was "auto" (resolved by the [load] reader)
};

/// \brief Loading: the displacement D of the driven edges, applied in increments.
struct Load {
  double tension = 1.0;     ///< weight of uniform opening (top +D/2, bottom -D/2)
  double bending = 0.0;     ///< weight of linear opening, largest at the notch side
  double final_displacement = 0.2;
  double initial_step = 0.02;  ///< InitialLoadStepSize
  double min_step = 0.02;      ///< MinLoadStepSize
  double max_step = 0.02;      ///< MaxLoadStepSize
  bool adaptive = false;       ///< forward control / backtracking of the increment (eq. 2.8, 2.9)
  /// Position predictor (eq. 2.10): each load step starts from the last converged poses
  /// extrapolated by the last increment's motion. `none`: no predictor; `damped`: eq. 2.11's
  /// (each brick's extrapolation damped by its energy against its joints' energy at x1);
  /// `secant`: every brick extrapolated alike; `automatic`: the secant where Newton relaxes
  /// (relaxation = "newton", "auto") and eq. 2.11's elsewhere.
  /// Deck: predictor = false | true (automatic) | "damped" | "secant".
  enum class Predictor { none, automatic, damped, secant } predictor = Predictor::none;
  /// Snap-back control: a converged increment that ruptured more interfaces than this is undone
  /// and retried at half the increment (down to min_step); 0: off.
  int max_ruptures_per_step = 0;
  /// Displacement targets in order (programme = [0.1, 0.05, 0.2]: load to 0.1, unload to 0.05,
  /// reload to 0.2); empty: from 0 to final_displacement. With a programme, final_displacement is
  /// its last target.
  std::vector<double> programme;

  /// \brief The targets in order: the programme, or final_displacement alone.
  [[nodiscard]] std::vector<double> targets() const {
    return programme.empty() ? std::vector<double>{final_displacement} : programme;
  }
  /// \brief Length of the whole load path, sum of |target_k - target_{k-1}| from 0.
  [[nodiscard]] double path_length() const {
    double s = 0, prev = 0;
    for (double t : targets()) s += t > prev ? t - prev : prev - t, prev = t;
    return s;
  }
  /// \brief Largest |D| on the path.
  [[nodiscard]] double max_displacement() const {
    double r = 0;
    for (double t : targets()) r = t > r ? t : (-t > r ? -t : r);
    return r;
  }
  /// \brief True when the path turns back somewhere (loads, then unloads).
  [[nodiscard]] bool unloads() const {
    double prev = 0, dir = 0;
    for (double t : targets()) {
      const double d = t > prev ? 1.0 : -1.0;
      if (dir != 0 && d != dir) return true;
      dir = d, prev = t;
    }
    return false;
  }
};

/// \brief Monte Carlo solver, the deck's [solver] table (named MonteCarlo so that it does not clash
/// with mc::Solver or a second solver family's parameters).
struct MonteCarlo {
  double temperature = 0.00075;  ///< TEMP
  double step = 0.001;           ///< InitialStepSize
  double min_step = 0.001;       ///< MinStepSize
  double max_step = 0.001;       ///< MaxStepSize
  double rot_step = 0.001;       ///< InitialRotSize
  double min_rot_step = 0.001;   ///< MinRotSize
  double max_rot_step = 0.001;   ///< MaxRotSize
  int adapt_interval = 0;        ///< AdaptInter (0: fixed step sizes)
  bool per_brick_steps = false;  ///< step_mode: adapt one step size per brick instead of one global
  double stol = 0.002;           ///< STOL
  double rtol = 0.03;            ///< RTOL
  bool stol_relative = true;     ///< STOL bounds var/mean^2 (true) or the variance itself
  int window_size = 3500;        ///< WindowSize
  int convergence_rep = 1500;    ///< ConvergenceRep
  double window_mul = 20;        ///< WindowMul: target cycles c_t = WindowMul * ConvergenceRep
  double window_upper_mul = 50000;  ///< WindowUpperMul: c_u = WindowUpperMul * ConvergenceRep
  long max_cycles = 2000000;     ///< hard cap of cycles per load step
  int quadrature_points = 4;     ///< Gauss-Legendre points per interface (1..8)
  std::string colouring = "auto";  ///< auto | natural | largest-first | random | balanced | tiles | kokkos-d1
  std::string rng = "philox";    ///< philox | aes-ctr | mt-aes
  int presim_cycles = 20;        ///< cycles per candidate colouring in the pre-simulation
  /// What ends a load step: "residual" (the largest generalised force on a free brick, relative
  /// to F_s = max(k x1) brick_width, below residual_tolerance) or "window" (the paper's
  /// variance / trend test alone; the residual is still reported).
  std::string convergence = "residual";
  double residual_tolerance = 1e-6;  ///< dimensionless, see convergence
  std::string polish = "fire";       ///< after the Monte Carlo relaxation: fire | newton | trust-region | anneal | none
  int polish_iterations = 20000;     ///< FIRE steps / Newton sweeps / trust-region steps per polish
  int cg_iterations = 500;           ///< CG iterations per trust-region Newton step
  long burst_cycles = 200;           ///< relaxation = "auto": cycles of a Monte Carlo burst
  std::string newton_preconditioner = "auto";  ///< auto | cholesky | block-jacobi (trust-region Newton)
  std::string factor_precision = "single";     ///< single | double: the Cholesky preconditioner's (CHOLMOD)
  /// How a load step is relaxed: "monte-carlo" (Monte Carlo phases, then the polish),
  /// "gradient" (the polish method alone, from the predicted poses: a pure gradient minimiser
  /// with the same load stepping; needs polish = fire, newton or trust-region), "newton"
  /// (trust-region Newton-CG alone) or "auto" (Newton, with Monte Carlo bursts where it stalls
  /// or where joints ruptured).
  std::string relaxation = "monte-carlo";
};

/// \brief Outputs.
struct Output {
  std::string directory = "out";
  int dump_interval = 10;  ///< DumpInter: HDF5 dump every this many load steps (0: final only)
  bool hdf5 = true;
  bool charts = true;
  bool progress = true;
  /// Off a terminal (a batch job's output file, a pipe): a plain log line at most every this
  /// many seconds while a load step or the time stepping runs (0: none; the lines at completed
  /// steps and dumps are written regardless).
  double heartbeat = 60.0;
};

/// \brief Limits of what a deck may ask for, checked from estimates before anything is built
/// (deck/limits.hpp); a deck that needs more must raise them explicitly in [limits].
struct Limits {
  double max_bricks = 5e6;         ///< estimated bricks (wall-grid cells covering the specimen)
  double max_load_steps = 1e6;     ///< final_displacement / smallest increment
  double max_time_steps = 1e9;     ///< dynamics: end_time / dt
  double max_memory_gib = 0;       ///< estimated memory; 0: 80 % of this machine's physical memory
};

/// \brief A whole run.
struct Deck {
  std::string path;  ///< where it was read from
  Geometry geometry;
  Mortar mortar;
  Load load;
  MonteCarlo solver;  ///< [solver] (members are named after their TOML table)
  Output output;
  Dynamics dynamics;  ///< enabled: the run is dynamic (Chapter 4), [solver] does not apply
  Limits limits;
  std::uint64_t seed = 1;
  /// \brief The deck's content that fixes the physics, canonical (one "section.key = value" line
  /// per key, sorted; comments, layout and key order ignored); [output], [limits] and
  /// load.final_displacement left out (a restart may extend a run, see the app's --extend).
  std::string canonical;
  /// \brief The deck's text as read (each run directory keeps a copy: deck.toml).
  std::string text;
  /// \brief Line of every key ("geometry.width") and section ("geometry") in the file.
  std::map<std::string, int> lines;
  /// \brief "file:line: key" for messages about a key (line 0 when unknown).
  [[nodiscard]] std::string where(const std::string& key) const;
};

/// \brief Parse and validate a deck file. Throws DeckError.
[[nodiscard]] Deck parse_deck_file(const std::string& path);
/// \brief Parse and validate deck text; `name` is used in messages.
[[nodiscard]] Deck parse_deck_string(std::string_view text, const std::string& name);

}  // namespace nacre::deck
