// SPDX-License-Identifier: BSD-3-Clause
#include <nacre/aes/aes128.hpp>
#include <nacre/aes/bitsliced_kernel.hpp>

#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>

static_assert(std::endian::native == std::endian::little,
              "nacre's AES packs bytes into little-endian lanes");

namespace nacre::aes {
namespace {

template <class L>
KOKKOS_INLINE_FUNCTION L load_lane(const std::uint8_t* p, bool aligned) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__) || defined(__SYCL_DEVICE_ONLY__)
  if (aligned) return *reinterpret_cast<const L*>(p);
  L v = 0;
  for (int k = 0; k < int(sizeof(L)); ++k) v |= L(p[k]) << (8 * k);
  return v;
#else
  (void)aligned;
  L v;
  std::memcpy(&v, p, sizeof v);
  return v;
#endif
}

template <class L>
KOKKOS_INLINE_FUNCTION void store_lane(std::uint8_t* p, L v, bool aligned) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__) || defined(__SYCL_DEVICE_ONLY__)
  if (aligned) {
    *reinterpret_cast<L*>(p) = v;
    return;
  }
  for (int k = 0; k < int(sizeof(L)); ++k) p[k] = std::uint8_t(v >> (8 * k));
#else
  (void)aligned;
  std::memcpy(p, &v, sizeof v);
#endif
}

/// Source: contiguous, team-strided copy of the chunk from global memory into scratch.
template <class MS, class L>
struct EcbLoad {
  Kokkos::View<const std::uint8_t*, MS> in;
  bool aligned;
  template <class Member>
  KOKKOS_INLINE_FUNCTION void operator()(const Member& team, std::size_t first, int nb,
                                         int chunk_blocks, L* buf) const {
    constexpr int per_block = 16 / int(sizeof(L));
    const int n = nb * per_block;
    const std::uint8_t* p = in.data() + first * 16;
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, n), [&](const int i) {
      buf[i] = load_lane<L>(p + std::size_t(i) * sizeof(L), aligned);
    });
    // Zero padding of a partial last chunk (its ciphertext is discarded).
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, n, chunk_blocks * per_block),
                         [&](const int i) { buf[i] = L(0); });
  }
  /// The chunk starting at block `first`, for the kernel's direct (unstaged) host path.
  const unsigned char* direct(std::size_t first) const { return in.data() + first * 16; }
};

/// Sink: contiguous copy of the encrypted chunk from scratch to global memory.
template <class MS, class L>
struct EcbStore {
  Kokkos::View<std::uint8_t*, MS> out;
  bool aligned;
  template <class Member>
  KOKKOS_INLINE_FUNCTION void operator()(const Member& team, std::size_t first, int nb,
                                         const L* buf) const {
    constexpr int per_block = 16 / int(sizeof(L));
    std::uint8_t* p = out.data() + first * 16;
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, nb * per_block), [&](const int i) {
      store_lane<L>(p + std::size_t(i) * sizeof(L), buf[i], aligned);
    });
  }
  /// The chunk starting at block `first`, for the kernel's direct (unstaged) host path.
  unsigned char* direct(std::size_t first) const { return out.data() + first * 16; }
};

}  // namespace

template <class Space>
void aes128_ecb_encrypt(const Space& space, const Key128& key,
                        Kokkos::View<const std::uint8_t*, typename Space::memory_space> in,
                        Kokkos::View<std::uint8_t*, typename Space::memory_space> out) {
  Kokkos::Profiling::ScopedRegion region("nacre::aes::ecb_encrypt");
  const std::size_t n = in.extent(0);
  if (n % 16 != 0)
    throw std::invalid_argument("nacre::aes::aes128_ecb_encrypt: input length " +
                                std::to_string(n) +
                                " bytes is not a multiple of the 16-byte AES block");
  if (out.extent(0) != n)
    throw std::invalid_argument("nacre::aes::aes128_ecb_encrypt: output length " +
                                std::to_string(out.extent(0)) + " differs from input length " +
                                std::to_string(n));
  if (n == 0) return;
  const auto ib = reinterpret_cast<std::uintptr_t>(in.data());
  const auto ob = reinterpret_cast<std::uintptr_t>(out.data());
  if (ib != ob && ib < ob + n && ob < ib + n)
    throw std::invalid_argument(
        "nacre::aes::aes128_ecb_encrypt: input and output overlap (only identical or disjoint "
        "buffers are supported)");

  using L = detail::exec_lane_t<Space>;
  using MS = typename Space::memory_space;
  Kokkos::View<const L*, MS> masks;
  {
    Kokkos::Profiling::ScopedRegion kregion("nacre::aes::key_expansion");
    masks = detail::make_masks(space, expand_key(key));
  }
  const EcbLoad<MS, L> src{in, ib % sizeof(L) == 0};
  const EcbStore<MS, L> sink{out, ob % sizeof(L) == 0};
  detail::run_bitsliced(space, "nacre::aes::ecb_encrypt", masks, n / 16, src, sink);
}

template <class Space>
std::string aes128_layout_description() {
  using W = typename detail::ExecWord<Space>::type;
  return std::string(bitslice::WordTraits<W>::name) + ", " +
         std::to_string(bitslice::kBlocks<W>) + " blocks/thread, team size " +
         std::to_string(detail::ExecWord<Space>::team_size) + ", transposition " +
         (bitslice::kGfniTranspose<W> ? "GFNI + vpermt2b (x86)" : "SWAPMOVE (portable)") +
         (detail::ExecWord<Space>::host && bitslice::kDirectIO<W> ? ", unstaged host I/O" : "");
}

void aes128_ecb_encrypt(const Key128& key, Kokkos::View<const std::uint8_t*, MemSpace> in,
                        Kokkos::View<std::uint8_t*, MemSpace> out) {
  aes128_ecb_encrypt(ExecSpace(), key, in, out);
}

void aes128_ecb_encrypt(const Backend& backend, const Key128& key, Kokkos::View<const std::uint8_t*, MemSpace> in,
                        Kokkos::View<std::uint8_t*, MemSpace> out) {
  backend.visit_in<MemSpace>([&](const auto& space) { aes128_ecb_encrypt(space, key, in, out); });
}

void aes128_ecb_encrypt(const Key128& key, Kokkos::View<std::uint8_t*, MemSpace> inout) {
  aes128_ecb_encrypt(ExecSpace(), key, inout, inout);
}

template void aes128_ecb_encrypt<ExecSpace>(const ExecSpace&, const Key128&,
                                            Kokkos::View<const std::uint8_t*, ExecSpace::memory_space>,
                                            Kokkos::View<std::uint8_t*, ExecSpace::memory_space>);
template std::string aes128_layout_description<ExecSpace>();
#if defined(KOKKOS_ENABLE_CUDA) || defined(KOKKOS_ENABLE_HIP) || defined(KOKKOS_ENABLE_SYCL)
template void aes128_ecb_encrypt<Kokkos::DefaultHostExecutionSpace>(
    const Kokkos::DefaultHostExecutionSpace&, const Key128&,
    Kokkos::View<const std::uint8_t*, Kokkos::HostSpace>, Kokkos::View<std::uint8_t*, Kokkos::HostSpace>);
template std::string aes128_layout_description<Kokkos::DefaultHostExecutionSpace>();
#endif

}  // namespace nacre::aes
