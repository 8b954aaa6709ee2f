# SPDX-License-Identifier: BSD-3-Clause
# Benchmarks of nacre's bitsliced AES and the AES random-number sources (included from
# perf/CMakeLists.txt). Driver scripts: perf/aes/run_aes_bench.sh, perf/aes/run_dieharder.sh.
include(${PROJECT_SOURCE_DIR}/src/aes/aes.cmake)
# OpenSSL is the CPU reference; the GPU runbook's bare machines may lack it (then --mode=openssl
# is refused at run time, the nacre and rng modes work).
find_package(OpenSSL COMPONENTS Crypto)
find_path(NACRE_RANDOM123_INCLUDE Random123/philox.h)

if(NACRE_RANDOM123_INCLUDE)
  add_executable(nacre_aes_bench ${CMAKE_CURRENT_LIST_DIR}/aes_bench.cpp)
  target_include_directories(nacre_aes_bench SYSTEM PRIVATE ${NACRE_RANDOM123_INCLUDE})
  target_link_libraries(nacre_aes_bench PRIVATE nacre_lib nacre_warnings)
  if(OpenSSL_FOUND)
    target_link_libraries(nacre_aes_bench PRIVATE OpenSSL::Crypto)
    target_compile_definitions(nacre_aes_bench PRIVATE NACRE_HAVE_OPENSSL)
  else()
    message(STATUS "nacre: OpenSSL not found: nacre_aes_bench without the OpenSSL reference")
  endif()
else()
  message(WARNING "nacre: Random123 headers not found; nacre_aes_bench is not built")
endif()

# Raw generator output for dieharder (-g 200 reads raw binary on stdin).
add_executable(nacre_rng_stream ${CMAKE_CURRENT_LIST_DIR}/rng_stream.cpp)
target_link_libraries(nacre_rng_stream PRIVATE nacre_lib nacre_warnings)

# The bare cipher core on one thread (no Kokkos kernel): build path vs portable transposition and
# the phases, per CPU second. Compiled like src/aes (-march=native under NACRE_AES_NATIVE).
add_executable(nacre_aes_core_bench ${CMAKE_CURRENT_LIST_DIR}/aes_core_bench.cpp)
target_link_libraries(nacre_aes_core_bench PRIVATE Kokkos::kokkos nacre_warnings)
target_include_directories(nacre_aes_core_bench PRIVATE ${PROJECT_SOURCE_DIR}/include)
if(NACRE_AES_NATIVE AND NACRE_CXX_HAS_MARCH_NATIVE)
  target_compile_options(nacre_aes_core_bench PRIVATE -march=native)
endif()
