// SPDX-License-Identifier: BSD-3-Clause
// BIE start-up (host, Eigen): the Jacobian of eq. 4.7 per element type, its inverse and
// condition number, the slot order (elements sorted by type) and the tiles of the shared-J^-1
// product. See include/nacre/dyn/bie.hpp for the method.
#include <nacre/dyn/bie.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace nacre::dyn {

namespace {
constexpr double kMaxCondition = 1e12;

/// J of eq. 4.7 for type t from host copies of the model's K and mass.
template <class Mem, class HostK, class HostM>
std::vector<double> jacobian_of_type(const Model<Mem>& m, const HostK& K, const HostM& M, int t) {
  const int nd = m.nd, n = 2 * nd;
  const double h = m.h;
  std::vector<double> J(static_cast<std::size_t>(n) * n, 0.0);  // row-major
  auto at = [&](int i, int j) -> double& { return J[static_cast<std::size_t>(i) * n + j]; };
  for (int i = 0; i < n; ++i) at(i, i) = 1.0;
  for (int i = 0; i < nd; ++i) {
    if (!(M(t, i) > 0)) continue;  // padded dof: identity
    const double mi = 1.0 / M(t, i);
    for (int j = 0; j < nd; ++j) {
      const double mk = mi * K(t, i, j);
      const double mc = m.alpha * (i == j ? 1.0 : 0.0) + m.beta * mk;  // M^-1 C, C = alpha M + beta K
      at(i, j) += 0.25 * h * h * mk;
      at(i, nd + j) += 0.25 * h * h * mc;
      at(nd + i, j) += 0.5 * h * mk;
      at(nd + i, nd + j) += 0.5 * h * mc;
    }
  }
  return J;
}
}  // namespace

template <class Mem>
std::vector<double> bie_jacobian_host(const Model<Mem>& m, int t) {
  // Whole views mirrored: a subview at fixed type is strided under the GPU's LayoutLeft, and
  // Kokkos cannot deep_copy a strided device view to the host (found on an H100).
  return jacobian_of_type(m, Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.K),
                          Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.mass), t);
}

template <class Mem>
BieTables<Mem> build_bie_tables(const Model<Mem>& m) {
  Kokkos::Profiling::ScopedRegion region("nacre::dyn::bie_tables");
  BieTables<Mem> b;
  const int nd = m.nd, n = 2 * nd, nt = m.n_types, ne = m.n_elem;
  b.n2 = n;
  b.block_lower = m.beta == 0.0;  // C = alpha M: the v-columns of J are diagonal (b I, c I)
  if (b.block_lower) {
    // b and c of J (eq. 4.7 as bie_jacobian_host forms them) on a dof with mass; the kernels use
    // b / c and 1 / c from here, so the blocks below are built from the same two numbers
    const double bq = 0.25 * m.h * m.h * m.alpha, c = 1.0 + 0.5 * m.h * m.alpha;
    b.jq = bq / c, b.jr = 1.0 / c;
  }
  b.vfirst = m.beta != 0.0;
  b.Jinv = typename BieTables<Mem>::TypeMat(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::bie_Jinv"), nt,
                                            n, n);
  auto Jh = Kokkos::create_mirror_view(b.Jinv);
  if (b.vfirst)
    b.Jv = typename BieTables<Mem>::TypeMat(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::bie_Jv"), nt,
                                            nd, n);
  auto Jvh = Kokkos::create_mirror_view(b.Jv);
  const auto Kh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.K);  // once for every type
  const auto Mh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.mass);
  for (int t = 0; t < nt; ++t) {
    const auto Jv = jacobian_of_type(m, Kh, Mh, t);
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Jraw(Jv.data(), n, n);
    // Rows/columns of p (mm) and v (mm/s) differ in unit: invert the dimensionless
    // J~ = D J D^-1, D = diag(I, h I) (velocity as h v), whose condition number means something,
    // then J^-1 = D^-1 J~^-1 D.
    Eigen::VectorXd d = Eigen::VectorXd::Ones(n);
    d.tail(nd).setConstant(m.h);
    const Eigen::MatrixXd J = d.asDiagonal() * Jraw * d.cwiseInverse().asDiagonal();
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(J);
    Eigen::MatrixXd Jti = lu.inverse(), Jis;
    if (b.block_lower) {
      // J = [[A, Bd], [P, Cd]], A = I + h^2/4 M^-1 K, P = h/2 M^-1 K, Bd = diag(q_i c_i), Cd = diag(c_i)
      // (q_i = b / c, c_i = c on dofs with mass, the kernels' test; 0 and 1 on padded ones).
      // Built blockwise; the rest agrees with the LU inverse to rounding (checked below).
      const Eigen::MatrixXd Jp = Jraw.topLeftCorner(nd, nd), Jvp = Jraw.bottomLeftCorner(nd, nd);
      Jis = Eigen::MatrixXd::Zero(n, n);
      if (b.jq == 0.0) {
        // C = 0: J^-1 = [[A^-1, 0], [-P A^-1, I]], the zero block and the identity exact (the
        // tiled apply skips them, bit for bit the dense product of this matrix)
        const Eigen::MatrixXd Ai = Eigen::PartialPivLU<Eigen::MatrixXd>(Jp).inverse();
        Jis.topLeftCorner(nd, nd) = Ai;
        Jis.bottomLeftCorner(nd, nd) = -(Jvp * Ai);
        Jis.bottomRightCorner(nd, nd).setIdentity();
      } else {
        // C = alpha M: J^-1 = [[S^-1, -S^-1 Q], [L, Cd^-1 - L Q]], S = A - Q P, Q = diag(q_i),
        // L = -Cd^-1 P S^-1
        Eigen::VectorXd q = Eigen::VectorXd::Zero(nd), r = Eigen::VectorXd::Ones(nd);
        for (int i = 0; i < nd; ++i)
          if (Mh(t, i) > 0) q(i) = b.jq, r(i) = b.jr;
        const Eigen::MatrixXd Si = Eigen::PartialPivLU<Eigen::MatrixXd>(Jp - q.asDiagonal() * Jvp).inverse();
        const Eigen::MatrixXd L = -(r.asDiagonal() * (Jvp * Si));
        Jis.topLeftCorner(nd, nd) = Si;
        Jis.bottomLeftCorner(nd, nd) = L;
        Jis.topRightCorner(nd, nd) = -(Si * q.asDiagonal());
        Jis.bottomRightCorner(nd, nd) = Eigen::MatrixXd(r.asDiagonal()) - L * q.asDiagonal();
      }
      Jti = d.asDiagonal() * Jis * d.cwiseInverse().asDiagonal();  // dimensionless, for the checks below
    }
    // cond_1(J~) = |J~|_1 |J~^-1|_1 (exact for the computed inverse, n <= 32: cheap)
    const double cond = J.cwiseAbs().colwise().sum().maxCoeff() * Jti.cwiseAbs().colwise().sum().maxCoeff();
    const double err = (J * Jti - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff();
    const Eigen::MatrixXd Ji = b.block_lower ? Jis : Eigen::MatrixXd(d.cwiseInverse().asDiagonal() * Jti * d.asDiagonal());
    if (!std::isfinite(cond) || cond > kMaxCondition || !Ji.allFinite())
      throw std::runtime_error("dyn: BIE Jacobian of element type " + std::to_string(t) + " is ill-conditioned (cond_1 of D J D^-1 = " +
                               std::to_string(cond) + " > 1e12); the step or the damping is out of range");
    b.max_condition = std::max(b.max_condition, cond);
    b.max_identity_error = std::max(b.max_identity_error, err);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) Jh(t, i, j) = Ji(i, j);
    if (b.vfirst) {
      // Jv = J^-1's velocity rows times E^-1, E = [[I, -h/2 I], [0, I]] on the dofs with mass
      // (the row operation that turns J's position rows into [I, -h/2 I]): J^-1 g = (E J)^-1 E g,
      // and (E J)^-1's velocity rows are Jv. The position rows are not stored: y_p = g~_p + h/2 y_v.
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) {
          const double hh = Mh(t, j) > 0 ? 0.5 * m.h : 0.0;
          Jvh(t, i, j) = Ji(nd + i, j);
          Jvh(t, i, nd + j) = Ji(nd + i, nd + j) + hh * Ji(nd + i, j);
        }
      // the row structure the apply relies on, checked on J itself: J_p - h/2 J_v = [I, -h/2 I]
      // (relative to the row's largest entry: the subtraction cancels terms as large as h^2/4 M^-1 K)
      double dev = 0;
      for (int i = 0; i < nd; ++i) {
        if (!(Mh(t, i) > 0)) continue;
        double scale = 1.0;
        for (int j = 0; j < n; ++j) scale = std::max(scale, std::abs(Jraw(i, j)) * (j < nd ? 1.0 : 1.0 / m.h));
        for (int j = 0; j < n; ++j) {
          const double want = j == i ? 1.0 : (j == nd + i ? -0.5 * m.h : 0.0);
          const double got = Jraw(i, j) - 0.5 * m.h * Jraw(nd + i, j);
          dev = std::max(dev, std::abs(got - want) * (j < nd ? 1.0 : 1.0 / m.h) / scale);
        }
      }
      if (dev > 1e-9)
        throw std::runtime_error("dyn: BIE Jacobian of element type " + std::to_string(t) +
                                 " lacks the row structure of eq. 4.7 (deviation " + std::to_string(dev) + ")");
    }
  }
  Kokkos::deep_copy(b.Jinv, Jh);
  if (b.vfirst) Kokkos::deep_copy(b.Jv, Jvh);

  // slots: elements sorted by type (stable), tiles of <= kTile slots of one type
  auto types = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace{}, m.type);
  b.type_offset.assign(nt + 1, 0);
  for (int e = 0; e < ne; ++e) ++b.type_offset[types(e) + 1];
  for (int t = 0; t < nt; ++t) b.type_offset[t + 1] += b.type_offset[t];
  b.slot_of_elem = Kokkos::View<int*, Mem>(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::bie_slot"), ne);
  b.slot_type = Kokkos::View<int*, Mem>(Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::dyn::bie_slot_type"),
                                        std::max(ne, 1));
  auto so = Kokkos::create_mirror_view(b.slot_of_elem);
  auto st = Kokkos::create_mirror_view(b.slot_type);
  std::vector<int> fill(b.type_offset.begin(), b.type_offset.end() - 1);
  for (int e = 0; e < ne; ++e) {
    const int s = fill[types(e)]++;
    so(e) = s, st(s) = types(e);
  }
  std::vector<int> ts, tc;
  for (int t = 0; t < nt; ++t)
    for (int s = b.type_offset[t]; s < b.type_offset[t + 1]; s += kTile)
      ts.push_back(s), tc.push_back(std::min(kTile, b.type_offset[t + 1] - s));
  const int ntile = static_cast<int>(ts.size());
  b.tile_start = Kokkos::View<int*, Mem>("nacre::dyn::bie_tile_start", std::max(ntile, 1));
  b.tile_count = Kokkos::View<int*, Mem>("nacre::dyn::bie_tile_count", std::max(ntile, 1));
  auto hts = Kokkos::create_mirror_view(b.tile_start);
  auto htc = Kokkos::create_mirror_view(b.tile_count);
  for (int w = 0; w < ntile; ++w) hts(w) = ts[w], htc(w) = tc[w];
  Kokkos::deep_copy(b.slot_of_elem, so), Kokkos::deep_copy(b.slot_type, st);
  Kokkos::deep_copy(b.tile_start, hts), Kokkos::deep_copy(b.tile_count, htc);
  return b;
}

template <class Mem>
std::size_t bie_bytes(const BieTables<Mem>& b) {
  return (b.Jinv.span() + b.Jv.span()) * sizeof(double) +
         (b.slot_of_elem.span() + b.slot_type.span() + b.tile_start.span() + b.tile_count.span()) * sizeof(int);
}

// the default memory space, and the host's where it differs (a CUDA build's host backends)
#define NACRE_DYN_BIE(M)                                                   \
  template std::vector<double> bie_jacobian_host<M>(const Model<M>&, int); \
  template BieTables<M> build_bie_tables<M>(const Model<M>&);              \
  template std::size_t bie_bytes<M>(const BieTables<M>&);
NACRE_DYN_BIE(MemSpace)
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
NACRE_DYN_BIE(Kokkos::HostSpace)
#endif
#undef NACRE_DYN_BIE

const char* bie_solve_name(BieSolve s) {
  switch (s) {
  case BieSolve::row: return "row";
  case BieSolve::reordered: return "reordered";
  case BieSolve::batched: return "batched";
  case BieSolve::shared_gemm: return "shared_gemm";
  }
  return "?";
}

bool parse_bie_solve(const std::string& name, BieSolve& out) {
  for (auto s : {BieSolve::row, BieSolve::reordered, BieSolve::batched, BieSolve::shared_gemm})
    if (name == bie_solve_name(s)) {
      out = s;
      return true;
    }
  return false;
}

bool bie_solve_available(BieSolve s) {
#if defined(NACRE_HAVE_KOKKOSKERNELS)
  (void)s;
  return true;
#else
  return s != BieSolve::batched;
#endif
}

}  // namespace nacre::dyn
