# SPDX-License-Identifier: BSD-3-Clause
# Build option of the dynamics kernels (src/dyn). Included from src/CMakeLists.txt after nacre_lib
# is defined.
include_guard(GLOBAL)

# The UE/BE/BIE kernels are instantiated in src/dyn/simulation.cpp only (Simulation is a pimpl),
# so -march=native on that one source lets the compiler use the machine's widest vectors and FMA
# for them (the tiled element apply and BIE's J^-1 product run over kTile elements in the
# innermost loop). OFF by default: FMA contraction changes rounding, so a native build's numbers
# are not bit-for-bit those of the default build (the tests compare paths within one build);
# benchmarks report it as a separate row (docs/dynamics.md). Host builds only, as NACRE_AES_NATIVE.
option(NACRE_DYN_NATIVE "Compile the dynamics kernels (src/dyn/simulation.cpp) with -march=native (host builds)" OFF)

if(NACRE_DYN_NATIVE AND TARGET nacre_lib)
  if(Kokkos_ENABLE_CUDA OR Kokkos_ENABLE_HIP OR Kokkos_ENABLE_SYCL OR Kokkos_ENABLE_OPENMPTARGET)
    message(FATAL_ERROR "nacre: NACRE_DYN_NATIVE is for host builds (the device compiler gets no -march)")
  endif()
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag(-march=native NACRE_CXX_HAS_MARCH_NATIVE)
  if(NOT NACRE_CXX_HAS_MARCH_NATIVE)
    message(FATAL_ERROR "nacre: NACRE_DYN_NATIVE=ON but the compiler lacks -march=native")
  endif()
  set_source_files_properties(${PROJECT_SOURCE_DIR}/src/dyn/simulation.cpp TARGET_DIRECTORY nacre_lib
                              PROPERTIES COMPILE_OPTIONS "-march=native")
  message(STATUS "nacre: dynamics kernels built with -march=native (NACRE_DYN_NATIVE=ON)")
endif()
