// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief A ToolClock fed by Kokkos Tools callbacks that this process registers for the timer's
/// lifetime (no tool library to install): `ToolTimer t(ToolTimer::kernels | ToolTimer::regions);
/// ... run ...; t.clock().kernels()`. One at a time (the callbacks are process-wide).
#include <nacre/perf/tool_clock.hpp>

#include <Kokkos_Core.hpp>

namespace nacre::perf {

class ToolTimer {
public:
  enum What : unsigned { kernels = 1, regions = 2 };

  explicit ToolTimer(unsigned what) : what_(what) {
    active() = &clock_;
    namespace T = Kokkos::Tools::Experimental;
    if (what_ & kernels) {
      T::set_begin_parallel_for_callback(&begin);
      T::set_end_parallel_for_callback(&end);
      T::set_begin_parallel_reduce_callback(&begin);
      T::set_end_parallel_reduce_callback(&end);
      T::set_begin_parallel_scan_callback(&begin);
      T::set_end_parallel_scan_callback(&end);
      T::set_begin_deep_copy_callback(&begin_copy);
      T::set_end_deep_copy_callback(&end_copy);
    }
    if (what_ & regions) {
      T::set_push_region_callback(&push);
      T::set_pop_region_callback(&pop);
    }
  }
  ~ToolTimer() {
    namespace T = Kokkos::Tools::Experimental;
    if (what_ & kernels) {
      T::set_begin_parallel_for_callback(nullptr);
      T::set_end_parallel_for_callback(nullptr);
      T::set_begin_parallel_reduce_callback(nullptr);
      T::set_end_parallel_reduce_callback(nullptr);
      T::set_begin_parallel_scan_callback(nullptr);
      T::set_end_parallel_scan_callback(nullptr);
      T::set_begin_deep_copy_callback(nullptr);
      T::set_end_deep_copy_callback(nullptr);
    }
    if (what_ & regions) {
      T::set_push_region_callback(nullptr);
      T::set_pop_region_callback(nullptr);
    }
    active() = nullptr;
  }
  ToolTimer(const ToolTimer&) = delete;
  ToolTimer& operator=(const ToolTimer&) = delete;

  /// \brief What was timed so far (deep copies as the kernel "deep_copy").
  [[nodiscard]] const ToolClock& clock() const { return clock_; }

private:
  static ToolClock*& active() {
    static ToolClock* c = nullptr;
    return c;
  }
  static void begin(const char* name, std::uint32_t, std::uint64_t* id) {
    if (active()) active()->begin_kernel(name, id);
  }
  static void end(std::uint64_t id) {
    if (active()) active()->end_kernel(id);
  }
  static void begin_copy(Kokkos::Tools::SpaceHandle, const char*, const void*, Kokkos::Tools::SpaceHandle, const char*,
                         const void*, std::uint64_t) {
    if (active()) active()->begin_kernel("deep_copy", &copy_id());
  }
  static void end_copy() {
    if (active()) active()->end_kernel(copy_id());
  }
  static std::uint64_t& copy_id() {
    static std::uint64_t id = 0;
    return id;
  }
  static void push(const char* name) {
    if (active()) active()->push_region(name);
  }
  static void pop() {
    if (active()) active()->pop_region();
  }
  unsigned what_;
  ToolClock clock_;
};

}  // namespace nacre::perf
