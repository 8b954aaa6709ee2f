// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The machine's two bounds that nacre's timings are read against, measured in the same
/// run on the same execution-space instance: a STREAM triad a = b + s c (the streaming rate; 3
/// arrays of doubles counted) and independent FMA chains (the arithmetic rate). One
/// implementation for `nacre bench` and every perf program, so their "fraction of the bound"
/// columns mean the same.
#include <Kokkos_Core.hpp>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstddef>

namespace nacre::perf {

struct Triad {
  double bytes_per_s = 0;      ///< best of the repeats, by wall time
  double cpu_bytes_per_s = 0;  ///< best by process CPU time per thread (robust on a shared machine)
};

/// \brief Process CPU time (user + system, every thread), s.
inline double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// \brief The triad over `n` doubles per array on `space`, best of `repeats` (after one untimed
/// pass that touches the pages).
template <class ExecutionSpace>
Triad triad(const ExecutionSpace& space, std::size_t n, int repeats) {
  using Mem = typename ExecutionSpace::memory_space;
  using V = Kokkos::View<double*, Mem>;  // contiguous: unit-stride on every backend
  V a(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::perf::triad_a"), n);
  V b(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::perf::triad_b"), n);
  V c(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::perf::triad_c"), n);
  const Kokkos::RangePolicy<ExecutionSpace, Kokkos::IndexType<std::size_t>> range(space, 0, n);
  Kokkos::parallel_for("nacre::perf::triad_init", range, KOKKOS_LAMBDA(const std::size_t i) {
    a(i) = 0, b(i) = 1.0 + 1e-9 * static_cast<double>(i), c(i) = 2.0;
  });
  space.fence("nacre::perf::triad_init");
  const double s = 0.5, bytes = 3.0 * 8.0 * static_cast<double>(n);
  double best = 1e300, best_cpu = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = process_cpu_seconds();
    Kokkos::parallel_for("nacre::perf::triad", range, KOKKOS_LAMBDA(const std::size_t i) { a(i) = b(i) + s * c(i); });
    space.fence("nacre::perf::triad");
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    best_cpu = std::min(best_cpu, (process_cpu_seconds() - c0) / std::max(1, space.concurrency()));
  }
  return {bytes / best, best_cpu > 0 ? bytes / best_cpu : 0.0};
}

/// \brief FMA throughput on `space`, flop/s (an FMA counted 2): 8 independent chains per work
/// item, 4096 items per thread of the space, best of `repeats`.
template <class ExecutionSpace>
double fma_flops(const ExecutionSpace& space, int repeats) {
  const int items = std::max(1, space.concurrency()) * 4096, iters = 4096;
  double best = 0;
  for (int r = 0; r < repeats; ++r) {
    double sink = 0;
    space.fence("nacre::perf::fma");
    const auto t0 = std::chrono::steady_clock::now();
    Kokkos::parallel_reduce(
        "nacre::perf::fma", Kokkos::RangePolicy<ExecutionSpace>(space, 0, items),
        KOKKOS_LAMBDA(const int i, double& sum) {
          double x[8];
          for (int k = 0; k < 8; ++k) x[k] = 1e-3 * (i + k);
          for (int it = 0; it < iters; ++it)
            for (int k = 0; k < 8; ++k) x[k] = x[k] * 0.999999 + 1e-7;
          for (int k = 0; k < 8; ++k) sum += x[k];
        },
        sink);
    space.fence("nacre::perf::fma");
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (sink != 0) best = std::max(best, 2.0 * 8.0 * double(items) * iters / t);
  }
  return best;
}

}  // namespace nacre::perf
