// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Time per labelled kernel and per profiling region, from Kokkos Tools events: the one
/// accumulator behind every timer of nacre (nacre bench's phases, the perf programs' kernel
/// tables, and the tool library perf/kp_timer.cpp that any run can load). No Kokkos here: the tool
/// library is loaded by Kokkos and links nothing of it. Host timing between the begin and end
/// events: exact on the OpenMP and Serial backends (synchronous kernels); on an asynchronous
/// backend (CUDA) a kernel's entry times its launch unless CUDA_LAUNCH_BLOCKING=1, while a region
/// that ends in a fence times its work.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace nacre::perf {

class ToolClock {
public:
  struct Entry {
    double seconds = 0;      ///< wall
    double cpu_seconds = 0;  ///< CPU time of the calling thread (robust on a loaded machine; one thread's)
    long calls = 0;
  };
  using Table = std::map<std::string, Entry>;

  /// \brief CPU time of the calling thread, s.
  static double thread_cpu() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }

  /// \brief A kernel (parallel_for / reduce / scan) or deep copy begins; `id` names it for end.
  void begin_kernel(const char* name, std::uint64_t* id) {
    *id = kernels_open_.size();
    kernels_open_.push_back({name, clock::now(), thread_cpu()});
  }
  void end_kernel(std::uint64_t id) {
    if (id >= kernels_open_.size()) return;
    close(kernels_open_[id], kernels_);
    kernels_open_.resize(id);  // kernels do not nest on the host backends
  }
  /// \brief Profiling regions (Kokkos::Profiling::ScopedRegion) nest: each counts its inner ones.
  void push_region(const char* name) { regions_open_.push_back({name, clock::now(), thread_cpu()}); }
  void pop_region() {
    if (regions_open_.empty()) return;
    close(regions_open_.back(), regions_);
    regions_open_.pop_back();
  }
  void clear() { *this = ToolClock{}; }

  [[nodiscard]] const Table& kernels() const { return kernels_; }
  [[nodiscard]] const Table& regions() const { return regions_; }
  /// \brief A table's entries, largest wall time first.
  [[nodiscard]] static std::vector<std::pair<std::string, Entry>> by_time(const Table& t) {
    std::vector<std::pair<std::string, Entry>> rows(t.begin(), t.end());
    std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.second.seconds > b.second.seconds; });
    return rows;
  }

private:
  using clock = std::chrono::steady_clock;
  struct Open {
    std::string name;
    clock::time_point t0;
    double c0 = 0;
  };
  static void close(const Open& o, Table& table) {
    Entry& e = table[o.name];
    e.seconds += std::chrono::duration<double>(clock::now() - o.t0).count();
    e.cpu_seconds += thread_cpu() - o.c0;
    ++e.calls;
  }
  Table kernels_, regions_;
  std::vector<Open> kernels_open_, regions_open_;
};

}  // namespace nacre::perf
