// SPDX-License-Identifier: BSD-3-Clause
// Determinism: a cracking run (interfaces through all branches of the law, rupture included)
// leaves the same bits on any thread count. CTest runs this on 1 and 2 threads; each run writes
// its fingerprints to NACRE_HASH_OUT and a third test compares the files.
#include "common.hpp"

#include <catch2/catch_test_macros.hpp>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

using namespace dyntest;

namespace {
std::uint64_t fnv(const std::vector<double>& v, std::uint64_t h = 1469598103934665603ull) {
  for (double x : v) {
    std::uint64_t b;
    std::memcpy(&b, &x, 8);
    for (int k = 0; k < 8; ++k) h = (h ^ ((b >> (8 * k)) & 0xff)) * 1099511628211ull;
  }
  return h;
}
}  // namespace

TEST_CASE("dyn: a cracking run is bit-identical for any thread count", "[dyn][determinism]") {
  const auto st = make(wall(6, 6, 2.5));
  const deck::Mortar weak{{7000, 0.0005, 0.001}, {7000, 0.0005, 0.001}};
  std::ostringstream prints;
  for (auto method : {dyn::Method::be, dyn::Method::ue}) {
    auto p = params(10, method);
    p.rate = 2000.0, p.ramp_time = 1e-6, p.ramp = dyn::Ramp::smooth;
    p.tension = 0.2, p.bending = 1;
    p.alpha_d = 1e5, p.beta_d = 1e-9;
    p.dt = 1.0;
    dyn::HostMap map;
    p.dt = 0.8 * dyn::build_model(p, st.s, st.f, weak, map).step_estimate;
    dyn::Simulation sim(p, st.s, st.f, weak);
    const bool ok = sim.advance(Kokkos::DefaultExecutionSpace{}, 1500);
    INFO(sim.why());
    REQUIRE(ok);
    const auto s = sim.save_state();
    const auto e = sim.energies();
    INFO("ruptured " << sim.ruptured() << " D " << sim.displacement());
    CHECK(sim.ruptured() > 0);
    std::uint64_t h = fnv(s.at("u"));
    h = fnv(s.at("v"), h);
    h = fnv(s.at("acc"), h);
    h = fnv({e.strain, e.kinetic, e.cohesive, e.external_work, e.damping_dissipated, sim.reaction()}, h);
    prints << int(method) << " " << sim.ruptured() << " " << std::hex << h << std::dec << "\n";
  }
  if (const char* out = std::getenv("NACRE_HASH_OUT")) std::ofstream(out) << prints.str();
}
