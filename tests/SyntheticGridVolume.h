#pragma once
// In-memory forecast grids for the sampler and renderer tests (no file, no ../shared).
#include <atmoglobe/volume/GridVolume.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

namespace atmoglobe::testutil {

/// first, first + step, ... (n values).
inline std::vector<double> evenlySpaced(double first, double step, int n) {
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(first + step * k);
  return v;
}

/// A rectilinear grid on the given axes; level k of column (j, i) at height
/// surface(lat, lon) + levelHeights[k] above the ellipsoid; value field(lat, lon, height).
inline volume::GridVolume rectilinearGrid(std::vector<double> lonDeg, std::vector<double> latDeg,
                                          const std::vector<double>& levelHeights,
                                          const std::function<double(double, double)>& surface,
                                          const std::function<double(double, double, double)>& field) {
  volume::GridVolume g;
  g.nx = lonDeg.size();
  g.ny = latDeg.size();
  g.nz = levelHeights.size();
  g.lonDeg = std::move(lonDeg);
  g.latDeg = std::move(latDeg);
  g.values.resize(g.nx * g.ny * g.nz);
  g.heightAboveEllipsoidMeters.resize(g.values.size());
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i) {
        const double h = surface(g.latDeg[j], g.lonDeg[i]) + levelHeights[k];
        g.heightAboveEllipsoidMeters[g.index(k, j, i)] = static_cast<float>(h);
        g.values[g.index(k, j, i)] = static_cast<float>(field(g.latDeg[j], g.lonDeg[i], h));
      }
  g.valueMin = *std::min_element(g.values.begin(), g.values.end());
  g.valueMax = *std::max_element(g.values.begin(), g.values.end());
  return g;
}

/// A reduced grid (GridVolume.h): row j at latitude latDeg[j] (ascending) with rowLengths[j]
/// points from firstLonDeg[j]; `wraps`: every row round the circle (spacing 360 / n), else spaced
/// `spacingDeg[j]`. Heights and values as rectilinearGrid; padding NaN.
inline volume::GridVolume reducedGrid(const std::vector<std::size_t>& rowLengths, std::vector<double> latDeg,
                                      const std::vector<double>& firstLonDeg, bool wraps,
                                      const std::vector<double>& spacingDeg, const std::vector<double>& levelHeights,
                                      const std::function<double(double, double)>& surface,
                                      const std::function<double(double, double, double)>& field) {
  volume::GridVolume g;
  g.ny = latDeg.size();
  g.nz = levelHeights.size();
  g.nx = *std::max_element(rowLengths.begin(), rowLengths.end());
  g.latDeg = std::move(latDeg);
  g.wrapsLongitude = wraps;
  g.rowLengthPoints = rowLengths;
  g.rowFirstLonDeg = firstLonDeg;
  for (std::size_t j = 0; j < g.ny; ++j)
    g.rowSpacingDeg.push_back(wraps ? 360.0 / static_cast<double>(rowLengths[j]) : spacingDeg[j]);
  (void)volume::finishReducedGrid(g);
  g.values.assign(g.nx * g.ny * g.nz, std::numeric_limits<float>::quiet_NaN());
  g.heightAboveEllipsoidMeters.assign(g.values.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < rowLengths[j]; ++i) {
        const double lat = g.latDeg[j], lon = g.lonDegAt(j, i);
        const double h = surface(lat, lon) + levelHeights[k];
        g.heightAboveEllipsoidMeters[g.index(k, j, i)] = static_cast<float>(h);
        g.values[g.index(k, j, i)] = static_cast<float>(field(lat, lon, h));
      }
  for (float v : g.values) {
    if (!std::isfinite(v)) continue;
    if (!(v >= g.valueMin)) g.valueMin = v;
    if (!(v <= g.valueMax)) g.valueMax = v;
  }
  return g;
}

/// A global reduced grid like a reduced Gaussian one: `rows` latitudes evenly spaced (half a
/// spacing from the poles), row j with about 4 x rows x cos(latitude) points (at least 8, a
/// multiple of 4), every row starting at longitude `firstLonDeg`.
inline volume::GridVolume globalReducedGrid(int rows, double firstLonDeg, const std::vector<double>& levelHeights,
                                            const std::function<double(double, double)>& surface,
                                            const std::function<double(double, double, double)>& field) {
  std::vector<std::size_t> lengths;
  std::vector<double> lat, first;
  const double step = 180.0 / rows;
  for (int j = 0; j < rows; ++j) {
    lat.push_back(-90.0 + step * (j + 0.5));
    const double n = 4.0 * rows * std::cos(lat.back() * 3.14159265358979323846 / 180.0);
    lengths.push_back(std::max<std::size_t>(8, 4 * static_cast<std::size_t>(std::lround(n / 4.0))));
    first.push_back(firstLonDeg);
  }
  return reducedGrid(lengths, std::move(lat), first, true, {}, levelHeights, surface, field);
}

}  // namespace atmoglobe::testutil
