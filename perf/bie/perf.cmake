# SPDX-License-Identifier: BSD-3-Clause
# Chapter 4 experiments for UE / BE / BIE (issue 8), included from perf/CMakeLists.txt.
# Driver: perf/bie/run_bie_bench.sh; charts: perf/bie/plot_bie.py; results: perf/results/bie*/.
add_executable(nacre_perf_bie ${CMAKE_CURRENT_LIST_DIR}/bie_bench.cpp)
target_link_libraries(nacre_perf_bie PRIVATE nacre_lib nacre_warnings CLI11::CLI11)
add_executable(nacre_perf_bie_penalty ${CMAKE_CURRENT_LIST_DIR}/bie_penalty.cpp)
target_link_libraries(nacre_perf_bie_penalty PRIVATE nacre_lib nacre_warnings CLI11::CLI11)
