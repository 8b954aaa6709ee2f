// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Why: Kokkos Tools (space-time-stack) are not installed in the dev root, but Kokkos core lets a
// program register the tool callbacks itself. This header times every labelled kernel
// (parallel_for / reduce / scan) and deep copy by name, so a benchmark can say which kernel of a
// step takes the time. Host timing between the begin and end callbacks: exact for the OpenMP and
// Serial backends (their kernels are synchronous); on an asynchronous backend (CUDA) it measures
// the launch only unless CUDA_LAUNCH_BLOCKING=1.
//
//   nacre::perf::KernelTimer::start();   ... run ...   auto t = nacre::perf::KernelTimer::stop();
#include <Kokkos_Core.hpp>

#include <time.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace nacre::perf {

class KernelTimer {
 public:
  struct Entry {
    double seconds = 0;      ///< wall
    double cpu_seconds = 0;  ///< CPU time of the calling thread (robust on a loaded machine; 1 thread only)
    long calls = 0;
  };

  /// CPU time of the calling thread, s.
  static double thread_cpu() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  using Table = std::map<std::string, Entry>;

  /// Register the callbacks and clear the table.
  static void start() {
    auto& s = state();
    s.table.clear();
    s.open.clear();
    namespace T = Kokkos::Tools::Experimental;
    T::set_begin_parallel_for_callback(&begin);
    T::set_end_parallel_for_callback(&end);
    T::set_begin_parallel_reduce_callback(&begin);
    T::set_end_parallel_reduce_callback(&end);
    T::set_begin_parallel_scan_callback(&begin);
    T::set_end_parallel_scan_callback(&end);
    T::set_begin_deep_copy_callback(&begin_copy);
    T::set_end_deep_copy_callback(&end_copy);
  }

  /// Unregister and return seconds and calls per kernel name (deep copies as "deep_copy").
  static Table stop() {
    namespace T = Kokkos::Tools::Experimental;
    T::set_begin_parallel_for_callback(nullptr);
    T::set_end_parallel_for_callback(nullptr);
    T::set_begin_parallel_reduce_callback(nullptr);
    T::set_end_parallel_reduce_callback(nullptr);
    T::set_begin_parallel_scan_callback(nullptr);
    T::set_end_parallel_scan_callback(nullptr);
    T::set_begin_deep_copy_callback(nullptr);
    T::set_end_deep_copy_callback(nullptr);
    return state().table;
  }

 private:
  using clock = std::chrono::steady_clock;
  struct Open {
    std::string name;
    clock::time_point t0;
    double c0 = 0;
  };
  struct State {
    Table table;
    std::vector<Open> open;  // kernel ids index this (kernels do not nest on the host backends)
    Open copy;
  };
  static State& state() {
    static State s;
    return s;
  }
  static void begin(const char* name, const std::uint32_t, std::uint64_t* id) {
    auto& s = state();
    *id = s.open.size();
    s.open.push_back({name, clock::now(), thread_cpu()});
  }
  static void end(std::uint64_t id) {
    auto& s = state();
    const auto t1 = clock::now();
    const double c1 = thread_cpu();
    if (id >= s.open.size()) return;
    auto& e = s.table[s.open[id].name];
    e.seconds += std::chrono::duration<double>(t1 - s.open[id].t0).count();
    e.cpu_seconds += c1 - s.open[id].c0;
    ++e.calls;
    s.open.resize(id);
  }
  static void begin_copy(Kokkos::Tools::SpaceHandle, const char*, const void*, Kokkos::Tools::SpaceHandle,
                         const char*, const void*, std::uint64_t) {
    state().copy = {"deep_copy", clock::now(), thread_cpu()};
  }
  static void end_copy() {
    auto& s = state();
    auto& e = s.table["deep_copy"];
    e.seconds += std::chrono::duration<double>(clock::now() - s.copy.t0).count();
    e.cpu_seconds += thread_cpu() - s.copy.c0;
    ++e.calls;
  }
};

}  // namespace nacre::perf
