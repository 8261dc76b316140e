// Lower-resolution copies of volumes (Decimate.h).
#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace atmoglobe::volume {
namespace {

// Indices 0, f, 2f, ... of n, with n - 1 added unless `periodic` (then n % f == 0 is required by
// the caller, so the kept samples stay evenly spaced across the seam).
std::vector<std::size_t> keptIndices(std::size_t n, std::size_t f, bool periodic) {
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; i += f) kept.push_back(i);
  if (!periodic && kept.back() != n - 1) kept.push_back(n - 1);
  return kept;
}

// The file's index of output index `i` of an axis whose output index 0 is file index `first` and
// runs with the file index in steps of `step` (negative: a north-to-south file's rows).
std::size_t fileIndexOf(std::size_t first, std::size_t i, int step) {
  const long long at = static_cast<long long>(first) + static_cast<long long>(i) * step;
  return at > 0 ? static_cast<std::size_t>(at) : 0;
}

// The points at columns `cols`, rows `rows` and levels `lev` of a grid that is not reduced, with
// their positions, heights and pressures; the value range recomputed.
GridVolume pickPoints(const GridVolume& g, const std::vector<std::size_t>& cols, const std::vector<std::size_t>& rows,
                      const std::vector<std::size_t>& lev) {
  GridVolume out = g;
  out.nx = cols.size();
  out.ny = rows.size();
  out.nz = lev.size();
  out.lonDeg.clear();
  out.latDeg.clear();
  if (g.curvilinear) {
    for (std::size_t j : rows)
      for (std::size_t i : cols) {
        out.lonDeg.push_back(g.lonDeg[j * g.nx + i]);
        out.latDeg.push_back(g.latDeg[j * g.nx + i]);
      }
  } else {
    for (std::size_t i : cols) out.lonDeg.push_back(g.lonDeg[i]);
    for (std::size_t j : rows) out.latDeg.push_back(g.latDeg[j]);
  }
  if (!g.levelValues.empty()) {
    out.levelValues.clear();
    for (std::size_t k : lev) out.levelValues.push_back(g.levelValues[k]);
  }
  const bool pressures = g.pressurePa.size() == g.values.size();
  out.values.assign(out.nx * out.ny * out.nz, 0.0f);
  out.heightAboveEllipsoidMeters.assign(out.values.size(), 0.0f);
  out.pressurePa.assign(pressures ? out.values.size() : 0, 0.0f);
  out.valueMin = out.valueMax = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t k = 0; k < lev.size(); ++k)
    for (std::size_t j = 0; j < rows.size(); ++j)
      for (std::size_t i = 0; i < cols.size(); ++i) {
        const float v = g.value(lev[k], rows[j], cols[i]);
        out.values[out.index(k, j, i)] = v;
        out.heightAboveEllipsoidMeters[out.index(k, j, i)] = g.heightMeters(lev[k], rows[j], cols[i]);
        if (pressures) out.pressurePa[out.index(k, j, i)] = g.pressurePa[g.index(lev[k], rows[j], cols[i])];
        if (std::isfinite(v)) {
          if (!(out.valueMin <= v)) out.valueMin = v;
          if (!(out.valueMax >= v)) out.valueMax = v;
        }
      }
  return out;
}

}  // namespace

namespace {

// A reduced grid (GridVolume.h): every `factor`-th row, and in each row every `factor`-th point
// (the row's spacing times factor). A wrapping row whose length is not a multiple of factor is
// resampled instead, linearly along the row to ceil(n / factor) points evenly round the circle,
// so that the grid keeps wrapping with even rows.
GridVolume decimateReduced(const GridVolume& g, std::size_t factor, const std::vector<std::size_t>& lev) {
  const std::vector<std::size_t> rows = keptIndices(g.ny, factor, false);
  GridVolume out = g;
  out.ny = rows.size();
  out.nz = lev.size();
  out.latDeg.clear();
  out.rowLengthPoints.clear();
  out.rowFirstLonDeg.clear();
  out.rowSpacingDeg.clear();
  for (std::size_t j : rows) {
    const std::size_t n = g.rowLengthPoints[j];
    const std::size_t m = g.wrapsLongitude ? (n + factor - 1) / factor : (n - 1) / factor + 1;
    out.latDeg.push_back(g.latDeg[j]);
    out.rowLengthPoints.push_back(m);
    out.rowFirstLonDeg.push_back(g.rowFirstLonDeg[j]);
    out.rowSpacingDeg.push_back(g.wrapsLongitude ? 360.0 / static_cast<double>(m)
                                                 : g.rowSpacingDeg[j] * static_cast<double>(factor));
  }
  out.nx = *std::max_element(out.rowLengthPoints.begin(), out.rowLengthPoints.end());
  out.fileRowStep = g.fileRowStep * static_cast<int>(factor);
  out.values.assign(out.nx * out.ny * out.nz, std::numeric_limits<float>::quiet_NaN());
  out.heightAboveEllipsoidMeters.assign(out.values.size(), std::numeric_limits<float>::quiet_NaN());
  out.valueMin = out.valueMax = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t k = 0; k < lev.size(); ++k)
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const std::size_t j = rows[r], n = g.rowLengthPoints[j], m = out.rowLengthPoints[r];
      for (std::size_t q = 0; q < m; ++q) {
        float v = 0.0f, h = 0.0f;
        if (!g.wrapsLongitude || n % factor == 0) {
          v = g.value(lev[k], j, q * factor);
          h = g.heightMeters(lev[k], j, q * factor);
        } else {
          // Point q at q / m of the circle: between points a and a + 1 (mod n) of the row.
          const double x = static_cast<double>(q) * static_cast<double>(n) / static_cast<double>(m);
          const std::size_t a = std::min(static_cast<std::size_t>(x), n - 1), b = (a + 1) % n;
          const double f = x - static_cast<double>(a);
          const float va = g.value(lev[k], j, a), vb = g.value(lev[k], j, b);
          v = f == 0.0 ? va : static_cast<float>((1.0 - f) * va + f * vb);  // NaN stays NaN
          h = static_cast<float>((1.0 - f) * g.heightMeters(lev[k], j, a) + f * g.heightMeters(lev[k], j, b));
        }
        out.values[out.index(k, r, q)] = v;
        out.heightAboveEllipsoidMeters[out.index(k, r, q)] = h;
        if (std::isfinite(v)) {
          if (!(out.valueMin <= v)) out.valueMin = v;
          if (!(out.valueMax >= v)) out.valueMax = v;
        }
      }
    }
  (void)finishReducedGrid(out);  // the reference axis (lonDeg); the rows are valid by construction
  return out;
}

// A window of a reduced grid (gridWindow): its columns are of the reference axis (lonDeg), the
// longitudes lonDeg[firstColumn] .. + (columnCount - 1) x reducedSpacingDeg() (across the seam of
// a wrapping grid). Each row of the window keeps its own points from the one at or west of the
// window's west edge to the one at or east of its east edge, so that between the edges every
// point has the same neighbours in the row as in the grid; a row of a regional grid keeps what it
// has there (its nearest point when it has nothing: a row holds at least one). The rows start
// where their first kept point is (continuous longitudes, not wrapped) and do not wrap, unless
// the window spans every column of a wrapping grid: then the rows are the grid's.
Result<GridVolume> reducedWindow(const GridVolume& g, const GridWindow& w, std::size_t pointStride) {
  const bool whole = g.wrapsLongitude && w.columnCount >= g.nx;
  const double west = g.lonDeg[w.firstColumn];
  const double east = west + static_cast<double>(w.columnCount - 1) * g.reducedSpacingDeg();
  GridVolume out = g;
  out.ny = w.rowCount;
  out.latDeg.assign(g.latDeg.begin() + static_cast<std::ptrdiff_t>(w.firstRow),
                    g.latDeg.begin() + static_cast<std::ptrdiff_t>(w.firstRow + w.rowCount));
  out.rowLengthPoints.clear();
  out.rowFirstLonDeg.clear();
  out.rowSpacingDeg.clear();
  std::vector<long long> firstPoint;  // per window row: the grid row's index of its first point
  for (std::size_t r = 0; r < w.rowCount; ++r) {
    const std::size_t j = w.firstRow + r, n = g.rowLengthPoints[j];
    const double first = g.rowFirstLonDeg[j], spacing = g.rowSpacingDeg[j];
    // 1e-9 of a spacing: a point on an edge (up to the rounding of the longitudes) is taken as on it.
    long long a = static_cast<long long>(std::floor((west - first) / spacing + 1e-9));
    long long b = static_cast<long long>(std::ceil((east - first) / spacing - 1e-9));
    // A multiple of the stride's spacings from the first point (decimateGrid keeps every
    // stride-th point of a row from its first).
    const long long stride = static_cast<long long>(std::max<std::size_t>(1, pointStride));
    b = a + (b - a + stride - 1) / stride * stride;
    if (whole) {
      a = 0, b = static_cast<long long>(n) - 1;
    } else if (!g.wrapsLongitude) {
      const long long last = static_cast<long long>(n) - 1;
      a = std::clamp(a, 0LL, last), b = std::clamp(b, 0LL, last);
      if (b < a) b = a;
    }
    firstPoint.push_back(a);
    out.rowLengthPoints.push_back(static_cast<std::size_t>(b - a + 1));
    out.rowFirstLonDeg.push_back(first + static_cast<double>(a) * spacing);
    out.rowSpacingDeg.push_back(spacing);
  }
  out.nx = *std::max_element(out.rowLengthPoints.begin(), out.rowLengthPoints.end());
  out.wrapsLongitude = whole;
  out.fileFirstRow = fileIndexOf(g.fileFirstRow, w.firstRow, g.fileRowStep);
  const bool pressures = g.pressurePa.size() == g.values.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  out.values.assign(out.nx * out.ny * out.nz, nan);
  out.heightAboveEllipsoidMeters.assign(out.values.size(), nan);
  out.pressurePa.assign(pressures ? out.values.size() : 0, nan);
  out.valueMin = out.valueMax = nan;
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t r = 0; r < out.ny; ++r) {
      const std::size_t j = w.firstRow + r;
      const long long n = static_cast<long long>(g.rowLengthPoints[j]);
      for (std::size_t q = 0; q < out.rowLengthPoints[r]; ++q) {
        const long long p = firstPoint[r] + static_cast<long long>(q);
        const std::size_t i = static_cast<std::size_t>(((p % n) + n) % n);  // a wrapping row's points modulo n
        const float v = g.value(k, j, i);
        out.values[out.index(k, r, q)] = v;
        out.heightAboveEllipsoidMeters[out.index(k, r, q)] = g.heightMeters(k, j, i);
        if (pressures) out.pressurePa[out.index(k, r, q)] = g.pressurePa[g.index(k, j, i)];
        if (std::isfinite(v)) {
          if (!(out.valueMin <= v)) out.valueMin = v;
          if (!(out.valueMax >= v)) out.valueMax = v;
        }
      }
    }
  if (auto st = finishReducedGrid(out); !st)
    return makeError(g.variable + ": window of the reduced grid: " + st.error());
  return out;
}

}  // namespace

GridVolume decimateGrid(const GridVolume& g, std::size_t factor, bool levels) {
  factor = std::max<std::size_t>(factor, 2);
  if (g.reduced()) {
    std::vector<std::size_t> lev;
    if (levels) {
      lev = keptIndices(g.nz, factor, false);
    } else {
      for (std::size_t k = 0; k < g.nz; ++k) lev.push_back(k);
    }
    GridVolume out = decimateReduced(g, factor, lev);
    if (levels) out.fileLevelStep = g.fileLevelStep * static_cast<int>(factor);
    if (!g.levelValues.empty() && levels) {
      out.levelValues.clear();
      for (std::size_t k : lev) out.levelValues.push_back(g.levelValues[k]);
    }
    return out;
  }
  const bool periodic = g.wrapsLongitude && !g.curvilinear && g.nx % factor == 0;
  const std::vector<std::size_t> cols = keptIndices(g.nx, factor, periodic);
  const std::vector<std::size_t> rows = keptIndices(g.ny, factor, false);
  std::vector<std::size_t> lev;
  if (levels) {
    lev = keptIndices(g.nz, factor, false);
  } else {
    for (std::size_t k = 0; k < g.nz; ++k) lev.push_back(k);
  }
  GridVolume out = pickPoints(g, cols, rows, lev);
  out.wrapsLongitude = periodic;
  out.fileColumnStep = g.fileColumnStep * static_cast<int>(factor);
  out.fileRowStep = g.fileRowStep * static_cast<int>(factor);
  if (levels) out.fileLevelStep = g.fileLevelStep * static_cast<int>(factor);
  return out;
}

Result<GridVolume> gridWindow(const GridVolume& g, const GridWindow& w, std::size_t pointStride) {
  if (w.columnCount < 2 || w.rowCount < 2 || w.firstRow + w.rowCount > g.ny || w.columnCount > g.nx ||
      w.firstColumn >= g.nx || (!g.wrapsLongitude && w.firstColumn + w.columnCount > g.nx))
    return makeError(g.variable + ": window of " + std::to_string(w.columnCount) + " x " + std::to_string(w.rowCount) +
                     " points at column " + std::to_string(w.firstColumn) + ", row " + std::to_string(w.firstRow) +
                     " is not inside the " + std::to_string(g.nx) + " x " + std::to_string(g.ny) + " grid");
  if (g.reduced()) return reducedWindow(g, w, pointStride);
  std::vector<std::size_t> cols, rows, lev;
  for (std::size_t i = 0; i < w.columnCount; ++i) cols.push_back((w.firstColumn + i) % g.nx);
  for (std::size_t j = 0; j < w.rowCount; ++j) rows.push_back(w.firstRow + j);
  for (std::size_t k = 0; k < g.nz; ++k) lev.push_back(k);
  GridVolume out = pickPoints(g, cols, rows, lev);
  out.wrapsLongitude = g.wrapsLongitude && w.columnCount == g.nx && w.firstColumn == 0;
  // The file's indices of the first point; a window across the seam keeps its first column's.
  out.fileFirstColumn = g.fileFirstColumn + w.firstColumn * static_cast<std::size_t>(std::max(1, g.fileColumnStep));
  out.fileFirstRow = fileIndexOf(g.fileFirstRow, w.firstRow, g.fileRowStep);
  if (!g.curvilinear) {  // longitudes increase along the window, across the seam too
    for (std::size_t i = 1; i < out.lonDeg.size(); ++i)
      while (out.lonDeg[i] < out.lonDeg[i - 1]) out.lonDeg[i] += 360.0;
  }
  return out;
}

PolarVolume decimatePolar(const PolarVolume& v, int factor, bool rays) {
  factor = std::max(factor, 2);
  PolarVolume out = v;
  const int rayStep = rays ? factor : 1;
  out.maxGates = (v.maxGates + factor - 1) / factor;
  out.maxRays = (v.maxRays + rayStep - 1) / rayStep;
  out.values.assign(v.sweeps.size() * static_cast<std::size_t>(out.maxRays) * static_cast<std::size_t>(out.maxGates),
                    std::numeric_limits<float>::quiet_NaN());
  out.minValue = std::numeric_limits<float>::max();
  out.maxValue = std::numeric_limits<float>::lowest();
  double maxRange = 0.0;
  for (std::size_t k = 0; k < v.sweeps.size(); ++k) {
    const PolarSweepLayout& s = v.sweeps[k];
    PolarSweepLayout& o = out.sweeps[k];
    o.gateCount = (s.gateCount + factor - 1) / factor;
    o.gateSpacingMeters = s.gateSpacingMeters * factor;
    o.rayCount = (s.rayCount + rayStep - 1) / rayStep;
    o.azimuthDeg.clear();
    for (int r = 0; r < s.rayCount; r += rayStep) o.azimuthDeg.push_back(s.azimuthDeg[static_cast<std::size_t>(r)]);
    maxRange = std::max(maxRange, o.firstGateRangeMeters + (o.gateCount - 0.5) * o.gateSpacingMeters);
    for (int r = 0; r < o.rayCount; ++r)
      for (int gate = 0; gate < o.gateCount; ++gate) {
        const float value = v.value(static_cast<int>(k), r * rayStep, gate * factor);
        out.values[(k * static_cast<std::size_t>(out.maxRays) + static_cast<std::size_t>(r)) * out.maxGates +
                   static_cast<std::size_t>(gate)] = value;
        if (isMeasuredValue(value)) {
          out.minValue = std::min(out.minValue, value);
          out.maxValue = std::max(out.maxValue, value);
        }
      }
  }
  // The clipping sphere grows with the range where the kept gates' half-widths reach further.
  if (maxRange > v.maxRangeMeters && v.maxRangeMeters > 0.0) out.clipRadiusMeters *= maxRange / v.maxRangeMeters;
  out.maxRangeMeters = std::max(maxRange, v.maxRangeMeters);
  if (out.minValue > out.maxValue) out.minValue = out.maxValue = 0.0f;
  return out;
}

}  // namespace atmoglobe::volume
