#include <atmoglobe/globe/TileMesh.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/TileSelection.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace atmoglobe::globe {

double skirtDepthMeters(const TileId& t, int segments) {
  assert(isValid(t) && segments >= 1);
  const int coarseLevel = std::max(t.level - 2, 0);
  // The row just north of the equator (level 0: the whole western root tile).
  const TileId equatorial{coarseLevel, 0u, coarseLevel == 0 ? 0u : tileRows(coarseLevel) / 2u - 1u};
  const double sagMeters = chordSagBoundMeters(equatorial, segments);
  const GeoRectangle r = tileRectangle(t);
  const double tileWidthMeters = kWgs84A * degreesToRadians(r.eastDeg - r.westDeg);
  constexpr double kFloatUlpRelative = 1.0 / 8388608.0;  // 2^-23
  return std::max(sagMeters, 4.0 * kFloatUlpRelative * tileWidthMeters);
}

TileMesh buildTileMesh(const TileId& t, int segments, double skirtDepth) {
  assert(isValid(t) && segments >= 1 && std::isfinite(skirtDepth) && skirtDepth >= 0.0);
  const int n = segments;
  const GeoRectangle r = tileRectangle(t);
  const double sizeDeg = r.eastDeg - r.westDeg;
  // size * k / n: exact at k = 0 and k = n, so neighbours share their edge coordinates.
  auto latAt = [&](int j) { return r.northDeg - sizeDeg * j / n; };
  auto lonAt = [&](int i) { return r.westDeg + sizeDeg * i / n; };

  const std::size_t gridCount = tileMeshGridVertexCount(n);
  const std::size_t ringCount = 4 * static_cast<std::size_t>(n);
  std::vector<glm::dvec3> positions;
  positions.reserve(gridCount + ringCount);
  TileMesh mesh;
  mesh.texCoords.reserve(gridCount + ringCount);
  mesh.normals.reserve(gridCount + ringCount);

  // GeographicLib works in degrees with exact sin/cos at multiples of 90 degrees, so a
  // pole row is exactly (0, 0, +-b) and carries no NaN.
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      positions.push_back(geodeticToEcef({latAt(j), lonAt(i), 0.0}));
      mesh.texCoords.emplace_back(static_cast<float>(static_cast<double>(i) / n),
                                  static_cast<float>(static_cast<double>(j) / n));
      mesh.normals.push_back(glm::vec3(surfaceNormal(latAt(j), lonAt(i))));
    }
  }

  // Boundary ring, counter-clockwise seen from above, as (row, column) pairs.
  std::vector<std::pair<int, int>> ring;
  ring.reserve(ringCount);
  for (int j = 0; j < n; ++j) ring.emplace_back(j, 0);  // west edge, southwards
  for (int i = 0; i < n; ++i) ring.emplace_back(n, i);  // south edge, eastwards
  for (int j = n; j > 0; --j) ring.emplace_back(j, n);  // east edge, northwards
  for (int i = n; i > 0; --i) ring.emplace_back(0, i);  // north edge, westwards
  auto gridIndex = [n](int j, int i) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (const auto& [j, i] : ring) {
    positions.push_back(geodeticToEcef({latAt(j), lonAt(i), -skirtDepth}));
    mesh.texCoords.push_back(mesh.texCoords[gridIndex(j, i)]);
    mesh.normals.push_back(mesh.normals[gridIndex(j, i)]);
  }

  glm::dvec3 lo(positions[0]), hi(positions[0]);
  for (std::size_t k = 0; k < gridCount; ++k) {
    lo = glm::min(lo, positions[k]);
    hi = glm::max(hi, positions[k]);
  }
  mesh.centerEcef = 0.5 * (lo + hi);
  mesh.positionsRelativeToCenter.reserve(positions.size());
  for (const glm::dvec3& p : positions) {
    const glm::dvec3 offset = p - mesh.centerEcef;
    mesh.positionsRelativeToCenter.emplace_back(static_cast<float>(offset.x), static_cast<float>(offset.y),
                                                static_cast<float>(offset.z));
  }

  mesh.indices.reserve(6 * static_cast<std::size_t>(n) * static_cast<std::size_t>(n) + 6 * ringCount);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = gridIndex(j, i), b = gridIndex(j, i + 1);
      const std::uint32_t c = gridIndex(j + 1, i), d = gridIndex(j + 1, i + 1);
      mesh.indices.insert(mesh.indices.end(), {c, d, b, c, b, a});
    }
  }
  for (std::size_t k = 0; k < ringCount; ++k) {
    const std::size_t next = (k + 1) % ringCount;
    const std::uint32_t p0 = gridIndex(ring[k].first, ring[k].second);
    const std::uint32_t p1 = gridIndex(ring[next].first, ring[next].second);
    const auto s0 = static_cast<std::uint32_t>(gridCount + k), s1 = static_cast<std::uint32_t>(gridCount + next);
    mesh.indices.insert(mesh.indices.end(), {p0, s0, s1, p0, s1, p1});
  }
  return mesh;
}

}  // namespace atmoglobe::globe
