#include <nacre/mc/colouring.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>

namespace nacre::mc {

const std::vector<std::string>& colouring_strategies() {
  static const std::vector<std::string> s{"natural", "largest-first", "balanced", "random"};
  return s;
}

Colouring colour_graph(const std::string& strategy, const geometry::Adjacency& adj,
                       const std::vector<bool>& free, std::uint64_t seed) {
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
      if (c.colour[adj.neighbour[j]] == ci)
        return "bricks " + std::to_string(i) + " and " + std::to_string(adj.neighbour[j]) +
               " share an interface and colour " + std::to_string(ci);
  }
  return {};
}

}  // namespace nacre::mc
