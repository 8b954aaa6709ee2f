#pragma once
/// \file
/// \brief Random-number generators built on nacre's bitsliced AES-128 (see aes/aes128.hpp).
#include <nacre/rng/uniform_source.hpp>

#include <cstdint>
#include <memory>

namespace nacre::aes {

/// \brief AES-CTR: the block for (stream, counter) is AES_key(stream || counter), key from seed.
[[nodiscard]] std::unique_ptr<rng::UniformSource> make_aes_ctr_source(std::uint64_t seed);
/// \brief The dissertation's pipeline: per-stream Mersenne Twister output whitened by AES-ECB.
[[nodiscard]] std::unique_ptr<rng::UniformSource> make_mt_aes_source(std::uint64_t seed);

}  // namespace nacre::aes
