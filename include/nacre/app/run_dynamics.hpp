// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The driver of a dynamic run (deck with a [dynamics] section): deck -> dyn::Params, the run loop
// with outputs, and the --critical-step command. run.cpp only dispatches here.
#include <nacre/deck/deck.hpp>
#include <nacre/dyn/simulation.hpp>

#include <cstddef>
#include <iosfwd>
#include <nacre/par/comm.hpp>

#include <string>

namespace nacre::app {

/// \brief Exit code of a run stopped by an instability (non-finite value or energy blow-up).
inline constexpr int exit_unstable = 3;

/// \brief dyn::Params of a deck's [dynamics] (and [load]) section; the Table 4.2 damping preset
/// needs the specimen's brick count. dt is the deck's dt (0 when the deck gives dt_fraction).
[[nodiscard]] dyn::Params dynamics_params(const deck::Deck& d, std::size_t bricks);

/// \brief A dt_fraction deck's step, as a run takes it: dt_fraction x the estimated critical step of
/// `sim` (built at any positive dt), the smaller of it and the bisected step for the iterated BIE
/// step with stiffness damping (which the estimate does not bound; bisection on `backend`, logged
/// to `log` when not null); the step checked against [limits] (DeckError), set in p.dt and
/// `sim`. Returns the critical step used.
double take_initial_step(dyn::Simulation& sim, dyn::Params& p, const deck::Deck& d, const Backend& backend,
                         const geometry::Specimen& s, const geometry::Interfaces& f, std::ostream* log);

struct DynRunOptions {
  bool quiet = false, tty = false;
  bool extend = false;   ///< with restart: the deck's end_time may differ from the checkpoint's run
  std::string restart;   ///< a checkpoint.h5, or ""
  Backend backend;       ///< where the kernels run (`--backend`; the default space unless asked)
  par::Comm comm;        ///< the ranks the run is spread over (`mpirun -np N`; rank 0 logs and writes)
};

/// \brief Run a dynamic deck (0 done, 3 unstable, 130/143 interrupted).
int run_dynamics(const deck::Deck& d, const DynRunOptions& opt);

/// \brief Print the largest stable step of the deck's method (bisection, dyn::critical_step).
int print_critical_step(const deck::Deck& d, bool quiet, const Backend& backend = {});

}  // namespace nacre::app
