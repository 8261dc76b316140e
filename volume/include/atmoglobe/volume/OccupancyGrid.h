#pragma once
// The empty-space (occupancy) grid of a volume: a box of cells in a local ENU frame holding,
// per cell, the largest value that any sample inside the cell can see, and a second level with
// the largest value per block of kBlock^3 cells. Conservative: a point whose sample is Echo with
// value v lies in a cell whose value is >= v (OccupancyGridTest checks this with random points
// inside every echo), so a renderer may jump over a cell whose value is below its threshold
// (DVR: the zero-opacity value; MIP: the maximum so far; isosurface: the iso value).
// GL-free; the engine uploads it as two 3-D textures.
#include <glm/glm.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace atmoglobe::volume {

/// Stored for "nothing measured here" (below every field value; representable as a half float).
inline constexpr float kOccupancyEmptyValue = -60000.0f;

struct OccupancyGrid {
  static constexpr int kBlock = 8;  ///< cells per block edge of the second level
  glm::dvec3 originEcef{0.0};       ///< origin of the local frame (m)
  glm::dmat3 localToEcef{1.0};      ///< columns: the frame's x, y, z (east, north, up) as ECEF unit vectors
  glm::ivec3 cells{1};
  glm::dvec3 minLocal{0.0};  ///< the box's lower corner in the local frame (m)
  glm::dvec3 cellSizeMeters{1.0};
  std::vector<float> maxValues{kOccupancyEmptyValue};  ///< [z][y][x]
  glm::ivec3 blocks{1};
  std::vector<float> blockMaxValues{kOccupancyEmptyValue};  ///< [z][y][x] over kBlock^3 cells

  glm::dvec3 localOfEcef(const glm::dvec3& ecef) const { return glm::transpose(localToEcef) * (ecef - originEcef); }
  /// The cell's value at a local position; kOccupancyEmptyValue outside the box.
  float maxAtLocal(const glm::dvec3& local) const;
  std::size_t cellIndex(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(cells.y) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(cells.x) +
           static_cast<std::size_t>(x);
  }
};

/// A box in the local frame (m) that holds every point whose sample can see `maxValue`.
struct OccupancyBox {
  glm::dvec3 lo{0.0}, hi{0.0};
  float maxValue = kOccupancyEmptyValue;
};

/// The union of the boxes (lo the smallest corner, hi the largest, maxValue the largest value);
/// none: lo +1e300, hi -1e300 (empty()).
OccupancyBox occupancyBounds(std::span<const OccupancyBox> boxes);
/// The union of two such unions.
OccupancyBox occupancyBounds(const OccupancyBox& a, const OccupancyBox& b);
inline bool empty(const OccupancyBox& b) { return !(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z); }

/// Cells for a grid over the union of `boxes`: about `targetCellMeters` a cell along each axis,
/// at least 8 per axis, and, where that would be more than `maxCells` in all, every axis scaled
/// down alike until it fits (the cells then grow alike in proportion). No boxes: 8 per axis.
glm::ivec3 occupancyCellsFor(const std::vector<OccupancyBox>& boxes, const glm::dvec3& targetCellMeters,
                             std::size_t maxCells);
/// The same over their union `bounds` (occupancyBounds).
glm::ivec3 occupancyCellsOver(const OccupancyBox& bounds, const glm::dvec3& targetCellMeters, std::size_t maxCells);

/// The grid of `cells` over the union of the boxes (one spare cell on each side), each cell the
/// largest value of the boxes it touches, and its block level. No boxes: a single empty cell.
OccupancyGrid buildOccupancyGrid(const glm::dvec3& originEcef, const glm::dmat3& localToEcef,
                                 const std::vector<OccupancyBox>& boxes, const glm::ivec3& cells);
/// The same from boxes in several lists (a network's radars), `bounds` their union.
OccupancyGrid buildOccupancyGrid(const glm::dvec3& originEcef, const glm::dmat3& localToEcef,
                                 const std::vector<std::span<const OccupancyBox>>& sources, const OccupancyBox& bounds,
                                 const glm::ivec3& cells);

/// The frame, cells and cell size buildOccupancyGrid gives over `bounds` (not empty), without
/// its values (maxValues and blockMaxValues empty): to tell whether a grid built before has the
/// layout a new one would have (sameOccupancyLayout), so that only a part of it need be redone.
OccupancyGrid occupancyLayout(const glm::dvec3& originEcef, const glm::dmat3& localToEcef, const OccupancyBox& bounds,
                              const glm::ivec3& cells);
/// Frames, cells and cell sizes equal bit for bit.
bool sameOccupancyLayout(const OccupancyGrid& a, const OccupancyGrid& b);

/// A box of cells, inclusive; empty where any last < first.
struct OccupancyCellRange {
  glm::ivec3 first{0}, last{-1};
  bool empty() const { return last.x < first.x || last.y < first.y || last.z < first.z; }
};
/// The cells that a box from lo to hi touches, as buildOccupancyGrid counts them (clamped to the
/// grid).
OccupancyCellRange occupancyCellsOf(const OccupancyGrid& grid, const glm::dvec3& lo, const glm::dvec3& hi);
/// Whether two ranges share a cell.
bool overlaps(const OccupancyCellRange& a, const OccupancyCellRange& b);

/// Computes the cells of `range` again from `sources` (every box that may touch them; boxes are
/// clipped to the range) and the blocks over them. Afterwards the grid is what buildOccupancyGrid
/// gives for the boxes in its layout wherever the boxes outside `sources` touch no cell of the
/// range and the cells outside it were built from the same boxes: a network step whose changed
/// radars' old and new boxes lie within the range (OccupancyGridTest checks the equality).
void rebuildOccupancyCells(OccupancyGrid& grid, const OccupancyCellRange& range,
                           const std::vector<std::span<const OccupancyBox>>& sources);

}  // namespace atmoglobe::volume
