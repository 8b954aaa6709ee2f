// SPDX-License-Identifier: BSD-3-Clause
// Graph colouring of the free bricks.
#include "wall_specimen.hpp"
#include <nacre/mc/colouring.hpp>

#include <catch2/catch_test_macros.hpp>

using namespace nacre;

using test::wall;

TEST_CASE("every strategy gives a valid distance-1 colouring", "[mc][colouring]") {
  for (double angle : {0.0, 30.0}) {
    const test::Wall w = wall(40, 30, angle, 15);
    for (const auto& name : mc::colouring_strategies()) {
      CAPTURE(angle, name);
      const auto c = mc::colour_graph(name, w.s, w.adj, w.free, 42);
      CHECK(mc::validate_colouring(c, w.adj, w.free).empty());
      CHECK(c.n_colours >= 2);
      CHECK(c.n_colours <= 8);  // running bond has degree <= 6 inside; greedy needs <= 7
    }
  }
}

TEST_CASE("balanced colouring evens out colour sizes", "[mc][colouring]") {
  const test::Wall w = wall(40, 30, 0.0, 15);
  auto sizes = [&](const mc::Colouring& c) {
    std::vector<int> n(c.n_colours, 0);
    for (int col : c.colour)
      if (col >= 0) ++n[col];
    return n;
  };
  const auto nat = sizes(mc::colour_graph("natural", w.s, w.adj, w.free, 1));
  const auto bal = sizes(mc::colour_graph("balanced", w.s, w.adj, w.free, 1));
  auto spread = [](const std::vector<int>& v) {
    return *std::max_element(v.begin(), v.end()) - *std::min_element(v.begin(), v.end());
  };
  CHECK(spread(bal) <= spread(nat));
}

TEST_CASE("validation catches neighbours that share a colour", "[mc][colouring]") {
  const test::Wall w = wall(40, 30, 0.0, 15);
  auto c = mc::colour_graph("natural", w.s, w.adj, w.free, 1);
  // find a free brick with a free neighbour and give both the same colour
  for (std::size_t i = 0; i < w.free.size(); ++i) {
    if (!w.free[i]) continue;
    for (int j = w.adj.offset[i]; j < w.adj.offset[i + 1]; ++j) {
      const int n = w.adj.neighbour[j];
      if (!w.free[n]) continue;
      c.colour[n] = c.colour[i];
      CHECK_FALSE(mc::validate_colouring(c, w.adj, w.free).empty());
      return;
    }
  }
  FAIL("no pair of free neighbours found");
}
