// SPDX-License-Identifier: BSD-3-Clause
// Interface detection: bricks are binned by centroid into square cells no smaller than a brick's
// diameter, so any two bricks sharing an edge sit in the same or adjacent cells (O(N) overall).
// Two bricks share an interface where an edge of one is collinear with, antiparallel to and
// overlapping an edge of the other.
#include <nacre/geometry/specimen.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace nacre::geometry {

Interfaces find_interfaces(Specimen& s, const deck::Geometry& g) {
  const double W = g.width, H = g.height;
  const double eps = 1e-9 * std::max(W, H);
  const double cell = std::hypot(g.brick_width, g.brick_height) * 1.0001;
  const int nx = std::max(1, static_cast<int>(std::ceil(W / cell))), ny = std::max(1, static_cast<int>(std::ceil(H / cell)));
  const std::size_t n = s.size();

  // counting sort of bricks by cell
  auto cell_of = [&](std::size_t i) {
    const int cx = std::clamp(static_cast<int>(s.cx[i] / cell), 0, nx - 1);
    const int cy = std::clamp(static_cast<int>(s.cy[i] / cell), 0, ny - 1);
    return cy * nx + cx;
  };
  std::vector<int> start(static_cast<std::size_t>(nx) * ny + 1, 0), order(n);
  for (std::size_t i = 0; i < n; ++i) ++start[cell_of(i) + 1];
  for (std::size_t c = 0; c + 1 < start.size(); ++c) start[c + 1] += start[c];
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order[fill[cell_of(i)]++] = static_cast<int>(i);
  }

  const double al = g.angle_deg * std::numbers::pi / 180.0;
  const double ux = std::cos(al), uy = std::sin(al);  // wall row direction
  Interfaces f;
  f.a.reserve(3 * n);

  auto add = [&](int a, int b, double x0, double y0, double x1, double y1, double nxv, double nyv) {
    // The notch: no bond along y = notch_y for x < notch_length (clip that part away).
    if (g.notch_length > 0 && std::abs(y0 - g.notch_y) <= eps && std::abs(y1 - g.notch_y) <= eps) {
      if (x0 > x1) std::swap(x0, x1), std::swap(y0, y1);
      if (x1 <= g.notch_length + eps) return;
      x0 = std::max(x0, g.notch_length);
    }
    const double len = std::hypot(x1 - x0, y1 - y0);
    if (len <= 1e-6 * std::min(g.brick_width, g.brick_height)) return;
    f.a.push_back(a), f.b.push_back(b);
    const double along = std::abs((x1 - x0) * ux + (y1 - y0) * uy) / len;
    f.kind.push_back(along > 0.5 ? JointKind::bed : JointKind::head);
    f.ra0x.push_back(x0 - s.cx[a]), f.ra0y.push_back(y0 - s.cy[a]);
    f.ra1x.push_back(x1 - s.cx[a]), f.ra1y.push_back(y1 - s.cy[a]);
    f.rb0x.push_back(x0 - s.cx[b]), f.rb0y.push_back(y0 - s.cy[b]);
    f.rb1x.push_back(x1 - s.cx[b]), f.rb1y.push_back(y1 - s.cy[b]);
    f.nx.push_back(nxv), f.ny.push_back(nyv), f.length.push_back(len);
  };

  // bounding boxes: most candidate pairs from the 3x3 cells do not even touch
  std::vector<double> bx0(n), bx1(n), by0(n), by1(n);
  for (std::size_t i = 0; i < n; ++i) {
    bx0[i] = by0[i] = 1e300, bx1[i] = by1[i] = -1e300;
    for (int v = s.poly_offset[i]; v < s.poly_offset[i + 1]; ++v) {
      bx0[i] = std::min(bx0[i], s.vx[v]), bx1[i] = std::max(bx1[i], s.vx[v]);
      by0[i] = std::min(by0[i], s.vy[v]), by1[i] = std::max(by1[i], s.vy[v]);
    }
  }
  const double touch = 1e3 * eps;
  auto match = [&](int a, int b) {
    if (bx0[b] > bx1[a] + touch || bx0[a] > bx1[b] + touch || by0[b] > by1[a] + touch || by0[a] > by1[b] + touch)
      return;
    if (s.parent[a] == s.parent[b]) return;  // two halves of a notch-split brick: the notch
    for (int i = s.poly_offset[a]; i < s.poly_offset[a + 1]; ++i) {
      const int i1 = (i + 1 == s.poly_offset[a + 1]) ? s.poly_offset[a] : i + 1;
      const double px = s.vx[i], py = s.vy[i], dx = s.vx[i1] - px, dy = s.vy[i1] - py;
      const double lp = std::hypot(dx, dy);
      if (lp <= eps) continue;
      const double ex = dx / lp, ey = dy / lp;
      for (int j = s.poly_offset[b]; j < s.poly_offset[b + 1]; ++j) {
        const int j1 = (j + 1 == s.poly_offset[b + 1]) ? s.poly_offset[b] : j + 1;
        const double qx = s.vx[j], qy = s.vy[j], fx = s.vx[j1] - qx, fy = s.vy[j1] - qy;
        const double lq = std::hypot(fx, fy);
        if (lq <= eps) continue;
        if ((ex * fx + ey * fy) / lq > -1 + 1e-9) continue;                         // antiparallel
        if (std::abs((qx - px) * ey - (qy - py) * ex) > 1e3 * eps) continue;       // collinear
        const double t0 = (qx - px) * ex + (qy - py) * ey, t1 = (s.vx[j1] - px) * ex + (s.vy[j1] - py) * ey;
        const double lo = std::max(0.0, std::min(t0, t1)), hi = std::min(lp, std::max(t0, t1));
        if (hi - lo <= eps) continue;
        // CCW polygons: the outward normal of edge (ex, ey) is (ey, -ex), pointing from a to b.
        add(a, b, px + lo * ex, py + lo * ey, px + hi * ex, py + hi * ey, ey, -ex);
      }
    }
  };

  for (int cy = 0; cy < ny; ++cy)
    for (int cx = 0; cx < nx; ++cx) {
      const int c = cy * nx + cx;
      for (int p = start[c]; p < start[c + 1]; ++p) {
        const int a = order[p];
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int ox = cx + dx, oy = cy + dy;
            if (ox < 0 || oy < 0 || ox >= nx || oy >= ny) continue;
            const int o = oy * nx + ox;
            for (int q = start[o]; q < start[o + 1]; ++q) {
              const int b = order[q];
              if (b > a) match(a, b);
            }
          }
      }
    }

  // Remove bricks without any interface (slivers cut off by the notch or the boundary).
  std::vector<int> degree(n, 0);
  for (std::size_t i = 0; i < f.size(); ++i) ++degree[f.a[i]], ++degree[f.b[i]];
  if (std::find(degree.begin(), degree.end(), 0) != degree.end()) {
    std::vector<int> renum(n, -1);
    Specimen t;
    t.width = s.width, t.height = s.height, t.full_brick_area = s.full_brick_area;
    for (std::size_t i = 0; i < n; ++i) {
      if (degree[i] == 0) continue;
      renum[i] = static_cast<int>(t.size());
      t.cx.push_back(s.cx[i]), t.cy.push_back(s.cy[i]), t.area.push_back(s.area[i]);
      t.drive.push_back(s.drive[i]), t.parent.push_back(s.parent[i]);
      for (int v = s.poly_offset[i]; v < s.poly_offset[i + 1]; ++v) t.vx.push_back(s.vx[v]), t.vy.push_back(s.vy[v]);
      t.poly_offset.push_back(static_cast<int>(t.vx.size()));
    }
    for (std::size_t i = 0; i < f.size(); ++i) f.a[i] = renum[f.a[i]], f.b[i] = renum[f.b[i]];
    s = std::move(t);
  }
  return f;
}

Adjacency build_adjacency(std::size_t n_bricks, const Interfaces& f) {
  Adjacency adj;
  adj.offset.assign(n_bricks + 1, 0);
  for (std::size_t i = 0; i < f.size(); ++i) ++adj.offset[f.a[i] + 1], ++adj.offset[f.b[i] + 1];
  for (std::size_t i = 0; i < n_bricks; ++i) adj.offset[i + 1] += adj.offset[i];
  adj.iface.resize(adj.offset.back());
  adj.neighbour.resize(adj.offset.back());
  std::vector<int> fill(adj.offset.begin(), adj.offset.end() - 1);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const int a = f.a[i], b = f.b[i];
    adj.iface[fill[a]] = static_cast<int>(i), adj.neighbour[fill[a]++] = b;
    adj.iface[fill[b]] = static_cast<int>(i), adj.neighbour[fill[b]++] = a;
  }
  return adj;
}

}  // namespace nacre::geometry
