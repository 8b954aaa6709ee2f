// SPDX-License-Identifier: BSD-3-Clause
// The generator table of rng/registry.hpp: the one place that knows every generator family.
#include <nacre/rng/aes_sources.hpp>
#include <nacre/rng/registry.hpp>

#include <stdexcept>

namespace nacre::rng {

std::unique_ptr<UniformSource> make_uniform_source(std::string_view kind, std::uint64_t seed) {
  if (kind == "philox") return std::make_unique<PhiloxSource>(seed);
  if (kind == "aes-ctr") return aes::make_aes_ctr_source(seed);
  if (kind == "mt-aes") return aes::make_mt_aes_source(seed);
  throw std::invalid_argument("unknown random generator '" + std::string(kind) + "', expected one of " +
                              uniform_source_kinds());
}

}  // namespace nacre::rng
