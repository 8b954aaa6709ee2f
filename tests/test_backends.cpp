// SPDX-License-Identifier: BSD-3-Clause
// The Monte Carlo kernels, written once, run on every enabled host backend (tests/backends.hpp)
// and must leave the same bits as on the default execution space: energies, rupture counts,
// and the poses after a series of colour sweeps with fixed uniforms. The deterministic sum and
// the cohesive law are checked the same way, and then the whole Monte Carlo solver on each backend
// a run can choose. (Which backends ran is printed by the first test.)
#include "backends.hpp"
#include "wall_specimen.hpp"

#include <nacre/aes/aes128.hpp>
#include <nacre/app/restart.hpp>
#include <nacre/cohesive/segment.hpp>
#include <nacre/core/backend.hpp>
#include <nacre/rng/uniform_source.hpp>
#include <nacre/loading/pattern.hpp>
#include <nacre/mc/kernels.hpp>
#include <nacre/mc/model.hpp>
#include <nacre/mc/solver.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/matchers/catch_matchers_string.hpp>
#include <catch2/catch_template_test_macros.hpp>
#include <catch2/catch_test_macros.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <utility>
#include <vector>

using namespace nacre;
using Catch::Matchers::ContainsSubstring;

// (external linkage: with CUDA and no host backend listed, nothing may instantiate the kernel
// sequence below, and nvcc would warn of an unreferenced internal function)
namespace nacre::test {
deck::Deck backend_deck() {
  deck::Deck d;
  d.geometry.width = 21.0, d.geometry.height = 8.0;
  d.geometry.brick_width = 3.5, d.geometry.brick_height = 1.0;
  d.geometry.notch_length = 8.0, d.geometry.notch_y = 4.0;
  d.mortar.bed = {100.0, 0.002, 0.004};
  d.mortar.head = {100.0, 0.001, 0.002};
  d.load.tension = 1.0, d.load.bending = 0.5;
  return d;
}
}  // namespace nacre::test

namespace {
using test::backend_deck;

/// What a backend leaves after the kernel sequence below (compared bit for bit).
struct Result {
  std::vector<double> pose;                  ///< n x 5 (with the cached rotation)
  std::vector<double> energies;              ///< total energy after each stage
  std::vector<double> brick_energy;          ///< per brick, final
  std::vector<double> iface_energy;          ///< per interface, final
  std::vector<std::int8_t> iface_state;
  std::vector<long> accepted;                ///< per sweep
  int ruptured = 0;
};

/// Load, then `cycles` cycles of colour sweeps with uniforms from a seeded host generator (the
/// same table for every backend), then the energy kernels; everything on `space`.
template <class ExecutionSpace>
Result run_kernels(const ExecutionSpace& space, int cycles) {
  const auto d = backend_deck();
  auto s = geometry::build_specimen(d.geometry);
  const auto f = geometry::find_interfaces(s, d.geometry);
  const auto adj = geometry::build_adjacency(s.size(), f);
  std::vector<bool> free(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) free[i] = s.drive[i] == geometry::Drive::free;
  const auto c = mc::colour_graph("tiles", s, adj, free, 1);
  auto m = mc::build_model(space, s, f, adj, c, d.mortar, 4);  // in the backend's own memory
  using MS = typename decltype(m)::memory_space;
  const loading::Pattern lp{d.load.tension, d.load.bending, d.geometry.width};
  SumWorkspace<MS> ws;
  Result r;
  mc::apply_load(space, m, lp, 0.01);
  r.energies.push_back(mc::total_energy(space, m, ws));
  rng::UniformTable<MS> u(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::test::u"), m.n_free);
  Field<double, MS> de(Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::test::de"), m.n_free);
  auto hu = Kokkos::create_mirror_view(u);
  std::mt19937_64 gen(2017);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int cyc = 0; cyc < cycles; ++cyc) {
    for (int b = 0; b < m.n_free; ++b)
      for (int k = 0; k < 4; ++k) hu(b, k) = U(gen);
    Kokkos::deep_copy(space, u, hu);
    for (std::size_t col = 0; col + 1 < m.colour_tiles.size(); ++col)
      r.accepted.push_back(mc::sweep_colour(space, m, m.colour_tiles[col], m.colour_tiles[col + 1], u, de, 2e-4,
                                            1e-4, 1e-7));
    auto dv = de;
    r.energies.push_back(deterministic_sum(space, "nacre::test::sum_de", ws, 0, m.n_free,
                                           KOKKOS_LAMBDA(const int b) { return dv(b); }));
    r.energies.push_back(mc::total_energy(space, m, ws));
  }
  Field<double, MS> be("nacre::test::brick_energy", m.n_bricks), ie("nacre::test::iface_energy", m.n_interfaces);
  Field<std::int8_t, MS> is("nacre::test::iface_state", m.n_interfaces);
  mc::brick_energy(space, m, be);
  r.ruptured = mc::interface_state(space, m, ie, is);
  space.fence();
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.pose);
  auto hbe = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), be);
  auto hie = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ie);
  auto his = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), is);
  for (int b = 0; b < m.n_bricks; ++b)
    for (int k = 0; k < 5; ++k) r.pose.push_back(hp(b, k));
  r.brick_energy.assign(hbe.data(), hbe.data() + hbe.extent(0));
  {  // from the interface energies already evaluated (the dumps' path): the same bits
    Field<double, MS> be2("nacre::test::brick_energy_from", m.n_bricks);
    mc::brick_energy(space, m, be2, Kokkos::View<const double*, MS>(ie));
    auto h2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), be2);
    bool same = true;
    for (int b = 0; b < m.n_bricks; ++b) same = same && std::memcmp(&h2(b), &hbe(b), sizeof(double)) == 0;
    CHECK(same);
  }
  r.iface_energy.assign(hie.data(), hie.data() + hie.extent(0));
  r.iface_state.assign(his.data(), his.data() + his.extent(0));
  return r;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

TEMPLATE_LIST_TEST_CASE("mc kernels leave the same bits on every host backend", "[mc][backends]",
                        test::HostBackends) {
  using Space = TestType;
  std::cout << "nacre backends test: " << Space::name() << " (enabled host backends: " << test::host_backend_names()
            << ")\n";
  const int cycles = 30;
  const Result ref = run_kernels(Kokkos::DefaultHostExecutionSpace{}, cycles);  // (the default one in a host build)
  const Result got = run_kernels(Space{}, cycles);
  // the run did something: trials were accepted and the energy moved
  long acc = 0;
  for (long a : got.accepted) acc += a;
  CHECK(acc > 0);
  REQUIRE(got.energies.size() == ref.energies.size());
  CHECK(got.energies.back() != got.energies.front());
  // energy bookkeeping inside the run: E(after cycle) - E(before) = sum of accepted changes
  for (int c = 0; c < cycles; ++c) {
    const double before = got.energies[2 * c], delta = got.energies[2 * c + 1], after = got.energies[2 * c + 2];
    CHECK(after - before == Catch::Approx(delta).margin(1e-12 * std::abs(after)));
  }
    CHECK(same_bits(got.pose, ref.pose));
    CHECK(same_bits(got.energies, ref.energies));
    CHECK(same_bits(got.brick_energy, ref.brick_energy));
    CHECK(same_bits(got.iface_energy, ref.iface_energy));
    CHECK(same_bits(got.iface_state, ref.iface_state));
    CHECK(got.accepted == ref.accepted);
    CHECK(got.ruptured == ref.ruptured);
}

TEMPLATE_LIST_TEST_CASE("deterministic_sum: the same bits in any order and any split, exact where the sum is",
                        "[core][backends]", test::HostBackends) {
  using Space = TestType;
  SumWorkspace<typename Space::memory_space> ws;
  // heavy cancellation over 16 binades: the order of a plain sum changes its last bits
  auto term = KOKKOS_LAMBDA(const int i) { return 1.0 / (1.0 + i) * ((i % 3) ? 1.0 : -1e3) * (1 + (i % 7) * 1e-9); };
  for (const auto& [begin, end] : {std::pair{0, 1000}, std::pair{3, 3 + 40000}}) {
    const double got = deterministic_sum(Space{}, "nacre::test::fold_sum", ws, begin, end, term);
    // the same terms folded on the host in a shuffled order, cut into pieces whose level sums
    // are joined in reverse (as ranks' partial results would be): the same bits
    std::vector<double> t;
    for (int i = begin; i < end; ++i) t.push_back(term(i));
    std::mt19937 g(7);
    std::shuffle(t.begin(), t.end(), g);
    double amax = 0;
    for (double x : t) amax = std::max(amax, std::abs(x));
    const sum::Plan plan = sum::plan(amax, static_cast<long long>(t.size()));
    std::vector<sum::Levels> pieces(5);
    for (std::size_t k = 0; k < t.size(); ++k) sum::fold(plan, t[k], pieces[(k * 7919) % pieces.size()]);
    sum::Levels joined;
    for (auto it = pieces.rbegin(); it != pieces.rend(); ++it)
      for (int l = 0; l < sum::kFolds; ++l) joined.s[l] += it->s[l];
    const double shuffled = sum::total(plan, joined);
    // an accurate reference: long double, compensated, sorted by magnitude
    std::sort(t.begin(), t.end(), [](double x, double y) { return std::abs(x) < std::abs(y); });
    long double ref = 0, c = 0;
    for (double x : t) {
      const long double y = x - c, z = ref + y;
      c = (z - ref) - y, ref = z;
    }
    CAPTURE(begin, end, got, shuffled, static_cast<double>(ref));
    CHECK(std::memcmp(&got, &shuffled, sizeof got) == 0);
    CHECK(std::abs(got - static_cast<double>(ref)) <= 2 * std::numeric_limits<double>::epsilon() * std::abs(got));
  }
  // exact where the exact sum is a double: +-x pairs across 40 binades cancel to the small tail
  auto pairs = KOKKOS_LAMBDA(const int i) {
    if (i >= 2000) return i == 2000 ? 0.375 : 0.0;
    const int k = i / 2;
    double p = 1.0 / 1024;  // 2^((k % 41) - 10), exactly
    for (int j = 0; j < k % 41; ++j) p *= 2;
    return ((i % 2) ? -1.0 : 1.0) * (1.0 + (k % 17) / 32.0) * p;
  };
  CHECK(deterministic_sum(Space{}, "nacre::test::fold_exact", ws, 0, 2500, pairs) == 0.375);
  // terms near the top of the range (the scaled path) and non-finite terms
  auto huge = KOKKOS_LAMBDA(const int i) { return i == 1000 ? 1e300 : (i % 2 ? -1.0 : 1.0) * 1e306; };
  CHECK(deterministic_sum(Space{}, "nacre::test::fold_huge", ws, 0, 1001, huge) == 1e300);
  const double inf = std::numeric_limits<double>::infinity();
  auto one_inf = KOKKOS_LAMBDA(const int i) { return i == 500 ? -inf : 1.0; };
  auto both_inf = KOKKOS_LAMBDA(const int i) { return i == 5 ? inf : (i == 6 ? -inf : 1.0); };
  auto a_nan = KOKKOS_LAMBDA(const int i) { return i == 9 ? 0.0 * inf : 1.0; };
  CHECK(deterministic_sum(Space{}, "nacre::test::fold_inf", ws, 0, 1000, one_inf) == -inf);
  CHECK(std::isnan(deterministic_sum(Space{}, "nacre::test::fold_infs", ws, 0, 1000, both_inf)));
  CHECK(std::isnan(deterministic_sum(Space{}, "nacre::test::fold_nan", ws, 0, 1000, a_nan)));
  CHECK(deterministic_sum(Space{}, "nacre::test::empty_sum", ws, 5, 5, term) == 0.0);
}

TEMPLATE_LIST_TEST_CASE("the cohesive law and the load pattern run inside kernels of every host backend",
                        "[cohesive][loading][backends]", test::HostBackends) {
  using Space = TestType;
  using MS = typename Space::memory_space;
  const cohesive::Law law{100.0, 0.01, 0.03};
  const cohesive::Quadrature q = cohesive::gauss_legendre(4);
  const loading::Pattern lp{1.0, 0.5, 20.0};
  const int n = 257;
  Kokkos::View<double* [7], MS> out("nacre::test::law_out", n);
  Kokkos::parallel_for(
      "nacre::test::law", Kokkos::RangePolicy<Space>(Space{}, 0, n), KOKKOS_LAMBDA(const int i) {
        const double g = -0.02 + 0.08 * i / (n - 1);  // through penetration, every branch and rupture
        const cohesive::Gap gap{0.3 * g, g, g, -0.5 * g, 0.0, 1.0};
        out(i, 0) = cohesive::integrate(cohesive::EnergyTag{}, law, q, gap, 1.5);
        const cohesive::EndForces ef = cohesive::integrate(cohesive::TractionTag{}, law, q, gap, 1.5);
        out(i, 1) = ef.f0x, out(i, 2) = ef.f1y;
        double fn, ft;
        law(cohesive::TractionTag{}, g, 0.5 * g, fn, ft);
        out(i, 3) = fn, out(i, 4) = ft;
        const kinematics::Pose p = loading::rigid_pose(lp, i % 2 ? 1 : -1, 20.0 * i / n, 0.0, g);
        out(i, 5) = p.y, out(i, 6) = p.t;
      });
  Space{}.fence();
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  for (int i = 0; i < n; ++i) {
    const double g = -0.02 + 0.08 * i / (n - 1);
    const cohesive::Gap gap{0.3 * g, g, g, -0.5 * g, 0.0, 1.0};
    CHECK(h(i, 0) == cohesive::integrate(cohesive::EnergyTag{}, law, q, gap, 1.5));
    const cohesive::EndForces ef = cohesive::integrate(cohesive::TractionTag{}, law, q, gap, 1.5);
    CHECK(h(i, 1) == ef.f0x);
    CHECK(h(i, 2) == ef.f1y);
    double fn, ft;
    law(cohesive::TractionTag{}, g, 0.5 * g, fn, ft);
    CHECK(h(i, 3) == fn);
    CHECK(h(i, 4) == ft);
    const kinematics::Pose p = loading::rigid_pose(lp, i % 2 ? 1 : -1, 20.0 * i / n, 0.0, g);
    CHECK(h(i, 5) == p.y);
    CHECK(h(i, 6) == p.t);
  }
}

TEMPLATE_LIST_TEST_CASE("Philox uniforms are the same numbers on every backend", "[rng][backends]", test::RunBackends) {
  // in the backend's own memory (where a Monte Carlo solver built for it keeps its table)
  using MS = MemOf<TestType>;
  const std::size_t n = 3001;
  Kokkos::View<std::uint64_t*, MS> id_view("nacre::test::ids", n);
  const rng::StreamIds<MS> ids = id_view;
  rng::UniformTable<MS> mine("nacre::test::u", n), ref("nacre::test::u_ref", n);
  auto hid = Kokkos::create_mirror_view(id_view);
  for (std::size_t i = 0; i < n; ++i) hid(i) = 7919 * i + 3;  // any stream ids, not contiguous
  Kokkos::deep_copy(id_view, hid);
  for (const std::uint64_t draw : {0ull, 1ull, 123456789ull}) {
    rng::philox_fill(TestType{}, 42, draw, ids, mine);
    TestType{}.fence();
    rng::PhiloxSource(42).fill(Backend(TestType{}), draw, ids, ref);  // the source the Monte Carlo sweep uses
    Kokkos::fence();
    auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, mine);
    auto b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, ref);
    INFO(TestType::name() << ", draw " << draw);
    CHECK(std::memcmp(a.data(), b.data(), a.span() * sizeof(double)) == 0);
    for (std::size_t i = 0; i < n; ++i) {  // and each value is the device function's, in (0, 1)
      double r[4];
      rng::philox_uniforms(42, hid(i), draw, r);
      for (int k = 0; k < 4; ++k) REQUIRE((a(i, k) == r[k] && r[k] >= 0 && r[k] < 1));
    }
  }
}

TEST_CASE("a restart is bit-compatible between host backends, not between a device and the host", "[backends]") {
  for (const auto& name : Backend::names()) {
    const Backend b = Backend::parse(name);
    INFO("backend " << name);
    CHECK(b.bit_compatible(name));
    CHECK(b.bit_compatible(b.kokkos_name()));  // case-insensitive
    const bool host = b.reaches<Kokkos::HostSpace>();
    CHECK(b.bit_compatible("serial") == (host || name == "serial"));
    CHECK(b.bit_compatible("openmp") == (host || name == "openmp"));
    CHECK(b.bit_compatible("cuda") == (name == "cuda"));
    // the app's restart check: a checkpoint from the device is refused on the host, naming the way out
    if (host) {
      CHECK_NOTHROW(app::check_restart_backend("cp.h5", "serial", name));
      // (a checkpoint older than the record: written on the build's default backend)
      if (Backend{}.bit_compatible(name))
        CHECK_NOTHROW(app::check_restart_backend("cp.h5", "", name));
      else
        CHECK_THROWS(app::check_restart_backend("cp.h5", "", name));
      CHECK_THROWS_WITH(app::check_restart_backend("cp.h5", "cuda", name),
                        ContainsSubstring("cp.h5: written on cuda") && ContainsSubstring("--backend cuda"));
    } else {
      CHECK_THROWS_WITH(app::check_restart_backend("cp.h5", "openmp", name), ContainsSubstring("--backend openmp"));
    }
  }
}

TEST_CASE("AES-128 encrypts to the same bytes on every backend of the build", "[aes][backends]") {
  // FIPS-197 Appendix C.1, then 4099 random blocks (several threads' chunks and a padded tail)
  // on each backend chosen at run time (nacre::Backend): the same bytes as the default space's
  aes::Key128 key{};
  for (int i = 0; i < 16; ++i) key.bytes[i] = static_cast<std::uint8_t>(i);
  const std::size_t nb = 4099;
  Kokkos::View<std::uint8_t*, MemSpace> in("nacre::test::aes_in", 16 * nb), ref("nacre::test::aes_ref", 16 * nb),
      out("nacre::test::aes_out", 16 * nb);
  auto hin = Kokkos::create_mirror_view(in);
  const std::uint8_t c1[16] = {0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77,
                               0x88, 0x99, 0xaa, 0xbb, 0xcc, 0xdd, 0xee, 0xff};
  const std::uint8_t c1_ct[16] = {0x69, 0xc4, 0xe0, 0xd8, 0x6a, 0x7b, 0x04, 0x30,
                                  0xd8, 0xcd, 0xb7, 0x80, 0x70, 0xb4, 0xc5, 0x5a};
  std::mt19937 gen(5);
  for (std::size_t i = 0; i < 16 * nb; ++i) hin(i) = i < 16 ? c1[i] : static_cast<std::uint8_t>(gen());
  Kokkos::deep_copy(in, hin);
  aes::aes128_ecb_encrypt(Backend{}, key, in, ref);
  Kokkos::fence();
  const auto href = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, ref);
  CHECK(std::memcmp(href.data(), c1_ct, 16) == 0);
  for (const auto& name : Backend::names()) {
    const Backend b = Backend::parse(name);
    if (!b.reaches<MemSpace>()) continue;  // (a host backend of a CUDA build: the generators' test below)
    Kokkos::deep_copy(out, std::uint8_t(0));
    aes::aes128_ecb_encrypt(b, key, in, out);
    b.fence();
    const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, out);
    INFO("backend " << name);
    CHECK(std::memcmp(h.data(), href.data(), h.span()) == 0);
  }
}

TEST_CASE("the Monte Carlo solver runs the same path on every backend, and a checkpoint moves between them",
          "[mc][backends][restart]") {
  // The whole solver (colour sweeps, the uniform source, the adaptive steps, the FIRE polish, the
  // residual test) built for each backend the run can choose (mc::Solver picks SolverOn<space>
  // once, its model in the backend's memory): every step record and the final poses the same bits
  // as on the reference of the backend's kind of arithmetic (the first host backend; the device);
  // a checkpoint written on that reference continues on each such backend to the same end.
  auto d = backend_deck();
  d.output.hdf5 = false, d.output.charts = false;
  d.solver.colouring = "tiles";
  test::cracking_path(d);
  d.load.final_displacement = 0.012;
  test::short_windows(d);
  auto s = geometry::build_specimen(d.geometry);  // (find_interfaces annotates it)
  const auto f = geometry::find_interfaces(s, d.geometry);
  struct Path {
    std::vector<mc::StepRecord> rows;
    std::vector<double> x, y, t;
  };
  auto run = [&](const Backend& b, const mc::Checkpoint* from, mc::Checkpoint* keep) {
    mc::Solver solver(b, d, s, f);
    CHECK(solver.backend().name() == b.name());
    if (from) solver.restore(*from);
    Path p;
    solver.run([&](const mc::StepRecord& r) {
      p.rows.push_back(r);
      if (keep && r.step == 1) *keep = solver.checkpoint();
    });
    REQUIRE_FALSE(solver.failed());
    solver.poses(p.x, p.y, p.t);
    return p;
  };
  for (const bool aes : {false, true}) {
    d.solver.rng = aes ? "aes-ctr" : "philox";  // in the sweep / a table the source fills
    d.solver.per_brick_steps = aes;             // and both step modes
    CAPTURE(d.solver.rng);
    // the reference of each kind of arithmetic: the first backend on the host, the device (a
    // CUDA build's host backends keep their model in host memory: bit for bit with each other,
    // not with the device, Backend::bit_compatible)
    std::vector<std::pair<std::string, std::pair<Path, mc::Checkpoint>>> refs;
    for (const auto& name : Backend::names()) {
      INFO("backend " << name);
      const Backend b = Backend::parse(name);
      std::size_t k_ref = 0;
      while (k_ref < refs.size() && !b.bit_compatible(refs[k_ref].first)) ++k_ref;
      if (k_ref == refs.size()) {
        mc::Checkpoint cp;
        Path ref = run(b, nullptr, &cp);
        REQUIRE(ref.rows.size() >= 3);
        CHECK(ref.rows.back().ruptured > 0);  // the notch opens: the non-elastic branches ran
        CHECK(cp.backend == name);
        refs.push_back({name, {std::move(ref), cp}});
      }
      // (the reference's own backend again: the run is deterministic)
      const auto& [ref, cp] = refs[k_ref].second;
      const Path p = run(b, nullptr, nullptr);
      REQUIRE(p.rows.size() == ref.rows.size());
      for (std::size_t k = 0; k < p.rows.size(); ++k) {
        CHECK(p.rows[k].energy == ref.rows[k].energy);  // bit for bit
        CHECK(p.rows[k].cycles == ref.rows[k].cycles);
        CHECK(p.rows[k].residual == ref.rows[k].residual);
        CHECK(p.rows[k].polish_iterations == ref.rows[k].polish_iterations);
      }
      CHECK(p.x == ref.x);
      CHECK(p.y == ref.y);
      CHECK(p.t == ref.t);
      // a checkpoint written on the reference's backend continues here to the same end
      const Path resumed = run(b, &cp, nullptr);
      REQUIRE(resumed.rows.size() == ref.rows.size() - 1);
      CHECK(resumed.rows.back().energy == ref.rows.back().energy);
      CHECK(resumed.t == ref.t);
    }
    // every host backend of the build ran against one reference; a device (a CUDA build) adds one
    CHECK(refs.size() == (Backend{}.reaches<Kokkos::HostSpace>() ? 1u : 2u));
  }
}
