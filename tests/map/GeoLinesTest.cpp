// Geometry of map lines: geodesic densification, the antimeridian split, range rings, chunks.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/map/GeoLines.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace atmoglobe;

namespace {
double distanceMeters(glm::dvec2 a, glm::dvec2 b) { return globe::geodesicInverse(a.y, a.x, b.y, b.x).distanceMeters; }
}  // namespace

TEST(GeoLines, DensifiedPointsLieOnTheGeodesic) {
  // A long segment (Lisbon to Novosibirsk, ~6000 km) cut into <= 50 km parts.
  map::GeoPolyline line{{{-9.14, 38.72}, {82.93, 55.03}}};
  const map::GeoPolyline dense = map::densifyGeodesic(line, 50000.0);
  const double total = distanceMeters(line.lonLatDeg[0], line.lonLatDeg[1]);
  ASSERT_GT(dense.lonLatDeg.size(), static_cast<std::size_t>(total / 50000.0));
  double worstOff = 0.0, longest = 0.0;
  for (std::size_t i = 0; i < dense.lonLatDeg.size(); ++i) {
    // On the geodesic, |AP| + |PB| = |AB| (on any other path it is longer): the excess is the
    // measure of being off it. GeographicLib is accurate to ~15 nm, so 1 mm is far above its noise
    // and far below what a line 1 m from the camera would show (~1 px per mm at 1 m and 60 deg).
    const glm::dvec2 p = dense.lonLatDeg[i];
    worstOff = std::max(worstOff, distanceMeters(line.lonLatDeg[0], p) + distanceMeters(p, line.lonLatDeg[1]) - total);
    if (i > 0) longest = std::max(longest, distanceMeters(dense.lonLatDeg[i - 1], p));
  }
  EXPECT_LT(worstOff, 1e-3);
  EXPECT_LE(longest, 50000.0 + 1e-6);
  // A plate-carree (straight in lon/lat) midpoint is NOT on it: the check can fail.
  const glm::dvec2 mid = 0.5 * (line.lonLatDeg[0] + line.lonLatDeg[1]);
  EXPECT_GT(distanceMeters(line.lonLatDeg[0], mid) + distanceMeters(mid, line.lonLatDeg[1]) - total, 1000.0);
}

TEST(GeoLines, SplitAtTheAntimeridianOnTheGeodesic) {
  const map::GeoPolyline line{{{170.0, 10.0}, {-170.0, 20.0}, {-160.0, 20.0}}};
  const auto pieces = map::splitAtAntimeridian(line);
  ASSERT_EQ(pieces.size(), 2u);
  const glm::dvec2 end = pieces[0].lonLatDeg.back(), start = pieces[1].lonLatDeg.front();
  EXPECT_EQ(end.x, 180.0);
  EXPECT_EQ(start.x, -180.0);
  EXPECT_EQ(end.y, start.y);
  EXPECT_EQ(pieces[1].lonLatDeg.size(), 3u);
  // The crossing is on the geodesic from (170, 10) to (-170, 20) (1 mm, as above).
  const double total = distanceMeters(line.lonLatDeg[0], line.lonLatDeg[1]);
  EXPECT_LT(distanceMeters(line.lonLatDeg[0], end) + distanceMeters(end, line.lonLatDeg[1]) - total, 1e-3);
  // Between the end latitudes, and not at their mean (the geodesic bows poleward).
  EXPECT_GT(end.y, 10.0);
  EXPECT_LT(end.y, 20.0);
  // Westward crossing too, and a line that does not cross stays whole.
  const auto west = map::splitAtAntimeridian({{{-175.0, -30.0}, {175.0, -35.0}}});
  ASSERT_EQ(west.size(), 2u);
  EXPECT_EQ(west[0].lonLatDeg.back().x, -180.0);
  EXPECT_EQ(map::splitAtAntimeridian({{{-10.0, 0.0}, {10.0, 0.0}}}).size(), 1u);
}

TEST(GeoLines, RangeRingsAreAtTheirRangeAndSpokesAtTheirAzimuth) {
  const double lat = 35.333, lon = -97.278;  // KTLX
  const auto lines = map::rangeRingsAndSpokes(lat, lon, 230000.0, 50000.0, 30.0);
  ASSERT_EQ(lines.size(), 4u + 12u);  // rings at 50..200 km, 12 spokes
  for (int r = 0; r < 4; ++r)
    for (const glm::dvec2& p : lines[static_cast<std::size_t>(r)].lonLatDeg)
      EXPECT_NEAR(distanceMeters({lon, lat}, p), 50000.0 * (r + 1), 1e-6);  // GeographicLib round trip
  for (int s = 0; s < 12; ++s) {
    const auto& spoke = lines[static_cast<std::size_t>(4 + s)].lonLatDeg;
    const globe::GeodesicLine g = globe::geodesicInverse(lat, lon, spoke.back().y, spoke.back().x);
    EXPECT_NEAR(g.distanceMeters, 230000.0, 1e-6);
    EXPECT_NEAR(std::remainder(g.azimuth1Deg - 30.0 * s, 360.0), 0.0, 1e-9);
  }
}

TEST(GeoLines, ChunkPointsAreRelativeToTheOriginToTheMillimetre) {
  const map::GeoPolyline line{{{-9.5, 38.78}, {-9.0, 38.5}, {-8.0, 39.0}}};
  const map::LineChunk chunk = map::buildLineChunk({line}, 1000.0);
  ASSERT_GT(chunk.segmentCount(), 100u);
  // The first point: hi + lo (floats) + origin (double) is its ECEF to well under 1 mm.
  const glm::dvec3 first = globe::geodeticToEcef({38.78, -9.5, 0.0});
  const glm::dvec3 hi(chunk.vertices[0], chunk.vertices[1], chunk.vertices[2]);
  const glm::dvec3 lo(chunk.vertices[3], chunk.vertices[4], chunk.vertices[5]);
  EXPECT_LT(glm::distance(chunk.originEcef + hi + lo, first), 1e-6);
  // hi alone is off by up to a float's rounding of ~100 km (~4 mm): lo carries the rest.
  EXPECT_GT(glm::distance(chunk.originEcef + hi, first), 1e-7);
  EXPECT_LE(chunk.sagMeters, map::chordSagMeters(1000.0));
  EXPECT_GT(chunk.sphereRadiusMeters, 50000.0);
}
