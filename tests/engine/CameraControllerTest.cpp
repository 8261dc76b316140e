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

TEST(CameraController, WheelZoomKeepsThePointUnderThePointer) {
  // Zoom in by 0.8 toward pixel (300, 120): the ground point under it stays under it
  // within 1 px (the move is exact for a flat ground; the Earth's curvature over the
  // ~5 km footprint at 10 km height bends it by less than 0.1 %).
  CameraPose pose{47.0, 8.0, 1e4, 0.0, -90.0, 0.0};
  const Camera before(pose, 60.0, 400, 400);
  const auto hit = globe::intersectRayEllipsoid(before.eyeEcef(), before.pixelRayDirection(300.0, 120.0));
  ASSERT_TRUE(hit);
  engine::zoomTowardPixel(pose, 60.0, 400, 400, 300.0, 120.0, 0.8);
  EXPECT_NEAR(pose.heightMeters, 8e3, 1e-9);
  const Camera after(pose, 60.0, 400, 400);
  const auto p = after.projectToPixel(*hit);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 300.0, 1.0);
  EXPECT_NEAR(p->y, 120.0, 1.0);
}

TEST(CameraController, ZoomIsClampedBetweenOneMetreAndOneHundredThousandKilometres) {
  CameraPose pose{0.0, 0.0, 2.0, 0.0, -90.0, 0.0};
  for (int i = 0; i < 20; ++i) engine::zoomTowardPixel(pose, 60.0, 100, 100, 50.0, 50.0, 0.5);
  EXPECT_EQ(pose.heightMeters, engine::kMinControllerHeightMeters);
  for (int i = 0; i < 100; ++i) engine::zoomTowardPixel(pose, 60.0, 100, 100, 50.0, 50.0, 2.0);
  EXPECT_EQ(pose.heightMeters, engine::kMaxControllerHeightMeters);
  EXPECT_TRUE(std::isfinite(pose.latDeg) && std::isfinite(pose.lonDeg));
}

TEST(CameraController, TiltStaysBetweenStraightDownAndHorizontal) {
  CameraPose pose{0.0, 0.0, 100.0, 350.0, -45.0, 0.0};
  engine::tiltByPixels(pose, 100.0, -1000.0);
  EXPECT_EQ(pose.pitchDeg, 0.0);
  EXPECT_NEAR(pose.headingDeg, 10.0, 1e-12);
  engine::tiltByPixels(pose, 0.0, 1000.0);
  EXPECT_EQ(pose.pitchDeg, -90.0);
}
