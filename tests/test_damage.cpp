// SPDX-License-Identifier: BSD-3-Clause
// Irreversible damage (cohesive/damage.hpp): the law with a history against its closed forms, one
// joint's load-unload-reload loop (its area is the dissipated energy), segment forces = the
// gradient of the segment energy at a fixed history, and the Monte Carlo load programme on a
// notched specimen: hysteresis, unloading along the secant, loop area = dissipated energy,
// ruptured joints stay ruptured, restart bit for bit.
#include <nacre/cohesive/damage.hpp>
#include <nacre/io/checkpoint.hpp>
#include <nacre/mc/output.hpp>
#include <nacre/mc/solver.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include "wall_specimen.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

using namespace nacre;
using namespace nacre::cohesive;

namespace {
const Law law{100.0, 0.01, 0.03};  // plateau to 0.03, rupture at 0.04, work to failure 0.03
}

TEST_CASE("damage: psi is C1 at the history, D(kappa) is the area above the secant", "[damage]") {
  const double x12 = law.x1 + law.x2;
  for (double kappa : {0.5 * law.x1, law.x1, 0.02, 0.035, x12, 2 * x12}) {
    CAPTURE(kappa);
    CHECK(damaged_energy(law, kappa, kappa) == Catch::Approx(f_energy(law, kappa)).epsilon(1e-14));
    CHECK(damaged_energy(law, 0.0, kappa) == dissipated(law, kappa));
    const double h = 1e-9;
    CHECK(damaged_energy(law, kappa - h, kappa) == Catch::Approx(damaged_energy(law, kappa + h, kappa)).margin(1e-9));
    // the traction psi' = ratio * d from both sides
    CHECK((kappa - h) * damaged_ratio(law, kappa - h, kappa) ==
          Catch::Approx((kappa + h) * damaged_ratio(law, kappa + h, kappa)).margin(1e-6));
    // the secant: psi is quadratic below the history, with stiffness f'(kappa) / kappa
    const double d = 0.3 * kappa;
    CHECK(damaged_energy(law, d, kappa) - dissipated(law, kappa) ==
          Catch::Approx(0.5 * f_slope(law, kappa) / kappa * d * d).margin(1e-15));
  }
  CHECK(dissipated(law, law.x1) == 0.0);                                                  // elastic
  CHECK(dissipated(law, 0.02) == Catch::Approx(0.5 * law.k * law.x1 * (0.02 - law.x1)));  // plateau
  CHECK(dissipated(law, x12) == Catch::Approx(law.k * law.x1 * law.x2));                  // rupture
  CHECK(dissipated(law, 3 * x12) == Catch::Approx(law.k * law.x1 * law.x2));
  CHECK(secant(law, x12) == 0.0);  // ruptured: no traction, whatever the opening
  double prev = 0;
  for (double kappa = 0; kappa < 0.06; kappa += 1e-4) {  // dissipation never decreases
    CHECK(dissipated(law, kappa) >= prev);
    prev = dissipated(law, kappa);
  }
}

TEST_CASE("damage: one joint loaded, unloaded and reloaded: the loop's area is the dissipated energy",
          "[damage][physics]") {
  // opening d along 0 -> a -> 0 -> b -> 0 in steps of h, the history raised after every step;
  // the work of the traction by the trapezoid rule (the traction is continuous: O(h^2) error)
  const double a = 0.025, b = 0.05, h = 2e-6;
  double kappa = 0, d = 0, work = 0;
  auto traction = [&](double x) { return x * damaged_ratio(law, x, kappa); };
  auto move_to = [&](double target) {
    const int n = static_cast<int>(std::lround(std::abs(target - d) / h));
    const double step = (target - d) / n;
    for (int k = 0; k < n; ++k) {
      const double t0 = traction(d);
      const double x = d + step;
      work += 0.5 * (t0 + traction(x)) * step;
      d = x;
      kappa = std::max(kappa, d);
    }
  };
  move_to(a);
  CHECK(work == Catch::Approx(f_energy(law, a)).epsilon(1e-8));  // the envelope's energy
  const double t_load_half = f_slope(law, 0.5 * a);
  move_to(0.5 * a);
  CHECK(traction(d) == Catch::Approx(0.5 * f_slope(law, a)).epsilon(1e-12));  // on the secant to the origin
  CHECK(traction(d) < t_load_half);                                           // below the loading curve: hysteresis
  move_to(0.0);
  CHECK(work == Catch::Approx(dissipated(law, a)).epsilon(1e-8));  // the closed loop's area
  CHECK(work > 0.1 * law.k * law.x1 * law.x2);
  move_to(a);  // reloading retraces the secant: back at the envelope's energy
  CHECK(work == Catch::Approx(f_energy(law, a)).epsilon(1e-8));
  move_to(b);  // through rupture
  move_to(0.0);
  CHECK(work == Catch::Approx(law.k * law.x1 * law.x2).epsilon(1e-8));  // all of the work to failure
  CHECK(traction(0.5 * b) == 0.0);                                      // a ruptured joint stays ruptured
}

TEST_CASE("damage: a segment's end forces are the gradient of its energy at a fixed history", "[damage][fd]") {
  const Quadrature q = gauss_legendre(4);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-0.03, 0.03), K(0.0, 0.045), A(-0.05, 0.05);
  const double length = 3.5;
  double worst = 0, scale = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const double th = A(rng);
    Gap g{U(rng), U(rng), U(rng), U(rng), -std::sin(th), std::cos(th)};
    double kappa[4];
    for (double& k : kappa) k = K(rng);
    const EndForces f = integrate(TractionTag{}, law, q, g, length, kappa);
    double* comp[4] = {&g.g0x, &g.g0y, &g.g1x, &g.g1y};
    const double fc[4] = {f.f0x, f.f0y, f.f1x, f.f1y};
    for (int c = 0; c < 4; ++c) {
      const double h = 1e-8, x = *comp[c];
      *comp[c] = x + h;
      const double ep = integrate(EnergyTag{}, law, q, g, length, kappa);
      *comp[c] = x - h;
      const double em = integrate(EnergyTag{}, law, q, g, length, kappa);
      *comp[c] = x;
      worst = std::max(worst, std::abs((ep - em) / (2 * h) - fc[c]));
      scale = std::max(scale, std::abs(fc[c]));
    }
  }
  INFO("worst " << worst << " of " << scale);
  CHECK(worst < 1e-6 * scale);
  // an intact segment in its elastic range takes the reversible closed form: the same bits
  const double zero[4] = {0, 0, 0, 0};
  const Gap e{0.002, 0.001, -0.003, 0.004, 0.0, 1.0};
  CHECK(integrate(EnergyTag{}, law, q, e, length, zero) == integrate(EnergyTag{}, law, e, length));
  CHECK(dissipated(law, q, zero, length) == 0.0);
}

namespace {

/// The notched 21 x 8 specimen loaded to 0.01, unloaded to 0 and reloaded to 0.016 in fixed
/// increments of 0.002.
deck::Deck programme_deck() {
  deck::Deck d = test::notched_21x8_deck();
  d.load.programme = {0.01, 0.0, 0.016};
  d.load.final_displacement = 0.016;
  d.load.initial_step = d.load.min_step = d.load.max_step = 0.002;
  d.load.adaptive = false, d.load.predictor = deck::Load::Predictor::automatic;
  d.mortar.damage = Damage::irreversible, d.mortar.damage_auto = false;
  d.solver.temperature = 1e-7;
  d.solver.step = 1e-4, d.solver.min_step = 1e-7, d.solver.max_step = 1e-3;
  d.solver.rot_step = 1e-4, d.solver.min_rot_step = 1e-7, d.solver.max_rot_step = 1e-3;
  d.solver.adapt_interval = 7;
  d.solver.window_size = 60, d.solver.convergence_rep = 20, d.solver.window_mul = 10, d.solver.window_upper_mul = 40;
  d.solver.colouring = "tiles";
  d.output.hdf5 = false, d.output.charts = false;
  return d;
}

struct Row {
  mc::StepRecord r;
  double dissipated;
};

}  // namespace

TEST_CASE("damage: a notched specimen loaded, unloaded and reloaded (Monte Carlo)", "[damage][mc][physics]") {
  const deck::Deck d = programme_deck();
  geometry::Specimen s = geometry::build_specimen(d.geometry);
  const geometry::Interfaces f = geometry::find_interfaces(s, d.geometry);
  std::vector<Row> rows;
  mc::Checkpoint cp;
  {
    mc::Solver solver(d, s, f);
    solver.run([&](const mc::StepRecord& r) {
      rows.push_back({r, solver.dissipated()});
      if (r.step == 7) cp = solver.checkpoint();  // on the unloading leg
    });
    CHECK(solver.finished());
  }
  REQUIRE(rows.size() == 18);  // 5 up, 5 down, 8 up
  const std::vector<double> at_d = [&] {
    std::vector<double> v;
    for (const auto& w : rows) v.push_back(w.r.displacement);
    return v;
  }();
  CHECK(at_d[4] == Catch::Approx(0.01));
  CHECK(std::abs(at_d[9]) < 1e-15);
  CHECK(at_d[17] == Catch::Approx(0.016));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    CAPTURE(k);
    CHECK(rows[k].r.last == (k + 1 == rows.size()));
    CHECK(rows[k].r.residual <= d.solver.residual_tolerance);
    if (k > 0) CHECK(rows[k].dissipated >= rows[k - 1].dissipated);  // never given back
  }
  const Row &peak = rows[4], &down6 = rows[6], &zero = rows[9], &up10 = rows[14];
  INFO("F at 0.01 " << peak.r.reaction << ", at 0.006 down " << down6.r.reaction << " (up " << rows[2].r.reaction
                    << "), dissipated " << peak.dissipated << ", E at 0 " << zero.r.energy);
  REQUIRE(peak.dissipated > 0);  // the loading damaged joints
  // unloading follows the secants: the specimen is linear on the way down and back up
  CHECK(down6.r.reaction == Catch::Approx(0.6 * peak.r.reaction).epsilon(1e-2));
  CHECK(down6.r.reaction < 0.98 * rows[2].r.reaction);  // below the loading curve at the same D: hysteresis
  CHECK(up10.r.reaction == Catch::Approx(peak.r.reaction).epsilon(1e-2));
  CHECK(up10.dissipated ==
        Catch::Approx(peak.dissipated).epsilon(1e-6));  // nothing new until past the peak (to the residual)
  // at D = 0 every gap closes (the unique minimum): the energy left is what was dissipated
  CHECK(zero.r.energy == Catch::Approx(zero.dissipated).epsilon(1e-6));
  // the closed loop's area (trapezoid over the steps, F = 0 at D = 0) is the dissipated energy
  double work = 0, dprev = 0, fprev = 0;
  for (int k = 0; k <= 9; ++k) {
    work += 0.5 * (fprev + rows[k].r.reaction) * (rows[k].r.displacement - dprev);
    dprev = rows[k].r.displacement, fprev = rows[k].r.reaction;
  }
  INFO("loop area " << work << ", dissipated " << zero.dissipated);
  CHECK(work == Catch::Approx(zero.dissipated).epsilon(0.01));  // measured: 0.1 %
  // ruptured joints stay ruptured: none heals on the way down
  for (int k = 5; k <= 9; ++k) CHECK(rows[k].r.ruptured >= peak.r.ruptured);
  CHECK(rows.back().r.ruptured >= peak.r.ruptured);
  CHECK(rows.back().dissipated > peak.dissipated);

  // restart from the unloading leg, through a file as the app does: the same bits
  const auto path = std::filesystem::temp_directory_path() / "nacre_test_damage_checkpoint.h5";
  io::write_checkpoint(path, mc::to_named(cp, "fingerprint", "deck text", d.load.final_displacement, 3));
  mc::Solver resumed(d, s, f);
  const mc::Checkpoint back =
      mc::from_named(io::read_checkpoint(path), s.size(), static_cast<std::size_t>(resumed.model().n_free));
  std::filesystem::remove(path);
  REQUIRE(back.history == cp.history);
  REQUIRE(!back.history.empty());
  CHECK(back.run.leg == 1);
  resumed.restore(back);
  std::vector<Row> rest;
  resumed.run([&](const mc::StepRecord& r) { rest.push_back({r, resumed.dissipated()}); });
  REQUIRE(rest.size() == rows.size() - 7);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    CAPTURE(i);
    CHECK(rest[i].r.energy == rows[i + 7].r.energy);  // bit for bit
    CHECK(rest[i].r.reaction == rows[i + 7].r.reaction);
    CHECK(rest[i].r.cycles == rows[i + 7].r.cycles);
    CHECK(rest[i].dissipated == rows[i + 7].dissipated);
  }
  // a checkpoint without the history is refused by a deck with irreversible damage
  mc::Checkpoint no_history = cp;
  no_history.history.clear();
  mc::Solver other(d, s, f);
  CHECK_THROWS(other.restore(no_history));
}
