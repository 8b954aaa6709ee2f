# SPDX-License-Identifier: BSD-3-Clause
# Warnings are on for nacre's own targets (not for third-party headers, included as SYSTEM).
# NACRE_WERROR (CI: the cuda-build of devenv/nacre-env) turns them into errors: the host
# compiler's (-Werror) and, under Kokkos' nvcc_wrapper, nvcc's own (--Werror=all-warnings).
option(NACRE_WERROR "Treat warnings in nacre's code as errors" OFF)
add_library(nacre_warnings INTERFACE)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(nacre_warnings INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow=local>)
  if(NACRE_WERROR)
    target_compile_options(nacre_warnings INTERFACE $<$<COMPILE_LANGUAGE:CXX>:-Werror>)
  endif()
endif()
get_filename_component(_nacre_cxx_name "${CMAKE_CXX_COMPILER}" NAME)
if(NACRE_WERROR AND _nacre_cxx_name STREQUAL "nvcc_wrapper")
  target_compile_options(nacre_warnings INTERFACE $<$<COMPILE_LANGUAGE:CXX>:--Werror=all-warnings>)
endif()
