// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The Kokkos team kernel around the bitsliced AES core (aes/bitsliced.hpp).
///
/// One team processes chunks of team_size * kBlocks<W> blocks:
///   1. once per team, the 11 x 128 round-key masks are copied into team scratch (the
///      dissertation's "round keys in shared memory");
///   2. per chunk, the team's threads copy the chunk's input into scratch with consecutive threads
///      touching consecutive words (contiguous/coalesced global reads; the Source may instead
///      generate the plaintext, e.g. counter blocks), barrier;
///   3. each thread bitslices its kBlocks<W> blocks out of scratch, encrypts and writes back;
///   4. barrier, the team stores the chunk contiguously (or the Sink converts it, e.g. to
///      doubles).
/// The last chunk is zero padded in scratch; the padding is encrypted and dropped. Sources and
/// sinks are functors: src(team, first_block, n_blocks, lanes) and sink(team, first_block,
/// n_blocks, lanes), both team-collective, lanes = the scratch chunk (P lanes per block).
#include <nacre/aes/bitsliced.hpp>

#include <cstddef>
#include <type_traits>

namespace nacre::aes::detail {

/// \brief Word of the bitsliced state for an execution space (see the layout discussion in
/// bitsliced.hpp): 32-bit words on GPUs, the widest SIMD vector word on CPUs.
template <class ExecSpace>
struct ExecWord {
  /// Host execution spaces get the SIMD vector word and one thread per team; device spaces
  /// (CUDA, HIP, SYCL) plain 32-bit words and 64-thread teams that share scratch.
  static constexpr bool host = Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible;
  using type = std::conditional_t<host, bitslice::HostWord, std::uint32_t>;
  static constexpr int team_size = host ? 1 : 64;
};

/// \brief Sources and sinks that are plain host memory say so with direct(first_block) (a byte
/// pointer to the chunk): with a SIMD host word and one thread per team the kernel then encrypts
/// full chunks straight from the input to the output, without the scratch copies.
template <class T, class = void>
struct has_direct : std::false_type {};
template <class T>
struct has_direct<T, std::void_t<decltype(&T::direct)>> : std::true_type {};

template <class ExecSpace>
using exec_lane_t = typename bitslice::WordTraits<typename ExecWord<ExecSpace>::type>::lane;

template <class ExecSpace, class Source, class Sink>
struct BitslicedTeamKernel {
  using Word = typename ExecWord<ExecSpace>::type;
  using Lane = typename bitslice::WordTraits<Word>::lane;
  using member_type = typename Kokkos::TeamPolicy<ExecSpace>::member_type;
  static constexpr int kB = bitslice::kBlocks<Word>;
  static constexpr int kP = bitslice::kLanesPerBlock<Word>;

  Kokkos::View<const Lane*, typename ExecSpace::memory_space> masks;
  Source src;
  Sink sink;
  std::size_t nblocks;
  std::size_t nchunks;
  int team_size;

  static std::size_t scratch_bytes(int team_size) {
    return bitslice::kMaskCount * sizeof(Lane) + std::size_t(team_size) * kB * 16 + 256;
  }

  KOKKOS_FUNCTION void operator()(const member_type& team) const {
    const int chunk_blocks = team_size * kB;
    Lane* smask = static_cast<Lane*>(
        team.team_scratch(0).get_shmem_aligned(bitslice::kMaskCount * sizeof(Lane), 64));
    Lane* sbuf = static_cast<Lane*>(
        team.team_scratch(0).get_shmem_aligned(std::size_t(chunk_blocks) * 16, 64));
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, bitslice::kMaskCount),
                         [&](const int i) { smask[i] = masks(i); });
    team.team_barrier();
    // Each team takes a contiguous range of chunks, so a CPU thread streams through memory in
    // order (the hardware prefetchers follow it; a stride of league_size chunks defeated them).
    const std::size_t per_team = (nchunks + std::size_t(team.league_size()) - 1) /
                                 std::size_t(team.league_size());
    const std::size_t c_begin = std::size_t(team.league_rank()) * per_team;
    const std::size_t c_end = c_begin + per_team < nchunks ? c_begin + per_team : nchunks;
    for (std::size_t chunk = c_begin; chunk < c_end; ++chunk) {
      const std::size_t first = chunk * std::size_t(chunk_blocks);
      const std::size_t left = nblocks - first;
      const int nb = left < std::size_t(chunk_blocks) ? int(left) : chunk_blocks;
      if constexpr (ExecWord<ExecSpace>::host && bitslice::kDirectIO<Word> &&
                    has_direct<Source>::value && has_direct<Sink>::value) {
        if (team_size == 1 && nb == chunk_blocks) {  // public: sizes only
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__CUDACC__) && !defined(__HIPCC__)
          if (chunk + 1 < c_end) {  // the next chunk's input towards L2 while this one runs
            const unsigned char* next = src.direct(first + std::size_t(chunk_blocks));
            for (int line = 0; line < chunk_blocks * 16; line += 64)
              __builtin_prefetch(next + line, 0, 2);
          }
#endif
          bitslice::encrypt_blocks_io<Word>(smask, src.direct(first), sink.direct(first));
          continue;
        }
      }
      src(team, first, nb, chunk_blocks, sbuf);
      team.team_barrier();
      if (team.team_rank() * kB < nb) {  // public: skip threads holding only padding
        bitslice::encrypt_blocks<Word>(smask, sbuf + std::size_t(team.team_rank()) * kB * kP);
      }
      team.team_barrier();
      sink(team, first, nb, sbuf);
      team.team_barrier();
    }
  }
};

/// \brief Run the bitsliced AES with round keys rk over nblocks blocks produced by src and
/// consumed by sink (see the file comment). masks: the device copy of the round-key masks.
template <class ExecSpace, class Source, class Sink>
void run_bitsliced(const ExecSpace& space, const char* label,
                   Kokkos::View<const exec_lane_t<ExecSpace>*, typename ExecSpace::memory_space>
                       masks,
                   std::size_t nblocks, const Source& src, const Sink& sink) {
  if (nblocks == 0) return;
  using K = BitslicedTeamKernel<ExecSpace, Source, Sink>;
  const int team_size = ExecWord<ExecSpace>::team_size;
  const std::size_t chunk_blocks = std::size_t(team_size) * K::kB;
  const std::size_t nchunks = (nblocks + chunk_blocks - 1) / chunk_blocks;
  // Enough teams to fill the machine several times over; each team reuses its scratch keys
  // for all the chunks it takes.
  // (A multiple of the thread count, so statically scheduled CPU teams get equal shares.)
  std::size_t max_league = std::size_t(space.concurrency()) / std::size_t(team_size) * 8;
  if (max_league == 0) max_league = 1;
  const int league = int(nchunks < max_league ? nchunks : max_league);
  Kokkos::TeamPolicy<ExecSpace> policy(space, league, team_size);
  policy.set_scratch_size(0, Kokkos::PerTeam(K::scratch_bytes(team_size)));
  K kernel{masks, src, sink, nblocks, nchunks, team_size};
  Kokkos::parallel_for(label, policy, kernel);
}

/// \brief Round-key masks for an execution space, on its memory space.
template <class ExecSpace>
Kokkos::View<const exec_lane_t<ExecSpace>*, typename ExecSpace::memory_space> make_masks(
    const ExecSpace& space, const RoundKeys& rk) {
  using Lane = exec_lane_t<ExecSpace>;
  Kokkos::View<Lane*, typename ExecSpace::memory_space> d(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "nacre::aes::round_key_masks"),
      bitslice::kMaskCount);
  auto h = Kokkos::create_mirror_view(d);
  bitslice::round_key_masks<Lane>(rk, h.data());
  Kokkos::deep_copy(space, d, h);
  space.fence();  // h is a temporary
  return d;
}

/// \brief Little-endian 64-bit halves of block k of a scratch chunk (any lane width).
template <class Lane>
KOKKOS_INLINE_FUNCTION void get_block_u64(const Lane* buf, std::size_t k, std::uint64_t& lo,
                                          std::uint64_t& hi) {
  if constexpr (sizeof(Lane) == 8) {
    lo = buf[2 * k];
    hi = buf[2 * k + 1];
  } else {
    lo = std::uint64_t(buf[4 * k]) | (std::uint64_t(buf[4 * k + 1]) << 32);
    hi = std::uint64_t(buf[4 * k + 2]) | (std::uint64_t(buf[4 * k + 3]) << 32);
  }
}

template <class Lane>
KOKKOS_INLINE_FUNCTION void set_block_u64(Lane* buf, std::size_t k, std::uint64_t lo,
                                          std::uint64_t hi) {
  if constexpr (sizeof(Lane) == 8) {
    buf[2 * k] = lo;
    buf[2 * k + 1] = hi;
  } else {
    buf[4 * k] = Lane(lo);
    buf[4 * k + 1] = Lane(lo >> 32);
    buf[4 * k + 2] = Lane(hi);
    buf[4 * k + 3] = Lane(hi >> 32);
  }
}

}  // namespace nacre::aes::detail
