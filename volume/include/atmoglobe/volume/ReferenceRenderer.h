#pragma once
// The CPU reference renderer of a PolarVolume: double precision, the exact inverse geolocation
// (antennaCoordinatesExact) at every sample, the sampling rule of PolarVolume.h and the transfer
// function of TransferFunction.h. It is the yardstick for every error figure of the GPU marcher
// (which implements the same rules: docs/volume-rendering.md). GL-free, no engine dependency:
// the camera comes as plain data with the engine::Camera convention.
//
// Per pixel (see renderReference for the full rule):
//   ray from the eye through the pixel centre; samples at t_i = (i + 0.5) * step (metres from
//   the eye, so the sample grid is anchored at the eye, not at the volume's entry point) for
//   every i whose t_i lies inside the ray's intersection with the sphere of radius
//   clipRadiusMeters (PolarVolume.h; the brief said maxRange, which cuts the far top of the
//   shell, see docs/volume-rendering.md) around the antenna and before the ray's first hit of the WGS84 ellipsoid.
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/TransferFunction.h>

#include <glm/glm.hpp>

#include <optional>
#include <vector>

namespace atmoglobe::volume {

enum class VolumeRenderMode { Dvr, Mip, Iso };

struct VolumeRenderSettings {
  VolumeRenderMode mode = VolumeRenderMode::Dvr;
  Interpolation interpolation = Interpolation::Linear;
  double stepMeters = 250.0;               ///< sample spacing along the ray (m), > 0
  TransferFunction transfer;               ///< DVR colour/opacity; MIP and ISO colours
  double isoValue = 40.0;                  ///< ISO threshold (field units)
  double earlyTerminationAlpha = 0.99;     ///< DVR stops once accumulated alpha >= this (> 1: never)
};

/// Pinhole camera, same convention as engine::Camera: eye space x right, y up, looking down -z;
/// pixel (i, j) has its centre at (i + 0.5, j + 0.5), origin top-left, y down; square pixels.
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

/// Premultiplied RGBA in [0, 1] per pixel, row-major, row 0 = top of the image.
struct VolumeImage {
  int widthPx = 0;
  int heightPx = 0;
  std::vector<glm::dvec4> rgbaPremultiplied;
  const glm::dvec4& at(int x, int y) const {
    return rgbaPremultiplied[static_cast<std::size_t>(y) * static_cast<std::size_t>(widthPx) + static_cast<std::size_t>(x)];
  }
};

/// Renders `volume` with the double-precision reference rule. For each pixel:
///  - samples at t_i = (i + 0.5) * stepMeters along the unit ray from the eye, for every i with
///    tEnter <= t_i <= tExit (the ray's intersection with the sphere of radius
///    volume.clipRadiusMeters around the antenna, ECEF) and, if occludeByEllipsoid, t_i < the ray's first hit of the
///    WGS84 ellipsoid (globe::intersectRayEllipsoid);
///  - each sample: antennaCoordinatesExact -> samplePolar(settings.interpolation);
///  - DVR: for Echo samples c = classify(value), a_s = correctedOpacity(c.a, step), front to back
///    premultiplied: C += (1 - A) a_s c.rgb, A += (1 - A) a_s; stop once A >= earlyTerminationAlpha;
///  - MIP: the largest Echo value m along the ray; pixel = (classify(m).rgb * a, a), a =
///    classify(m).a (no step correction); no Echo: transparent;
///  - ISO: the first sample i with Echo value >= isoValue; between lo = t_i - step (the previous
///    sample position, not clamped) and hi = t_i, 8 bisection steps on the predicate "samplePolar
///    is Echo with value >= isoValue" (true -> hi = mid, else lo = mid); the surface point is
///    p = eye + 0.5 (lo + hi) dir. Normal n = -normalize(grad f) with f = the Echo value, or
///    opacityZeroValue for NoEcho/NoData, by central differences along ECEF x, y, z with delta =
///    stepMeters / 2 (zero gradient: shade 1). Pixel = (classify(isoValue).rgb * (0.3 + 0.7
///    |dot(n, dir)|), 1). No crossing: transparent.
/// Rows are split over `threads` std::threads (row y goes to thread y mod threads); the result
/// does not depend on the thread count. Cost: one antennaCoordinatesExact (~1 us) per sample,
/// except where `rejectOutsideShell` proves a sample NoData by its straight-line elevation
/// (outside the band of beam elevations widened by the beam's bending and 0.25 deg; see
/// ReferenceRenderer.cpp): an acceleration only, the image is bit-identical (tested).
VolumeImage renderReference(const PolarVolume& volume, const VolumeRenderSettings& settings,
                            const RenderCamera& camera, bool occludeByEllipsoid = true, int threads = 2,
                            bool rejectOutsideShell = true);

/// The colour of one ray (premultiplied RGBA) by the rule of renderReference.
glm::dvec4 renderReferenceRay(const PolarVolume& volume, const VolumeRenderSettings& settings,
                              const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, bool occludeByEllipsoid);

/// Image difference for the bench and the tests: both images composited over black (the
/// premultiplied RGB, clamped to [0, 1]), quantised to 8 bits (round(255 c)), compared per RGB
/// channel. meanAbs / maxAbs in 8-bit steps (0..255); psnrDb = 10 log10(255^2 / MSE), +inf when
/// equal. Precondition (asserted): equal sizes.
struct ImageError {
  double meanAbs = 0.0;
  double maxAbs = 0.0;
  double psnrDb = 0.0;
};
ImageError compareImages(const VolumeImage& a, const VolumeImage& b);

}  // namespace atmoglobe::volume
