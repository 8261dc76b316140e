#include <atmoglobe/globe/TileSelection.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Horizon.h>
#include <atmoglobe/globe/TileMesh.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace atmoglobe::globe {

namespace {

constexpr double kMinDistanceMeters = 1e-3;

/// Squared chord between two unit vectors: increases with the angle between them, which is
/// 2 asin(chord / 2) (accurate for tiny angles, unlike acos of a dot product).
double chordSq(const glm::dvec3& u, const glm::dvec3& v) {
  const glm::dvec3 d = u - v;
  return glm::dot(d, d);
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
  // Cells of one row are congruent (rotation about the axis): one cell per row suffices,
  // the one between longitudes 0 and step.
  const double sinStep = std::sin(degreesToRadians(stepDeg)), cosStep = std::cos(degreesToRadians(stepDeg));
  auto rowDirections = [&](int j, glm::dvec3& west, glm::dvec3& east) {
    const double lat = degreesToRadians(r.northDeg - stepDeg * j);
    const double sinLat = std::sin(lat), cosLat = std::cos(lat);
    west = glm::normalize(ecefToScaledSpace(ecefFromSinCos(sinLat, cosLat, 0.0, 1.0, 0.0)));
    east = glm::normalize(ecefToScaledSpace(ecefFromSinCos(sinLat, cosLat, sinStep, cosStep, 0.0)));
  };
  double rhoChordSq = 0.0;  // squared chord 2 sin(rho/2) of the largest corner angle
  glm::dvec3 nw, ne, sw, se;
  rowDirections(0, nw, ne);
  for (int j = 0; j < segments; ++j) {
    rowDirections(j + 1, sw, se);
    const glm::dvec3 sum = nw + ne + sw + se;
    if (glm::length(sum) < 1e-9) return kWgs84A;  // corners spread over a half-space
    const glm::dvec3 centre = glm::normalize(sum);
    for (const glm::dvec3& c : {nw, ne, sw, se}) rhoChordSq = std::max(rhoChordSq, chordSq(centre, c));
    nw = sw;
    ne = se;
  }
  if (rhoChordSq >= 2.0) return kWgs84A;  // rho >= 90 degrees
  // a (1 - cos(rho)) = a 2 sin^2(rho/2) = a chord^2 / 2: no cancellation for tiny cells.
  return kWgs84A * 0.5 * rhoChordSq;
}

double geometricErrorMeters(const TileId& t, const SelectionOptions& options) {
  assert(isValid(t));
  double error = chordSagBoundMeters(t, options.meshSegments);
  if (t.level < options.imageryMaxLevel) {
    const GeoRectangle r = tileRectangle(t);
    const double sizeRad = degreesToRadians(r.eastDeg - r.westDeg);
    const double poleward = degreesToRadians(std::max(std::abs(r.northDeg), std::abs(r.southDeg)));
    const double equatorward = (r.southDeg <= 0.0 && r.northDeg >= 0.0)
                                   ? 0.0
                                   : degreesToRadians(std::min(std::abs(r.northDeg), std::abs(r.southDeg)));
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
    const double lat = degreesToRadians(r.northDeg - stepDeg * k), lon = degreesToRadians(r.westDeg + stepDeg * k);
    sinLat[k] = std::sin(lat);
    cosLat[k] = std::cos(lat);
    sinLon[k] = std::sin(lon);
    cosLon[k] = std::cos(lon);
  }
  // Per row and height: the distance from the axis and z (prime-vertical radius N(lat)).
  double axial[2][kCells + 1], zs[2][kCells + 1];
  const double heights[2] = {lowHeight, highHeight};
  for (int j = 0; j <= kCells; ++j) {
    const double n = kWgs84A / std::sqrt(1.0 - kWgs84E2 * sinLat[j] * sinLat[j]);
    for (int k = 0; k < 2; ++k) {
      axial[k][j] = (n + heights[k]) * cosLat[j];
      zs[k][j] = (n * (1.0 - kWgs84E2) + heights[k]) * sinLat[j];
    }
  }
  auto forEachSample = [&](auto&& f) {
    for (int k = 0; k < 2; ++k) {
      for (int j = 0; j <= kCells; ++j) {
        for (int i = 0; i <= kCells; ++i) f(glm::dvec3(axial[k][j] * cosLon[i], axial[k][j] * sinLon[i], zs[k][j]));
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
  const double stepRad = degreesToRadians(stepDeg);
  const double margin = 0.5 * radiusBound * stepRad * (1.0 + std::cos(degreesToRadians(equatorward)));
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
