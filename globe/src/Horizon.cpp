#include <atmoglobe/globe/Horizon.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace atmoglobe::globe {

namespace {
const glm::dvec3 kRadii(kWgs84A, kWgs84A, kWgs84B);

/// Angle (rad) between two non-zero vectors; atan2 keeps it accurate for tiny angles.
double angleBetween(const glm::dvec3& u, const glm::dvec3& v) {
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}
}  // namespace

glm::dvec3 ecefToScaledSpace(const glm::dvec3& ecef) { return ecef / kRadii; }
glm::dvec3 scaledSpaceToEcef(const glm::dvec3& scaled) { return scaled * kRadii; }

bool isScaledSpacePointOccluded(const glm::dvec3& eyeScaled, const glm::dvec3& pointScaled) {
  // |V|^2 - 1: squared distance from the eye to its horizon circle (scaled units).
  const double horizonDistanceSq = glm::dot(eyeScaled, eyeScaled) - 1.0;
  if (!(horizonDistanceSq > 0.0)) return false;  // eye inside: cull nothing
  const glm::dvec3 eyeToPoint = pointScaled - eyeScaled;
  // -(P - V).V > |V|^2 - 1  <=>  P.V < 1: beyond the horizon plane.
  const double towardCentre = -glm::dot(eyeToPoint, eyeScaled);
  if (!(towardCentre > horizonDistanceSq)) return false;
  // Inside the tangent cone: cos^2(angle to -V) > cos^2(half-angle) = (|V|^2-1)/|V|^2.
  return towardCentre * towardCentre > horizonDistanceSq * glm::dot(eyeToPoint, eyeToPoint);
}

bool isOccludedByEllipsoid(const glm::dvec3& eyeEcef, const glm::dvec3& pointEcef) {
  return isScaledSpacePointOccluded(ecefToScaledSpace(eyeEcef), ecefToScaledSpace(pointEcef));
}

std::optional<glm::dvec3> horizonCullingPoint(const TileId& t, double minHeightMeters, double maxHeightMeters) {
  assert(isValid(t));
  assert(std::isfinite(minHeightMeters) && std::isfinite(maxHeightMeters) && minHeightMeters <= maxHeightMeters);
  (void)minHeightMeters;  // everything below the ellipsoid is hidden anyway
  constexpr int kSamples = 8;  // cells per edge
  const double topHeight = std::max(maxHeightMeters, 0.0);
  const GeoRectangle r = tileRectangle(t);
  const double stepDeg = (r.eastDeg - r.westDeg) / kSamples;
  // Pad the latitudes by half a step: the tile's north/south edges are small circles, which
  // bulge (toward the equator) past the great-circle arcs between samples by at most
  // step^2/16 rad, far less than step/2; the padding also absorbs the tiny difference
  // between the direction of a point at topHeight and of its foot on the ellipsoid.
  const double southDeg = std::max(r.southDeg - 0.5 * stepDeg, -90.0);
  const double northDeg = std::min(r.northDeg + 0.5 * stepDeg, 90.0);
  const double latStepDeg = (northDeg - southDeg) / kSamples;

  auto direction = [&](double latDeg, double lonDeg) {
    return glm::normalize(ecefToScaledSpace(geodeticToEcef({latDeg, lonDeg, topHeight})));
  };
  glm::dvec3 dirs[kSamples + 1][kSamples + 1];
  for (int j = 0; j <= kSamples; ++j) {
    for (int i = 0; i <= kSamples; ++i) dirs[j][i] = direction(northDeg - latStepDeg * j, r.westDeg + stepDeg * i);
  }
  // rho: how far (angle) any sample cell's corners are from that cell's centre direction.
  double rho = 0.0;
  for (int j = 0; j < kSamples; ++j) {
    for (int i = 0; i < kSamples; ++i) {
      const glm::dvec3 centre = direction(northDeg - latStepDeg * (j + 0.5), r.westDeg + stepDeg * (i + 0.5));
      for (int k = 0; k < 4; ++k) rho = std::max(rho, angleBetween(centre, dirs[j + (k >> 1)][i + (k & 1)]));
    }
  }
  constexpr double kHalfPi = 1.5707963267948966;
  if (rho >= kHalfPi) return std::nullopt;
  // Every point of the tile surface at topHeight has scaled radius <= 1 + topHeight/b.
  const double sampleRadius = (1.0 + topHeight / kWgs84B) / std::cos(rho);
  const double horizonAngle = std::acos(1.0 / sampleRadius);  // angular radius of C(sample)

  const glm::dvec3 d = direction(0.5 * (r.northDeg + r.southDeg), 0.5 * (r.westDeg + r.eastDeg));
  double maxAngle = 0.0;
  for (auto& row : dirs) {
    for (const glm::dvec3& s : row) maxAngle = std::max(maxAngle, angleBetween(s, d));
  }
  const double total = maxAngle + horizonAngle;
  // Keep well away from 90 degrees, where the point runs off to infinity.
  if (total >= kHalfPi - 1e-6) return std::nullopt;
  const double magnitude = 1.0 / std::cos(total);
  return scaledSpaceToEcef(d * magnitude);
}

}  // namespace atmoglobe::globe
