#pragma once
// The grid bench's volumes and views: the built-in SYNTHETIC grids (the regional 400 x 400 x 35
// grid of `atmoglobe synth --grid` and the global 0.25-degree 1440 x 721 x 37 pressure-level grid
// of volume::writeSyntheticGlobalGrid) or a file given with --grid; the crop of a grid each view
// can see; the ellipsoid's depth for the marcher.
//
// Views (fixed, so that references can be cached):
//  - regional-oblique: 250 km south-south-west of the grid centre, 100 km up, looking at the
//    centre (the supercell and the squall line at 21Z), fovY 50 deg;
//  - regional-down: 2500 km above the grid centre, fovY 50 deg (the whole 2000 km domain);
//  - global-space: 12,000 km above 15N 40W, fovY 45 deg (the Atlantic half of the globe: the
//    cyclone, the storm tracks, the ITCZ);
//  - global-cyclone: the north Atlantic cyclone from 900 km south-south-west, 450 km up, fovY 50.
//  - global-far: 35,000 km above 15N 40W, fovY 45: the disc small in the picture (level of detail).
// A grid given as a file gets FILE-oblique and FILE-down views of the same kind around its centre.
#include <atmoglobe/bench/Views.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridVolume.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::bench {

/// A grid of the bench: a built-in synthetic one (path empty: written to OUT/grids/ when missing)
/// or a file.
struct GridBenchFile {
  std::string key;       ///< regional, global, or the file's stem
  std::string path;      ///< the netCDF file
  std::string variable;  ///< empty: the reader's default
  std::size_t timeIndex = 0;
  long member = -1;  ///< ensemble member (GridReadOptions::member); -1: the first
  bool synthetic = false;
};

/// The built-in grids: regional (time step 3, 21Z: the supercell at KTLX) and global; quick: the
/// same two (each has one quick view). Their files go to `dir` (written only when missing or from
/// another version: the name holds the version).
std::vector<GridBenchFile> builtinGridFiles(const std::filesystem::path& dir);

/// Writes a built-in grid's file if it is not there yet; progress on `log`.
Status ensureGridFile(const GridBenchFile& file, std::ostream& log);

/// Reads the whole grid at its time step (the reference's), with its transfer function (auto, by
/// the variable) and height variables. Errors name the file.
Result<BenchVolume> loadGridBenchVolume(const GridBenchFile& file);

/// The view names of a grid (see the file comment); quick: the first only.
std::vector<std::string> gridViewNames(const GridBenchFile& file, bool quick);

/// The views of a loaded grid volume (crops not yet read: attachCropGL does it).
std::vector<BenchView> gridViews(const BenchVolume& v, bool quick);

/// The crop of `grid` that a camera can see: columns whose bottom or top point lies in front of
/// the camera, inside the image (plus a margin of 4 % of its size) and not behind the ellipsoid,
/// tested on every `stride`-th column and row (stride chosen for about 256 x 256 tests), then
/// widened by a stride. Longitudes: the shortest arc holding every visible column (a wrapping
/// grid may cross the antimeridian); all of them where the arc exceeds 300 deg; latitudes reach
/// the pole where a global grid's end row is visible. Nothing visible: an empty crop (south > north).
volume::GridCrop visibleCrop(const engine::Camera& camera, const volume::GridVolume& grid);

/// Reads the view's crop of its grid and uploads it (view.gl, view.crop, view.cropBytesRead).
Status attachCropGL(BenchView& view);

/// The reverse-Z depth of the WGS84 ellipsoid for `camera` (GL row order: bottom row first;
/// 0 where the ray misses): near / (distance along the view axis), what the globe pass leaves in
/// the depth buffer, computed exactly in double per pixel centre.
std::vector<float> ellipsoidDepth(const engine::Camera& camera);

}  // namespace atmoglobe::bench
