// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Sums whose bits depend on neither the thread count, the backend, nor how the terms are
/// split among processes: exact folding (Demmel and Nguyen's pre-rounding, "Fast reproducible
/// floating-point summation", 2013).
///
/// Why: a Kokkos parallel_reduce adds partial sums in an order set by the number of threads, so
/// a floating-point total differs in its last bits between 1 and 2 threads, and the Monte Carlo
/// convergence test would stop at different cycles. nacre used to fix the order instead (blocks
/// of 128 consecutive indices, added in order); that stops working once the terms are spread
/// over MPI ranks by a 2-D decomposition (a rank owns pieces of many blocks). Here the order
/// does not matter at all:
///   1. amax = max |term| (a max is exact in any order); with n terms, sigma_1 = 1.5 * 2^E1 where
///      2^E1 >= 4 n amax;
///   2. each term t is split t = hi_1 + r with hi_1 = (t + sigma_1) - sigma_1: hi_1 is t rounded to
///      the grid of ulp(sigma_1), and r = t - hi_1 is exact; every partial sum of n such hi_1 is
///      a multiple of ulp(sigma_1) below 2^53 ulps, so it is EXACT, whatever the order;
///   3. the remainders are folded the same way on finer grids (kFolds levels); what is left after
///      the last (below n^4 2^-150 amax-ish for n up to 2^26) is dropped.
/// The level sums are exact, so they add in any order (threads, GPU blocks, MPI_Allreduce) to
/// the same bits; the result is s_1 + (s_2 + s_3), also more accurate than any fixed-order sum.
/// Cost: the terms are evaluated once into a scratch row with the max, then read once more.
#include <nacre/core/types.hpp>

#include <cfloat>
#include <cmath>
#include <limits>
#include <string>

namespace nacre {

/// \brief Workspace for deterministic_sum (one per solver; reused every call): the terms' row.
template <class MemorySpace = MemSpace>
struct SumWorkspace {
  Kokkos::View<double*, MemorySpace> terms;  ///< term(i), one per index of the current sum

  void reserve_terms(int n) {
    if (static_cast<int>(terms.extent(0)) < n)
      terms = Kokkos::View<double*, MemorySpace>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::core::sum_terms"), n);
  }
};

namespace sum {

/// Levels of folding (header, step 3).
inline constexpr int kFolds = 3;

/// \brief What the first pass finds: the largest finite |term| and the non-finite terms.
struct Scan {
  double amax = 0.0;
  long long pos_inf = 0, neg_inf = 0, nan = 0;
};

/// \brief The exact level sums of a fold.
struct Levels {
  double s[kFolds] = {};
};

/// \brief The grids of one sum (host-computed from amax and the global term count).
struct Plan {
  double sigma[kFolds] = {};
  int levels = 0;      ///< grids in use (0: every term is zero)
  double scale = 1.0;  ///< power of two applied to each term first (1 unless n amax nears overflow)
};

/// \brief The grids for n terms of largest magnitude amax (finite, >= 0).
inline Plan plan(double amax, long long n) {
  Plan p;
  if (!(amax > 0.0) || n <= 0) return p;
  int e = 0;
  (void)std::frexp(amax, &e);  // amax < 2^e
  int lg = 0;
  while ((1LL << lg) < n) ++lg;  // n <= 2^lg
  // keep sigma_1 = 1.5 2^E1 finite: scale every term by a power of two (exact for normal terms)
  const int top = std::numeric_limits<double>::max_exponent - 2;  // E1 <= 1021
  if (e + lg + 2 > top) {
    const int shift = e + lg + 2 - top;
    p.scale = std::ldexp(1.0, -shift);
    e -= shift;
  }
  for (int l = 0; l < kFolds; ++l) {
    const int E = e + lg + 2;
    if (E - 52 < std::numeric_limits<double>::min_exponent - 53) break;  // grid below the subnormals
    p.sigma[l] = std::ldexp(1.5, E);
    p.levels = l + 1;
    e = E - 53;  // |remainder| <= ulp(sigma) / 2 = 2^(E - 53)
  }
  return p;
}

/// \brief Fold one term into the level sums (the same operations on every backend).
KOKKOS_INLINE_FUNCTION void fold(const Plan& p, double t, Levels& acc) {
  t *= p.scale;
  for (int l = 0; l < p.levels; ++l) {
    const double hi = (t + p.sigma[l]) - p.sigma[l];
    acc.s[l] += hi;
    t -= hi;
  }
}

/// \brief The total from exact level sums: s_1 + (s_2 + (... + s_k)), unscaled.
inline double total(const Plan& p, const Levels& acc) {
  if (p.levels == 0) return 0.0;
  double r = acc.s[p.levels - 1];
  for (int l = p.levels - 2; l >= 0; --l) r += acc.s[l];
  return r / p.scale;
}

/// \brief The sum a non-finite term makes: NaN if any is NaN or +inf meets -inf, else +-inf.
inline double non_finite(const Scan& s) {
  if (s.nan > 0 || (s.pos_inf > 0 && s.neg_inf > 0)) return std::numeric_limits<double>::quiet_NaN();
  return s.pos_inf > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
}

/// \brief How a sum's partial results combine across processes: in one process, not at all
/// (par::Comm supplies the MPI one: max and counts by MPI_Allreduce, the exact level sums
/// likewise, so every rank gets the bits of the one-process sum).
struct Local {
  void combine(Scan&, long long&) const {}
  void combine(Levels&) const {}
};

/// \brief Pass 1: term(begin + k) into terms(k), and the Scan.
template <class Term, class TermsView>
struct ScanTerms {
  using value_type = Scan;
  Term term;
  TermsView terms;
  int begin;
  KOKKOS_INLINE_FUNCTION void operator()(const int k, Scan& s) const {
    const double t = term(begin + k);
    terms(k) = t;
    const double a = Kokkos::fabs(t);
    if (a <= DBL_MAX) {  // finite (NaN fails every comparison)
      if (a > s.amax) s.amax = a;
    } else if (t != t) {
      ++s.nan;
    } else if (t > 0) {
      ++s.pos_inf;
    } else {
      ++s.neg_inf;
    }
  }
  KOKKOS_INLINE_FUNCTION void init(Scan& s) const { s = Scan{}; }
  KOKKOS_INLINE_FUNCTION void join(Scan& d, const Scan& s) const {
    if (s.amax > d.amax) d.amax = s.amax;
    d.pos_inf += s.pos_inf, d.neg_inf += s.neg_inf, d.nan += s.nan;
  }
};

/// \brief Pass 2: the level sums of terms(k).
template <class TermsView>
struct FoldTerms {
  using value_type = Levels;
  TermsView terms;
  Plan plan;
  KOKKOS_INLINE_FUNCTION void operator()(const int k, Levels& acc) const { fold(plan, terms(k), acc); }
  KOKKOS_INLINE_FUNCTION void init(Levels& v) const { v = Levels{}; }
  KOKKOS_INLINE_FUNCTION void join(Levels& d, const Levels& s) const {
    for (int l = 0; l < kFolds; ++l) d.s[l] += s.s[l];
  }
};

}  // namespace sum

/// \brief sum_{i in [begin, end)} term(i) on `space`, bit-identical for any thread count, backend
/// and (with an MPI `combine`) rank count: the header's exact folding. `combine` joins the
/// partial results of the processes that share the sum (sum::Local: this process alone; every
/// process of a shared sum must call with its own terms, possibly none).
template <class ExecutionSpace, class MemorySpace, class Term, class Combine = sum::Local>
double deterministic_sum(const ExecutionSpace& space, const char* label, SumWorkspace<MemorySpace>& ws, int begin,
                         int end, const Term& term, const Combine& combine = {}) {
  static_assert(Kokkos::is_execution_space_v<ExecutionSpace>, "deterministic_sum: not an execution space");
  static_assert(Kokkos::SpaceAccessibility<ExecutionSpace, MemorySpace>::accessible,
                "deterministic_sum: workspace memory not accessible from the execution space");
  const int n = end > begin ? end - begin : 0;
  ws.reserve_terms(n);
  using TermsView = Kokkos::View<double*, MemorySpace>;
  const TermsView terms = ws.terms;
  sum::Scan scan;
  if (n > 0)
    Kokkos::parallel_reduce(std::string(label) + "_scan", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
                            sum::ScanTerms<Term, TermsView>{term, terms, begin}, scan);
  long long count = n;
  combine.combine(scan, count);
  if (scan.nan + scan.pos_inf + scan.neg_inf > 0) return sum::non_finite(scan);
  const sum::Plan plan = sum::plan(scan.amax, count);
  sum::Levels levels;
  if (n > 0 && plan.levels > 0)
    Kokkos::parallel_reduce(label, Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
                            sum::FoldTerms<TermsView>{terms, plan}, levels);
  combine.combine(levels);
  return sum::total(plan, levels);
}

/// \brief The same on a default instance of ExecutionSpace.
template <class ExecutionSpace = ExecSpace, class Term>
double deterministic_sum(const char* label, SumWorkspace<typename ExecutionSpace::memory_space>& ws, int begin,
                         int end, const Term& term) {
  return deterministic_sum(ExecutionSpace{}, label, ws, begin, end, term);
}

}  // namespace nacre
