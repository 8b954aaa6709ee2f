// SPDX-License-Identifier: BSD-3-Clause
// Wall construction: each wall-grid brick is a rectangle in the wall frame; mapped to the
// specimen frame it is clipped (Sutherland-Hodgman) to the specimen rectangle, and bricks whose
// centroid lies left of the notch tip and that straddle the notch line are split in two.
#include <nacre/geometry/specimen.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace nacre::geometry {
namespace {

struct P {
  double x, y;
};
using Poly = std::vector<P>;

/// \brief Keep the part of `in` where a*x + b*y <= c.
Poly clip(const Poly& in, double a, double b, double c) {
  Poly out;
  out.reserve(in.size() + 2);
  const std::size_t n = in.size();
  for (std::size_t i = 0; i < n; ++i) {
    const P p = in[i], q = in[(i + 1) % n];
    const double fp = a * p.x + b * p.y - c, fq = a * q.x + b * q.y - c;
    if (fp <= 0) out.push_back(p);
    if ((fp < 0 && fq > 0) || (fp > 0 && fq < 0)) {
      const double t = fp / (fp - fq);
      out.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
    }
  }
  return out;
}

/// \brief Area and centroid (shoelace); vertices closer than eps are merged first. The sums run
/// on coordinates relative to the first vertex: on absolute ones the cross products of a brick far
/// from the origin cancel (~78 mm x 39 mm against a 0.003 mm^2 brick) and left ~4e-11 mm of
/// rounding in the centroid, enough to split equal shapes into element types of their own
/// (669 types at 980,535 bricks, 13 at 98,325, where 2 shapes exist); relative, the error is that
/// of the inputs.
bool finish(Poly& p, double eps, double& area, double& cx, double& cy) {
  Poly q;
  for (auto& v : p)
    if (q.empty() || std::hypot(v.x - q.back().x, v.y - q.back().y) > eps) q.push_back(v);
  while (q.size() > 1 && std::hypot(q.front().x - q.back().x, q.front().y - q.back().y) <= eps) q.pop_back();
  p = q;
  if (p.size() < 3) return false;
  const P o = p[0];
  double a = 0, sx = 0, sy = 0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {  // edges touching o have c = 0
    const P u{p[i].x - o.x, p[i].y - o.y}, v{p[i + 1].x - o.x, p[i + 1].y - o.y};
    const double c = u.x * v.y - v.x * u.y;
    a += c;
    sx += (u.x + v.x) * c;
    sy += (u.y + v.y) * c;
  }
  area = 0.5 * a;
  if (area <= 0) return false;
  cx = o.x + sx / (6 * area);
  cy = o.y + sy / (6 * area);
  return true;
}

/// \brief A grid index from a double, refusing what a long cannot hold (the deck's limits stop
/// such specimens first; this keeps the conversion defined if a caller skips them).
long grid_index(double v) {
  if (!std::isfinite(v) || std::abs(v) > 1e12)
    throw std::invalid_argument("specimen: wall grid index " + std::to_string(v) +
                                " out of range (brick size too small for the specimen, or not finite)");
  return static_cast<long>(v);
}

}  // namespace

Specimen build_specimen(const deck::Geometry& g) {
  Specimen s;
  s.width = g.width;
  s.height = g.height;
  s.full_brick_area = g.brick_width * g.brick_height;
  const double w = g.brick_width, h = g.brick_height, W = g.width, H = g.height;
  const double eps = 1e-9 * std::max(W, H);
  const double al = g.angle_deg * std::numbers::pi / 180.0, ca = std::cos(al), sa = std::sin(al);
  const double xc = 0.5 * W, yc = 0.5 * H;
  // wall frame (u, v) -> specimen frame (x, y): rotate by the wall angle about the centre.
  auto to_specimen = [&](double u, double v) { return P{xc + ca * u - sa * v, yc + sa * u + ca * v}; };
  // bounding box of the specimen in the wall frame
  double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
  for (P c : {P{0, 0}, P{W, 0}, P{W, H}, P{0, H}}) {
    const double u = ca * (c.x - xc) + sa * (c.y - yc), v = -sa * (c.x - xc) + ca * (c.y - yc);
    umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  }
  // Rows are anchored at the specimen's bottom-left corner (u, v) = (-W/2, -H/2), so an
  // unrotated wall has no slivers at the bottom edge and the notch at mid-height falls on a bed
  // joint whenever H/2 is a multiple of the brick height.
  const double u0 = -0.5 * W, v0 = -0.5 * H;
  const long j0 = grid_index(std::floor((vmin - v0) / h)) - 1;
  const long j1 = grid_index(std::ceil((vmax - v0) / h)) + 1;
  const double min_area = g.min_piece_fraction * s.full_brick_area;
  const long ncols = grid_index(std::ceil((umax - umin) / w)) + 4;
  const double cells = static_cast<double>(j1 - j0) * static_cast<double>(ncols);
  if (cells > 1e10) throw std::invalid_argument("specimen: " + std::to_string(cells) + " wall-grid cells; too many");
  const std::size_t estimate = static_cast<std::size_t>(cells);
  s.cx.reserve(estimate), s.cy.reserve(estimate), s.area.reserve(estimate), s.drive.reserve(estimate);
  s.vx.reserve(5 * estimate), s.vy.reserve(5 * estimate), s.poly_offset.reserve(estimate + 1);

  auto emit = [&](Poly& p, std::int64_t parent) {
    double a, cx, cy;
    if (!finish(p, eps, a, cx, cy) || a < min_area) return;
    double ylo = 1e300, yhi = -1e300;
    for (auto& v : p) ylo = std::min(ylo, v.y), yhi = std::max(yhi, v.y);
    Drive d = Drive::free;
    const double band = (g.driven_rows - 1) * h + eps;
    if (yhi >= H - band) d = Drive::top;
    else if (ylo <= band) d = Drive::bottom;
    s.cx.push_back(cx), s.cy.push_back(cy), s.area.push_back(a), s.drive.push_back(d);
    s.parent.push_back(parent);
    for (auto& v : p) s.vx.push_back(v.x), s.vy.push_back(v.y);
    s.poly_offset.push_back(static_cast<int>(s.vx.size()));
  };

  for (long j = j0; j <= j1; ++j) {
    const double shift = (j * g.overlap - std::floor(j * g.overlap)) * w;
    const double vlo = v0 + j * h, vhi = vlo + h;
    const long i0 = grid_index(std::floor((umin - u0 - shift) / w)) - 1;
    const long i1 = grid_index(std::ceil((umax - u0 - shift) / w)) + 1;
    for (long i = i0; i <= i1; ++i) {
      const double ulo = u0 + shift + i * w, uhi = ulo + w;
      Poly p{to_specimen(ulo, vlo), to_specimen(uhi, vlo), to_specimen(uhi, vhi), to_specimen(ulo, vhi)};
      // quick reject: rectangle outside the specimen's bounding box
      double xl = 1e300, xh = -1e300, yl = 1e300, yh = -1e300;
      for (auto& v : p) xl = std::min(xl, v.x), xh = std::max(xh, v.x), yl = std::min(yl, v.y), yh = std::max(yh, v.y);
      if (xh <= 0 || xl >= W || yh <= 0 || yl >= H) continue;
      if (xl < 0) p = clip(p, -1, 0, 0);
      if (xh > W) p = clip(p, 1, 0, W);
      if (yl < 0) p = clip(p, 0, -1, 0);
      if (yh > H) p = clip(p, 0, 1, H);
      if (p.size() < 3) continue;
      const std::int64_t parent = j * (ncols + 8) * 4 + i;  // unique per grid brick
      // The notch (a slit along y = notch_y from x = 0 to notch_length) splits bricks it crosses;
      // bricks past the tip (centroid beyond it) stay whole, so the tip is rounded to a brick edge.
      double a, cx, cy;
      Poly tmp = p;
      bool straddles = false;
      if (g.notch_length > 0 && finish(tmp, eps, a, cx, cy) && cx < g.notch_length) {
        double lo = 1e300, hi = -1e300;
        for (auto& v : p) lo = std::min(lo, v.y), hi = std::max(hi, v.y);
        straddles = lo < g.notch_y - eps && hi > g.notch_y + eps;
      }
      if (straddles) {
        Poly below = clip(p, 0, 1, g.notch_y), above = clip(p, 0, -1, -g.notch_y);
        emit(below, parent);
        emit(above, parent);
      } else {
        emit(p, parent);
      }
    }
  }
  return s;
}

}  // namespace nacre::geometry
