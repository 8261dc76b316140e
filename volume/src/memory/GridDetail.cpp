// Level of detail for forecast grids (GridDetail.h).
#include <atmoglobe/volume/GridDetail.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace atmoglobe::volume {

namespace {

/// [first, end) of block b of `factor` items among `count`.
std::pair<std::size_t, std::size_t> block(std::size_t b, std::size_t factor, std::size_t count) {
  return {b * factor, std::min(count, (b + 1) * factor)};
}

std::size_t blocks(std::size_t count, std::size_t factor) { return (count + factor - 1) / factor; }

}  // namespace

Result<GridVolume> coarsenGrid(const GridVolume& g, std::size_t hf, std::size_t vf) {
  const std::string what = g.path + ": '" + g.variable + "'";
  if (g.reduced()) return makeError(what + " is on a reduced grid: no coarser copies (rows of different lengths)");
  if (hf == 0 || vf == 0) return makeError(what + ": a coarsening factor must be at least 1");
  const std::size_t nx = blocks(g.nx, hf), ny = blocks(g.ny, hf), nz = blocks(g.nz, vf);
  if (nx < 2 || ny < 2 || nz < 2)
    return makeError(what + ": coarsened by " + std::to_string(hf) + " x " + std::to_string(vf) + " it keeps " +
                     std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz) +
                     " points (2 x 2 x 2 needed)");
  GridVolume out;
  out.path = g.path;
  out.format = g.format;
  out.variable = g.variable;
  out.units = g.units;
  out.standardName = g.standardName;
  out.longName = g.longName;
  out.curvilinear = g.curvilinear;
  out.nx = nx;
  out.ny = ny;
  out.nz = nz;
  out.wrapsLongitude = g.wrapsLongitude && !g.curvilinear && g.nx % hf == 0;
  out.projection = g.projection;
  out.vectorsRelativeToGrid = g.vectorsRelativeToGrid;
  out.fileFirstColumn = g.fileFirstColumn;
  out.fileFirstRow = g.fileFirstRow;
  out.fileFirstLevel = g.fileFirstLevel;
  out.fileColumnStep = g.fileColumnStep * static_cast<int>(hf);
  out.fileRowStep = g.fileRowStep * static_cast<int>(hf);
  out.fileLevelStep = g.fileLevelStep * static_cast<int>(vf);
  out.verticalKind = g.verticalKind;
  out.heightSource = g.heightSource;
  out.verticalVariable = g.verticalVariable;
  out.heightNote = g.heightNote;
  out.approximateHeights = g.approximateHeights;
  out.levelUnits = g.levelUnits;
  out.times = g.times;
  out.timeIndex = g.timeIndex;
  out.validTime = g.validTime;
  out.member = g.member;
  out.ensembleStatistic = g.ensembleStatistic;
  out.ensembleMembers = g.ensembleMembers;
  out.extraDimensions = g.extraDimensions;
  out.bytesRead = g.bytesRead;

  // Positions: the block's mean latitude and longitude (longitudes are continuous across a grid).
  if (g.curvilinear) {
    out.lonDeg.assign(nx * ny, 0.0);
    out.latDeg.assign(nx * ny, 0.0);
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const auto [j0, j1] = block(j, hf, g.ny);
        const auto [i0, i1] = block(i, hf, g.nx);
        double lat = 0.0, lon = 0.0;
        for (std::size_t jj = j0; jj < j1; ++jj)
          for (std::size_t ii = i0; ii < i1; ++ii) {
            lat += g.latDeg[jj * g.nx + ii];
            lon += g.lonDeg[jj * g.nx + ii];
          }
        const double n = static_cast<double>((j1 - j0) * (i1 - i0));
        out.latDeg[j * nx + i] = lat / n;
        out.lonDeg[j * nx + i] = lon / n;
      }
  } else {
    auto meanOf = [](const std::vector<double>& axis, std::size_t a, std::size_t b) {
      double s = 0.0;
      for (std::size_t k = a; k < b; ++k) s += axis[k];
      return s / static_cast<double>(b - a);
    };
    for (std::size_t i = 0; i < nx; ++i) {
      const auto [i0, i1] = block(i, hf, g.nx);
      out.lonDeg.push_back(meanOf(g.lonDeg, i0, i1));
    }
    for (std::size_t j = 0; j < ny; ++j) {
      const auto [j0, j1] = block(j, hf, g.ny);
      out.latDeg.push_back(meanOf(g.latDeg, j0, j1));
    }
  }
  for (std::size_t k = 0; k < nz && !g.levelValues.empty(); ++k) {
    const auto [k0, k1] = block(k, vf, g.nz);
    double s = 0.0;
    for (std::size_t kk = k0; kk < k1; ++kk) s += g.levelValues[kk];
    out.levelValues.push_back(s / static_cast<double>(k1 - k0));
  }

  // Values and heights: block means (values: of the finite ones, where at least half are).
  out.values.assign(nx * ny * nz, std::numeric_limits<float>::quiet_NaN());
  out.heightAboveEllipsoidMeters.assign(out.values.size(), 0.0f);
  for (std::size_t k = 0; k < nz; ++k) {
    const auto [k0, k1] = block(k, vf, g.nz);
    for (std::size_t j = 0; j < ny; ++j) {
      const auto [j0, j1] = block(j, hf, g.ny);
      for (std::size_t i = 0; i < nx; ++i) {
        const auto [i0, i1] = block(i, hf, g.nx);
        double value = 0.0, height = 0.0;
        std::size_t finite = 0, all = 0;
        for (std::size_t kk = k0; kk < k1; ++kk)
          for (std::size_t jj = j0; jj < j1; ++jj)
            for (std::size_t ii = i0; ii < i1; ++ii) {
              const std::size_t n = g.index(kk, jj, ii);
              height += g.heightAboveEllipsoidMeters[n];
              ++all;
              if (std::isfinite(g.values[n])) {
                value += g.values[n];
                ++finite;
              }
            }
        const std::size_t n = out.index(k, j, i);
        out.heightAboveEllipsoidMeters[n] = static_cast<float>(height / static_cast<double>(all));
        if (finite > 0 && 2 * finite >= all) out.values[n] = static_cast<float>(value / static_cast<double>(finite));
      }
    }
  }
  setValueRange(out);
  return out;
}

std::size_t detailHorizontalFactor(int level) { return std::size_t{1} << std::max(0, level); }

std::size_t detailVerticalFactor(const GridVolume& grid, int level) {
  std::size_t f = 1;
  for (int l = 0; l < level && blocks(grid.nz, 2 * f) >= kMinDetailLevels; ++l) f *= 2;
  return f;
}

int maxDetailLevel(const GridVolume& grid) {
  if (grid.reduced()) return 0;
  int level = 0;
  for (;;) {
    const std::size_t f = detailHorizontalFactor(level + 1);
    if (blocks(grid.nx, f) < 8 || blocks(grid.ny, f) < 8) break;
    if (grid.wrapsLongitude && !grid.curvilinear && grid.nx % f != 0) break;
    ++level;
  }
  return level;
}

double pixelFootprintMeters(double distanceMeters, double fovYDeg, int heightPx, double imageScale) {
  const double pixelAngle = 2.0 * std::tan(0.5 * fovYDeg * 3.14159265358979323846 / 180.0) /
                            (std::max(1, heightPx) * std::clamp(imageScale, 1e-3, 1.0));
  return std::max(0.0, distanceMeters) * pixelAngle;
}

int gridDetailLevel(double columnSpacingMeters, double footprintMeters, int maxLevel) {
  if (!(columnSpacingMeters > 0.0) || !(footprintMeters > 0.0) || maxLevel <= 0) return 0;
  const double ratio = footprintMeters / columnSpacingMeters;
  if (!(ratio >= 2.0)) return 0;
  return std::min(maxLevel, static_cast<int>(std::floor(std::log2(ratio))));
}

}  // namespace atmoglobe::volume
