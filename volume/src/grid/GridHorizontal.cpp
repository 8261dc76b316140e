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

Result<ReducedHorizontal> reducedAxes(const std::vector<long>& pl, const std::vector<double>& lat,
                                      const std::vector<double>& lon, const GridCrop& crop, std::size_t sample,
                                      const CoordinateError& error) {
  if (auto st = checkCoordinates(error, lat, true); !st) return st.forwardError();
  if (auto st = checkCoordinates(error, lon, false); !st) return st.forwardError();
  std::size_t total = 0;
  std::size_t firstFull = pl.size(), lastFull = 0;
  for (std::size_t r = 0; r < pl.size(); ++r) {
    if (pl[r] < 0) return error("pl[" + std::to_string(r) + "] = " + std::to_string(pl[r]) + " is negative");
    total += static_cast<std::size_t>(pl[r]);
    if (pl[r] > 0) {
      firstFull = std::min(firstFull, r);
      lastFull = r;
    }
  }
  if (total != lat.size() || total != lon.size())
    return error("the reduced grid's pl (" + std::to_string(pl.size()) + " rows) counts " + std::to_string(total) +
                 " points, the message has " + std::to_string(lat.size()) +
                 " (a sub-area whose pl counts whole circles is not read yet)");
  if (firstFull == pl.size()) return error("every row of the reduced grid is empty (pl all 0)");
  for (std::size_t r = firstFull; r <= lastFull; ++r)
    if (pl[r] == 0)
      return error("row " + std::to_string(r) + " of the reduced grid has no points (pl 0) between rows that have");

  // The file's rows with points: their latitude and, eastward, their first longitude and spacing.
  struct Row {
    std::size_t fileRow = 0, start = 0, n = 0;
    double lat = 0, first = 0, step = 360.0;
    bool global = false, west = false;        // west: the file lists the row westward
    std::size_t nFile = 0;                    // the row's points in the file (n + 1 when its last repeats its first)
    std::size_t point(std::size_t a) const {  // eastward index -> message index
      return start + (west ? nFile - 1 - a : a);
    }
  };
  std::vector<Row> rows;
  std::size_t start = 0;
  for (std::size_t r = 0; r < pl.size(); start += static_cast<std::size_t>(pl[r]), ++r) {
    if (pl[r] == 0) continue;
    Row w;
    w.fileRow = r;
    w.start = start;
    w.n = w.nFile = static_cast<std::size_t>(pl[r]);
    w.lat = lat[start];
    const std::string name = "row " + std::to_string(r) + " (latitude " + num(w.lat) + ")";
    for (std::size_t m = 1; m < w.n; ++m)
      if (std::abs(lat[start + m] - w.lat) > 1e-6)
        return error(name + ": its points are at different latitudes (" + num(w.lat) + " and " + num(lat[start + m]) +
                     ")");
    // The direction from the longitudes themselves (ecCodes' reduced iterators differ in how they
    // honour iScansNegatively).
    w.west = w.n >= 2 && std::remainder(lon[start + 1] - lon[start], 360.0) < 0.0;
    auto east = [&](std::size_t a) { return lon[w.point(a)]; };
    w.first = east(0);
    if (w.n >= 2) {
      double span = 0;
      for (std::size_t a = 1; a < w.n; ++a) span += mod360(east(a) - east(a - 1));
      const double d = span / static_cast<double>(w.n - 1);
      const double tolerance = std::max(1e-6, 1e-4 * d);
      for (std::size_t a = 1; a < w.n; ++a)
        if (!(std::abs(mod360(east(a) - east(a - 1)) - d) <= tolerance))
          return error(name + ": its longitudes are not equally spaced (" + num(east(a - 1), 6) + ", " +
                       num(east(a), 6) + " after a mean step of " + num(d, 6) + ")");
      if (!(d > 0.0)) return error(name + ": its points are at one longitude");
      if (span >= 360.0 - 0.5 * d) {
        if (span > 360.0 + 0.5 * d) return error(name + ": its longitudes span more than 360 degrees");
        --w.n;  // the last point repeats the first (0 .. 360 inclusive)
        w.global = true;
      } else {
        w.global = span + d >= 360.0 - 0.5 * d;
      }
      w.step = w.global ? 360.0 / static_cast<double>(w.n) : d;
    }
    rows.push_back(w);
  }
  bool gridWraps = false, anyLong = false;
  for (const Row& w : rows)
    if (w.nFile >= 2) {
      gridWraps = anyLong ? gridWraps && w.global : w.global;
      anyLong = true;
    }
  for (Row& w : rows)
    if (w.nFile < 2) w.step = 360.0;  // a single point: any spacing names it
  // Latitudes: strictly monotonic; output rows ascend.
  const std::size_t ny = rows.size();
  const bool latDown = ny >= 2 && rows[1].lat < rows[0].lat;
  for (std::size_t a = 1; a < ny; ++a)
    if (!(latDown ? rows[a].lat < rows[a - 1].lat : rows[a].lat > rows[a - 1].lat))
      return error("the reduced grid's row latitudes are not strictly monotonic (row " +
                   std::to_string(rows[a - 1].fileRow) + ": " + num(rows[a - 1].lat) + ", row " +
                   std::to_string(rows[a].fileRow) + ": " + num(rows[a].lat) + ")");
  auto asc = [&](std::size_t a) -> const Row& { return rows[latDown ? ny - 1 - a : a]; };
  if (crop.southDeg > asc(ny - 1).lat || crop.northDeg < asc(0).lat)
    return error("the crop's latitudes " + num(crop.southDeg) + " .. " + num(crop.northDeg) +
                 " do not overlap the grid's " + num(asc(0).lat) + " .. " + num(asc(ny - 1).lat));
  std::size_t ra = 0, rb = ny - 1;  // as rectilinearAxes: one row beyond each edge, strictly outside
  for (std::size_t a = 0; a < ny; ++a)
    if (asc(a).lat < crop.southDeg) ra = a;
  for (std::size_t a = ny; a-- > 0;)
    if (asc(a).lat > crop.northDeg) rb = a;

  // Per kept row the logical (eastward) indices a .. b it keeps; past n - 1 or below 0 across the
  // seam of a wrapping row (the point of index mod n).
  const double span = cropSpanDeg(crop);
  struct Kept {
    const Row* row;
    long a, b;
  };
  std::vector<Kept> kept;
  bool allWhole = true;
  for (std::size_t a : strided(ra, rb, sample)) {
    const Row& w = asc(a);
    const long n = static_cast<long>(w.n);
    Kept k{&w, 0, n - 1};
    if (span < 360.0) {
      const double o = mod360(crop.westDeg - w.first);  // the box's west edge east of the row's first point
      if (gridWraps) {
        k.a = static_cast<long>(std::ceil(o / w.step - 1e-9)) - 1;  // the last point strictly west of the edge
        k.b = static_cast<long>(std::floor((o + span) / w.step + 1e-9)) + 1;  // the first strictly east of it
        allWhole = allWhole && k.b - k.a + 1 >= n;
      } else {
        const double end = w.first + static_cast<double>(n - 1) * w.step;
        long lo = n, hi = -1;
        for (double west : {w.first + o - 360.0, w.first + o}) {
          const double a0 = std::max(west, w.first), b0 = std::min(west + span, end);
          if (a0 > b0) continue;
          lo = std::min(lo, std::max(0L, static_cast<long>(std::ceil((a0 - w.first) / w.step - 1e-9)) - 1));
          hi = std::max(hi, std::min(n - 1, static_cast<long>(std::floor((b0 - w.first) / w.step + 1e-9)) + 1));
        }
        if (hi < 0)
          return error("the crop's longitudes " + num(crop.westDeg) + " .. " + num(crop.eastDeg) +
                       " do not overlap the row at latitude " + num(w.lat) + " (" + num(wrap180(w.first)) + " .. " +
                       num(wrap180(w.first) + end - w.first) + ")");
        k.a = lo;
        k.b = hi;
        allWhole = false;
      }
    }
    kept.push_back(k);
  }
  const bool wraps = gridWraps && sample == 1 && (span >= 360.0 || allWhole);
  ReducedHorizontal out;
  out.emptyRowsDropped = pl.size() - rows.size();
  Horizontal& h = out.hz;
  for (Kept& k : kept) {
    const Row& w = *k.row;
    const long n = static_cast<long>(w.n);
    if (wraps) {
      k.a = 0;
      k.b = n - 1;
    } else if (gridWraps) {
      k.b = std::min(k.b, k.a + n);  // at most the circle from point a, to a's copy one circle on
    }
    const std::size_t row = h.rows.size();
    h.rows.push_back(w.fileRow);
    h.latDeg.push_back(w.lat);
    std::size_t m = 0;
    for (long q = k.a; q <= k.b; q += static_cast<long>(sample), ++m) {
      const auto e = static_cast<std::size_t>(((q % n) + n) % n);
      out.points.push_back(w.point(e));
      out.pointRow.push_back(row);
    }
    out.rowLength.push_back(m);
    out.rowFirstLonDeg.push_back(w.first + static_cast<double>(k.a) * w.step);
    out.rowSpacingDeg.push_back(w.step * static_cast<double>(sample));
  }
  // First longitudes continuous with each other (a crop's rows all start just west of its west
  // edge), the westernmost in [-180, 180).
  const double ref = span < 360.0 ? crop.westDeg : wrap180(out.rowFirstLonDeg.front());
  for (double& x : out.rowFirstLonDeg) x = ref + wrap180(x - ref);
  const double west = *std::min_element(out.rowFirstLonDeg.begin(), out.rowFirstLonDeg.end());
  const double shift = 360.0 * std::floor((west + 180.0) / 360.0);
  for (double& x : out.rowFirstLonDeg) x -= shift;
  for (std::size_t p = 0, j = 0; j < out.rowLength.size(); ++j)
    for (std::size_t i = 0; i < out.rowLength[j]; ++i, ++p) {
      out.pointLatDeg.push_back(h.latDeg[j]);
      out.pointLonDeg.push_back(out.rowFirstLonDeg[j] + static_cast<double>(i) * out.rowSpacingDeg[j]);
    }
  out.nx = *std::max_element(out.rowLength.begin(), out.rowLength.end());
  h.wrapsLongitude = wraps;
  h.rowStep = latDown ? -1 : 1;
  h.southDeg = h.latDeg.front();
  h.northDeg = h.latDeg.back();
  // The reference axis (GridVolume::reducedWestDeg, reducedSpacingDeg).
  double finest = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < out.rowLength.size(); ++j)
    if (out.rowLength[j] >= 2) finest = std::min(finest, out.rowSpacingDeg[j]);
  if (!std::isfinite(finest)) finest = *std::min_element(out.rowSpacingDeg.begin(), out.rowSpacingDeg.end());
  const double step = wraps ? 360.0 / static_cast<double>(out.nx) : finest;
  h.westDeg = west - shift;
  h.eastDeg = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < out.rowLength.size(); ++j)
    h.eastDeg =
        std::max(h.eastDeg, out.rowFirstLonDeg[j] + static_cast<double>(out.rowLength[j] - 1) * out.rowSpacingDeg[j]);
  if (wraps) h.eastDeg = h.westDeg + 360.0 - step;
  for (std::size_t i = 0; i < out.nx; ++i) h.lonDeg.push_back(h.westDeg + static_cast<double>(i) * step);
  return out;
}

double ReducedHorizontal::meanSpacingKm() const {
  if (rowLength.empty()) return 0.0;
  const std::size_t j = rowLength.size() / 2, i = rowLength[j] / 2;
  const double la = hz.latDeg[j], lo = rowFirstLonDeg[j] + static_cast<double>(i) * rowSpacingDeg[j];
  double sum = 0;
  int n = 0;
  if (i + 1 < rowLength[j]) {
    sum += globe::geodesicInverse(la, lo, la, lo + rowSpacingDeg[j]).distanceMeters;
    ++n;
  }
  if (j + 1 < rowLength.size()) {
    sum += globe::geodesicInverse(la, lo, hz.latDeg[j + 1], lo).distanceMeters;
    ++n;
  }
  return n ? sum / n / 1000.0 : 0.0;
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
