// SPDX-License-Identifier: BSD-3-Clause
// Loading: the prescribed-displacement pattern (a displacement at a point), the rigid pose a
// driven brick derives from it, and the time ramp D(t) with its derivatives.
#include <nacre/loading/pattern.hpp>
#include <nacre/loading/ramp.hpp>

#include <catch2/catch_approx.hpp>
#include <catch2/catch_test_macros.hpp>

#include <cmath>

using namespace nacre;

TEST_CASE("pattern: opening profile of the driven edges", "[loading]") {
  const loading::Pattern p{0.5, 2.0, 40.0};
  const double D = 0.1;
  double ux, uy;
  // top edge at the notch mouth: D/2 (tension + bending); at the far edge: D/2 tension
  p.displacement(+1, 0.0, 17.0, D, ux, uy);
  CHECK(ux == 0.0);
  CHECK(uy == Catch::Approx(0.5 * D * (0.5 + 2.0)));
  p.displacement(+1, 40.0, 17.0, D, ux, uy);
  CHECK(uy == Catch::Approx(0.5 * D * 0.5));
  // bottom edge mirrors the top; a free point does not move
  double ub;
  p.displacement(-1, 13.0, 0.0, D, ux, ub);
  p.displacement(+1, 13.0, 40.0, D, ux, uy);
  CHECK(ub == -uy);
  p.displacement(0, 13.0, 20.0, D, ux, uy);
  CHECK(uy == 0.0);
  // the slope is the x-derivative of the field (linear: a chord gives it exactly)
  double u0, u1;
  p.displacement(+1, 10.0, 0.0, D, ux, u0);
  p.displacement(+1, 30.0, 0.0, D, ux, u1);
  CHECK(p.slope(+1, D) == Catch::Approx((u1 - u0) / 20.0));
  CHECK(p.slope(-1, D) == -p.slope(+1, D));
}

TEST_CASE("pattern: a driven rigid brick follows the field at its centroid and turns with the edge",
          "[loading]") {
  const loading::Pattern p{1.0, 0.5, 14.0};
  const double D = 0.02, cx = 3.5, cy = 5.5;
  const kinematics::Pose q = loading::rigid_pose(p, +1, cx, cy, D);
  double ux, uy;
  p.displacement(+1, cx, cy, D, ux, uy);
  CHECK(q.x == ux);
  CHECK(q.y == uy);
  CHECK(q.t == Catch::Approx(std::atan(p.slope(+1, D))));
  // the brick's material points along the edge follow the field to first order in the rotation
  for (double rx : {-1.75, 0.0, 1.75}) {
    double dx, dy, fx, fy;
    kinematics::point_displacement(q, rx, 0.0, dx, dy);
    p.displacement(+1, cx + rx, cy, D, fx, fy);
    CHECK(dy == Catch::Approx(fy).margin(1e-9));
    CHECK(std::abs(dx - fx) < 1e-6);  // (cos t - 1) rx: second order
  }
  // the pose reproduces what the Monte Carlo solver used before the loading module (regression
  // of the formula: translation D/2 (tension + bending (1 - cx / width)), rotation atan(slope))
  const double lever = 1.0 - cx / 14.0;
  CHECK(q.y == 0.5 * D * (1.0 + 0.5 * lever) * 1);
  CHECK(q.t == std::atan(-0.5 * D * 0.5 / 14.0 * 1));
}

TEST_CASE("ramp: D(t) is continuous with its rate, reaches the steady rate and holds at the end",
          "[loading]") {
  for (auto profile : {loading::Profile::linear, loading::Profile::smooth}) {
    const loading::Ramp r{profile, 2.0, 0.5, 1.2};
    INFO("profile " << static_cast<int>(profile));
    CHECK(r(0.0).D == 0.0);
    CHECK(r(0.0).rate == 0.0);
    // continuity at the end of the ramp
    const double T = 0.5, e = 1e-9;
    CHECK(r(T - e).D == Catch::Approx(r(T + e).D).margin(1e-8));
    CHECK(r(T - e).rate == Catch::Approx(r(T + e).rate).margin(1e-6));
    // derivatives by central differences inside the ramp and after it
    for (double t : {0.1, 0.3, 0.45, 0.6, 0.8}) {
      const double h = 1e-6;
      CHECK(r(t).rate == Catch::Approx((r(t + h).D - r(t - h).D) / (2 * h)).epsilon(1e-6));
      CHECK(r(t).accel == Catch::Approx((r(t + h).rate - r(t - h).rate) / (2 * h)).margin(1e-4));
    }
    // after the ramp: steady rate, D = rate (t - T/2)
    CHECK(r(0.6).rate == 2.0);
    CHECK(r(0.6).D == Catch::Approx(2.0 * (0.6 - 0.25)));
    // held at final_displacement
    CHECK(r(10.0).D == 1.2);
    CHECK(r(10.0).rate == 0.0);
    CHECK(r.displacement(10.0) == 1.2);
  }
  // smooth: the acceleration starts at zero; linear: it jumps to rate / ramp_time
  CHECK(loading::Ramp{loading::Profile::smooth, 2.0, 0.5, 0.0}(0.0).accel == 0.0);
  CHECK(loading::Ramp{loading::Profile::linear, 2.0, 0.5, 0.0}(0.0).accel == Catch::Approx(4.0));
  // no ramp: D = rate t
  CHECK(loading::Ramp{loading::Profile::linear, 3.0, 0.0, 0.0}(0.7).D == Catch::Approx(2.1));
}
