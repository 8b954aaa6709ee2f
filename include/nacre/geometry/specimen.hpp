// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The brick-and-mortar specimen: a running-bond wall, rotated, clipped to the specimen
/// rectangle and cut by the notch. Host-side construction; the solver uploads what it needs.
#include <nacre/deck/deck.hpp>
#include <nacre/geometry/joint_kind.hpp>

#include <cstdint>
#include <vector>

namespace nacre::geometry {

/// \brief Which edge drives a brick (driven bricks follow the prescribed load, never move by MC).
enum class Drive : std::int8_t { bottom = -1, free = 0, top = 1 };

/// \brief Bricks (whole or partial), structure of arrays, in wall order (row by row).
struct Specimen {
  std::vector<double> cx, cy, area;   ///< reference centroid and area
  std::vector<int> poly_offset{0};    ///< CSR into vx/vy: vertices of brick i (CCW, specimen frame)
  std::vector<double> vx, vy;
  std::vector<Drive> drive;
  std::vector<std::int64_t> parent;   ///< wall-grid brick this piece came from (notch splits one in two)
  double full_brick_area = 0;
  double width = 0, height = 0;

  [[nodiscard]] std::size_t size() const { return cx.size(); }
  [[nodiscard]] int vertex_count(std::size_t i) const { return poly_offset[i + 1] - poly_offset[i]; }
};

/// \brief Interfaces (shared edge segments), structure of arrays. Brick a < brick b. The
/// segment is stored in each brick's local frame (relative to its reference centroid), so the
/// energy kernels need no centroid gathers; normal points from a into b.
struct Interfaces {
  std::vector<int> a, b;
  std::vector<JointKind> kind;
  std::vector<double> ra0x, ra0y, ra1x, ra1y;  ///< segment ends relative to a's centroid
  std::vector<double> rb0x, rb0y, rb1x, rb1y;  ///< same points relative to b's centroid
  std::vector<double> nx, ny, length;

  [[nodiscard]] std::size_t size() const { return a.size(); }
};

/// \brief Brick-to-interface adjacency (CSR): interfaces of brick i are iface[offset[i] .. offset[i+1]).
struct Adjacency {
  std::vector<int> offset, iface, neighbour;
};

/// \brief Build the wall, clip it to the specimen and the notch, drop slivers.
[[nodiscard]] Specimen build_specimen(const deck::Geometry& g);

/// \brief Find interfaces with an O(N) cell-list search over matching polygon edges; bonds along
/// the notch (y = notch_y, x < notch_length) are left out. Bricks with no interface are removed
/// from `s` (they would float freely) before the result is returned.
[[nodiscard]] Interfaces find_interfaces(Specimen& s, const deck::Geometry& g);

/// \brief CSR adjacency of bricks through interfaces.
[[nodiscard]] Adjacency build_adjacency(std::size_t n_bricks, const Interfaces& f);

}  // namespace nacre::geometry
