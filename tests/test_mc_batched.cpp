// SPDX-License-Identifier: BSD-3-Clause
// The host sweep's batched trials (mc::BatchedTrials: 8 same-colour work items side by side,
// vectorised) against the per-brick scalar trials (mc::ScalarTrials, the GPU schedule): same
// proposals, same energies, same acceptances, so the same poses and cached energies bit for bit,
// on elastic, penetrating and damaged interfaces, on both schedules (single bricks and tiles),
// with global and per-brick step sizes. This source is compiled with the solver's sweep flags
// (src/mc/mc.cmake: -march=native -ffp-contract=off where NACRE_MC_NATIVE), so the vector code
// tested is the vector code the solver runs.
#include <nacre/mc/kernels.hpp>

#include <catch2/catch_test_macros.hpp>

#include "wall_specimen.hpp"

#include <cstring>
#include <vector>

using namespace nacre;

namespace {

struct Run {
  std::vector<double> pose, cache, de;
  long accepted = 0;
};

template <class Space, class Trials>
Run sweep(Trials trials, const deck::Deck& d, geometry::Specimen& s, const geometry::Interfaces& f,
          const mc::Colouring& c, bool per_brick, int cycles, double opening) {
  const Space space;
  const auto adj = geometry::build_adjacency(s.size(), f);
  auto m = mc::build_model(space, s, f, adj, c, d.mortar, 4);
  // opening 0.004: past x1, plastic interfaces at the driven rows; -0.004: closing, the joints
  // pressed into each other, where the penetration penalty is far from negligible against the
  // elastic energy (so its last bits show in the sums)
  mc::apply_load(space, m, loading::Pattern{d.load.tension, d.load.bending, d.geometry.width}, opening);
  Field<double> cache("nacre::test::cache", m.n_interfaces), de("nacre::test::de", m.n_free);
  mc::BrickSteps<> bs;
  if (per_brick) {
    bs.step = decltype(bs.step)("nacre::test::step", m.n_free);
    bs.accepted = decltype(bs.accepted)("nacre::test::accepted", m.n_free);
    auto h = Kokkos::create_mirror_view(bs.step);
    for (int b = 0; b < m.n_free; ++b) h(b, 0) = 1e-5 * (1 + b % 5), h(b, 1) = 5e-6 * (1 + b % 3);
    Kokkos::deep_copy(space, bs.step, h);
  }
  mc::interface_energies(space, m, cache);
  Run r;
  for (std::uint64_t cyc = 0; cyc < static_cast<std::uint64_t>(cycles); ++cyc)
    for (std::size_t k = 0; k + 1 < m.colour_tiles.size(); ++k)
      r.accepted += mc::sweep_colour(trials, space, m, m.colour_tiles[k], m.colour_tiles[k + 1],
                                     mc::PhiloxUniforms<MemSpace>{m.id, 0x5eedull, cyc}, cache, de, 2e-5, 1e-5, 1e-7, bs);
  space.fence();
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.pose);
  auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cache);
  auto hd = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), de);
  r.pose.assign(hp.data(), hp.data() + hp.size());
  r.cache.assign(hc.data(), hc.data() + hc.size());
  r.de.assign(hd.data(), hd.data() + hd.size());
  // the damaged (non-elastic, scalar fallback) branch must have been exercised
  Field<std::int8_t> state("nacre::test::state", m.n_interfaces);
  mc::interface_state(space, m, Field<double>(), state);
  auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), state);
  int damaged = 0;
  for (int i = 0; i < m.n_interfaces; ++i) damaged += hs(i) > 0;
  CHECK(damaged > 0);
  return r;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

}  // namespace

/// Both paths on one host execution space (a device build has none for the model's memory, and
/// there BatchedTrials is not compiled: the test then only says so).
template <class Space>
void compare_paths() {
  if constexpr (Kokkos::SpaceAccessibility<Space, Kokkos::HostSpace>::accessible) {
    const auto d = test::notched_21x8_deck();
    auto s = geometry::build_specimen(d.geometry);
    const auto f = geometry::find_interfaces(s, d.geometry);
    const auto adj = geometry::build_adjacency(s.size(), f);
    std::vector<bool> free(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) free[i] = s.drive[i] == geometry::Drive::free;
    for (const char* colouring : {"natural", "tiles", "largest-first"}) {
      for (const bool per_brick : {false, true}) {
        for (const double opening : {0.004, -0.004}) {
        CAPTURE(colouring, per_brick, opening);
        const auto c = mc::colour_graph(colouring, s, adj, free, 1);
        const Run a = sweep<Space>(mc::ScalarTrials{}, d, s, f, c, per_brick, 40, opening);
        const Run b = sweep<Space>(mc::BatchedTrials{}, d, s, f, c, per_brick, 40, opening);
        CHECK(a.accepted > 0);
        CHECK(a.accepted < 40L * static_cast<long>(a.de.size()));  // some rejected too
        CHECK(a.accepted == b.accepted);
        CHECK(same_bits(a.pose, b.pose));
        CHECK(same_bits(a.cache, b.cache));
        CHECK(same_bits(a.de, b.de));
        }
      }
    }
  } else {
    SUCCEED("the model lives in device memory: BatchedTrials is a host schedule");
  }
}

TEST_CASE("batched host trials give the scalar trials' poses, energies and acceptances bit for bit",
          "[mc][determinism][batched]") {
  compare_paths<ExecSpace>();
}
