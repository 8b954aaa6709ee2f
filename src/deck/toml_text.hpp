// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Deck-internal helpers over the parsed TOML document (toml++ stays out of the public headers).
#include <toml++/toml.hpp>

#include <map>
#include <string>

namespace nacre::deck {

/// \brief "section.key" -> line, for every key and table of the document.
[[nodiscard]] std::map<std::string, int> key_lines(const toml::table& root);

/// \brief See Deck::canonical.
[[nodiscard]] std::string canonical_physics(const toml::table& root);

}  // namespace nacre::deck
