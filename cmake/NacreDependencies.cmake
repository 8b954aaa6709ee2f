# SPDX-License-Identifier: BSD-3-Clause
# A header-only library without its CMake package: an imported target over the directory that
# holds HEADER (toml++, CLI11, nlohmann-json).
function(nacre_header_only target var header)
  if(NOT TARGET ${target})
    find_path(${var} ${header} REQUIRED)
    add_library(${target} INTERFACE IMPORTED GLOBAL)
    target_include_directories(${target} INTERFACE ${${var}})
  endif()
endfunction()

# Third-party libraries. Each one is a Debian package in the dev root; on other machines
# (Spack, modules) the usual CMake config/find modules locate them.
if(NACRE_BENCHMARKS_ONLY)
  # the core library names these targets; what needs them (deck parser, HDF5 output, app) is
  # left out of the build (src/CMakeLists.txt), so empty stand-ins do where they are missing
  # Eigen (header-only) is needed by the dynamics (BIE's J^-1 at start-up): a CMake package, or
  # the headers the GPU bundle carries (perf/gpu/pack.sh: NACRE_EIGEN_INCLUDE=vendor/include/eigen3)
  find_package(Eigen3 3.3 QUIET NO_MODULE)
  if(NOT TARGET Eigen3::Eigen)
    find_path(NACRE_EIGEN_INCLUDE Eigen/Dense PATH_SUFFIXES eigen3 REQUIRED)
    add_library(Eigen3::Eigen INTERFACE IMPORTED)
    target_include_directories(Eigen3::Eigen SYSTEM INTERFACE ${NACRE_EIGEN_INCLUDE})
  endif()
  foreach(_t HDF5::HDF5 tomlplusplus::tomlplusplus)
    if(NOT TARGET ${_t})
      add_library(${_t} INTERFACE IMPORTED)
    endif()
  endforeach()
  message(STATUS "nacre: benchmarks-only build: no deck parser, HDF5 output, app or tests")
else()
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(HDF5 REQUIRED COMPONENTS C)

# toml++ and CLI11 are header-only; prefer their CMake packages, fall back to the headers.
find_package(tomlplusplus 3 QUIET CONFIG)
nacre_header_only(tomlplusplus::tomlplusplus NACRE_TOMLPP_INCLUDE toml++/toml.hpp)
endif()
find_package(CLI11 2 QUIET CONFIG)
nacre_header_only(CLI11::CLI11 NACRE_CLI11_INCLUDE CLI/CLI.hpp)

# Optional: Kokkos Kernels, header-only use (the dev root builds it: devenv/nacre-env; elsewhere
# a Spack or hand install is found through KokkosKernels_ROOT / CMAKE_PREFIX_PATH). Without it
# nacre builds and runs fully; the "kokkos-d1" colouring and its tests and benchmark are skipped.
option(NACRE_ENABLE_KOKKOSKERNELS "Use Kokkos Kernels when it is found" ON)
if(NACRE_ENABLE_KOKKOSKERNELS)
  find_package(KokkosKernels CONFIG QUIET)
endif()
if(KokkosKernels_FOUND)
  message(STATUS "nacre: Kokkos Kernels ${KokkosKernels_VERSION} found in ${KokkosKernels_DIR}: "
                 "colouring strategy 'kokkos-d1', its tests and perf/colouring_compare are built")
else()
  message(STATUS "nacre: Kokkos Kernels not found (set KokkosKernels_ROOT to use it): SKIPPING the "
                 "'kokkos-d1' colouring strategy, test_kokkos_kernels and nacre_perf_colouring")
endif()

# Optional: CHOLMOD (SuiteSparse) for the Newton preconditioner's sparse Cholesky, supernodal with
# a nested-dissection ordering; without it Eigen's SimplicialLLT (AMD ordering) factorises.
option(NACRE_ENABLE_CHOLMOD "Use CHOLMOD for the Newton factor when it is found" ON)
if(NACRE_ENABLE_CHOLMOD AND NOT NACRE_BENCHMARKS_ONLY)
  enable_language(C)  # CHOLMOD's package looks for OpenMP's C component
  find_package(CHOLMOD CONFIG QUIET)
endif()
if(CHOLMOD_FOUND)
  message(STATUS "nacre: CHOLMOD ${CHOLMOD_VERSION} found: the Newton factor is supernodal (METIS order)")
else()
  message(STATUS "nacre: CHOLMOD not found (set CHOLMOD_ROOT to use it): the Newton factor is Eigen's SimplicialLLT")
endif()

# nlohmann-json (header-only) for summary.json: its CMake package, or the headers (the
# benchmarks-only build leaves the outputs out: src/CMakeLists.txt).
if(NOT NACRE_BENCHMARKS_ONLY)
  find_package(nlohmann_json 3 QUIET CONFIG)
  nacre_header_only(nlohmann_json::nlohmann_json NACRE_NLOHMANN_INCLUDE nlohmann/json.hpp)
endif()
