// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief A static 2-D decomposition of a specimen over the ranks of a run, with a one-brick halo.
///
/// Why this shape: bricks never migrate and every coupling is an interface between two bricks,
/// so each rank keeps the bricks it owns plus the bricks that share an interface with one of
/// them (the halo: in running bond the 6-8 neighbours of a brick, corners included) and never
/// needs more. The ranks form a dims[0] x dims[1] Cartesian grid over the specimen (rank =
/// column * dims[1] + row, MPI_Cart_create's numbering without reordering); the grid's cuts are
/// quantiles of the bricks' x and y so blocks hold similar brick counts. A brick is owned by the
/// block holding the centre of its work item (its tile when the colouring sweeps tiles, itself
/// otherwise): a tile is swept in order by one thread, so it must not be split between ranks.
/// An interface is owned by the owner of its brick a (each counted once in a sum over ranks).
///
/// Everything here is computed from the whole specimen on every rank (no communication): the
/// geometry generator is cheap and deterministic. (Generating only a rank's part is what a
/// 40-million-brick run will need; docs/scaling.md.)
#include <nacre/geometry/specimen.hpp>

#include <vector>

namespace nacre::par {

struct Decomposition {
  int rank = 0, size = 1;
  int dims[2] = {1, 1}, coords[2] = {0, 0};
  std::vector<double> xcut, ycut;  ///< block edges: column i holds x in [xcut[i], xcut[i+1]) (outer edges +-inf)
  std::vector<int> owner;          ///< per specimen brick: its owning rank
  std::vector<int> bricks;         ///< local bricks (specimen indices): owned ascending, then halo ascending
  int n_owned = 0;
  std::vector<int> local_of;      ///< per specimen brick: local index, or -1
  std::vector<int> interfaces;    ///< local interfaces (specimen indices, ascending): those with an owned end
  std::vector<char> iface_owned;  ///< per local interface: this rank owns it
  long long owned_interfaces = 0;
  std::vector<int> neighbours;  ///< ranks this one exchanges halo bricks with (ascending)
  /// per neighbour: local indices of the owned bricks it holds in its halo / of this rank's halo
  /// bricks it owns; both in specimen order, so the two sides of a message list the same bricks
  std::vector<std::vector<int>> send, recv;
};

/// \brief The decomposition of specimen s for rank `rank` of `size` (process grid par::process_grid).
/// `item`: per brick its work item (tile) or -1 (its own); empty: every brick its own.
[[nodiscard]] Decomposition decompose(int rank, int size, const geometry::Specimen& s, const geometry::Interfaces& f,
                                      const geometry::Adjacency& adj, const std::vector<int>& item);

/// \brief The local bricks of d as a specimen (same geometry, local order) and the local
/// interfaces with their ends renumbered to local bricks.
[[nodiscard]] geometry::Specimen local_specimen(const Decomposition& d, const geometry::Specimen& s);
[[nodiscard]] geometry::Interfaces local_interfaces(const Decomposition& d, const geometry::Interfaces& f);

}  // namespace nacre::par
