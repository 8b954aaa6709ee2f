// The factorised Newton preconditioner (include/nacre/mc/hessian_factor.hpp): Eigen's sparse
// Cholesky on host memory. Unknown 3 i + k is free brick i's x (k = 0), y (1) or theta (2).
#include <nacre/mc/hessian_factor.hpp>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace nacre::mc {

struct HessianFactor::Impl {
  Eigen::SparseMatrix<double> H, M;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
  std::vector<int> off, adj, ends;  // host copies of the adjacency (fixed for the run)
  bool analysed = false;
  double shift = 0;
  int nf = 0;
};

HessianFactor::HessianFactor() : impl_(std::make_unique<Impl>()) {}
HessianFactor::~HessianFactor() = default;
HessianFactor::HessianFactor(HessianFactor&&) noexcept = default;
HessianFactor& HessianFactor::operator=(HessianFactor&&) noexcept = default;
double HessianFactor::shift() const { return impl_->shift; }

void HessianFactor::factor(const Model<>& m, const BlockView<>& diag, const SlotBlockView<>& slots, double floor_t,
                           double floor_r) {
  if (!Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible)
    throw std::logic_error("nacre::mc::HessianFactor: host memory only (device builds use block-Jacobi)");
  Kokkos::Profiling::ScopedRegion region("nacre::mc::newton::factor");
  auto& I = *impl_;
  const int nf = m.n_free;
  if (I.off.empty()) {
    I.nf = nf;
    I.off.assign(m.adj_offset.data(), m.adj_offset.data() + nf + 1);
    I.adj.assign(m.adj_iface.data(), m.adj_iface.data() + I.off[nf]);
    I.ends.assign(m.ends.data(), m.ends.data() + 2 * m.n_interfaces);
  }
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(9 * nf + 9 * I.off[nf]));
  std::vector<double> scale(3 * static_cast<std::size_t>(nf));
  const int idx[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
  for (int b = 0; b < nf; ++b) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) t.emplace_back(3 * b + r, 3 * b + c, diag(b, idx[r][c]));
    scale[3 * b] = std::max(std::abs(diag(b, 0)), floor_t);
    scale[3 * b + 1] = std::max(std::abs(diag(b, 1)), floor_t);
    scale[3 * b + 2] = std::max(std::abs(diag(b, 2)), floor_r);
    for (int j = I.off[b]; j < I.off[b + 1]; ++j) {
      const int i = I.adj[j];
      const int other = I.ends[2 * i] == b ? I.ends[2 * i + 1] : I.ends[2 * i];
      if (other >= nf) continue;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) t.emplace_back(3 * b + r, 3 * other + c, slots(j, 3 * r + c));
    }
  }
  const int n = 3 * nf;
  I.H.resize(n, n);
  I.H.setFromTriplets(t.begin(), t.end());  // duplicates (two joints between one pair) add up
  if (!I.analysed) {
    I.llt.analyzePattern(I.H);
    I.analysed = true;
  }
  // H itself, else H + sigma diag(scale) with sigma growing tenfold from 1e-4
  for (double sigma = 0.0;; sigma = sigma == 0.0 ? 1e-4 : 10.0 * sigma) {
    I.M = I.H;
    if (sigma > 0.0)
      for (int k = 0; k < n; ++k) I.M.coeffRef(k, k) += sigma * scale[static_cast<std::size_t>(k)];
    I.llt.factorize(I.M);
    if (I.llt.info() == Eigen::Success) {
      I.shift = sigma;
      return;
    }
    if (sigma > 1e12) throw std::runtime_error("nacre::mc::HessianFactor: no positive definite shift found");
  }
}

void HessianFactor::solve(const GradientView<>& r, const GradientView<>& y) const {
  const auto& I = *impl_;
  Eigen::VectorXd v(3 * I.nf);
  for (int b = 0; b < I.nf; ++b)
    for (int k = 0; k < 3; ++k) v(3 * b + k) = r(b, k);
  const Eigen::VectorXd x = I.llt.solve(v);
  for (int b = 0; b < I.nf; ++b)
    for (int k = 0; k < 3; ++k) y(b, k) = x(3 * b + k);
}

void HessianFactor::apply(const GradientView<>& b, const GradientView<>& y) const {
  const auto& I = *impl_;
  Eigen::VectorXd v(3 * I.nf);
  for (int i = 0; i < I.nf; ++i)
    for (int k = 0; k < 3; ++k) v(3 * i + k) = b(i, k);
  const Eigen::VectorXd x = I.M.selfadjointView<Eigen::Lower>() * v;
  for (int i = 0; i < I.nf; ++i)
    for (int k = 0; k < 3; ++k) y(i, k) = x(3 * i + k);
}

}  // namespace nacre::mc
