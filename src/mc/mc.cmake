# SPDX-License-Identifier: BSD-3-Clause
# Build options of the Monte Carlo sweep (src/mc). Included from src/CMakeLists.txt after
# nacre_lib is defined.
include_guard(GLOBAL)

# The sweep (include/nacre/mc/kernels.hpp) is instantiated for the solver in src/mc/solver.cpp
# only. With NACRE_MC_BATCHED it evaluates 8 same-colour bricks side by side on a host
# (BatchedTrials); -march=native on that one source lets those lanes use the machine's widest
# vectors (AVX-512: one register).
# -ffp-contract=off keeps the compiler from fusing a multiply and an add into an FMA, so every
# operation rounds as in the portable (x86-64 baseline) build: the native source gives the same
# bits as the portable one (perf/results/mc/sweep_simd/ compares energy_after; the thread-count
# fingerprints do not move). OFF by default: it only pays together with NACRE_MC_BATCHED (the
# scalar sweep runs at the same rate with it, 0.96-1.11x), and a binary built with it needs the
# build machine's instruction set.
option(NACRE_MC_NATIVE "Compile the MC solver (src/mc/solver.cpp) with -march=native -ffp-contract=off (host builds)"
       OFF)
# ON: the solver's host sweeps evaluate kSweepLanes same-colour work items side by side
# (mc::BatchedTrials, include/nacre/mc/kernels.hpp); same bits as the default ScalarTrials. OFF by
# default: on the CPU it was measured on it is slower than the scalar sweep at 300k bricks and
# only faster at 10k (perf/results/mc/sweep_simd/).
option(NACRE_MC_BATCHED "Host sweeps evaluate kSweepLanes same-colour bricks side by side (BatchedTrials)" OFF)

if(TARGET nacre_lib)
  set(_nacre_mc_opts "")
  if(NACRE_MC_NATIVE)
    if(Kokkos_ENABLE_CUDA OR Kokkos_ENABLE_HIP OR Kokkos_ENABLE_SYCL OR Kokkos_ENABLE_OPENMPTARGET)
      message(FATAL_ERROR "nacre: NACRE_MC_NATIVE is for host builds (the device compiler gets no -march)")
    endif()
    include(CheckCXXCompilerFlag)
    check_cxx_compiler_flag(-march=native NACRE_CXX_HAS_MARCH_NATIVE)
    if(NACRE_CXX_HAS_MARCH_NATIVE)
      list(APPEND _nacre_mc_opts -march=native -mprefer-vector-width=512 -ffp-contract=off)
      message(STATUS "nacre: MC sweep built with -march=native -ffp-contract=off (NACRE_MC_NATIVE=ON)")
    else()
      message(STATUS "nacre: compiler lacks -march=native; the MC sweep uses the baseline vector width")
    endif()
  endif()
  # sqrt without errno (its value is the same correctly rounded one): otherwise every square
  # root in the batched trial keeps a branch to the library call and the lane loop cannot be
  # vectorised. Host builds with a GNU-style compiler only.
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang" AND NOT Kokkos_ENABLE_CUDA AND NOT Kokkos_ENABLE_HIP
     AND NOT Kokkos_ENABLE_SYCL AND NOT Kokkos_ENABLE_OPENMPTARGET)
    list(APPEND _nacre_mc_opts -fno-math-errno)
  endif()
  # the flags, for tests that must run the same vector code (tests/test_mc_batched.cpp)
  set(NACRE_MC_SWEEP_OPTIONS "${_nacre_mc_opts}" CACHE INTERNAL "compile options of the MC sweep's source")
  if(_nacre_mc_opts)
    set_source_files_properties(${PROJECT_SOURCE_DIR}/src/mc/solver.cpp TARGET_DIRECTORY nacre_lib
                                PROPERTIES COMPILE_OPTIONS "${_nacre_mc_opts}")
  endif()
  if(NACRE_MC_BATCHED)
    set_source_files_properties(${PROJECT_SOURCE_DIR}/src/mc/solver.cpp TARGET_DIRECTORY nacre_lib
                                PROPERTIES COMPILE_DEFINITIONS NACRE_MC_BATCHED_SWEEP)
  endif()
endif()
