// Reduced grids in the forecast-grid model (GridVolume.h): the reference longitude axis and the
// check of a reduced grid's row tables.
#include <atmoglobe/volume/GridVolume.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace atmoglobe::volume {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double GridVolume::reducedWestDeg() const {
  if (!reduced() || rowFirstLonDeg.empty()) return kNaN;
  return *std::min_element(rowFirstLonDeg.begin(), rowFirstLonDeg.end());
}

double GridVolume::reducedSpacingDeg() const {
  if (!reduced() || nx == 0) return kNaN;
  if (wrapsLongitude) return 360.0 / static_cast<double>(nx);
  double finest = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < rowSpacingDeg.size() && j < rowLengthPoints.size(); ++j)
    if (rowLengthPoints[j] >= 2) finest = std::min(finest, rowSpacingDeg[j]);
  if (std::isfinite(finest)) return finest;
  // Single points only: any spacing names them.
  return rowSpacingDeg.empty() ? 1.0 : *std::min_element(rowSpacingDeg.begin(), rowSpacingDeg.end());
}

double GridVolume::reducedEastDeg() const {
  if (!reduced()) return kNaN;
  if (wrapsLongitude) return reducedWestDeg() + 360.0 - reducedSpacingDeg();
  double east = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < rowLengthPoints.size(); ++j)
    east = std::max(east, rowFirstLonDeg[j] + static_cast<double>(rowLengthPoints[j] - 1) * rowSpacingDeg[j]);
  return east;
}

Status finishReducedGrid(GridVolume& g) {
  if (g.curvilinear) return makeError("a reduced grid is not curvilinear");
  if (g.ny == 0 || g.nx == 0) return makeError("a reduced grid needs at least one row and one point");
  if (g.rowLengthPoints.size() != g.ny || g.rowFirstLonDeg.size() != g.ny || g.rowSpacingDeg.size() != g.ny ||
      g.latDeg.size() != g.ny)
    return makeError("a reduced grid needs a latitude, a length, a first longitude and a spacing per row (" +
                     std::to_string(g.ny) + " rows)");
  std::size_t longest = 0;
  for (std::size_t j = 0; j < g.ny; ++j) {
    const std::size_t n = g.rowLengthPoints[j];
    const std::string row = "row " + std::to_string(j) + ": ";
    if (n == 0) return makeError(row + "no points (a reduced grid's rows hold at least one)");
    if (n > g.nx) return makeError(row + std::to_string(n) + " points, more than nx = " + std::to_string(g.nx));
    if (!std::isfinite(g.rowFirstLonDeg[j]) || !(g.rowSpacingDeg[j] > 0.0) || !std::isfinite(g.rowSpacingDeg[j]))
      return makeError(row + "first longitude and spacing must be finite, the spacing positive");
    if (g.wrapsLongitude && std::abs(static_cast<double>(n) * g.rowSpacingDeg[j] - 360.0) > 1e-6)
      return makeError(row + std::to_string(n) + " points " + std::to_string(g.rowSpacingDeg[j]) +
                       " degrees apart do not cover the circle of a wrapping grid");
    longest = std::max(longest, n);
  }
  if (longest != g.nx) return makeError("nx must be the longest row's length");
  for (std::size_t j = 1; j < g.ny; ++j)
    if (!(g.latDeg[j] > g.latDeg[j - 1])) return makeError("row latitudes must increase strictly");
  const double west = g.reducedWestDeg(), step = g.reducedSpacingDeg();
  g.lonDeg.resize(g.nx);
  for (std::size_t i = 0; i < g.nx; ++i) g.lonDeg[i] = west + static_cast<double>(i) * step;
  return Ok{};
}

}  // namespace atmoglobe::volume
