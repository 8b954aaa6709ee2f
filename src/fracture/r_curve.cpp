// SPDX-License-Identifier: BSD-3-Clause
// The R-curve and the toughening ratio from a run's table (fracture/r_curve.hpp): host code over
// a few hundred rows at the end of a run.
#include <nacre/core/format.hpp>
#include <nacre/fracture/r_curve.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace nacre::fracture {

RCurve r_curve(const std::vector<double>& extension, const std::vector<double>& fracture_energy, double thickness,
               double gc) {
  if (extension.size() != fracture_energy.size())
    throw std::invalid_argument("r_curve: the extension and fracture_energy columns differ in length");
  RCurve c;
  double amax = 0, base_a = 0, base_w = 0;
  for (std::size_t i = 0; i < extension.size(); ++i) {
    const double a = extension[i], w = fracture_energy[i];
    if (a <= amax + 1e-12) {
      if (c.points.empty()) base_w = w;  // before the crack leaves the notch: the last such row
      continue;
    }
    const double a0 = c.points.empty() ? base_a : c.points.back().extension;
    const double w0 = c.points.empty() ? base_w : c.points.back().fracture_energy;
    const double g = (w - w0) / (a - a0) / thickness;
    c.points.push_back({a, w, g, g / gc});
    amax = a;
  }
  c.toughening_ratio = std::numeric_limits<double>::quiet_NaN();
  if (c.points.size() >= 2) {
    const RCurvePoint& last = c.points.back();
    const RCurvePoint* half = &last;
    for (const RCurvePoint& p : c.points)
      if (p.extension >= 0.5 * last.extension) {
        half = &p;
        break;
      }
    if (half == &last) half = &c.points[c.points.size() - 2];
    c.toughening_ratio =
        (last.fracture_energy - half->fracture_energy) / (last.extension - half->extension) / thickness / gc;
  }
  return c;
}

std::string r_curve_csv(const RCurve& c) {
  std::string t = "extension,fracture_energy,G_R,toughening\n";
  for (const RCurvePoint& p : c.points)
    t += format_real(p.extension, 17) + "," + format_real(p.fracture_energy, 17) + "," + format_real(p.G_R, 17) +
         "," + format_real(p.toughening, 17) + "\n";
  return t;
}

}  // namespace nacre::fracture
