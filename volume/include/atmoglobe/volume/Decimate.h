#pragma once
// Lower-resolution copies of volumes, for drawing when the full one does not fit the GPU
// (engine: GridVolumeGL / RadarVolumeGL fall back to them with a warning). Every `factor`-th
// sample is kept (no averaging: values stay values the file holds), so the copy samples like the
// original at its kept points. GL-free.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <cstddef>

namespace atmoglobe::volume {

/// Every `factor`-th column and row (the last ones kept, so the grid covers the same region) and,
/// when `levels` is true, every `factor`-th level (the top kept). A wrapping global grid stays
/// wrapping only when its kept columns stay evenly spaced across the seam. A reduced grid keeps
/// every `factor`-th row and in each row every `factor`-th point, except that a wrapping row
/// whose length is not a multiple of `factor` is resampled linearly along the row to
/// ceil(n / factor) points evenly round the circle (the grid keeps wrapping). factor >= 2.
GridVolume decimateGrid(const GridVolume& grid, std::size_t factor, bool levels = false);

/// A rectangle of a grid's columns and rows (all levels): columns firstColumn .. firstColumn +
/// columnCount - 1, taken modulo nx on a grid that wraps in longitude (a window across the seam).
struct GridWindow {
  std::size_t firstColumn = 0, columnCount = 0;
  std::size_t firstRow = 0, rowCount = 0;
  bool empty() const { return columnCount == 0 || rowCount == 0; }
};

/// The points of `window` as a grid of their own, at the grid's resolution (values, positions,
/// heights, pressures as they are; longitudes made increasing across the seam). It wraps only
/// when the window is the whole grid. A reduced grid's window counts columns on its reference
/// axis (lonDeg) and is a reduced grid whose rows keep their own points from the one at or west
/// of the window's west edge to the one at or east of its east edge (between the edges a sample
/// has the neighbours it has in the grid). `pointStride` > 1 (reduced grids; a window to be
/// decimated by that factor, decimateGrid): each such row is lengthened eastwards (within the row)
/// to a multiple of `pointStride` spacings, so that every pointStride-th point from its first still
/// reaches the east edge. Errors: a window of fewer than 2 x 2 points or outside the grid.
Result<GridVolume> gridWindow(const GridVolume& grid, const GridWindow& window, std::size_t pointStride = 1);

/// Every `factor`-th gate of every sweep (gate spacing times factor, the first gate kept), and,
/// when `rays` is true, every `factor`-th ray. Value range recomputed. factor >= 2.
PolarVolume decimatePolar(const PolarVolume& volume, int factor, bool rays = false);

}  // namespace atmoglobe::volume
