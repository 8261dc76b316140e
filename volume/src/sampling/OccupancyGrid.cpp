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

OccupancyBox occupancyBounds(std::span<const OccupancyBox> boxes) {
  OccupancyBox u{glm::dvec3(1e300), glm::dvec3(-1e300), kOccupancyEmptyValue};
  for (const OccupancyBox& b : boxes) u = occupancyBounds(u, b);
  return u;
}

OccupancyBox occupancyBounds(const OccupancyBox& a, const OccupancyBox& b) {
  return {glm::min(a.lo, b.lo), glm::max(a.hi, b.hi), std::max(a.maxValue, b.maxValue)};
}

glm::ivec3 occupancyCellsFor(const std::vector<OccupancyBox>& boxes, const glm::dvec3& targetCellMeters,
                             std::size_t maxCells) {
  return occupancyCellsOver(occupancyBounds(boxes), targetCellMeters, maxCells);
}

glm::ivec3 occupancyCellsOver(const OccupancyBox& bounds, const glm::dvec3& targetCellMeters, std::size_t maxCells) {
  constexpr int kMin = 8;
  if (empty(bounds)) return glm::ivec3(kMin);
  const glm::dvec3 want =
      glm::max(glm::ceil((bounds.hi - bounds.lo) / targetCellMeters) + 2.0, glm::dvec3(kMin));  // 2 spare
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

OccupancyGrid occupancyLayout(const glm::dvec3& originEcef, const glm::dmat3& localToEcef, const OccupancyBox& bounds,
                              const glm::ivec3& cells) {
  OccupancyGrid grid;
  grid.originEcef = originEcef;
  grid.localToEcef = localToEcef;
  grid.cells = glm::max(cells, glm::ivec3(3));
  grid.cellSizeMeters = (bounds.hi - bounds.lo) / glm::dvec3(grid.cells - 2) + 1e-3;  // one spare cell on each side
  grid.minLocal = bounds.lo - grid.cellSizeMeters;
  grid.blocks = (grid.cells + (OccupancyGrid::kBlock - 1)) / OccupancyGrid::kBlock;
  grid.maxValues.clear();
  grid.blockMaxValues.clear();
  return grid;
}

bool sameOccupancyLayout(const OccupancyGrid& a, const OccupancyGrid& b) {
  return a.originEcef == b.originEcef && a.localToEcef == b.localToEcef && a.cells == b.cells &&
         a.minLocal == b.minLocal && a.cellSizeMeters == b.cellSizeMeters;
}

OccupancyCellRange occupancyCellsOf(const OccupancyGrid& grid, const glm::dvec3& lo, const glm::dvec3& hi) {
  return {glm::max(glm::ivec3(glm::floor((lo - grid.minLocal) / grid.cellSizeMeters)), glm::ivec3(0)),
          glm::min(glm::ivec3(glm::floor((hi - grid.minLocal) / grid.cellSizeMeters)), grid.cells - 1)};
}

bool overlaps(const OccupancyCellRange& a, const OccupancyCellRange& b) {
  return !a.empty() && !b.empty() && glm::all(glm::lessThanEqual(glm::max(a.first, b.first), glm::min(a.last, b.last)));
}

void rebuildOccupancyCells(OccupancyGrid& grid, const OccupancyCellRange& range,
                           const std::vector<std::span<const OccupancyBox>>& sources) {
  constexpr int kB = OccupancyGrid::kBlock;
  const OccupancyCellRange all{glm::ivec3(0), grid.cells - 1};
  const OccupancyCellRange r{glm::max(range.first, all.first), glm::min(range.last, all.last)};
  if (r.empty()) return;
  // Each box's cells within the range found once, the boxes listed by the slabs of kBlock layers
  // they reach, and each slab written on its own thread (it writes its own cells only; the
  // maximum does not depend on the order).
  struct Touch {
    OccupancyCellRange cells;
    float value;
  };
  std::vector<Touch> touches;
  for (std::span<const OccupancyBox> boxes : sources) {
    const std::size_t base = touches.size();
    touches.resize(base + boxes.size());
    globe::parallelFor((boxes.size() + 4095) / 4096, [&](std::size_t chunk) {
      for (std::size_t i = chunk * 4096; i < std::min(boxes.size(), (chunk + 1) * 4096); ++i) {
        const OccupancyCellRange c = occupancyCellsOf(grid, boxes[i].lo, boxes[i].hi);
        touches[base + i] = {{glm::max(c.first, r.first), glm::min(c.last, r.last)}, boxes[i].maxValue};
      }
    });
    touches.erase(std::remove_if(touches.begin() + static_cast<std::ptrdiff_t>(base), touches.end(),
                                 [](const Touch& t) { return t.cells.empty(); }),
                  touches.end());
  }
  const int slab0 = r.first.z / kB, slabs = r.last.z / kB - slab0 + 1;
  std::vector<std::size_t> slabStart(static_cast<std::size_t>(slabs) + 1, 0);
  for (const Touch& t : touches)
    for (int z = t.cells.first.z / kB; z <= t.cells.last.z / kB; ++z)
      ++slabStart[static_cast<std::size_t>(z - slab0) + 1];
  for (std::size_t k = 0; k + 1 < slabStart.size(); ++k) slabStart[k + 1] += slabStart[k];
  std::vector<std::uint32_t> slabTouches(slabStart.back());
  {
    std::vector<std::size_t> fill(slabStart.begin(), slabStart.end() - 1);
    for (std::size_t i = 0; i < touches.size(); ++i)
      for (int z = touches[i].cells.first.z / kB; z <= touches[i].cells.last.z / kB; ++z)
        slabTouches[fill[static_cast<std::size_t>(z - slab0)]++] = static_cast<std::uint32_t>(i);
  }
  globe::parallelFor(static_cast<std::size_t>(slabs), [&](std::size_t k) {
    const int slab = slab0 + static_cast<int>(k);
    const int zLo = std::max(slab * kB, r.first.z), zHi = std::min(slab * kB + kB - 1, r.last.z);
    for (int z = zLo; z <= zHi; ++z)
      for (int y = r.first.y; y <= r.last.y; ++y)
        std::fill_n(grid.maxValues.begin() + static_cast<std::ptrdiff_t>(grid.cellIndex(r.first.x, y, z)),
                    r.last.x - r.first.x + 1, kOccupancyEmptyValue);
    for (std::size_t j = slabStart[k]; j < slabStart[k + 1]; ++j) {
      const Touch& t = touches[slabTouches[j]];
      for (int z = std::max(t.cells.first.z, zLo); z <= std::min(t.cells.last.z, zHi); ++z)
        for (int y = t.cells.first.y; y <= t.cells.last.y; ++y)
          for (int x = t.cells.first.x; x <= t.cells.last.x; ++x) {
            float& cell = grid.maxValues[grid.cellIndex(x, y, z)];
            cell = std::max(cell, t.value);
          }
    }
  });
  // The second level over the blocks the range meets: the max over blocks of kBlock^3 cells, so
  // that a ray crosses a large empty region in a few jumps instead of one per cell.
  const glm::ivec3 b0 = r.first / kB, b1 = r.last / kB;
  globe::parallelFor(static_cast<std::size_t>(b1.z - b0.z + 1), [&](std::size_t k) {
    const int bz = b0.z + static_cast<int>(k);
    for (int by = b0.y; by <= b1.y; ++by)
      for (int bx = b0.x; bx <= b1.x; ++bx) {
        float m = kOccupancyEmptyValue;
        for (int z = bz * kB; z < std::min(bz * kB + kB, grid.cells.z); ++z)
          for (int y = by * kB; y < std::min(by * kB + kB, grid.cells.y); ++y)
            for (int x = bx * kB; x < std::min(bx * kB + kB, grid.cells.x); ++x)
              m = std::max(m, grid.maxValues[grid.cellIndex(x, y, z)]);
        grid.blockMaxValues[(static_cast<std::size_t>(bz) * grid.blocks.y + by) * grid.blocks.x + bx] = m;
      }
  });
}

OccupancyGrid buildOccupancyGrid(const glm::dvec3& originEcef, const glm::dmat3& localToEcef,
                                 const std::vector<OccupancyBox>& boxes, const glm::ivec3& cells) {
  return buildOccupancyGrid(originEcef, localToEcef, {std::span<const OccupancyBox>(boxes)}, occupancyBounds(boxes),
                            cells);
}

OccupancyGrid buildOccupancyGrid(const glm::dvec3& originEcef, const glm::dmat3& localToEcef,
                                 const std::vector<std::span<const OccupancyBox>>& sources, const OccupancyBox& bounds,
                                 const glm::ivec3& cells) {
  if (empty(bounds)) {
    OccupancyGrid grid;
    grid.originEcef = originEcef;
    grid.localToEcef = localToEcef;
    return grid;
  }
  OccupancyGrid grid = occupancyLayout(originEcef, localToEcef, bounds, cells);
  grid.maxValues.assign(static_cast<std::size_t>(grid.cells.x) * grid.cells.y * grid.cells.z, kOccupancyEmptyValue);
  grid.blockMaxValues.assign(static_cast<std::size_t>(grid.blocks.x) * grid.blocks.y * grid.blocks.z,
                             kOccupancyEmptyValue);
  rebuildOccupancyCells(grid, {glm::ivec3(0), grid.cells - 1}, sources);
  return grid;
}

}  // namespace atmoglobe::volume
