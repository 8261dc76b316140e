// The viewer's mouse interaction, driven without a window.
#include <atmoglobe/engine/CameraController.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <gtest/gtest.h>

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;

TEST(CameraController, DragMovesTheGroundWithThePointer) {
  // Looking straight down, heading 30 deg: after dragging by (40, -25) px the ground point
  // that was at the centre must be at centre + (40, -25) px. Tolerance 0.5 px: the move
  // uses the nadir pixel scale; off the nadir the perspective scale differs by
  // (1 + tan^2) ~ 1 % at 40 px of 400 px at 60 deg fov.
  for (double lat : {0.0, 60.0, -85.0}) {
    CameraPose pose{lat, 179.99, 2e4, 30.0, -90.0, 0.0};
    const glm::dvec3 ground = globe::geodeticToEcef({lat, 179.99, 0.0});
    engine::orbitByPixels(pose, 60.0, 400, 40.0, -25.0);
    const Camera after(pose, 60.0, 400, 400);
    const auto p = after.projectToPixel(ground);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->x, 240.0, 0.5) << lat;
    EXPECT_NEAR(p->y, 175.0, 0.5) << lat;
  }
}

TEST(CameraController, WheelZoomKeepsThePointUnderThePointerAtAnyTilt) {
  // Zoom toward pixel (300, 220): the eye slides along that pixel's ray and keeps its axes, so
  // the ground point under it would stay exactly under it; but a pose has no roll to spare (the
  // horizon is kept level), and the eye's local frame turns by the arc it moved over, theta =
  // move / R. Dropping that roll moves a pixel r px from the centre by at most r * theta; near
  // straight down the turn also tilts the line of sight sideways, which a roll-free pose cannot
  // hold (pitch tilts only along the heading), shifting the picture by up to focal * theta. The
  // tolerance is (r + focal) * theta x 1.1 (the ellipsoid's radii) + 1e-6 px for rounding.
  for (double pitch : {-90.0, -60.0, -25.0, -8.0}) {
    for (double factor : {0.8, 0.3, 1.25}) {
      CameraPose pose{47.0, 8.0, 1e4, 40.0, pitch, 0.0};
      const Camera before(pose, 60.0, 400, 400);
      const auto hit = globe::intersectRayEllipsoid(before.eyeEcef(), before.pixelRayDirection(300.0, 220.0));
      ASSERT_TRUE(hit) << pitch;
      const double distanceBefore = glm::length(*hit - before.eyeEcef());
      engine::zoomTowardPixel(pose, 60.0, 400, 400, 300.0, 220.0, factor);
      const Camera after(pose, 60.0, 400, 400);
      const auto p = after.projectToPixel(*hit);
      ASSERT_TRUE(p);
      const double theta = glm::length(after.eyeEcef() - before.eyeEcef()) / 6.3567e6;
      const double tolerance = 1.1 * (std::hypot(100.0, 20.0) + after.focalLengthPx()) * theta + 1e-6;
      EXPECT_NEAR(p->x, 300.0, tolerance) << pitch << " " << factor;
      EXPECT_NEAR(p->y, 220.0, tolerance) << pitch << " " << factor;
      EXPECT_LT(std::hypot(p->x - 300.0, p->y - 220.0), 0.25);  // sub-pixel in practice (measured <= 0.19)
      // The distance to the point is scaled by the factor (1 mm: the height round trip through
      // geodetic coordinates, GeographicLib's ~nm accuracy, with margin).
      EXPECT_NEAR(glm::length(*hit - after.eyeEcef()), factor * distanceBefore, 1e-3);
    }
  }
  // Looking straight down at the centre, the height scales by the factor (flat-ground similar
  // triangles; the hit is the nadir point, so exactly: 1e-6 m for the geodetic round trip).
  CameraPose nadir{47.0, 8.0, 1e4, 0.0, -90.0, 0.0};
  engine::zoomTowardPixel(nadir, 60.0, 400, 400, 200.0, 200.0, 0.8);
  EXPECT_NEAR(nadir.heightMeters, 8e3, 1e-6);
}

TEST(CameraController, ZoomIsClampedBetweenOneMetreAndOneHundredThousandKilometres) {
  CameraPose pose{0.0, 0.0, 2.0, 0.0, -90.0, 0.0};
  for (int i = 0; i < 20; ++i) engine::zoomTowardPixel(pose, 60.0, 100, 100, 50.0, 50.0, 0.5);
  EXPECT_EQ(pose.heightMeters, engine::kMinControllerHeightMeters);
  for (int i = 0; i < 100; ++i) engine::zoomTowardPixel(pose, 60.0, 100, 100, 50.0, 50.0, 2.0);
  EXPECT_EQ(pose.heightMeters, engine::kMaxControllerHeightMeters);
  EXPECT_TRUE(std::isfinite(pose.latDeg) && std::isfinite(pose.lonDeg));
  // Tilted: the eye moves along a slanted ray, and stops at the limits too.
  CameraPose tilted{10.0, 20.0, 50.0, 0.0, -30.0, 0.0};
  for (int i = 0; i < 30; ++i) engine::zoomTowardPixel(tilted, 60.0, 100, 100, 50.0, 70.0, 0.5);
  EXPECT_NEAR(tilted.heightMeters, engine::kMinControllerHeightMeters, 1e-6);
  for (int i = 0; i < 100; ++i) engine::zoomTowardPixel(tilted, 60.0, 100, 100, 50.0, 70.0, 2.0);
  EXPECT_LE(tilted.heightMeters, engine::kMaxControllerHeightMeters);
  EXPECT_GT(tilted.heightMeters, 0.5 * engine::kMaxControllerHeightMeters);
  EXPECT_TRUE(std::isfinite(tilted.latDeg) && std::isfinite(tilted.lonDeg) && std::isfinite(tilted.pitchDeg));
}

TEST(CameraController, TiltStaysBetweenStraightDownAndHorizontal) {
  CameraPose pose{0.0, 0.0, 100.0, 350.0, -45.0, 0.0};
  engine::tiltByPixels(pose, 100.0, -1000.0);
  EXPECT_EQ(pose.pitchDeg, 0.0);
  EXPECT_NEAR(pose.headingDeg, 10.0, 1e-12);
  engine::tiltByPixels(pose, 0.0, 1000.0);
  EXPECT_EQ(pose.pitchDeg, -90.0);
}

TEST(CameraController, PoseFromAxesRoundTrips) {
  // Camera(pose) -> eye and axes -> pose gives the pose back (1e-9 deg, 1e-6 m: double rounding
  // through trigonometry and GeographicLib's geodetic conversion), rolled or not, looking down.
  for (const CameraPose& p :
       {CameraPose{47.0, 8.0, 1e4, 40.0, -30.0, 0.0}, CameraPose{-33.0, 151.0, 3e6, 300.0, -90.0, 0.0},
        CameraPose{89.5, -179.0, 500.0, 10.0, -5.0, 12.0}}) {
    const Camera c(p, 60.0, 200, 100);
    const CameraPose q = engine::poseFromEyeAndAxes(c.eyeEcef(), c.forwardEcef(), c.rightEcef(), c.upEcef(), p.rollDeg);
    EXPECT_NEAR(q.latDeg, p.latDeg, 1e-9);
    EXPECT_NEAR(q.lonDeg, p.lonDeg, 1e-9);
    EXPECT_NEAR(q.heightMeters, p.heightMeters, 1e-6);
    EXPECT_NEAR(q.headingDeg, p.headingDeg, 1e-9);
    EXPECT_NEAR(q.pitchDeg, p.pitchDeg, 1e-9);
  }
}

TEST(CameraController, GrabDragKeepsTheGrabbedPointUnderThePointerAtAnyTilt) {
  // Grab the ground under (150, 260), drag it to (230, 200) in 8 steps: it must end under the
  // pointer. The rotation about the centre is exact; two things then move it: the height is put
  // back to the one before the step (the eye moves radially by the ellipsoid radius change over
  // the step, centimetres over a 10 km step) and the roll the turn introduced against the
  // ellipsoid normal (geodetic and geocentric up differ by up to 0.19 deg, and by ~1e-5 deg
  // across a step) is dropped to keep the horizon level; 0.05 px bounds both (measured <= 0.02).
  for (double pitch : {-90.0, -50.0, -20.0}) {
    for (double lat : {0.0, 45.0, -70.0}) {
      CameraPose pose{lat, 179.5, 3e4, 70.0, pitch, 0.0};
      const auto grabbed = engine::groundUnderPixel(pose, 60.0, 400, 300, 150.0, 260.0);
      ASSERT_TRUE(grabbed);
      for (int k = 1; k <= 8; ++k) {
        const double x = 150.0 + 80.0 * k / 8.0, y = 260.0 - 60.0 * k / 8.0;
        ASSERT_TRUE(engine::dragGroundPoint(pose, 60.0, 400, 300, *grabbed, x, y));
      }
      const auto p = Camera(pose, 60.0, 400, 300).projectToPixel(*grabbed);
      ASSERT_TRUE(p);
      EXPECT_NEAR(p->x, 230.0, 0.05) << pitch << " " << lat;
      EXPECT_NEAR(p->y, 200.0, 0.05) << pitch << " " << lat;
      EXPECT_NEAR(pose.heightMeters, 3e4, 1e-9);  // kept exactly
      EXPECT_NEAR(pose.pitchDeg, pitch, 0.5);     // a grab turns the globe, not the camera's tilt
    }
  }
  // Beyond the limb: the pointer's ray misses the globe; nothing moves.
  CameraPose far{0.0, 0.0, 2e7, 0.0, -90.0, 0.0};
  const CameraPose before = far;
  const auto grabbed = engine::groundUnderPixel(far, 60.0, 400, 400, 200.0, 200.0);
  ASSERT_TRUE(grabbed);
  EXPECT_FALSE(engine::dragGroundPoint(far, 60.0, 400, 400, *grabbed, 2.0, 2.0));
  EXPECT_EQ(far.latDeg, before.latDeg);
}

TEST(CameraController, OrbitOverThePoleHasNoFlipsOrNaN) {
  // Keyboard moves north over the north pole, then the same straight down and tilted. At every
  // step: finite values, pitch continuous, and the picture's orientation (the camera's ECEF axes)
  // turns by little. Heading is measured from local north, so it turns by 180 deg as the eye
  // passes the pole (facing north before, south after): that is geometry, not a flip; the check
  // is that the axes do not jump. Bounds: one step moves the ground 10 % of the view (about
  // 0.06 x height / R of arc, < 0.1 deg at 1e5 m); 0.5 deg per step allows for that turn.
  for (double pitch : {-90.0, -45.0}) {
    CameraPose pose{88.0, 30.0, 1e5, 0.0, pitch, 0.0};
    Camera last(pose, 60.0, 400, 400);
    bool crossed = false;
    double lastPitch = pose.pitchDeg;
    for (int i = 0; i < 600; ++i) {
      engine::panByFraction(pose, 60.0, 400, 400, 0.0, 0.1);  // ground moves down: camera goes forward
      ASSERT_TRUE(std::isfinite(pose.latDeg) && std::isfinite(pose.lonDeg) && std::isfinite(pose.headingDeg) &&
                  std::isfinite(pose.pitchDeg) && std::isfinite(pose.heightMeters))
          << i;
      const Camera now(pose, 60.0, 400, 400);
      const double turnF = glm::degrees(std::acos(std::min(1.0, glm::dot(now.forwardEcef(), last.forwardEcef()))));
      const double turnU = glm::degrees(std::acos(std::min(1.0, glm::dot(now.upEcef(), last.upEcef()))));
      EXPECT_LT(turnF, 0.5) << i;
      EXPECT_LT(turnU, 0.5) << i;
      EXPECT_LT(std::abs(pose.pitchDeg - lastPitch), 0.5) << i;
      lastPitch = pose.pitchDeg;
      last = now;
      if (pose.latDeg < 88.0 && std::abs(globe::wrapLongitudeDeg(pose.lonDeg - 30.0 - 180.0)) < 1.0) crossed = true;
    }
    EXPECT_TRUE(crossed) << "the walk went over the pole to the other side (lon + 180)";
    EXPECT_NEAR(pose.pitchDeg, pitch, 1.0);
    EXPECT_NEAR(pose.heightMeters, 1e5, 1e-6);
  }
}

TEST(CameraController, TiltAboutCentreKeepsTheCentrePoint) {
  CameraPose pose{35.0, -97.0, 5e4, 20.0, -90.0, 0.0};
  const auto centre = engine::groundUnderPixel(pose, 60.0, 400, 300, 200.0, 150.0);
  ASSERT_TRUE(centre);
  const double distance = glm::length(*centre - Camera(pose, 60.0, 400, 300).eyeEcef());
  engine::tiltAboutCentre(pose, 60.0, 400, 300, 30.0, 40.0);
  const Camera after(pose, 60.0, 400, 300);
  const auto p = after.projectToPixel(*centre);
  ASSERT_TRUE(p);
  // The centre stays at the centre (1e-6 px: double rounding) at the same distance (1 mm).
  EXPECT_NEAR(p->x, 200.0, 1e-6);
  EXPECT_NEAR(p->y, 150.0, 1e-6);
  EXPECT_NEAR(glm::length(*centre - after.eyeEcef()), distance, 1e-3);
  // Pitch -50 seen from the centre point; the eye's own local frame is tilted by the arc between
  // them (about 40 km / 6371 km = 0.4 deg), so 1 deg.
  EXPECT_NEAR(pose.pitchDeg, -50.0, 1.0);
  EXPECT_NEAR(pose.headingDeg, 50.0, 1.0);
  // Never past the centre point's horizon.
  engine::tiltAboutCentre(pose, 60.0, 400, 300, 0.0, 200.0);
  EXPECT_LE(pose.pitchDeg, engine::kMaxTiltPitchDeg + 1.0);
  EXPECT_GT(pose.heightMeters, engine::kMinControllerHeightMeters);
}

TEST(CameraController, FlightEndsExactlyArcsUpAndStaysFinite) {
  struct Case {
    CameraPose from, to;
  };
  const Case cases[] = {
      {{35.0, -97.0, 1e4, 0.0, -90.0, 0.0}, {48.8, 2.3, 2e5, 90.0, -45.0, 0.0}},
      {{10.0, 179.9, 1.0, 350.0, -90.0, 0.0}, {-10.0, -179.9, 1.0, 10.0, -60.0, 0.0}},     // antimeridian
      {{90.0, 0.0, 1e8, 0.0, -90.0, 0.0}, {-90.0, 45.0, 1.0, 0.0, -90.0, 0.0}},            // pole to pole
      {{89.9999, -120.0, 1e3, 0.0, -30.0, 0.0}, {89.9999, 60.0, 1e3, 180.0, -30.0, 0.0}},  // over the pole
      {{0.0, 0.0, 1.0, 0.0, -90.0, 0.0}, {0.0, 0.0, 1e8, 0.0, -90.0, 0.0}},                // straight up
  };
  for (const Case& c : cases) {
    const CameraPose a = engine::flightPose(c.from, c.to, 0.0), b = engine::flightPose(c.from, c.to, 1.0);
    EXPECT_EQ(a.latDeg, c.from.latDeg);
    EXPECT_EQ(a.lonDeg, c.from.lonDeg);
    EXPECT_EQ(a.heightMeters, c.from.heightMeters);
    EXPECT_EQ(a.headingDeg, c.from.headingDeg);
    EXPECT_EQ(b.latDeg, c.to.latDeg);
    EXPECT_EQ(b.lonDeg, c.to.lonDeg);
    EXPECT_EQ(b.heightMeters, c.to.heightMeters);
    EXPECT_EQ(b.pitchDeg, c.to.pitchDeg);
    const double lowest = std::min(c.from.heightMeters, c.to.heightMeters);
    const double distance =
        globe::geodesicInverse(c.from.latDeg, c.from.lonDeg, c.to.latDeg, c.to.lonDeg).distanceMeters;
    double highest = 0.0;
    CameraPose previous = a;
    for (int i = 1; i <= 1000; ++i) {
      const CameraPose p = engine::flightPose(c.from, c.to, i / 1000.0);
      ASSERT_TRUE(std::isfinite(p.latDeg) && std::isfinite(p.lonDeg) && std::isfinite(p.heightMeters) &&
                  std::isfinite(p.headingDeg) && std::isfinite(p.pitchDeg))
          << i;
      EXPECT_GE(p.heightMeters, lowest) << i;
      EXPECT_LE(p.heightMeters, engine::kMaxControllerHeightMeters * (1 + 1e-12)) << i;
      EXPECT_TRUE(p.latDeg >= -90.0 && p.latDeg <= 90.0);
      // The short way: consecutive samples are close on the ground (a step is 1/1000 of the
      // flight; the cubic ease runs at up to 3 times the mean rate: 0.31 % of the distance, + 1 m).
      const double step = globe::geodesicInverse(previous.latDeg, previous.lonDeg, p.latDeg, p.lonDeg).distanceMeters;
      EXPECT_LE(step, 0.0031 * distance + 1.0) << i;
      highest = std::max(highest, p.heightMeters);
      previous = p;
    }
    // A long flight rises above both ends (the arc) unless an end is already at the top.
    if (distance > 1e6 && std::max(c.from.heightMeters, c.to.heightMeters) < 1e7) {
      EXPECT_GT(highest, std::max(c.from.heightMeters, c.to.heightMeters));
    }
  }
  // The antimeridian case stays near it (never the long way round through Greenwich).
  for (int i = 0; i <= 100; ++i) {
    const CameraPose p = engine::flightPose(cases[1].from, cases[1].to, i / 100.0);
    EXPECT_GT(std::abs(p.lonDeg), 179.0) << i;
  }
  EXPECT_GE(engine::flightSeconds(cases[0].from, cases[0].to), 1.0);
  EXPECT_LE(engine::flightSeconds(cases[2].from, cases[2].to), 4.0);
}
