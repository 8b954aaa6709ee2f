// SPDX-License-Identifier: BSD-3-Clause
// This core's measured peaks, for the bound of the Monte Carlo sweep (perf/README.md, "Bound"):
// double-precision flop rate with the instructions the build may use (independent multiply-add
// chains: the portable x86-64 build has no FMA, -march=native has; 1 lane and the compiler's
// widest vectors) and the streaming read bandwidth of one core. Plain C++ on one thread: a peak
// is a property of the core, not of nacre's kernels.
//
//   nacre_perf_mc_peak            (prints one line per measurement, rates per CPU-second)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <vector>

namespace {
// CPU seconds of this process: on a shared machine the wall clock measures the neighbours; the
// sweep's rates are compared per CPU-second too.
double now() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// 16 independent chains x = x * a + b (2 flops per lane each) in registers: enough chains to
// cover the multiply-add latency. V is a GCC vector type of 1, 4 or 8 doubles.
template <class V>
double flops_rate(long iters) {
  constexpr int C = 16, W = static_cast<int>(sizeof(V) / sizeof(double));
  V x[C];
  for (int c = 0; c < C; ++c)
    for (int w = 0; w < W; ++w) x[c][w] = 1.0 + 1e-3 * (c * W + w);
  V a, b;
  for (int w = 0; w < W; ++w) a[w] = 0.999999999, b[w] = 1e-9;
  const double t0 = now();
  for (long it = 0; it < iters; ++it) {
#pragma GCC unroll 16
    for (int c = 0; c < C; ++c) x[c] = x[c] * a + b;
  }
  const double sec = now() - t0;
  double s = 0;
  for (int c = 0; c < C; ++c)
    for (int w = 0; w < W; ++w) s += x[c][w];
  std::fprintf(stderr, "(checksum %g)\n", s);
  return 2.0 * C * W * iters / sec;
}
struct V1 {  // one lane: plain doubles (a 1-wide GCC vector type is not kept in registers)
  double v;
  double& operator[](int) { return v; }
  V1 operator*(V1 o) const { return {v * o.v}; }
  V1 operator+(V1 o) const { return {v + o.v}; }
};
using V4 = double __attribute__((vector_size(32)));
using V8 = double __attribute__((vector_size(64)));

double read_bandwidth(std::size_t bytes, int reps) {
  std::vector<double> v(bytes / sizeof(double), 1.0);
  double best = 1e300, s = 0;
  for (int r = 0; r < reps; ++r) {
    const double t0 = now();
    double a0 = 0, a1 = 0, a2 = 0, a3 = 0;
    for (std::size_t i = 0; i + 3 < v.size(); i += 4) a0 += v[i], a1 += v[i + 1], a2 += v[i + 2], a3 += v[i + 3];
    best = std::min(best, now() - t0);
    s += a0 + a1 + a2 + a3;
  }
  std::fprintf(stderr, "(checksum %g)\n", s);
  return static_cast<double>(bytes) / best;
}
}  // namespace

int main() {
  std::printf("scalar flops (1 lane, multiply-add chains): %.2f GFlop/s\n", flops_rate<V1>(100000000) / 1e9);
  std::printf("vector flops (4 lanes): %.2f GFlop/s\n", flops_rate<V4>(50000000) / 1e9);
  std::printf("vector flops (8 lanes): %.2f GFlop/s\n", flops_rate<V8>(25000000) / 1e9);
  std::printf("read bandwidth, 1 core, 512 MiB: %.2f GB/s\n", read_bandwidth(512ul << 20, 5) / 1e9);
  return 0;
}
