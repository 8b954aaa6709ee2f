// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file
/// \brief The R-curve of a run: the crack-growth resistance G_R against the crack extension, from
/// the table's crack_extension and fracture_energy columns (both solver families), and the
/// toughening ratio. A data product computed here, never in a chart script: r_curve.csv and
/// summary.json's crack.toughening_ratio exist whether or not charts are drawn.
///
/// Definitions (docs/fracture.md): one point each time the crack extension reaches a new largest
/// value (by more than 1e-12); G_R = the energy of fracture gained since the previous point over
/// the extension gained, per unit thickness; the first point is measured from the last row before
/// the crack left the notch (or from zero). Toughening ratio = the mean G_R over the second half of
/// the final extension (from the first point at or past half of it, or the last but one point)
/// over the mortar's work of fracture gc = k x1 x2; NaN with fewer than 2 points.
#include <string>
#include <vector>

namespace nacre::fracture {

struct RCurvePoint {
  double extension = 0;        ///< crack extension (length)
  double fracture_energy = 0;  ///< the energy of fracture at that extension
  double G_R = 0;              ///< energy per unit crack area
  double toughening = 0;       ///< G_R / gc
};

struct RCurve {
  std::vector<RCurvePoint> points;
  double toughening_ratio = 0;  ///< NaN with fewer than 2 points
};

/// \brief The R-curve of the rows (`extension[i]`, `fracture_energy[i]`), per unit `thickness`,
/// against the mortar's work of fracture `gc`.
[[nodiscard]] RCurve r_curve(const std::vector<double>& extension, const std::vector<double>& fracture_energy,
                             double thickness, double gc);

/// \brief r_curve.csv's text: "extension,fracture_energy,G_R,toughening" and one row per point,
/// each number with 17 significant digits (it reads back to the same double).
[[nodiscard]] std::string r_curve_csv(const RCurve& c);

}  // namespace nacre::fracture
