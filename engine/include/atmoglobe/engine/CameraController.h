#pragma once
// Navigation for the viewer, GL-free so tests can drive it: each function changes a CameraPose
// from pointer positions in pixels (the Camera.h convention: origin top left, y down) or key
// steps. The viewer (tools/ViewCommand.cpp) maps mouse and keys onto them:
//   grab-drag  dragGroundPoint: the globe turns about its centre so the grabbed ground point stays
//              under the pointer, at any tilt (orbitByPixels where the press was on the sky);
//   wheel      zoomTowardPixel: the eye moves along the pointer's ray, so the point under the
//              pointer stays there exactly, at any tilt;
//   tilt/turn  tiltAboutCentre: the eye swings about the ground point at the view centre;
//   keys       panByFraction (the ground at the centre dragged by a fraction of the view),
//              zoomTowardPixel at the centre, tiltAboutCentre;
//   fly-to     flightPose(from, to, t): an eased arc in height along the geodesic, t in [0, 1].
// Poses are rebuilt from the eye and the camera's ECEF axes (poseFromEyeAndAxes), so moving over a
// pole never flips the view: the heading, relative to local north, turns by 180 degrees as the
// eye passes the pole, as it must, while the picture turns smoothly.
#include <atmoglobe/engine/Camera.h>

#include <optional>

namespace atmoglobe::engine {

/// Lowest and highest camera heights the controller goes to (m above the ellipsoid).
inline constexpr double kMinControllerHeightMeters = 1.0;
inline constexpr double kMaxControllerHeightMeters = 1e8;
/// Highest pitch tiltAboutCentre goes to (degrees): the eye stays above the centre point's
/// horizon plane, so it never meets the ground it looks at.
inline constexpr double kMaxTiltPitchDeg = -2.0;

/// The pose of a camera at `eyeEcef` whose axes (unit ECEF vectors, as Camera gives them) are
/// forward/right/up and whose roll is `rollDeg`: latitude, longitude and height of the eye, and
/// heading and pitch in the eye's local east-north-up frame (heading from the un-rolled right
/// axis, so it is defined when looking straight down and at the poles).
CameraPose poseFromEyeAndAxes(const glm::dvec3& eyeEcef, const glm::dvec3& forwardEcef, const glm::dvec3& rightEcef,
                              const glm::dvec3& upEcef, double rollDeg);

/// The ellipsoid point under pixel (x, y), or nullopt on the sky.
std::optional<glm::dvec3> groundUnderPixel(const CameraPose& pose, double fovYDeg, int widthPx, int heightPx,
                                           double xPx, double yPx);

/// Grab-drag: turns the camera about the Earth's centre so that `grabbedEcef` (a ground point,
/// taken at the press with groundUnderPixel) lies on the ray through pixel (x, y); the height
/// above the ellipsoid is kept. Returns false (pose unchanged) when that pixel's ray misses the
/// sphere through the grabbed point (the pointer is beyond the globe's limb).
bool dragGroundPoint(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, const glm::dvec3& grabbedEcef,
                     double xPx, double yPx);

/// Drag on the sky: moves the camera over the ground by the pixel motion at the nadir scale
/// (height / focal length).
void orbitByPixels(CameraPose& pose, double fovYDeg, int heightPx, double dxPx, double dyPx);

/// Wheel: moves the eye along the ray through pixel (x, y) so that its distance to the ground
/// point under that pixel is scaled by `factor` (< 1 zooms in); the camera's axes are kept, so the
/// point stays exactly under the pointer at any tilt. Heights are clamped to
/// [kMinControllerHeightMeters, kMaxControllerHeightMeters]. A pointer on the sky scales the
/// height about the eye's nadir.
void zoomTowardPixel(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, double xPx, double yPx,
                     double factor);

/// Tilt and turn about the ground point at the view centre: the eye swings about it at a fixed
/// distance; pitch (as seen from that point) is clamped to [-90, kMaxTiltPitchDeg]. With the
/// centre on the sky the camera turns in place (tiltByPixels' rule).
void tiltAboutCentre(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, double dHeadingDeg, double dPitchDeg);

/// Turn in place: vertical motion tilts (pitch, clamped to [-90, 0]), horizontal turns
/// (heading), 0.2 degrees per pixel.
void tiltByPixels(CameraPose& pose, double dxPx, double dyPx);

/// Keyboard move: the ground at the view centre is dragged by (fx * width, fy * height) pixels
/// (fx > 0 moves the view right, fy > 0 moves it down the screen, i.e. the camera goes the
/// other way); on the sky, orbitByPixels.
void panByFraction(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, double fx, double fy);

/// Smooth fly-to: the pose at t in [0, 1] of a flight from `from` to `to` (t <= 0 gives `from`,
/// t >= 1 gives `to`, exactly). Eased (cubic in and out); the eye follows the geodesic between
/// the two positions (across the antimeridian and the poles the short way) while its height
/// rises in an arc: the heights' geometric interpolation plus a bump that peaks at about half
/// the distance flown (capped at kMaxControllerHeightMeters), so the height is never below the
/// lower of the two ends. Heading turns the short way; pitch and roll interpolate linearly.
CameraPose flightPose(const CameraPose& from, const CameraPose& to, double t);

/// Seconds a flight takes: 1 s for short hops, growing with the log of the distance and height
/// change to 4 s for the other side of the globe.
double flightSeconds(const CameraPose& from, const CameraPose& to);

}  // namespace atmoglobe::engine
