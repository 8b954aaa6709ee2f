#pragma once
/// \file
/// \brief Sums whose rounding does not depend on the thread count.
///
/// A Kokkos parallel_reduce adds partial sums in an order set by the number of threads, so a
/// floating-point total differs in its last bits between 1 and 2 threads; the Monte Carlo
/// convergence test would then stop at different cycles and runs would diverge. Here the
/// terms are summed in fixed blocks of kBlock consecutive indices (in parallel over blocks, in
/// order inside a block), and the block sums are added in order on the host. Same bits for
/// any thread count; one extra pass over nb = n / kBlock partials.
///
/// Why two passes on a device: a thread per block walks 128 consecutive terms, so a warp's
/// loads hit 32 blocks 128 elements apart (uncoalesced) and only n / 128 threads run: at 1M
/// elements 7,800 threads, a few percent of an H200, each a chain of 128 dependent loads (the
/// dynamic solver's energy checks cost 7 ms per 32-step chunk there). On a device the terms are
/// first evaluated one thread per index (coalesced, every lane busy) into a scratch row, and the
/// blocks then add that row in the same order: the same bits as the one-pass host path, which
/// keeps the terms in cache and needs no scratch.
#include <nacre/core/types.hpp>

#include <string>

namespace nacre {

/// \brief Workspace for deterministic_sum (one per solver; reused every call).
template <class MemorySpace = MemSpace>
struct SumWorkspace {
  static constexpr int kBlock = 128;
  /// Device sums of at least this many terms take the two passes (header).
  static constexpr int kTwoPassMin = 1 << 15;
  Kokkos::View<double*, MemorySpace> partial;
  typename Kokkos::View<double*, MemorySpace>::host_mirror_type host;
  Kokkos::View<double*, MemorySpace> terms;  ///< device execution spaces only: term(i), one per index

  void reserve(int n) {
    const int nb = (n + kBlock - 1) / kBlock;
    if (static_cast<int>(partial.extent(0)) < nb) {
      partial = Kokkos::View<double*, MemorySpace>("nacre::core::sum_partials", nb);
      host = Kokkos::create_mirror_view(partial);
    }
  }
  void reserve_terms(int n) {
    if (static_cast<int>(terms.extent(0)) < n)
      terms = Kokkos::View<double*, MemorySpace>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::core::sum_terms"), n);
  }
};

/// \brief sum_{i in [begin, end)} term(i), bit-identical for any thread count; runs on `space`
/// (the host copy of the block sums waits for it).
template <class ExecutionSpace, class MemorySpace, class Term>
double deterministic_sum(const ExecutionSpace& space, const char* label, SumWorkspace<MemorySpace>& ws,
                         int begin, int end, const Term& term) {
  static_assert(Kokkos::is_execution_space_v<ExecutionSpace>, "deterministic_sum: not an execution space");
  static_assert(Kokkos::SpaceAccessibility<ExecutionSpace, MemorySpace>::accessible,
                "deterministic_sum: workspace memory not accessible from the execution space");
  const int n = end - begin;
  if (n <= 0) return 0.0;
  constexpr int B = SumWorkspace<MemorySpace>::kBlock;
  ws.reserve(n);
  const int nb = (n + B - 1) / B;
  auto partial = ws.partial;
  // device, and enough terms that one thread per block would leave the device mostly idle (below
  // this a second launch costs more than it saves): the two passes of the header
  constexpr bool kHostExec = Kokkos::SpaceAccessibility<ExecutionSpace, Kokkos::HostSpace>::accessible;
  if (!kHostExec && n >= SumWorkspace<MemorySpace>::kTwoPassMin) {
    ws.reserve_terms(n);
    auto terms = ws.terms;
    Kokkos::parallel_for(
        std::string(label) + "_terms", Kokkos::RangePolicy<ExecutionSpace>(space, 0, n),
        KOKKOS_LAMBDA(const int k) { terms(k) = term(begin + k); });
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecutionSpace>(space, 0, nb), KOKKOS_LAMBDA(const int blk) {
          const int lo = blk * B, hi = Kokkos::min(n, lo + B);
          double s = 0.0;
          for (int k = lo; k < hi; ++k) s += terms(k);
          partial(blk) = s;
        });
  } else {
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecutionSpace>(space, 0, nb), KOKKOS_LAMBDA(const int blk) {
          const int lo = begin + blk * B, hi = Kokkos::min(end, lo + B);
          double s = 0.0;
          for (int i = lo; i < hi; ++i) s += term(i);
          partial(blk) = s;
        });
  }
  Kokkos::deep_copy(space, Kokkos::subview(ws.host, Kokkos::make_pair(0, nb)),
                    Kokkos::subview(partial, Kokkos::make_pair(0, nb)));
  space.fence("nacre::core::deterministic_sum");
  double total = 0.0;
  for (int b = 0; b < nb; ++b) total += ws.host(b);
  return total;
}

/// \brief The same on a default instance of ExecutionSpace.
template <class ExecutionSpace = ExecSpace, class Term>
double deterministic_sum(const char* label, SumWorkspace<typename ExecutionSpace::memory_space>& ws, int begin,
                         int end, const Term& term) {
  return deterministic_sum(ExecutionSpace{}, label, ws, begin, end, term);
}

}  // namespace nacre
