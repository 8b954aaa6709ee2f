// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Kinds of joint between pieces of material; each kind has its own cohesive law
/// (cohesive::LawTable). A header of its own so the law table need not pull in the specimen.
#include <cstdint>

namespace nacre::geometry {

/// \brief bed: joints along the wall's rows; head: joints between bricks of one row; internal:
/// the stiff joints on the diagonals inside a deformable brick (Chapter 4, unbolted explicit).
/// Rigid-brick models have bed and head joints only.
enum class JointKind : std::uint8_t { bed = 0, head = 1, internal = 2 };

/// \brief Number of joint kinds (size of a law table).
inline constexpr int kJointKinds = 3;

}  // namespace nacre::geometry
