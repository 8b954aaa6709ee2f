// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The prescribed-displacement pattern of the driven edges (docs/decks.md, [load]): the
/// displacement of a driven point for an opening D, from which every solver family derives what
/// it prescribes (a rigid brick's pose here, a deformable model's nodal values from
/// displacement() at each node).
///
/// Top edge: u = (0, +D/2 [tension + bending (1 - x / width)]); bottom edge: its mirror. Tension
/// opens the specimen uniformly, bending opens it most at the notch mouth (x = 0) and not at all
/// at the far edge.
#include <nacre/kinematics/rigid.hpp>

#include <Kokkos_Core.hpp>

namespace nacre::loading {

/// \brief Weights of the two load components and the specimen width they are measured over.
struct Pattern {
  double tension = 1.0;  ///< weight of the uniform opening
  double bending = 0.0;  ///< weight of the linear opening, largest at x = 0
  double width = 1.0;    ///< specimen width (the lever arm's length)

  /// \brief Displacement (ux, uy) of the point (x, y) of edge `side` (+1 top, -1 bottom, 0: a
  /// free point, zero) at opening D. The field does not depend on y.
  KOKKOS_INLINE_FUNCTION void displacement(int side, double x, double /*y*/, double D, double& ux,
                                           double& uy) const {
    const double lever = 1.0 - x / width;  // 1 at the notch mouth, 0 at the far edge
    ux = 0.0;
    uy = 0.5 * D * (tension + bending * lever) * side;
  }

  /// \brief d uy / d x along edge `side` at opening D (the field is linear in x).
  KOKKOS_INLINE_FUNCTION double slope(int side, double D) const { return -0.5 * D * bending / width * side; }
};

/// \brief Pose of a rigid brick driven by edge `side` with reference centroid (cx, cy): it moves
/// with the pattern's displacement at its centroid and turns by the slope of the edge.
KOKKOS_INLINE_FUNCTION kinematics::Pose rigid_pose(const Pattern& p, int side, double cx, double cy, double D) {
  double ux, uy;
  p.displacement(side, cx, cy, D, ux, uy);
  return kinematics::Pose{ux, uy, Kokkos::atan(p.slope(side, D))};
}

}  // namespace nacre::loading
