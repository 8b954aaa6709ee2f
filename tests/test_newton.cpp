// SPDX-License-Identifier: BSD-3-Clause
// The trust-region Newton minimiser (relaxation = "newton", "auto"; mc/trust_region.hpp): its
// Hessian-vector product against finite differences of the exact gradient away from kinks, and
// symmetric; the elastic minimum against the closed form; a cracking load path converged step
// by step with few iterations; the same bits on a repeat and on every backend; "auto" escaping
// the ruptured plateau where the gradient (and Newton) stop.
#include <nacre/mc/hessian.hpp>
#include <nacre/mc/trust_region.hpp>
#include <nacre/mc/solver.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include "elastic_exact.hpp"
#include "wall_specimen.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace nacre;

namespace {

/// The notched 21 x 8 specimen of the polish tests, relaxed by Newton.
deck::Deck newton_deck(const char* relaxation = "newton") {
  auto d = test::notched_21x8_deck();
  test::cracking_path(d);
  test::short_windows(d);
  d.solver.residual_tolerance = 1e-9;
  d.solver.relaxation = relaxation;
  return d;
}


using Host = Kokkos::View<double* [3], Kokkos::LayoutLeft, Kokkos::HostSpace>;

/// Gradient of the model at its current poses (host copy).
Host gradient_now(const mc::Model<>& m) {
  mc::GradientView<> g("nacre::test::g", m.n_free);
  mc::brick_gradient(ExecSpace{}, m, g);
  return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, g);
}

/// Moves the free bricks by h v (host side, frames refreshed).
void move(const mc::Model<>& m, const Host& base, const Host& v, double h) {
  auto p = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.pose);
  for (int b = 0; b < m.n_free; ++b) {
    const auto f = kinematics::make_frame(
        kinematics::Pose{base(b, 0) + h * v(b, 0), base(b, 1) + h * v(b, 1), base(b, 2) + h * v(b, 2)});
    p(b, 0) = f.x, p(b, 1) = f.y, p(b, 2) = f.t, p(b, 3) = f.s, p(b, 4) = f.c1;
  }
  Kokkos::deep_copy(m.pose, p);
}

}  // namespace

TEST_CASE("H v is the directional derivative of the exact gradient, and H is symmetric", "[mc][newton][physics]") {
  // A loaded notched specimen relaxed by FIRE: its joints span the elastic, plateau and
  // softening branches. For random directions v, H v (dual numbers through the gradient code)
  // against central differences of the exact gradient with steps that cross no kink (the
  // interface states at x +- h v are those at x): relative error ~h^2; and u.Hv = v.Hu.
  auto d = newton_deck();
  d.solver.relaxation = "monte-carlo";
  auto st = test::make_setup(d);
  mc::Solver solver(d, st.s, st.f);
  std::vector<std::int8_t> states;
  int softening = 0, ruptured = 0;
  for (int k = 1; k <= 40 && softening < 3; ++k) {  // the continuation, until joints soften at the notch
    solver.set_load(0.0005 * k);
    REQUIRE(solver.polish("fire", 1e-8).converged);
    states = solver.interface_states();
    softening = static_cast<int>(std::count(states.begin(), states.end(), std::int8_t{1}));
    ruptured = static_cast<int>(std::count(states.begin(), states.end(), std::int8_t{2}));
  }
  const auto& m = solver.model();
  INFO("D " << solver.load() << ": " << softening << " softening, " << ruptured << " ruptured");
  REQUIRE(softening >= 3);  // the non-elastic branches are in play
  const int nf = m.n_free;
  auto base = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{},
                                                  Kokkos::subview(m.pose, Kokkos::ALL, Kokkos::make_pair(0, 3)));
  Host b0("b0", nf);
  for (int b = 0; b < nf; ++b)
    for (int c = 0; c < 3; ++c) b0(b, c) = base(b, c);
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  auto random_dir = [&] {
    Host v("v", nf);
    for (int b = 0; b < nf; ++b) v(b, 0) = U(gen), v(b, 1) = U(gen), v(b, 2) = 0.3 * U(gen);
    return v;
  };
  mc::GradientView<> vd("nacre::test::v", nf), hv("nacre::test::hv", nf);
  auto apply = [&](const Host& v) {
    Kokkos::deep_copy(vd, v);
    mc::hessian_vector(ExecSpace{}, m, vd, hv);
    Host out("hv", nf);  // a copy of its own (a host mirror of a host View is the View itself)
    Kokkos::deep_copy(out, hv);
    return out;
  };
  int checked = 0;
  std::vector<Host> dirs, prods;
  for (int trial = 0; trial < 8; ++trial) {
    const Host v = random_dir();
    const Host H = apply(v);
    dirs.push_back(v), prods.push_back(H);
    const double h = 1e-7;
    move(m, b0, v, h);
    const bool same_p = solver.interface_states() == states;
    const Host gp = gradient_now(m);
    move(m, b0, v, -h);
    const bool same_m = solver.interface_states() == states;
    const Host gm = gradient_now(m);
    move(m, b0, v, 0.0);
    if (!same_p || !same_m) continue;  // a kink between: no derivative to compare
    double err = 0, scale = 0;
    for (int b = 0; b < nf; ++b)
      for (int c = 0; c < 3; ++c) {
        const double fd = (gp(b, c) - gm(b, c)) / (2 * h);
        err = std::max(err, std::abs(fd - H(b, c)));
        scale = std::max(scale, std::abs(H(b, c)));
      }
    INFO("trial " << trial << ": max |FD - Hv| " << err << " of max |Hv| " << scale);
    CHECK(scale > 0);
    CHECK(err <= 1e-5 * scale);
    ++checked;
  }
  CHECK(checked >= 4);
  for (std::size_t i = 0; i < dirs.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      double uhv = 0, vhu = 0, norm = 0;
      for (int b = 0; b < nf; ++b)
        for (int c = 0; c < 3; ++c) {
          uhv += dirs[i](b, c) * prods[j](b, c), vhu += dirs[j](b, c) * prods[i](b, c);
          norm += std::abs(dirs[i](b, c) * prods[j](b, c));
        }
      CHECK(std::abs(uhv - vhu) <= 1e-10 * norm);
    }
  // The cached sines and cosines (brick_trig, TrigView) give the bits of kinematics::make_frame
  // on dual numbers, evaluated per interface end: the product before the cache, written out
  // here (per-interface tangents, then each brick's in adjacency order)
  {
    const mc::InterfaceEvaluator<MemSpace> ev(m);
    auto off = m.adj_offset, adj = m.adj_iface;
    mc::GradientView<> ref("nacre::test::hv_make_frame", nf);
    Kokkos::View<double* [6], MemSpace> tangent("nacre::test::tangents", m.n_interfaces);
    for (std::size_t q = 0; q < 3; ++q) {
      Kokkos::deep_copy(vd, dirs[q]);
      Kokkos::parallel_for(
          "nacre::test::tangent_make_frame", Kokkos::RangePolicy<ExecSpace>(0, m.n_interfaces),
          KOKKOS_LAMBDA(const int i) {
            const int a = ev.ends(i, 0), c = ev.ends(i, 1);
            auto seeded = [&](int j) {
              const bool f = j < nf;
              return kinematics::make_frame(ad::Dual{ev.pose(j, 0), f ? vd(j, 0) : 0.0},
                                            ad::Dual{ev.pose(j, 1), f ? vd(j, 1) : 0.0},
                                            ad::Dual{ev.pose(j, 2), f ? vd(j, 2) : 0.0});
            };
            ad::Dual ga[3], gc[3];
            kinematics::interface_gradient(ev.law(i), mc::load_segment(ev.seg, i), seeded(a), seeded(c), ga, gc);
            for (int k = 0; k < 3; ++k) tangent(i, k) = ga[k].d, tangent(i, 3 + k) = gc[k].d;
          });
      Kokkos::parallel_for(
          "nacre::test::hv_make_frame", Kokkos::RangePolicy<ExecSpace>(0, nf), KOKKOS_LAMBDA(const int b) {
            double h[3] = {0.0, 0.0, 0.0};
            for (int j = off(b); j < off(b + 1); ++j) {
              const int i = adj(j), o = ev.ends(i, 0) == b ? 0 : 3;
              h[0] += tangent(i, o), h[1] += tangent(i, o + 1), h[2] += tangent(i, o + 2);
            }
            ref(b, 0) = h[0], ref(b, 1) = h[1], ref(b, 2) = h[2];
          });
      const auto rh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, ref);
      int differ = 0;
      for (int b = 0; b < nf; ++b)
        for (int c = 0; c < 3; ++c) differ += rh(b, c) != prods[q](b, c);
      CHECK(differ == 0);
    }
  }
  // the diagonal blocks are H applied to one brick's unit directions
  mc::BlockView<> blocks("nacre::test::blocks", nf);
  mc::hessian_blocks(ExecSpace{}, m, blocks);
  auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, blocks);
  for (const int b : {0, nf / 2, nf - 1}) {
    for (int c = 0; c < 3; ++c) {
      Host e("e", nf);
      Kokkos::deep_copy(e, 0.0);
      e(b, c) = 1.0;
      const Host H = apply(e);
      const int idx[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
      for (int r = 0; r < 3; ++r)
        CHECK(H(b, r) == Catch::Approx(hb(b, idx[r][c])).epsilon(1e-10).margin(1e-12 * std::abs(hb(b, 0))));
    }
  }
  // The shifted factor (hessian_factor.cpp): told that H is likely indefinite, the search starts
  // at sigma >= 1e-4, and its solve y = M^-1 r must satisfy H y + sigma diag(scale) y = r, where
  // scale is max(|H_ii|, floor) (the shift written into the factor's own copy of H's values, in
  // float and in double); then, told nothing, it starts from sigma = 0 again
  {
    const double floor_t = 1e-8 * d.mortar.bed.k, floor_r = floor_t * d.geometry.brick_width * d.geometry.brick_width;
    Host r("r", nf);
    for (int b = 0; b < nf; ++b) r(b, 0) = U(gen), r(b, 1) = U(gen), r(b, 2) = U(gen);
    mc::GradientView<> rd("nacre::test::r", nf), yd("nacre::test::y", nf);
    Kokkos::deep_copy(rd, r);
    for (const auto precision : {mc::FactorPrecision::single, mc::FactorPrecision::double_precision}) {
      mc::TrustRegion<ExecSpace> tr(ExecSpace{}, m, mc::NewtonPreconditioner::automatic, precision);
      if (!tr.has_factor()) continue;  // a device build: block-Jacobi only
      tr.precondition(ExecSpace{}, m, floor_t, floor_r, true);
      const double sigma = tr.shift();
      CHECK(sigma >= 1e-4);
      tr.precondition_apply(ExecSpace{}, rd, yd, nf);
      const auto y = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, yd);
      const Host hy = apply(y);
      double err = 0, norm = 0;
      for (int b = 0; b < nf; ++b)
        for (int c = 0; c < 3; ++c) {
          const double sc = std::max(std::abs(hb(b, c)), c == 2 ? floor_r : floor_t);
          err = std::max(err, std::abs(hy(b, c) + sigma * sc * y(b, c) - r(b, c)));
          norm = std::max(norm, std::abs(r(b, c)));
        }
      INFO("precision " << static_cast<int>(precision) << ", sigma " << sigma << ": max |M y - r| " << err
                        << " of max |r| " << norm);
      CHECK(err <= (precision == mc::FactorPrecision::single ? 1e-5 : 1e-12) * norm);  // measured 6.7e-7, 1.6e-15
      tr.precondition(ExecSpace{}, m, floor_t, floor_r, false);
      CHECK(tr.shift() <= sigma);  // from sigma = 0 again: never a larger shift than the hinted search's
      // A factor after the first writes H's values into the run's fixed pattern instead of
      // assembling triplets: at another state (the poses moved), its solve has the bits of a
      // new factor's, which assembles from triplets
      move(m, b0, dirs[0], 1e-6);
      tr.precondition(ExecSpace{}, m, floor_t, floor_r, false);
      mc::TrustRegion<ExecSpace> fresh(ExecSpace{}, m, mc::NewtonPreconditioner::automatic, precision);
      fresh.precondition(ExecSpace{}, m, floor_t, floor_r, false);
      CHECK(tr.shift() == fresh.shift());
      mc::GradientView<> y2("nacre::test::y2", nf);
      tr.precondition_apply(ExecSpace{}, rd, yd, nf);
      fresh.precondition_apply(ExecSpace{}, rd, y2, nf);
      const auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, yd);
      const auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, y2);
      int differ = 0;
      for (int b = 0; b < nf; ++b)
        for (int c = 0; c < 3; ++c) differ += a(b, c) != f(b, c);
      CHECK(differ == 0);
      move(m, b0, dirs[0], 0.0);
    }
  }
  // Steihaug-CG's recurrences (trust_region.hpp): its model value q(s) against g.s + s.H s / 2
  // from an H s of the step it returns, inside the region and on its boundary (there ||s||_M is
  // the radius), for each preconditioner and both factor precisions. Away from equilibrium (the
  // poses moved), and with the intact wall's factor (a stale one, as in a Newton step that does
  // not refactor), so that CG takes several iterations
  move(m, b0, random_dir(), 1e-5);
  mc::GradientView<> g("nacre::test::g", nf), hs("nacre::test::hs", nf);
  mc::brick_gradient(ExecSpace{}, m, g);
  SumWorkspace<> ws;
  struct Pc {
    mc::NewtonPreconditioner pc;
    mc::FactorPrecision precision;
  };
  for (const Pc pc : {Pc{mc::NewtonPreconditioner::automatic, mc::FactorPrecision::single},
                      Pc{mc::NewtonPreconditioner::automatic, mc::FactorPrecision::double_precision},
                      Pc{mc::NewtonPreconditioner::block_jacobi, mc::FactorPrecision::single}}) {
    mc::TrustRegion<ExecSpace> tr(ExecSpace{}, m, pc.pc, pc.precision);
    const double floor_t = 1e-8 * d.mortar.bed.k, floor_r = floor_t * d.geometry.brick_width * d.geometry.brick_width;
    if (tr.has_factor())
      tr.reference_factor(ExecSpace{}, m, floor_t, floor_r);
    else
      tr.precondition(ExecSpace{}, m, floor_t, floor_r);
    const double g_norm = std::sqrt(tr.minv_norm2(ExecSpace{}, ws, g, nf));
    // first a region CG stays inside, then one just short of its interior step (M-norm): CG's
    // iterates grow in the M-norm, so it leaves the region after several iterations
    double interior = 0.0;
    for (const bool inside : {true, false}) {
      const double radius = inside ? 1e3 * g_norm : 0.999 * std::sqrt(interior);
      const auto cg = tr.steihaug(ExecSpace{}, m, g, radius, 1e-6, 200, ws);
      mc::hessian_vector(ExecSpace{}, m, tr.step(), hs);
      Host gh("g", nf), hsh("hs", nf);
      Kokkos::deep_copy(gh, g), Kokkos::deep_copy(hsh, hs);
      const auto sh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, tr.step());  // a row per brick
      double gs = 0, shs = 0, size = 0;
      for (int b = 0; b < nf; ++b)
        for (int c = 0; c < 3; ++c)
          gs += gh(b, c) * sh(b, c), shs += sh(b, c) * hsh(b, c), size += std::abs(gh(b, c) * sh(b, c));
      INFO("preconditioner " << static_cast<int>(pc.pc) << ", precision " << static_cast<int>(pc.precision)
                             << ", radius " << radius << ": " << cg.iterations << " CG iterations, boundary "
                             << cg.on_boundary << ", q " << cg.model << " against " << gs + 0.5 * shs);
      CHECK(cg.iterations >= 2);
      CHECK(cg.model < 0.0);
      CHECK(std::abs(cg.model - (gs + 0.5 * shs)) <= 1e-8 * size);
      CHECK(cg.on_boundary == !inside);
      if (inside)
        interior = cg.snorm2;
      else
        CHECK(cg.snorm2 == Catch::Approx(radius * radius).epsilon(1e-10));
    }
  }
}

TEST_CASE("relaxation = \"newton\" reaches the elastic minimum of the closed form in a few steps",
          "[mc][newton][physics]") {
  auto d = newton_deck();
  d.geometry.notch_length = 0.0;
  auto st = test::make_setup(d);
  const double D = 1e-4;  // separations ~1e-5 << x1: quadratic regime
  const double exact = test::exact_elastic_energy(d, st.s, st.f, D);
  mc::Solver solver(d, st.s, st.f);
  solver.set_load(D);
  const double e_start = solver.energy();
  const auto r = solver.polish("trust-region", 1e-11);
  const double e = solver.energy();
  INFO("exact " << exact << ", Newton " << e << " in " << r.iterations << " steps, " << r.inner_iterations
                << " CG iterations, residual " << r.residual);
  CHECK(r.converged);
  CHECK(e_start > 2 * exact);
  CHECK(r.iterations <= 10);
  CHECK(e == Catch::Approx(exact).epsilon(1e-6));  // the small-rotation closed form (geometric terms ~1e-6)
}

TEST_CASE("relaxation = \"newton\" follows a cracking load path, each step to the residual, deterministic",
          "[mc][newton][determinism]") {
  auto st = test::make_setup(newton_deck());
  auto run = [&](const Backend& b) {
    mc::Solver solver(b, st.d, st.s, st.f);
    std::vector<mc::StepRecord> rows;
    solver.run([&](const mc::StepRecord& r) { rows.push_back(r); });
    REQUIRE_FALSE(solver.failed());
    return rows;
  };
  const auto ref = run(Backend{});
  REQUIRE(ref.size() >= 4);
  CHECK(ref.back().ruptured > 0);  // the crack ran
  long newton_steps = 0;
  for (const auto& r : ref) {
    CAPTURE(r.step, r.displacement, r.residual, r.polish_iterations, r.inner_iterations);
    CHECK(r.converged);
    CHECK(r.residual < 1e-9);
    CHECK(r.cycles == 0);  // no Monte Carlo
    CHECK(r.method == "newton");
    CHECK(r.inner_iterations > 0);
    newton_steps += r.polish_iterations;
  }
  CHECK(newton_steps < 60L * static_cast<long>(ref.size()));  // tens per step, not FIRE's thousands
  // a repeat, and every backend of the default's kind of arithmetic: the same bits (a CUDA build's
  // host backends: the host's arithmetic and the sparse Cholesky, another path within the tolerance)
  for (const auto& name : Backend::names()) {
    if (!Backend{}.bit_compatible(name)) continue;
    INFO("backend " << name);
    const auto again = run(Backend::parse(name));
    REQUIRE(again.size() == ref.size());
    for (std::size_t k = 0; k < ref.size(); ++k) {
      CHECK(again[k].energy == ref[k].energy);
      CHECK(again[k].residual == ref[k].residual);
      CHECK(again[k].inner_iterations == ref[k].inner_iterations);
    }
  }
}

TEST_CASE("relaxation = \"auto\" escapes the ruptured plateau where Newton stops", "[mc][newton][metastable]") {
  // The notched specimen loaded in one jump to D = 0.012 (tests/test_polish.cpp: FIRE from rest
  // pulls the loaded row off onto a plateau of ruptured joints with zero gradient). Newton from
  // rest stops there too (residual zero); "auto" sees joints rupture in the step, runs a Monte
  // Carlo burst, Newton again, and keeps the lower state.
  auto d = newton_deck("auto");
  d.load.initial_step = d.load.min_step = d.load.max_step = 0.012;
  d.load.final_displacement = 0.012;
  d.load.adaptive = false, d.load.predictor = deck::Load::Predictor::none;
  d.solver.burst_cycles = 500;
  auto st = test::make_setup(d);
  mc::Solver newton(d, st.s, st.f);
  newton.set_load(0.012);
  REQUIRE(newton.polish("trust-region", 1e-9).converged);
  const double e_newton = newton.energy();
  const int r_newton = newton.ruptured();
  mc::Solver automatic(d, st.s, st.f);
  std::vector<mc::StepRecord> rows;
  automatic.run([&](const mc::StepRecord& r) { rows.push_back(r); });
  REQUIRE(rows.size() == 1);
  INFO("Newton from rest: E " << e_newton << ", " << r_newton << " ruptured; auto: E " << rows[0].energy << ", "
                              << rows[0].ruptured << " ruptured, " << rows[0].cycles << " cycles, " << rows[0].method);
  CHECK(rows[0].converged);
  CHECK(rows[0].cycles > 0);
  CHECK(rows[0].method == "newton+monte-carlo");
  CHECK(rows[0].energy < 0.6 * e_newton);
  CHECK(rows[0].ruptured < r_newton);
}

TEST_CASE("the predictors: the secant moves every brick by the last increment, eq. 2.11 holds back the loaded ones",
          "[mc][newton]") {
  // Two converged states of the continuation past the first softening joints (the H v test's);
  // each predictor applied to a copy of the later poses with ratio 1/2.
  auto d = newton_deck();
  d.solver.relaxation = "monte-carlo";
  auto st = test::make_setup(d);
  mc::Solver solver(d, st.s, st.f);
  const auto& m = solver.model();
  Kokkos::View<double* [5], Kokkos::LayoutRight, Kokkos::HostSpace> prev;
  int softening = 0;
  for (int k = 1; k <= 40 && softening < 3; ++k) {
    prev = Kokkos::create_mirror(Kokkos::HostSpace{}, m.pose);  // a copy, also where m.pose is host memory
    Kokkos::deep_copy(prev, m.pose);
    solver.set_load(0.0005 * k);
    REQUIRE(solver.polish("fire", 1e-8).converged);
    const auto states = solver.interface_states();
    softening = static_cast<int>(std::count(states.begin(), states.end(), std::int8_t{1}));
  }
  REQUIRE(softening >= 3);
  const auto now = Kokkos::create_mirror(Kokkos::HostSpace{}, m.pose);
  Kokkos::deep_copy(now, m.pose);
  const double ratio = 0.5;
  auto predicted = [&](bool secant) {
    mc::Model<> c = m;  // the same interfaces, its own poses
    c.pose = mc::Model<>::PoseView("nacre::test::pose", static_cast<std::size_t>(m.n_bricks));
    Kokkos::deep_copy(c.pose, m.pose);
    auto p_prev = mc::Model<>::PoseView("nacre::test::prev", static_cast<std::size_t>(m.n_bricks));
    Kokkos::deep_copy(p_prev, prev);
    if (secant) {
      mc::predict_poses(ExecSpace{}, mc::SecantPredictor{}, c, p_prev, ratio);
    } else {
      Field<double> phi("nacre::test::phi", static_cast<std::size_t>(m.n_bricks));
      mc::brick_energy(ExecSpace{}, c, phi);
      mc::predict_poses(ExecSpace{}, c, p_prev, phi, ratio);
    }
    return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, c.pose);
  };
  const auto s = predicted(true), e = predicted(false);
  Field<double> phi("nacre::test::phi", static_cast<std::size_t>(m.n_bricks));
  mc::brick_energy(ExecSpace{}, m, phi);
  const auto hphi = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, phi);
  const auto hphi0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.phi0);
  int held = 0, moved = 0;
  double secant_err = 0.0, damped_err = 0.0;
  for (int b = 0; b < m.n_free; ++b) {
    const double r = hphi0(b) > 0 ? hphi(b) / hphi0(b) : 0.0;
    const double mfac = 1.0 - 1.8 * (std::max(std::min(r, 1.0), 0.5) - 0.5);  // eq. 2.11
    held += mfac < 1.0;
    for (int k = 0; k < 3; ++k) {
      const double step = now(b, k) - prev(b, k);
      moved += step != 0.0;
      secant_err = std::max(secant_err, std::abs(s(b, k) - (now(b, k) + ratio * step)));
      damped_err = std::max(damped_err, std::abs(e(b, k) - (now(b, k) + ratio * step * mfac)));
    }
    // the frame's sine and cosine - 1 follow the predicted angle
    CHECK(s(b, 3) == Catch::Approx(std::sin(s(b, 2))).margin(1e-15));
    CHECK(s(b, 4) == Catch::Approx(std::cos(s(b, 2)) - 1.0).margin(1e-15));
  }
  INFO(held << " of " << m.n_free << " bricks held back by eq. 2.11; " << moved << " moving components");
  CHECK(held > 0);  // the damping is in play: the predictors differ
  CHECK(moved > m.n_free);
  CHECK(secant_err < 1e-15);
  CHECK(damped_err < 1e-15);
}

TEST_CASE("predictor = true is the secant where Newton relaxes, eq. 2.11 where asked", "[mc][newton]") {
  // The cracking load path three ways: the automatic predictor (the deck's true) gives the
  // secant's bits under Newton; "damped" starts the loaded steps elsewhere (other bits), and all
  // three end every step below the residual.
  auto run = [&](deck::Load::Predictor kind) {
    auto d = newton_deck();
    d.load.predictor = kind;
    auto st = test::make_setup(d);
    mc::Solver solver(d, st.s, st.f);
    std::vector<mc::StepRecord> rows;
    solver.run([&](const mc::StepRecord& r) { rows.push_back(r); });
    REQUIRE_FALSE(solver.failed());
    for (const auto& r : rows) CHECK(r.residual < 1e-9);
    return rows;
  };
  using Kind = deck::Load::Predictor;
  const auto automatic = run(Kind::automatic), secant = run(Kind::secant), damped = run(Kind::damped);
  REQUIRE(automatic.size() == secant.size());
  bool differs = damped.size() != secant.size();
  for (std::size_t k = 0; k < secant.size(); ++k) {
    CHECK(automatic[k].energy == secant[k].energy);
    CHECK(automatic[k].inner_iterations == secant[k].inner_iterations);
    if (k < damped.size()) differs = differs || damped[k].inner_iterations != secant[k].inner_iterations;
  }
  CHECK(differs);
}
