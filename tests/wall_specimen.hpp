#pragma once
// A notched running-bond wall and its brick graph, shared by the colouring tests (nacre's own
// strategies and Kokkos Kernels' distance-1 colouring run on the same specimens).
#include <nacre/geometry/specimen.hpp>

#include <cmath>
#include <vector>

namespace nacre::test {

struct Wall {
  geometry::Specimen s;
  geometry::Interfaces f;
  geometry::Adjacency adj;
  std::vector<bool> free;
};

/// A width x height wall at the given bond angle, notched from the left over notch_length at
/// mid-height.
inline Wall wall(double width, double height, double angle, double notch_length) {
  deck::Geometry g;
  g.width = width, g.height = height, g.angle_deg = angle, g.notch_length = notch_length;
  g.notch_y = std::floor(height / 2);
  Wall w;
  w.s = geometry::build_specimen(g);
  w.f = geometry::find_interfaces(w.s, g);
  w.adj = geometry::build_adjacency(w.s.size(), w.f);
  for (auto d : w.s.drive) w.free.push_back(d == geometry::Drive::free);
  return w;
}

}  // namespace nacre::test
