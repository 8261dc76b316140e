// Tests of buildTileMesh / skirtDepthMeters (globe/TileMesh.h) and of the chord-sag part
// of geometricErrorMeters (globe/TileSelection.h).
#include <atmoglobe/globe/TileMesh.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/TileSelection.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::globe {
namespace {

constexpr int kSegments = 16;

/// Tiles spread over the globe: roots, equator, mid-latitude, both poles, antimeridian, deep.
const TileId kTiles[] = {{0, 0, 0},  {0, 1, 0},    {2, 3, 0},       {2, 5, 3},     {3, 7, 3},
                         {5, 40, 6}, {7, 255, 60}, {10, 1100, 200}, {10, 0, 1023}, {14, 20000, 4000}};

glm::dvec3 vertexEcef(const TileMesh& m, std::size_t k) {
  return m.centerEcef + glm::dvec3(m.positionsRelativeToCenter[k]);
}

/// Spacing of float32 numbers around |x| (one ulp).
double floatUlp(double x) { return std::ldexp(1.0, std::ilogb(static_cast<float>(std::max(std::abs(x), 1e-30))) - 23); }

/// Largest rounding error of one vertex: each component is rounded to the nearest float
/// (half an ulp of the largest offset component), so the error vector is at most
/// sqrt(3) * ulp/2 long.
double vertexRoundingMeters(const TileMesh& m) {
  double largest = 0.0;
  for (const glm::vec3& p : m.positionsRelativeToCenter) {
    largest = std::max({largest, std::abs(double(p.x)), std::abs(double(p.y)), std::abs(double(p.z))});
  }
  return std::sqrt(3.0) * 0.5 * floatUlp(largest);
}

TEST(TileMeshTest, GridVerticesLieOnTheEllipsoid) {
  for (const TileId& t : kTiles) {
    const TileMesh m = buildTileMesh(t, kSegments, skirtDepthMeters(t, kSegments));
    ASSERT_EQ(m.positionsRelativeToCenter.size(), tileMeshGridVertexCount(kSegments) + 4 * kSegments);
    ASSERT_EQ(m.texCoords.size(), m.positionsRelativeToCenter.size());
    ASSERT_EQ(m.normals.size(), m.positionsRelativeToCenter.size());
    // The only error is the float32 rounding of the offsets (GeographicLib: 7 nm). For a tile
    // of level >= 10 (< 20 km across, offsets < 16 km) the ulp is <= 2^-10 m, so the bound
    // is sqrt(3)/2 * 0.98 mm = 0.85 mm < 1 mm; coarse tiles have larger offsets and ulps.
    const double tol = vertexRoundingMeters(m) + 1e-8;
    if (t.level >= 10) {
      EXPECT_LT(tol, 1e-3);
    }
    double worst = 0.0;
    for (std::size_t k = 0; k < tileMeshGridVertexCount(kSegments); ++k) {
      worst = std::max(worst, std::abs(ecefToGeodetic(vertexEcef(m, k)).heightMeters));
    }
    EXPECT_LE(worst, tol) << "level " << t.level << " x " << t.x << " y " << t.y;
  }
}

TEST(TileMeshTest, TexCoordsSpanTheUnitSquare) {
  const TileMesh m = buildTileMesh({5, 40, 6}, kSegments, 10.0);
  float minU = 1, maxU = 0, minV = 1, maxV = 0;
  for (std::size_t k = 0; k < m.texCoords.size(); ++k) {
    const glm::vec2 uv = m.texCoords[k];
    minU = std::min(minU, uv.x), maxU = std::max(maxU, uv.x);
    minV = std::min(minV, uv.y), maxV = std::max(maxV, uv.y);
  }
  EXPECT_EQ(minU, 0.0f);
  EXPECT_EQ(maxU, 1.0f);
  EXPECT_EQ(minV, 0.0f);
  EXPECT_EQ(maxV, 1.0f);
  // u grows eastwards, v southwards: the vertex at u = 1 is east of the one at u = 0.
  const Geodetic nw = ecefToGeodetic(vertexEcef(m, 0));
  const Geodetic ne = ecefToGeodetic(vertexEcef(m, kSegments));
  const Geodetic sw = ecefToGeodetic(vertexEcef(m, std::size_t{kSegments} * (kSegments + 1)));
  EXPECT_GT(ne.lonDeg, nw.lonDeg);
  EXPECT_LT(sw.latDeg, nw.latDeg);
  // Corners at the tile's corners, up to the float rounding (converted to degrees with the
  // smallest radii of curvature: b^2/a along the meridian, N cos(lat) >= b cos(lat) along
  // the parallel).
  const GeoRectangle r = tileRectangle({5, 40, 6});
  const double rounding = vertexRoundingMeters(m);
  const double latTolDeg = radiansToDegrees(rounding / (kWgs84B * kWgs84B / kWgs84A));
  const double lonTolDeg = radiansToDegrees(rounding / (kWgs84B * std::cos(degreesToRadians(r.northDeg))));
  EXPECT_NEAR(nw.latDeg, r.northDeg, latTolDeg);
  EXPECT_NEAR(nw.lonDeg, r.westDeg, lonTolDeg);
  EXPECT_NEAR(sw.latDeg, r.southDeg, latTolDeg);
  EXPECT_NEAR(ne.lonDeg, r.eastDeg, lonTolDeg);
  for (int j = 0; j <= kSegments; ++j) {
    for (int i = 0; i <= kSegments; ++i) {
      const glm::vec2 uv = m.texCoords[static_cast<std::size_t>(j * (kSegments + 1) + i)];
      EXPECT_FLOAT_EQ(uv.x, static_cast<float>(i) / kSegments);
      EXPECT_FLOAT_EQ(uv.y, static_cast<float>(j) / kSegments);
    }
  }
}

TEST(TileMeshTest, PoleTilesHaveNoNanAndCollapseToThePole) {
  const TileId north{2, 3, 0}, south{2, 5, 3};
  for (const TileId& t : {north, south}) {
    const TileMesh m = buildTileMesh(t, kSegments, skirtDepthMeters(t, kSegments));
    for (std::size_t k = 0; k < m.positionsRelativeToCenter.size(); ++k) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(m.positionsRelativeToCenter[k][c]));
        ASSERT_TRUE(std::isfinite(m.normals[k][c]));
      }
      ASSERT_TRUE(std::isfinite(m.texCoords[k].x) && std::isfinite(m.texCoords[k].y));
    }
    const bool isNorth = t.y == 0;
    const int poleRow = isNorth ? 0 : kSegments;
    const glm::dvec3 pole(0.0, 0.0, isNorth ? kWgs84B : -kWgs84B);
    const std::size_t first = static_cast<std::size_t>(poleRow * (kSegments + 1));
    for (int i = 0; i <= kSegments; ++i) {
      const std::size_t k = first + static_cast<std::size_t>(i);
      // Every vertex of the pole row is the same float triple (same double input) ...
      EXPECT_EQ(m.positionsRelativeToCenter[k], m.positionsRelativeToCenter[first]);
      // ... and that is the pole, up to the float rounding of the offset.
      EXPECT_LE(glm::length(vertexEcef(m, k) - pole), vertexRoundingMeters(m));
      EXPECT_NEAR(m.normals[k].z, isNorth ? 1.0f : -1.0f, 1e-7f);
    }
    // No triangle has a NaN normal; the degenerate ones have exactly zero area.
    for (std::size_t k = 0; k < m.indices.size(); k += 3) {
      const glm::dvec3 n = glm::cross(vertexEcef(m, m.indices[k + 1]) - vertexEcef(m, m.indices[k]),
                                      vertexEcef(m, m.indices[k + 2]) - vertexEcef(m, m.indices[k]));
      ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    }
  }
}

TEST(TileMeshTest, SkirtHangsSkirtDepthBelowItsEdgeVertex) {
  for (const TileId& t : kTiles) {
    const double depth = skirtDepthMeters(t, kSegments);
    const TileMesh m = buildTileMesh(t, kSegments, depth);
    const std::size_t grid = tileMeshGridVertexCount(kSegments);
    const double tol = 2.0 * vertexRoundingMeters(m) + 1e-8;  // two rounded vertices
    // Walk the ring as documented: west edge south, south edge east, east edge north, north edge west.
    std::vector<std::size_t> ring;
    for (int j = 0; j < kSegments; ++j) ring.push_back(static_cast<std::size_t>(j * (kSegments + 1)));
    for (int i = 0; i < kSegments; ++i) ring.push_back(static_cast<std::size_t>(kSegments * (kSegments + 1) + i));
    for (int j = kSegments; j > 0; --j) ring.push_back(static_cast<std::size_t>(j * (kSegments + 1) + kSegments));
    for (int i = kSegments; i > 0; --i) ring.push_back(static_cast<std::size_t>(i));
    ASSERT_EQ(ring.size() + grid, m.positionsRelativeToCenter.size());
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const std::size_t edge = ring[k], skirt = grid + k;
      const glm::dvec3 expected = vertexEcef(m, edge) - depth * glm::dvec3(m.normals[edge]);
      // The float normal is off by ~6e-8, times the depth.
      EXPECT_LE(glm::length(vertexEcef(m, skirt) - expected), tol + depth * 1e-7)
          << "tile level " << t.level << " k " << k;
      EXPECT_NEAR(ecefToGeodetic(vertexEcef(m, skirt)).heightMeters, -depth, tol);
      EXPECT_EQ(m.texCoords[skirt], m.texCoords[edge]);
      EXPECT_EQ(m.normals[skirt], m.normals[edge]);
    }
  }
}

/// Edge vertices of two neighbours must coincide up to the rounding of both meshes.
void expectSharedEdge(const TileId& a, const TileId& b, bool eastWest) {
  const TileMesh ma = buildTileMesh(a, kSegments, 0.0), mb = buildTileMesh(b, kSegments, 0.0);
  const double tol = vertexRoundingMeters(ma) + vertexRoundingMeters(mb) + 1e-9;
  for (int k = 0; k <= kSegments; ++k) {
    // a's east column vs b's west column, or a's south row vs b's north row.
    const std::size_t ka =
        static_cast<std::size_t>(eastWest ? k * (kSegments + 1) + kSegments : kSegments * (kSegments + 1) + k);
    const std::size_t kb = static_cast<std::size_t>(eastWest ? k * (kSegments + 1) : k);
    EXPECT_LE(glm::length(vertexEcef(ma, ka) - vertexEcef(mb, kb)), tol) << "k " << k;
  }
}

TEST(TileMeshTest, NeighboursShareEdgeVertices) {
  expectSharedEdge({6, 70, 20}, {6, 71, 20}, true);
  expectSharedEdge({6, 70, 20}, {6, 70, 21}, false);
  expectSharedEdge({10, 1100, 200}, {10, 1101, 200}, true);
  expectSharedEdge({3, 15, 2}, {3, 0, 2}, true);  // across the antimeridian (180 == -180)
  expectSharedEdge({1, 1, 0}, {1, 1, 1}, false);  // across the equator
  expectSharedEdge({0, 0, 0}, {0, 1, 0}, true);   // the two roots
}

/// Closest distance from p to the segment [a, b] (b may equal a).
double distanceToSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + s * ab));
}

/// Closest distance from p to the triangle (a, b, c): the plane distance when the foot of
/// the perpendicular lies inside (barycentric test), else the nearest edge.
double distanceToTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double n2 = glm::dot(n, n);
  if (n2 > 0.0) {
    const glm::dvec3 foot = p - glm::dot(p - a, n) / n2 * n;
    const double u = glm::dot(glm::cross(c - b, foot - b), n), v = glm::dot(glm::cross(a - c, foot - c), n),
                 w = glm::dot(glm::cross(b - a, foot - a), n);
    if (u >= 0 && v >= 0 && w >= 0) return std::abs(glm::dot(p - a, n)) / std::sqrt(n2);
  }
  return std::min({distanceToSegment(p, a, b), distanceToSegment(p, b, c), distanceToSegment(p, c, a)});
}

/// The grid vertices of tile t in double precision, row-major from the north-west corner
/// (the layout buildTileMesh documents), straight from GeographicLib: the chord-sag test
/// below must not mix the bound with float rounding.
std::vector<glm::dvec3> exactGrid(const TileId& t) {
  const GeoRectangle r = tileRectangle(t);
  std::vector<glm::dvec3> out;
  for (int j = 0; j <= kSegments; ++j) {
    for (int i = 0; i <= kSegments; ++i) {
      out.push_back(geodeticToEcef({r.northDeg - (r.northDeg - r.southDeg) * j / kSegments,
                                    r.westDeg + (r.eastDeg - r.westDeg) * i / kSegments, 0.0}));
    }
  }
  return out;
}

// The chord sag: every vertex of the four children (true surface points, a finer
// sampling) lies within geometricErrorMeters(parent) of the parent's triangles. Distance to
// the parent mesh: minimum over the triangles of the parent cell under the vertex and its
// 8 neighbours (the true closest triangle is among them; this is an upper bound anyway).
// Positions in double (exactGrid), so the only slack is double rounding (1e-9 relative).
TEST(TileMeshTest, ChildVerticesWithinParentGeometricError) {
  SelectionOptions sagOnly;
  sagOnly.imageryMaxLevel = 0;  // the texel term would only raise the bound
  sagOnly.meshSegments = kSegments;
  const TileId parents[] = {{0, 0, 0},  {2, 3, 0},    {2, 5, 3},        {3, 7, 3},
                            {5, 40, 6}, {7, 255, 60}, {12, 5000, 1000}, {18, 300000, 200000}};
  for (const TileId& parent : parents) {
    const std::vector<glm::dvec3> pm = exactGrid(parent);
    const double bound = geometricErrorMeters(parent, sagOnly);
    double worst = 0.0;
    for (int c = 0; c < 4; ++c) {
      const std::vector<glm::dvec3> cm = exactGrid(childTile(parent, c));
      const int rowOffset = (c >> 1) * kSegments, colOffset = (c & 1) * kSegments;  // in child steps
      for (int j = 0; j <= kSegments; ++j) {
        for (int i = 0; i <= kSegments; ++i) {
          const glm::dvec3 p = cm[static_cast<std::size_t>(j * (kSegments + 1) + i)];
          const int pj = std::min((rowOffset + j) / 2, kSegments - 1),
                    pi = std::min((colOffset + i) / 2, kSegments - 1);
          double best = 1e300;
          for (int dj = -1; dj <= 1; ++dj) {
            for (int di = -1; di <= 1; ++di) {
              const int cj = pj + dj, ci = pi + di;
              if (cj < 0 || ci < 0 || cj >= kSegments || ci >= kSegments) continue;
              auto v = [&](int jj, int ii) { return pm[static_cast<std::size_t>(jj * (kSegments + 1) + ii)]; };
              const glm::dvec3 a = v(cj, ci), b = v(cj, ci + 1), cc = v(cj + 1, ci), d = v(cj + 1, ci + 1);
              best = std::min({best, distanceToTriangle(p, cc, d, b), distanceToTriangle(p, cc, b, a)});
            }
          }
          worst = std::max(worst, best);
        }
      }
    }
    SCOPED_TRACE(testing::Message() << "parent level " << parent.level << " x " << parent.x << " y " << parent.y
                                    << " worst " << worst << " m, bound " << bound << " m");
    // Double rounding of distances between points ~6.4e6 m from the origin: ~1e-9 m each.
    EXPECT_LE(worst, bound * (1.0 + 1e-9) + 1e-8);
    RecordProperty("sagOverBoundLevel" + std::to_string(parent.level) + "y" + std::to_string(parent.y),
                   std::to_string(worst / bound));
    // Not a vacuous bound: the children's vertices at the parent cells' centres reach most of it.
    EXPECT_GE(worst, 0.7 * bound);
    // The default options (texel term at coarse levels) can only be larger.
    EXPECT_GE(geometricErrorMeters(parent, SelectionOptions{}), bound);
  }
}

TEST(TileMeshTest, TrianglesFaceOutward) {
  for (const TileId& t : kTiles) {
    const TileMesh m = buildTileMesh(t, kSegments, skirtDepthMeters(t, kSegments));
    const std::size_t gridTriangles = 2 * std::size_t{kSegments} * kSegments;
    ASSERT_EQ(m.indices.size(), 3 * gridTriangles + 3 * 2 * 4 * std::size_t{kSegments});
    int nonDegenerate = 0;
    const glm::dvec3 tileMiddle = m.centerEcef;
    for (std::size_t k = 0; k < m.indices.size(); k += 3) {
      ASSERT_LT(m.indices[k], m.positionsRelativeToCenter.size());
      // Positions relative to the centre in double: the cross product of float offsets.
      const glm::dvec3 a(m.positionsRelativeToCenter[m.indices[k]]), b(m.positionsRelativeToCenter[m.indices[k + 1]]),
          c(m.positionsRelativeToCenter[m.indices[k + 2]]);
      const glm::dvec3 n = glm::cross(b - a, c - a);
      const double area2 = glm::length(n);
      const double scale = std::max({glm::length(b - a), glm::length(c - a), 1e-300});
      if (area2 <= 1e-9 * scale * scale) continue;  // degenerate (pole rows, pole skirts)
      ++nonDegenerate;
      const glm::dvec3 centroid = m.centerEcef + (a + b + c) / 3.0;
      if (k / 3 < gridTriangles) {
        ASSERT_GT(glm::dot(n, centroid), 0.0) << "grid triangle " << k / 3 << " faces the Earth centre";
      } else {
        // Skirt walls face away from the tile: the normal points from the tile's middle
        // towards the wall (horizontal component).
        const glm::dvec3 up = glm::normalize(centroid);
        const glm::dvec3 away = centroid - tileMiddle - glm::dot(centroid - tileMiddle, up) * up;
        ASSERT_GT(glm::dot(n, away), 0.0) << "skirt triangle " << k / 3 << " faces into the tile";
      }
    }
    EXPECT_GE(nonDegenerate, static_cast<int>(gridTriangles));
  }
}

// skirtDepthMeters covers the chord sag of a neighbour up to two levels coarser at the
// worst latitude (the equator), and is never zero.
TEST(TileMeshTest, SkirtDepthCoversCoarserNeighbours) {
  SelectionOptions sagOnly;
  sagOnly.imageryMaxLevel = 0;
  for (int level = 2; level <= 20; level += 3) {
    for (const TileId& t : {TileId{level, 0u, 0u}, TileId{level, tileColumns(level) / 3u, tileRows(level) / 2u}}) {
      const double depth = skirtDepthMeters(t, kSegments);
      EXPECT_GT(depth, 0.0);
      for (int up = 1; up <= 2; ++up) {
        const int coarse = level - up;
        const TileId equatorial{coarse, 0u, tileRows(coarse) / 2u};
        EXPECT_GE(depth, geometricErrorMeters(equatorial, sagOnly)) << "level " << level << " up " << up;
      }
    }
  }
}

}  // namespace
}  // namespace atmoglobe::globe
