// SPDX-License-Identifier: BSD-3-Clause
// Deck parsing with toml++: the file is parsed once, then each top-level section is read by its
// own reader (src/deck/sections/<name>.cpp) through the shared table walker (section.hpp), in the
// order of kSections. A new section is one more reader file and one more row below.
#include "section.hpp"
#include "toml_text.hpp"

#include <nacre/deck/limits.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace nacre::deck {
namespace {

struct SectionReader {
  const char* name;  ///< TOML table name (also listed in the "unknown key" message)
  void (*read)(detail::Section& top, Deck& d);
};

/// Order matters: a reader may refine what an earlier one set ([random] sets solver.rng), and
/// the first error met is the one reported.
constexpr SectionReader kSections[] = {
    {"geometry", detail::read_geometry}, {"mortar", detail::read_mortar},
    {"load", detail::read_load},         {"solver", detail::read_solver},
    {"random", detail::read_random},     {"output", detail::read_output},
    {"dynamics", detail::read_dynamics},
    {"limits", detail::read_limits},
};

Deck parse_table(const toml::table& root, const std::string& file) {
  Deck d;
  d.path = file;
  detail::Section top(file, "", &root, 1);
  std::vector<std::string> known;
  for (const auto& s : kSections) {
    s.read(top, d);
    known.emplace_back(s.name);
  }
  top.reject_unknown(known);
  return d;
}

}  // namespace

Deck parse_deck_string(std::string_view text, const std::string& name) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << name << ':' << e.source().begin.line << ": (syntax): " << e.description();
    throw DeckError(os.str());
  }
  Deck d = parse_table(root, name);
  d.lines = key_lines(root);
  d.canonical = canonical_physics(root);
  d.text = std::string(text);
  check_limits(d);  // estimates from the deck, before anything is built
  return d;
}

Deck parse_deck_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw DeckError(path + ":0: (file): is a directory; expected a TOML deck file");
  std::ifstream in(path);
  if (!in) throw DeckError(path + ":0: (file): cannot open; expected a readable TOML deck");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_deck_string(ss.str(), path);
}

}  // namespace nacre::deck
