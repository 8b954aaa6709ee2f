// SPDX-License-Identifier: BSD-3-Clause
// The cohesive law integrated along a segment with a linear gap (cohesive/segment.hpp): energy and
// end forces exact on every branch, against an independent long-double reference (branch points
// found by bisection, composite 8-point Gauss-Legendre on each smooth piece), forces against
// finite differences of the energy, and the rupture test over the whole segment.
#include <nacre/cohesive/segment.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace nacre::cohesive;

namespace {
using LD = long double;
const Law seg_law{100.0, 0.01, 0.03};  // branch points |g| = 0.01, 0.03, 0.04 and dn = 0

struct Ref {
  LD e = 0, f[4] = {0, 0, 0, 0};
};

LD ref_f(const Law& m, LD r) {
  const LD k = m.k, x1 = m.x1, x2 = m.x2;
  if (r <= x1) return 0.5L * k * r * r;
  if (r <= x2) return k * x1 * (r - 0.5L * x1);
  if (r < x1 + x2) return -0.5L * k * (x1 * x1 + x2 * x2 + r * r - 2 * r * (x1 + x2));
  return k * x1 * x2;
}
LD ref_fslope(const Law& m, LD r) {
  const LD k = m.k, x1 = m.x1, x2 = m.x2;
  if (r <= x1) return k * r;
  if (r <= x2) return k * x1;
  if (r < x1 + x2) return k * (x1 + x2 - r);
  return 0;
}

/// Independent reference: breakpoints of |g(s)| = x1, x2, x1 + x2 and dn(s) = 0 by a sign scan and
/// bisection in long double, then 64 panels of 8-point Gauss-Legendre on each piece.
Ref reference(const Law& m, const Gap& g, double length) {
  const LD g0x = g.g0x, g0y = g.g0y, dx = LD(g.g1x) - g0x, dy = LD(g.g1y) - g0y;
  const LD nl = std::sqrt(LD(g.nx) * g.nx + LD(g.ny) * g.ny), nx = g.nx / nl, ny = g.ny / nl;
  auto gx = [&](LD s) { return g0x + s * dx; };
  auto gy = [&](LD s) { return g0y + s * dy; };
  std::vector<LD> cuts{0.0L, 1.0L};
  auto roots = [&](auto fn) {
    const int n = 4096;
    LD prev = fn(0.0L);
    for (int i = 1; i <= n; ++i) {
      const LD s = LD(i) / n, v = fn(s);
      if ((prev < 0) != (v < 0)) {
        LD lo = LD(i - 1) / n, hi = s;
        const bool neg_lo = prev < 0;
        for (int it = 0; it < 200; ++it) {
          const LD mid = 0.5L * (lo + hi);
          ((fn(mid) < 0) == neg_lo ? lo : hi) = mid;
        }
        cuts.push_back(0.5L * (lo + hi));
      }
      prev = v;
    }
  };
  for (LD c : {LD(m.x1), LD(m.x2), LD(m.x1) + LD(m.x2)})
    roots([&](LD s) { return gx(s) * gx(s) + gy(s) * gy(s) - c * c; });
  roots([&](LD s) { return gx(s) * nx + gy(s) * ny; });
  std::sort(cuts.begin(), cuts.end());
  const Quadrature q = gauss_legendre(8);
  Ref out;
  const LD r1 = 1.0L / m.x1;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
    const int panels = 64;
    const LD h = (cuts[c + 1] - cuts[c]) / panels;
    for (int p = 0; p < panels; ++p)
      for (int k = 0; k < q.n; ++k) {
        const LD s = cuts[c] + h * (p + LD(q.s[k])), w = h * LD(q.w[k]);
        const LD x = gx(s), y = gy(s), r = std::sqrt(x * x + y * y), dn = x * nx + y * ny;
        LD e = ref_f(m, r), tx = r > 0 ? ref_fslope(m, r) * x / r : 0, ty = r > 0 ? ref_fslope(m, r) * y / r : 0;
        if (dn < 0) {
          const LD t = dn * r1, t4 = t * t * t * t;
          e += 0.0625L * m.k * dn * dn * t4;
          const LD gs = 0.375L * m.k * dn * t4;
          tx += gs * nx, ty += gs * ny;
        }
        out.e += w * e;
        out.f[0] += w * (1 - s) * tx, out.f[1] += w * (1 - s) * ty;
        out.f[2] += w * s * tx, out.f[3] += w * s * ty;
      }
  }
  out.e *= length;
  for (LD& f : out.f) f *= length;
  return out;
}

/// Segments that straddle each branch point (and some that do not), in every regime the closed
/// forms have to survive: nearly constant gaps, gaps passing close to or through zero, gaps
/// running across all branches, penetration entering, leaving or throughout.
std::vector<Gap> straddling_cases() {
  std::vector<Gap> cases;
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> A(0.0, 6.283185307179586), U(-1.0, 1.0);
  const double levels[] = {seg_law.x1, seg_law.x2, seg_law.x1 + seg_law.x2};
  for (double c : levels)
    for (double rel : {1e-9, 1e-6, 1e-3, 0.05, 0.4})
      for (int rep = 0; rep < 6; ++rep) {
        // |g| from c (1 - rel) to c (1 + rel), directions a little apart; normal at any angle
        const double a0 = A(gen), a1 = a0 + rel * U(gen), an = A(gen), sc = 1.0 + 0.3 * U(gen);
        const double r0 = c * (1 - rel), r1 = c * (1 + rel);
        const bool flip = rep % 2;
        Gap g{r0 * std::cos(a0), r0 * std::sin(a0), r1 * std::cos(a1), r1 * std::sin(a1), sc * std::cos(an),
              sc * std::sin(an)};
        if (flip) std::swap(g.g0x, g.g1x), std::swap(g.g0y, g.g1y);
        cases.push_back(g);
      }
  // a chord whose middle dips below a level while both ends are above it (two roots inside)
  for (double c : levels)
    for (double depth : {1e-6, 1e-2, 0.3, 0.9}) {
      const double y = c * (1 - depth), x = c * 1.2;
      cases.push_back({-x, y, x, y, 0.3, 1.0});
      cases.push_back({x, -y, -x, y * 0.5, 1.0, -0.2});
    }
  // through zero gap (the line passes the origin), across every branch on both sides
  cases.push_back({-0.05, 0.0, 0.05, 0.0, 0.0, 1.0});
  cases.push_back({-0.05, -0.02, 0.045, 0.018, 1.0, 0.0});
  cases.push_back({0.0, 0.0, 0.0, 0.05, 0.0, 1.0});  // opening from zero through all branches
  // penetration: dn crossing zero inside, negative throughout, with and without other branches
  cases.push_back({0.002, 0.001, -0.003, -0.004, 0.0, 1.0});
  cases.push_back({0.001, -0.002, 0.003, -0.006, 0.0, 1.0});
  cases.push_back({0.02, -0.001, 0.025, 0.02, 0.1, 1.0});
  cases.push_back({0.0, -0.015, 0.0, 0.012, 0.0, 1.0});
  // nearly constant gaps in each branch
  for (double r : {0.005, 0.02, 0.035, 0.05})
    cases.push_back({r, 0.3 * r, r * (1 + 1e-11), 0.3 * r * (1 - 1e-11), 0.6, 0.8});
  // random segments over the whole range
  std::uniform_real_distribution<double> G(-0.06, 0.06);
  for (int k = 0; k < 300; ++k) cases.push_back({G(gen), G(gen), G(gen), G(gen), U(gen), U(gen) + 1.5});
  return cases;
}
}  // namespace

TEST_CASE("segment integral: energy and end forces exact on every branch (1e-12 against a long-double reference)",
          "[cohesive][quadrature]") {
  const double L = 1.7;
  double worst_e = 0, worst_f = 0;
  for (const Gap& g : straddling_cases()) {
    const Ref ref = reference(seg_law, g, L);
    const double e = integrate(EnergyTag{}, seg_law, g, L);
    const EndForces f = integrate(TractionTag{}, seg_law, g, L);
    const double fv[4] = {f.f0x, f.f0y, f.f1x, f.f1y};
    const double fnorm = static_cast<double>(std::sqrt(ref.f[0] * ref.f[0] + ref.f[1] * ref.f[1] +
                                                       ref.f[2] * ref.f[2] + ref.f[3] * ref.f[3]));
    INFO("gap ends (" << g.g0x << ", " << g.g0y << ") (" << g.g1x << ", " << g.g1y << "), normal (" << g.nx << ", "
                      << g.ny << ")");
    const double ee = std::abs(e - static_cast<double>(ref.e)) / std::abs(static_cast<double>(ref.e));
    CHECK(ee <= 1e-12);
    worst_e = std::max(worst_e, ee);
    // relative to the forces, plus a floor at the rounding of the traction itself (a few ulps of
    // k (x1 + x2) L): near |g| = x1 + x2 the traction k (x1 + x2 - |g|) cancels
    const double floor = 1e-15 * seg_law.k * (seg_law.x1 + seg_law.x2) * L;
    for (int c = 0; c < 4; ++c) {
      const double excess = std::max(0.0, std::abs(fv[c] - static_cast<double>(ref.f[c])) - floor);
      const double fe = excess > 0.0 ? excess / fnorm : 0.0;
      CHECK(fe <= 1e-12);
      worst_f = std::max(worst_f, fe);
    }
  }
  // the accuracy the header states (a few ulps); printed with -s
  WARN("worst relative error: energy " << worst_e << ", forces " << worst_f);
  CHECK(worst_e < 1e-13);
  CHECK(worst_f < 1e-13);
}

TEST_CASE("segment integral: the old fixed 4-point rule missed by far more across a branch point",
          "[cohesive][quadrature]") {
  // the reference discriminates: the rule this replaces is off by > 1e-5 here, the new one is exact
  const Gap g{0.0, 0.0, 0.0, 0.05, 0.0, 1.0};
  const Quadrature q = gauss_legendre(4);
  double old = 0;
  for (int k = 0; k < q.n; ++k) old += q.w[k] * seg_law(EnergyTag{}, 0.0, q.s[k] * 0.05, 0.0, 1.0);
  const double ref = static_cast<double>(reference(seg_law, g, 1.0).e);
  CHECK(std::abs(old - ref) > 1e-5 * ref);
  CHECK(integrate(EnergyTag{}, seg_law, g, 1.0) == Catch::Approx(ref).epsilon(1e-14));
}

TEST_CASE("segment integral: polynomial pieces agree with a Gauss rule that is exact for them", "[cohesive][quadrature]") {
  // elastic and penetrating along the whole segment: density degree 6 in s, 4 points exact
  const Quadrature q = gauss_legendre(4);
  const Gap cases[] = {{0.0, -0.002, 0.0, -0.006, 0.0, 1.0}, {0.001, -0.004, -0.002, -0.003, 0.2, 1.1},
                       {0.003, 0.004, -0.002, 0.005, 0.3, 0.9}};
  for (const Gap& g : cases) {
    double e = 0, f[4] = {0, 0, 0, 0};
    for (int k = 0; k < q.n; ++k) {
      const double s = q.s[k], gx = g.g0x + s * (g.g1x - g.g0x), gy = g.g0y + s * (g.g1y - g.g0y);
      double tx, ty;
      seg_law(TractionTag{}, gx, gy, g.nx, g.ny, tx, ty);
      e += q.w[k] * seg_law(EnergyTag{}, gx, gy, g.nx, g.ny);
      f[0] += q.w[k] * (1 - s) * tx, f[1] += q.w[k] * (1 - s) * ty, f[2] += q.w[k] * s * tx, f[3] += q.w[k] * s * ty;
    }
    const EndForces ef = integrate(TractionTag{}, seg_law, g, 1.0);
    CHECK(integrate(EnergyTag{}, seg_law, g, 1.0) == Catch::Approx(e).epsilon(1e-13));
    const double fv[4] = {ef.f0x, ef.f0y, ef.f1x, ef.f1y};
    for (int c = 0; c < 4; ++c) CHECK(fv[c] == Catch::Approx(f[c]).epsilon(1e-12).margin(1e-18));
  }
}

TEST_CASE("segment integral: end forces are the gradient of the energy, across every branch point",
          "[cohesive][quadrature]") {
  const double L = 1.3;
  int checked = 0;
  for (const Gap& g : straddling_cases()) {
    const EndForces f = integrate(TractionTag{}, seg_law, g, L);
    const double fv[4] = {f.f0x, f.f0y, f.f1x, f.f1y};
    const double scale = std::max({std::abs(g.g0x), std::abs(g.g0y), std::abs(g.g1x), std::abs(g.g1y), 1e-3});
    const double h = 1e-8 * scale;
    auto E = [&](int c, double d) {
      Gap p = g;
      double* v[4] = {&p.g0x, &p.g0y, &p.g1x, &p.g1y};
      *v[c] += d;
      return integrate(EnergyTag{}, seg_law, p, L);
    };
    const double fnorm = std::sqrt(fv[0] * fv[0] + fv[1] * fv[1] + fv[2] * fv[2] + fv[3] * fv[3]);
    INFO("gap ends (" << g.g0x << ", " << g.g0y << ") (" << g.g1x << ", " << g.g1y << ")");
    for (int c = 0; c < 4; ++c) {
      // 4th-order central difference; the energy is C1 with piecewise-smooth second derivatives
      const double fd = (8 * (E(c, h) - E(c, -h)) - (E(c, 2 * h) - E(c, -2 * h))) / (12 * h);
      // tolerance: truncation (relative), the rounding of the energy differences (eps E / h), and
      // a stencil straddling a branch point, where the second derivative jumps by up to k L
      CHECK(std::abs(fv[c] - fd) <= 1e-6 * fnorm + 1e-14 * std::abs(E(c, 0.0)) / h + 2 * h * seg_law.k * L);
    }
    ++checked;
  }
  CHECK(checked > 350);
}

TEST_CASE("segment integral: continuous where the elastic fast path hands over", "[cohesive][quadrature]") {
  // |g1| just below and just above x1: fast closed form on one side, the piece loop on the other
  for (double eps : {1e-13, 1e-9}) {
    const Gap below{0.004, 0.001, seg_law.x1 * (1 - eps), 0.0, 0.0, 1.0}, above{0.004, 0.001, seg_law.x1 * (1 + eps), 0.0, 0.0, 1.0};
    const double e0 = integrate(EnergyTag{}, seg_law, below, 1.0), e1 = integrate(EnergyTag{}, seg_law, above, 1.0);
    CHECK(std::abs(e1 - e0) <= 4 * eps * e0 + 1e-17);
    const EndForces f0 = integrate(TractionTag{}, seg_law, below, 1.0), f1 = integrate(TractionTag{}, seg_law, above, 1.0);
    CHECK(f1.f1x == Catch::Approx(f0.f1x).epsilon(10 * eps + 1e-14));
    CHECK(f1.f0y == Catch::Approx(f0.f0y).epsilon(10 * eps + 1e-14));
  }
  // ruptured everywhere: constant energy, no force
  const Gap broken{0.05, 0.01, 0.06, -0.02, 1.0, 0.0};  // dn > 0
  CHECK(integrate(EnergyTag{}, seg_law, broken, 2.0) == Catch::Approx(2.0 * seg_law.k * seg_law.x1 * seg_law.x2).epsilon(1e-15));
  const EndForces fb = integrate(TractionTag{}, seg_law, broken, 2.0);
  CHECK(fb.f0x == 0.0);
  CHECK(fb.f1y == 0.0);
}

TEST_CASE("min_separation is the exact minimum of |gap| over the whole segment", "[cohesive][rupture]") {
  // a chord whose ends are far past rupture (x1 + x2 = 0.04) but whose middle is at 0.03: the
  // 4 Gauss points all lie past rupture, yet the interface is not broken everywhere
  const Gap g{-0.2, 0.03, 0.2, 0.03, 0.0, 1.0};
  CHECK(min_separation(g) == Catch::Approx(0.03).epsilon(1e-15));
  CHECK(min_separation(g) < seg_law.rupture_distance());
  const Quadrature q = gauss_legendre(4);
  for (int k = 0; k < q.n; ++k) CHECK(std::hypot(-0.2 + 0.4 * q.s[k], 0.03) > seg_law.rupture_distance());
  // its energy counts the intact middle: below the fully ruptured k x1 x2 L
  CHECK(integrate(EnergyTag{}, seg_law, g, 1.0) < seg_law.k * seg_law.x1 * seg_law.x2);
  // minimum at an end, at the foot inside, constant gap, and against dense sampling
  CHECK(min_separation({0.01, 0.0, 0.03, 0.0, 0, 1}) == 0.01);
  CHECK(min_separation({0.03, 0.01, 0.01, 0.01, 0, 1}) == Catch::Approx(std::hypot(0.01, 0.01)).epsilon(1e-15));
  CHECK(min_separation({0.02, 0.0, 0.02, 0.0, 0, 1}) == Catch::Approx(0.02).epsilon(1e-15));
  CHECK(min_separation({-0.01, -0.01, 0.01, 0.01, 0, 1}) == Catch::Approx(0.0).margin(1e-18));
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> G(-0.05, 0.05);
  for (int t = 0; t < 200; ++t) {
    const Gap r{G(gen), G(gen), G(gen), G(gen), 0, 1};
    double sampled = 1e300;
    for (int i = 0; i <= 20000; ++i) {
      const double s = i / 20000.0;
      sampled = std::min(sampled, std::hypot(r.g0x + s * (r.g1x - r.g0x), r.g0y + s * (r.g1y - r.g0y)));
    }
    const double m = min_separation(r);
    CHECK(m <= sampled * (1 + 1e-14));
    CHECK(m >= sampled - 1e-5 * std::hypot(r.g1x - r.g0x, r.g1y - r.g0y));  // the grid's step
  }
}

// ---- flops::Counted: the scalar that counts a unit's flops for nacre bench's FMA fraction
// (core/flop_count.hpp). The counts must be exact where they can be worked out by hand, and the
// counted code must compute the same values as the double code it counts.

TEST_CASE("Counted counts each operation once and computes the double's value", "[segment][flops]") {
  using nacre::flops::Counted;
  const Counted a = 1.5, b = -0.25, c = 3.0;
  Counted r;
  const auto n = nacre::flops::count([&] { r = (a * b + c) / (a - 2.0) + nacre::sc::sqrt(c) * nacre::sc::asinh(b); });
  CHECK(n.add == 3);  // a * b + c, a - 2, the outer +
  CHECK(n.mul == 2);
  CHECK(n.div == 1);
  CHECK(n.sqrt == 1);
  CHECK(n.transcendental == 1);
  CHECK(n.flops() == 3 + 2 + 1 + 1 + nacre::flops::kTranscendentalFlops);
  CHECK(r.v == (1.5 * -0.25 + 3.0) / (1.5 - 2.0) + std::sqrt(3.0) * std::asinh(-0.25));
  // comparisons, fabs, fmin / fmax and copysign are free
  const auto z = nacre::flops::count(
      [&] { (void)(a < b), (void)nacre::sc::fabs(b), (void)nacre::sc::fmax(a, b), (void)nacre::sc::copysign(a, b); });
  CHECK(z.flops() == 0);
}

TEST_CASE("the energy of a segment counted on Counted: exact counts, the double's bits", "[segment][flops]") {
  using nacre::flops::Counted;
  auto counted = [](const Gap& g, double L, Counted& e) {
    const BasicGap<Counted> c{g.g0x, g.g0y, g.g1x, g.g1y, g.nx, g.ny};
    return nacre::flops::count([&] { e = integrate(EnergyTag{}, seg_law, c, L); });
  };
  Counted e;
  // elastic along its whole length, no penetration: |g0|^2, |g1|^2 (3 each), the closed form
  // (4 * and 3 +), both ends' openings (3 each), the penalty's sum and the length: 21 flops
  const Gap elastic{0.002, 0.004, -0.001, 0.006, 0.0, 1.0};
  const auto n = counted(elastic, 0.7, e);
  CHECK(n.flops() == 21);
  CHECK(n.sqrt == 0);
  CHECK(n.transcendental == 0);
  CHECK(e.v == integrate(EnergyTag{}, seg_law, elastic, 0.7));
  // softening at one end, penetrating at the other: pieces with square roots and the asinh mean
  const Gap softening{0.001, -0.002, 0.02, 0.025, 0.0, 1.0};
  const auto s = counted(softening, 0.7, e);
  CHECK(e.v == integrate(EnergyTag{}, seg_law, softening, 0.7));
  CHECK(s.flops() > 3 * n.flops());
  CHECK(s.sqrt >= 2);
  CHECK(s.transcendental >= 1);
  const auto p = counted(Gap{0.002, -0.004, -0.001, 0.006, 0.0, 1.0}, 0.7, e);  // one end penetrates
  CHECK(p.flops() > n.flops());
  CHECK(p.div == 1);  // the penalty's one quotient
}

TEST_CASE("segment integral: finite and zero for the subnormal gaps ahead of a wave front", "[cohesive][quadrature]") {
  // the gap that stopped a 98,603-brick BE run at step 72 (its penalty's a^7 and (a - a') x1^4
  // both underflowed: 0 / 0), with the run's law (k 7000, x1 0.002, x2 0.004) and length
  const Law mortar{7000.0, 0.002, 0.004};
  const Gap front{
      -1.3861505759722013e-319, -3.0223873005563248e-318, 1.0869444208507424e-322, -7.9050503334599447e-322, 1.0, -0.0};
  const double e = integrate(EnergyTag{}, mortar, front, 0.030000000000000249);
  CHECK(std::isfinite(e));
  CHECK(std::abs(e) < 1e-290);
  const EndForces f = integrate(TractionTag{}, mortar, front, 0.030000000000000249);
  CHECK((std::isfinite(f.f0x) && std::isfinite(f.f0y) && std::isfinite(f.f1x) && std::isfinite(f.f1y)));
  // every scale from normal down to the smallest subnormal, no, one or both ends penetrating: the
  // energy finite and >= 0, the forces finite
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale = 1e-20; scale > 4e-324; scale *= 1e-4)
    for (int k = 0; k < 200; ++k) {
      const Gap g{scale * u(rng), scale * u(rng), scale * u(rng), scale * u(rng), 1.0, 0.0};
      const double eg = integrate(EnergyTag{}, mortar, g, 0.03);
      INFO("scale " << scale << " gap " << g.g0x << " " << g.g0y << " " << g.g1x << " " << g.g1y);
      CHECK(std::isfinite(eg));
      CHECK(eg >= 0.0);
      const EndForces fg = integrate(TractionTag{}, mortar, g, 0.03);
      CHECK((std::isfinite(fg.f0x) && std::isfinite(fg.f0y) && std::isfinite(fg.f1x) && std::isfinite(fg.f1y)));
    }
}

TEST_CASE("segment integral: finite where the gap barely changes along the segment, at every branch",
          "[cohesive][quadrature]") {
  // g1 = g0 + a tiny step (an almost rigid shift of the two sides): every piece's end values and
  // lengths near the underflow, on the elastic, plateau, softening and ruptured branches and
  // across dn = 0
  const Law mortar{7000.0, 0.002, 0.004};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double big : {0.0, 1e-3, 2.5e-3, 5e-3, 1e-2})
    for (double step = 1e-6; step > 4e-324; step *= 1e-5)
      for (int k = 0; k < 100; ++k) {
        const double gx = big * u(rng), gy = big * u(rng);
        const Gap g{gx, gy, gx + step * u(rng), gy + step * u(rng), u(rng), u(rng)};
        const double e = integrate(EnergyTag{}, mortar, g, 0.03);
        INFO("gap " << g.g0x << " " << g.g0y << " " << g.g1x << " " << g.g1y << " normal " << g.nx << " " << g.ny);
        CHECK(std::isfinite(e));
        CHECK(e >= 0.0);
        const EndForces f = integrate(TractionTag{}, mortar, g, 0.03);
        CHECK((std::isfinite(f.f0x) && std::isfinite(f.f0y) && std::isfinite(f.f1x) && std::isfinite(f.f1y)));
      }
}
