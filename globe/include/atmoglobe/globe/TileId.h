#pragma once
// Geographic (EPSG:4326, plate carree) quadtree tile addressing.
//
// Level 0 has 2 x 1 root tiles, each 180 x 180 degrees: x = 0 covers [-180, 0] longitude,
// x = 1 covers [0, 180]. Level z has 2^(z+1) columns and 2^z rows. Column x counts from
// the antimeridian (-180) eastwards; row y counts from the NORTH pole (90) southwards
// (same row order as images and slippy-map tiles). The poles are tile edges, so the
// tiling covers them without a hole.
#include <cassert>
#include <cstdint>
#include <functional>

#include <glm/glm.hpp>

namespace atmoglobe::globe {

/// Largest level the tiling supports (tile size ~ 6e-7 deg ~ 7 cm at level 28).
inline constexpr int kMaxTileLevel = 28;

struct TileId {
  int level = 0;
  std::uint32_t x = 0;  ///< column from -180 deg eastwards
  std::uint32_t y = 0;  ///< row from +90 deg southwards

  friend bool operator==(const TileId&, const TileId&) = default;
};

inline std::uint32_t tileColumns(int level) { return 2u << level; }
inline std::uint32_t tileRows(int level) { return 1u << level; }
inline bool isValid(const TileId& t) {
  return t.level >= 0 && t.level <= kMaxTileLevel && t.x < tileColumns(t.level) && t.y < tileRows(t.level);
}

/// Longitude/latitude box in degrees. For a box that crosses the antimeridian,
/// westDeg > eastDeg (e.g. west 170, east -170).
struct GeoRectangle {
  double westDeg = -180.0;
  double southDeg = -90.0;
  double eastDeg = 180.0;
  double northDeg = 90.0;
};

/// Extent of a tile in degrees (never crosses the antimeridian).
inline GeoRectangle tileRectangle(const TileId& t) {
  assert(isValid(t));
  const double size = 180.0 / static_cast<double>(1u << t.level);
  GeoRectangle r;
  r.westDeg = -180.0 + size * t.x;
  r.eastDeg = r.westDeg + size;
  r.northDeg = 90.0 - size * t.y;
  r.southDeg = r.northDeg - size;
  return r;
}

inline TileId parentTile(const TileId& t) {
  assert(t.level > 0);
  return {t.level - 1, t.x / 2, t.y / 2};
}

/// Child i in 0..3: 0 = north-west, 1 = north-east, 2 = south-west, 3 = south-east.
inline TileId childTile(const TileId& t, int i) {
  assert(t.level < kMaxTileLevel && i >= 0 && i < 4);
  return {t.level + 1, t.x * 2 + static_cast<std::uint32_t>(i & 1), t.y * 2 + static_cast<std::uint32_t>(i >> 1)};
}

/// The ancestor of `t` at `level` (<= t.level); `t` itself when level == t.level.
inline TileId ancestorTile(const TileId& t, int level) {
  assert(level >= 0 && level <= t.level);
  const int shift = t.level - level;
  return {level, t.x >> shift, t.y >> shift};
}

/// Texture-coordinate transform mapping `t`'s own (u, v) in [0,1]^2 (u east, v south)
/// into the image of its ancestor `a`: uv_a = uv_t * scale + offset, returned as
/// (scaleU, scaleV, offsetU, offsetV).
inline glm::dvec4 uvTransformInAncestor(const TileId& t, const TileId& a) {
  assert(a.level <= t.level && ancestorTile(t, a.level) == a);
  const int shift = t.level - a.level;
  const double n = static_cast<double>(1u << shift);
  const double fx = static_cast<double>(t.x - (a.x << shift));
  const double fy = static_cast<double>(t.y - (a.y << shift));
  return {1.0 / n, 1.0 / n, fx / n, fy / n};
}

struct TileIdHash {
  std::size_t operator()(const TileId& t) const {
    std::uint64_t k = (static_cast<std::uint64_t>(t.level) << 58) ^ (static_cast<std::uint64_t>(t.x) << 29) ^ t.y;
    return std::hash<std::uint64_t>{}(k);
  }
};

}  // namespace atmoglobe::globe
