#pragma once
// The camera: defined and evaluated in double precision.
//
// Convention (also in the README; tests and users place things with it):
//  - Position: WGS84 geodetic latitude/longitude (degrees) and height above the
//    ellipsoid (m).
//  - Orientation relative to the local east-north-up frame at that position:
//      heading: degrees clockwise from north (0 = north, 90 = east), about local up;
//      pitch:   degrees above the local horizontal (0 = horizontal, -90 = straight down,
//               +90 = straight up);
//      roll:    degrees about the viewing direction; positive banks the camera to the
//               right like an aircraft (its right side goes down), so the picture's
//               content turns counter-clockwise.
//    With pitch -90 and heading 0 the camera looks straight down with north at the top
//    of the image and east to the right.
//  - fovYDeg: vertical field of view (degrees). The horizontal one follows from the
//    image aspect ratio (square pixels).
//  - Pixels: origin at the top-left corner of the image, x to the right, y down; the
//    centre of pixel (i, j) is at (i + 0.5, j + 0.5).
//
// Eye space is OpenGL's: x right, y up, looking down -z. The view transform is a pure
// rotation: the camera translation is removed in double on the CPU (positions are
// handed to the GPU relative to the eye), so float32 never holds an ECEF coordinate.
// Depth: reverse-Z with an infinite far plane into a 32-bit float depth buffer
// (glClipControl ZERO_TO_ONE; clear to 0, GL_GREATER): depth = near / distance, whose
// float relative precision (~6e-8) is the same at every distance, so 1 m and 1e8 m
// cameras both resolve depth. Logarithmic depth would need gl_FragDepth writes, which
// disable early-Z (expensive on llvmpipe); reverse-Z keeps it.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/globe/TileSelection.h>

#include <glm/glm.hpp>

#include <optional>

namespace atmoglobe::engine {

struct CameraPose {
  double latDeg = 0.0;        ///< geodetic latitude (degrees)
  double lonDeg = 0.0;        ///< longitude (degrees)
  double heightMeters = 1e7;  ///< above the WGS84 ellipsoid (m)
  double headingDeg = 0.0;    ///< clockwise from north (degrees)
  double pitchDeg = -90.0;    ///< above horizontal (degrees); -90 looks straight down
  double rollDeg = 0.0;       ///< about the view direction (degrees)
};

/// Checks a pose given by a user: finite, latitude in [-90, 90], pitch in [-90, 90],
/// height above -6.3e6 m (inside the Earth is allowed but not through its centre).
Status validatePose(const CameraPose& pose);

class Camera {
 public:
  /// fovYDeg in (0, 180); widthPx, heightPx >= 1. Validate user input first.
  Camera(const CameraPose& pose, double fovYDeg, int widthPx, int heightPx);

  const CameraPose& pose() const { return pose_; }
  double fovYDeg() const { return fovYDeg_; }
  int widthPx() const { return widthPx_; }
  int heightPx() const { return heightPx_; }

  const glm::dvec3& eyeEcef() const { return eyeEcef_; }
  /// Unit vectors in ECEF.
  glm::dvec3 forwardEcef() const { return -cameraToEcef_[2]; }
  glm::dvec3 rightEcef() const { return cameraToEcef_[0]; }
  glm::dvec3 upEcef() const { return cameraToEcef_[1]; }
  /// Columns: eye-space x (right), y (up), z (backwards) in ECEF.
  const glm::dmat3& cameraToEcef() const { return cameraToEcef_; }

  /// Near plane distance (m): chosen from the height so that the nearest visible ground
  /// is never clipped; with reverse-Z float depth the near plane does not limit
  /// precision elsewhere.
  double nearMeters() const { return nearMeters_; }

  /// Rotation ECEF -> eye space (no translation). Apply to (p - eyeEcef()).
  glm::dmat4 viewRotation() const;
  /// Reverse-Z infinite perspective (clip z = near, clip w = -z_eye).
  glm::dmat4 projection() const;
  /// projection() * viewRotation() * translate(originEcef - eye): maps positions given
  /// relative to `originEcef` (m) to clip space. Computed in double; narrow to float
  /// only after this, so the large translation never passes through float32.
  glm::dmat4 modelViewProjectionRelativeTo(const glm::dvec3& originEcef) const;

  /// Pixel position (double, see the convention) of an ECEF point, or nullopt when it
  /// is behind the camera. The yardstick for the rendering precision tests.
  std::optional<glm::dvec2> projectToPixel(const glm::dvec3& ecef) const;
  /// Unit direction (ECEF) of the ray through pixel position (x, y).
  glm::dvec3 pixelRayDirection(double xPx, double yPx) const;

  /// Focal length in pixels: heightPx / (2 tan(fovY / 2)).
  double focalLengthPx() const;
  /// The view for tile selection (frustum planes in ECEF).
  globe::ViewState viewState() const;

 private:
  CameraPose pose_;
  double fovYDeg_;
  int widthPx_;
  int heightPx_;
  glm::dvec3 eyeEcef_;
  glm::dmat3 cameraToEcef_;
  double nearMeters_;
};

}  // namespace atmoglobe::engine
