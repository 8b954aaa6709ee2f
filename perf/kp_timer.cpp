// SPDX-License-Identifier: BSD-3-Clause
// Why: Kokkos Tools (space-time-stack, kernel-timer) are not installed in the dev root. This is a
// tool library any nacre run can load (KOKKOS_TOOLS_LIBS=build/openmp/perf/libnacre_kp_timer.so):
// wall time and calls per labelled kernel and per profiling region (Kokkos::Profiling::ScopedRegion,
// nested regions counted in each), printed to stderr at Kokkos' finalize, largest first. The same
// accumulator as nacre bench's and the perf programs' in-process timers (nacre/perf/tool_clock.hpp);
// used for docs/speed_accuracy.md's Newton breakdown.
#include <nacre/perf/tool_clock.hpp>

#include <cstdint>
#include <cstdio>

namespace {
nacre::perf::ToolClock g_clock;

void print(const char* what, const nacre::perf::ToolClock::Table& table) {
  const auto rows = nacre::perf::ToolClock::by_time(table);
  std::fprintf(stderr, "nacre_kp_timer: %s (wall s, calls)\n", what);
  for (std::size_t k = 0; k < rows.size() && k < 30; ++k)
    std::fprintf(stderr, "%12.3f %9ld  %s\n", rows[k].second.seconds, rows[k].second.calls, rows[k].first.c_str());
}
}  // namespace

extern "C" {
void kokkosp_init_library(int, std::uint64_t, std::uint32_t, void*) {}
void kokkosp_finalize_library() {
  print("regions", g_clock.regions());
  print("kernels", g_clock.kernels());
}
void kokkosp_begin_parallel_for(const char* name, std::uint32_t, std::uint64_t* id) { g_clock.begin_kernel(name, id); }
void kokkosp_end_parallel_for(std::uint64_t id) { g_clock.end_kernel(id); }
void kokkosp_begin_parallel_reduce(const char* name, std::uint32_t, std::uint64_t* id) { g_clock.begin_kernel(name, id); }
void kokkosp_end_parallel_reduce(std::uint64_t id) { g_clock.end_kernel(id); }
void kokkosp_begin_parallel_scan(const char* name, std::uint32_t, std::uint64_t* id) { g_clock.begin_kernel(name, id); }
void kokkosp_end_parallel_scan(std::uint64_t id) { g_clock.end_kernel(id); }
void kokkosp_push_profile_region(const char* name) { g_clock.push_region(name); }
void kokkosp_pop_profile_region() { g_clock.pop_region(); }
}
