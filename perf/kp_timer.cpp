// SPDX-License-Identifier: BSD-3-Clause
// Why: Kokkos Tools (space-time-stack, kernel-timer) are not installed in the dev root, and
// perf/kernel_timer.hpp only serves a benchmark that registers it. This is a tool library any
// nacre run can load (KOKKOS_TOOLS_LIBS=build/openmp/perf/libnacre_kp_timer.so): wall time and
// calls per labelled kernel and per profiling region (Kokkos::Profiling::ScopedRegion, nested
// regions counted in each), printed to stderr at Kokkos' finalize, largest first. Host timing
// between the callbacks: exact on OpenMP and Serial (synchronous kernels); on CUDA it times the
// launch unless CUDA_LAUNCH_BLOCKING=1. Used for docs/speed_accuracy.md's Newton breakdown.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {
using Clock = std::chrono::steady_clock;
struct Entry {
  double seconds = 0;
  long calls = 0;
};
struct Open {
  std::string name;
  Clock::time_point t0;
};
std::map<std::string, Entry> kernels, regions;
std::vector<Open> open_kernels, open_regions;  // kernels do not nest on the host backends

void close(Open& o, std::map<std::string, Entry>& table) {
  Entry& e = table[o.name];
  e.seconds += std::chrono::duration<double>(Clock::now() - o.t0).count();
  ++e.calls;
}
void print(const char* what, const std::map<std::string, Entry>& table) {
  std::vector<std::pair<std::string, Entry>> rows(table.begin(), table.end());
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.second.seconds > b.second.seconds; });
  std::fprintf(stderr, "nacre_kp_timer: %s (wall s, calls)\n", what);
  for (std::size_t k = 0; k < rows.size() && k < 30; ++k)
    std::fprintf(stderr, "%12.3f %9ld  %s\n", rows[k].second.seconds, rows[k].second.calls, rows[k].first.c_str());
}
void begin(const char* name, std::uint64_t* id) {
  *id = open_kernels.size();
  open_kernels.push_back({name, Clock::now()});
}
void end(std::uint64_t id) {
  if (id >= open_kernels.size()) return;
  close(open_kernels[id], kernels);
  open_kernels.resize(id);
}
}  // namespace

extern "C" {
void kokkosp_init_library(int, std::uint64_t, std::uint32_t, void*) {}
void kokkosp_finalize_library() {
  print("regions", regions);
  print("kernels", kernels);
}
void kokkosp_begin_parallel_for(const char* name, std::uint32_t, std::uint64_t* id) { begin(name, id); }
void kokkosp_end_parallel_for(std::uint64_t id) { end(id); }
void kokkosp_begin_parallel_reduce(const char* name, std::uint32_t, std::uint64_t* id) { begin(name, id); }
void kokkosp_end_parallel_reduce(std::uint64_t id) { end(id); }
void kokkosp_begin_parallel_scan(const char* name, std::uint32_t, std::uint64_t* id) { begin(name, id); }
void kokkosp_end_parallel_scan(std::uint64_t id) { end(id); }
void kokkosp_push_profile_region(const char* name) { open_regions.push_back({name, Clock::now()}); }
void kokkosp_pop_profile_region() {
  if (open_regions.empty()) return;
  close(open_regions.back(), regions);
  open_regions.pop_back();
}
}
