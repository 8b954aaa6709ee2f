#include <nacre/mc/model.hpp>

#include <algorithm>
#include <numeric>

namespace nacre::mc {

Model<> build_model(const geometry::Specimen& s, const geometry::Interfaces& f,
                    const Colouring& colouring, const deck::Mortar& mortar, int quadrature_points) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::build_model");
  Model<> m;
  const int n = static_cast<int>(s.size()), ni = static_cast<int>(f.size());
  m.n_bricks = n;
  m.n_interfaces = ni;
  m.colouring_name = colouring.name;
  m.law[0] = mortar.bed;
  m.law[1] = mortar.head;
  m.quad = cohesive::gauss_legendre(quadrature_points);

  // Sweep order: free bricks by colour (stable: wall order inside a colour keeps neighbours of
  // neighbours close in memory), then the driven bricks.
  m.colour_offset.assign(colouring.n_colours + 1, 0);
  for (int i = 0; i < n; ++i)
    if (colouring.colour[i] >= 0) ++m.colour_offset[colouring.colour[i] + 1];
  for (int c = 0; c < colouring.n_colours; ++c) m.colour_offset[c + 1] += m.colour_offset[c];
  m.n_free = m.colour_offset.back();
  m.perm.resize(n);
  {
    std::vector<int> fill(m.colour_offset.begin(), m.colour_offset.end() - 1);
    int driven = m.n_free;
    for (int i = 0; i < n; ++i) {
      const int c = colouring.colour[i];
      m.perm[c >= 0 ? fill[c]++ : driven++] = i;
    }
  }
  std::vector<int> inv(n);
  for (int k = 0; k < n; ++k) inv[m.perm[k]] = k;

  auto alloc = [](auto& v, const char* label, std::size_t len) {
    v = std::remove_reference_t<decltype(v)>(Kokkos::view_alloc(std::string("nacre::mc::") + label), len);
  };
  alloc(m.x, "x", n), alloc(m.y, "y", n), alloc(m.t, "t", n);
  alloc(m.cx, "cx", n), alloc(m.cy, "cy", n), alloc(m.drive, "drive", n), alloc(m.id, "id", n);
  alloc(m.phi0, "phi0", n);
  alloc(m.adj_offset, "adj_offset", n + 1);
  alloc(m.ends, "ends", ni), alloc(m.seg, "seg", ni), alloc(m.kind, "kind", ni);

  auto hcx = Kokkos::create_mirror_view(m.cx), hcy = Kokkos::create_mirror_view(m.cy);
  auto hdrive = Kokkos::create_mirror_view(m.drive);
  auto hid = Kokkos::create_mirror_view(m.id);
  for (int k = 0; k < n; ++k) {
    const int i = m.perm[k];
    hcx(k) = s.cx[i], hcy(k) = s.cy[i];
    hdrive(k) = static_cast<std::int8_t>(s.drive[i]);
    hid(k) = static_cast<std::uint64_t>(i);
  }
  auto hends = Kokkos::create_mirror_view(m.ends);
  auto hseg = Kokkos::create_mirror_view(m.seg);
  auto hkind = Kokkos::create_mirror_view(m.kind);
  for (int i = 0; i < ni; ++i) {
    hends(i, 0) = inv[f.a[i]], hends(i, 1) = inv[f.b[i]];
    hkind(i) = static_cast<std::uint8_t>(f.kind[i]);
    const double v[SEG_COLS] = {f.ra0x[i], f.ra0y[i], f.ra1x[i], f.ra1y[i], f.rb0x[i], f.rb0y[i],
                                f.rb1x[i], f.rb1y[i], f.nx[i],   f.ny[i],   f.length[i]};
    for (int c = 0; c < SEG_COLS; ++c) hseg(i, c) = v[c];
  }
  // CSR in sweep order, and the predictor's reference energy phi0 (all interfaces at x1).
  auto hoff = Kokkos::create_mirror_view(m.adj_offset);
  auto hphi0 = Kokkos::create_mirror_view(m.phi0);
  std::vector<int> deg(n, 0);
  for (int i = 0; i < ni; ++i) ++deg[hends(i, 0)], ++deg[hends(i, 1)];
  hoff(0) = 0;
  for (int k = 0; k < n; ++k) hoff(k + 1) = hoff(k) + deg[k];
  alloc(m.adj_iface, "adj_iface", hoff(n));
  auto hadj = Kokkos::create_mirror_view(m.adj_iface);
  std::vector<int> fill(n);
  for (int k = 0; k < n; ++k) fill[k] = hoff(k), hphi0(k) = 0;
  for (int i = 0; i < ni; ++i)
    for (int side = 0; side < 2; ++side) {
      const int k = hends(i, side);
      hadj(fill[k]++) = i;
      const auto& law = m.law[hkind(i)];
      hphi0(k) += 0.5 * law.k * law.x1 * law.x1 * f.length[i];
    }
  Kokkos::deep_copy(m.cx, hcx), Kokkos::deep_copy(m.cy, hcy), Kokkos::deep_copy(m.drive, hdrive);
  Kokkos::deep_copy(m.id, hid), Kokkos::deep_copy(m.ends, hends), Kokkos::deep_copy(m.seg, hseg);
  Kokkos::deep_copy(m.kind, hkind), Kokkos::deep_copy(m.adj_offset, hoff);
  Kokkos::deep_copy(m.adj_iface, hadj), Kokkos::deep_copy(m.phi0, hphi0);
  return m;
}

}  // namespace nacre::mc
