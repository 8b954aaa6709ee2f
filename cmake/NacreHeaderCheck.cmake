# SPDX-License-Identifier: BSD-3-Clause
# NACRE_HEADER_CHECK (CI's default build): every public header compiled alone, twice in one
# translation unit, so a header that leans on what its includer happened to include first, or
# whose guard is missing, fails the build. One object per header at -O0 (the check is about
# declarations, not code); headers that need HDF5 or nlohmann-json (io) get their include paths.
option(NACRE_HEADER_CHECK "Compile every public header on its own (CI)" OFF)
if(NACRE_HEADER_CHECK)
  file(GLOB_RECURSE _nacre_headers RELATIVE "${PROJECT_SOURCE_DIR}/include" CONFIGURE_DEPENDS
       "${PROJECT_SOURCE_DIR}/include/nacre/*.hpp")
  set(_nacre_header_sources)
  foreach(_h IN LISTS _nacre_headers)
    string(MAKE_C_IDENTIFIER "${_h}" _id)
    set(_f "${CMAKE_BINARY_DIR}/header_check/${_id}.cpp")
    file(CONFIGURE OUTPUT "${_f}" CONTENT "#include <${_h}>\n#include <${_h}>  // twice: the guard holds\n" @ONLY)
    list(APPEND _nacre_header_sources "${_f}")
  endforeach()
  add_library(nacre_header_check OBJECT ${_nacre_header_sources})
  target_link_libraries(nacre_header_check PRIVATE nacre_lib nacre_warnings HDF5::HDF5)
  if(TARGET nlohmann_json::nlohmann_json)
    target_link_libraries(nacre_header_check PRIVATE nlohmann_json::nlohmann_json)
  endif()
  target_compile_options(nacre_header_check PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-O0>)
  list(LENGTH _nacre_headers _n)
  message(STATUS "nacre: header check of ${_n} public headers (NACRE_HEADER_CHECK)")
endif()
