// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal to src/deck: the table walker every section reader shares. A Section reads one TOML
// table and remembers the keys it consumed, so unknown keys, wrong types and out-of-range values
// all produce "file:line: key: expected ..." errors. One reader per deck section lives in
// src/deck/sections/<name>.cpp; adding a section is one more file and one row in deck.cpp.
#include <nacre/deck/deck.hpp>

#include <toml++/toml.hpp>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace nacre::deck::detail {

/// \brief Reads one TOML table, remembering the keys it consumed.
class Section {
public:
  Section(const std::string& file, std::string name, const toml::table* table, int line)
      : file_(file), name_(std::move(name)), table_(table), line_(line) {}

  [[nodiscard]] bool present() const { return table_ != nullptr; }

  /// \brief Error at a key's line (or the section's line when the key is absent).
  [[noreturn]] void fail(std::string_view key, const std::string& what) const;

  /// \brief The node for a key or any of its aliases (the paper's Table 2.1 names); at most one.
  const toml::node* find(std::string_view key, std::initializer_list<std::string_view> aliases);

  /// \brief Number (integers accepted) with a range check.
  void number(std::string_view key, std::initializer_list<std::string_view> aliases, double& out,
              const std::function<bool(double)>& ok, const std::string& expected,
              bool required = false);

  /// \brief Integer (an integral float such as 5e3 is accepted, as written in Table 2.1).
  template <class Int>
  void integer(std::string_view key, std::initializer_list<std::string_view> aliases, Int& out,
               long lo, long hi, const std::string& expected) {
    std::int64_t v;
    if (!integer_value(key, aliases, v, lo, hi, expected)) return;
    out = static_cast<Int>(v);
  }

  void boolean(std::string_view key, bool& out);

  void string(std::string_view key, std::string& out, const std::vector<std::string>& choices,
              const std::string& expected);

  /// \brief Sub-table (or absent); a non-table value under that name is an error.
  Section sub(std::string_view key);

  /// \brief Every key not consumed is an error (typos must not be silently ignored).
  void reject_unknown(const std::vector<std::string>& known_for_message) const;

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::string& file() const { return file_; }
  /// \brief The TOML table read (nullptr when the section is absent).
  [[nodiscard]] const toml::table* table() const { return table_; }
  [[nodiscard]] int line() const { return line_; }
  /// \brief A node's TOML type in words ("an integer"), for "wrong type (...)" messages.
  static std::string type_name(const toml::node& n);

private:
  bool integer_value(std::string_view key, std::initializer_list<std::string_view> aliases,
                     std::int64_t& out, long lo, long hi, const std::string& expected);
  [[nodiscard]] std::string qualified(std::string_view key) const;
  static std::string fmt(double v);

  std::string file_, name_;
  const toml::table* table_;
  int line_;
  std::set<std::string> used_;
  std::string last_key_;
};

inline const auto positive = [](double v) { return v > 0; };
inline const auto non_negative = [](double v) { return v >= 0; };
/// \brief A closed range [lo, hi] as a predicate for Section::number.
inline auto within(double lo, double hi) {
  return [lo, hi](double v) { return v >= lo && v <= hi; };
}

/// \brief A key of a method or variant other than the deck's, refused rather than ignored: fail at
/// `key` when the deck gives it, "KEY: WHAT, and this deck's SETTING; expected FIX or no KEY".
void reject_if_given(Section& s, std::string_view key, const std::string& what, const std::string& setting,
                     const std::string& fix);

/// \brief k, x1, x2 of a cohesive law (any absent key keeps its value in `law`).
void read_law(Section& s, cohesive::Law& law);
/// \brief x2 >= x1.
void check_law(Section& s, const cohesive::Law& law);
/// \brief A [min, max] pair with an initial value inside it.
void check_bracket(Section& s, std::string_view init_key, double init, double lo, double hi,
                   std::string_view min_key);

// ---- one reader per section (src/deck/sections/<name>.cpp), each given the top-level table
void read_geometry(Section& top, Deck& d);
void read_mortar(Section& top, Deck& d);
void read_load(Section& top, Deck& d);
void read_solver(Section& top, Deck& d);
void read_random(Section& top, Deck& d);
void read_output(Section& top, Deck& d);
void read_dynamics(Section& top, Deck& d);
void read_limits(Section& top, Deck& d);

}  // namespace nacre::deck::detail
