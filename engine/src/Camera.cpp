#include <atmoglobe/engine/Camera.h>

#include <atmoglobe/globe/Angles.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace atmoglobe::engine {

Status validatePose(const CameraPose& p) {
  const double values[] = {p.latDeg, p.lonDeg, p.heightMeters, p.headingDeg, p.pitchDeg, p.rollDeg};
  for (double v : values) {
    if (!std::isfinite(v)) return makeError("camera: every value must be a finite number");
  }
  if (p.latDeg < -90.0 || p.latDeg > 90.0) {
    return makeError("camera: latitude " + std::to_string(p.latDeg) + " deg is outside [-90, 90]");
  }
  if (p.pitchDeg < -90.0 || p.pitchDeg > 90.0) {
    return makeError("camera: pitch " + std::to_string(p.pitchDeg) + " deg is outside [-90, 90]");
  }
  if (p.heightMeters < -6.3e6 || p.heightMeters > 1e10) {
    return makeError("camera: height " + std::to_string(p.heightMeters) + " m is outside [-6.3e6, 1e10]");
  }
  return Ok{};
}

Camera::Camera(const CameraPose& pose, double fovYDeg, int widthPx, int heightPx)
    : pose_(pose), fovYDeg_(fovYDeg), widthPx_(widthPx), heightPx_(heightPx) {
  assert(fovYDeg > 0.0 && fovYDeg < 180.0 && widthPx >= 1 && heightPx >= 1);
  eyeEcef_ = globe::geodeticToEcef({pose.latDeg, pose.lonDeg, pose.heightMeters});
  const glm::dmat3 enu = globe::enuAxes(pose.latDeg, pose.lonDeg);
  const double h = degreesToRadians(pose.headingDeg), p = degreesToRadians(pose.pitchDeg);
  const double r = degreesToRadians(pose.rollDeg);
  // In ENU components. right/up at zero roll: right is horizontal, up = right x forward.
  const glm::dvec3 forward(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
  const glm::dvec3 right0(std::cos(h), -std::sin(h), 0.0);
  const glm::dvec3 up0 = glm::cross(right0, forward);
  // Positive roll: the camera's right side goes down (image turns clockwise).
  const glm::dvec3 right = right0 * std::cos(r) - up0 * std::sin(r);
  const glm::dvec3 up = up0 * std::cos(r) + right0 * std::sin(r);
  cameraToEcef_ = glm::dmat3(glm::normalize(enu * right), glm::normalize(enu * up), glm::normalize(enu * -forward));
  // Nearest possible visible surface is about `height` away (flat-earth bound is
  // conservative near the ground); keep near well inside it. Reverse-Z float depth keeps
  // ~24 bits of relative precision at every distance, so a small near costs nothing.
  nearMeters_ = std::clamp(0.25 * std::abs(pose.heightMeters), 0.01, 1000.0);
}

glm::dmat4 Camera::viewRotation() const { return glm::dmat4(glm::transpose(cameraToEcef_)); }

double Camera::focalLengthPx() const { return heightPx_ / (2.0 * std::tan(degreesToRadians(0.5 * fovYDeg_))); }

glm::dmat4 Camera::projection() const {
  const double f = 1.0 / std::tan(degreesToRadians(0.5 * fovYDeg_));
  const double aspect = static_cast<double>(widthPx_) / heightPx_;
  glm::dmat4 m(0.0);
  m[0][0] = f / aspect;
  m[1][1] = f;
  m[2][3] = -1.0;         // w = -z_eye
  m[3][2] = nearMeters_;  // z = near  -> ndc depth = near / distance in (0, 1]
  return m;
}

glm::dmat4 Camera::modelViewProjectionRelativeTo(const glm::dvec3& originEcef) const {
  glm::dmat4 mv = viewRotation();
  mv[3] = glm::dvec4(glm::transpose(cameraToEcef_) * (originEcef - eyeEcef_), 1.0);
  return projection() * mv;
}

std::optional<glm::dvec2> Camera::projectToPixel(const glm::dvec3& ecef) const {
  const glm::dvec3 e = glm::transpose(cameraToEcef_) * (ecef - eyeEcef_);
  if (e.z >= 0.0) return std::nullopt;
  const double f = focalLengthPx();
  const double x = 0.5 * widthPx_ + f * (e.x / -e.z);
  const double y = 0.5 * heightPx_ - f * (e.y / -e.z);
  return glm::dvec2(x, y);
}

glm::dvec3 Camera::pixelRayDirection(double xPx, double yPx) const {
  const double f = focalLengthPx();
  const glm::dvec3 e((xPx - 0.5 * widthPx_) / f, (0.5 * heightPx_ - yPx) / f, -1.0);
  return glm::normalize(cameraToEcef_ * e);
}

globe::ViewState Camera::viewState() const {
  globe::ViewState v;
  v.eyeEcef = eyeEcef_;
  v.pixelsPerRadian = focalLengthPx();
  const double tanY = std::tan(degreesToRadians(0.5 * fovYDeg_));
  const double tanX = tanY * widthPx_ / heightPx_;
  const glm::dvec3 fwd = forwardEcef(), right = rightEcef(), up = upEcef();
  auto plane = [&](const glm::dvec3& normal) {
    const glm::dvec3 n = glm::normalize(normal);
    return glm::dvec4(n, -glm::dot(n, eyeEcef_));
  };
  // Inward unit normals of the four side planes (each contains the eye), then near.
  // The projection has no far plane; the sixth plane sits 1e12 m away (past anything).
  v.frustumPlanesEcef[0] = plane(right + fwd * tanX);   // left plane, normal points right/in
  v.frustumPlanesEcef[1] = plane(-right + fwd * tanX);  // right plane
  v.frustumPlanesEcef[2] = plane(up + fwd * tanY);      // bottom plane
  v.frustumPlanesEcef[3] = plane(-up + fwd * tanY);     // top plane
  v.frustumPlanesEcef[4] = glm::dvec4(fwd, -glm::dot(fwd, eyeEcef_) - nearMeters_);  // near
  v.frustumPlanesEcef[5] = glm::dvec4(fwd, -glm::dot(fwd, eyeEcef_) + 1e12);         // far: 1e12 m away
  return v;
}

}  // namespace atmoglobe::engine
