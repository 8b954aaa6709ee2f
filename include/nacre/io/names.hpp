// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The file names of a run directory, spelled once: the writer, the drivers (overwrite
/// guard, restart hints), `nacre sweep` and the list of files a new run replaces all use these.
/// The chart modules (python/nacre/charts/) write the chart files named here.
#include <array>
#include <string_view>

namespace nacre::io::names {

inline constexpr std::string_view mesh = "mesh.h5";
inline constexpr std::string_view xdmf = "nacre.xdmf";
inline constexpr std::string_view summary = "summary.json";
inline constexpr std::string_view checkpoint = "checkpoint.h5";
inline constexpr std::string_view mc_table = "steps.csv";    ///< Monte Carlo: one row per load step
inline constexpr std::string_view dyn_table = "series.csv";  ///< dynamics: one row per csv_interval steps
inline constexpr std::string_view r_curve = "r_curve.csv";  ///< the R-curve (fracture/r_curve.hpp)
inline constexpr std::string_view deck_copy = "deck.toml";  ///< the deck the run ran, as given
inline constexpr std::string_view log = "log.txt";          ///< the run's log (app/run_log.hpp)
/// \brief Derived files a new run replaces: the charts (python -m nacre.charts.mc / .dyn), the
/// R-curve, the deck's copy and the log.
inline constexpr std::array<std::string_view, 6> charts = {"energy_force.png", "crack.png", "r_curve.png",
                                                           "r_curve.csv", "deck.toml", "log.txt"};

}  // namespace nacre::io::names
