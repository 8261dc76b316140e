#include <atmoglobe/globe/TileCover.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace atmoglobe::globe {

namespace {

/// Inclusive index range [first, last] of cells of width `size` (starting at 0) overlapping
/// [lo, hi] (both measured from the start of the axis), clamped to [0, count - 1].
/// A zero-width range gives the one cell containing it.
struct IndexRange {
  std::int64_t first;
  std::int64_t last;
};

IndexRange cellsOverlapping(double lo, double hi, double size, std::int64_t count) {
  assert(lo <= hi);
  auto clampIndex = [count](double v) { return std::clamp<std::int64_t>(static_cast<std::int64_t>(v), 0, count - 1); };
  const std::int64_t first = clampIndex(std::floor(lo / size));
  // ceil(hi/size) - 1 is the last cell starting strictly below hi; it can fall below
  // `first` only for a zero-width range, which then keeps its own cell.
  const std::int64_t last = std::max(first, clampIndex(std::ceil(hi / size) - 1.0));
  return {first, last};
}

}  // namespace

std::vector<TileId> tilesCovering(const GeoRectangle& rect, int level) {
  assert(level >= 0 && level <= kMaxTileLevel);
  assert(std::isfinite(rect.westDeg) && std::isfinite(rect.eastDeg) && std::isfinite(rect.southDeg) &&
         std::isfinite(rect.northDeg));
  const double size = 180.0 / static_cast<double>(1u << level);  // exact: power-of-two division
  const auto columns = static_cast<std::int64_t>(tileColumns(level));
  const auto rows = static_cast<std::int64_t>(tileRows(level));

  const double south = std::clamp(rect.southDeg, -90.0, 90.0);
  const double north = std::clamp(rect.northDeg, -90.0, 90.0);
  if (south > north) return {};
  // Rows count from the north pole: distance from 90 deg.
  const IndexRange rowRange = cellsOverlapping(90.0 - north, 90.0 - south, size, rows);

  // Column ranges, as offsets from -180.
  std::vector<IndexRange> columnRanges;
  if (rect.eastDeg >= rect.westDeg && rect.eastDeg - rect.westDeg >= 360.0) {
    columnRanges.push_back({0, columns - 1});
  } else if (rect.eastDeg == rect.westDeg) {
    const double lon = wrapLongitudeDeg(rect.westDeg);
    columnRanges.push_back(cellsOverlapping(lon + 180.0, lon + 180.0, size, columns));
  } else {
    // West into [-180, 180), east into (-180, 180]: a box ending at 180 stays a plain box.
    const double west = wrapLongitudeDeg(rect.westDeg);
    double east = wrapLongitudeDeg(rect.eastDeg);
    if (east == -180.0) east = 180.0;
    if (west <= east) {
      columnRanges.push_back(cellsOverlapping(west + 180.0, east + 180.0, size, columns));
    } else {  // crosses the antimeridian: [west, 180] and [-180, east]
      columnRanges.push_back(cellsOverlapping(0.0, east + 180.0, size, columns));
      columnRanges.push_back(cellsOverlapping(west + 180.0, 360.0, size, columns));
    }
  }

  // Union of the column ranges, ascending and without duplicates.
  std::vector<std::uint32_t> xs;
  for (const IndexRange& r : columnRanges) {
    for (std::int64_t x = r.first; x <= r.last; ++x) xs.push_back(static_cast<std::uint32_t>(x));
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());

  std::vector<TileId> tiles;
  tiles.reserve(static_cast<std::size_t>(rowRange.last - rowRange.first + 1) * xs.size());
  for (std::int64_t y = rowRange.first; y <= rowRange.last; ++y) {
    for (std::uint32_t x : xs) tiles.push_back({level, x, static_cast<std::uint32_t>(y)});
  }
  return tiles;
}

}  // namespace atmoglobe::globe
