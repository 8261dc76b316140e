// The reference renderers' camera (RenderCamera.h).
#include <atmoglobe/volume/RenderCamera.h>

#include <atmoglobe/globe/Angles.h>

#include <cassert>
#include <cmath>

namespace atmoglobe::volume {

RenderCamera makeLookAtCamera(const glm::dvec3& eyeEcef, const glm::dvec3& targetEcef, const glm::dvec3& upHintEcef,
                              double fovYDeg, int widthPx, int heightPx) {
  assert(fovYDeg > 0.0 && fovYDeg < 180.0 && widthPx >= 1 && heightPx >= 1);
  const glm::dvec3 forward = glm::normalize(targetEcef - eyeEcef);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, upHintEcef));
  const glm::dvec3 up = glm::cross(right, forward);
  RenderCamera cam;
  cam.eyeEcef = eyeEcef;
  cam.cameraToEcef = glm::dmat3(right, up, -forward);
  cam.focalLengthPx = heightPx / (2.0 * std::tan(0.5 * degreesToRadians(fovYDeg)));
  cam.widthPx = widthPx;
  cam.heightPx = heightPx;
  return cam;
}

glm::dvec3 pixelRayDirection(const RenderCamera& camera, double xPx, double yPx) {
  const double f = camera.focalLengthPx;
  const glm::dvec3 e((xPx - 0.5 * camera.widthPx) / f, (0.5 * camera.heightPx - yPx) / f, -1.0);
  return glm::normalize(camera.cameraToEcef * e);
}

std::optional<glm::dvec2> projectToPixel(const RenderCamera& camera, const glm::dvec3& ecef) {
  const glm::dvec3 e = glm::transpose(camera.cameraToEcef) * (ecef - camera.eyeEcef);
  if (e.z >= 0.0) return std::nullopt;
  const double f = camera.focalLengthPx;
  return glm::dvec2(0.5 * camera.widthPx + f * (e.x / -e.z), 0.5 * camera.heightPx - f * (e.y / -e.z));
}

}  // namespace atmoglobe::volume
