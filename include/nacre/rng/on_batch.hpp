// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief How a uniform source launches on a batch: the batch's memory space picks the instance.
///
/// Why one helper: every generator (Philox, AES-CTR, MT+AES) fills a batch that lives in one of
/// the build's memory spaces (rng::AnyBatch) on the run's backend; this is the one place that
/// opens the batch and the backend together, so no source repeats the two visits.
#include <nacre/core/backend.hpp>
#include <nacre/rng/uniform_source.hpp>

#include <type_traits>
#include <variant>

namespace nacre::rng {

/// \brief f(space, batch): `batch` with its own memory space MS (Batch<MS>), `space` the
/// backend's instance, which must reach MS (Backend::visit_in: std::logic_error otherwise).
template <class F>
void on_batch(const Backend& backend, const AnyBatch& batch, F&& f) {
  std::visit(
      [&](const auto& b) {
        using MS = typename std::decay_t<decltype(b)>::memory_space;
        backend.visit_in<MS>([&](const auto& space) { f(space, b); });
      },
      batch);
}

}  // namespace nacre::rng
