#pragma once
/// \file
/// \brief The file names of a run directory, spelled once: the writer, the drivers (overwrite
/// guard, restart hints), `nacre sweep` and the list of files a new run replaces all use these.
/// The chart scripts (src/io/*.py) write the chart files named here.
#include <array>
#include <string_view>

namespace nacre::io::names {

inline constexpr std::string_view mesh = "mesh.h5";
inline constexpr std::string_view xdmf = "nacre.xdmf";
inline constexpr std::string_view summary = "summary.json";
inline constexpr std::string_view checkpoint = "checkpoint.h5";
inline constexpr std::string_view mc_table = "steps.csv";    ///< Monte Carlo: one row per load step
inline constexpr std::string_view dyn_table = "series.csv";  ///< dynamics: one row per csv_interval steps
/// \brief What the chart scripts write (nacre_plot.py, nacre_dyn_plot.py): charts and the R-curve.
inline constexpr std::array<std::string_view, 4> charts = {"energy_force.png", "crack.png", "r_curve.png",
                                                           "r_curve.csv"};

}  // namespace nacre::io::names
