// SPDX-License-Identifier: BSD-3-Clause
// The crack read from interface states: a network of interface end points built once per
// specimen (host, O(N) with a cell hash), then per reading a Dijkstra over the ruptured
// interfaces from the notch and a breadth-first walk over the softening ones. Host code: a
// reading is O(ruptured + softening) after an O(nodes) reset, small beside a row of steps.
#include <nacre/fracture/crack.hpp>

#include <nacre/core/format.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace nacre::fracture {

CrackTracker::CrackTracker(const geometry::Specimen& s, const geometry::Interfaces& f, const deck::Geometry& g) {
  const double tol = 1e-6 * std::min(g.brick_width, g.brick_height);
  notch_y_ = g.notch_y < 0 ? 0.5 * g.height : g.notch_y;

  // end points merged within tol: a hash of cells of size tol, the 3x3 cells searched
  std::unordered_map<std::uint64_t, int> cell_node;
  auto key = [](std::int64_t i, std::int64_t j) {
    return (static_cast<std::uint64_t>(i) << 32) ^ static_cast<std::uint64_t>(j & 0xffffffff);
  };
  auto node_of = [&](double x, double y) {
    const auto ci = static_cast<std::int64_t>(std::floor(x / tol)), cj = static_cast<std::int64_t>(std::floor(y / tol));
    for (std::int64_t di = -1; di <= 1; ++di)
      for (std::int64_t dj = -1; dj <= 1; ++dj)
        if (auto it = cell_node.find(key(ci + di, cj + dj)); it != cell_node.end()) {
          const int n = it->second;
          if (std::abs(node_x_[n] - x) <= tol && std::abs(node_y_[n] - y) <= tol) return n;
        }
    const int n = static_cast<int>(node_x_.size());
    node_x_.push_back(x), node_y_.push_back(y);
    cell_node.emplace(key(ci, cj), n);
    return n;
  };
  const std::size_t ni = f.size();
  end0_.resize(ni), end1_.resize(ni), length_.assign(f.length.begin(), f.length.end()), kind_ = f.kind;
  for (std::size_t i = 0; i < ni; ++i) {
    const auto a = static_cast<std::size_t>(f.a[i]);
    end0_[i] = node_of(s.cx[a] + f.ra0x[i], s.cy[a] + f.ra0y[i]);
    end1_[i] = node_of(s.cx[a] + f.ra1x[i], s.cy[a] + f.ra1y[i]);
  }
  const std::size_t nn = node_x_.size();
  adj_offset_.assign(nn + 1, 0);
  for (std::size_t i = 0; i < ni; ++i) ++adj_offset_[end0_[i] + 1], ++adj_offset_[end1_[i] + 1];
  for (std::size_t n = 0; n < nn; ++n) adj_offset_[n + 1] += adj_offset_[n];
  adj_iface_.resize(2 * ni);
  {
    std::vector<int> fill(adj_offset_.begin(), adj_offset_.end() - 1);
    for (std::size_t i = 0; i < ni; ++i)
      adj_iface_[fill[end0_[i]]++] = static_cast<int>(i), adj_iface_[fill[end1_[i]]++] = static_cast<int>(i);
  }

  // the notch tip: the right end of the notch's free faces, the parts of brick edges along
  // y = notch_y that no interface covers (the bed joint left of notch_length on an unrotated
  // wall; on a rotated one the faces of the bricks the notch splits, specimen.cpp, reaching past
  // notch_length where the last split brick does)
  notch_tip_x_ = g.notch_length;
  if (g.notch_length > 0) {
    auto on_line = [&](double y) { return std::abs(y - notch_y_) <= tol; };
    std::vector<std::pair<double, double>> covered;  // interfaces along the line, as x intervals
    for (std::size_t i = 0; i < ni; ++i)
      if (on_line(node_y_[end0_[i]]) && on_line(node_y_[end1_[i]]))
        covered.emplace_back(std::min(node_x_[end0_[i]], node_x_[end1_[i]]),
                             std::max(node_x_[end0_[i]], node_x_[end1_[i]]));
    std::sort(covered.begin(), covered.end());
    double tip = -1;
    for (std::size_t b = 0; b < s.size(); ++b)
      for (int v = s.poly_offset[b]; v < s.poly_offset[b + 1]; ++v) {
        const int w = v + 1 == s.poly_offset[b + 1] ? s.poly_offset[b] : v + 1;
        if (!on_line(s.vy[v]) || !on_line(s.vy[w])) continue;
        // the uncovered parts of the edge [lo, hi]: its free face
        double lo = std::min(s.vx[v], s.vx[w]);
        const double hi = std::max(s.vx[v], s.vx[w]);
        for (const auto& [c0, c1] : covered) {
          if (c1 <= lo + tol) continue;
          if (c0 >= hi - tol) break;
          if (c0 > lo + tol) tip = std::max(tip, c0);  // a free part [lo, c0]
          lo = std::max(lo, c1);
        }
        if (hi > lo + tol) tip = std::max(tip, hi);
      }
    if (tip >= 0) notch_tip_x_ = tip;
    for (std::size_t n = 0; n < nn; ++n)
      if (std::abs(node_y_[n] - notch_y_) <= tol && node_x_[n] <= notch_tip_x_ + tol)
        roots_.push_back(static_cast<int>(n));
  }
}

template <class T>
CrackReading CrackTracker::measure_impl(std::span<const T> state, std::span<const double> energy,
                                        std::vector<int>* members) const {
  const std::size_t ni = end0_.size(), nn = node_x_.size();
  if (state.size() != ni || (!energy.empty() && energy.size() != ni))
    throw std::invalid_argument("crack: " + std::to_string(state.size()) + " interface states and " +
                                std::to_string(energy.size()) + " energies for " + std::to_string(ni) + " interfaces");
  CrackReading r;
  for (std::size_t i = 0; i < energy.size(); ++i)  // in interface order: the same sum on every backend
    if (state[i] != 0) r.fracture_energy += energy[i];
  r.tip_x = notch_tip_x_, r.tip_y = notch_y_;
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(nn, inf);
  // Dijkstra from the notch through ruptured interfaces (ties broken by node index: deterministic)
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (int n : roots_) dist[n] = 0, queue.push({0.0, n});
  std::vector<char> in_crack(ni, 0);
  while (!queue.empty()) {
    const auto [d, n] = queue.top();
    queue.pop();
    if (d > dist[n]) continue;
    for (int k = adj_offset_[n]; k < adj_offset_[n + 1]; ++k) {
      const int i = adj_iface_[k];
      if (state[i] != 2) continue;
      in_crack[i] = 1;
      const int o = end0_[i] == n ? end1_[i] : end0_[i];
      if (d + length_[i] < dist[o]) dist[o] = d + length_[i], queue.push({dist[o], o});
    }
  }
  int tip = -1;
  for (std::size_t i = 0; i < ni; ++i) {
    if (!in_crack[i]) continue;
    ++r.interfaces;
    (kind_[i] == geometry::JointKind::head ? r.head : r.bed) += 1;
    if (members) members->push_back(static_cast<int>(i));
    for (int n : {end0_[i], end1_[i]})
      if (tip < 0 || node_x_[n] > node_x_[tip] || (node_x_[n] == node_x_[tip] && dist[n] < dist[tip])) tip = n;
  }
  if (tip >= 0) {
    r.tip_x = node_x_[tip], r.tip_y = node_y_[tip];
    r.extension = std::max(0.0, r.tip_x - notch_tip_x_);
    r.path_length = dist[tip];
    r.deflection = r.extension > 0 ? r.path_length / r.extension : 0.0;
  }
  // the process zone: softening interfaces reached from the crack's nodes and the notch
  std::vector<char> seen(nn, 0), in_zone(ni, 0);
  std::vector<int> stack;
  for (std::size_t n = 0; n < nn; ++n)
    if (dist[n] < inf) seen[n] = 1, stack.push_back(static_cast<int>(n));
  double reach = r.tip_x;
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    for (int k = adj_offset_[n]; k < adj_offset_[n + 1]; ++k) {
      const int i = adj_iface_[k];
      if (state[i] != 1 || in_zone[i]) continue;
      in_zone[i] = 1, ++r.process_zone;
      const int o = end0_[i] == n ? end1_[i] : end0_[i];
      reach = std::max({reach, node_x_[n], node_x_[o]});
      if (!seen[o]) seen[o] = 1, stack.push_back(o);
    }
  }
  r.process_zone_extent = reach - r.tip_x;
  return r;
}

CrackReading CrackTracker::measure(std::span<const int> state, std::span<const double> energy) const {
  return measure_impl(state, energy, nullptr);
}
CrackReading CrackTracker::measure(std::span<const std::int8_t> state, std::span<const double> energy) const {
  return measure_impl(state, energy, nullptr);
}

std::vector<int> CrackTracker::crack_interfaces(std::span<const int> state) const {
  std::vector<int> m;
  (void)measure_impl(state, std::span<const double>{}, &m);
  return m;
}

template <class T>
std::vector<std::int8_t> CrackTracker::mask_impl(std::span<const T> state) const {
  std::vector<int> members;
  (void)measure_impl(state, std::span<const double>{}, &members);
  std::vector<std::int8_t> mask(end0_.size(), 0);
  for (int i : members) mask[static_cast<std::size_t>(i)] = 1;
  return mask;
}

std::vector<std::int8_t> CrackTracker::crack_mask(std::span<const int> state) const { return mask_impl(state); }
std::vector<std::int8_t> CrackTracker::crack_mask(std::span<const std::int8_t> state) const { return mask_impl(state); }

std::string csv_header() {
  return "crack_interfaces,crack_bed,crack_head,crack_tip_x,crack_tip_y,crack_extension,crack_path_length,"
         "crack_deflection,process_zone,process_zone_extent,fracture_energy";
}

std::string csv_columns(const CrackReading& c, int digits) {
  auto num = [digits](double v) { return format_real(v, digits); };
  return std::to_string(c.interfaces) + "," + std::to_string(c.bed) + "," + std::to_string(c.head) + "," +
         num(c.tip_x) + "," + num(c.tip_y) + "," + num(c.extension) + "," + num(c.path_length) + "," +
         num(c.deflection) + "," + std::to_string(c.process_zone) + "," + num(c.process_zone_extent) + "," +
         num(c.fracture_energy);
}

double rayleigh_speed_plane_stress(double E, double nu, double rho) {
  if (!(E > 0) || !(rho > 0) || !(nu > -1 && nu < 0.5))
    throw std::invalid_argument("Rayleigh speed: need E > 0, rho > 0 and -1 < nu < 0.5");
  const double cs = std::sqrt(E / (2 * rho * (1 + nu))), cp = std::sqrt(E / (rho * (1 - nu * nu)));
  const double k2 = (cs / cp) * (cs / cp);
  // R(xi) = (2 - xi^2)^2 - 4 sqrt(1 - k2 xi^2) sqrt(1 - xi^2) ~ -2 (1 - k2) xi^2 < 0 near 0+
  // (xi = 0 is the trivial root) and R(1) = 1 > 0: the Rayleigh root in (0, 1), by bisection
  auto R = [&](double xi) {
    const double x2 = xi * xi;
    return (2 - x2) * (2 - x2) - 4 * std::sqrt(1 - k2 * x2) * std::sqrt(1 - x2);
  };
  double lo = 1e-3, hi = 1.0;
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    (R(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi) * cs;
}

}  // namespace nacre::fracture
