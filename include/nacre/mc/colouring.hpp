// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Distance-1 graph colouring of the free bricks (§2.4): same-colour bricks share no
/// interface, so a colour can be swept in parallel without races.
#include <nacre/geometry/specimen.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace nacre::mc {

/// \brief A colouring of the bricks flagged free; driven bricks get colour -1.
///
/// Colours are swept one after another; inside a colour, work items run in parallel. A work
/// item is a single brick (graph colourings, one thread per brick: what GPUs want) or a tile of
/// bricks swept in wall order by one thread (the "tiles" strategy: a 2 x 2 checkerboard of
/// square tiles, wider than any brick, so same-colour tiles never touch; what CPU caches want).
/// Either way no two neighbours are ever updated at the same time.
struct Colouring {
  std::string name;
  std::vector<int> colour;  ///< per brick, -1 for bricks that are not swept
  std::vector<int> tile;    ///< per brick: its tile, or -1 when each brick is its own work item
  int n_colours = 0;
};

/// \brief Candidate strategies, all greedy first-fit over different visiting orders, except
/// "balanced" which picks, among the allowed colours, the least used so far.
/// natural: wall order (rows), keeps neighbours close in memory;
/// largest-first: decreasing degree (Welsh-Powell), usually fewest colours;
/// random: a seeded random order; balanced: near-equal colour sizes (even parallel work);
/// tiles: checkerboard of tiles of about 256 bricks (see Colouring).
[[nodiscard]] Colouring colour_graph(const std::string& strategy, const geometry::Specimen& s,
                                     const geometry::Adjacency& adj, const std::vector<bool>& free,
                                     std::uint64_t seed);

/// \brief Kokkos Kernels' deterministic distance-1 colouring (strategy "kokkos-d1", vertex-based
/// VBD), run in parallel on the default execution space. Defined only when nacre is built with
/// Kokkos Kernels (NACRE_HAVE_KOKKOSKERNELS); see src/mc/colouring_kk.cpp. deterministic = false
/// selects the library's default algorithm for the backend (faster, but the colouring depends on
/// thread timing: measured in perf/colouring_compare.cpp, never used for a run).
[[nodiscard]] Colouring colour_kokkos_d1(const geometry::Adjacency& adj, const std::vector<bool>& free,
                                         bool deterministic = true);

/// \brief The strategies colour_graph knows, in the order the pre-simulation tries them.
[[nodiscard]] const std::vector<std::string>& colouring_strategies();

/// \brief Empty string when valid, else a description of the first violation (two neighbours
/// with one colour in different work items, a free brick without colour, a colour out of range).
[[nodiscard]] std::string validate_colouring(const Colouring& c, const geometry::Adjacency& adj,
                                             const std::vector<bool>& free);

}  // namespace nacre::mc
