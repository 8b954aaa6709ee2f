#pragma once
// Internal to src/deck: the table walker every section reader uses. It records which keys were
// read, so unknown keys, wrong types and out-of-range values all produce
// "file:line: key: expected ..." errors (DeckError).
#include <nacre/deck/deck.hpp>

#include <toml++/toml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace nacre::deck::detail {

/// \brief Reads one TOML table, remembering the keys it consumed.
class Section {
public:
  Section(const std::string& file, std::string name, const toml::table* table, int line)
      : file_(file), name_(std::move(name)), table_(table), line_(line) {}

  [[nodiscard]] bool present() const { return table_ != nullptr; }

  /// \brief Error at a key's line (or the section's line when the key is absent).
  [[noreturn]] void fail(std::string_view key, const std::string& what) const {
    int line = line_;
    if (table_)
      if (auto* n = table_->get(key)) line = static_cast<int>(n->source().begin.line);
    std::ostringstream os;
    os << file_ << ':' << line << ": " << qualified(key) << ": " << what;
    throw DeckError(os.str());
  }

  /// \brief The node for a key or any of its aliases (the paper's Table 2.1 names); at most one.
  const toml::node* find(std::string_view key, std::initializer_list<std::string_view> aliases) {
    const toml::node* found = nullptr;
    std::string_view found_name;
    auto check = [&](std::string_view k) {
      if (!table_) return;
      if (auto* n = table_->get(k)) {
        used_.insert(std::string(k));
        if (found)
          fail(k, "given twice (also as '" + std::string(found_name) + "'); keep one");
        found = n;
        found_name = k;
      }
    };
    check(key);
    for (auto a : aliases) check(a);
    last_key_ = found ? std::string(found_name) : std::string(key);
    return found;
  }

  /// \brief Number (integers accepted) with a range check.
  void number(std::string_view key, std::initializer_list<std::string_view> aliases, double& out,
              const std::function<bool(double)>& ok, const std::string& expected,
              bool required = false) {
    const toml::node* n = find(key, aliases);
    if (!n) {
      if (required) fail(key, "missing; expected " + expected);
      return;
    }
    double v;
    if (auto d = n->value_exact<double>()) v = *d;
    else if (auto i = n->value_exact<std::int64_t>()) v = static_cast<double>(*i);
    else fail(last_key_, "wrong type (" + type_name(*n) + "); expected " + expected);
    if (!std::isfinite(v) || !ok(v)) fail(last_key_, "value " + fmt(v) + " out of range; expected " + expected);
    out = v;
  }

  template <class Int>
  void integer(std::string_view key, std::initializer_list<std::string_view> aliases, Int& out,
               long lo, long hi, const std::string& expected) {
    const toml::node* n = find(key, aliases);
    if (!n) return;
    std::int64_t v;
    if (auto i = n->value_exact<std::int64_t>()) v = *i;
    else if (auto d = n->value_exact<double>(); d && std::floor(*d) == *d && std::abs(*d) < 9e15)
      v = static_cast<std::int64_t>(*d);  // 5e3 as written in Table 2.1
    else fail(last_key_, "wrong type (" + type_name(*n) + "); expected " + expected);
    if (v < lo || v > hi) fail(last_key_, "value " + std::to_string(v) + " out of range; expected " + expected);
    out = static_cast<Int>(v);
  }

  void boolean(std::string_view key, bool& out) {
    const toml::node* n = find(key, {});
    if (!n) return;
    if (auto b = n->value_exact<bool>()) out = *b;
    else fail(key, "wrong type (" + type_name(*n) + "); expected true or false");
  }

  void string(std::string_view key, std::string& out, const std::vector<std::string>& choices,
              const std::string& expected) {
    const toml::node* n = find(key, {});
    if (!n) return;
    auto s = n->value_exact<std::string>();
    if (!s) fail(key, "wrong type (" + type_name(*n) + "); expected " + expected);
    if (!choices.empty() && std::find(choices.begin(), choices.end(), *s) == choices.end())
      fail(key, "unknown value \"" + *s + "\"; expected " + expected);
    if (choices.empty() && s->empty()) fail(key, "empty; expected " + expected);
    out = *s;
  }

  /// \brief Sub-table (or absent); a non-table value under that name is an error.
  Section sub(std::string_view key) {
    const toml::node* n = find(key, {});
    if (!n) return Section(file_, qualified(key), nullptr, line_);
    if (!n->is_table()) fail(key, "wrong type (" + type_name(*n) + "); expected a table [" + qualified(key) + "]");
    return Section(file_, qualified(key), n->as_table(), static_cast<int>(n->source().begin.line));
  }

  /// \brief Every key not consumed is an error (typos must not be silently ignored).
  void reject_unknown(const std::vector<std::string>& known_for_message) const {
    if (!table_) return;
    for (auto&& [k, v] : *table_) {
      if (used_.count(std::string(k.str()))) continue;
      std::string list;
      for (auto& s : known_for_message) list += (list.empty() ? "" : ", ") + s;
      fail(k.str(), "unknown key; expected one of: " + list);
    }
  }

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] const toml::table* table() const { return table_; }
  [[nodiscard]] int line() const { return line_; }

private:
  [[nodiscard]] std::string qualified(std::string_view key) const {
    return name_.empty() ? std::string(key) : name_ + "." + std::string(key);
  }
  static std::string type_name(const toml::node& n) {
    switch (n.type()) {
      case toml::node_type::string: return "a string";
      case toml::node_type::integer: return "an integer";
      case toml::node_type::floating_point: return "a number";
      case toml::node_type::boolean: return "a boolean";
      case toml::node_type::array: return "an array";
      case toml::node_type::table: return "a table";
      default: return "a date/time";
    }
  }
  static std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

  std::string file_, name_;
  const toml::table* table_;
  int line_;
  std::set<std::string> used_;
  std::string last_key_;
};

inline const auto positive = [](double v) { return v > 0; };
inline const auto non_negative = [](double v) { return v >= 0; };

/// \brief Section readers living in their own files (one per section).
void read_dynamics(Section& top, Deck& d);

}  // namespace nacre::deck::detail
