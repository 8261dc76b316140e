#include <atmoglobe/engine/CameraController.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::engine {

namespace {
constexpr double kMaxLatDeg = 89.999;  // orbitByPixels' geodesic walk keeps clear of the poles

double wrapHeadingDeg(double headingDeg) {
  const double h = std::fmod(std::fmod(headingDeg, 360.0) + 360.0, 360.0);
  return h >= 360.0 ? 0.0 : h;
}

/// Rodrigues: v turned by angleRad about the unit axis k.
glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& k, double angleRad) {
  const double c = std::cos(angleRad), s = std::sin(angleRad);
  return v * c + glm::cross(k, v) * s + k * (glm::dot(k, v) * (1.0 - c));
}

/// Camera axes (ECEF) for heading/pitch given in the local frame `enu` (columns east, north, up).
void axesInFrame(const glm::dmat3& enu, double headingDeg, double pitchDeg, glm::dvec3* forward, glm::dvec3* right,
                 glm::dvec3* up) {
  const double h = degreesToRadians(headingDeg), p = degreesToRadians(pitchDeg);
  const glm::dvec3 f(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
  const glm::dvec3 r(std::cos(h), -std::sin(h), 0.0);
  *forward = glm::normalize(enu * f);
  *right = glm::normalize(enu * r);
  *up = glm::normalize(enu * glm::cross(r, f));
}

/// The view centre's ground point, when it is on the globe.
std::optional<glm::dvec3> centreGround(const CameraPose& pose, double fovYDeg, int widthPx, int heightPx) {
  return groundUnderPixel(pose, fovYDeg, widthPx, heightPx, 0.5 * widthPx, 0.5 * heightPx);
}

double clampHeight(double h) { return std::clamp(h, kMinControllerHeightMeters, kMaxControllerHeightMeters); }
}  // namespace

CameraPose poseFromEyeAndAxes(const glm::dvec3& eyeEcef, const glm::dvec3& forwardEcef, const glm::dvec3& rightEcef,
                              const glm::dvec3& upEcef, double rollDeg) {
  const globe::Geodetic g = globe::ecefToGeodetic(eyeEcef);
  const glm::dmat3 toLocal = glm::transpose(globe::enuAxes(g.latDeg, g.lonDeg));
  // Undo the roll (Camera: right = right0 cos r - up0 sin r, up = up0 cos r + right0 sin r).
  const double r = degreesToRadians(rollDeg);
  const glm::dvec3 right0 = toLocal * (rightEcef * std::cos(r) + upEcef * std::sin(r));
  const glm::dvec3 f = toLocal * forwardEcef;
  CameraPose pose;
  pose.latDeg = g.latDeg;
  pose.lonDeg = g.lonDeg;
  pose.heightMeters = g.heightMeters;
  pose.pitchDeg = radiansToDegrees(std::asin(std::clamp(f.z / glm::length(f), -1.0, 1.0)));
  // Heading from the line of sight keeps the view centre exact; looking (nearly) straight down
  // it is undefined, and the un-rolled right axis gives it.
  const double horizontal = std::hypot(f.x, f.y);
  pose.headingDeg = wrapHeadingDeg(
      radiansToDegrees(horizontal > 1e-3 * glm::length(f) ? std::atan2(f.x, f.y) : std::atan2(-right0.y, right0.x)));
  pose.rollDeg = rollDeg;
  return pose;
}

std::optional<glm::dvec3> groundUnderPixel(const CameraPose& pose, double fovYDeg, int widthPx, int heightPx,
                                           double xPx, double yPx) {
  const Camera camera(pose, fovYDeg, widthPx, heightPx);
  return globe::intersectRayEllipsoid(camera.eyeEcef(), camera.pixelRayDirection(xPx, yPx));
}

bool dragGroundPoint(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, const glm::dvec3& grabbedEcef,
                     double xPx, double yPx) {
  const Camera camera(pose, fovYDeg, widthPx, heightPx);
  const glm::dvec3 eye = camera.eyeEcef(), dir = camera.pixelRayDirection(xPx, yPx);
  // Where the pixel's ray meets the sphere (about the Earth's centre) through the grabbed point.
  const double radius = glm::length(grabbedEcef);
  const double b = glm::dot(eye, dir), c = glm::dot(eye, eye) - radius * radius;
  const double disc = b * b - c;
  if (!(disc >= 0.0) || radius <= 0.0) return false;
  const double tNear = -b - std::sqrt(disc), tFar = -b + std::sqrt(disc);
  const double t = tNear > 0.0 ? tNear : tFar;
  if (!(t > 0.0)) return false;
  const glm::dvec3 onRay = eye + t * dir;
  // The rotation about the centre taking that point to the grabbed one, applied to the camera.
  const glm::dvec3 axis = glm::cross(onRay, grabbedEcef);
  const double sinLen = glm::length(axis);
  if (sinLen <= 1e-12 * radius * radius) return true;  // already there
  const glm::dvec3 k = axis / sinLen;
  const double angle = std::atan2(sinLen, glm::dot(onRay, grabbedEcef));
  const double keptHeight = pose.heightMeters;
  pose = poseFromEyeAndAxes(rotate(eye, k, angle), rotate(camera.forwardEcef(), k, angle),
                            rotate(camera.rightEcef(), k, angle), rotate(camera.upEcef(), k, angle), pose.rollDeg);
  // Turning about the centre would change the height above the oblate ellipsoid (by up to its
  // 21 km flattening over a long drag); keep it. Per drag step the eye then moves radially by the
  // change of the ellipsoid's radius over the step, which is far below a pixel.
  pose.heightMeters = keptHeight;
  return true;
}

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
  if (!hit) {
    pose.heightMeters = clampHeight(pose.heightMeters * factor);
    return;
  }
  // The eye slides along the pointer's ray; the axes stay, so the hit stays on that pixel.
  auto eyeAt = [&](double f) { return *hit + f * (camera.eyeEcef() - *hit); };
  auto heightAt = [&](double f) { return globe::ecefToGeodetic(eyeAt(f)).heightMeters; };
  double f = factor;
  const double h = heightAt(f);
  std::optional<double> limited;
  if (h < kMinControllerHeightMeters || h > kMaxControllerHeightMeters) {
    // Stop where the height reaches the limit: bisection on the factor between 1 (no move, in
    // range) and the asked one; the height is monotonic along the ray segment.
    const double limit = h < kMinControllerHeightMeters ? kMinControllerHeightMeters : kMaxControllerHeightMeters;
    double inside = 1.0, outside = factor;
    if ((pose.heightMeters - limit) * (h - limit) > 0.0) inside = factor;  // already beyond: nothing to keep
    for (int i = 0; i < 80 && inside != factor; ++i) {
      const double mid = 0.5 * (inside + outside);
      ((heightAt(mid) - limit) * (pose.heightMeters - limit) > 0.0 ? inside : outside) = mid;
    }
    f = inside;
    limited = limit;
  }
  const double roll = pose.rollDeg;
  pose = poseFromEyeAndAxes(eyeAt(f), camera.forwardEcef(), camera.rightEcef(), camera.upEcef(), roll);
  pose.heightMeters = limited ? *limited : clampHeight(pose.heightMeters);
}

void tiltAboutCentre(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, double dHeadingDeg,
                     double dPitchDeg) {
  const auto centre = centreGround(pose, fovYDeg, widthPx, heightPx);
  if (!centre) {
    pose.pitchDeg = std::clamp(pose.pitchDeg + dPitchDeg, -90.0, 0.0);
    pose.headingDeg = wrapHeadingDeg(pose.headingDeg + dHeadingDeg);
    return;
  }
  const Camera camera(pose, fovYDeg, widthPx, heightPx);
  const globe::Geodetic g = globe::ecefToGeodetic(*centre);
  const glm::dmat3 enu = globe::enuAxes(g.latDeg, g.lonDeg);
  const glm::dvec3 toCentre = *centre - camera.eyeEcef();
  const double distance = glm::length(toCentre);
  // The line of sight's heading and pitch in the centre point's frame, turned.
  const glm::dvec3 f = glm::transpose(enu) * (toCentre / distance);
  const double pitch = radiansToDegrees(std::asin(std::clamp(f.z, -1.0, 1.0)));
  const double heading = radiansToDegrees(std::atan2(f.x, f.y));
  // Heading from the line of sight is undefined looking straight down: take the camera's.
  const double baseHeading = std::hypot(f.x, f.y) < 1e-9 ? pose.headingDeg : heading;
  const double newPitch = std::clamp(pitch + dPitchDeg, -90.0, kMaxTiltPitchDeg);
  const double newHeading = wrapHeadingDeg(baseHeading + dHeadingDeg);
  glm::dvec3 forward, right, up;
  axesInFrame(enu, newHeading, newPitch, &forward, &right, &up);
  const glm::dvec3 eye = *centre - distance * forward;
  const double roll = pose.rollDeg;
  CameraPose moved = poseFromEyeAndAxes(eye, forward, right, up, roll);
  if (moved.heightMeters < kMinControllerHeightMeters) return;  // would put the eye in the ground
  pose = moved;
}

void tiltByPixels(CameraPose& pose, double dxPx, double dyPx) {
  pose.pitchDeg = std::clamp(pose.pitchDeg - dyPx * 0.2, -90.0, 0.0);
  pose.headingDeg = wrapHeadingDeg(pose.headingDeg + dxPx * 0.2);
}

void panByFraction(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, double fx, double fy) {
  const double cx = 0.5 * widthPx, cy = 0.5 * heightPx;
  const double dx = fx * widthPx, dy = fy * heightPx;
  if (const auto centre = centreGround(pose, fovYDeg, widthPx, heightPx)) {
    if (dragGroundPoint(pose, fovYDeg, widthPx, heightPx, *centre, cx + dx, cy + dy)) return;
  }
  orbitByPixels(pose, fovYDeg, heightPx, dx, dy);
}

namespace {
double easeInOutCubic(double t) { return t < 0.5 ? 4.0 * t * t * t : 1.0 - 0.5 * std::pow(2.0 - 2.0 * t, 3.0); }

/// Wraps an angle difference to [-180, 180).
double shortTurnDeg(double d) { return std::fmod(std::fmod(d + 180.0, 360.0) + 360.0, 360.0) - 180.0; }
}  // namespace

CameraPose flightPose(const CameraPose& from, const CameraPose& to, double t) {
  if (!(t > 0.0)) return from;
  if (t >= 1.0) return to;
  const double s = easeInOutCubic(t);
  const globe::GeodesicLine line = globe::geodesicInverse(from.latDeg, from.lonDeg, to.latDeg, to.lonDeg);
  const globe::GeodesicPoint p =
      globe::geodesicDirect(from.latDeg, from.lonDeg, line.azimuth1Deg, s * line.distanceMeters);
  // Height: geometric interpolation (even in zoom: 1 m to 1e8 m does not rush through the low
  // part), linear where a height is not positive, plus a bump rising to about half the distance
  // flown so a long flight shows where it goes. Both terms are >= min(from, to).
  const double h0 = from.heightMeters, h1 = to.heightMeters;
  const double base = (h0 > 0.0 && h1 > 0.0) ? h0 * std::pow(h1 / h0, s) : h0 + (h1 - h0) * s;
  const double top = std::min(0.5 * line.distanceMeters, kMaxControllerHeightMeters);
  const double bump = std::max(0.0, top - std::max(h0, h1)) * 4.0 * s * (1.0 - s);
  CameraPose out;
  out.latDeg = std::clamp(p.latDeg, -90.0, 90.0);
  out.lonDeg = globe::wrapLongitudeDeg(p.lonDeg);
  out.heightMeters = std::max(base, std::min(h0, h1)) + bump;
  out.headingDeg = wrapHeadingDeg(from.headingDeg + s * shortTurnDeg(to.headingDeg - from.headingDeg));
  out.pitchDeg = from.pitchDeg + s * (to.pitchDeg - from.pitchDeg);
  out.rollDeg = from.rollDeg + s * (to.rollDeg - from.rollDeg);
  return out;
}

double flightSeconds(const CameraPose& from, const CameraPose& to) {
  const double distance = globe::geodesicInverse(from.latDeg, from.lonDeg, to.latDeg, to.lonDeg).distanceMeters;
  const double zoom = std::abs(std::log10(std::max(from.heightMeters, 1.0) / std::max(to.heightMeters, 1.0)));
  // log10 of 20000 km is 7.3: a hop of 1 km (3) takes 1 s; half the globe 4 s.
  const double seconds = 1.0 + 0.7 * std::max(0.0, std::log10(std::max(distance, 1.0)) - 3.0) + 0.2 * zoom;
  return std::clamp(seconds, 1.0, 4.0);
}

}  // namespace atmoglobe::engine
