// Tests of tile selection, bounds and horizon culling (globe/TileSelection.h, Horizon.h).
// The camera maths (frustum planes, rays through pixels, ray-ellipsoid hits) is written
// here, independently of the engine.
#include <atmoglobe/globe/TileSelection.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Horizon.h>
#include <atmoglobe/globe/TileMesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <tuple>

namespace atmoglobe::globe {
namespace {

struct Camera {
  glm::dvec3 eye, forward, right, up;
  double tanHalfFovY, aspect;
  int heightPx;
};

Camera makeCamera(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& upHint, double fovYDeg,
                  double aspect, int heightPx) {
  Camera c;
  c.eye = eye;
  c.forward = glm::normalize(target - eye);
  c.right = glm::normalize(glm::cross(c.forward, upHint));
  c.up = glm::cross(c.right, c.forward);
  c.tanHalfFovY = std::tan(degreesToRadians(0.5 * fovYDeg));
  c.aspect = aspect;
  c.heightPx = heightPx;
  return c;
}

/// Frustum planes of a symmetric perspective: inside iff n.p + d >= 0. Side planes pass
/// through the eye; a point at depth z = (p - eye).forward along the camera axis is inside
/// iff |(p - eye).right| <= aspect tan(fovY/2) z and |(p - eye).up| <= tan(fovY/2) z.
ViewState makeView(const Camera& c, double nearMeters, double farMeters) {
  ViewState v;
  v.eyeEcef = c.eye;
  const double tx = c.aspect * c.tanHalfFovY, ty = c.tanHalfFovY;
  auto throughEye = [&](const glm::dvec3& n) {
    const glm::dvec3 u = glm::normalize(n);
    return glm::dvec4(u, -glm::dot(u, c.eye));
  };
  v.frustumPlanesEcef = {throughEye(c.right + tx * c.forward),
                         throughEye(-c.right + tx * c.forward),
                         throughEye(c.up + ty * c.forward),
                         throughEye(-c.up + ty * c.forward),
                         glm::dvec4(c.forward, -(glm::dot(c.forward, c.eye) + nearMeters)),
                         glm::dvec4(-c.forward, glm::dot(c.forward, c.eye) + farMeters)};
  v.pixelsPerRadian = c.heightPx / (2.0 * c.tanHalfFovY);
  return v;
}

/// A camera at (lat, lon, height) looking straight down, north up the screen.
Camera cameraLookingDown(double latDeg, double lonDeg, double heightMeters, double fovYDeg = 60.0) {
  const glm::dvec3 eye = geodeticToEcef({latDeg, lonDeg, heightMeters});
  const glm::dmat3 enu = enuAxes(latDeg, lonDeg);
  return makeCamera(eye, eye - enu[2], enu[1], fovYDeg, 1.5, 1000);
}

/// Planes that accept everything (to test horizon culling alone).
ViewState allPassView(const glm::dvec3& eye, double pixelsPerRadian) {
  ViewState v;
  v.eyeEcef = eye;
  for (auto& p : v.frustumPlanesEcef) p = glm::dvec4(1.0, 0.0, 0.0, 1e12);
  v.pixelsPerRadian = pixelsPerRadian;
  return v;
}

/// First hit of a ray with the WGS84 ellipsoid (scaled space: |o + t d|^2 = 1).
std::optional<glm::dvec3> hitEllipsoid(const glm::dvec3& origin, const glm::dvec3& dir) {
  const glm::dvec3 radii(kWgs84A, kWgs84A, kWgs84B);
  const glm::dvec3 o = origin / radii, d = dir / radii;
  const double a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
  const double disc = b * b - a * c;
  if (disc < 0.0) return std::nullopt;
  const double t = (-b - std::sqrt(disc)) / a;
  if (t < 0.0) return std::nullopt;
  return origin + t * dir;
}

/// The tile of `level` containing (lat, lon), boundaries going east/south (as TileCover).
TileId tileAt(double latDeg, double lonDeg, int level) {
  const double size = 180.0 / static_cast<double>(1u << level);
  const auto x =
      static_cast<std::uint32_t>(std::clamp(std::floor((lonDeg + 180.0) / size), 0.0, tileColumns(level) - 1.0));
  const auto y = static_cast<std::uint32_t>(std::clamp(std::floor((90.0 - latDeg) / size), 0.0, tileRows(level) - 1.0));
  return {level, x, y};
}

/// No selected tile is an ancestor of another (nor selected twice).
void expectNoOverlap(const std::vector<TileId>& tiles) {
  std::set<std::tuple<int, std::uint32_t, std::uint32_t>> all;
  for (const TileId& t : tiles) ASSERT_TRUE(all.insert({t.level, t.x, t.y}).second) << "tile selected twice";
  for (const TileId& t : tiles) {
    for (int l = 0; l < t.level; ++l) {
      const TileId a = ancestorTile(t, l);
      ASSERT_EQ(all.count({a.level, a.x, a.y}), 0u)
          << "ancestor of " << t.level << "/" << t.x << "/" << t.y << " also selected";
    }
  }
}

/// Casts rays through an n x n grid of pixels; every one that hits the ellipsoid must land
/// in exactly one selected tile. Returns the number of hits.
int expectCoverage(const Camera& c, const std::vector<TileId>& tiles, int n = 25) {
  int hits = 0;
  for (int py = 0; py < n; ++py) {
    for (int px = 0; px < n; ++px) {
      const double sx = (2.0 * (px + 0.5) / n - 1.0) * c.aspect * c.tanHalfFovY;
      const double sy = (2.0 * (py + 0.5) / n - 1.0) * c.tanHalfFovY;
      const auto hit = hitEllipsoid(c.eye, c.forward + sx * c.right + sy * c.up);
      if (!hit) continue;
      ++hits;
      const Geodetic g = ecefToGeodetic(*hit);
      int containing = 0;
      for (const TileId& t : tiles) containing += tileAt(g.latDeg, g.lonDeg, t.level) == t ? 1 : 0;
      EXPECT_EQ(containing, 1) << "pixel " << px << "," << py << " at " << g.latDeg << " " << g.lonDeg;
    }
  }
  return hits;
}

TEST(TileSelectionTest, FarCameraSelectsOnlyCoarseTiles) {
  for (const auto& [lat, lon] : {std::pair{0.0, 0.0}, std::pair{45.0, 100.0}, std::pair{-89.0, -170.0}}) {
    const Camera c = cameraLookingDown(lat, lon, 1e8);
    SelectionStats stats;
    const std::vector<TileId> tiles = selectTiles(makeView(c, 1.0, 1e9), SelectionOptions{}, &stats);
    ASSERT_FALSE(tiles.empty());
    for (const TileId& t : tiles) EXPECT_LE(t.level, 1);
    EXPECT_EQ(stats.selected, static_cast<int>(tiles.size()));
    EXPECT_LE(stats.maxLevel, 1);
    expectNoOverlap(tiles);
    EXPECT_GT(expectCoverage(c, tiles), 0);
  }
}

TEST(TileSelectionTest, CameraOneMetreUpSelectsDeepTilesWithoutOverlapOrGap) {
  const Camera c = cameraLookingDown(47.3, 8.5, 1.0);
  const ViewState view = makeView(c, 0.05, 1e7);
  SelectionStats stats;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<TileId> tiles = selectTiles(view, SelectionOptions{}, &stats);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("selectMs", std::to_string(ms));
  RecordProperty("visited", stats.visited);
  RecordProperty("selected", stats.selected);
  RecordProperty("maxLevel", stats.maxLevel);
  ASSERT_FALSE(tiles.empty());
  // The nadir tile is deep: its geometric error (sag ~ a rho^2 / 2) must be <= 2 px at 1 m,
  // i.e. under 2 / 866 m, which needs level >= 12 (hand estimate: cell 180/2^L/16 deg).
  const Geodetic nadir{47.3, 8.5, 0.0};
  std::optional<TileId> nadirTile;
  for (const TileId& t : tiles) {
    if (tileAt(nadir.latDeg, nadir.lonDeg, t.level) == t) nadirTile = t;
  }
  ASSERT_TRUE(nadirTile.has_value());
  EXPECT_GE(nadirTile->level, 12);
  EXPECT_EQ(stats.maxLevel, nadirTile->level);  // the nadir is the closest point: deepest tile
  expectNoOverlap(tiles);
  EXPECT_EQ(expectCoverage(c, tiles), 25 * 25);  // looking down: every pixel sees the ground
  EXPECT_LT(tiles.size(), 200u);
  EXPECT_GT(stats.culledFrustum, 0);
}

TEST(TileSelectionTest, TilesBehindTheEarthAreHorizonCulled) {
  const glm::dvec3 eye = geodeticToEcef({0.0, 0.0, 1e6});
  SelectionStats stats;
  const std::vector<TileId> tiles = selectTiles(allPassView(eye, 866.0), SelectionOptions{}, &stats);
  EXPECT_GT(stats.culledHorizon, 0);
  EXPECT_EQ(stats.culledFrustum, 0);
  expectNoOverlap(tiles);
  bool nearNadir = false;
  for (const TileId& t : tiles) {
    const GeoRectangle r = tileRectangle(t);
    // Nothing around 0N 180E: no selected tile meets lat [-10, 10] x lon [170, 180] u [-180, -170].
    const bool latMeets = r.southDeg < 10.0 && r.northDeg > -10.0;
    const bool lonMeets = r.eastDeg > 170.0 || r.westDeg < -170.0;
    EXPECT_FALSE(latMeets && lonMeets) << "tile " << t.level << "/" << t.x << "/" << t.y << " near 0N 180E selected";
    nearNadir = nearNadir || tileAt(0.5, 0.5, t.level) == t;
  }
  EXPECT_TRUE(nearNadir);
  // Every point the eye can see (samples on rays towards the visible cap) is in a selected
  // tile: horizon culling never removes a visible tile. The horizon is at 30.0 deg
  // (acos(a / (a + 1000 km))); sample the cap up to 29 deg from the nadir.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    const double lat = 29.0 * u(rng), lon = 29.0 * u(rng);
    if (std::acos(std::cos(degreesToRadians(lat)) * std::cos(degreesToRadians(lon))) > degreesToRadians(29.0)) continue;
    int containing = 0;
    for (const TileId& t : tiles) containing += tileAt(lat, lon, t.level) == t ? 1 : 0;
    EXPECT_EQ(containing, 1) << lat << " " << lon;
  }
}

TEST(TileSelectionTest, FrustumCullingRemovesTilesOutsideTheView) {
  // From 1000 km over 0N 0E, 0N 20E is above the horizon (30 deg away) but seen 58 deg off
  // the nadir direction (atan(a sin 20 / (a + 1e6 - a cos 20))): outside a 10 deg view,
  // inside a 150 deg one.
  auto selectsAround20E = [](double fovDeg, SelectionStats* stats) {
    const Camera c = cameraLookingDown(0.0, 0.0, 1e6, fovDeg);
    const std::vector<TileId> tiles = selectTiles(makeView(c, 1.0, 1e8), SelectionOptions{}, stats);
    expectNoOverlap(tiles);
    expectCoverage(c, tiles);
    return std::any_of(tiles.begin(), tiles.end(), [](const TileId& t) { return tileAt(0.0, 20.0, t.level) == t; });
  };
  SelectionStats narrow, wide;
  EXPECT_FALSE(selectsAround20E(10.0, &narrow));
  EXPECT_TRUE(selectsAround20E(150.0, &wide));
  EXPECT_GT(narrow.culledFrustum, 0);
  EXPECT_GT(narrow.culledFrustum, wide.culledFrustum);
}

TEST(TileSelectionTest, ScreenSpaceErrorDecreasesWithDistance) {
  const SelectionOptions options;
  for (const TileId& t : {TileId{0, 1, 0}, TileId{3, 9, 2}, TileId{12, 4200, 900}}) {
    const GeoRectangle r = tileRectangle(t);
    const double lat = 0.5 * (r.northDeg + r.southDeg), lon = 0.5 * (r.westDeg + r.eastDeg);
    // Straight above the tile: the distance is the height, so SSE = error * ppr / height.
    double previous = 1e300;
    for (double h = 0.5; h < 2e8; h *= 1.7) {
      ViewState v = allPassView(geodeticToEcef({lat, lon, h}), 866.0);
      const double sse = screenSpaceErrorPx(t, v, options);
      EXPECT_LT(sse, previous) << "height " << h;
      // The height comes back from GeographicLib's ECEF round trip: 2 x 7 nm (its stated bound).
      EXPECT_NEAR(sse, geometricErrorMeters(t, options) * 866.0 / h, sse * (1e-12 + 2.0 * 7e-9 / h));
      previous = sse;
    }
    // Moving away sideways, outside the tile (and across the antimeridian for x = 0).
    previous = 1e300;
    for (double away = 0.01; away < 60.0; away *= 1.5) {
      ViewState v = allPassView(geodeticToEcef({lat, r.westDeg - away, 1000.0}), 866.0);
      const double sse = screenSpaceErrorPx(t, v, options);
      EXPECT_LT(sse, previous) << "away " << away;
      previous = sse;
    }
  }
  // The distance never drops below 1e-3 m (eye on the surface).
  ViewState v = allPassView(geodeticToEcef({10.0, 10.0, 0.0}), 866.0);
  EXPECT_TRUE(std::isfinite(screenSpaceErrorPx({5, 34, 12}, v, options)));
  EXPECT_GE(tileDistanceMeters({5, 34, 12}, v.eyeEcef), 1e-3);
}

TEST(TileSelectionTest, DistanceHandlesTheAntimeridian) {
  // A tile just east of -180 seen from 179.9E: the nearest edge is 0.1 deg away across the
  // antimeridian, not 359.9 deg round the other way.
  const TileId t{6, 0, 20};  // lon [-180, -177.1875]
  const GeoRectangle r = tileRectangle(t);
  const double lat = 0.5 * (r.northDeg + r.southDeg);
  const glm::dvec3 eye = geodeticToEcef({lat, 179.9, 0.0});
  const double expected = glm::length(eye - geodeticToEcef({lat, -180.0, 0.0}));
  EXPECT_NEAR(tileDistanceMeters(t, eye), expected, 1e-6);
  EXPECT_LT(expected, 12e3);  // 0.1 deg of longitude at this latitude
}

// LOD at the nadir against height. Hand estimate (independent of the code): for a camera
// straight above the tile the distance is the height h; past the imagery levels the error
// is the sag, ~ a rho^2 / 2 with rho ~ half the cell diagonal, cell = 180/2^L/16 deg, i.e.
// sag(L) ~ a (pi / 2^L / 16)^2 (1 + cos^2 lat) / 8. The level is the first L with
// sag(L) * ppr / h <= 2 px (below imageryMaxLevel the texel term a pi/2^L/256 also counts).
// Measured (60 deg fov, 1000 px, 47.3N 8.5E): 1e8 m -> 0, 1e7 -> 2, 1e6 -> 3, 1e5 -> 4,
// 1e4 -> 6, 1e3 -> 8, 100 -> 9, 10 -> 11, 1 m -> 13.
TEST(TileSelectionTest, NadirLevelIncreasesAsTheCameraComesDown) {
  const double lat = 47.3, lon = 8.5;
  const double heights[] = {1e8, 1e7, 1e6, 1e5, 1e4, 1e3, 100.0, 10.0, 1.0};
  const SelectionOptions options;
  int previous = -1;
  std::string table;
  for (double h : heights) {
    const Camera c = cameraLookingDown(lat, lon, h);
    const ViewState view = makeView(c, 0.05, 1e9);
    const std::vector<TileId> tiles = selectTiles(view, options);
    std::optional<TileId> nadirTile;
    for (const TileId& t : tiles) {
      if (tileAt(lat, lon, t.level) == t) nadirTile = t;
    }
    ASSERT_TRUE(nadirTile.has_value()) << "height " << h;
    const int level = nadirTile->level;
    table += std::to_string(h) + "->" + std::to_string(level) + " ";
    // The refinement rule: the drawn tile meets the budget, its parent did not.
    EXPECT_LE(screenSpaceErrorPx(*nadirTile, view, options), options.maxScreenSpaceErrorPx);
    if (level > 0) {
      EXPECT_GT(screenSpaceErrorPx(parentTile(*nadirTile), view, options), options.maxScreenSpaceErrorPx);
    }
    // The hand estimate.
    int estimate = 0;
    for (;; ++estimate) {
      const double cell = kPi / std::ldexp(1.0, estimate) / 16.0;
      double err = kWgs84A * cell * cell * (1.0 + std::pow(std::cos(degreesToRadians(lat)), 2)) / 8.0;
      if (estimate < options.imageryMaxLevel) err = std::max(err, kWgs84A * kPi / std::ldexp(1.0, estimate) / 256.0);
      if (err * view.pixelsPerRadian / h <= options.maxScreenSpaceErrorPx) break;
    }
    EXPECT_NEAR(level, estimate, 1) << "height " << h;
    // Comes down -> finer; one decade lower in height is a factor 10 in allowed sag,
    // log4(10) = 1.66 levels, so each step of the table below 1e6 m adds at least one level.
    if (h <= 1e5) {
      EXPECT_GT(level, previous) << "height " << h;
    }
    EXPECT_GE(level, previous);
    previous = level;
  }
  RecordProperty("heightToLevel", table);
}

// computeTileBounds encloses the mesh (with its skirt) and random surface points at
// heights in [-500, 100] m; the horizon point is hidden only when the whole tile is.
TEST(TileSelectionTest, BoundsEncloseTheTile) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const TileId tiles[] = {{0, 0, 0}, {1, 3, 1}, {2, 3, 0}, {4, 17, 15}, {8, 300, 100}, {13, 9000, 3000}, {20, 1, 2}};
  for (const TileId& t : tiles) {
    const TileBounds b = computeTileBounds(t);
    const TileMesh m = buildTileMesh(t, kDefaultMeshSegments, skirtDepthMeters(t, kDefaultMeshSegments));
    double farthest = 0.0;
    for (const glm::vec3& p : m.positionsRelativeToCenter) {
      // Float rounding of the offsets: ~1e-7 relative to the tile size.
      const double d = glm::length(m.centerEcef + glm::dvec3(p) - b.sphereCenterEcef);
      EXPECT_LE(d, b.sphereRadiusMeters * (1.0 + 1e-6));
      farthest = std::max(farthest, d);
    }
    const GeoRectangle r = tileRectangle(t);
    for (int k = 0; k < 2000; ++k) {
      const Geodetic g{r.southDeg + (r.northDeg - r.southDeg) * u(rng), r.westDeg + (r.eastDeg - r.westDeg) * u(rng),
                       -500.0 + 600.0 * u(rng)};
      const double d = glm::length(geodeticToEcef(g) - b.sphereCenterEcef);
      EXPECT_LE(d, b.sphereRadiusMeters * (1.0 + 1e-12));
      farthest = std::max(farthest, d);
    }
    // Not wildly loose: the margin is documented as about 9 %.
    EXPECT_LE(b.sphereRadiusMeters, 1.12 * farthest) << "level " << t.level;
    // Half a globe has no culling point; from level 2 (45 deg tiles) on there is one.
    EXPECT_TRUE(t.level == 1 || b.horizonPointEcef.has_value() == (t.level >= 2)) << "level " << t.level;
  }
}

// isOccludedByEllipsoid against a brute-force segment-ellipsoid intersection.
TEST(TileSelectionHorizonTest, OcclusionMatchesSegmentIntersection) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const glm::dvec3 radii(kWgs84A, kWgs84A, kWgs84B);
  int hidden = 0, visible = 0;
  for (int k = 0; k < 20000; ++k) {
    auto randomOutside = [&](double maxScale) {
      for (;;) {
        const glm::dvec3 s(u(rng), u(rng), u(rng));
        const double len = glm::length(s);
        if (len < 1e-3 || len > 1.0) continue;
        const double scale = 1.0 + std::pow(maxScale, 0.5 * (u(rng) + 1.0)) - 1.0 + 1e-4;
        return glm::normalize(s) * scale * radii;
      }
    };
    const glm::dvec3 eye = randomOutside(20.0), p = randomOutside(3.0);
    // Segment eye -> p against the unit sphere in scaled space: the segment meets it iff the
    // closest point of the segment to the origin is inside.
    const glm::dvec3 o = eye / radii, d = p / radii - o;
    const double t = std::clamp(-glm::dot(o, d) / glm::dot(d, d), 0.0, 1.0);
    const double closest = glm::length(o + t * d);
    if (std::abs(closest - 1.0) < 1e-9) continue;  // grazing: either answer is right
    const bool expected = closest < 1.0;
    ASSERT_EQ(isOccludedByEllipsoid(eye, p), expected) << k;
    (expected ? hidden : visible)++;
  }
  EXPECT_GT(hidden, 1000);
  EXPECT_GT(visible, 1000);
  // Eye inside the ellipsoid: nothing is reported hidden.
  EXPECT_FALSE(isOccludedByEllipsoid(glm::dvec3(0.0), glm::dvec3(1e7, 0.0, 0.0)));
}

// The culling point is conservative: whenever it is hidden, every point of the tile
// (a dense grid at the extreme heights, and the mesh vertices) is hidden too.
TEST(TileSelectionHorizonTest, CullingPointHiddenImpliesTileHidden) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int culled = 0, tested = 0, none = 0;
  for (int k = 0; k < 3000; ++k) {
    const int level = 1 + static_cast<int>(u(rng) * 14.0);
    const TileId t{level, static_cast<std::uint32_t>(u(rng) * tileColumns(level)) % tileColumns(level),
                   static_cast<std::uint32_t>(u(rng) * tileRows(level)) % tileRows(level)};
    const double maxHeight = k % 3 == 0 ? 8848.0 : 100.0;
    const std::optional<glm::dvec3> q = horizonCullingPoint(t, -500.0, maxHeight);
    if (!q) {
      ++none;
      continue;
    }
    const GeoRectangle r = tileRectangle(t);
    // An eye anywhere (uniform direction), 1 m to 1e8 m up.
    const double eyeLat = radiansToDegrees(std::asin(2.0 * u(rng) - 1.0));
    const double eyeLon = 360.0 * u(rng) - 180.0;
    const glm::dvec3 eye = geodeticToEcef({eyeLat, eyeLon, std::pow(10.0, 8.0 * u(rng))});
    ++tested;
    if (!isOccludedByEllipsoid(eye, *q)) continue;
    ++culled;
    constexpr int n = 24;
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        for (double h : {0.0, maxHeight}) {
          const glm::dvec3 p = geodeticToEcef(
              {r.northDeg - (r.northDeg - r.southDeg) * j / n, r.westDeg + (r.eastDeg - r.westDeg) * i / n, h});
          ASSERT_TRUE(isOccludedByEllipsoid(eye, p))
              << "tile " << t.level << "/" << t.x << "/" << t.y << " point " << j << "," << i;
        }
      }
    }
  }
  RecordProperty("culled", culled);
  RecordProperty("tested", tested);
  EXPECT_GT(culled, tested / 5);                                                // the test is not vacuous
  EXPECT_LT(culled, tested);                                                    // nor is the culling
  EXPECT_EQ(horizonCullingPoint({0, 0, 0}, -500.0, 100.0).has_value(), false);  // half the globe: no point
}

// The culling point is not needlessly high. Any valid point over the tile centre must at
// least see past the corners: with s the half-diagonal of the tile, its height is at least
// about s^2 / (2a) (the height from which the horizon is s away). Ours may be higher (it
// is conservative) but not by much.
TEST(TileSelectionHorizonTest, CullingPointIsTightForSmallTiles) {
  const TileId t{12, 5000, 1000};
  const std::optional<glm::dvec3> q = horizonCullingPoint(t, 0.0, 0.0);
  ASSERT_TRUE(q.has_value());
  const double height = ecefToGeodetic(*q).heightMeters;
  const GeoRectangle r = tileRectangle(t);
  const double s =
      0.5 * glm::length(geodeticToEcef({r.northDeg, r.westDeg, 0.0}) - geodeticToEcef({r.southDeg, r.eastDeg, 0.0}));
  const double tightest = s * s / (2.0 * kWgs84A);
  RecordProperty("cullingPointHeight", std::to_string(height));
  RecordProperty("tightestHeight", std::to_string(tightest));
  EXPECT_GE(height, 0.9 * tightest);
  EXPECT_LE(height, 4.0 * tightest);
}

}  // namespace
}  // namespace atmoglobe::globe
