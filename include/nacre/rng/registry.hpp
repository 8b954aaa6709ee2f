// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The random generators a deck can name ([random] generator), in one table: Philox
/// (rng/philox.hpp) and the AES family (rng/aes_sources.hpp). Why a registry apart from
/// rng/uniform_source.hpp: the interface knows no generator family, so rng does not depend on aes
/// (aes implements rng's interface, the registry depends on both, the deck and the solver on the
/// registry).
#include <nacre/rng/kinds.hpp>
#include <nacre/rng/uniform_source.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace nacre::rng {

/// \brief A new source of the named generator (one of kGeneratorKinds), keyed by `seed`. Throws
/// std::invalid_argument for an unknown name.
[[nodiscard]] std::unique_ptr<UniformSource> make_uniform_source(std::string_view kind, std::uint64_t seed);

}  // namespace nacre::rng
