// The empty-space grid (OccupancyGrid.h).
#include <atmoglobe/volume/OccupancyGrid.h>

#include <atmoglobe/globe/ParallelFor.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

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
  // Every cell each box touches, in slabs of kBlock layers on several threads: each box's cells
  // found once, the boxes listed by the slabs they reach, and each slab writing its own cells and
  // blocks only (the maximum does not depend on the order).
  constexpr int kB = OccupancyGrid::kBlock;
  grid.blocks = (grid.cells + (kB - 1)) / kB;
  grid.blockMaxValues.assign(static_cast<std::size_t>(grid.blocks.x) * grid.blocks.y * grid.blocks.z,
                             kOccupancyEmptyValue);
  std::vector<glm::ivec3> first(boxes.size()), last(boxes.size());
  globe::parallelFor((boxes.size() + 4095) / 4096, [&](std::size_t chunk) {
    for (std::size_t i = chunk * 4096; i < std::min(boxes.size(), (chunk + 1) * 4096); ++i) {
      first[i] = glm::max(glm::ivec3(glm::floor((boxes[i].lo - grid.minLocal) / grid.cellSizeMeters)), glm::ivec3(0));
      last[i] = glm::min(glm::ivec3(glm::floor((boxes[i].hi - grid.minLocal) / grid.cellSizeMeters)), grid.cells - 1);
    }
  });
  const std::size_t slabs = static_cast<std::size_t>(grid.blocks.z);
  std::vector<std::size_t> slabStart(slabs + 1, 0);
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (int z = first[i].z / kB; z <= last[i].z / kB; ++z) ++slabStart[static_cast<std::size_t>(z) + 1];
  for (std::size_t k = 0; k < slabs; ++k) slabStart[k + 1] += slabStart[k];
  std::vector<std::uint32_t> slabBoxes(slabStart.back());
  {
    std::vector<std::size_t> fill(slabStart.begin(), slabStart.end() - 1);
    for (std::size_t i = 0; i < boxes.size(); ++i)
      for (int z = first[i].z / kB; z <= last[i].z / kB; ++z)
        slabBoxes[fill[static_cast<std::size_t>(z)]++] = static_cast<std::uint32_t>(i);
  }
  globe::parallelFor(slabs, [&](std::size_t slab) {
    const int zLo = static_cast<int>(slab) * kB, zHi = std::min(zLo + kB, grid.cells.z) - 1;
    for (std::size_t k = slabStart[slab]; k < slabStart[slab + 1]; ++k) {
      const std::uint32_t i = slabBoxes[k];
      const glm::ivec3 c0 = first[i], c1 = last[i];
      const float value = boxes[i].maxValue;
      for (int z = std::max(c0.z, zLo); z <= std::min(c1.z, zHi); ++z)
        for (int y = c0.y; y <= c1.y; ++y)
          for (int x = c0.x; x <= c1.x; ++x) {
            float& cell = grid.maxValues[grid.cellIndex(x, y, z)];
            cell = std::max(cell, value);
          }
    }
    // The second level: the max over blocks of kBlock^3 cells, so that a ray crosses a large
    // empty region in a few jumps instead of one per cell.
    for (int z = zLo; z <= zHi; ++z)
      for (int y = 0; y < grid.cells.y; ++y)
        for (int x = 0; x < grid.cells.x; ++x) {
          float& m =
              grid.blockMaxValues[(static_cast<std::size_t>(z / kB) * grid.blocks.y + y / kB) * grid.blocks.x + x / kB];
          m = std::max(m, grid.maxValues[grid.cellIndex(x, y, z)]);
        }
  });
  return grid;
}

}  // namespace atmoglobe::volume
