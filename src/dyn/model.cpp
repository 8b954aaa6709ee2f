// SPDX-License-Identifier: BSD-3-Clause
// Builds the deformable model from the specimen: element types deduplicated by shape, elements,
// bed/head interfaces located on one polygon edge of each brick, UE's internal joints, the gather
// list, prescribed forces. Host assembly (Eigen), then one upload. See model.hpp for the layout.
#include <nacre/dyn/element.hpp>
#include <nacre/dyn/model.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <unordered_map>
#include <vector>
#include <stdexcept>
#include <string>

namespace nacre::dyn {

double whole_brick_height(const geometry::Specimen& s) {
  double h = 0;
  for (std::size_t b = 0; b < s.size(); ++b) {
    if (std::abs(s.area[b] - s.full_brick_area) > 1e-9 * s.full_brick_area) continue;
    for (int v = s.poly_offset[b]; v < s.poly_offset[b + 1]; ++v) {
      const int w = v + 1 == s.poly_offset[b + 1] ? s.poly_offset[b] : v + 1;
      const double l = std::hypot(s.vx[w] - s.vx[v], s.vy[w] - s.vy[v]);
      if (l > 1e-12 && (h == 0 || l < h)) h = l;
    }
  }
  return h > 0 ? h : std::sqrt(s.full_brick_area);
}

namespace {

// Deduplication keys (element shapes, interface shapes) as fixed arrays in hash maps: ids are
// handed out in order of first appearance, as with the ordered maps these replace, but a lookup
// is one probe instead of a walk down a tree of ~N nodes that miss cache (the interface-shape
// map was 55 % of build_model at 300k bricks) and no key allocates.
template <std::size_t N>
struct KeyHash {
  std::size_t operator()(const std::array<std::uint64_t, N>& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (std::uint64_t w : k) {  // splitmix64-style mixing of each word into the state
      h ^= w + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      h ^= h >> 31, h *= 0xbf58476d1ce4e5b9ull, h ^= h >> 27;
    }
    return static_cast<std::size_t>(h);
  }
};
template <std::size_t N, class Value = int>
using KeyMap = std::unordered_map<std::array<std::uint64_t, N>, Value, KeyHash<N>>;

template <class V>
V alloc(const std::string& label, std::size_t n0, std::size_t n1 = KOKKOS_IMPL_CTOR_DEFAULT_ARG,
        std::size_t n2 = KOKKOS_IMPL_CTOR_DEFAULT_ARG) {
  return V(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::" + label), n0, n1, n2);
}

// A side of an interface located on an element edge.
struct Side {
  int elem = -1;
  int n0 = 0, n1 = 0;
  double xi0 = 0, xi1 = 0;
};

}  // namespace

namespace {
/// (M + h/2 C)^-1 = ((1 + h alpha/2) M + h beta/2 K)^-1 per type into the host table A (zeros
/// beyond a type's dofs) from host K, lumped M and node counts, at m.h, m.alpha, m.beta; and
/// whether every one is diagonal (beta = 0). build_model and set_model_step share it.
template <class Mem, class KH, class MH, class NH, class AH>
void step_tables(Model<Mem>& m, const KH& K, const MH& M, const NH& N, const AH& A) {
  const double h = m.h;
  Kokkos::deep_copy(A, 0.0);
  for (int t = 0; t < m.n_types; ++t) {
    const int d = 2 * N(t);
    Eigen::MatrixXd Amat(d, d);
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j)
        Amat(i, j) = (i == j ? (1.0 + 0.5 * h * m.alpha) * M(t, i) : 0.0) + (0.5 * h * m.beta) * K(t, i, j);
    const Eigen::MatrixXd Ai = Amat.ldlt().solve(Eigen::MatrixXd::Identity(d, d));
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) A(t, i, j) = Ai(i, j);
  }
  m.ainv_diagonal = true;
  for (int t = 0; t < m.n_types; ++t)
    for (int i = 0; i < m.nd; ++i)
      for (int j = 0; j < m.nd; ++j)
        if (i != j && A(t, i, j) != 0.0) m.ainv_diagonal = false;
}
}  // namespace

namespace {

// An interface between two element edges (build_model's interface stage).
struct Rec {
  Side a, b;
  double nx, ny, len;
  std::uint8_t kind;
};

/// What build_model's stages share: the inputs, the model and host map being filled, and the
/// host tables one stage leaves for the next. Each stage is a function of its own (a stage
/// reads only the members named at its top).
template <class Mem>
struct Build {
  const Params& p;
  const geometry::Specimen& s;
  const geometry::Interfaces& f;
  const deck::Mortar& mortar;
  HostMap& map;
  Model<Mem>& m;
  bool ue;
  Material mat;
  int nb;
  std::vector<ElementMatrices> types;               ///< element types (shared matrices)
  std::vector<std::vector<double>> poly_x, poly_y;  ///< brick polygons about their centroids
  int ne = 0, nt = 0, nd = 0;                       ///< elements, types, dofs per element
  std::vector<double> lam_t;                        ///< largest eigenvalue of M_e^-1 K_e per type
  std::vector<Rec> rec;                             ///< interfaces, in the model's order
  std::vector<int> goff;                            ///< gather-list offsets per element
  const par::Decomposition* part = nullptr;         ///< a rank's part (MPI), null: the whole specimen
  std::vector<int> elem_of;                         ///< model element -> whole-model element (restrict_to_part)
};

/// Elements and their types: one bolted element per brick (BE, BIE) or a fan of triangles (UE),
/// equal shapes sharing one type.
template <class Mem>
void add_elements(Build<Mem>& B) {
  const Params& p = B.p;
  const geometry::Specimen& s = B.s;
  HostMap& map = B.map;
  Model<Mem>& m = B.m;
  const bool ue = B.ue;
  const Material& mat = B.mat;
  const int nb = B.nb;
  // Equal shapes: the same node count and every node within tol of the type's first element.
  // Found through a key of the coordinates rounded to a coarse grid (1000 tol): rounded to tol
  // itself, the rounding noise of node positions taken relative to centroids far from the
  // origin fell on cell boundaries and split equal shapes (a 98,325-brick wall: 36 types, 13
  // with the coarse key; a 980,535-brick one: 3,039, 669). The coarse cell lists its types; a
  // shape near one of its edges may still start a type of its own. With the shoelace taken
  // relative to each brick's first vertex (geometry/specimen.cpp) the centroids carry ~1e-14 mm,
  // not ~4e-11 mm (about tol): both walls have 2 types, a whole brick and a half brick at the
  // row ends.
  const double tol = 1e-9 * std::sqrt(std::max(s.full_brick_area, 1e-300)), cell = 1000.0 * tol;
  KeyMap<1 + 2 * kMaxNodes, std::vector<int>> type_of_shape;  // coarse cell -> its types
  type_of_shape.reserve(64);
  auto& types = B.types;
  map = HostMap{};
  map.brick_elem.assign(1, 0);
  map.cx = s.cx, map.cy = s.cy;
  auto& poly_x = B.poly_x;
  auto& poly_y = B.poly_y;
  poly_x.assign(nb, {}), poly_y.assign(nb, {});
  auto add_element = [&](int brick, const ElementMatrices& e) {
    int t;
    if (p.share_element_matrices) {
      std::array<std::uint64_t, 1 + 2 * kMaxNodes> key{};
      key[0] = static_cast<std::uint64_t>(e.nodes);
      for (int k = 0; k < e.nodes; ++k)
        key[1 + 2 * k] = static_cast<std::uint64_t>(std::llround(e.x[k] / cell)),
                    key[2 + 2 * k] = static_cast<std::uint64_t>(std::llround(e.y[k] / cell));
      auto& listed = type_of_shape[key];
      const auto same = std::find_if(listed.begin(), listed.end(), [&](int c) {
        const ElementMatrices& r = types[c];
        for (int k = 0; k < e.nodes; ++k)
          if (std::abs(r.x[k] - e.x[k]) > tol || std::abs(r.y[k] - e.y[k]) > tol) return false;
        return true;
      });
      if (same != listed.end()) {
        t = *same;
      } else {
        t = static_cast<int>(types.size());
        listed.push_back(t);
        types.push_back(e);
      }
    } else {
      t = static_cast<int>(types.size());
      types.push_back(e);
    }
    map.elem_brick.push_back(brick);
    map.elem_type.push_back(t);
  };
  for (int b = 0; b < nb; ++b) {
    const int n = s.vertex_count(b);
    if (n + 1 > kMaxNodes)
      throw std::runtime_error("dyn: brick " + std::to_string(b) + " has " + std::to_string(n) +
                               " vertices; at most " + std::to_string(kMaxNodes - 1) + " supported");
    for (int v = s.poly_offset[b]; v < s.poly_offset[b + 1]; ++v)
      poly_x[b].push_back(s.vx[v] - s.cx[b]), poly_y[b].push_back(s.vy[v] - s.cy[b]);
    if (ue) {
      for (const auto& e : unbolted_brick(poly_x[b], poly_y[b], mat)) add_element(b, e);
    } else {
      add_element(b, bolted_brick(poly_x[b], poly_y[b], mat));
    }
    map.brick_elem.push_back(static_cast<int>(map.elem_brick.size()));
    for (int i = 0; i < n; ++i) {
      map.tri_brick.push_back(b);
      if (ue) {
        map.tri_elem.push_back(map.brick_elem[b] + i);
        map.tri_local.push_back({0, 1, 2});
      } else {
        map.tri_elem.push_back(map.brick_elem[b]);
        map.tri_local.push_back(fan_triangle(n, i));
      }
    }
  }
  const int ne = static_cast<int>(map.elem_brick.size()), nt = static_cast<int>(types.size());
  int max_nodes = 0;
  for (const auto& e : types) max_nodes = std::max(max_nodes, e.nodes);
  const int nd = 2 * max_nodes;
  m.n_elem = ne, m.nd = nd, m.n_types = nt;
  B.ne = ne, B.nt = nt, B.nd = nd;
}

/// Slivers (docs/dynamics.md "Slivers"): selective mass scaling of the element types whose
/// largest eigenvalue of M_e^-1 K_e exceeds the median free element's by more than
/// 1 / sliver_step_ratio^2 (a clipped sliver, or a whole brick with a near-degenerate fan
/// triangle where the clip cut a corner by a hair). The nodes that carry the offending mode get
/// heavier until the element's step bound is sliver_step_ratio times the median element's:
/// one element no longer sets the step of the whole specimen, at a mass cost that is reported.
/// lam_t: the largest eigenvalue of M_e^-1 K_e per type (lumped M), after the scaling: the
/// element's part of the step bound (Model::klam)
template <class Mem>
void scale_slivers(Build<Mem>& B) {
  const Params& p = B.p;
  const geometry::Specimen& s = B.s;
  const HostMap& map = B.map;
  Model<Mem>& m = B.m;
  auto& types = B.types;
  auto& lam_t = B.lam_t;
  lam_t.assign(types.size(), 0.0);
  {
    auto lam_of = [](const ElementMatrices& e, Eigen::VectorXd* mode) {
      const Eigen::VectorXd r = e.mass.cwiseSqrt().cwiseInverse();
      const Eigen::MatrixXd S = r.asDiagonal() * e.K * r.asDiagonal();
      if (!mode) return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
      const int top = static_cast<int>(S.rows()) - 1;
      *mode = r.asDiagonal() * es.eigenvectors().col(top);
      return es.eigenvalues()(top);
    };
    for (std::size_t t = 0; t < types.size(); ++t) lam_t[t] = lam_of(types[t], nullptr);
    const double lam_max_before = lam_t.empty() ? 0.0 : *std::max_element(lam_t.begin(), lam_t.end());
    std::vector<double> lam_free;
    for (std::size_t e = 0; e < map.elem_brick.size(); ++e)
      if (s.drive[map.elem_brick[e]] == geometry::Drive::free) lam_free.push_back(lam_t[map.elem_type[e]]);
    double mass_before = 0, mass_after = 0;
    std::vector<char> scaled(types.size(), 0);
    std::vector<double> type_mass0(types.size());
    for (std::size_t t = 0; t < types.size(); ++t) type_mass0[t] = types[t].mass.sum();
    // no element gains more than a quarter of a whole brick's mass (a near-degenerate vertex on
    // a large piece would otherwise take tens of bricks' mass; that element then keeps a smaller step)
    const double cap = 0.25 * p.density * p.thickness * s.full_brick_area;
    if (p.sliver_step_ratio > 0 && !lam_free.empty()) {
      std::nth_element(lam_free.begin(), lam_free.begin() + lam_free.size() / 2, lam_free.end());
      const double target = lam_free[lam_free.size() / 2] / (p.sliver_step_ratio * p.sliver_step_ratio);
      for (std::size_t t = 0; t < types.size(); ++t) {
        auto& e = types[t];
        if (!(lam_t[t] > target * (1 + 1e-9))) continue;
        Eigen::VectorXd x;
        double lam = lam_of(e, &x);
        // at most a quarter brick added (the rest is dt's), at most 64 rounds
        for (int it = 0; it < 64 && lam > target * (1 + 1e-9) && e.mass.sum() - type_mass0[t] < cap; ++it) {
          const Eigen::VectorXd before = e.mass;
          // kinetic share of the mode per node; the nodes holding >= 10 % of the largest share
          std::vector<double> share(e.nodes);
          double top = 0;
          for (int j = 0; j < e.nodes; ++j)
            top = std::max(top, share[j] = e.mass(2 * j) * x(2 * j) * x(2 * j) + e.mass(2 * j + 1) * x(2 * j + 1) * x(2 * j + 1));
          // the light ones first (a sliver's mode lives on its light corner nodes): a node that
          // carries the mode and is lighter than the element's mean node gets heavier, others only
          // when no light one carries it
          const double grow = std::min(4.0, lam / target), mean = e.mass.sum() / (2.0 * e.nodes);
          bool any = false;
          for (int j = 0; j < e.nodes; ++j)
            if (share[j] >= 0.1 * top && e.mass(2 * j) < mean) e.mass(2 * j) *= grow, e.mass(2 * j + 1) *= grow, any = true;
          if (!any)
            for (int j = 0; j < e.nodes; ++j)
              if (share[j] >= 0.1 * top) e.mass(2 * j) *= grow, e.mass(2 * j + 1) *= grow;
          if (e.mass.sum() - type_mass0[t] > cap)  // this step overshoots the cap: scale it back
            e.mass = before + (e.mass - before) * ((cap - (before.sum() - type_mass0[t])) / (e.mass.sum() - before.sum()));
          scaled[t] = 1;
          lam = lam_of(e, &x);
        }
        if (scaled[t]) lam_t[t] = lam_of(e, nullptr);
      }
    }
    for (std::size_t e = 0; e < map.elem_brick.size(); ++e) {
      const int t = map.elem_type[e];
      const double me = types[t].mass.sum();
      mass_after += me;
      mass_before += type_mass0[t];
      if (scaled[t]) ++m.sliver_elements;
    }
    m.sliver_mass_added = mass_before > 0 ? (mass_after - mass_before) / mass_before : 0.0;
    // the elements' part of the step bound goes like 1 / sqrt(largest eigenvalue)
    const double lam_max_after = lam_t.empty() ? 0.0 : *std::max_element(lam_t.begin(), lam_t.end());
    m.sliver_step_gain = lam_max_after > 0 ? std::sqrt(lam_max_before / lam_max_after) : 1.0;
  }
}

/// Type tables on the device: K, (M + h/2 C)^-1, mass, Theta, node positions, the element step bound.
template <class Mem>
void upload_types(Build<Mem>& B) {
  const Params& p = B.p;
  HostMap& map = B.map;
  Model<Mem>& m = B.m;
  const auto& types = B.types;
  const auto& lam_t = B.lam_t;
  const int nt = B.nt, nd = B.nd;
  m.K = alloc<typename Model<Mem>::TypeMat>("K", nt, nd, nd);
  m.Ainv = alloc<typename Model<Mem>::TypeMat>("Ainv", nt, nd, nd);
  m.mass = alloc<typename Model<Mem>::Dof>("mass", nt, nd);
  m.klam = alloc<Kokkos::View<double*, Mem>>("klam", nt);
  m.theta = alloc<typename Model<Mem>::Dof>("theta", nt, nd);
  m.node_x = alloc<typename Model<Mem>::Dof>("node_x", nt, kMaxNodes);
  m.node_y = alloc<typename Model<Mem>::Dof>("node_y", nt, kMaxNodes);
  m.type_nodes = alloc<Kokkos::View<int*, Mem>>("type_nodes", nt);
  {
    auto K = Kokkos::create_mirror_view(m.K);
    auto A = Kokkos::create_mirror_view(m.Ainv);
    auto M = Kokkos::create_mirror_view(m.mass);
    auto KL = Kokkos::create_mirror_view(m.klam);
    auto T = Kokkos::create_mirror_view(m.theta);
    auto X = Kokkos::create_mirror_view(m.node_x);
    auto Y = Kokkos::create_mirror_view(m.node_y);
    auto N = Kokkos::create_mirror_view(m.type_nodes);
    Kokkos::deep_copy(K, 0.0), Kokkos::deep_copy(A, 0.0), Kokkos::deep_copy(M, 0.0);
    Kokkos::deep_copy(T, 0.0), Kokkos::deep_copy(X, 0.0), Kokkos::deep_copy(Y, 0.0);
    map.type_nodes.resize(nt);
    map.type_x.assign(static_cast<std::size_t>(nt) * kMaxNodes, 0.0);
    map.type_y.assign(static_cast<std::size_t>(nt) * kMaxNodes, 0.0);
    for (int t = 0; t < nt; ++t) {
      const auto& e = types[t];
      const int d = 2 * e.nodes;
      for (int i = 0; i < d; ++i) {
        M(t, i) = e.mass(i);
        T(t, i) = p.thermal_strain * e.theta_unit(i);
        for (int j = 0; j < d; ++j) K(t, i, j) = e.K(i, j);
      }
      KL(t) = lam_t[t];
      N(t) = e.nodes;
      map.type_nodes[t] = e.nodes;
      for (int k = 0; k < e.nodes; ++k) {
        X(t, k) = e.x[k], Y(t, k) = e.y[k];
        map.type_x[t * kMaxNodes + k] = e.x[k], map.type_y[t * kMaxNodes + k] = e.y[k];
      }
    }
    step_tables(m, K, M, N, A);
    Kokkos::deep_copy(m.K, K), Kokkos::deep_copy(m.Ainv, A), Kokkos::deep_copy(m.mass, M), Kokkos::deep_copy(m.klam, KL);
    Kokkos::deep_copy(m.theta, T), Kokkos::deep_copy(m.node_x, X), Kokkos::deep_copy(m.node_y, Y);
    Kokkos::deep_copy(m.type_nodes, N);
  }
}

/// Per element: type, drive, the driven elements' centroids, and the tiles of the tiled apply.
template <class Mem>
void upload_elements(Build<Mem>& B) {
  const geometry::Specimen& s = B.s;
  const HostMap& map = B.map;
  Model<Mem>& m = B.m;
  const int ne = B.ne;
  m.type = alloc<Kokkos::View<int*, Mem>>("type", ne);
  m.drive = alloc<Kokkos::View<std::int8_t*, Mem>>("drive", ne);
  m.driven_index = alloc<Kokkos::View<int*, Mem>>("driven_index", ne);
  {
    auto T = Kokkos::create_mirror_view(m.type);
    auto D = Kokkos::create_mirror_view(m.drive);
    auto DI = Kokkos::create_mirror_view(m.driven_index);
    std::vector<double> X, Y;
    for (int e = 0; e < ne; ++e) {
      const int b = map.elem_brick[B.elem_of[e]];
      T(e) = map.elem_type[B.elem_of[e]];
      auto dv = static_cast<std::int8_t>(s.drive[b]);
      if (dv > 0 && !m.top_prescribed) dv = 0;
      D(e) = dv;
      DI(e) = dv != 0 ? static_cast<int>(X.size()) : -1;
      if (dv != 0) X.push_back(s.cx[b]), Y.push_back(s.cy[b]);
    }
    m.cx = alloc<Field<double, Mem>>("cx", std::max<std::size_t>(X.size(), 1));
    m.cy = alloc<Field<double, Mem>>("cy", std::max<std::size_t>(Y.size(), 1));
    auto HX = Kokkos::create_mirror_view(m.cx);
    auto HY = Kokkos::create_mirror_view(m.cy);
    for (std::size_t k = 0; k < X.size(); ++k) HX(k) = X[k], HY(k) = Y[k];
    Kokkos::deep_copy(m.type, T), Kokkos::deep_copy(m.cx, HX), Kokkos::deep_copy(m.cy, HY), Kokkos::deep_copy(m.drive, D);
    Kokkos::deep_copy(m.driven_index, DI);
    // tiles of the tiled element apply: within each window of kTileWindow consecutive elements,
    // the free elements of each type in increasing order, cut into groups of at most kTile. The
    // window keeps the tiles local (a pass touches each cache line of the state once: UE's 4
    // triangles of a brick are 4 types, so its tiles take every 4th element of a window), the
    // grouping by type lets a tile share one matrix. Driven elements are listed apart.
    // Per window, the free elements sorted by (type, element): O(ne log kTileWindow), not a
    // pass over every type per window (that was O(ne * nt / kTileWindow): quadratic with
    // share_element_matrices = false, where nt = ne; 11+ minutes at 1M bricks).
    std::vector<int> te, ts, dr;
    std::vector<std::pair<int, int>> win;  // (type, element) of the window's free elements
    win.reserve(kTileWindow);
    for (int w0 = 0; w0 < ne; w0 += kTileWindow) {
      win.clear();
      for (int e = w0; e < std::min(ne, w0 + kTileWindow); ++e) {
        if (D(e) != 0) dr.push_back(e);
        else win.emplace_back(T(e), e);
      }
      std::sort(win.begin(), win.end());
      for (std::size_t k = 0, run = 0; k < win.size(); ++k, ++run) {
        if (k > 0 && win[k].first != win[k - 1].first) run = 0;  // a new type starts a new tile
        if (run % kTile == 0) ts.push_back(static_cast<int>(te.size()));
        te.push_back(win[k].second);
      }
    }
    ts.push_back(static_cast<int>(te.size()));
    m.n_tiles = static_cast<int>(ts.size()) - 1, m.n_driven = static_cast<int>(dr.size());
    m.tile_start = alloc<Kokkos::View<int*, Mem>>("tile_start", ts.size());
    m.tile_elem = alloc<Kokkos::View<int*, Mem>>("tile_elem", std::max<std::size_t>(te.size(), 1));
    m.driven = alloc<Kokkos::View<int*, Mem>>("driven", std::max<std::size_t>(dr.size(), 1));
    auto TS = Kokkos::create_mirror_view(m.tile_start);
    auto TE = Kokkos::create_mirror_view(m.tile_elem);
    auto DR = Kokkos::create_mirror_view(m.driven);
    for (std::size_t k = 0; k < ts.size(); ++k) TS(k) = ts[k];
    for (std::size_t k = 0; k < te.size(); ++k) TE(k) = te[k];
    for (std::size_t k = 0; k < dr.size(); ++k) DR(k) = dr[k];
    Kokkos::deep_copy(m.tile_start, TS), Kokkos::deep_copy(m.tile_elem, TE), Kokkos::deep_copy(m.driven, DR);
  }
}

/// Interfaces: each geometry segment located on one polygon edge of each brick (and UE's
/// internal joints), in element order; the damage history where the deck asks for it.
template <class Mem>
void locate_interfaces(Build<Mem>& B) {
  const Params& p = B.p;
  const geometry::Specimen& s = B.s;
  const geometry::Interfaces& f = B.f;
  HostMap& map = B.map;
  Model<Mem>& m = B.m;
  const bool ue = B.ue;
  const int nb = B.nb;
  const auto& poly_x = B.poly_x;
  const auto& poly_y = B.poly_y;
  auto locate = [&](int b, double x0, double y0, double x1, double y1, int iface) {
    const auto& px = poly_x[b];
    const auto& py = poly_y[b];
    const int n = static_cast<int>(px.size());
    int best = -1;
    double best_err = 1e300, bxi0 = 0, bxi1 = 0;
    for (int k = 0; k < n; ++k) {
      const int k1 = (k + 1) % n;
      const double ex = px[k1] - px[k], ey = py[k1] - py[k], l2 = ex * ex + ey * ey;
      if (l2 <= 0) continue;
      const double l = std::sqrt(l2);
      const double xi0 = ((x0 - px[k]) * ex + (y0 - py[k]) * ey) / l2;
      const double xi1 = ((x1 - px[k]) * ex + (y1 - py[k]) * ey) / l2;
      const double d0 = std::abs((x0 - px[k]) * ey - (y0 - py[k]) * ex) / l;
      const double d1 = std::abs((x1 - px[k]) * ey - (y1 - py[k]) * ex) / l;
      const double out = std::max({0.0, -xi0, -xi1, xi0 - 1, xi1 - 1}) * l;
      const double err = d0 + d1 + out;
      if (err < best_err) best_err = err, best = k, bxi0 = xi0, bxi1 = xi1;
    }
    if (best < 0 || best_err > 1e-6 * std::sqrt(s.full_brick_area))
      throw std::runtime_error("dyn: interface " + std::to_string(iface) + " does not lie on an edge of brick " +
                               std::to_string(b));
    Side sd;
    sd.xi0 = std::clamp(bxi0, 0.0, 1.0), sd.xi1 = std::clamp(bxi1, 0.0, 1.0);
    if (ue) {
      sd.elem = map.brick_elem[b] + best, sd.n0 = 1, sd.n1 = 2;
    } else {
      sd.elem = map.brick_elem[b], sd.n0 = 1 + best, sd.n1 = 1 + (best + 1) % n;
    }
    return sd;
  };
  auto& rec = B.rec;
  rec.reserve(f.size() + (ue ? s.vx.size() : 0));
  for (std::size_t i = 0; i < f.size(); ++i) {
    Rec r;
    r.a = locate(f.a[i], f.ra0x[i], f.ra0y[i], f.ra1x[i], f.ra1y[i], static_cast<int>(i));
    r.b = locate(f.b[i], f.rb0x[i], f.rb0y[i], f.rb1x[i], f.rb1y[i], static_cast<int>(i));
    r.nx = f.nx[i], r.ny = f.ny[i], r.len = f.length[i];
    r.kind = static_cast<std::uint8_t>(f.kind[i]);
    rec.push_back(r);
  }
  m.n_mortar = static_cast<int>(rec.size());
  if (B.mortar.damage == cohesive::Damage::irreversible && m.quad.n < 2)
    throw std::invalid_argument("dyn: damage = \"irreversible\" needs quadrature_points >= 2");
  // Interfaces in element order (by their lower element, the geometry's cell order among ties):
  // the geometry lists them cell by cell (a cell spans ~3.6 brick rows), so the gather of an
  // element's force rows jumped between rows; in element order the rows an element gathers, and
  // the elements an interface loads, are close in memory (BE step -20 % at 50k-100k bricks,
  // docs/dynamics.md). Results equal to rounding (the gather's summation order changes), still
  // the same bits on any thread count; outputs are mapped back to the geometry's order.
  {
    std::vector<int> order(rec.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    auto low = [&](int i) { return std::min(rec[i].a.elem, rec[i].b.elem); };
    if (p.iface_element_order)
      std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return low(x) < low(y); });
    std::vector<Rec> sorted;
    sorted.reserve(rec.size());
    for (int i : order) sorted.push_back(rec[i]);
    rec = std::move(sorted);
    map.iface_geom = std::move(order);
  }
  if (ue) {
    // spoke j (centre -> corner j) is shared by triangle j-1 (its nodes 0, 2) and triangle j
    // (nodes 0, 1); triangle j-1 lies clockwise of the spoke, so the normal from a into b is the
    // spoke direction turned counter-clockwise.
    for (int b = 0; b < nb; ++b) {
      const int n = static_cast<int>(poly_x[b].size());
      for (int j = 0; j < n; ++j) {
        Rec r;
        const double l = std::hypot(poly_x[b][j], poly_y[b][j]);
        r.a = Side{map.brick_elem[b] + (j + n - 1) % n, 0, 2, 0.0, 1.0};
        r.b = Side{map.brick_elem[b] + j, 0, 1, 0.0, 1.0};
        r.nx = -poly_y[b][j] / l, r.ny = poly_x[b][j] / l, r.len = l;
        r.kind = static_cast<std::uint8_t>(geometry::JointKind::internal);
        rec.push_back(r);
      }
    }
  }
}

/// Interface tables on the device: elements, shapes shared by bitwise-equal geometry; the
/// gather counts per element.
template <class Mem>
void upload_interfaces(Build<Mem>& B) {
  Model<Mem>& m = B.m;
  const auto& rec = B.rec;
  const int ne = B.ne;
  const int ni = static_cast<int>(rec.size());
  if (ni >= kMaxGatherIface)
    throw std::runtime_error("dyn: " + std::to_string(ni) + " interfaces; the gather list encodes at most " +
                             std::to_string(kMaxGatherIface - 1));
  m.n_iface = ni;
  m.ielem = alloc<decltype(m.ielem)>("ielem", ni);
  m.ishape = alloc<Kokkos::View<int*, Mem>>("ishape", ni);
  auto& goff = B.goff;
  goff.assign(ne + 1, 0);
  {
    auto E = Kokkos::create_mirror_view(m.ielem);
    auto SH = Kokkos::create_mirror_view(m.ishape);
    // shapes: bitwise-equal geometry shares one (exact: no result changes)
    KeyMap<9> shape_of;
    shape_of.reserve(static_cast<std::size_t>(ni));
    std::vector<const Rec*> shape_rec;
    auto bits = [](double x) {
      std::uint64_t b;
      std::memcpy(&b, &x, sizeof b);
      return b;
    };
    for (int i = 0; i < ni; ++i) {
      const auto& r = rec[i];
      E(i, 0) = r.a.elem, E(i, 1) = r.b.elem;
      const std::array<std::uint64_t, 9> key{
          bits(r.a.xi0), bits(r.a.xi1), bits(r.b.xi0), bits(r.b.xi1), bits(r.nx), bits(r.ny), bits(r.len), r.kind,
          static_cast<std::uint64_t>(r.a.n0 | (r.a.n1 << 8) | (r.b.n0 << 16) | (r.b.n1 << 24))};
      auto [it, fresh] = shape_of.try_emplace(key, static_cast<int>(shape_rec.size()));
      if (fresh) shape_rec.push_back(&r);
      SH(i) = it->second;
      ++goff[r.a.elem + 1], ++goff[r.b.elem + 1];
    }
    const int ns = static_cast<int>(shape_rec.size());
    m.n_shapes = ns;
    m.ixi = alloc<decltype(m.ixi)>("ixi", std::max(ns, 1));
    m.inx = alloc<Field<double, Mem>>("inx", std::max(ns, 1));
    m.iny = alloc<Field<double, Mem>>("iny", std::max(ns, 1));
    m.ilen = alloc<Field<double, Mem>>("ilen", std::max(ns, 1));
    m.ikind = alloc<decltype(m.ikind)>("ikind", std::max(ns, 1));
    auto XI = Kokkos::create_mirror_view(m.ixi);
    auto NX = Kokkos::create_mirror_view(m.inx);
    auto NY = Kokkos::create_mirror_view(m.iny);
    auto L = Kokkos::create_mirror_view(m.ilen);
    auto KK = Kokkos::create_mirror_view(m.ikind);
    m.inode = alloc<decltype(m.inode)>("inode", std::max(ns, 1));
    auto Nn = Kokkos::create_mirror_view(m.inode);
    for (int k = 0; k < ns; ++k) {
      const auto& r = *shape_rec[k];
      Nn(k, 0) = static_cast<std::int8_t>(r.a.n0), Nn(k, 1) = static_cast<std::int8_t>(r.a.n1);
      Nn(k, 2) = static_cast<std::int8_t>(r.b.n0), Nn(k, 3) = static_cast<std::int8_t>(r.b.n1);
      XI(k, 0) = r.a.xi0, XI(k, 1) = r.a.xi1, XI(k, 2) = r.b.xi0, XI(k, 3) = r.b.xi1;
      NX(k) = r.nx, NY(k) = r.ny, L(k) = r.len, KK(k) = r.kind;
    }
    Kokkos::deep_copy(m.ielem, E), Kokkos::deep_copy(m.inode, Nn), Kokkos::deep_copy(m.ishape, SH);
    Kokkos::deep_copy(m.ixi, XI), Kokkos::deep_copy(m.inx, NX), Kokkos::deep_copy(m.iny, NY), Kokkos::deep_copy(m.ilen, L);
    Kokkos::deep_copy(m.ikind, KK);
  }
}

/// Step estimate, as the run's monitor computes it (monitor.hpp StepBound) for the elastic state:
/// per free element, the largest eigenvalue of M_e^-1 K_e plus the Gershgorin row sum of the
/// elastic interface stiffness k L t int N N^T ds (same in x and y) over the node's mass; the
/// largest over the elements gives 2 / sqrt(it), a start for critical_step's bisection.
template <class Mem>
void estimate_step(Build<Mem>& B) {
  const Params& p = B.p;
  const geometry::Specimen& s = B.s;
  const HostMap& map = B.map;
  Model<Mem>& m = B.m;
  const auto& types = B.types;
  const auto& lam_t = B.lam_t;
  const auto& rec = B.rec;
  const int ne = B.ne, nd = B.nd;
  {
    std::vector<double> row(static_cast<std::size_t>(ne) * nd, 0.0);
    const auto q = cohesive::gauss_legendre(2);  // N N^T is quadratic in s: exact
    for (const auto& r : rec) {
      const double klt = m.laws[r.kind].k * r.len * p.thickness;
      int el[4] = {r.a.elem, r.a.elem, r.b.elem, r.b.elem}, nn[4] = {r.a.n0, r.a.n1, r.b.n0, r.b.n1};
      double c[4][4] = {};
      for (int g = 0; g < q.n; ++g) {
        const double xa = r.a.xi0 + q.s[g] * (r.a.xi1 - r.a.xi0), xb = r.b.xi0 + q.s[g] * (r.b.xi1 - r.b.xi0);
        const double N[4] = {-(1 - xa), -xa, 1 - xb, xb};
        for (int i = 0; i < 4; ++i)
          for (int j = 0; j < 4; ++j) c[i][j] += q.w[g] * klt * N[i] * N[j];
      }
      for (int i = 0; i < 4; ++i) {
        double sum = 0;
        for (int j = 0; j < 4; ++j) sum += std::abs(c[i][j]);
        row[el[i] * nd + 2 * nn[i]] += sum, row[el[i] * nd + 2 * nn[i] + 1] += sum;
      }
    }
    auto is_free = [&](int e) {
      const auto dr = s.drive[map.elem_brick[e]];
      return dr == geometry::Drive::free || (dr == geometry::Drive::top && !m.top_prescribed);
    };
    double omega2 = 0;
    for (int e = 0; e < ne; ++e) {
      if (!is_free(e)) continue;
      const int t = map.elem_type[e];
      const auto& T = types[t];
      double w2 = 0;
      for (int i = 0; i < 2 * T.nodes; ++i) w2 = std::max(w2, row[e * nd + i] / T.mass(i));
      omega2 = std::max(omega2, lam_t[t] + w2);
    }
    m.step_estimate = omega2 > 0 ? 2.0 / std::sqrt(omega2) : p.dt;
  }
}

/// A rank's part (B.part) of the whole model assembled so far: the elements of its owned and halo
/// bricks (increasing whole-model index) and the interfaces with an owned element (the whole
/// model's order, bed/head first), renumbered; the maps back in HostMap; then the damage history
/// for the model's bed/head interfaces. One process: every row, the identity maps.
template <class Mem>
void restrict_to_part(Build<Mem>& B) {
  const geometry::Specimen& s = B.s;
  HostMap& map = B.map;
  Model<Mem>& m = B.m;
  const par::Decomposition* part = B.part;
  const int ng = B.ne, nig = static_cast<int>(B.rec.size()), nmg = m.n_mortar;
  map.n_elem = ng, map.n_iface = nig, map.n_mortar = nmg;
  std::vector<int> driven_row(ng, -1);  // whole-model element -> its driven row (upload_elements' rule)
  int nd_g = 0;
  for (int e = 0; e < ng; ++e) {
    auto dv = static_cast<int>(s.drive[map.elem_brick[e]]);
    if (dv > 0 && !m.top_prescribed) dv = 0;
    if (dv != 0) driven_row[e] = nd_g++;
  }
  map.n_driven = nd_g;
  auto held = [&](int e) { return !part || part->local_of[map.elem_brick[e]] >= 0; };
  auto owns = [&](int e) { return !part || part->owner[map.elem_brick[e]] == part->rank; };
  std::vector<int> local(part ? ng : 0, -1);
  B.elem_of.clear(), map.elem_owned.clear(), map.driven_global.clear(), map.driven_owned.clear();
  for (int e = 0; e < ng; ++e) {
    if (!held(e)) continue;
    if (part) local[e] = static_cast<int>(B.elem_of.size());
    B.elem_of.push_back(e);
    map.elem_owned.push_back(owns(e) ? 1 : 0);
    if (driven_row[e] >= 0) map.driven_global.push_back(driven_row[e]), map.driven_owned.push_back(owns(e) ? 1 : 0);
  }
  map.elem_global = B.elem_of;
  map.iface_global.clear(), map.iface_owned.clear();
  if (part) {
    std::vector<Rec> kept;
    int nm = 0;
    for (int i = 0; i < nig; ++i) {
      Rec r = B.rec[i];
      if (!owns(r.a.elem) && !owns(r.b.elem)) continue;
      const bool own = owns(r.a.elem);
      r.a.elem = local[r.a.elem], r.b.elem = local[r.b.elem];
      if (r.a.elem < 0 || r.b.elem < 0)
        throw std::logic_error("dyn: interface " + std::to_string(i) +
                               " of an owned element has an end outside the halo");
      kept.push_back(r);
      map.iface_global.push_back(i), map.iface_owned.push_back(own ? 1 : 0);
      nm += i < nmg;
    }
    B.rec = std::move(kept);
    m.n_mortar = nm;
  } else {
    for (int i = 0; i < nig; ++i) map.iface_global.push_back(i), map.iface_owned.push_back(1);
  }
  B.ne = static_cast<int>(B.elem_of.size());
  m.n_elem = B.ne;
  if (part) {  // the masks of the sums (empty in one process: every row counts)
    auto mask = [](const char* label, const std::vector<char>& x) {
      Kokkos::View<std::uint8_t*, Mem> v(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string("nacre::dyn::") + label),
          std::max<std::size_t>(x.size(), 1));
      auto h = Kokkos::create_mirror_view(v);
      h(0) = 0;
      for (std::size_t k = 0; k < x.size(); ++k) h(k) = static_cast<std::uint8_t>(x[k]);
      Kokkos::deep_copy(v, h);
      return v;
    };
    m.elem_owned = mask("elem_owned", map.elem_owned);
    m.iface_owned = mask("iface_owned", map.iface_owned);
    m.driven_owned = mask("driven_owned", map.driven_owned);
  }
  m.irreversible = B.mortar.damage == cohesive::Damage::irreversible;
  if (m.irreversible)
    m.hist = decltype(m.hist)("nacre::dyn::history", m.n_mortar, m.quad.n);  // zero: no separation seen
}

/// The gather list: entries of an element in increasing interface order (a fixed summation order).
template <class Mem>
void build_gather(Build<Mem>& B) {
  Model<Mem>& m = B.m;
  const auto& rec = B.rec;
  auto& goff = B.goff;
  const int ne = B.ne, ni = m.n_iface;
  for (int e = 0; e < ne; ++e) goff[e + 1] += goff[e];
  {
    m.goff = alloc<Kokkos::View<int*, Mem>>("goff", ne + 1);
    m.gent = alloc<decltype(m.gent)>("gent", std::max(goff[ne], 1));
    auto O = Kokkos::create_mirror_view(m.goff);
    auto G = Kokkos::create_mirror_view(m.gent);
    std::vector<int> fill(goff.begin(), goff.end() - 1);
    for (int i = 0; i < ni; ++i) {
      G(fill[rec[i].a.elem]++) = gather_entry(i, 0, rec[i].a.n0, rec[i].a.n1);
      G(fill[rec[i].b.elem]++) = gather_entry(i, 1, rec[i].b.n0, rec[i].b.n1);
    }
    for (int e = 0; e <= ne; ++e) O(e) = goff[e];
    Kokkos::deep_copy(m.goff, O), Kokkos::deep_copy(m.gent, G);
  }
}

/// The prescribed force on the top edge (edges of the polygons lying on y = height).
template <class Mem>
void top_force(Build<Mem>& B) {
  const Params& p = B.p;
  const geometry::Specimen& s = B.s;
  const HostMap& map = B.map;
  Model<Mem>& m = B.m;
  const bool ue = B.ue;
  const int nb = B.nb, ne = B.ne, nd = B.nd;
  if (p.force_top != 0.0) {
    m.fp = alloc<typename Model<Mem>::Dof>("fp", ne, nd);
    auto F = Kokkos::create_mirror_view(m.fp);
    Kokkos::deep_copy(F, 0.0);
    std::vector<int> local(map.elem_brick.size(), -1);  // whole-model element -> model element
    for (int e = 0; e < ne; ++e) local[B.elem_of[e]] = e;
    const double ytol = 1e-9 * std::max(s.width, s.height);
    for (int b = 0; b < nb; ++b) {
      const int n = s.vertex_count(b), o = s.poly_offset[b];
      for (int k = 0; k < n; ++k) {
        const int k1 = (k + 1) % n;
        if (std::abs(s.vy[o + k] - s.height) > ytol || std::abs(s.vy[o + k1] - s.height) > ytol) continue;
        const double half = 0.5 * p.force_top * std::abs(s.vx[o + k1] - s.vx[o + k]);
        int e, n0, n1;
        if (ue) e = map.brick_elem[b] + k, n0 = 1, n1 = 2;
        else e = map.brick_elem[b], n0 = 1 + k, n1 = 1 + k1;
        e = local[e];
        if (e < 0) continue;  // not this rank's
        F(e, 2 * n0 + 1) += half, F(e, 2 * n1 + 1) += half;
      }
    }
    Kokkos::deep_copy(m.fp, F);
  }
}
}  // namespace

template <class Mem>
Model<Mem> build_model(const Params& p, const geometry::Specimen& s, const geometry::Interfaces& f,
                       const deck::Mortar& mortar, HostMap& map, const par::Decomposition* part) {
  Kokkos::Profiling::ScopedRegion region("nacre::dyn::build_model");
  if (!(p.dt > 0)) throw std::invalid_argument("dyn: time step dt must be > 0");
  if (!(p.youngs_modulus > 0) || !(p.density > 0) || !(p.thickness > 0) || !(p.poisson > -1 && p.poisson < 0.5))
    throw std::invalid_argument("dyn: need E > 0, rho > 0, thickness > 0, -1 < nu < 0.5");
  const bool ue = p.method == Method::ue;
  const Material mat{p.youngs_modulus, p.poisson, p.density, p.thickness};
  const int nb = static_cast<int>(s.size());
  Model<Mem> m;
  m.h = p.dt, m.alpha = p.alpha_d, m.beta = p.beta_d, m.thickness = p.thickness, m.eps_th = p.thermal_strain;
  m.pattern = loading::Pattern{p.tension, p.bending, s.width > 0 ? s.width : 1.0};
  m.top_prescribed = p.force_top == 0.0;
  m.brick_height = whole_brick_height(s);
  if (p.quadrature_points < 1 || p.quadrature_points > 8)
    throw std::invalid_argument("dyn: quadrature_points must be 1..8");
  m.quad = cohesive::gauss_legendre(p.quadrature_points);
  // Internal joints (UE): stiff and never leaving the elastic range (x1 far beyond any opening),
  // so they tie the triangles as in §4.4 and cannot rupture.
  m.laws = cohesive::make_law_table(
      mortar.bed, mortar.head,
      cohesive::Law{p.internal_stiffness_factor * p.youngs_modulus / m.brick_height, 1e6, 1e6});

  Build<Mem> B{p, s, f, mortar, map, m, ue, mat, nb, {}, {}, {}, 0, 0, 0, {}, {}, {}, part, {}};
  add_elements(B);
  scale_slivers(B);
  upload_types(B);
  locate_interfaces(B);
  estimate_step(B);  // the whole specimen's (every rank the same)
  restrict_to_part(B);
  upload_elements(B);
  upload_interfaces(B);
  build_gather(B);
  top_force(B);
  return m;
}

template <class Mem>
void set_model_step(Model<Mem>& m, double h) {
  if (!(h > 0)) throw std::invalid_argument("dyn: time step dt must be > 0");
  m.h = h;
  auto K = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.K);
  auto M = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.mass);
  auto N = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.type_nodes);
  auto A = Kokkos::create_mirror_view(m.Ainv);
  step_tables(m, K, M, N, A);
  Kokkos::deep_copy(m.Ainv, A);
}

template <class Mem>
std::size_t model_bytes(const Model<Mem>& m) {
  std::size_t b = 0;
  auto add = [&](const auto& v) { b += v.span() * sizeof(typename std::decay_t<decltype(v)>::value_type); };
  add(m.K), add(m.Ainv), add(m.mass), add(m.klam), add(m.theta), add(m.node_x), add(m.node_y), add(m.type_nodes);
  add(m.type), add(m.driven_index), add(m.cx), add(m.cy), add(m.drive), add(m.fp), add(m.goff), add(m.gent);
  add(m.tile_start), add(m.tile_elem), add(m.driven);
  add(m.ielem), add(m.inode), add(m.ishape), add(m.ixi), add(m.inx), add(m.iny), add(m.ilen), add(m.ikind);
  return b;
}

// the default memory space, and the host's where it differs (a CUDA build's host backends)
#define NACRE_DYN_MODEL(M)                                                                                \
  template Model<M> build_model<M>(const Params&, const geometry::Specimen&, const geometry::Interfaces&, \
                                   const deck::Mortar&, HostMap&, const par::Decomposition*);             \
  template void set_model_step<M>(Model<M>&, double);                                                     \
  template std::size_t model_bytes<M>(const Model<M>&);
NACRE_DYN_MODEL(MemSpace)
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
NACRE_DYN_MODEL(Kokkos::HostSpace)
#endif
#undef NACRE_DYN_MODEL

}  // namespace nacre::dyn
