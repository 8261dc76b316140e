#include <atmoglobe/globe/Horizon.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace atmoglobe::globe {

namespace {
const glm::dvec3 kRadii(kWgs84A, kWgs84A, kWgs84B);

/// Angle (rad) between two non-zero vectors; atan2 keeps it accurate for tiny angles.
/// Squared chord between two unit vectors: increases with the angle between them, which is
/// 2 asin(chord / 2) (accurate for tiny angles, unlike acos of a dot product).
double chordSq(const glm::dvec3& u, const glm::dvec3& v) {
  const glm::dvec3 d = u - v;
  return glm::dot(d, d);
}
double angleFromChordSq(double c2) { return 2.0 * std::asin(std::min(1.0, 0.5 * std::sqrt(c2))); }
}  // namespace

glm::dvec3 ecefFromSinCos(double sinLat, double cosLat, double sinLon, double cosLon, double heightMeters) {
  const double n = kWgs84A / std::sqrt(1.0 - kWgs84E2 * sinLat * sinLat);
  const double r = (n + heightMeters) * cosLat;
  return {r * cosLon, r * sinLon, (n * (1.0 - kWgs84E2) + heightMeters) * sinLat};
}

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
  (void)minHeightMeters;       // everything below the ellipsoid is hidden anyway
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

  // Sines and cosines of the sample rows/columns (k even) and of the cell centres (k odd).
  double sinLat[2 * kSamples + 1], cosLat[2 * kSamples + 1], sinLon[2 * kSamples + 1], cosLon[2 * kSamples + 1];
  for (int k = 0; k <= 2 * kSamples; ++k) {
    const double lat = degreesToRadians(northDeg - 0.5 * latStepDeg * k);
    const double lon = degreesToRadians(r.westDeg + 0.5 * stepDeg * k);
    sinLat[k] = std::sin(lat), cosLat[k] = std::cos(lat), sinLon[k] = std::sin(lon), cosLon[k] = std::cos(lon);
  }
  auto direction = [&](int j2, int i2) {  // half-step indices
    return glm::normalize(ecefToScaledSpace(ecefFromSinCos(sinLat[j2], cosLat[j2], sinLon[i2], cosLon[i2], topHeight)));
  };
  glm::dvec3 dirs[kSamples + 1][kSamples + 1];
  for (int j = 0; j <= kSamples; ++j) {
    for (int i = 0; i <= kSamples; ++i) dirs[j][i] = direction(2 * j, 2 * i);
  }
  // rho: how far (angle) any sample cell's corners are from that cell's centre direction.
  double rhoChordSq = 0.0;
  for (int j = 0; j < kSamples; ++j) {
    for (int i = 0; i < kSamples; ++i) {
      const glm::dvec3 centre = direction(2 * j + 1, 2 * i + 1);
      for (int k = 0; k < 4; ++k) rhoChordSq = std::max(rhoChordSq, chordSq(centre, dirs[j + (k >> 1)][i + (k & 1)]));
    }
  }
  const double rho = angleFromChordSq(rhoChordSq);
  if (rho >= kPi / 2.0) return std::nullopt;
  // Every point of the tile surface at topHeight has scaled radius <= 1 + topHeight/b.
  const double sampleRadius = (1.0 + topHeight / kWgs84B) / std::cos(rho);
  const double horizonAngle = std::acos(1.0 / sampleRadius);  // angular radius of C(sample)

  const glm::dvec3 d = direction(kSamples, kSamples);  // the middle of the (padded) grid
  double maxChordSq = 0.0;
  for (auto& row : dirs) {
    for (const glm::dvec3& s : row) maxChordSq = std::max(maxChordSq, chordSq(s, d));
  }
  const double total = angleFromChordSq(maxChordSq) + horizonAngle;
  // Keep well away from 90 degrees, where the point runs off to infinity.
  if (total >= kPi / 2.0 - 1e-6) return std::nullopt;
  const double magnitude = 1.0 / std::cos(total);
  return scaledSpaceToEcef(d * magnitude);
}

}  // namespace atmoglobe::globe
