// SPDX-License-Identifier: BSD-3-Clause
// Static 2-D decomposition with a one-brick halo (include/nacre/par/decomposition.hpp says why).
#include <nacre/par/comm.hpp>
#include <nacre/par/decomposition.hpp>

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace nacre::par {

namespace {
/// Cuts of `parts` blocks at the quantiles of v (outer edges -inf, +inf): block k holds
/// [cut[k], cut[k+1]). Values equal to a cut go to the upper block.
std::vector<double> quantile_cuts(std::vector<double> v, int parts) {
  std::vector<double> cut(parts + 1);
  cut.front() = -std::numeric_limits<double>::infinity();
  cut.back() = std::numeric_limits<double>::infinity();
  std::sort(v.begin(), v.end());
  for (int k = 1; k < parts; ++k) cut[k] = v.empty() ? 0.0 : v[v.size() * k / parts];
  return cut;
}
int block_of(const std::vector<double>& cut, double x) {
  return static_cast<int>(std::upper_bound(cut.begin() + 1, cut.end() - 1, x) - (cut.begin() + 1));
}
}  // namespace

Decomposition decompose(int rank, int size, const geometry::Specimen& s, const geometry::Interfaces& f,
                        const geometry::Adjacency& adj, const std::vector<int>& item) {
  if (size < 1 || rank < 0 || rank >= size)
    throw std::invalid_argument("nacre::par::decompose: rank " + std::to_string(rank) + " of " + std::to_string(size));
  const int n = static_cast<int>(s.size());
  if (!item.empty() && static_cast<int>(item.size()) != n)
    throw std::invalid_argument("nacre::par::decompose: one work item per brick expected");
  Decomposition d;
  d.rank = rank, d.size = size;
  process_grid(size, s.width, s.height, d.dims);
  d.coords[0] = rank / d.dims[1], d.coords[1] = rank % d.dims[1];
  // the point that places each brick: its work item's mean centroid
  std::vector<double> px(s.cx), py(s.cy);
  if (!item.empty()) {
    std::map<int, std::pair<double, double>> sum;
    std::map<int, int> count;
    for (int i = 0; i < n; ++i)
      if (item[i] >= 0) sum[item[i]].first += s.cx[i], sum[item[i]].second += s.cy[i], ++count[item[i]];
    for (int i = 0; i < n; ++i)
      if (item[i] >= 0) px[i] = sum[item[i]].first / count[item[i]], py[i] = sum[item[i]].second / count[item[i]];
  }
  d.xcut = quantile_cuts(px, d.dims[0]);
  d.ycut = quantile_cuts(py, d.dims[1]);
  d.owner.resize(n);
  for (int i = 0; i < n; ++i) d.owner[i] = block_of(d.xcut, px[i]) * d.dims[1] + block_of(d.ycut, py[i]);

  // owned, then the halo: bricks of other ranks sharing an interface with an owned one
  std::set<int> halo;
  for (int i = 0; i < n; ++i) {
    if (d.owner[i] != rank) continue;
    d.bricks.push_back(i);
    for (int j = adj.offset[i]; j < adj.offset[i + 1]; ++j)
      if (d.owner[adj.neighbour[j]] != rank) halo.insert(adj.neighbour[j]);
  }
  d.n_owned = static_cast<int>(d.bricks.size());
  d.bricks.insert(d.bricks.end(), halo.begin(), halo.end());
  d.local_of.assign(n, -1);
  for (std::size_t k = 0; k < d.bricks.size(); ++k) d.local_of[d.bricks[k]] = static_cast<int>(k);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const bool oa = d.owner[f.a[i]] == rank, ob = d.owner[f.b[i]] == rank;
    if (!oa && !ob) continue;
    d.interfaces.push_back(static_cast<int>(i));
    d.iface_owned.push_back(oa);
    d.owned_interfaces += oa;
  }

  // messages: what rank q needs from this one are this rank's bricks in q's halo, i.e. owned
  // bricks with a neighbour owned by q (the relation is symmetric, so both sides agree)
  std::map<int, std::set<int>> send, recv;
  for (int k = 0; k < d.n_owned; ++k) {
    const int i = d.bricks[k];
    for (int j = adj.offset[i]; j < adj.offset[i + 1]; ++j) {
      const int q = d.owner[adj.neighbour[j]];
      if (q != rank) send[q].insert(i), recv[q].insert(adj.neighbour[j]);
    }
  }
  for (const auto& [q, bricks] : send) {
    d.neighbours.push_back(q);
    std::vector<int> out, in;
    for (int i : bricks) out.push_back(d.local_of[i]);
    for (int i : recv[q]) in.push_back(d.local_of[i]);
    d.send.push_back(std::move(out));
    d.recv.push_back(std::move(in));
  }
  return d;
}

geometry::Specimen local_specimen(const Decomposition& d, const geometry::Specimen& s) {
  geometry::Specimen l;
  l.full_brick_area = s.full_brick_area, l.width = s.width, l.height = s.height;
  for (int i : d.bricks) {
    l.cx.push_back(s.cx[i]), l.cy.push_back(s.cy[i]), l.area.push_back(s.area[i]);
    for (int v = s.poly_offset[i]; v < s.poly_offset[i + 1]; ++v) l.vx.push_back(s.vx[v]), l.vy.push_back(s.vy[v]);
    l.poly_offset.push_back(static_cast<int>(l.vx.size()));
    l.drive.push_back(s.drive[i]);
    l.parent.push_back(s.parent[i]);
  }
  return l;
}

geometry::Interfaces local_interfaces(const Decomposition& d, const geometry::Interfaces& f) {
  geometry::Interfaces l;
  for (int i : d.interfaces) {
    l.a.push_back(d.local_of[f.a[i]]), l.b.push_back(d.local_of[f.b[i]]), l.kind.push_back(f.kind[i]);
    l.ra0x.push_back(f.ra0x[i]), l.ra0y.push_back(f.ra0y[i]), l.ra1x.push_back(f.ra1x[i]), l.ra1y.push_back(f.ra1y[i]);
    l.rb0x.push_back(f.rb0x[i]), l.rb0y.push_back(f.rb0y[i]), l.rb1x.push_back(f.rb1x[i]), l.rb1y.push_back(f.rb1y[i]);
    l.nx.push_back(f.nx[i]), l.ny.push_back(f.ny[i]), l.length.push_back(f.length[i]);
  }
  return l;
}

}  // namespace nacre::par
