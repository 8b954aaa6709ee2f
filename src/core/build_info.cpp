// SPDX-License-Identifier: BSD-3-Clause
// The build's identity (core/build_info.hpp): CMake hands the versions it found over as
// definitions on this source alone, the commit comes from a file regenerated at every build
// (cmake/NacreCommit.cmake), so a new commit recompiles one small source, not the library.
#include <nacre/core/backend.hpp>
#include <nacre/core/build_info.hpp>
#include <nacre/par/comm.hpp>

#include <Kokkos_Macros.hpp>

#include <sstream>

#ifndef NACRE_VERSION
#define NACRE_VERSION "unknown"
#endif

namespace nacre {

const char* build_commit();  // nacre_commit.cpp, generated

const BuildInfo& build_info() {
  static const BuildInfo info = [] {
    BuildInfo b;
    b.version = NACRE_VERSION;
    b.commit = build_commit();
    b.kokkos_version = std::to_string(KOKKOS_VERSION / 10000) + "." + std::to_string(KOKKOS_VERSION / 100 % 100) +
                       "." + std::to_string(KOKKOS_VERSION % 100);
    b.backends = Backend::names();
#ifdef NACRE_KOKKOSKERNELS_VERSION
    b.libraries.emplace_back("Kokkos Kernels", NACRE_KOKKOSKERNELS_VERSION);
#endif
#ifdef NACRE_CHOLMOD_VERSION
    b.libraries.emplace_back("CHOLMOD", NACRE_CHOLMOD_VERSION);
#endif
#ifdef NACRE_HDF5_VERSION
    b.libraries.emplace_back("HDF5", NACRE_HDF5_VERSION);
#endif
    if (par::has_mpi()) b.libraries.emplace_back("MPI", par::mpi_library());
    return b;
  }();
  return info;
}

std::string version_text() {
  const BuildInfo& b = build_info();
  std::ostringstream s;
  s << "nacre " << b.version << " (commit " << b.commit << ")\n";
  s << "Kokkos " << b.kokkos_version << ": ";
  for (std::size_t k = 0; k < b.backends.size(); ++k) s << (k ? ", " : "") << b.backends[k] << (k == 0 ? " (default)" : "");
  s << "\nlibraries: ";
  if (b.libraries.empty()) s << "none optional";
  for (std::size_t k = 0; k < b.libraries.size(); ++k)
    s << (k ? ", " : "") << b.libraries[k].first << " " << b.libraries[k].second;
  s << "\n";
  return s.str();
}

}  // namespace nacre
