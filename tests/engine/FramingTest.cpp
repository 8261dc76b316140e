// The camera that frames named data (engine/Framing.h): every point of a volume's box that the
// camera can see lies inside the picture, with the box filling a good part of it, for boxes from
// a radar's 460 km to the whole globe, over the antimeridian and around a pole.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Framing.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace atmoglobe;
using namespace atmoglobe::engine;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

/// Great-circle angle (deg) by the haversine formula: an independent path to Framing's vectors.
double haversineDeg(double lat1, double lon1, double lat2, double lon2) {
  const double a = std::pow(std::sin(0.5 * (lat2 - lat1) * kDeg), 2) +
                   std::cos(lat1 * kDeg) * std::cos(lat2 * kDeg) * std::pow(std::sin(0.5 * (lon2 - lon1) * kDeg), 2);
  return 2.0 * std::asin(std::sqrt(a)) / kDeg;
}

/// Points on the edge of a box, on the ellipsoid and 20 km above it (a volume's top).
std::vector<glm::dvec3> edgeOf(double s, double n, double w, double e) {
  std::vector<glm::dvec3> out;
  for (int i = 0; i <= 40; ++i)
    for (double h : {0.0, 20e3}) {
      const double lon = w + (e - w) * i / 40.0, lat = s + (n - s) * i / 40.0;
      for (auto [la, lo] : {std::pair{s, lon}, {n, lon}, {lat, w}, {lat, e}})
        out.push_back(globe::geodeticToEcef({la, lo, h}));
    }
  return out;
}

struct Fit {
  int visible = 0, outside = 0;
  double maxFraction = 0.0;  ///< the farthest visible point from the centre, as a fraction of the half-size
};

/// Where the visible edge points land (visible: in front of the camera and not behind the Earth).
Fit fitOf(const Camera& camera, const std::vector<glm::dvec3>& points) {
  Fit f;
  const glm::dvec3 eye = camera.eyeEcef();
  for (const glm::dvec3& p : points) {
    // Behind the Earth: the segment eye -> p meets the sphere of the minor radius first.
    const glm::dvec3 d = p - eye;
    const double t = -glm::dot(eye, d) / glm::dot(d, d);
    if (t > 0.0 && t < 1.0 && glm::length(eye + t * d) < globe::kWgs84B - 50e3) continue;
    auto px = camera.projectToPixel(p);
    if (!px) continue;
    ++f.visible;
    const double fx = std::abs(px->x - 0.5 * camera.widthPx()) / (0.5 * camera.widthPx());
    const double fy = std::abs(px->y - 0.5 * camera.heightPx()) / (0.5 * camera.heightPx());
    f.maxFraction = std::max({f.maxFraction, fx, fy});
    if (fx > 1.0 || fy > 1.0) ++f.outside;
  }
  return f;
}
}  // namespace

TEST(Framing, TheCapOfABoxReachesItsFarthestCorner) {
  const GeoCap cap = capOfBox(30.0, 40.0, -100.0, -90.0);
  EXPECT_NEAR(cap.latDeg, 35.0, 1e-12);
  EXPECT_NEAR(cap.lonDeg, -95.0, 1e-12);
  // The south corners are the farthest (the box is wider there); the cap's radius is their
  // distance, to rounding (1e-9 deg: the two formulas differ in the last digits).
  EXPECT_NEAR(cap.radiusDeg, haversineDeg(35.0, -95.0, 30.0, -100.0), 1e-9);
  // Over the antimeridian: 170 .. -170 (given as 170 .. 190, or west > east).
  for (double east : {190.0, -170.0}) {
    const GeoCap a = capOfBox(-10.0, 10.0, 170.0, east);
    EXPECT_NEAR(std::abs(a.lonDeg), 180.0, 1e-9);
    EXPECT_NEAR(a.radiusDeg, haversineDeg(0.0, 180.0, 10.0, 170.0), 1e-9);
  }
  // Every longitude: about the pole the box reaches, or the whole sphere.
  const GeoCap arctic = capOfBox(60.0, 90.0, 0.0, 360.0);
  EXPECT_EQ(arctic.latDeg, 90.0);
  EXPECT_EQ(arctic.radiusDeg, 30.0);
  EXPECT_EQ(capOfBox(-90.0, 90.0, -180.0, 180.0).radiusDeg, 180.0);
}

TEST(Framing, CapsOfSeveralVolumesHoldEachOfThem) {
  const std::vector<GeoCap> caps{{35.3, -97.3, 2.0}, {30.0, -90.0, 2.5}, {41.0, -88.0, 2.0}};
  auto all = capOfCaps(caps);
  ASSERT_TRUE(all) << all.error();
  for (const GeoCap& c : caps)
    EXPECT_LE(haversineDeg(all->latDeg, all->lonDeg, c.latDeg, c.lonDeg) + c.radiusDeg, all->radiusDeg + 1e-9);
  EXPECT_LT(all->radiusDeg, 12.0);  // bounded by the caps, not the whole Earth
  EXPECT_FALSE(capOfCaps({}));
  auto opposite = capOfCaps({{0.0, 0.0, 1.0}, {0.0, 180.0, 1.0}});
  ASSERT_TRUE(opposite);
  EXPECT_EQ(opposite->radiusDeg, 180.0);
}

// The picture: every visible point of the box's edge (on the ground and 20 km up) is inside it,
// and the farthest is at 85 % of the half-size (the rule's fill; 0.1 % bisection tolerance and
// the outline's 32 points per edge against the test's 40: 0.83..0.851). Boxes wider than the
// visible disc and global ones: the limb is inside the picture, at 85 % of the narrower half.
TEST(Framing, TheBoxIsInsideThePictureAndFillsIt) {
  struct Box {
    double s, n, w, e;
    bool wholeDisc;
  };
  for (const Box& b : std::vector<Box>{{34.8, 35.8, -98.0, -96.6, false},   // a radar's neighbourhood
                                       {33.0, 37.5, -102.0, -92.5, false},  // a radar's 460 km
                                       {21.0, 50.0, -125.0, -66.0, false},  // a continent
                                       {-10.0, 10.0, 170.0, 190.0, false},  // over the antimeridian
                                       {60.0, 90.0, -180.0, 180.0, false},  // the Arctic
                                       {-60.0, 60.0, -100.0, 60.0, true},   // wider than the visible disc
                                       {-90.0, 90.0, 0.0, 360.0, true}})    // the globe
    for (auto [w, h] : {std::pair{1280, 720}, {480, 640}})
      for (double fov : {30.0, 45.0, 60.0}) {
        const FramingTarget target = framingTargetOfBox(b.s, b.n, b.w, b.e);
        const CameraPose pose = poseFraming(target, fov, w, h);
        ASSERT_TRUE(validatePose(pose));
        const Camera camera(pose, fov, w, h);
        const Fit f = fitOf(camera, edgeOf(b.s, b.n, b.w, b.e));
        SCOPED_TRACE(::testing::Message() << "box " << b.s << ".." << b.n << ", " << b.w << ".." << b.e << "; " << w
                                          << "x" << h << " fov " << fov << "; height " << pose.heightMeters);
        EXPECT_GT(f.visible, 0);
        EXPECT_EQ(f.outside, 0) << "farthest at " << f.maxFraction << " of the half-size";
        // The limb: the tangent cone seen from the eye on a sphere of the equatorial radius.
        const double limbFromNadirDeg = std::asin(globe::kWgs84A / (globe::kWgs84A + pose.heightMeters)) / kDeg;
        const double halfXDeg = std::atan(std::tan(0.5 * fov * kDeg) * w / h) / kDeg;
        const double narrowerHalfDeg = std::min(0.5 * fov, halfXDeg);
        if (b.wholeDisc) {
          EXPECT_NEAR(limbFromNadirDeg, 0.85 * narrowerHalfDeg, 1e-6);
        } else {
          EXPECT_GT(f.maxFraction, 0.83);
          EXPECT_LT(f.maxFraction, 0.851);
        }
      }
}

// A radar's circle: its cap's outline keeps all of the circle in view at the same fill.
TEST(Framing, ARadarCircleFillsThePicture) {
  const GeoCap cap{35.333, -97.278, 460e3 / 6371e3 * 180.0 / std::numbers::pi};
  const FramingTarget target = framingTargetOfCap(cap);
  for (const glm::dvec3& p : target.outlineEcef) {
    const globe::Geodetic g = globe::ecefToGeodetic(p);
    EXPECT_NEAR(haversineDeg(cap.latDeg, cap.lonDeg, g.latDeg, g.lonDeg), cap.radiusDeg, 1e-6);
  }
  const CameraPose pose = poseFraming(target, 45.0, 1280, 720);
  const Fit f = fitOf(Camera(pose, 45.0, 1280, 720), target.outlineEcef);
  EXPECT_EQ(f.outside, 0);
  EXPECT_NEAR(f.maxFraction, 0.85, 0.002);
}
