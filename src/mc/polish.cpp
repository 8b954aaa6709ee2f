// SPDX-License-Identifier: BSD-3-Clause
// The polish methods' names (include/nacre/mc/polish.hpp holds the Polisher, a template on the
// execution space: FIRE over all free bricks, or colour-swept 3x3 Newton per brick).
#include <nacre/mc/polish.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace nacre::mc {

PolishMethod parse_polish_method(const std::string& name) {
  for (const auto m :
       {PolishMethod::fire, PolishMethod::newton, PolishMethod::trust_region, PolishMethod::anneal, PolishMethod::none})
    if (name == polish_method_name(m)) return m;
  throw std::invalid_argument("unknown polish method '" + name +
                              "' (expected fire, newton, trust-region, anneal or none)");
}

const char* polish_method_name(PolishMethod m) {
  switch (m) {
    case PolishMethod::fire: return "fire";
    case PolishMethod::newton: return "newton";
    case PolishMethod::trust_region: return "trust-region";
    case PolishMethod::anneal: return "anneal";
    case PolishMethod::none: return "none";
  }
  return "?";
}

}  // namespace nacre::mc
