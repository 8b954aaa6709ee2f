# SPDX-License-Identifier: BSD-3-Clause
# Build options of nacre's bitsliced AES (src/aes). Included from src/CMakeLists.txt after
# nacre_lib is defined (tests/aes/tests.cmake and perf/aes/perf.cmake include it too, guarded).
include_guard(GLOBAL)

# The bitsliced word is as wide as the widest SIMD register the compiler targets (see
# include/nacre/aes/bitsliced.hpp): with -march=native on an AVX-512 machine that is 512 bits
# (512 blocks per thread), with the x86-64 baseline only 128. The flag goes on the AES sources
# only; everything still compiles (and is correct) without it.
set(_nacre_aes_native_default ON)
if(CMAKE_CROSSCOMPILING OR Kokkos_ENABLE_CUDA OR Kokkos_ENABLE_HIP OR Kokkos_ENABLE_SYCL
   OR Kokkos_ENABLE_OPENMPTARGET)
  set(_nacre_aes_native_default OFF)
endif()
option(NACRE_AES_NATIVE "Compile nacre's AES sources with -march=native (host builds)"
       ${_nacre_aes_native_default})

if(NACRE_AES_NATIVE AND TARGET nacre_lib)
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag(-march=native NACRE_CXX_HAS_MARCH_NATIVE)
  if(NACRE_CXX_HAS_MARCH_NATIVE)
    set_source_files_properties(
      ${PROJECT_SOURCE_DIR}/src/aes/aes128.cpp ${PROJECT_SOURCE_DIR}/src/rng/aes_sources.cpp
      TARGET_DIRECTORY nacre_lib
      PROPERTIES COMPILE_OPTIONS "-march=native")
    message(STATUS "nacre: AES sources built with -march=native (NACRE_AES_NATIVE=ON)")
  else()
    message(STATUS "nacre: compiler lacks -march=native; AES uses the baseline vector width")
  endif()
endif()
