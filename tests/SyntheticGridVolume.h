#pragma once
// In-memory forecast grids for the sampler and renderer tests (no file, no ../shared).
#include <atmoglobe/volume/GridVolume.h>

#include <algorithm>
#include <functional>
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

}  // namespace atmoglobe::testutil
