// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/mc/model.hpp>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <tuple>

namespace nacre::mc {

std::vector<int> sweep_order(const Colouring& colouring) {
  // free bricks by (colour, tile, wall order), then the driven bricks. Wall order inside a colour
  // or tile keeps neighbours of neighbours close in memory.
  const int n = static_cast<int>(colouring.colour.size());
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  auto key = [&](int i) {
    const int c = colouring.colour[i];
    return std::make_tuple(c < 0 ? colouring.n_colours : c, colouring.tile[i], i);
  };
  std::sort(perm.begin(), perm.end(), [&](int a, int b) { return key(a) < key(b); });
  return perm;
}

namespace {
template <class ExecutionSpace>
void alloc_tile_offset(const ExecutionSpace& space, Model<MemOf<ExecutionSpace>>& m, const std::vector<int>& toff) {
  m.tile_offset = Kokkos::View<int*, MemOf<ExecutionSpace>>(
      Kokkos::view_alloc(space, Kokkos::WithoutInitializing, "nacre::mc::tile_offset"), toff.size());
  auto h = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.tile_offset);
  for (std::size_t i = 0; i < toff.size(); ++i) h(i) = toff[i];
  Kokkos::deep_copy(space, m.tile_offset, h);
}

template <class ExecutionSpace>
Model<MemOf<ExecutionSpace>> build_model_on(const ExecutionSpace& space, const geometry::Specimen& s,
                                            const geometry::Interfaces& f, const geometry::Adjacency& adj,
                                            const Colouring& colouring, const deck::Mortar& mortar,
                                            int quadrature_points) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::build_model");
  using Mem = MemOf<ExecutionSpace>;
  Model<Mem> m;
  const int n = static_cast<int>(s.size()), ni = static_cast<int>(f.size());
  m.n_bricks = n;
  m.n_interfaces = ni;
  m.colouring_name = colouring.name;
  m.laws = cohesive::make_law_table(mortar.bed, mortar.head);  // no internal joints in rigid bricks
  m.quad = cohesive::gauss_legendre(quadrature_points);
  if (mortar.damage == cohesive::Damage::irreversible) {
    if (m.quad.n < 2) throw std::invalid_argument("mc: damage = \"irreversible\" needs at least 2 quadrature points");
    // zero: no separation seen yet (view_alloc initialises)
    m.hist = decltype(m.hist)(Kokkos::view_alloc(space, "nacre::mc::history"), ni, m.quad.n);
  }

  m.perm = sweep_order(colouring);
  m.colour_offset.assign(colouring.n_colours + 1, 0);
  for (int i = 0; i < n; ++i)
    if (colouring.colour[i] >= 0) ++m.colour_offset[colouring.colour[i] + 1];
  for (int c = 0; c < colouring.n_colours; ++c) m.colour_offset[c + 1] += m.colour_offset[c];
  m.n_free = m.colour_offset.back();
  // work items: a new one starts at each colour boundary, at each tile change, and at every
  // brick that has no tile
  std::vector<int> toff{0};
  m.colour_tiles.assign(1, 0);
  for (int c = 0; c < colouring.n_colours; ++c) {
    for (int k = m.colour_offset[c]; k < m.colour_offset[c + 1]; ++k) {
      const int t = colouring.tile[m.perm[k]];
      const bool last = k + 1 == m.colour_offset[c + 1];
      if (t < 0 || last || colouring.tile[m.perm[k + 1]] != t) toff.push_back(k + 1);
    }
    m.colour_tiles.push_back(static_cast<int>(toff.size()) - 1);
  }
  alloc_tile_offset(space, m, toff);
  std::vector<int> inv(n);
  for (int k = 0; k < n; ++k) inv[m.perm[k]] = k;

  // Interfaces are renumbered in the order the sweep first touches them (bricks in sweep order,
  // each brick's interfaces in turn), so the largest colours stream through the interface
  // array instead of hopping across it. iperm[new] = old.
  std::vector<int> iperm;
  iperm.reserve(ni);
  {
    std::vector<char> seen(ni, 0);
    for (int k = 0; k < n; ++k) {
      const int b = m.perm[k];
      for (int j = adj.offset[b]; j < adj.offset[b + 1]; ++j)
        if (!seen[adj.iface[j]]) seen[adj.iface[j]] = 1, iperm.push_back(adj.iface[j]);
    }
  }

  // Every View but the poses is filled from its host mirror below: no initialisation pass.
  auto alloc = [&](auto& v, const char* label, std::size_t len) {
    v = std::remove_reference_t<decltype(v)>(
        Kokkos::view_alloc(space, Kokkos::WithoutInitializing, std::string("nacre::mc::") + label), len);
  };
  m.pose = typename Model<Mem>::PoseView(Kokkos::view_alloc(space, std::string("nacre::mc::pose")), n);  // zero poses
  alloc(m.cx, "cx", n), alloc(m.cy, "cy", n), alloc(m.drive, "drive", n), alloc(m.id, "id", n);
  alloc(m.phi0, "phi0", n);
  alloc(m.adj_offset, "adj_offset", n + 1);
  alloc(m.ends, "ends", ni), alloc(m.seg, "seg", ni), alloc(m.kind, "kind", ni);

  auto hcx = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.cx), hcy = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.cy);
  auto hdrive = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.drive);
  auto hid = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.id);
  for (int k = 0; k < n; ++k) {
    const int i = m.perm[k];
    hcx(k) = s.cx[i], hcy(k) = s.cy[i];
    hdrive(k) = static_cast<std::int8_t>(s.drive[i]);
    hid(k) = static_cast<std::uint64_t>(i);
  }
  auto hends = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.ends);
  auto hseg = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.seg);
  auto hkind = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.kind);
  for (int i = 0; i < ni; ++i) {
    const int o = iperm[i];
    hends(i, 0) = inv[f.a[o]], hends(i, 1) = inv[f.b[o]];
    hkind(i) = static_cast<std::uint8_t>(f.kind[o]);
    const double v[col(SegCol::count)] = {f.ra0x[o], f.ra0y[o], f.ra1x[o], f.ra1y[o], f.rb0x[o], f.rb0y[o],
                                f.rb1x[o], f.rb1y[o], f.nx[o],   f.ny[o],   f.length[o]};
    for (int c = 0; c < col(SegCol::count); ++c) hseg(i, c) = v[c];
  }
  m.iface_perm = iperm;
  // CSR in sweep order, and the predictor's reference energy phi0 (all interfaces at x1).
  auto hoff = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.adj_offset);
  auto hphi0 = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.phi0);
  std::vector<int> deg(n, 0);
  for (int i = 0; i < ni; ++i) ++deg[hends(i, 0)], ++deg[hends(i, 1)];
  hoff(0) = 0;
  for (int k = 0; k < n; ++k) hoff(k + 1) = hoff(k) + deg[k];
  alloc(m.adj_iface, "adj_iface", hoff(n));
  auto hadj = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.adj_iface);
  std::vector<int> fill(n);
  for (int k = 0; k < n; ++k) fill[k] = hoff(k), hphi0(k) = 0;
  for (int i = 0; i < ni; ++i)
    for (int side = 0; side < 2; ++side) hadj(fill[hends(i, side)]++) = i;
  // Each brick's slots in the geometry's interface order, which is every sum's order per brick
  // (trial energies, brick energies, gradients): it does not depend on the sweep order, so a
  // rank's model of a part of the specimen (mc/halo.hpp) adds in the order of the whole one.
  for (int k = 0; k < n; ++k) {
    std::sort(hadj.data() + hoff(k), hadj.data() + hoff(k + 1), [&](int x, int y) { return iperm[x] < iperm[y]; });
    for (int j = hoff(k); j < hoff(k + 1); ++j) {
      const int i = hadj(j);
      const auto& law = m.laws[hkind(i)];
      hphi0(k) += 0.5 * law.k * law.x1 * law.x1 * hseg(i, col(SegCol::length));
    }
  }
  // The sweep's oriented records, slot by slot in adjacency order (the order of the sums).
  const int ns = hoff(n);
  alloc(m.slot, "slot", ns), alloc(m.slot_link, "slot_link", ns), alloc(m.slot_kind, "slot_kind", ns);
  auto hslot = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.slot);
  auto hlink = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.slot_link);
  auto hskind = Kokkos::create_mirror_view(Kokkos::WithoutInitializing, m.slot_kind);
  for (int k = 0; k < n; ++k)
    for (int j = hoff(k); j < hoff(k + 1); ++j) {
      const int i = hadj(j);
      const bool own_a = hends(i, 0) == k;
      using C = SegCol;
      const int own = own_a ? col(C::ra0x) : col(C::rb0x), other = own_a ? col(C::rb0x) : col(C::ra0x);
      for (int c = 0; c < 4; ++c) hslot(j, col(SlotCol::r0x) + c) = hseg(i, own + c);
      for (int c = 0; c < 4; ++c) hslot(j, col(SlotCol::o0x) + c) = hseg(i, other + c);
      hslot(j, col(SlotCol::nx)) = own_a ? hseg(i, col(C::nx)) : -hseg(i, col(C::nx));
      hslot(j, col(SlotCol::ny)) = own_a ? hseg(i, col(C::ny)) : -hseg(i, col(C::ny));
      hslot(j, col(SlotCol::length)) = hseg(i, col(C::length));
      hlink(j, 0) = hends(i, own_a ? 1 : 0), hlink(j, 1) = i;
      hskind(j) = hkind(i);
    }
  Kokkos::deep_copy(space, m.slot, hslot), Kokkos::deep_copy(space, m.slot_link, hlink);
  Kokkos::deep_copy(space, m.slot_kind, hskind);
  Kokkos::deep_copy(space, m.cx, hcx), Kokkos::deep_copy(space, m.cy, hcy);
  Kokkos::deep_copy(space, m.drive, hdrive), Kokkos::deep_copy(space, m.id, hid);
  Kokkos::deep_copy(space, m.ends, hends), Kokkos::deep_copy(space, m.seg, hseg);
  Kokkos::deep_copy(space, m.kind, hkind), Kokkos::deep_copy(space, m.adj_offset, hoff);
  Kokkos::deep_copy(space, m.adj_iface, hadj), Kokkos::deep_copy(space, m.phi0, hphi0);
  space.fence("nacre::mc::build_model");  // the host mirrors go out of scope
  return m;
}

}  // namespace

template <class ExecutionSpace, class>
Model<MemOf<ExecutionSpace>> build_model(const ExecutionSpace& space, const geometry::Specimen& s,
                                         const geometry::Interfaces& f, const geometry::Adjacency& adj,
                                         const Colouring& colouring, const deck::Mortar& mortar,
                                         int quadrature_points) {
  return build_model_on(space, s, f, adj, colouring, mortar, quadrature_points);
}

Model<> build_model(const Backend& backend, const geometry::Specimen& s, const geometry::Interfaces& f,
                    const geometry::Adjacency& adj, const Colouring& colouring, const deck::Mortar& mortar,
                    int quadrature_points) {
  return backend.visit_in<MemSpace>([&](const auto& space) -> Model<> {
    return build_model_on(space, s, f, adj, colouring, mortar, quadrature_points);
  });
}

// every enabled space (the default is one of them)
#define NACRE_MC_BUILD_MODEL(E)                                                                                    \
  template Model<MemOf<E>> build_model<E, void>(const E&, const geometry::Specimen&, const geometry::Interfaces&,  \
                                                const geometry::Adjacency&, const Colouring&, const deck::Mortar&, \
                                                int);
#ifdef KOKKOS_ENABLE_CUDA
NACRE_MC_BUILD_MODEL(Kokkos::Cuda)
#endif
#ifdef KOKKOS_ENABLE_HIP
NACRE_MC_BUILD_MODEL(Kokkos::HIP)
#endif
#ifdef KOKKOS_ENABLE_SYCL
NACRE_MC_BUILD_MODEL(Kokkos::SYCL)
#endif
#ifdef KOKKOS_ENABLE_THREADS
NACRE_MC_BUILD_MODEL(Kokkos::Threads)
#endif
#ifdef KOKKOS_ENABLE_SERIAL
NACRE_MC_BUILD_MODEL(Kokkos::Serial)
#endif
#ifdef KOKKOS_ENABLE_OPENMP
NACRE_MC_BUILD_MODEL(Kokkos::OpenMP)
#endif
#undef NACRE_MC_BUILD_MODEL

}  // namespace nacre::mc
