#pragma once
// The pinhole camera of the CPU renderers as plain data (no engine dependency), with the
// engine::Camera convention (README, "Camera convention"): eye space x right, y up, looking
// down -z; pixel (i, j) has its centre at (i + 0.5, j + 0.5), origin top-left, y down; square
// pixels. GL-free, double precision.
#include <glm/glm.hpp>

#include <optional>

namespace atmoglobe::volume {

struct RenderCamera {
  glm::dvec3 eyeEcef{0.0};       ///< (m)
  glm::dmat3 cameraToEcef{1.0};  ///< columns: eye x (right), y (up), z (backwards) as ECEF unit vectors
  double focalLengthPx = 1.0;    ///< heightPx / (2 tan(fovY / 2)) (pixels)
  int widthPx = 1;
  int heightPx = 1;
};

/// A camera at `eyeEcef` looking at `targetEcef` (m) with `upHintEcef` (not parallel to the view
/// direction) as the image's up, vertical field of view fovYDeg (degrees, in (0, 180)).
RenderCamera makeLookAtCamera(const glm::dvec3& eyeEcef, const glm::dvec3& targetEcef, const glm::dvec3& upHintEcef,
                              double fovYDeg, int widthPx, int heightPx);

/// Unit direction (ECEF) of the ray through pixel position (xPx, yPx) (pixel units, see the
/// convention; the centre of pixel (i, j) is (i + 0.5, j + 0.5)).
glm::dvec3 pixelRayDirection(const RenderCamera& camera, double xPx, double yPx);

/// Pixel position of an ECEF point (m), nullopt when it is not in front of the camera.
std::optional<glm::dvec2> projectToPixel(const RenderCamera& camera, const glm::dvec3& ecef);

}  // namespace atmoglobe::volume
