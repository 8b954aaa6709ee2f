// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief Element library of the deformable bricks (MODEL.md §5): constant-strain triangles
/// (CST), the fan triangulation of a brick polygon about its centroid, and "bolting" (eq. 4.5):
/// the triangles' matrices assembled into one (n+1)-node brick element through a mapping table.
///
/// Why these choices (docs/dynamics.md, "model"):
/// - Plane stress: the bricks are platelets of a 2-D wall whose faces are traction-free, so
///   sigma_zz = 0; the dissertation's Table 4.1 gives one E and nu and no out-of-plane constraint.
/// - Lumped (row-sum) mass, rho A t / 3 per triangle node: an explicit integrator then needs no
///   mass solve (with beta_d = 0, (M + h/2 C)^-1 is diagonal), the critical step is larger than
///   with the consistent mass (the lumped highest frequency is lower), and the total mass and the
///   momentum of translations are exact; tests/dyn checks both.
/// - Fan from the centroid: for a rectangle it is exactly the cut by the two diagonals (4 CSTs);
///   clipped and notch-split pieces are convex polygons, so the fan is valid for them too.
/// Host-only (Eigen); the device sees the assembled tables (model.hpp).
#include <Eigen/Dense>

#include <array>
#include <vector>

namespace nacre::dyn {

/// \brief Linear elastic material of the bricks and the out-of-plane thickness.
struct Material {
  double E = 0, nu = 0, rho = 0, thickness = 1;
};

/// \brief Plane-stress elasticity matrix (Voigt: xx, yy, engineering xy).
Eigen::Matrix3d plane_stress(double E, double nu);

/// \brief Strain-displacement matrix of a CST with nodes (x[k], y[k]), CCW; throws if the
/// area is not positive.
struct Cst {
  double area = 0;
  Eigen::Matrix<double, 3, 6> B;
};
Cst cst(const std::array<double, 3>& x, const std::array<double, 3>& y);

/// \brief Matrices of one element (a triangle, or a bolted brick) over 2 * nodes dof, dof order
/// (u0x, u0y, u1x, u1y, ...): stiffness K = sum B^T D B A t, lumped mass per dof, thermal load
/// Theta = sum B^T D eps_th A t for a unit isotropic eigenstrain, node positions.
struct ElementMatrices {
  int nodes = 0;
  Eigen::MatrixXd K;
  Eigen::VectorXd mass;
  Eigen::VectorXd theta_unit;
  std::vector<double> x, y;  ///< node positions (relative to the brick centroid)
};

/// \brief One CST (own 3 nodes).
ElementMatrices triangle_element(const std::array<double, 3>& x, const std::array<double, 3>& y,
                                 const Material& m);

/// \brief Nodes of fan triangle i of an n-gon: centre node 0, corners 1 + i and 1 + (i+1) % n.
inline std::array<int, 3> fan_triangle(int n, int i) { return {0, 1 + i, 1 + (i + 1) % n}; }

/// \brief Bolt the fan triangles of a convex CCW polygon (vertices relative to its centroid)
/// into one (n+1)-node element: entries of the unbolted matrices that belong to the same
/// vertex are added (the mapping table is fan_triangle).
ElementMatrices bolted_brick(const std::vector<double>& px, const std::vector<double>& py,
                             const Material& m);

/// \brief The n fan triangles of the polygon as separate elements (UE).
std::vector<ElementMatrices> unbolted_brick(const std::vector<double>& px,
                                            const std::vector<double>& py, const Material& m);

/// \brief Cauchy stress of a CST with nodal displacements u (6), eigenstrain eps_th (isotropic).
Eigen::Vector3d cst_stress(const Cst& c, const Eigen::Matrix3d& D, const double* u, double eps_th);

}  // namespace nacre::dyn
