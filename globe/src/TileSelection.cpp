#include <atmoglobe/globe/TileSelection.h>

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Horizon.h>
#include <atmoglobe/globe/TileMesh.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace atmoglobe::globe {

namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);  ///< first eccentricity squared
constexpr double kMinDistanceMeters = 1e-3;

/// Geodetic -> ECEF from precomputed sines/cosines (the textbook N(phi) formula, the same
/// one GeographicLib's Forward uses); for the many samples of the bounding sphere.
glm::dvec3 ecefFromTrig(double sinLat, double cosLat, double sinLon, double cosLon, double heightMeters) {
  const double n = kWgs84A / std::sqrt(1.0 - kWgs84E2 * sinLat * sinLat);
  const double r = (n + heightMeters) * cosLat;
  return {r * cosLon, r * sinLon, (n * (1.0 - kWgs84E2) + heightMeters) * sinLat};
}

double angleBetween(const glm::dvec3& u, const glm::dvec3& v) {
  return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

/// Direction of the scaled-space image of the surface point (latDeg, lonDeg, 0).
glm::dvec3 scaledDirection(double latDeg, double lonDeg) {
  const double lat = latDeg * kDegToRad, lon = lonDeg * kDegToRad;
  return glm::normalize(ecefToScaledSpace(ecefFromTrig(std::sin(lat), std::cos(lat), std::sin(lon), std::cos(lon), 0.0)));
}

/// Longitude difference to - from folded into [0, 360).
double eastwardDeg(double fromDeg, double toDeg) {
  double d = std::fmod(toDeg - fromDeg, 360.0);
  if (d < 0.0) d += 360.0;
  return d;
}

}  // namespace

double chordSagBoundMeters(const TileId& t, int segments) {
  assert(isValid(t) && segments >= 1);
  const GeoRectangle r = tileRectangle(t);
  const double stepDeg = (r.eastDeg - r.westDeg) / segments;
  // Cells of one row are congruent (rotation about the axis): one cell per row suffices.
  double rho = 0.0;
  for (int j = 0; j < segments; ++j) {
    const double northDeg = r.northDeg - stepDeg * j;
    const double southDeg = northDeg - stepDeg;
    const glm::dvec3 corners[4] = {scaledDirection(northDeg, 0.0), scaledDirection(northDeg, stepDeg),
                                   scaledDirection(southDeg, 0.0), scaledDirection(southDeg, stepDeg)};
    const glm::dvec3 sum = corners[0] + corners[1] + corners[2] + corners[3];
    if (glm::length(sum) < 1e-9) return kWgs84A;  // corners spread over a half-space
    const glm::dvec3 centre = glm::normalize(sum);
    for (const glm::dvec3& c : corners) rho = std::max(rho, angleBetween(centre, c));
  }
  if (rho >= 0.5 * M_PI) return kWgs84A;
  // 1 - cos(rho) = 2 sin^2(rho/2): no cancellation for tiny cells.
  const double s = std::sin(0.5 * rho);
  return kWgs84A * 2.0 * s * s;
}

double geometricErrorMeters(const TileId& t, const SelectionOptions& options) {
  assert(isValid(t));
  double error = chordSagBoundMeters(t, options.meshSegments);
  if (t.level < options.imageryMaxLevel) {
    const GeoRectangle r = tileRectangle(t);
    const double sizeRad = (r.eastDeg - r.westDeg) * kDegToRad;
    const double poleward = std::max(std::abs(r.northDeg), std::abs(r.southDeg)) * kDegToRad;
    const double equatorward =
        (r.southDeg <= 0.0 && r.northDeg >= 0.0) ? 0.0 : std::min(std::abs(r.northDeg), std::abs(r.southDeg)) * kDegToRad;
    auto w = [](double lat) { return std::sqrt(1.0 - kWgs84E2 * std::sin(lat) * std::sin(lat)); };
    const double meridianRadius = kWgs84A * (1.0 - kWgs84E2) / (w(poleward) * w(poleward) * w(poleward));
    const double parallelRadius = kWgs84A / w(equatorward) * std::cos(equatorward);
    constexpr double kImageryTileWidthPx = 256.0;
    error = std::max(error, std::max(meridianRadius, parallelRadius) * sizeRad / kImageryTileWidthPx);
  }
  return error;
}

double tileDistanceMeters(const TileId& t, const glm::dvec3& eyeEcef) {
  assert(isValid(t));
  const Geodetic eye = ecefToGeodetic(eyeEcef);
  const GeoRectangle r = tileRectangle(t);
  const double sizeDeg = r.eastDeg - r.westDeg;
  const bool latInside = eye.latDeg >= r.southDeg && eye.latDeg <= r.northDeg;
  const bool lonInside = eastwardDeg(r.westDeg, eye.lonDeg) <= sizeDeg;
  if (latInside && lonInside) return std::max(std::abs(eye.heightMeters), kMinDistanceMeters);
  const double latDeg = std::clamp(eye.latDeg, r.southDeg, r.northDeg);
  double lonDeg = eye.lonDeg;
  if (!lonInside) {
    // The nearer edge, going round either way (handles the antimeridian).
    lonDeg = eastwardDeg(eye.lonDeg, r.westDeg) <= eastwardDeg(r.eastDeg, eye.lonDeg) ? r.westDeg : r.eastDeg;
  }
  return std::max(glm::length(eyeEcef - geodeticToEcef({latDeg, lonDeg, 0.0})), kMinDistanceMeters);
}

double screenSpaceErrorPx(const TileId& t, const ViewState& view, const SelectionOptions& options) {
  return geometricErrorMeters(t, options) * view.pixelsPerRadian / tileDistanceMeters(t, view.eyeEcef);
}

TileBounds computeTileBounds(const TileId& t, double minHeightMeters, double maxHeightMeters) {
  return computeTileBounds(t, minHeightMeters, maxHeightMeters, kDefaultMeshSegments);
}

TileBounds computeTileBounds(const TileId& t, double minHeightMeters, double maxHeightMeters, int meshSegments) {
  assert(isValid(t) && meshSegments >= 1);
  assert(std::isfinite(minHeightMeters) && std::isfinite(maxHeightMeters) && minHeightMeters <= maxHeightMeters);
  const double lowHeight = std::min(minHeightMeters, -skirtDepthMeters(t, meshSegments));
  const double highHeight = maxHeightMeters;
  constexpr int kCells = 32;
  const GeoRectangle r = tileRectangle(t);
  const double stepDeg = (r.eastDeg - r.westDeg) / kCells;

  double sinLat[kCells + 1], cosLat[kCells + 1], sinLon[kCells + 1], cosLon[kCells + 1];
  for (int k = 0; k <= kCells; ++k) {
    const double lat = (r.northDeg - stepDeg * k) * kDegToRad, lon = (r.westDeg + stepDeg * k) * kDegToRad;
    sinLat[k] = std::sin(lat);
    cosLat[k] = std::cos(lat);
    sinLon[k] = std::sin(lon);
    cosLon[k] = std::cos(lon);
  }
  auto forEachSample = [&](auto&& f) {
    for (int j = 0; j <= kCells; ++j) {
      for (int i = 0; i <= kCells; ++i) {
        f(ecefFromTrig(sinLat[j], cosLat[j], sinLon[i], cosLon[i], lowHeight));
        f(ecefFromTrig(sinLat[j], cosLat[j], sinLon[i], cosLon[i], highHeight));
      }
    }
  };
  glm::dvec3 lo(1e300), hi(-1e300);
  forEachSample([&](const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  });
  TileBounds b;
  b.sphereCenterEcef = 0.5 * (lo + hi);
  double maxDistSq = 0.0;
  forEachSample([&](const glm::dvec3& p) {
    const glm::dvec3 d = p - b.sphereCenterEcef;
    maxDistSq = std::max(maxDistSq, glm::dot(d, d));
  });
  // Any point of a cell is within half a meridian step plus half a parallel step (at the
  // widest parallel of the tile) of a sample; radii of curvature are <= a^2/b.
  const double equatorward =
      (r.southDeg <= 0.0 && r.northDeg >= 0.0) ? 0.0 : std::min(std::abs(r.northDeg), std::abs(r.southDeg));
  const double radiusBound = kWgs84A * kWgs84A / kWgs84B + std::max(highHeight, 0.0);
  const double stepRad = stepDeg * kDegToRad;
  const double margin = 0.5 * radiusBound * stepRad * (1.0 + std::cos(equatorward * kDegToRad));
  b.sphereRadiusMeters = std::sqrt(maxDistSq) + margin;
  b.horizonPointEcef = horizonCullingPoint(t, minHeightMeters, maxHeightMeters);
  return b;
}

std::vector<TileId> selectTiles(const ViewState& view, const SelectionOptions& options, SelectionStats* stats) {
  assert(options.maxLevel >= 0 && options.maxLevel <= kMaxTileLevel && options.meshSegments >= 1);
  SelectionStats local;
  std::vector<TileId> selected;
  const glm::dvec3 eyeScaled = ecefToScaledSpace(view.eyeEcef);
  // Explicit stack, children pushed in reverse so they pop north-west first.
  std::vector<TileId> stack = {{0, 1, 0}, {0, 0, 0}};
  while (!stack.empty()) {
    const TileId t = stack.back();
    stack.pop_back();
    ++local.visited;
    const TileBounds b = computeTileBounds(t, -500.0, 100.0, options.meshSegments);
    bool outside = false;
    for (const glm::dvec4& plane : view.frustumPlanesEcef) {
      if (glm::dot(glm::dvec3(plane), b.sphereCenterEcef) + plane.w < -b.sphereRadiusMeters) {
        outside = true;
        break;
      }
    }
    if (outside) {
      ++local.culledFrustum;
      continue;
    }
    if (b.horizonPointEcef && isScaledSpacePointOccluded(eyeScaled, ecefToScaledSpace(*b.horizonPointEcef))) {
      ++local.culledHorizon;
      continue;
    }
    if (t.level < options.maxLevel && screenSpaceErrorPx(t, view, options) > options.maxScreenSpaceErrorPx) {
      for (int i = 3; i >= 0; --i) stack.push_back(childTile(t, i));
      continue;
    }
    selected.push_back(t);
    local.maxLevel = std::max(local.maxLevel, t.level);
  }
  local.selected = static_cast<int>(selected.size());
  if (stats) *stats = local;
  return selected;
}

}  // namespace atmoglobe::globe
