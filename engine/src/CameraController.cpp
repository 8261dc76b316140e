#include <atmoglobe/engine/CameraController.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::engine {

namespace {
constexpr double kMaxLatDeg = 89.999;  // keep heading well defined
}  // namespace

void orbitByPixels(CameraPose& pose, double fovYDeg, int heightPx, double dxPx, double dyPx) {
  const double focal = heightPx / (2.0 * std::tan(degreesToRadians(0.5 * fovYDeg)));
  const double metersPerPixel = std::max(pose.heightMeters, kMinControllerHeightMeters) / focal;
  const double h = degreesToRadians(pose.headingDeg);
  // Screen right is (cos h, -sin h) in (east, north); screen down is -(sin h, cos h).
  // Dragging right/down moves the ground right/down, i.e. the camera left/up.
  const double east = (-dxPx * std::cos(h) + dyPx * std::sin(h)) * metersPerPixel;
  const double north = (dxPx * std::sin(h) + dyPx * std::cos(h)) * metersPerPixel;
  // Walk the geodesic so the move is right at every latitude.
  const double distance = std::hypot(east, north);
  if (distance <= 0.0) return;
  const globe::GeodesicPoint p =
      globe::geodesicDirect(pose.latDeg, pose.lonDeg, radiansToDegrees(std::atan2(east, north)), distance);
  pose.latDeg = std::clamp(p.latDeg, -kMaxLatDeg, kMaxLatDeg);
  pose.lonDeg = globe::wrapLongitudeDeg(p.lonDeg);
}

void zoomTowardPixel(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, double xPx, double yPx,
                     double factor) {
  const Camera camera(pose, fovYDeg, widthPx, heightPx);
  const auto hit = globe::intersectRayEllipsoid(camera.eyeEcef(), camera.pixelRayDirection(xPx, yPx));
  const double newHeight =
      std::clamp(pose.heightMeters * factor, kMinControllerHeightMeters, kMaxControllerHeightMeters);
  if (hit) {
    const double moved = 1.0 - newHeight / pose.heightMeters;  // fraction of the way to the point
    const globe::Geodetic g = globe::ecefToGeodetic(*hit);
    const globe::GeodesicLine line = globe::geodesicInverse(pose.latDeg, pose.lonDeg, g.latDeg, g.lonDeg);
    const globe::GeodesicPoint p =
        globe::geodesicDirect(pose.latDeg, pose.lonDeg, line.azimuth1Deg, line.distanceMeters * moved);
    pose.latDeg = std::clamp(p.latDeg, -kMaxLatDeg, kMaxLatDeg);
    pose.lonDeg = globe::wrapLongitudeDeg(p.lonDeg);
  }
  pose.heightMeters = newHeight;
}

void tiltByPixels(CameraPose& pose, double dxPx, double dyPx) {
  pose.pitchDeg = std::clamp(pose.pitchDeg - dyPx * 0.2, -90.0, 0.0);
  pose.headingDeg = std::fmod(pose.headingDeg + dxPx * 0.2 + 360.0, 360.0);
}

}  // namespace atmoglobe::engine
