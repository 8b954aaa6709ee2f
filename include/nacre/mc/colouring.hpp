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
struct Colouring {
  std::string name;
  std::vector<int> colour;  ///< per brick, -1 for bricks that are not swept
  int n_colours = 0;
};

/// \brief Candidate strategies, all greedy first-fit over different visiting orders, except
/// "balanced" which picks, among the allowed colours, the least used so far.
/// natural: wall order (rows), keeps neighbours close in memory;
/// largest-first: decreasing degree (Welsh-Powell), usually fewest colours;
/// random: a seeded random order; balanced: near-equal colour sizes (even parallel work).
[[nodiscard]] Colouring colour_graph(const std::string& strategy, const geometry::Adjacency& adj,
                                     const std::vector<bool>& free, std::uint64_t seed);

/// \brief The strategies colour_graph knows, in the order the pre-simulation tries them.
[[nodiscard]] const std::vector<std::string>& colouring_strategies();

/// \brief Empty string when valid, else a description of the first violation (two neighbours
/// with one colour, a free brick without colour, a colour out of range).
[[nodiscard]] std::string validate_colouring(const Colouring& c, const geometry::Adjacency& adj,
                                             const std::vector<bool>& free);

}  // namespace nacre::mc
