// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Random-number generators built on nacre's bitsliced AES-128 (see aes/aes128.hpp).
///
/// Both fill the generator interface of rng/uniform_source.hpp: for stream s (a brick's original
/// id) and draw index d they produce two 128-bit blocks (half h = 0, 1); block h gives
/// u(., 2h) and u(., 2h+1) from its low and high 64-bit halves (little-endian) through
/// rng::to_unit_double (the top 53 bits times 2^-53: exact and unbiased in [0, 1)).
#include <nacre/aes/aes128.hpp>
#include <nacre/aes/bitsliced_kernel.hpp>
#include <nacre/rng/uniform_source.hpp>

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

namespace nacre::aes {

namespace detail {
template <class Variant>
struct MasksOf;
template <class... E>
struct MasksOf<std::variant<E...>> {
  using type = std::tuple<Kokkos::View<const exec_lane_t<E>*, MemOf<E>>...>;
};
}  // namespace detail
/// \brief The round-key masks on every enabled backend (its lane type, in its memory space):
/// element space_index_v<E> serves execution space E; a few KiB each, made once per generator.
using SpaceMasks = typename detail::MasksOf<AnySpace>::type;

/// \brief AES-CTR: the block for (stream, counter) is AES_key(stream || counter), key from seed.
[[nodiscard]] std::unique_ptr<rng::UniformSource> make_aes_ctr_source(std::uint64_t seed);
/// \brief The dissertation's pipeline: per-stream Mersenne Twister output whitened by AES-ECB.
[[nodiscard]] std::unique_ptr<rng::UniformSource> make_mt_aes_source(std::uint64_t seed);

/// \brief Raw generator output: bits(i, 2h) / bits(i, 2h+1) = low / high 64 bits of block h.
template <class MS = MemSpace>
using BitsTable = Kokkos::View<std::uint64_t* [4], Kokkos::LayoutLeft, MS>;

/// \brief SplitMix64 finaliser (Steele, Lea, Flood 2014), used to derive keys from seeds.
[[nodiscard]] constexpr std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// \brief The AES-CTR key of a seed: k0 = splitmix64(seed ^ "aes-ctr\0" as a little-endian
/// 64-bit tag), k1 = splitmix64(k0); key bytes 0..7 = k0, 8..15 = k1 (little-endian). Any seed,
/// 0 included, gives a full-entropy-looking key; different tags separate the two generators.
[[nodiscard]] Key128 aes_ctr_key(std::uint64_t seed);
/// \brief The MT+AES whitening key: as aes_ctr_key with the tag "mt-aes\0\0".
[[nodiscard]] Key128 mt_aes_key(std::uint64_t seed);

/// \brief AES-CTR generator. Block (s, d, h) = AES_k(P) with plaintext bytes 0..7 = s and bytes
/// 8..15 = 2d + h (little-endian), k = aes_ctr_key(seed). Stateless: any (stream, draw) order.
class AesCtrSource final : public rng::UniformSource {
public:
  explicit AesCtrSource(std::uint64_t seed);
  [[nodiscard]] std::string name() const override { return "aes-ctr"; }
  using rng::UniformSource::fill;
  void fill(const Backend& backend, std::uint64_t draw, const rng::AnyBatch& batch) override;
  /// \brief The raw 128-bit blocks behind fill (tests, dieharder).
  void fill_bits(std::uint64_t draw, rng::StreamIds<> streams, BitsTable<> bits);

private:
  SpaceMasks masks_;
};

/// \brief The dissertation's pipeline: Mersenne Twister output whitened by AES-ECB.
///
/// kMtStreams MT19937 generators (a fixed number, independent of threads and backend); MT m is
/// seeded with std::seed_seq{lo32(seed), hi32(seed), m, 0x6d74} (seed_seq and mt19937 are fully
/// specified by the C++ standard, so the sequence is portable). Every MT advances by exactly 8
/// outputs per draw index, whatever the batch: at draw d, MT m's outputs 8d .. 8d+7 form two
/// plaintext blocks M(m, d, h) (words 4h .. 4h+3, little-endian). Brick stream s uses MT
/// m = s mod kMtStreams and q = s div kMtStreams; its block is AES_k(M(m, d, h) ^ (q << 64))
/// (q XORed into the high 64 bits, so bricks sharing an MT get distinct plaintexts),
/// k = mt_aes_key(seed). The result is a function of (seed, s, d) only.
/// Stateful: draws must come in non-decreasing order (a repeated draw is answered identically
/// from the cached MT block table; skipping draws costs 8 MT outputs per skipped draw and MT).
class MtAesSource final : public rng::UniformSource {
public:
  static constexpr int kMtStreams = 1024;
  explicit MtAesSource(std::uint64_t seed);
  [[nodiscard]] std::string name() const override { return "mt-aes"; }
  using rng::UniformSource::fill;
  void fill(const Backend& backend, std::uint64_t draw, const rng::AnyBatch& batch) override;
  /// \brief The raw AES output behind fill.
  void fill_bits(std::uint64_t draw, rng::StreamIds<> streams, BitsTable<> bits);
  /// \brief The MT plaintexts before whitening (with the q tweak): raw MT for streams < 1024.
  void fill_plain_bits(std::uint64_t draw, rng::StreamIds<> streams, BitsTable<> bits);

private:
  void advance_to(std::uint64_t draw);
  SpaceMasks masks_;
  std::vector<std::mt19937> mt_;
  /// table_, uploaded first when the host's table moved since (a device build; else the same view)
  const Kokkos::View<std::uint64_t*, MemSpace>& device_table();
  // kMtStreams x 4 (2 blocks of 2 x 64 bits), filled on the host; table_ is its copy in the
  // default memory space (the same view in a host build), which backends on the host do not
  // read, so a host backend's run of a device build never uploads it
  Kokkos::View<std::uint64_t*, Kokkos::HostSpace> table_host_;
  Kokkos::View<std::uint64_t*, MemSpace> table_;
  bool device_stale_ = false;
  bool have_draw_ = false;
  std::uint64_t last_draw_ = 0;
};

}  // namespace nacre::aes
