#pragma once
// Mouse interaction for the viewer, GL-free so tests can drive it: each function changes
// a CameraPose from pointer movement in pixels.
#include <atmoglobe/engine/Camera.h>

namespace atmoglobe::engine {

/// Lowest and highest camera heights the controller goes to (m above the ellipsoid).
inline constexpr double kMinControllerHeightMeters = 1.0;
inline constexpr double kMaxControllerHeightMeters = 1e8;

/// Drag: moves the camera over the ground so that the ground below follows the pointer
/// (exact for a camera looking straight down at the nadir scale; the pixel scale is
/// height / focal length).
void orbitByPixels(CameraPose& pose, double fovYDeg, int heightPx, double dxPx, double dyPx);

/// Wheel: scales the height by `factor` (< 1 zooms in) and moves toward the ground point
/// under pixel (xPx, yPx) by the same proportion, so that point stays under the pointer
/// for a camera looking down. A pointer off the globe zooms about the view centre.
void zoomTowardPixel(CameraPose& pose, double fovYDeg, int widthPx, int heightPx, double xPx, double yPx,
                     double factor);

/// Modifier-drag: vertical motion tilts (pitch, clamped to [-90, 0]), horizontal turns
/// (heading), 0.2 degrees per pixel.
void tiltByPixels(CameraPose& pose, double dxPx, double dyPx);

}  // namespace atmoglobe::engine
