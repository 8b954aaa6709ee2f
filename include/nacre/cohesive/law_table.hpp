// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief One cohesive law per joint kind (bed, head, internal), shared by every interface of
/// that kind: a model stores a one-byte kind per interface, not a law per interface.
#include <nacre/cohesive/law.hpp>
#include <nacre/geometry/joint_kind.hpp>

#include <cstdint>

namespace nacre::cohesive {

/// \brief Laws indexed by geometry::JointKind. Trivially copyable (9 doubles), so kernels capture
/// it by value.
struct LawTable {
  Law law[geometry::kJointKinds];

  /// \brief Law of a stored kind byte (as kept in a model's per-interface kind View).
  KOKKOS_INLINE_FUNCTION const Law& operator[](std::uint8_t kind) const { return law[kind]; }
  KOKKOS_INLINE_FUNCTION const Law& operator[](geometry::JointKind kind) const {
    return law[static_cast<int>(kind)];
  }
  KOKKOS_INLINE_FUNCTION Law& operator[](geometry::JointKind kind) { return law[static_cast<int>(kind)]; }
};

/// \brief The table of a model with the given laws; a rigid-brick model has no internal joints
/// (kNoJoint).
inline LawTable make_law_table(const Law& bed, const Law& head, const Law& internal = kNoJoint) {
  LawTable t{};
  t[geometry::JointKind::bed] = bed;
  t[geometry::JointKind::head] = head;
  t[geometry::JointKind::internal] = internal;
  return t;
}

}  // namespace nacre::cohesive
