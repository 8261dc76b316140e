#pragma once
// Level of detail for forecast grids: coarser copies of a grid (block means of its columns, rows
// and levels) and the rule that picks one by the footprint of a pixel, so that a grid seen from
// far is marched on cells about as large as the pixels that show it (docs/grids.md, "Level of
// detail"). GL-free: engine/GridSourceGL.h keeps the copies on the GPU and picks one per frame.
//
// Level L halves the columns and rows L times (blocks of 2^L x 2^L grid points) and the levels
// as often as the grid keeps at least kMinDetailLevels of them. A coarse point is the block's
// mean: its position (the mean latitude and longitude of the block's points), each level's
// height (the mean of the block's heights, so heights still increase upwards) and its value
// (the mean of the block's finite values where at least half of them are finite, else missing).
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridVolume.h>

#include <cstddef>

namespace atmoglobe::volume {

/// Levels are halved only while at least this many remain (the vertical structure a view from
/// far still shows).
constexpr std::size_t kMinDetailLevels = 8;

/// The grid with blocks of `horizontalFactor` x `horizontalFactor` points and `verticalFactor`
/// levels replaced by their means (file comment); a last partial block is the mean of what it
/// holds. A grid that wraps in longitude keeps wrapping when its columns divide by the factor.
/// Errors: a reduced grid (rows of different lengths: no blocks), a factor of 0, fewer than
/// 2 x 2 x 2 points left.
Result<GridVolume> coarsenGrid(const GridVolume& grid, std::size_t horizontalFactor, std::size_t verticalFactor);

/// The factors of detail level `level` of `grid` (0: the grid itself): 2^level across, and 2^level
/// upwards while at least kMinDetailLevels levels remain.
std::size_t detailHorizontalFactor(int level);
std::size_t detailVerticalFactor(const GridVolume& grid, int level);
/// The coarsest level worth building for `grid`: columns and rows stay at least 8, and a
/// wrapping grid's columns divide evenly (so it keeps wrapping); 0 for reduced grids.
int maxDetailLevel(const GridVolume& grid);

/// The ground a pixel spans at `distanceMeters` from the eye (fovY in degrees over heightPx
/// pixels, drawn at `imageScale` of the frame's resolution).
double pixelFootprintMeters(double distanceMeters, double fovYDeg, int heightPx, double imageScale);
/// The detail level for a pixel footprint: the coarsest whose column spacing (columnSpacingMeters
/// x 2^L) is at most one footprint (no cell wider than a pixel), clamped to [0, maxLevel]. Cells
/// of up to two pixels were measured and rejected: 2.3 dB further from the 4 x 4-ray reference
/// than the grid itself on the bench's global view (docs/grids.md, "Level of detail").
int gridDetailLevel(double columnSpacingMeters, double footprintMeters, int maxLevel);

}  // namespace atmoglobe::volume
