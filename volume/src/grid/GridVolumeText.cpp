// What a grid volume says about itself in titles, and its value range (GridVolume.h).
#include "GridInternal.h"

#include <atmoglobe/volume/GridVolume.h>

#include <cmath>
#include <limits>

namespace atmoglobe::volume {

void setValueRange(GridVolume& grid) {
  grid.valueMin = grid.valueMax = std::numeric_limits<float>::quiet_NaN();
  for (float v : grid.values) {
    if (!std::isfinite(v)) continue;
    if (!(v >= grid.valueMin)) grid.valueMin = v;  // NaN start: the first finite value
    if (!(v <= grid.valueMax)) grid.valueMax = v;
  }
}

long memberLabel(const GridVolume& grid, long fallback) {
  long label = grid.member >= 0 ? grid.member : fallback;
  for (const GridExtraDimension& e : grid.extraDimensions)
    if (e.ensemble) label = std::isfinite(e.value) ? std::lround(e.value) : static_cast<long>(e.index);
  return label;
}

std::string memberText(const GridVolume& grid) {
  if (!grid.ensembleStatistic.empty())
    return grid.ensembleStatistic + " of " + std::to_string(grid.ensembleMembers.size()) + " members";
  if (grid.member >= 0) return "member " + std::to_string(grid.member);
  return {};
}

std::string extraIndexText(const GridVolume& grid) {
  std::string out;
  for (const GridExtraDimension& e : grid.extraDimensions) {
    if (e.ensemble) continue;  // said as the member
    out += out.empty() ? "" : ", ";
    if (std::isfinite(e.value))
      out += e.name + " " + grid::num(e.value, e.value == std::floor(e.value) ? 0 : 3) +
             (e.units.empty() ? "" : " " + e.units) + " (index " + std::to_string(e.index) + ")";
    else out += e.name + " index " + std::to_string(e.index);
  }
  return out;
}

}  // namespace atmoglobe::volume
