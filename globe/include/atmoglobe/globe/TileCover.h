#pragma once
// Which tiles of one level cover a longitude/latitude box (GL-free).
#include <atmoglobe/globe/TileId.h>

#include <vector>

namespace atmoglobe::globe {

/// Tiles of `level` that intersect `rect` (degrees), sorted by (y, x).
///
/// - rect.westDeg > rect.eastDeg means the box crosses the antimeridian (e.g. west 170,
///   east -170). Longitudes outside [-180, 180] are wrapped; a box with
///   eastDeg - westDeg >= 360 covers every column.
/// - Latitudes are clamped to [-90, 90]; southDeg > northDeg (after clamping) is an empty
///   box and gives no tiles.
/// - "Intersect" means a common area of positive size: a box whose edge lies exactly on a
///   tile boundary does not pick up the tile on the other side of it. A box of zero width
///   (or height) picks the single column (row) containing it; a value exactly on a
///   boundary goes to the tile east (south) of it, except at 180 deg east / 90 deg south
///   which belong to the last column / row.
/// Preconditions (asserted): finite values, 0 <= level <= kMaxTileLevel. The result has
/// one entry per tile: the caller bounds its size by the level it asks for (a whole-world
/// box at level z gives 2^(2z+1) tiles).
std::vector<TileId> tilesCovering(const GeoRectangle& rect, int level);

}  // namespace atmoglobe::globe
