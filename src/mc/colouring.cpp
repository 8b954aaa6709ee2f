// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/mc/colouring.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

namespace nacre::mc {

const std::vector<std::string>& colouring_strategies() {
  // order = preference on ties in the pre-simulation: tiles first (best cache use on CPUs;
  // on GPUs it is far slower and never ties), then the graph colourings. Kokkos Kernels'
  // "kokkos-d1" (colour_graph knows it) is no candidate: more colours, worse balance and ~1000x
  // the time to colour (docs/design.md, "Which colouring").
  static const std::vector<std::string> s{"tiles", "natural", "largest-first", "balanced", "random"};
  return s;
}

namespace {
Colouring colour_tiles(const geometry::Specimen& s, const std::vector<bool>& free) {
  // Tile side: about 256 bricks per tile (fewer for small specimens, so that each colour still
  // has ~64 tiles to share among threads; the size depends on the specimen only, never on the
  // thread count), and at least twice the largest brick extent, so two tiles of one
  // checkerboard colour (one tile apart) can never hold neighbouring bricks.
  double extent = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (int v = s.poly_offset[i]; v < s.poly_offset[i + 1]; ++v)
      extent = std::max(extent, std::hypot(s.vx[v] - s.cx[i], s.vy[v] - s.cy[i]));
  const double n_free = static_cast<double>(std::count(free.begin(), free.end(), true));
  const double per_tile = std::clamp(n_free / 256.0, 16.0, 256.0);
  const double side = std::max(4.0 * extent, std::sqrt(per_tile * s.full_brick_area));
  const int nx = std::max(1, static_cast<int>(std::ceil(s.width / side)));
  Colouring c;
  c.name = "tiles";
  c.colour.assign(s.size(), -1);
  c.tile.assign(s.size(), -1);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!free[i]) continue;
    const int tx = std::max(0, static_cast<int>(s.cx[i] / side)), ty = std::max(0, static_cast<int>(s.cy[i] / side));
    c.colour[i] = (ty % 2) * 2 + (tx % 2);
    c.tile[i] = ty * nx + tx;
    c.n_colours = std::max(c.n_colours, c.colour[i] + 1);
  }
  return c;
}
}  // namespace

Colouring colour_graph(const std::string& strategy, const geometry::Specimen& s,
                       const geometry::Adjacency& adj, const std::vector<bool>& free, std::uint64_t seed) {
  if (strategy == "tiles") return colour_tiles(s, free);
#ifdef NACRE_HAVE_KOKKOSKERNELS
  if (strategy == "kokkos-d1") return colour_kokkos_d1(adj, free);  // src/mc/colouring_kk.cpp
#endif
  const std::size_t n = free.size();
  std::vector<int> order;
  order.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    if (free[i]) order.push_back(static_cast<int>(i));
  auto degree = [&](int i) { return adj.offset[i + 1] - adj.offset[i]; };
  if (strategy == "largest-first") {
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return degree(a) > degree(b); });
  } else if (strategy == "random") {
    std::mt19937_64 gen(seed ^ 0x9E3779B97F4A7C15ull);
    std::shuffle(order.begin(), order.end(), gen);
  } else if (strategy != "natural" && strategy != "balanced") {
    throw std::invalid_argument("unknown colouring strategy '" + strategy + "'");
  }
  Colouring c;
  c.name = strategy;
  c.colour.assign(n, -1);
  c.tile.assign(n, -1);
  std::vector<int> used_by(64, -1), size;  // used_by[col] == i: col taken by a neighbour of i
  for (int i : order) {
    for (int j = adj.offset[i]; j < adj.offset[i + 1]; ++j) {
      const int col = c.colour[adj.neighbour[j]];
      if (col >= 0) {
        if (col >= static_cast<int>(used_by.size())) used_by.resize(2 * col + 2, -1);
        used_by[col] = i;
      }
    }
    int pick = -1;
    if (strategy == "balanced") {
      for (int col = 0; col < c.n_colours; ++col)
        if (used_by[col] != i && (pick < 0 || size[col] < size[pick])) pick = col;
    } else {
      for (int col = 0; col < c.n_colours && pick < 0; ++col)
        if (used_by[col] != i) pick = col;
    }
    if (pick < 0) {
      pick = c.n_colours++;
      size.push_back(0);
      if (pick >= static_cast<int>(used_by.size())) used_by.resize(2 * pick + 2, -1);
    }
    c.colour[i] = pick;
    ++size[pick];
  }
  return c;
}

std::string validate_colouring(const Colouring& c, const geometry::Adjacency& adj,
                               const std::vector<bool>& free) {
  for (std::size_t i = 0; i < free.size(); ++i) {
    const int ci = c.colour[i];
    if (!free[i]) {
      if (ci != -1) return "driven brick " + std::to_string(i) + " has a colour";
      continue;
    }
    if (ci < 0 || ci >= c.n_colours) return "free brick " + std::to_string(i) + " has no valid colour";
    for (int j = adj.offset[i]; j < adj.offset[i + 1]; ++j)
      if (c.colour[adj.neighbour[j]] == ci && (c.tile[i] < 0 || c.tile[i] != c.tile[adj.neighbour[j]]))
        return "bricks " + std::to_string(i) + " and " + std::to_string(adj.neighbour[j]) +
               " share an interface and colour " + std::to_string(ci);
  }
  return {};
}

}  // namespace nacre::mc
