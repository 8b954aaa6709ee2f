// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/rng/aes_sources.hpp>
#include <nacre/rng/on_batch.hpp>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace nacre::aes {
namespace {

constexpr std::uint64_t kTagCtr = 0x0000'7274'632d'7365'61ull;  // "aes-ctr\0" (little-endian)
constexpr std::uint64_t kTagMt = 0x0000'7365'612d'746dull;      // "mt-aes\0\0"

Key128 key_from(std::uint64_t seed, std::uint64_t tag) {
  const std::uint64_t k0 = splitmix64(seed ^ tag);
  const std::uint64_t k1 = splitmix64(k0);
  Key128 k{};
  for (int b = 0; b < 8; ++b) {
    k.bytes[b] = static_cast<std::uint8_t>(k0 >> (8 * b));
    k.bytes[8 + b] = static_cast<std::uint8_t>(k1 >> (8 * b));
  }
  return k;
}

/// The masks of every enabled space, made from one key schedule.
template <std::size_t... I>
SpaceMasks make_space_masks(const RoundKeys& rk, std::index_sequence<I...>) {
  return SpaceMasks{detail::make_masks(std::variant_alternative_t<I, AnySpace>(), rk)...};
}
SpaceMasks make_space_masks(const Key128& key) {
  return make_space_masks(expand_key(key), std::make_index_sequence<std::variant_size_v<AnySpace>>{});
}
/// Space E's masks.
template <class E>
const auto& masks_for(const SpaceMasks& m) {
  return std::get<space_index_v<E>>(m);
}

/// Plaintext of AES-CTR: block g = 2 i + h of the batch is (streams(i), 2 draw + h).
template <class MS = MemSpace>
struct CtrPlain {
  rng::StreamIds<MS> streams;
  std::uint64_t draw;
  template <class Member, class Lane>
  KOKKOS_INLINE_FUNCTION void operator()(const Member& team, std::size_t first, int nb, int chunk_blocks,
                                         Lane* buf) const {
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, chunk_blocks), [&](const int k) {
      std::uint64_t lo = 0, hi = 0;
      if (k < nb) {  // public: padding blocks are zero
        const std::size_t g = first + std::size_t(k);
        lo = streams(g / 2);
        hi = 2 * draw + (g & 1);
      }
      detail::set_block_u64(buf, std::size_t(k), lo, hi);
    });
  }
};

/// Plaintext of MT+AES: M(m, d, h) ^ (q << 64) with m = s mod kMtStreams, q = s div kMtStreams.
template <class MS = MemSpace>
struct MtPlain {
  rng::StreamIds<MS> streams;
  Kokkos::View<const std::uint64_t*, MS> table;
  template <class Member, class Lane>
  KOKKOS_INLINE_FUNCTION void operator()(const Member& team, std::size_t first, int nb, int chunk_blocks,
                                         Lane* buf) const {
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, chunk_blocks), [&](const int k) {
      std::uint64_t lo = 0, hi = 0;
      if (k < nb) {
        const std::size_t g = first + std::size_t(k);
        const std::uint64_t s = streams(g / 2);
        const std::uint64_t m = s % MtAesSource::kMtStreams;
        const std::uint64_t q = s / MtAesSource::kMtStreams;
        lo = table(4 * m + 2 * (g & 1));
        hi = table(4 * m + 2 * (g & 1) + 1) ^ q;
      }
      detail::set_block_u64(buf, std::size_t(k), lo, hi);
    });
  }
};

/// Sink: block g = 2 i + h -> out(i, 2h), out(i, 2h+1), as doubles or raw bits.
template <class Out>
struct TableSink {
  Out out;
  template <class Member, class Lane>
  KOKKOS_INLINE_FUNCTION void operator()(const Member& team, std::size_t first, int nb, const Lane* buf) const {
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, nb), [&](const int k) {
      const std::size_t g = first + std::size_t(k);
      std::uint64_t lo, hi;
      detail::get_block_u64(buf, std::size_t(k), lo, hi);
      const std::size_t i = g / 2;
      const int c = 2 * int(g & 1);
      if constexpr (std::is_same_v<typename Out::non_const_value_type, double>) {
        out(i, c) = rng::to_unit_double(lo);
        out(i, c + 1) = rng::to_unit_double(hi);
      } else {
        out(i, c) = lo;
        out(i, c + 1) = hi;
      }
    });
  }
};

/// Identity "cipher" sink for fill_plain_bits: copy the plaintext as produced.
struct PlainCopy {
  MtPlain<> plain;
  BitsTable<> out;
  KOKKOS_INLINE_FUNCTION void operator()(const std::size_t g) const {
    const std::uint64_t s = plain.streams(g / 2);
    const std::uint64_t m = s % MtAesSource::kMtStreams;
    const std::uint64_t q = s / MtAesSource::kMtStreams;
    const int c = 2 * int(g & 1);
    out(g / 2, c) = plain.table(4 * m + 2 * (g & 1));
    out(g / 2, c + 1) = plain.table(4 * m + 2 * (g & 1) + 1) ^ q;
  }
};

void check_extents(const char* who, std::size_t nstreams, std::size_t nrows) {
  if (nrows < nstreams)
    throw std::invalid_argument(std::string(who) + ": output table has " +
                                std::to_string(nrows) + " rows for " + std::to_string(nstreams) +
                                " streams");
}

}  // namespace

Key128 aes_ctr_key(std::uint64_t seed) { return key_from(seed, kTagCtr); }
Key128 mt_aes_key(std::uint64_t seed) { return key_from(seed, kTagMt); }

// ------------------------------------------------------------------------------------ AES-CTR

AesCtrSource::AesCtrSource(std::uint64_t seed) {
  Kokkos::Profiling::ScopedRegion region("nacre::aes::key_expansion");
  masks_ = make_space_masks(aes_ctr_key(seed));
}

void AesCtrSource::fill(const Backend& backend, std::uint64_t draw, const rng::AnyBatch& batch) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::aes_ctr");
  rng::on_batch(backend, batch, [&](const auto& space, const auto& b) {
    using E = std::decay_t<decltype(space)>;
    using MS = typename std::decay_t<decltype(b)>::memory_space;
    check_extents("aes-ctr", b.streams.extent(0), b.u.extent(0));
    detail::run_bitsliced(space, "nacre::rng::aes_ctr_fill", masks_for<E>(masks_), 2 * b.streams.extent(0),
                          CtrPlain<MS>{b.streams, draw}, TableSink<rng::UniformTable<MS>>{b.u});
  });
}

void AesCtrSource::fill_bits(std::uint64_t draw, rng::StreamIds<> streams, BitsTable<> bits) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::aes_ctr");
  check_extents("aes-ctr", streams.extent(0), bits.extent(0));
  detail::run_bitsliced(ExecSpace(), "nacre::rng::aes_ctr_bits", masks_for<ExecSpace>(masks_), 2 * streams.extent(0),
                        CtrPlain<>{streams, draw}, TableSink<BitsTable<>>{bits});
}

std::unique_ptr<rng::UniformSource> make_aes_ctr_source(std::uint64_t seed) {
  return std::make_unique<AesCtrSource>(seed);
}

// ------------------------------------------------------------------------------------ MT + AES

MtAesSource::MtAesSource(std::uint64_t seed)
    : table_host_("nacre::rng::mt_aes_table_host", 4 * kMtStreams),
      table_(Kokkos::create_mirror_view(Kokkos::WithoutInitializing, MemSpace(), table_host_)) {
  Kokkos::Profiling::ScopedRegion region("nacre::aes::key_expansion");
  masks_ = make_space_masks(mt_aes_key(seed));
  mt_.reserve(kMtStreams);
  for (int m = 0; m < kMtStreams; ++m) {
    std::seed_seq seq{std::uint32_t(seed), std::uint32_t(seed >> 32), std::uint32_t(m),
                      std::uint32_t(0x6d74)};
    mt_.emplace_back(seq);
  }
}

void MtAesSource::advance_to(std::uint64_t draw) {
  if (have_draw_ && draw == last_draw_) return;  // repeated draw: same table
  if (have_draw_ && draw < last_draw_)
    throw std::logic_error("mt-aes: draw " + std::to_string(draw) + " requested after draw " +
                           std::to_string(last_draw_) +
                           " (this stateful generator needs non-decreasing draw indices)");
  Kokkos::Profiling::ScopedRegion region("nacre::rng::mt_advance");
  const std::uint64_t skip = have_draw_ ? draw - last_draw_ - 1 : draw;
  std::mt19937* mt = mt_.data();
  std::uint64_t* t = table_host_.data();
  // Each MT is independent and advanced by a fixed amount: the table does not depend on the
  // thread count or on which host thread handles which MT.
  Kokkos::parallel_for(
      "nacre::rng::mt_advance",
      Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace>(0, kMtStreams), [=](const int m) {
        if (skip) mt[m].discard(8 * skip);
        std::uint64_t w[8];
        for (auto& x : w) x = mt[m]();
        for (int k = 0; k < 4; ++k) t[4 * m + k] = w[2 * k] | (w[2 * k + 1] << 32);
      });
  Kokkos::DefaultHostExecutionSpace().fence();
  device_stale_ = table_.data() != table_host_.data();  // uploaded when a default-memory fill needs it
  have_draw_ = true;
  last_draw_ = draw;
}

const Kokkos::View<std::uint64_t*, MemSpace>& MtAesSource::device_table() {
  if (device_stale_) Kokkos::deep_copy(table_, table_host_);  // (a fence: the kernels that read it follow)
  device_stale_ = false;
  return table_;
}

void MtAesSource::fill(const Backend& backend, std::uint64_t draw, const rng::AnyBatch& batch) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::mt_aes");
  rng::on_batch(backend, batch, [&](const auto& space, const auto& b) {
    using E = std::decay_t<decltype(space)>;
    using MS = typename std::decay_t<decltype(b)>::memory_space;
    static_assert(std::is_same_v<MS, MemSpace> || std::is_same_v<MS, Kokkos::HostSpace>);
    check_extents("mt-aes", b.streams.extent(0), b.u.extent(0));
    advance_to(draw);  // host MT state
    Kokkos::View<const std::uint64_t*, MS> table;
    if constexpr (std::is_same_v<MS, MemSpace>)
      table = device_table();
    else
      table = table_host_;  // a host backend reads the host's table: nothing is uploaded
    detail::run_bitsliced(space, "nacre::rng::mt_aes_fill", masks_for<E>(masks_), 2 * b.streams.extent(0),
                          MtPlain<MS>{b.streams, table}, TableSink<rng::UniformTable<MS>>{b.u});
  });
}

void MtAesSource::fill_bits(std::uint64_t draw, rng::StreamIds<> streams, BitsTable<> bits) {
  Kokkos::Profiling::ScopedRegion region("nacre::rng::mt_aes");
  check_extents("mt-aes", streams.extent(0), bits.extent(0));
  advance_to(draw);
  detail::run_bitsliced(ExecSpace(), "nacre::rng::mt_aes_bits", masks_for<ExecSpace>(masks_), 2 * streams.extent(0),
                        MtPlain<>{streams, device_table()}, TableSink<BitsTable<>>{bits});
}

void MtAesSource::fill_plain_bits(std::uint64_t draw, rng::StreamIds<> streams,
                                  BitsTable<> bits) {
  check_extents("mt-aes", streams.extent(0), bits.extent(0));
  advance_to(draw);
  Kokkos::parallel_for("nacre::rng::mt_plain_bits", Kokkos::RangePolicy<ExecSpace>(0, 2 * streams.extent(0)),
                       PlainCopy{MtPlain<>{streams, device_table()}, bits});
}

std::unique_ptr<rng::UniformSource> make_mt_aes_source(std::uint64_t seed) {
  return std::make_unique<MtAesSource>(seed);
}

}  // namespace nacre::aes
