// The camera convention (README "Camera"), checked in double without a GL context.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <gtest/gtest.h>

#include <cmath>

using atmoglobe::engine::Camera;
using atmoglobe::engine::CameraPose;
using atmoglobe::globe::geodeticToEcef;

namespace {
// Projection is evaluated in double: 1e-9 px leaves room for rounding in ~20 flops on
// coordinates of ~1e7 m (relative 1e-16 * 1e7 m * focal / distance).
constexpr double kPxTol = 1e-6;

glm::dvec2 project(const Camera& c, double lat, double lon, double h) {
  auto p = c.projectToPixel(geodeticToEcef({lat, lon, h}));
  EXPECT_TRUE(p.has_value());
  return p.value_or(glm::dvec2(NAN));
}
}  // namespace

TEST(Camera, StraightDownPutsNadirAtImageCentreNorthUpEastRight) {
  const Camera c(CameraPose{45.0, 7.0, 1000.0, 0.0, -90.0, 0.0}, 60.0, 640, 480);
  const glm::dvec2 nadir = project(c, 45.0, 7.0, 0.0);
  EXPECT_NEAR(nadir.x, 320.0, kPxTol);
  EXPECT_NEAR(nadir.y, 240.0, kPxTol);
  const glm::dvec2 north = project(c, 45.001, 7.0, 0.0);
  EXPECT_LT(north.y, 240.0 - 10.0);  // north is up (smaller y)
  EXPECT_NEAR(north.x, 320.0, 0.5);  // meridian convergence over 111 m is tiny
  const glm::dvec2 east = project(c, 45.0, 7.001, 0.0);
  EXPECT_GT(east.x, 320.0 + 10.0);  // east is right
}

TEST(Camera, HeadingTurnsClockwiseFromNorth) {
  // Looking horizontally east (heading 90): a point due east at eye height is at the centre.
  const Camera c(CameraPose{0.0, 0.0, 100.0, 90.0, 0.0, 0.0}, 60.0, 400, 400);
  const glm::dvec3 eye = c.eyeEcef();
  const glm::dvec3 east = atmoglobe::globe::enuAxes(0.0, 0.0)[0];
  const auto p = c.projectToPixel(eye + 1000.0 * east);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 200.0, kPxTol);
  EXPECT_NEAR(p->y, 200.0, kPxTol);
  // North is then on the left.
  const glm::dvec3 north = atmoglobe::globe::enuAxes(0.0, 0.0)[1];
  const auto q = c.projectToPixel(eye + 1000.0 * east + 100.0 * north);
  ASSERT_TRUE(q);
  EXPECT_LT(q->x, 200.0);
}

TEST(Camera, PitchZeroIsHorizontalAndPositiveRollBanksRight) {
  const CameraPose level{10.0, 20.0, 50.0, 0.0, 0.0, 0.0};
  const Camera c(level, 60.0, 400, 400);
  const glm::dmat3 enu = atmoglobe::globe::enuAxes(10.0, 20.0);
  EXPECT_NEAR(glm::dot(c.forwardEcef(), enu[2]), 0.0, 1e-12);  // horizontal
  EXPECT_NEAR(glm::dot(c.forwardEcef(), enu[1]), 1.0, 1e-12);  // north
  // A point up and ahead: with +30 deg roll the camera's right side goes down, so a
  // point straight above the view centre appears up and to the LEFT (content turns
  // counter-clockwise by 30 deg).
  CameraPose rolled = level;
  rolled.rollDeg = 30.0;
  const Camera r(rolled, 60.0, 400, 400);
  const auto p = r.projectToPixel(r.eyeEcef() + 1000.0 * enu[1] + 200.0 * enu[2]);
  ASSERT_TRUE(p);
  EXPECT_LT(p->x, 200.0);
  EXPECT_LT(p->y, 200.0);
  const double angle = atmoglobe::radiansToDegrees(std::atan2(200.0 - p->x, 200.0 - p->y));
  EXPECT_NEAR(angle, 30.0, 1e-9);
}

TEST(Camera, PixelRayRoundTripsThroughProjection) {
  const Camera c(CameraPose{-33.9, 151.2, 2500.0, 37.0, -25.0, 5.0}, 50.0, 1280, 720);
  for (double x : {0.0, 0.5, 333.25, 1279.5, 1280.0}) {
    for (double y : {0.0, 0.5, 360.0, 719.5}) {
      const glm::dvec3 p = c.eyeEcef() + 12345.0 * c.pixelRayDirection(x, y);
      const auto q = c.projectToPixel(p);
      ASSERT_TRUE(q);
      EXPECT_NEAR(q->x, x, kPxTol);
      EXPECT_NEAR(q->y, y, kPxTol);
    }
  }
}

TEST(Camera, ProjectionMatrixAgreesWithProjectToPixelAndDepthIsNearOverDistance) {
  const Camera c(CameraPose{60.0, -150.0, 3e5, 200.0, -40.0, 0.0}, 40.0, 800, 600);
  const glm::dvec3 target = geodeticToEcef({59.0, -151.0, 0.0});
  const glm::dvec4 clip = c.modelViewProjectionRelativeTo(target) * glm::dvec4(0, 0, 0, 1);
  const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
  const auto px = c.projectToPixel(target);
  ASSERT_TRUE(px);
  EXPECT_NEAR((ndc.x * 0.5 + 0.5) * 800.0, px->x, kPxTol);
  EXPECT_NEAR((0.5 - ndc.y * 0.5) * 600.0, px->y, kPxTol);
  const double distanceAlongView = glm::dot(target - c.eyeEcef(), c.forwardEcef());
  EXPECT_NEAR(ndc.z, c.nearMeters() / distanceAlongView, 1e-15);
  EXPECT_GT(ndc.z, 0.0);
  EXPECT_LT(ndc.z, 1.0);
}

TEST(Camera, PointsBehindAreNotProjected) {
  const Camera c(CameraPose{0.0, 0.0, 1000.0, 0.0, -90.0, 0.0}, 60.0, 100, 100);
  EXPECT_FALSE(c.projectToPixel(geodeticToEcef({0.0, 0.0, 2000.0})).has_value());
}

TEST(Camera, FrustumPlanesAcceptVisiblePointsAndRejectOthers) {
  const Camera c(CameraPose{30.0, 40.0, 5000.0, 10.0, -30.0, 0.0}, 60.0, 640, 480);
  const auto view = c.viewState();
  auto inside = [&](const glm::dvec3& p) {
    for (const glm::dvec4& pl : view.frustumPlanesEcef) {
      if (glm::dot(glm::dvec3(pl), p) + pl.w < 0.0) return false;
    }
    return true;
  };
  for (double x : {1.0, 320.0, 639.0}) {
    for (double y : {1.0, 240.0, 479.0}) {
      EXPECT_TRUE(inside(c.eyeEcef() + 1e4 * c.pixelRayDirection(x, y))) << x << "," << y;
    }
  }
  EXPECT_FALSE(inside(c.eyeEcef() + 1e4 * c.pixelRayDirection(-40.0, 240.0)));
  EXPECT_FALSE(inside(c.eyeEcef() + 1e4 * c.pixelRayDirection(320.0, 530.0)));
  EXPECT_FALSE(inside(c.eyeEcef() - 1e4 * c.forwardEcef()));
  EXPECT_NEAR(view.pixelsPerRadian, 480.0 / (2.0 * std::tan(atmoglobe::kPi / 6.0)), 1e-9);
}
