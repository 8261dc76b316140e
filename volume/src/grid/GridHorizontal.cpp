// The forecast-grid reader's horizontal side: the crop checked, and the columns and rows a crop
// keeps with their latitudes and longitudes, for rectilinear grids (1-D coordinates normalised:
// latitudes ascending, longitudes continuous, global grids across the seam) and curvilinear ones
// (2-D coordinates, WRF's mass points).
#include "GridInternal.h"

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume::grid {

namespace {

double mod360(double x) {
  double r = std::fmod(x, 360.0);
  if (r < 0) r += 360.0;
  return r;
}

double wrap180(double x) {  // [-180, 180)
  return mod360(x + 180.0) - 180.0;
}

/// Span (degrees, (0, 360]) of the crop's longitudes going east; >= 360: every longitude.
double cropSpanDeg(const GridCrop& c) {
  if (c.eastDeg - c.westDeg >= 360.0) return 360.0;
  const double s = c.eastDeg >= c.westDeg ? c.eastDeg - c.westDeg : c.eastDeg + 360.0 - c.westDeg;
  return std::min(s, 360.0);
}

/// Every `stride`-th element of [a, b] plus b.
std::vector<std::size_t> strided(std::size_t a, std::size_t b, std::size_t stride) {
  std::vector<std::size_t> v;
  for (std::size_t i = a; i <= b; i += stride) v.push_back(i);
  if (v.back() != b) v.push_back(b);
  return v;
}

Status checkCoordinates(const CoordinateError& error, const std::vector<double>& values, bool latitude) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      return error(std::string(latitude ? "latitude" : "longitude") + " at index " + std::to_string(i) +
                   " is not a finite number (missing or NaN coordinates)");
    if (latitude && std::fabs(values[i]) > 90.0)
      return error("latitude " + num(values[i]) + " at index " + std::to_string(i) + " is beyond +-90 degrees");
  }
  return Ok{};
}

}  // namespace

Status checkCrop(const std::string& label, const GridCrop& c) {
  for (double v : {c.southDeg, c.northDeg, c.westDeg, c.eastDeg})
    if (!std::isfinite(v)) return makeError(label + ": crop: bounds must be finite numbers");
  if (c.southDeg < -90 || c.northDeg > 90 || c.southDeg > c.northDeg)
    return makeError(label + ": crop: latitudes " + num(c.southDeg) + " .. " + num(c.northDeg) +
                     " must satisfy -90 <= south <= north <= 90");
  if (c.levelCount == 0) return makeError(label + ": crop: a level count of 0 keeps nothing");
  return Ok{};
}

Status checkCrop(const io::NetcdfFile& f, const GridCrop& c) { return checkCrop(f.path(), c); }

Result<Horizontal> rectilinear(const io::NetcdfFile& f, const GridLayout& l, const GridCrop& crop, std::size_t sample) {
  auto latR = readPicked<double>(f, l.lat, {iota(0, l.ny)});
  if (!latR) return latR.forwardError();
  auto lonR = readPicked<double>(f, l.lon, {iota(0, l.nx)});
  if (!lonR) return lonR.forwardError();
  return rectilinearAxes(
      *latR, *lonR, crop, sample, [&](const std::string& what) { return varError(f, l.lat, what); },
      [&](const std::string& what) { return varError(f, l.lon, what); });
}

Result<Horizontal> rectilinearAxes(const std::vector<double>& lat, const std::vector<double>& lon, const GridCrop& crop,
                                   std::size_t sample, const CoordinateError& latError,
                                   const CoordinateError& lonError) {
  if (lat.empty() || lon.empty()) return latError("no latitudes or no longitudes");
  if (auto st = checkCoordinates(latError, lat, true); !st) return st.forwardError();
  if (auto st = checkCoordinates(lonError, lon, false); !st) return st.forwardError();
  Horizontal h;
  // Latitudes: strictly monotonic; rows in output order ascend.
  const std::size_t ny = lat.size(), nx = lon.size();
  const bool latDown = ny >= 2 && lat[1] < lat[0];
  for (std::size_t i = 1; i < ny; ++i)
    if (!(latDown ? lat[i] < lat[i - 1] : lat[i] > lat[i - 1]))
      return latError("latitudes are not strictly monotonic (index " + std::to_string(i - 1) + ": " + num(lat[i - 1]) +
                      ", index " + std::to_string(i) + ": " + num(lat[i]) + ")");
  std::vector<double> latAsc(ny);
  for (std::size_t a = 0; a < ny; ++a) latAsc[a] = lat[latDown ? ny - 1 - a : a];
  // Longitudes: steps of one sign once wrapped to (-180, 180]; unwrapped to ascend.
  bool lonDown = false;
  std::vector<double> u(nx);  // ascending, continuous, u[0] in [-180, 180)
  if (nx >= 2) lonDown = wrap180(lon[1] - lon[0]) < 0;
  for (std::size_t a = 0; a < nx; ++a) {
    const double x = lon[lonDown ? nx - 1 - a : a];
    if (a == 0) {
      u[0] = wrap180(x);
      continue;
    }
    const double step = mod360(x - lon[lonDown ? nx - a : a - 1]);
    if (!(step > 0.0 && step < 180.0))
      return lonError("longitudes are not strictly monotonic (near index " + std::to_string(lonDown ? nx - 1 - a : a) +
                      ")");
    u[a] = u[a - 1] + step;
  }
  std::size_t n = nx;
  if (nx >= 2) {
    const double step = (u[nx - 1] - u[0]) / static_cast<double>(nx - 1);
    if (u[nx - 1] - u[0] >= 360.0 - 0.5 * step) {
      if (u[nx - 1] - u[0] > 360.0 + 0.5 * step) return lonError("longitudes span more than 360 degrees");
      n = nx - 1;  // the last column repeats the first (0 .. 360 inclusive)
      h.wrapsLongitude = true;
    } else if (u[nx - 1] - u[0] + step >= 360.0 - 0.5 * step) {
      h.wrapsLongitude = true;
    }
  }
  auto lonFile = [&](std::size_t a) { return lonDown ? nx - 1 - a : a; };  // logical -> file column
  auto U = [&](std::size_t m) { return u[m % n] + 360.0 * static_cast<double>(m / n); };

  // Rows.
  if (crop.southDeg > latAsc[ny - 1] || crop.northDeg < latAsc[0])
    return latError("the crop's latitudes " + num(crop.southDeg) + " .. " + num(crop.northDeg) +
                    " do not overlap the grid's " + num(latAsc[0]) + " .. " + num(latAsc[ny - 1]));
  // The rows inside the box and one more on each side, strictly outside it: a box edge on a grid
  // line keeps the line beyond, so that a point on the edge (after the round trip through ECEF
  // a sampler makes, a hair outside it) still lies between kept rows.
  std::size_t ra = 0, rb = ny - 1;
  for (std::size_t a = 0; a < ny; ++a)
    if (latAsc[a] < crop.southDeg) ra = a;
  for (std::size_t a = ny; a-- > 0;)
    if (latAsc[a] > crop.northDeg) rb = a;
  // Columns (logical indices m, possibly past n for a crop across the seam of a global grid).
  std::size_t ca = 0, cb = n - 1;
  const double span = cropSpanDeg(crop);
  if (span < 360.0) {
    // Columns as rows: one more on each side, strictly outside the box.
    double w1 = u[0] + mod360(crop.westDeg - u[0]);
    if (h.wrapsLongitude) {
      if (w1 == u[0]) w1 += 360.0;  // the west edge on column 0: keep the column west of it, across the seam
      ca = 0;
      for (std::size_t a = 0; a < n; ++a)
        if (u[a] < w1) ca = a;
      const double e = w1 + span;
      cb = ca;
      while (U(cb) <= e && cb < ca + n) ++cb;
      if (cb - ca + 1 >= n) {
        ca = 0;
        cb = n - 1;
      } else {
        h.wrapsLongitude = false;
      }
    } else {
      bool any = false;
      std::size_t lo = n, hi = 0;
      for (double w : {w1 - 360.0, w1}) {
        const double a0 = std::max(w, u[0]), b0 = std::min(w + span, u[n - 1]);
        if (a0 > b0) continue;
        std::size_t a = 0, b = n - 1;
        for (std::size_t i = 0; i < n; ++i)
          if (u[i] < a0) a = i;
        for (std::size_t i = n; i-- > 0;)
          if (u[i] > b0) b = i;
        lo = std::min(lo, a);
        hi = std::max(hi, b);
        any = true;
      }
      if (!any)
        return lonError("the crop's longitudes " + num(crop.westDeg) + " .. " + num(crop.eastDeg) +
                        " do not overlap the grid's " + num(u[0]) + " .. " + num(u[n - 1]));
      ca = lo;
      cb = hi;
    }
  }
  if (sample > 1) h.wrapsLongitude = false;
  for (std::size_t a : strided(ra, rb, sample)) {
    h.rows.push_back(latDown ? ny - 1 - a : a);
    h.latDeg.push_back(latAsc[a]);
  }
  for (std::size_t m : strided(ca, cb, sample)) {
    h.cols.push_back(lonFile(m % n));
    h.lonDeg.push_back(U(m));
  }
  const double shift = 360.0 * std::floor((h.lonDeg.front() + 180.0) / 360.0);
  for (double& x : h.lonDeg) x -= shift;
  h.rowStep = latDown ? -1 : 1;
  h.colStep = lonDown ? -1 : 1;
  h.southDeg = h.latDeg.front();
  h.northDeg = h.latDeg.back();
  h.westDeg = h.lonDeg.front();
  h.eastDeg = h.lonDeg.back();
  return h;
}

Result<Horizontal> curvilinear(const io::NetcdfFile& f, const GridLayout& l, std::size_t timeIndex,
                               const GridCrop& crop, std::size_t sample) {
  // 2-D (or time, y, x) latitude and longitude: the whole plane at the time step read.
  auto picks = [&](const io::NcVar& c) {
    Picks p;
    for (std::size_t d = 0; d < c.dimIds.size(); ++d) {
      if (c.dimIds[d] == l.yDim) p.push_back(iota(0, l.ny));
      else if (c.dimIds[d] == l.xDim) p.push_back(iota(0, l.nx));
      else if (c.dimIds[d] == l.time.dimId) p.push_back({std::min(timeIndex, c.shape[d] - 1)});
      else p.push_back({0});
    }
    return p;
  };
  auto latR = readPicked<double>(f, l.lat, picks(l.lat));
  if (!latR) return latR.forwardError();
  auto lonR = readPicked<double>(f, l.lon, picks(l.lon));
  if (!lonR) return lonR.forwardError();
  return curvilinearAxes(
      std::move(*latR), std::move(*lonR), l.ny, l.nx, crop, sample,
      [&](const std::string& what) { return varError(f, l.lat, what); },
      [&](const std::string& what) { return varError(f, l.lon, what); });
}

Result<Horizontal> curvilinearAxes(std::vector<double> lat, std::vector<double> lon, std::size_t ny, std::size_t nx,
                                   const GridCrop& crop, std::size_t sample, const CoordinateError& latError,
                                   const CoordinateError& lonError) {
  if (ny == 0 || nx == 0 || lat.size() != ny * nx || lon.size() != ny * nx)
    return latError("a curvilinear grid needs a latitude and a longitude per point (" + std::to_string(lat.size()) +
                    " and " + std::to_string(lon.size()) + " for " + std::to_string(ny) + " x " + std::to_string(nx) +
                    ")");
  if (auto st = checkCoordinates(latError, lat, true); !st) return st.forwardError();
  if (auto st = checkCoordinates(lonError, lon, false); !st) return st.forwardError();
  // Continuous longitudes: each within 180 degrees of the centre column's.
  const double ref = wrap180(lon[(ny / 2) * nx + nx / 2]);
  for (double& x : lon) x = ref + wrap180(x - ref);
  std::size_t ra = 0, rb = ny - 1, ca = 0, cb = nx - 1;
  const double span = cropSpanDeg(crop);
  const bool full = span >= 360.0 && crop.southDeg <= -90.0 && crop.northDeg >= 90.0;
  if (!full) {
    bool any = false;
    std::size_t r0 = ny, r1 = 0, c0 = nx, c1 = 0;
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const double la = lat[j * nx + i], lo = lon[j * nx + i];
        if (la < crop.southDeg || la > crop.northDeg) continue;
        if (span < 360.0 && mod360(lo - crop.westDeg) > span) continue;
        any = true;
        r0 = std::min(r0, j);
        r1 = std::max(r1, j);
        c0 = std::min(c0, i);
        c1 = std::max(c1, i);
      }
    if (!any)
      return latError("no grid point lies in the crop (latitudes " + num(crop.southDeg) + " .. " + num(crop.northDeg) +
                      ", longitudes " + num(crop.westDeg) + " .. " + num(crop.eastDeg) + ")");
    ra = r0 > 0 ? r0 - 1 : 0;
    rb = std::min(r1 + 1, ny - 1);
    ca = c0 > 0 ? c0 - 1 : 0;
    cb = std::min(c1 + 1, nx - 1);
  }
  Horizontal h;
  h.rows = strided(ra, rb, sample);
  h.cols = strided(ca, cb, sample);
  h.latDeg.reserve(h.rows.size() * h.cols.size());
  h.lonDeg.reserve(h.rows.size() * h.cols.size());
  double west = std::numeric_limits<double>::infinity(), east = -west;
  for (std::size_t j : h.rows)
    for (std::size_t i : h.cols) {
      const double la = lat[j * nx + i], lo = lon[j * nx + i];
      h.latDeg.push_back(la);
      h.lonDeg.push_back(lo);
      h.southDeg = std::min(h.southDeg, la);
      h.northDeg = std::max(h.northDeg, la);
      west = std::min(west, lo);
      east = std::max(east, lo);
    }
  const double shift = 360.0 * std::floor((west + 180.0) / 360.0);
  for (double& x : h.lonDeg) x -= shift;
  h.westDeg = west - shift;
  h.eastDeg = east - shift;
  return h;
}

double Horizontal::meanSpacingKm(bool curvilinear) const {
  if (rows.empty() || cols.empty()) return 0.0;
  const std::size_t j = rows.size() / 2, i = cols.size() / 2;
  const double la = latAt(j, i, curvilinear), lo = lonAt(j, i, curvilinear);
  double sum = 0;
  int n = 0;
  if (i + 1 < cols.size()) {
    sum += globe::geodesicInverse(la, lo, latAt(j, i + 1, curvilinear), lonAt(j, i + 1, curvilinear)).distanceMeters;
    ++n;
  }
  if (j + 1 < rows.size()) {
    sum += globe::geodesicInverse(la, lo, latAt(j + 1, i, curvilinear), lonAt(j + 1, i, curvilinear)).distanceMeters;
    ++n;
  }
  return n ? sum / n / 1000.0 : 0.0;
}

void describeExtent(const Horizontal& full, bool curvilinear, GridFileInfo& info) {
  info.southDeg = full.southDeg;
  info.northDeg = full.northDeg;
  info.westDeg = full.westDeg;
  info.eastDeg = full.eastDeg;
  info.wrapsLongitude = full.wrapsLongitude;
  info.meanSpacingKm = full.meanSpacingKm(curvilinear);
}

}  // namespace atmoglobe::volume::grid
