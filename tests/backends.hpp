#pragma once
// The host backends of the installed Kokkos, as a type list for Catch2's
// TEMPLATE_LIST_TEST_CASE (Cabana style): a test written once runs on Kokkos::Serial and on
// Kokkos::OpenMP where the installed Kokkos enables them (Debian's 5.2 has OpenMP only; a
// Serial+OpenMP build, e.g. Kokkos 4.6, runs both).
#include <Kokkos_Core.hpp>

#include <string>
#include <tuple>

namespace nacre::test {

#ifdef KOKKOS_ENABLE_SERIAL
using SerialBackend = std::tuple<Kokkos::Serial>;
#else
using SerialBackend = std::tuple<>;
#endif
#ifdef KOKKOS_ENABLE_OPENMP
using OpenMPBackend = std::tuple<Kokkos::OpenMP>;
#else
using OpenMPBackend = std::tuple<>;
#endif

/// \brief Enabled host execution spaces.
using HostBackends = decltype(std::tuple_cat(std::declval<SerialBackend>(), std::declval<OpenMPBackend>()));

/// \brief Names of the enabled host backends, for the log of a test run.
inline std::string host_backend_names() {
  std::string s;
#ifdef KOKKOS_ENABLE_SERIAL
  s += "Serial ";
#endif
#ifdef KOKKOS_ENABLE_OPENMP
  s += "OpenMP ";
#endif
  return s;
}

}  // namespace nacre::test
