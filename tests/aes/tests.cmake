# SPDX-License-Identifier: BSD-3-Clause
# Tests of nacre's bitsliced AES and the AES random-number sources (included from
# tests/CMakeLists.txt; sources of nacre_add_test are relative to tests/).
include(${PROJECT_SOURCE_DIR}/src/aes/aes.cmake)
find_package(OpenSSL REQUIRED COMPONENTS Crypto)

set(_nacre_aes_env "${NACRE_TEST_ENV};NACRE_SOURCE_DIR=${PROJECT_SOURCE_DIR}")

# Cipher: FIPS-197 vectors, the circuit, OpenSSL equality. Generators: determinism,
# independence, uniformity and serial-correlation smoke tests (label rng). Each is registered for
# the default thread count by nacre_add_test and again for 1 and 2 threads explicitly.
nacre_add_test(test_aes LABELS aes SOURCES aes/test_aes.cpp LIBS OpenSSL::Crypto)
nacre_add_test(test_aes_sources LABELS aes rng SOURCES aes/test_aes_sources.cpp LIBS OpenSSL::Crypto)
# The cipher compiled like src/aes (-march=native): the x86 GFNI transposition where the build
# machine has it, checked against the portable path and OpenSSL.
nacre_add_test(test_aes_native LABELS aes SOURCES aes/test_aes_native.cpp LIBS OpenSSL::Crypto)
if(NACRE_AES_NATIVE AND NACRE_CXX_HAS_MARCH_NATIVE)
  target_compile_options(test_aes_native PRIVATE -march=native)
  include(CheckCXXSourceCompiles)
  set(CMAKE_REQUIRED_FLAGS -march=native)
  check_cxx_source_compiles("#if !(defined(__GFNI__) && defined(__AVX512BW__) && defined(__AVX512VBMI__))
#error no GFNI
#endif
int main() { return 0; }" NACRE_AES_HAS_GFNI)
  unset(CMAKE_REQUIRED_FLAGS)
  if(NACRE_AES_HAS_GFNI)
    message(STATUS "nacre: AES uses the GFNI transposition (x86 AVX-512 + GFNI); test_aes_native checks it")
  else()
    message(STATUS "nacre: no GFNI on this build machine: AES uses the portable transposition")
  endif()
endif()
# (nacre_add_test labels the default-thread cases "aes"; these the 1- and 2-thread ones; the
# sources' cases also "rng")
foreach(_t 1 2)
  nacre_discover_tiers(test_aes "aes" LIST nacre_test_aes_${_t}t SUFFIX " [${_t} thread(s)]"
    EXTRA_ARGS --kokkos-num-threads=${_t})
  nacre_discover_tiers(test_aes_sources "aes;rng" LIST nacre_test_aes_sources_${_t}t SUFFIX " [${_t} thread(s)]"
    EXTRA_ARGS --kokkos-num-threads=${_t})
endforeach()

# Constant time under valgrind memcheck: key and plaintext are marked undefined; memcheck
# reports any conditional jump or memory address computed from them. nacre's AES must pass,
# a deliberately table-based AES in the same program must be caught. ct_check is built without
# -march flags and without nacre_lib (valgrind does not decode AVX-512); it needs only headers.
find_program(NACRE_VALGRIND valgrind)
if(NACRE_SANITIZE)
  # valgrind cannot run AddressSanitizer binaries (both replace the allocator and shadow memory);
  # the constant-time property is checked by the regular build's suite.
  message(STATUS "nacre: sanitizer build (${NACRE_SANITIZE}): AES constant-time tests under valgrind skipped")
  set(NACRE_VALGRIND OFF)
endif()
add_executable(nacre_aes_ct_check ${CMAKE_CURRENT_LIST_DIR}/ct_check.cpp)
target_link_libraries(nacre_aes_ct_check PRIVATE Kokkos::kokkos nacre_warnings)
target_include_directories(nacre_aes_ct_check PRIVATE ${PROJECT_SOURCE_DIR}/include)
if(NACRE_VALGRIND)
  set(_vg ${NACRE_VALGRIND} --tool=memcheck --error-exitcode=1 --track-origins=yes)
  add_test(NAME aes_constant_time_nacre COMMAND ${_vg} $<TARGET_FILE:nacre_aes_ct_check> nacre)
  # The table variant must make memcheck fail: the wrapper passes only on exit code 1 together
  # with memcheck's "Use of uninitialised value" / "Conditional jump" report.
  add_test(NAME aes_constant_time_table_is_caught
           COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/expect_memcheck_error.sh
                   ${_vg} $<TARGET_FILE:nacre_aes_ct_check> table)
  set_tests_properties(aes_constant_time_nacre aes_constant_time_table_is_caught PROPERTIES
    LABELS "aes;constant-time;quick" ENVIRONMENT "${_nacre_aes_env}" TIMEOUT 120)
elseif(NOT NACRE_SANITIZE)
  message(WARNING "nacre: valgrind not found; the AES constant-time tests are not registered")
endif()
