// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The names of the random generators a deck can ask for ([random] generator), as plain
/// constants: the deck reader validates a name with them and needs nothing else of rng (no
/// Kokkos); rng/registry.hpp makes a source for each (a test checks both lists agree).
#include <string>
#include <string_view>

namespace nacre::rng {

inline constexpr std::string_view kGeneratorKinds[] = {"philox", "aes-ctr", "mt-aes"};

/// \brief True when `kind` names a generator (rng::make_uniform_source makes one).
constexpr bool is_uniform_source_kind(std::string_view kind) {
  for (auto k : kGeneratorKinds)
    if (k == kind) return true;
  return false;
}

/// \brief The names, quoted and comma-separated (for error messages and docs).
inline std::string uniform_source_kinds() {
  std::string s;
  for (auto k : kGeneratorKinds) {
    if (!s.empty()) s += ", ";
    s += '"';
    s += k;
    s += '"';
  }
  return s;
}

}  // namespace nacre::rng
