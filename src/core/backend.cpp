// SPDX-License-Identifier: BSD-3-Clause
// The run-time backend choice (include/nacre/core/backend.hpp): names, parsing, and the few
// calls that need no kernel.
#include <nacre/core/backend.hpp>

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <utility>

namespace nacre {

namespace {
std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Kokkos' names of AnySpace's alternatives, in order (static: no instance, no initialised Kokkos).
template <std::size_t... I>
std::vector<std::string> space_names(std::index_sequence<I...>) {
  return {std::string(std::variant_alternative_t<I, AnySpace>::name())...};
}

/// An instance of alternative k (Kokkos initialised).
template <std::size_t... I>
AnySpace instance(std::size_t k, std::index_sequence<I...>) {
  AnySpace s;
  ((k == I ? (s = AnySpace(std::in_place_index<I>), 0) : 0), ...);
  return s;
}
constexpr auto kAll = std::make_index_sequence<std::variant_size_v<AnySpace>>{};
}  // namespace

std::vector<std::string> Backend::names() {
  auto n = space_names(kAll);
  for (auto& x : n) x = lower(x);
  return n;
}

std::string Backend::canonical(const std::string& name) {
  const auto n = names();
  const auto it = std::find(n.begin(), n.end(), lower(name));
  return it == n.end() ? std::string() : *it;
}

std::string Backend::names_list() {
  std::string list;
  for (const auto& x : names()) list += (list.empty() ? "" : ", ") + x;
  return list;
}

Backend Backend::parse(const std::string& name) {
  const auto n = names();
  const auto it = std::find(n.begin(), n.end(), canonical(name));
  if (it == n.end())
    throw std::invalid_argument("backend \"" + name +
                                "\" is not one this build can run; expected one of: " + names_list());
  Backend b;
  b.space_ = instance(static_cast<std::size_t>(it - n.begin()), kAll);
  return b;
}

bool Backend::bit_compatible(const std::string& a, const std::string& b) {
  const auto host = [](const std::string& n) { return n == "serial" || n == "openmp" || n == "threads"; };
  const std::string x = lower(a), y = lower(b);
  return x == y || (host(x) && host(y));
}

std::string Backend::name() const { return lower(kokkos_name()); }
const char* Backend::kokkos_name() const {
  return visit([](const auto& e) { return e.name(); });
}
int Backend::concurrency() const {
  return visit([](const auto& e) { return e.concurrency(); });
}
void Backend::fence() const {
  visit([](const auto& e) { e.fence(); });
}

}  // namespace nacre
