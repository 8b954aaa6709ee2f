// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The generator interface of nacre: reproducible uniforms keyed by (seed, stream, draw).
///
/// Every Monte Carlo trial needs four uniforms (dx, dy, dtheta, acceptance). A source fills a
/// table of them for a batch of streams (one stream per brick, keyed by the brick's original id,
/// so the numbers do not depend on storage order, colouring, thread count or backend) at one
/// draw index (the global cycle number). Batching lets table-free generators such as bitsliced
/// AES work on many blocks at once; it also makes the RNG a separately timed phase (Fig. 2.12).
#include <nacre/core/backend.hpp>
#include <nacre/core/types.hpp>
#include <nacre/rng/philox.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace nacre::rng {

/// \brief u(i, 0..3): four uniforms for stream i. LayoutLeft: column j is contiguous, so thread i
/// and thread i+1 read adjacent doubles (coalesced on GPUs, unit stride for CPU vector lanes).
template <class MS = MemSpace>
using UniformTable = Kokkos::View<double* [4], Kokkos::LayoutLeft, MS>;

/// \brief Stream ids of a batch (e.g. original brick ids in colour order).
template <class MS = MemSpace>
using StreamIds = Kokkos::View<const std::uint64_t*, MS>;

/// \brief Exact, unbiased map of 64 random bits to a double in [0, 1): the top 53 bits times
/// 2^-53 hit each of the 2^53 equally spaced values with equal probability.
KOKKOS_INLINE_FUNCTION double to_unit_double(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

/// \brief The four uniforms of Philox4x32-10 (key = seed) for `stream` at draw index `draw`:
/// counters (stream, 2 draw + half), each 128-bit block giving two doubles from its 64-bit
/// halves. PhiloxSource fills its table with these, and the sweep can call it in place.
KOKKOS_INLINE_FUNCTION void philox_uniforms(std::uint64_t seed, std::uint64_t stream, std::uint64_t draw,
                                            double u[4]) {
  const std::uint32_t k0 = static_cast<std::uint32_t>(seed), k1 = static_cast<std::uint32_t>(seed >> 32);
  Block128 r[2];
  for (int half = 0; half < 2; ++half) {
    const std::uint64_t c = 2 * draw + static_cast<std::uint64_t>(half);
    r[half] = Block128{{static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32),
                        static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(c >> 32)}};
  }
  philox4x32_10_pair(r[0], r[1], k0, k1);  // the two blocks of counters 2 draw, 2 draw + 1
  for (int half = 0; half < 2; ++half) {
    u[2 * half + 0] = to_unit_double((std::uint64_t(r[half].w[1]) << 32) | r[half].w[0]);
    u[2 * half + 1] = to_unit_double((std::uint64_t(r[half].w[3]) << 32) | r[half].w[2]);
  }
}

/// \brief One batch to fill: stream ids and the table, in memory space MS.
template <class MS>
struct Batch {
  using memory_space = MS;
  StreamIds<MS> streams;
  UniformTable<MS> u;
};
/// \brief A batch in any memory space a backend of this build keeps its models in (the device's
/// or the host's in a CUDA build with host backends).
using AnyBatch = PerMemorySpace<Batch>;

/// \brief Host-side handle of a generator. (Virtual dispatch happens once per batch, on the host;
/// kernels only see the concrete generator.)
class UniformSource {
public:
  virtual ~UniformSource() = default;
  /// \brief Name used in decks and outputs ("philox", "aes-ctr", "mt-aes").
  [[nodiscard]] virtual std::string name() const = 0;
  /// \brief Fill u(i, 0..3) with the uniforms of stream streams(i) at draw index `draw`, on
  /// the backend's instance (asynchronous: fence it before reading u elsewhere); the same bits
  /// on every backend. The batch's memory space must be one the backend reaches.
  /// Sources may be stateful (mt-aes) and then require draws to be requested in increasing order
  /// (a repeated draw index is answered identically).
  virtual void fill(const Backend& backend, std::uint64_t draw, const AnyBatch& batch) = 0;
  /// \brief The same for a table `u` and ids `streams` in one memory space.
  template <class Ids, class Table>
  void fill(const Backend& backend, std::uint64_t draw, const Ids& streams, const Table& u) {
    using MS = typename Table::memory_space;
    fill(backend, draw, AnyBatch(Batch<MS>{StreamIds<MS>(streams), u}));
  }
  /// \brief The same on the default backend.
  void fill(std::uint64_t draw, StreamIds<> streams, UniformTable<> u) { fill(Backend{}, draw, streams, u); }
};

/// (The generators a deck can name, Philox and the AES ones, are listed by rng/registry.hpp: this
/// header knows no generator family but its own.)

/// \brief u(i, 0..3) = the Philox uniforms of stream streams(i) at draw `draw` under key `seed`,
/// on `space` (PhiloxSource::fill; any execution space that reaches the views).
template <class ExecutionSpace, class MS>
void philox_fill(const ExecutionSpace& space, std::uint64_t seed, std::uint64_t draw, StreamIds<MS> streams,
                 UniformTable<MS> u) {
  static_assert(Kokkos::SpaceAccessibility<ExecutionSpace, MS>::accessible);
  Kokkos::parallel_for(
      "nacre::rng::philox_fill", Kokkos::RangePolicy<ExecutionSpace>(space, 0, streams.extent(0)),
      KOKKOS_LAMBDA(const std::size_t i) {
        double r[4];
        philox_uniforms(seed, streams(i), draw, r);
        for (int k = 0; k < 4; ++k) u(i, k) = r[k];
      });
}

/// \brief Philox4x32-10: key = seed, counter = (stream, 2*draw + half); each 128-bit block gives
/// two doubles from its two 64-bit halves.
class PhiloxSource final : public UniformSource {
public:
  explicit PhiloxSource(std::uint64_t seed) : seed_(seed) {}
  [[nodiscard]] std::string name() const override { return "philox"; }
  using UniformSource::fill;
  void fill(const Backend& backend, std::uint64_t draw, const AnyBatch& batch) override;
  /// \brief The key (for callers that generate the same numbers in place: philox_uniforms).
  [[nodiscard]] std::uint64_t seed() const { return seed_; }

private:
  std::uint64_t seed_;
};

}  // namespace nacre::rng
