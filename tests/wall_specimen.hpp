// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A notched running-bond wall and its brick graph, shared by the colouring tests (nacre's own
// strategies and Kokkos Kernels' distance-1 colouring run on the same specimens) and the Monte
// Carlo tests (the 21 x 8 notched specimen that cracks by D ~ 0.02).
#include <nacre/deck/deck.hpp>
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

/// The specimen of a deck's geometry with its interfaces, brick graph and free flags.
inline Wall wall_of(const deck::Geometry& g) {
  Wall w;
  w.s = geometry::build_specimen(g);
  w.f = geometry::find_interfaces(w.s, g);
  w.adj = geometry::build_adjacency(w.s.size(), w.f);
  for (auto d : w.s.drive) w.free.push_back(d == geometry::Drive::free);
  return w;
}

/// A width x height wall at the given bond angle, notched from the left over notch_length at
/// mid-height.
inline Wall wall(double width, double height, double angle, double notch_length) {
  deck::Geometry g;
  g.width = width, g.height = height, g.angle_deg = angle, g.notch_length = notch_length;
  g.notch_y = std::floor(height / 2);
  return wall_of(g);
}

/// The Monte Carlo tests' notched specimen (21 x 8 bricks of 3.5 x 1, notch 8 at mid-height) and
/// its brittle mortar (bed x1 0.002, x2 0.004; head 0.001, 0.002): it cracks by D ~ 0.02.
inline void notched_21x8(deck::Deck& d) {
  d.geometry.width = 21, d.geometry.height = 8, d.geometry.notch_length = 8, d.geometry.notch_y = 4;
  d.geometry.brick_width = 3.5, d.geometry.brick_height = 1.0;
  d.mortar.bed = {100.0, 0.002, 0.004};
  d.mortar.head = {100.0, 0.001, 0.002};
}

/// The cracking load path of the Monte Carlo tests on that specimen: adaptive increments 0.004
/// (0.002 to 0.006) with the predictor to D = 0.02, a cold chain (T 1e-7) whose trial steps
/// adapt between 1e-7 and 1e-3.
inline void cracking_path(deck::Deck& d) {
  d.load.final_displacement = 0.02;
  d.load.initial_step = 0.004, d.load.min_step = 0.002, d.load.max_step = 0.006;
  d.load.adaptive = true, d.load.predictor = deck::Load::Predictor::automatic;
  d.solver.temperature = 1e-7;
  d.solver.step = 1e-4, d.solver.min_step = 1e-7, d.solver.max_step = 1e-3;
  d.solver.rot_step = 1e-4, d.solver.min_rot_step = 1e-7, d.solver.max_rot_step = 1e-3;
}

/// Short windows (a load step converges in hundreds of cycles, not tens of thousands).
inline void short_windows(deck::Deck& d) {
  d.solver.adapt_interval = 20;
  d.solver.window_size = 60, d.solver.convergence_rep = 20;
  d.solver.window_mul = 10, d.solver.window_upper_mul = 40;
}

/// A deck with its specimen and interfaces.
struct Setup {
  deck::Deck d;
  geometry::Specimen s;
  geometry::Interfaces f;
};
inline Setup make_setup(deck::Deck d) {
  Setup st{d, geometry::build_specimen(d.geometry), {}};
  st.f = geometry::find_interfaces(st.s, d.geometry);
  return st;
}

/// A default deck on that specimen, loaded in tension + bending (opening D/2 (1 + 0.5 (1 - x/w))).
inline deck::Deck notched_21x8_deck() {
  deck::Deck d;
  notched_21x8(d);
  d.load.tension = 1.0, d.load.bending = 0.5;
  return d;
}

}  // namespace nacre::test
