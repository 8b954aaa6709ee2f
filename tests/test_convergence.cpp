// SPDX-License-Identifier: BSD-3-Clause
// The sliding-window convergence test.
#include <nacre/mc/convergence.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include <random>

using namespace nacre::mc;

TEST_CASE("window statistics are exact, even far from zero", "[mc][convergence]") {
  std::mt19937_64 gen(3);
  std::normal_distribution<double> N(0.0, 1e-3);
  std::vector<double> y(3500);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 1e8 + 2e-7 * i + N(gen);
  const auto s = window_stats(y.data(), y.size());
  // reference in long double
  long double m = 0, vyy = 0, vxy = 0, vxx = 0;
  for (double v : y) m += v;
  m /= y.size();
  const long double xm = (y.size() - 1) / 2.0L;
  for (std::size_t i = 0; i < y.size(); ++i) {
    vyy += (y[i] - m) * (y[i] - m);
    vxy += (i - xm) * (y[i] - m);
    vxx += (i - xm) * (i - xm);
  }
  CHECK(s.mean == Catch::Approx(static_cast<double>(m)).epsilon(1e-15));
  CHECK(s.variance == Catch::Approx(static_cast<double>(vyy / y.size())).epsilon(1e-6));
  CHECK(s.r2 == Catch::Approx(static_cast<double>(vxy * vxy / (vxx * vyy))).epsilon(1e-6));
}

TEST_CASE("stationary noise converges after WindowSize + ConvergenceRep - 1 cycles", "[mc][convergence]") {
  ConvergenceMonitor mon(100, 20, 0.002, 0.03, true);
  std::mt19937_64 gen(5);
  std::normal_distribution<double> N(0.0, 0.001);
  int cycles = 0;
  while (!mon.push(1.0 + N(gen)) && cycles < 100000) ++cycles;
  ++cycles;
  CHECK(cycles >= 119);
  CHECK(cycles < 1000);
}

TEST_CASE("a steady trend never converges", "[mc][convergence]") {
  ConvergenceMonitor mon(100, 20, 0.002, 0.03, true);
  bool conv = false;
  for (int c = 0; c < 5000 && !conv; ++c) conv = mon.push(1.0 - 1e-5 * c);  // tiny but steady drift
  CHECK_FALSE(conv);
  CHECK(mon.last().r2 > 0.99);
}

TEST_CASE("relative STOL is independent of the energy scale, absolute STOL is not", "[mc][convergence]") {
  auto run = [](double scale, bool relative) {
    ConvergenceMonitor mon(50, 10, 1e-4, 0.5, relative);
    std::mt19937_64 gen(11);
    std::normal_distribution<double> N(0.0, 0.005);
    for (int c = 0; c < 2000; ++c)
      if (mon.push(scale * (1.0 + N(gen)))) return c;
    return -1;
  };
  // var/mean^2 = 2.5e-5 < 1e-4: converges, at the same cycle for any scale
  CHECK(run(1.0, true) > 0);
  CHECK(run(1.0, true) == run(1e6, true));
  CHECK(run(1.0, true) == run(1e-6, true));
  // absolute: var = 2.5e-5 scale^2 -> converges at scale 1, not at scale 1e3
  CHECK(run(1.0, false) > 0);
  CHECK(run(1e3, false) == -1);
}
