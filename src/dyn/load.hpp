#pragma once
// Opening D(t) of the driven edges and its first two derivatives: the rate ramps up from 0 over
// ramp_time (linearly, or smoothly as (1 - cos(pi t / T)) / 2 so the acceleration is continuous
// at t = 0), then stays constant; D stops at final_displacement when that is > 0 (held after).
// Local to dyn until the loading module (issue 7 §1) lands; the pattern itself is in
// Integrator::pattern.
#include <nacre/dyn/simulation.hpp>

#include <cmath>
#include <numbers>

namespace nacre::dyn {

struct Opening {
  double D = 0, Dd = 0, Ddd = 0;
};

inline Opening opening(const Params& p, double t) {
  const double r = p.rate, T = p.ramp_time;
  Opening o;
  if (T > 0 && t < T) {
    if (p.ramp == Ramp::linear) {
      o.D = 0.5 * r * t * t / T, o.Dd = r * t / T, o.Ddd = r / T;
    } else {
      const double w = std::numbers::pi / T;
      o.D = 0.5 * r * (t - std::sin(w * t) / w), o.Dd = 0.5 * r * (1 - std::cos(w * t)), o.Ddd = 0.5 * r * w * std::sin(w * t);
    }
  } else {
    o.D = r * (t - 0.5 * T), o.Dd = r, o.Ddd = 0;
  }
  if (p.final_displacement > 0 && std::abs(o.D) >= p.final_displacement)
    o.D = std::copysign(p.final_displacement, o.D), o.Dd = 0, o.Ddd = 0;
  return o;
}

}  // namespace nacre::dyn
