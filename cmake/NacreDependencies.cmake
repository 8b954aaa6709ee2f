# Third-party libraries. Each one is a Debian package in the dev root; on other machines
# (Spack, modules) the usual CMake config/find modules locate them.
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(HDF5 REQUIRED COMPONENTS C)

# toml++ and CLI11 are header-only; prefer their CMake packages, fall back to the headers.
find_package(tomlplusplus 3 QUIET CONFIG)
if(NOT TARGET tomlplusplus::tomlplusplus)
  find_path(NACRE_TOMLPP_INCLUDE toml++/toml.hpp REQUIRED)
  add_library(tomlplusplus::tomlplusplus INTERFACE IMPORTED)
  target_include_directories(tomlplusplus::tomlplusplus INTERFACE ${NACRE_TOMLPP_INCLUDE})
endif()
find_package(CLI11 2 QUIET CONFIG)
if(NOT TARGET CLI11::CLI11)
  find_path(NACRE_CLI11_INCLUDE CLI/CLI.hpp REQUIRED)
  add_library(CLI11::CLI11 INTERFACE IMPORTED)
  target_include_directories(CLI11::CLI11 INTERFACE ${NACRE_CLI11_INCLUDE})
endif()

# Optional: Kokkos Kernels (not obtainable matched with Kokkos 5 OpenMP on Debian; never required).
find_package(KokkosKernels QUIET CONFIG)
if(KokkosKernels_FOUND)
  message(STATUS "nacre: Kokkos Kernels found")
endif()
