// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The floating-point operations of one Monte Carlo trial at the model's current state,
/// counted by running the trial's own code (trial_frame, slot_energy) on flops::Counted.
///
/// Why: `nacre bench` reports a sweep's fraction of the backend's FMA bound; its numerator is
/// the flops a cycle does, which depend on the state (elastic interfaces take a closed form of
/// ~20 flops, softening ones up to 7 pieces with square roots and asinh). Counting on the state
/// the bench runs from keeps the figure true for that deck. Host only: it reads a host copy of
/// the model (once per bench, outside the timed stretch).
#include <nacre/core/flop_count.hpp>
#include <nacre/mc/kernels.hpp>

#include <algorithm>
#include <optional>

namespace nacre::mc {

/// \brief Mean flops per trial over (up to `max_samples`, evenly spaced) free bricks, each
/// trying a move of half the step in every coordinate (the mean size of a uniform move): the
/// trial pose, every adjacent interface's energy, the sums and the energy change, and the
/// Metropolis exponential where the move raises the energy at temperature > 0. Nullopt for a
/// model with a damage history (the irreversible law's energy is not templated on the scalar).
template <class MemorySpace>
std::optional<double> trial_flops(const Model<MemorySpace>& m, double step, double rot_step, double temperature,
                                  int max_samples = 20000) {
  if (m.hist.data() || m.n_free == 0) return std::nullopt;
  using flops::Counted;
  const auto pose = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.pose);
  const auto off = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.adj_offset);
  const auto slot = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.slot);
  const auto link = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.slot_link);
  const auto skind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.slot_kind);
  const int stride = std::max(1, m.n_free / std::max(1, max_samples));
  const double u[4] = {0.75, 0.25, 0.75, 0.5};  // |2u - 1| = 1/2: the mean move of a uniform
  double total = 0;
  long samples = 0;
  for (int b = 0; b < m.n_free; b += stride, ++samples) {
    total += flops::count([&] {
      const kinematics::BasicFrame<Counted> f_new = trial_frame<Counted>(frame_of(pose, b), u, step, rot_step);
      Counted e_old = 0.0, e_new = 0.0;
      for (int j = off(b); j < off(b + 1); ++j) {
        const kinematics::Frame o = frame_of(pose, link(j, 0));
        const kinematics::BasicFrame<Counted> fo{o.x, o.y, o.t, o.s, o.c1};
        e_new += slot_energy(slot, j, m.laws[skind(j)], f_new, fo, m.quad, nullptr);
        e_old += Counted(0.0);  // the cached energy of the interface (a load and an add)
      }
      const Counted d = e_new - e_old;
      if (temperature > 0.0 && d > 0.0) (void)sc::exp(-d * (1.0 / temperature));
    }).flops();
  }
  return total / static_cast<double>(samples);
}

}  // namespace nacre::mc
