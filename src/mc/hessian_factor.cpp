// SPDX-License-Identifier: BSD-3-Clause
// The factorised Newton preconditioner (include/nacre/mc/hessian_factor.hpp): a sparse Cholesky
// on host memory, CHOLMOD's (its C interface, float or double) where the build found it, else
// Eigen's own. Unknown 3 i + k is free brick i's x (k = 0), y (1) or theta (2), i in the
// one-process numbering; on several ranks rank 0 alone holds the matrix and its factor.
#include <nacre/mc/hessian_factor.hpp>

#include <Eigen/SparseCore>
#ifdef NACRE_HAVE_CHOLMOD
#include <cholmod.h>
#else
#include <Eigen/SparseCholesky>
#endif

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace nacre::mc {

namespace {
#ifdef NACRE_HAVE_CHOLMOD
/// CHOLMOD's supernodal LL^T in a nested-dissection order (METIS), through its C interface (Eigen's
/// wrapper is double only). Measured on the 20k-brick reference path (docs/speed_accuracy.md):
/// 1.1 GFlop and 5.3M entries of L per factor with METIS against 1.6 GFlop and 6.1M with AMD; run
/// time 80 / 101 / 124 CPU-s (METIS, AMD, Eigen's SimplicialLLT with AMD). `single`: the factor
/// and its solves in float (CHOLMOD 5), half the bytes a solve streams; the preconditioner only
/// (CG's vectors, H v and the residual stay double). A non-positive pivot ends the factor at once
/// (the shift loop then tries the next sigma), and says nothing (an indefinite H is expected
/// there). CHOLMOD's own threads are off: the factor's bits must not depend on the thread count
/// (its BLAS must be single-threaded too: the dev root's OpenBLAS is the serial build).
class Factor {
public:
  explicit Factor(bool single) : dtype_(single ? CHOLMOD_SINGLE : CHOLMOD_DOUBLE) {
    cholmod_start(&c_);
    c_.final_asis = 1;
    c_.supernodal = CHOLMOD_SUPERNODAL;
    c_.quick_return_if_not_posdef = 1;
    c_.nmethods = 1;
    c_.method[0].ordering = CHOLMOD_METIS;
    c_.postorder = 1;
    c_.print = 0;
    c_.nthreads_max = 1;
    // relaxed supernodes twice CHOLMOD's defaults (nrelax 4/16/48, zrelax 0.8/0.1/0.05): larger
    // dense blocks, more explicit zeros. On the 20k-brick reference path (one thread, side by
    // side): factorisations 11.5 -> 6.6 s, each solve 12-24 % slower; none (1/1/1, 0/0/0)
    // doubled the factorisations' time (docs/speed_accuracy.md)
    c_.nrelax[0] = 16, c_.nrelax[1] = 48, c_.nrelax[2] = 96;
    c_.zrelax[0] = 0.8, c_.zrelax[1] = 0.2, c_.zrelax[2] = 0.1;
  }
  ~Factor() {
    if (L_) cholmod_free_factor(&L_, &c_);
    if (X_) cholmod_free_dense(&X_, &c_);
    if (Y_) cholmod_free_dense(&Y_, &c_);
    if (E_) cholmod_free_dense(&E_, &c_);
    cholmod_finish(&c_);
  }
  Factor(const Factor&) = delete;
  Factor& operator=(const Factor&) = delete;

  /// the ordering and symbolic factor; AMD where this CHOLMOD was built without METIS
  void analyse(const Eigen::SparseMatrix<double>& H) {
    // where each diagonal entry lies in H's values (the pattern is fixed for the run)
    diag_.resize(static_cast<std::size_t>(H.cols()));
    for (Eigen::Index k = 0; k < H.cols(); ++k) {
      const int* first = H.innerIndexPtr() + H.outerIndexPtr()[k];
      const int* last = H.innerIndexPtr() + H.outerIndexPtr()[k + 1];
      const int* at = std::lower_bound(first, last, static_cast<int>(k));
      if (at == last || *at != k) throw std::logic_error("nacre::mc::HessianFactor: a diagonal entry is missing");
      diag_[static_cast<std::size_t>(k)] = at - H.innerIndexPtr();
    }
    cholmod_sparse A = view(H, 0.0, {});
    L_ = cholmod_analyze(&A, &c_);
    if (c_.status == CHOLMOD_NOT_INSTALLED) {
      if (L_) cholmod_free_factor(&L_, &c_);
      c_.method[0].ordering = CHOLMOD_AMD;
      L_ = cholmod_analyze(&A, &c_);
    }
    if (!L_ || c_.status < 0)
      throw std::runtime_error("nacre::mc::HessianFactor: CHOLMOD's analysis failed (status " +
                               std::to_string(c_.status) + ")");
  }
  /// the numeric factor of H + sigma diag(scale) (H: the analysed pattern); false where it is not
  /// positive definite. The shifted values are written once, in the factor's precision, straight
  /// from H's (no shifted copy of H is kept).
  bool factorize(const Eigen::SparseMatrix<double>& H, double sigma, const std::vector<double>& scale) {
    cholmod_sparse A = view(H, sigma, scale);
    cholmod_factorize(&A, L_, &c_);
    if (c_.status < 0)
      throw std::runtime_error("nacre::mc::HessianFactor: CHOLMOD's factorisation failed (status " +
                               std::to_string(c_.status) + ")");
    return L_->minor == L_->n;
  }
  [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& v) {
    const auto n = static_cast<std::size_t>(v.size());
    cholmod_dense B{};
    B.nrow = B.d = B.nzmax = n;
    B.ncol = 1;
    B.xtype = CHOLMOD_REAL;
    B.dtype = dtype_;
    if (dtype_ == CHOLMOD_SINGLE) {
      bf_.resize(n);
      for (std::size_t k = 0; k < n; ++k) bf_[k] = static_cast<float>(v[static_cast<Eigen::Index>(k)]);
      B.x = bf_.data();
    } else {
      B.x = const_cast<double*>(v.data());  // read only
    }
    if (!cholmod_solve2(CHOLMOD_A, L_, &B, nullptr, &X_, nullptr, &Y_, &E_, &c_))
      throw std::runtime_error("nacre::mc::HessianFactor: CHOLMOD's solve failed (status " + std::to_string(c_.status) +
                               ")");
    Eigen::VectorXd x(v.size());
    if (dtype_ == CHOLMOD_SINGLE) {
      const auto* p = static_cast<const float*>(X_->x);
      for (std::size_t k = 0; k < n; ++k) x[static_cast<Eigen::Index>(k)] = p[k];
    } else {
      const auto* p = static_cast<const double*>(X_->x);
      for (std::size_t k = 0; k < n; ++k) x[static_cast<Eigen::Index>(k)] = p[k];
    }
    return x;
  }

private:
  /// H + sigma diag(scale) as CHOLMOD's symmetric matrix (lower triangle used), in the factor's
  /// precision: H's own values where double and unshifted, else one converted, shifted copy
  cholmod_sparse view(const Eigen::SparseMatrix<double>& H, double sigma, const std::vector<double>& scale) {
    cholmod_sparse A{};
    A.nrow = A.ncol = static_cast<std::size_t>(H.rows());
    A.nzmax = static_cast<std::size_t>(H.nonZeros());
    A.p = const_cast<int*>(H.outerIndexPtr());  // read only
    A.i = const_cast<int*>(H.innerIndexPtr());
    A.stype = -1;
    A.itype = CHOLMOD_INT;
    A.xtype = CHOLMOD_REAL;
    A.dtype = dtype_;
    A.sorted = 1;
    A.packed = 1;
    const double* h = H.valuePtr();
    if (dtype_ == CHOLMOD_SINGLE) {
      xf_.assign(h, h + A.nzmax);  // converted to float
      for (std::size_t k = 0; k < diag_.size() && sigma > 0.0; ++k)
        xf_[static_cast<std::size_t>(diag_[k])] = static_cast<float>(h[diag_[k]] + sigma * scale[k]);
      A.x = xf_.data();
    } else if (sigma > 0.0) {
      xd_.assign(h, h + A.nzmax);
      for (std::size_t k = 0; k < diag_.size(); ++k) xd_[static_cast<std::size_t>(diag_[k])] += sigma * scale[k];
      A.x = xd_.data();
    } else {
      A.x = const_cast<double*>(h);  // read only
    }
    return A;
  }
  int dtype_;
  cholmod_common c_{};
  cholmod_factor* L_ = nullptr;
  cholmod_dense *X_ = nullptr, *Y_ = nullptr, *E_ = nullptr;  // solve2's reused workspace
  std::vector<float> xf_, bf_;
  std::vector<double> xd_;
  std::vector<std::ptrdiff_t> diag_;  // H's diagonal entries' positions in its values
};
#else
/// Eigen's SimplicialLLT in an AMD order (double; `single` is CHOLMOD's only)
class Factor {
public:
  explicit Factor(bool /*single*/) {}
  void analyse(const Eigen::SparseMatrix<double>& H) { llt_.analyzePattern(H); }
  bool factorize(const Eigen::SparseMatrix<double>& H, double sigma, const std::vector<double>& scale) {
    if (sigma == 0.0) {
      llt_.factorize(H);
    } else {
      Eigen::SparseMatrix<double> M = H;  // a shifted copy for this attempt only
      for (Eigen::Index k = 0; k < M.rows(); ++k) M.coeffRef(k, k) += sigma * scale[static_cast<std::size_t>(k)];
      llt_.factorize(M);
    }
    return llt_.info() == Eigen::Success;
  }
  [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& v) { return llt_.solve(v); }

private:
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt_;
};
#endif
}  // namespace

struct HessianFactor::Impl {
  Eigen::SparseMatrix<double> H;  // rank 0
  int last_shifted = 0;           // rank 0: the attempt (1: 1e-4, 2: 1e-3, ...) of the last shifted factor
  std::unique_ptr<Factor> llt;
  std::vector<int> off, adj, ends;              // host copies of the local adjacency (fixed for the run)
  par::Comm comm;                               // one process unless distribute()d
  std::vector<int> global_free;                 // per local brick: one-process free index, -1 held
  std::vector<std::vector<long long>> of_rank;  // rank 0: each rank's free bricks' one-process indices
  bool analysed = false, ready = false;
  std::vector<std::size_t> value_at;  // rank 0: per entry in factor()'s order, its place among H's values
  std::vector<char> first_at;         // rank 0: 1 where that entry is its place's first
  double shift = 0;
  int nf = 0;       // this rank's free bricks
  long long n = 0;  // free bricks of the whole specimen

  /// first call: the adjacency, the numbering and (rank 0) who holds which unknowns
  void setup(const Model<Kokkos::HostSpace>& m) {
    if (ready) return;
    nf = m.n_free;
    off.assign(m.adj_offset.data(), m.adj_offset.data() + nf + 1);
    adj.assign(m.adj_iface.data(), m.adj_iface.data() + off[nf]);
    ends.assign(m.ends.data(), m.ends.data() + 2 * m.n_interfaces);
    if (global_free.empty()) {  // one process: the model's own numbering
      global_free.assign(static_cast<std::size_t>(m.n_bricks), -1);
      for (int k = 0; k < nf; ++k) global_free[k] = k;
    }
    if (static_cast<int>(global_free.size()) != m.n_bricks)
      throw std::logic_error("nacre::mc::HessianFactor: a numbering of another model");
    std::vector<long long> mine(global_free.begin(), global_free.begin() + nf);
    n = comm.sum(static_cast<long long>(nf));
    of_rank = comm.gather(std::move(mine));
    ready = true;
  }
  /// rank 0: the pieces of every rank in one-process order (x placed at of_rank's indices)
  [[nodiscard]] Eigen::VectorXd assemble(const std::vector<std::vector<double>>& parts) const {
    Eigen::VectorXd v(3 * n);
    for (std::size_t r = 0; r < parts.size(); ++r)
      for (std::size_t k = 0; k < of_rank[r].size(); ++k)
        for (int c = 0; c < 3; ++c) v(3 * of_rank[r][k] + c) = parts[r][3 * k + static_cast<std::size_t>(c)];
    return v;
  }
  /// y = op(r) on the whole vector: gathered to rank 0, op there, scattered back
  template <class Op>
  void through_root(const GradientView<Kokkos::HostSpace>& r, const GradientView<Kokkos::HostSpace>& y,
                    const Op& op) const {
    std::vector<double> mine(3 * static_cast<std::size_t>(nf));
    for (int b = 0; b < nf; ++b)
      for (int k = 0; k < 3; ++k) mine[3 * static_cast<std::size_t>(b) + k] = r(b, k);
    const std::vector<std::vector<double>> parts = comm.gather(std::move(mine));
    std::vector<std::vector<double>> out(parts.size());
    if (comm.rank() == 0) {
      const Eigen::VectorXd x = op(assemble(parts));
      for (std::size_t q = 0; q < parts.size(); ++q) {
        out[q].resize(parts[q].size());
        for (std::size_t k = 0; k < of_rank[q].size(); ++k)
          for (int c = 0; c < 3; ++c) out[q][3 * k + static_cast<std::size_t>(c)] = x(3 * of_rank[q][k] + c);
      }
    }
    mine.assign(3 * static_cast<std::size_t>(nf), 0.0);
    comm.scatter(out, mine);
    for (int b = 0; b < nf; ++b)
      for (int k = 0; k < 3; ++k) y(b, k) = mine[3 * static_cast<std::size_t>(b) + k];
  }
};

HessianFactor::HessianFactor(bool single) : impl_(std::make_unique<Impl>()) {
  impl_->llt = std::make_unique<Factor>(single);
}
HessianFactor::~HessianFactor() = default;
HessianFactor::HessianFactor(HessianFactor&&) noexcept = default;
HessianFactor& HessianFactor::operator=(HessianFactor&&) noexcept = default;
double HessianFactor::shift() const { return impl_->shift; }
void HessianFactor::forget_shift() { impl_->last_shifted = 0; }

void HessianFactor::distribute(const par::Comm& comm, std::vector<int> global_free) {
  if (impl_->ready) throw std::logic_error("nacre::mc::HessianFactor::distribute: before the first factor()");
  impl_->comm = comm;
  impl_->global_free = std::move(global_free);
}

void HessianFactor::factor(const Model<Kokkos::HostSpace>& m, const BlockView<Kokkos::HostSpace>& diag,
                           const SlotBlockView<Kokkos::HostSpace>& slots, double floor_t, double floor_r,
                           bool indefinite) {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::newton::factor");
  auto& I = *impl_;
  I.setup(m);
  // this rank's rows, brick by brick: the diagonal block (6), the count of free neighbours' slots,
  // then per such slot (adjacency order) the neighbour's one-process index and its 9 values
  std::vector<double> rows;
  rows.reserve(static_cast<std::size_t>(7 * I.nf + 10 * I.off[I.nf]));
  for (int b = 0; b < I.nf; ++b) {
    for (int k = 0; k < 6; ++k) rows.push_back(diag(b, k));
    const std::size_t count_at = rows.size();
    rows.push_back(0.0);
    for (int j = I.off[b]; j < I.off[b + 1]; ++j) {
      const int i = I.adj[j];
      const int other = I.ends[2 * i] == b ? I.ends[2 * i + 1] : I.ends[2 * i];
      const int g = I.global_free[other];
      if (g < 0) continue;  // a held neighbour: no unknowns
      rows.push_back(g);
      for (int q = 0; q < 9; ++q) rows.push_back(slots(j, q));
      rows[count_at] += 1.0;
    }
  }
  std::vector<std::vector<double>> parts = I.comm.gather(std::move(rows));
  double result[2] = {0.0, 1.0};  // the shift, success
  if (I.comm.rank() == 0) {
    // where each unknown's row lies, then the triplets in the one-process order
    std::vector<const double*> at(static_cast<std::size_t>(I.n), nullptr);
    for (std::size_t r = 0; r < parts.size(); ++r) {
      const double* p = parts[r].data();
      for (long long g : I.of_rank[r]) {
        at[static_cast<std::size_t>(g)] = p;
        p += 7 + 10 * static_cast<std::ptrdiff_t>(p[6]);
      }
    }
    const long long n = 3 * I.n;
    std::vector<double> scale(static_cast<std::size_t>(n));
    const int idx[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    // H's entries in one fixed order (brick by brick: its diagonal block, then its slots'):
    // the first call makes H from them as triplets and records where each lands among H's
    // values; later calls (the pattern is the run's) write them there, duplicates (two joints
    // between one pair) added in the same order as Eigen's setFromTriplets adds them, so H has
    // the same bits without a triplet sort per factor (about 60 ms a factor at 20k bricks)
    const bool first = !I.analysed;
    std::size_t words = 0;  // 7 a brick, 10 a slot of 9 entries
    for (const auto& p : parts) words += p.size();
    const std::size_t entries =
        9 * static_cast<std::size_t>(I.n) + 9 * (words - 7 * static_cast<std::size_t>(I.n)) / 10;
    if (!first && entries != I.value_at.size())
      throw std::logic_error("nacre::mc::HessianFactor: the Hessian's pattern changed within a run");
    std::vector<Eigen::Triplet<double>> t;
    if (first) t.reserve(entries);
    double* h = first ? nullptr : I.H.valuePtr();  // every place has a first entry: no zeroing needed
    std::size_t e = 0;  // the entry's rank in the fixed order
    auto put = [&](int r, int c, double v) {
      if (first)
        t.emplace_back(r, c, v);
      else if (I.first_at[e])
        h[I.value_at[e]] = v;
      else
        h[I.value_at[e]] += v;
      ++e;
    };
    for (long long b = 0; b < I.n; ++b) {
      const double* p = at[static_cast<std::size_t>(b)];
      const auto B = static_cast<int>(3 * b);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) put(B + r, B + c, p[idx[r][c]]);
      scale[B] = std::max(std::abs(p[0]), floor_t);
      scale[B + 1] = std::max(std::abs(p[1]), floor_t);
      scale[B + 2] = std::max(std::abs(p[2]), floor_r);
      const int cnt = static_cast<int>(p[6]);
      for (int s = 0; s < cnt; ++s) {
        const double* q = p + 7 + 10 * s;
        const int O = 3 * static_cast<int>(q[0]);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) put(B + r, O + c, q[1 + 3 * r + c]);
      }
    }
    parts.clear();
    if (first) {
      I.H.resize(n, n);
      I.H.setFromTriplets(t.begin(), t.end());  // duplicates add up, in the triplets' order
      I.value_at.resize(t.size());
      I.first_at.assign(t.size(), 0);
      std::vector<char> seen(static_cast<std::size_t>(I.H.nonZeros()), 0);
      for (std::size_t k = 0; k < t.size(); ++k) {  // column-major: the row among the column's
        const int* lo = I.H.innerIndexPtr() + I.H.outerIndexPtr()[t[k].col()];
        const int* hi = I.H.innerIndexPtr() + I.H.outerIndexPtr()[t[k].col() + 1];
        const auto at_k = static_cast<std::size_t>(std::lower_bound(lo, hi, t[k].row()) - I.H.innerIndexPtr());
        I.value_at[k] = at_k;
        I.first_at[k] = seen[at_k] ? 0 : 1;
        seen[at_k] = 1;
      }
      I.llt->analyse(I.H);
      I.analysed = true;
    }
    // H itself, else H + sigma diag(scale), sigma in 1e-4, 1e-3, ... (tenfold). A failed attempt
    // costs about what a factor does (0.24 s against 0.27 s at 20k bricks), so past sigma = 0 the
    // search resumes a decade below the last positive shift since forget_shift() (the smallest
    // decade that works whenever that is at most one decade lower), and starts there where the
    // caller says H is likely indefinite (trust_region.hpp: CG met negative curvature). On the
    // 20k-brick reference path 48 -> 44 failed attempts; the memory is a load step's own (see
    // docs/speed_accuracy.md for what a memory across steps would save).
    Kokkos::Profiling::ScopedRegion numeric("nacre::mc::newton::factor_numeric");
    // attempt k: sigma = 0 (k = 0), else 1e-4 10^(k - 1) by repeated products (the former bits)
    auto sigma_of = [](int k) {
      double sg = k == 0 ? 0.0 : 1e-4;
      for (int q = 1; q < k; ++q) sg *= 10.0;
      return sg;
    };
    const int resume = std::max(1, I.last_shifted - 1);
    for (int k = indefinite ? resume : 0;; k = k == 0 ? resume : k + 1) {
      const double sigma = sigma_of(k);
      if (I.llt->factorize(I.H, sigma, scale)) {
        result[0] = sigma;
        if (k > 0) I.last_shifted = k;
        break;
      }
      if (sigma > 1e12) {
        result[1] = 0.0;
        break;
      }
    }
  }
  I.comm.broadcast(result, 2);
  if (result[1] == 0.0) throw std::runtime_error("nacre::mc::HessianFactor: no positive definite shift found");
  I.shift = result[0];
}

void HessianFactor::solve(const GradientView<Kokkos::HostSpace>& r, const GradientView<Kokkos::HostSpace>& y) const {
  Kokkos::Profiling::ScopedRegion region("nacre::mc::newton::factor_solve");
  const auto& I = *impl_;
  I.through_root(r, y, [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return I.llt->solve(v); });
}

}  // namespace nacre::mc
