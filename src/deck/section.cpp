// SPDX-License-Identifier: BSD-3-Clause
// The shared table walker of the deck readers (see section.hpp): lookups with aliases, typed
// reads with range checks, and the "file:line: key: what was expected" errors.
#include "section.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nacre::deck::detail {

void Section::fail(std::string_view key, const std::string& what) const {
  int line = line_;
  if (table_)
    if (auto* n = table_->get(key)) line = static_cast<int>(n->source().begin.line);
  std::ostringstream os;
  os << file_ << ':' << line << ": " << qualified(key) << ": " << what;
  throw DeckError(os.str());
}

const toml::node* Section::find(std::string_view key, std::initializer_list<std::string_view> aliases) {
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

void Section::number(std::string_view key, std::initializer_list<std::string_view> aliases, double& out,
                     const std::function<bool(double)>& ok, const std::string& expected, bool required) {
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

bool Section::integer_value(std::string_view key, std::initializer_list<std::string_view> aliases,
                            std::int64_t& out, long lo, long hi, const std::string& expected) {
  const toml::node* n = find(key, aliases);
  if (!n) return false;
  std::int64_t v;
  if (auto i = n->value_exact<std::int64_t>()) v = *i;
  else if (auto d = n->value_exact<double>(); d && std::floor(*d) == *d && std::abs(*d) < 9e15)
    v = static_cast<std::int64_t>(*d);  // 5e3 as written in Table 2.1
  else fail(last_key_, "wrong type (" + type_name(*n) + "); expected " + expected);
  if (v < lo || v > hi) fail(last_key_, "value " + std::to_string(v) + " out of range; expected " + expected);
  out = v;
  return true;
}

void Section::boolean(std::string_view key, bool& out) {
  const toml::node* n = find(key, {});
  if (!n) return;
  if (auto b = n->value_exact<bool>()) out = *b;
  else fail(key, "wrong type (" + type_name(*n) + "); expected true or false");
}

void Section::string(std::string_view key, std::string& out, const std::vector<std::string>& choices,
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

Section Section::sub(std::string_view key) {
  const toml::node* n = find(key, {});
  if (!n) return Section(file_, qualified(key), nullptr, line_);
  if (!n->is_table()) fail(key, "wrong type (" + type_name(*n) + "); expected a table [" + qualified(key) + "]");
  return Section(file_, qualified(key), n->as_table(), static_cast<int>(n->source().begin.line));
}

void Section::reject_unknown(const std::vector<std::string>& known_for_message) const {
  if (!table_) return;
  for (auto&& [k, v] : *table_) {
    if (used_.count(std::string(k.str()))) continue;
    std::string list;
    for (auto& s : known_for_message) list += (list.empty() ? "" : ", ") + s;
    fail(k.str(), "unknown key; expected one of: " + list);
  }
}

std::string Section::qualified(std::string_view key) const {
  return name_.empty() ? std::string(key) : name_ + "." + std::string(key);
}

std::string Section::type_name(const toml::node& n) {
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

std::string Section::fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

void reject_if_given(Section& s, std::string_view key, const std::string& what, const std::string& setting,
                     const std::string& fix) {
  if (s.find(key, {}) != nullptr)
    s.fail(key, what + ", and this deck's " + setting + "; expected " + fix + " or no " + std::string(key));
}

void read_law(Section& s, cohesive::Law& law) {
  s.number("k", {}, law.k, positive, "a positive stiffness per unit length^3");
  s.number("x1", {}, law.x1, positive, "a positive length (end of the elastic range)");
  s.number("x2", {}, law.x2, positive, "a positive length (end of the plateau), x2 >= x1");
}

void check_law(Section& s, const cohesive::Law& law) {
  if (law.x2 < law.x1)
    s.fail("x2", "x2 = " + std::to_string(law.x2) + " is smaller than x1 = " + std::to_string(law.x1) +
                     "; expected x2 >= x1 (x2 ends the plateau)");
}

void check_bracket(Section& s, std::string_view init_key, double init, double lo, double hi,
                   std::string_view min_key) {
  if (lo > hi) s.fail(min_key, "minimum exceeds the maximum; expected min <= max");
  if (init < lo || init > hi) s.fail(init_key, "initial value outside [min, max]; expected min <= initial <= max");
}

}  // namespace nacre::deck::detail
