// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Two runs' states compared array by array: each named array (a dynamic run's u, v, a,
/// acc...; a Monte Carlo run's x, y, theta) against the scale of its own largest |value|.
///
/// Why per array: one scale for the whole state let a small array's difference hide under a
/// large one's. A BIE state holds accelerations near 1e10 beside displacements near 1e-6, so
/// "1e-6 of the largest |value|" allowed any displacement at all. An array whose reference is all
/// zeros is measured against the whole state's largest |value| instead (any difference over a
/// zero scale would read as infinite). Host code only (the bench and its tests).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace nacre::io {

/// \brief One array of a saved state, with its name (the order is the state's).
struct NamedArray {
  std::string name;
  std::vector<double> values;
};
using NamedArrays = std::vector<NamedArray>;

/// \brief How far `other` is from `reference`.
struct StateDifference {
  bool same_layout = true;    ///< the same names and lengths in the same order
  bool bit_identical = true;  ///< every value's bits
  double max_abs = 0;         ///< largest |a - b| over the whole state
  double relative = 0;        ///< largest over the arrays of max |a - b| / the array's scale
  std::string worst;          ///< the array of `relative` ("" when none differs)
  double worst_scale = 0;     ///< that array's scale
};

[[nodiscard]] inline double largest_magnitude(const std::vector<double>& v) {
  double m = 0;
  for (const double x : v) m = std::max(m, std::abs(x));
  return m;
}

/// \brief Array by array (see the file comment); a different layout gives infinite differences.
[[nodiscard]] inline StateDifference compare_states(const NamedArrays& reference, const NamedArrays& other) {
  StateDifference d;
  constexpr double inf = std::numeric_limits<double>::infinity();
  d.same_layout = reference.size() == other.size();
  for (std::size_t k = 0; d.same_layout && k < reference.size(); ++k)
    d.same_layout = reference[k].name == other[k].name && reference[k].values.size() == other[k].values.size();
  if (!d.same_layout) {
    d.bit_identical = false, d.max_abs = inf, d.relative = inf, d.worst = "(layout)";
    return d;
  }
  double whole = -1;  // the whole state's largest |value|, found when an all-zero array differs
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const auto& r = reference[k].values;
    const auto& o = other[k].values;
    if (r.empty() || std::memcmp(r.data(), o.data(), r.size() * sizeof(double)) == 0) continue;  // the same bits
    d.bit_identical = false;
    double diff = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double e = std::abs(r[i] - o[i]);
      diff = std::max(diff, std::isnan(e) ? inf : e);
    }
    d.max_abs = std::max(d.max_abs, diff);
    if (diff == 0) continue;
    const double own = largest_magnitude(r);
    if (!(own > 0) && whole < 0) {
      whole = 0;
      for (const auto& a : reference) whole = std::max(whole, largest_magnitude(a.values));
    }
    const double scale = own > 0 ? own : whole > 0 ? whole : 1.0;
    if (const double rel = diff / scale; rel > d.relative || d.worst.empty())
      d.relative = rel, d.worst = reference[k].name, d.worst_scale = scale;
  }
  return d;
}

/// \brief The values of every array one after the other (a state file's bytes).
[[nodiscard]] inline std::vector<double> flatten(const NamedArrays& s) {
  std::vector<double> v;
  for (const auto& a : s) v.insert(v.end(), a.values.begin(), a.values.end());
  return v;
}

/// \brief Cut `flat` into arrays of the given names and lengths; false when the lengths do not
/// add up to its size.
[[nodiscard]] inline bool unflatten(const std::vector<double>& flat,
                                    const std::vector<std::pair<std::string, std::size_t>>& layout, NamedArrays& out) {
  std::size_t total = 0;
  for (const auto& [name, n] : layout) total += n;
  if (total != flat.size()) return false;
  out.clear();
  std::size_t at = 0;
  for (const auto& [name, n] : layout) {
    out.push_back({name, std::vector<double>(flat.begin() + static_cast<std::ptrdiff_t>(at),
                                             flat.begin() + static_cast<std::ptrdiff_t>(at + n))});
    at += n;
  }
  return true;
}

}  // namespace nacre::io
