// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief What this nacre is and what it was built with: its version and commit, the Kokkos it
/// runs on with its backends, and the optional libraries found. `nacre --version` prints it,
/// summary.json and every HDF5 file record it, so a result always names the code that made it.
#include <string>
#include <utility>
#include <vector>

namespace nacre {

struct BuildInfo {
  std::string version;         ///< nacre's, "1.0.0" (CMake's project version)
  std::string commit;          ///< git's short hash at build time, "-dirty" appended; "unknown" outside git
  std::string kokkos_version;  ///< "5.2.2"
  std::vector<std::string> backends;  ///< this build's host and device backends, the default first
  /// \brief Optional and required libraries with their versions ("Kokkos Kernels", "4.7.99"); a
  /// library the build left out is absent.
  std::vector<std::pair<std::string, std::string>> libraries;
};

/// \brief This build's information (computed once).
[[nodiscard]] const BuildInfo& build_info();

/// \brief The text of `nacre --version`: three lines, "nacre 1.0.0 (commit ...)", the Kokkos
/// version with its backends, the libraries.
[[nodiscard]] std::string version_text();

/// \brief The build as summary.json members: "nacre" {version, commit}, "kokkos" {version,
/// backends}, "libraries" {name: version}; a template so this file needs no JSON library.
template <class Json>
void put_build_json(Json& j) {
  const BuildInfo& b = build_info();
  j["nacre"]["version"] = b.version;
  j["nacre"]["commit"] = b.commit;
  j["kokkos"]["version"] = b.kokkos_version;
  j["kokkos"]["backends"] = b.backends;
  j["libraries"] = Json::object();
  for (const auto& [name, version] : b.libraries) j["libraries"][name] = version;
}

}  // namespace nacre
