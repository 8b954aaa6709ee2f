// SPDX-License-Identifier: BSD-3-Clause
// Kokkos Kernels in nacre: the "kokkos-d1" sweep schedule (KokkosGraph distance-1 colouring) and
// the KokkosBatched dense kernels part 4b will use (batched GEMV, LU solve), each checked
// against a plain loop. Built only when CMake finds Kokkos Kernels.
#include "wall_specimen.hpp"
#include <nacre/mc/colouring.hpp>

#include <KokkosBatched_Gemv_Decl.hpp>
#include <KokkosBatched_LU_Decl.hpp>
#include <KokkosBatched_SolveLU_Decl.hpp>
#include <Kokkos_Core.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include <algorithm>
#include <cmath>

using namespace nacre;

using test::wall;

TEST_CASE("kokkos-d1: no two neighbouring free bricks share a colour, reproducibly", "[mc][colouring][kokkoskernels]") {
  for (double angle : {0.0, 30.0}) {
    const test::Wall w = wall(120, 80, angle, 0.4 * 120);  // ~2700 bricks
    CAPTURE(angle, w.s.size());
    const auto c = mc::colour_graph("kokkos-d1", w.s, w.adj, w.free, 7);
    REQUIRE(c.colour.size() == w.s.size());
    int max_degree = 0, coloured = 0;
    for (std::size_t i = 0; i < w.s.size(); ++i) {
      if (!w.free[i]) {
        CHECK(c.colour[i] == -1);
        continue;
      }
      ++coloured;
      REQUIRE(c.colour[i] >= 0);
      REQUIRE(c.colour[i] < c.n_colours);
      int degree = 0;
      for (int j = w.adj.offset[i]; j < w.adj.offset[i + 1]; ++j) {
        const int n = w.adj.neighbour[j];
        if (!w.free[n]) continue;
        ++degree;
        REQUIRE(c.colour[n] != c.colour[i]);
      }
      max_degree = std::max(max_degree, degree);
    }
    CHECK(coloured == std::count(w.free.begin(), w.free.end(), true));
    CHECK(c.n_colours <= max_degree + 1);  // each brick takes the smallest colour its neighbours left
    CHECK(mc::validate_colouring(c, w.adj, w.free).empty());
    // deterministic variant: the same deck gives the same schedule (reproducible runs)
    const auto again = mc::colour_graph("kokkos-d1", w.s, w.adj, w.free, 99);
    CHECK(again.colour == c.colour);
  }
}

TEST_CASE("KokkosBatched: team GEMV and LU solve of a batch of small matrices match a plain loop", "[kokkoskernels]") {
  using exec = Kokkos::DefaultExecutionSpace;
  constexpr int batch = 64, m = 6, n = 4;
  // batch index first (LayoutRight): each team's matrix is contiguous
  Kokkos::View<double***, Kokkos::LayoutRight> A("nacre::test::A", batch, m, n), L("nacre::test::L", batch, m, m);
  Kokkos::View<double**, Kokkos::LayoutRight> x("nacre::test::x", batch, n), y("nacre::test::y", batch, m),
      b("nacre::test::b", batch, m);
  auto hA = Kokkos::create_mirror(A);  // copies, never aliases: A, L, y, b are overwritten
  auto hL = Kokkos::create_mirror(L);
  auto hx = Kokkos::create_mirror(x);
  auto hy = Kokkos::create_mirror(y);
  auto hb = Kokkos::create_mirror(b);
  for (int k = 0; k < batch; ++k) {
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < n; ++j) hA(k, i, j) = std::sin(1.0 + k + 3.0 * i + 7.0 * j);
      for (int j = 0; j < m; ++j) hL(k, i, j) = (i == j ? 8.0 : 0.0) + std::cos(k + 2.0 * i - j);  // diagonally dominant
      hy(k, i) = 0.5 * i - k;
      hb(k, i) = 1.0 + i * k;
    }
    for (int j = 0; j < n; ++j) hx(k, j) = std::cos(0.3 * j + k);
  }
  Kokkos::deep_copy(A, hA), Kokkos::deep_copy(L, hL), Kokkos::deep_copy(x, hx), Kokkos::deep_copy(y, hy);
  Kokkos::deep_copy(b, hb);
  const double alpha = 1.5, beta = -0.25;
  using member = Kokkos::TeamPolicy<exec>::member_type;
  // batched TeamGemv: each team multiplies a block of `per_team` matrices (rank-3 A, rank-2 x, y)
  constexpr int per_team = 8;
  Kokkos::parallel_for(
      "nacre::test::batched_gemv", Kokkos::TeamPolicy<exec>(batch / per_team, Kokkos::AUTO),
      KOKKOS_LAMBDA(const member& t) {
        const auto r = Kokkos::make_pair(t.league_rank() * per_team, (t.league_rank() + 1) * per_team);
        KokkosBatched::TeamGemv<member, KokkosBatched::Trans::NoTranspose, KokkosBatched::Algo::Gemv::Unblocked>::invoke(
            t, alpha, Kokkos::subview(A, r, Kokkos::ALL, Kokkos::ALL), Kokkos::subview(x, r, Kokkos::ALL), beta,
            Kokkos::subview(y, r, Kokkos::ALL));
      });
  Kokkos::parallel_for(
      "nacre::test::batched_lu", Kokkos::RangePolicy<exec>(0, batch), KOKKOS_LAMBDA(const int k) {
        auto Lk = Kokkos::subview(L, k, Kokkos::ALL, Kokkos::ALL);
        KokkosBatched::SerialLU<KokkosBatched::Algo::LU::Unblocked>::invoke(Lk);
        KokkosBatched::SerialSolveLU<KokkosBatched::Trans::NoTranspose, KokkosBatched::Algo::SolveLU::Unblocked>::invoke(
            Lk, Kokkos::subview(b, k, Kokkos::ALL));
      });
  auto ry = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, y);
  auto rb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, b);
  for (int k = 0; k < batch; ++k)
    for (int i = 0; i < m; ++i) {
      double ref = beta * hy(k, i), res = -(1.0 + i * k);
      for (int j = 0; j < n; ++j) ref += alpha * hA(k, i, j) * hx(k, j);
      for (int j = 0; j < m; ++j) res += hL(k, i, j) * rb(k, j);  // original matrix times solution
      CHECK(ry(k, i) == Catch::Approx(ref).epsilon(1e-13).margin(1e-13));
      CHECK(std::abs(res) <= 1e-12 * (1.0 + i * k));
    }
}
