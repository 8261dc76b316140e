// The empty-space grid (OccupancyGrid.h).
#include <atmoglobe/volume/OccupancyGrid.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {

float OccupancyGrid::maxAtLocal(const glm::dvec3& local) const {
  const glm::dvec3 c = glm::floor((local - minLocal) / cellSizeMeters);
  if (!(c.x >= 0.0 && c.y >= 0.0 && c.z >= 0.0 && c.x < cells.x && c.y < cells.y && c.z < cells.z))
    return kOccupancyEmptyValue;
  return maxValues[cellIndex(static_cast<int>(c.x), static_cast<int>(c.y), static_cast<int>(c.z))];
}

glm::ivec3 occupancyCellsFor(const std::vector<OccupancyBox>& boxes, const glm::dvec3& targetCellMeters,
                             std::size_t maxCells) {
  constexpr int kMin = 8;
  if (boxes.empty()) return glm::ivec3(kMin);
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const OccupancyBox& b : boxes) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  const glm::dvec3 want = glm::max(glm::ceil((hi - lo) / targetCellMeters) + 2.0, glm::dvec3(kMin));  // 2 spare
  const double total = want.x * want.y * want.z;
  const double scale = total > static_cast<double>(maxCells) ? std::cbrt(static_cast<double>(maxCells) / total) : 1.0;
  glm::ivec3 cells = glm::max(glm::ivec3(glm::floor(want * scale)), glm::ivec3(kMin));
  // An axis held at the minimum leaves the others more room: shrink the largest until it fits.
  while (static_cast<double>(cells.x) * cells.y * cells.z > static_cast<double>(maxCells)) {
    int& largest = cells.x >= cells.y && cells.x >= cells.z ? cells.x : (cells.y >= cells.z ? cells.y : cells.z);
    if (largest <= kMin) break;
    --largest;
  }
  return cells;
}

OccupancyGrid buildOccupancyGrid(const glm::dvec3& originEcef, const glm::dmat3& localToEcef,
                                 const std::vector<OccupancyBox>& boxes, const glm::ivec3& cells) {
  OccupancyGrid grid;
  grid.originEcef = originEcef;
  grid.localToEcef = localToEcef;
  if (boxes.empty()) return grid;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const OccupancyBox& b : boxes) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  grid.cells = glm::max(cells, glm::ivec3(3));
  grid.cellSizeMeters = (hi - lo) / glm::dvec3(grid.cells - 2) + 1e-3;  // one spare cell on each side
  grid.minLocal = lo - grid.cellSizeMeters;
  grid.maxValues.assign(static_cast<std::size_t>(grid.cells.x) * grid.cells.y * grid.cells.z, kOccupancyEmptyValue);
  for (const OccupancyBox& b : boxes) {
    // Every cell the box touches.
    const glm::ivec3 c0 = glm::max(glm::ivec3(glm::floor((b.lo - grid.minLocal) / grid.cellSizeMeters)), glm::ivec3(0));
    const glm::ivec3 c1 =
        glm::min(glm::ivec3(glm::floor((b.hi - grid.minLocal) / grid.cellSizeMeters)), grid.cells - 1);
    for (int z = c0.z; z <= c1.z; ++z)
      for (int y = c0.y; y <= c1.y; ++y)
        for (int x = c0.x; x <= c1.x; ++x) {
          float& cell = grid.maxValues[grid.cellIndex(x, y, z)];
          cell = std::max(cell, b.maxValue);
        }
  }
  // The second level: the max over blocks of kBlock^3 cells, so that a ray crosses a large empty
  // region in a few jumps instead of one per cell.
  constexpr int kB = OccupancyGrid::kBlock;
  grid.blocks = (grid.cells + (kB - 1)) / kB;
  grid.blockMaxValues.assign(static_cast<std::size_t>(grid.blocks.x) * grid.blocks.y * grid.blocks.z,
                             kOccupancyEmptyValue);
  for (int z = 0; z < grid.cells.z; ++z)
    for (int y = 0; y < grid.cells.y; ++y)
      for (int x = 0; x < grid.cells.x; ++x) {
        float& b =
            grid.blockMaxValues[(static_cast<std::size_t>(z / kB) * grid.blocks.y + y / kB) * grid.blocks.x + x / kB];
        b = std::max(b, grid.maxValues[grid.cellIndex(x, y, z)]);
      }
  return grid;
}

}  // namespace atmoglobe::volume
