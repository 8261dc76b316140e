// The forecast-grid reader: region, levels and time step to hyperslab picks; values; heights
// above the WGS84 ellipsoid for every column and level. Layout detection is in GridLayout.cpp,
// the netCDF layer in GridNetcdf.cpp, the descriptions in GridDescribe.cpp.
#include "GridInternal.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace atmoglobe::volume {

const char* toString(VerticalKind k) {
  switch (k) {
    case VerticalKind::HeightAboveEllipsoid: return "height above ellipsoid";
    case VerticalKind::HeightAboveSeaLevel: return "height above sea level";
    case VerticalKind::HeightAboveGround: return "height above ground";
    case VerticalKind::GeopotentialHeight: return "geopotential height";
    case VerticalKind::Pressure: return "pressure";
    case VerticalKind::HybridSigmaPressure: return "hybrid sigma-pressure";
    case VerticalKind::Sigma: return "sigma";
    case VerticalKind::HybridHeight: return "hybrid height";
    case VerticalKind::WrfEta: return "WRF eta";
  }
  return "?";
}

const char* toString(HeightSource s) {
  switch (s) {
    case HeightSource::Coordinate: return "coordinate";
    case HeightSource::GeopotentialField: return "geopotential field";
    case HeightSource::WrfGeopotential: return "WRF geopotential (PH+PHB)";
    case HeightSource::StandardAtmosphere: return "standard atmosphere";
  }
  return "?";
}

namespace grid {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string num(double v, int decimals = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

double mod360(double x) {
  double r = std::fmod(x, 360.0);
  if (r < 0) r += 360.0;
  return r;
}

double wrap180(double x) {  // [-180, 180)
  return mod360(x + 180.0) - 180.0;
}

Error varError(const io::NetcdfFile& f, const io::NcVar& v, const std::string& what) {
  return makeError(f.message("variable '" + v.name + "': " + what));
}

// ------------------------------------------------------------------------------- horizontal

/// The columns to read and their coordinates, in output order.
struct Horizontal {
  std::vector<std::size_t> rows, cols;  ///< file indices (mass points for WRF)
  std::vector<double> latDeg, lonDeg;   ///< 1-D (rectilinear) or rows x cols (curvilinear)
  bool wrapsLongitude = false;
  int rowStep = 1, colStep = 1;
  double southDeg = 90, northDeg = -90, westDeg = 0, eastDeg = 0;  ///< extent of what is kept
  double latAt(std::size_t j, std::size_t i, bool curvilinear) const {
    return curvilinear ? latDeg[j * cols.size() + i] : latDeg[j];
  }
  double lonAt(std::size_t j, std::size_t i, bool curvilinear) const {
    return curvilinear ? lonDeg[j * cols.size() + i] : lonDeg[i];
  }
};

Status checkCrop(const io::NetcdfFile& f, const GridCrop& c) {
  for (double v : {c.southDeg, c.northDeg, c.westDeg, c.eastDeg})
    if (!std::isfinite(v)) return makeError(f.message("crop: bounds must be finite numbers"));
  if (c.southDeg < -90 || c.northDeg > 90 || c.southDeg > c.northDeg)
    return makeError(f.message("crop: latitudes " + num(c.southDeg) + " .. " + num(c.northDeg) +
                               " must satisfy -90 <= south <= north <= 90"));
  if (c.levelCount == 0) return makeError(f.message("crop: a level count of 0 keeps nothing"));
  return Ok{};
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

Status checkCoordinates(const io::NetcdfFile& f, const io::NcVar& v, const std::vector<double>& values, bool latitude) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      return varError(f, v,
                      std::string(latitude ? "latitude" : "longitude") + " at index " + std::to_string(i) +
                          " is not a finite number (missing or NaN coordinates)");
    if (latitude && std::fabs(values[i]) > 90.0)
      return varError(f, v,
                      "latitude " + num(values[i]) + " at index " + std::to_string(i) + " is beyond +-90 degrees");
  }
  return Ok{};
}

Result<Horizontal> rectilinear(const io::NetcdfFile& f, const grid::GridLayout& l, const GridCrop& crop,
                               std::size_t sample) {
  auto latR = readPicked<double>(f, l.lat, {iota(0, l.ny)});
  if (!latR) return latR.forwardError();
  auto lonR = readPicked<double>(f, l.lon, {iota(0, l.nx)});
  if (!lonR) return lonR.forwardError();
  const std::vector<double>& lat = *latR;
  const std::vector<double>& lon = *lonR;
  if (auto st = checkCoordinates(f, l.lat, lat, true); !st) return st.forwardError();
  if (auto st = checkCoordinates(f, l.lon, lon, false); !st) return st.forwardError();
  Horizontal h;
  // Latitudes: strictly monotonic; rows in output order ascend.
  const std::size_t ny = lat.size(), nx = lon.size();
  const bool latDown = ny >= 2 && lat[1] < lat[0];
  for (std::size_t i = 1; i < ny; ++i)
    if (!(latDown ? lat[i] < lat[i - 1] : lat[i] > lat[i - 1]))
      return varError(f, l.lat,
                      "latitudes are not strictly monotonic (index " + std::to_string(i - 1) + ": " + num(lat[i - 1]) +
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
      return varError(
          f, l.lon,
          "longitudes are not strictly monotonic (near index " + std::to_string(lonDown ? nx - 1 - a : a) + ")");
    u[a] = u[a - 1] + step;
  }
  std::size_t n = nx;
  if (nx >= 2) {
    const double step = (u[nx - 1] - u[0]) / static_cast<double>(nx - 1);
    if (u[nx - 1] - u[0] >= 360.0 - 0.5 * step) {
      if (u[nx - 1] - u[0] > 360.0 + 0.5 * step) return varError(f, l.lon, "longitudes span more than 360 degrees");
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
    return varError(f, l.lat,
                    "the crop's latitudes " + num(crop.southDeg) + " .. " + num(crop.northDeg) +
                        " do not overlap the grid's " + num(latAsc[0]) + " .. " + num(latAsc[ny - 1]));
  std::size_t ra = 0, rb = ny - 1;
  for (std::size_t a = 0; a < ny; ++a)
    if (latAsc[a] <= crop.southDeg) ra = a;
  for (std::size_t a = ny; a-- > 0;)
    if (latAsc[a] >= crop.northDeg) rb = a;
  // Columns (logical indices m, possibly past n for a crop across the seam of a global grid).
  std::size_t ca = 0, cb = n - 1;
  const double span = cropSpanDeg(crop);
  if (span < 360.0) {
    const double w1 = u[0] + mod360(crop.westDeg - u[0]);
    if (h.wrapsLongitude) {
      ca = 0;
      for (std::size_t a = 0; a < n; ++a)
        if (u[a] <= w1) ca = a;
      const double e = w1 + span;
      cb = ca;
      while (U(cb) < e && cb < ca + n) ++cb;
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
          if (u[i] <= a0) a = i;
        for (std::size_t i = n; i-- > 0;)
          if (u[i] >= b0) b = i;
        lo = std::min(lo, a);
        hi = std::max(hi, b);
        any = true;
      }
      if (!any)
        return varError(f, l.lon,
                        "the crop's longitudes " + num(crop.westDeg) + " .. " + num(crop.eastDeg) +
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

Result<Horizontal> curvilinear(const io::NetcdfFile& f, const grid::GridLayout& l, std::size_t timeIndex,
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
  std::vector<double>& lat = *latR;
  std::vector<double>& lon = *lonR;
  if (auto st = checkCoordinates(f, l.lat, lat, true); !st) return st.forwardError();
  if (auto st = checkCoordinates(f, l.lon, lon, false); !st) return st.forwardError();
  const std::size_t ny = l.ny, nx = l.nx;
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
      return varError(f, l.lat,
                      "no grid point lies in the crop (latitudes " + num(crop.southDeg) + " .. " + num(crop.northDeg) +
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

// ------------------------------------------------------------------------------- vertical

/// Level direction and the coordinate's own values (SI units), file order.
struct Levels {
  std::vector<double> valuesSi;  ///< per file level (empty when the file gives none)
  std::string units;             ///< of valuesSi
  bool upward = true;
};

Result<std::vector<double>> readTerm(const io::NetcdfFile& f, const grid::VerticalSpec& vs, const std::string& term) {
  const io::NcVar& v = vs.terms.at(term);
  Picks p;
  for (std::size_t d = 0; d < v.shape.size(); ++d) p.push_back(iota(0, v.shape[d]));
  auto r = readPicked<double>(f, v, p);
  if (!r) return r.forwardError();
  const double k = vs.termToSi.count(term) ? vs.termToSi.at(term) : 1.0;
  for (std::size_t i = 0; i < r->size(); ++i) {
    if (!std::isfinite((*r)[i]))
      return varError(f, v, "value " + std::to_string(i) + " is missing or not finite (term '" + term + "')");
    (*r)[i] *= k;
  }
  return r;
}

Result<Levels> levelsOf(const io::NetcdfFile& f, const grid::GridLayout& l) {
  const grid::VerticalSpec& vs = l.vertical;
  Levels lv;
  const std::size_t n = vs.fileLevels;
  if (l.wrf) {
    lv.upward = true;
    return lv;  // eta values (ZNU) are read per time step with the heights
  }
  auto c = readPicked<double>(f, *vs.coordinate, {iota(0, n)});
  if (!c) return c.forwardError();
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite((*c)[i]))
      return varError(f, *vs.coordinate, "level " + std::to_string(i) + " is missing or not finite (NaN coordinate)");
  std::vector<double> ref(n);  // a quantity that increases upwards, for the direction
  switch (vs.kind) {
    case VerticalKind::Pressure:
      for (std::size_t i = 0; i < n; ++i) {
        lv.valuesSi.push_back((*c)[i] * vs.toSi);
        if (!(lv.valuesSi[i] > 0))
          return varError(f, *vs.coordinate,
                          "pressure level " + std::to_string(i) + " is " + num((*c)[i]) + " " + vs.coordinateUnits +
                              ": pressures must be positive");
        ref[i] = -lv.valuesSi[i];
      }
      lv.units = "Pa";
      break;
    case VerticalKind::HybridSigmaPressure:
    case VerticalKind::Sigma: {
      // Direction from the pressure of each level over a column whose surface is at 1000 hPa.
      lv.valuesSi = *c;
      lv.units = vs.coordinateUnits.empty() ? "1" : vs.coordinateUnits;
      std::vector<double> a, b;
      double p0 = 0, ptop = 0;
      if (vs.kind == VerticalKind::HybridSigmaPressure) {
        auto bb = readTerm(f, vs, "b");
        if (!bb) return bb.forwardError();
        b = *bb;
        if (vs.terms.count("ap")) {
          auto aa = readTerm(f, vs, "ap");
          if (!aa) return aa.forwardError();
          a = *aa;
          p0 = 1.0;
        } else {
          auto aa = readTerm(f, vs, "a");
          if (!aa) return aa.forwardError();
          a = *aa;
          auto pp = readTerm(f, vs, "p0");
          if (!pp) return pp.forwardError();
          p0 = pp->front();
        }
        for (std::size_t i = 0; i < n; ++i) ref[i] = -(a[i] * p0 + b[i] * 1.0e5);
      } else {
        auto s = readTerm(f, vs, "sigma");
        if (!s) return s.forwardError();
        auto pt = readTerm(f, vs, "ptop");
        if (!pt) return pt.forwardError();
        ptop = pt->front();
        for (std::size_t i = 0; i < n; ++i) ref[i] = -(ptop + (*s)[i] * (1.0e5 - ptop));
      }
      break;
    }
    case VerticalKind::HybridHeight: {
      lv.valuesSi = *c;
      lv.units = vs.coordinateUnits;
      auto a = readTerm(f, vs, "a");
      if (!a) return a.forwardError();
      ref = *a;
      break;
    }
    default:  // lengths, geopotential metres
      for (std::size_t i = 0; i < n; ++i) {
        lv.valuesSi.push_back((*c)[i] * vs.toSi);
        ref[i] = vs.positiveDown ? -lv.valuesSi[i] : lv.valuesSi[i];
      }
      lv.units = vs.kind == VerticalKind::GeopotentialHeight ? "gpm" : "m";
      break;
  }
  if (n >= 2) {
    lv.upward = ref[n - 1] > ref[0];
    for (std::size_t i = 1; i < n; ++i)
      if (!(lv.upward ? ref[i] > ref[i - 1] : ref[i] < ref[i - 1]))
        return varError(
            f, *vs.coordinate,
            "levels are not strictly monotonic (levels " + std::to_string(i - 1) + " and " + std::to_string(i) + ")");
  }
  return lv;
}

/// File level indices, bottom first, for the crop.
Result<std::vector<std::size_t>> levelPicks(const io::NetcdfFile& f, const grid::GridLayout& l, const Levels& lv,
                                            const GridCrop& crop) {
  const std::size_t n = l.vertical.fileLevels;
  if (crop.firstLevel >= n)
    return varError(
        f, l.var,
        "crop: first level " + std::to_string(crop.firstLevel) + " is beyond its " + std::to_string(n) + " levels");
  const std::size_t count = std::min(crop.levelCount, n - crop.firstLevel);
  std::vector<std::size_t> p(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t b = crop.firstLevel + k;  // counted from the bottom
    p[k] = lv.upward ? b : n - 1 - b;
  }
  return p;
}

/// What to read: the time step, levels (file indices, bottom first) and columns.
struct Selection {
  std::size_t time = 0;
  std::vector<std::size_t> levels;
  const Horizontal* hz = nullptr;
};

/// Picks for a variable on (some of) the grid variable's dimensions. `zStagger`: the variable
/// is on WRF's W levels (levels k and k+1 of each mass level k are read).
Result<Picks> supportPicks(const io::NetcdfFile& f, const grid::GridLayout& l, const Selection& s, const io::NcVar& v) {
  Picks p;
  for (std::size_t d = 0; d < v.dimIds.size(); ++d) {
    const int id = v.dimIds[d];
    if (id == l.time.dimId && l.time.dimId >= 0) p.push_back({s.time});
    else if (id == l.zDim) p.push_back(s.levels);
    else if (id == l.zStagDim && l.zStagDim >= 0) {
      std::vector<std::size_t> z = s.levels;
      z.push_back(s.levels.back() + 1);
      p.push_back(std::move(z));
    } else if (id == l.yDim) p.push_back(s.hz->rows);
    else if (id == l.xDim) p.push_back(s.hz->cols);
    else if (v.shape[d] == 1) p.push_back({0});
    else
      return varError(f, v,
                      "dimension '" + dimensionName(v.groupId, id) + "' is not a dimension of '" + l.var.name +
                          "': inconsistent sizes");
  }
  return p;
}

struct Heights {
  std::vector<double> h;  ///< nz x ny x nx, above the ellipsoid
  HeightSource source = HeightSource::Coordinate;
  std::string note;
  bool approximate = false;
  std::string fromVariable;  ///< named in errors about the heights
  std::vector<double> levelValues;
  std::string levelUnits;
};

constexpr const char* kStandardAtmosphereNote =
    "standard-atmosphere height of each pressure (APPROXIMATE: a real pressure level lies up to a few hundred "
    "metres away)";

Result<Heights> computeHeights(const io::NetcdfFile& f, const grid::GridLayout& l, const Levels& lv, const Selection& s,
                               bool useGeoid) {
  const grid::VerticalSpec& vs = l.vertical;
  const Horizontal& hz = *s.hz;
  const std::size_t nz = s.levels.size(), ny = hz.rows.size(), nx = hz.cols.size(), nc = ny * nx;
  Heights out;
  out.h.assign(nz * nc, kNaN);
  const std::string coordName = vs.coordinate ? "'" + vs.coordinate->name + "'" : std::string();
  out.fromVariable = vs.coordinate ? vs.coordinate->name : l.var.name;
  for (std::size_t k = 0; k < nz && !lv.valuesSi.empty(); ++k) out.levelValues.push_back(lv.valuesSi[s.levels[k]]);
  out.levelUnits = lv.units;

  // Per column: latitude and geometric-height converter.
  std::vector<double> colLat(nc), colLon(nc);
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      colLat[j * nx + i] = hz.latAt(j, i, l.curvilinear);
      colLon[j * nx + i] = hz.lonAt(j, i, l.curvilinear);
    }
  auto toGeometric = [&](std::vector<double>& geopotentialHeight) {  // nz x nc in place, level by level
    std::vector<GeopotentialToGeometric> conv;
    conv.reserve(nc);
    for (std::size_t c = 0; c < nc; ++c) conv.emplace_back(colLat[c]);
    for (std::size_t k = 0; k < nz; ++k) {
      double* h = geopotentialHeight.data() + k * nc;
      for (std::size_t c = 0; c < nc; ++c) h[c] = conv[c](h[c]);
    }
  };
  auto readField = [&](const io::NcVar& v, std::vector<double>* values) -> Status {
    auto p = supportPicks(f, l, s, v);
    if (!p) return p.forwardError();
    auto r = readPicked<double>(f, v, *p);
    if (!r) return r.forwardError();
    *values = std::move(*r);
    return Ok{};
  };
  // Pressure per level and column -> heights, from the geopotential field if there is one.
  auto fromPressure = [&](const std::vector<double>& pressurePa, bool perColumn, const std::string& what) -> Status {
    if (vs.geopotential) {
      std::vector<double> g;
      if (auto st = readField(*vs.geopotential, &g); !st) return st;
      for (double& x : g) x *= vs.geopotentialToGpm;
      toGeometric(g);
      out.h = std::move(g);
      out.source = HeightSource::GeopotentialField;
      out.fromVariable = vs.geopotential->name;
      out.note =
          what + " with the geopotential field '" + vs.geopotential->name + "'" +
          (vs.geopotentialToGpm != 1.0 ? " (m2 s-2 / 9.80665 = geopotential height)" : " (geopotential height)") +
          " -> geometric height above mean sea level (WGS84 normal gravity)";
      return Ok{};
    }
    for (std::size_t k = 0; k < nz; ++k)
      for (std::size_t c = 0; c < nc; ++c) {
        const double p = perColumn ? pressurePa[k * nc + c] : pressurePa[k];
        out.h[k * nc + c] = p > 0 ? standardAtmosphereGeopotentialHeightMeters(p) : kNaN;
      }
    toGeometric(out.h);
    out.source = HeightSource::StandardAtmosphere;
    out.approximate = true;
    out.note = what + " without a geopotential field: " + kStandardAtmosphereNote +
               " -> geometric height above mean sea level";
    return Ok{};
  };
  bool seaLevel = true;  // heights so far are above sea level (the geoid); else above the ellipsoid

  switch (vs.kind) {
    case VerticalKind::HeightAboveEllipsoid:
    case VerticalKind::HeightAboveSeaLevel:
    case VerticalKind::HeightAboveGround: {
      const double sign = vs.positiveDown ? -1.0 : 1.0;
      for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t c = 0; c < nc; ++c) out.h[k * nc + c] = sign * lv.valuesSi[s.levels[k]];
      if (vs.datum == grid::LengthDatum::Ellipsoid) {
        seaLevel = false;
        out.note = "heights above the WGS84 ellipsoid from " + coordName + " (" + vs.datumReason + ")";
      } else if (vs.datum == grid::LengthDatum::Ground) {
        if (vs.surfaceAltitude) {
          std::vector<double> surf;
          if (auto st = readField(*vs.surfaceAltitude, &surf); !st) return st.forwardError();
          for (std::size_t c = 0; c < nc; ++c) {
            if (!std::isfinite(surf[c]))
              return varError(f, *vs.surfaceAltitude,
                              "surface altitude missing or not finite at row " + std::to_string(hz.rows[c / nx]) +
                                  ", column " + std::to_string(hz.cols[c % nx]));
            surf[c] *= vs.surfaceToMeters;
          }
          for (std::size_t k = 0; k < nz; ++k)
            for (std::size_t c = 0; c < nc; ++c) out.h[k * nc + c] += surf[c];
          out.note = "heights above ground from " + coordName + " (" + vs.datumReason + ") + the surface altitude '" +
                     vs.surfaceAltitude->name + "' -> above mean sea level";
        } else {
          out.approximate = true;
          out.note = "heights above ground from " + coordName + " (" + vs.datumReason +
                     "); the file has no surface altitude, so the ground is taken at sea level (APPROXIMATE)";
        }
      } else if (vs.datum == grid::LengthDatum::Unknown) {
        out.approximate = true;
        out.note = "lengths from " + coordName + " whose datum the file does not state (" + vs.datumReason +
                   "), taken as heights above mean sea level (APPROXIMATE)";
      } else {
        out.note = "heights above mean sea level from " + coordName + " (" + vs.datumReason + ")";
      }
      break;
    }
    case VerticalKind::GeopotentialHeight:
      for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t c = 0; c < nc; ++c) out.h[k * nc + c] = lv.valuesSi[s.levels[k]];
      toGeometric(out.h);
      out.note = "geopotential heights from " + coordName +
                 " (about heights above mean sea level) -> geometric heights (WGS84 normal gravity)";
      break;
    case VerticalKind::Pressure: {
      std::vector<double> p(nz);
      for (std::size_t k = 0; k < nz; ++k) p[k] = lv.valuesSi[s.levels[k]];
      if (auto st = fromPressure(p, false, "pressure levels " + coordName); !st) return st.forwardError();
      break;
    }
    case VerticalKind::HybridSigmaPressure:
    case VerticalKind::Sigma: {
      const bool hybrid = vs.kind == VerticalKind::HybridSigmaPressure;
      std::vector<double> ps;
      if (auto st = readField(vs.terms.at("ps"), &ps); !st) return st.forwardError();
      const double psToPa = vs.termToSi.at("ps");
      std::vector<double> p(nz * nc, kNaN);
      std::string terms;
      if (hybrid) {
        auto b = readTerm(f, vs, "b");
        if (!b) return b.forwardError();
        std::vector<double> a;
        double p0 = 1.0;
        if (vs.terms.count("ap")) {
          auto ap = readTerm(f, vs, "ap");
          if (!ap) return ap.forwardError();
          a = *ap;
          terms = "p = ap + b ps with '" + vs.terms.at("ap").name + "', '" + vs.terms.at("b").name + "', '" +
                  vs.terms.at("ps").name + "'";
        } else {
          auto aa = readTerm(f, vs, "a");
          if (!aa) return aa.forwardError();
          a = *aa;
          auto pp = readTerm(f, vs, "p0");
          if (!pp) return pp.forwardError();
          p0 = pp->front();
          terms = "p = a p0 + b ps with '" + vs.terms.at("a").name + "', '" + vs.terms.at("p0").name + "', '" +
                  vs.terms.at("b").name + "', '" + vs.terms.at("ps").name + "'";
        }
        for (std::size_t k = 0; k < nz; ++k)
          for (std::size_t c = 0; c < nc; ++c) p[k * nc + c] = a[s.levels[k]] * p0 + (*b)[s.levels[k]] * ps[c] * psToPa;
      } else {
        auto sg = readTerm(f, vs, "sigma");
        if (!sg) return sg.forwardError();
        auto pt = readTerm(f, vs, "ptop");
        if (!pt) return pt.forwardError();
        const double ptop = pt->front();
        terms = "p = ptop + sigma (ps - ptop) with '" + vs.terms.at("ptop").name + "', '" + vs.terms.at("sigma").name +
                "', '" + vs.terms.at("ps").name + "'";
        for (std::size_t k = 0; k < nz; ++k)
          for (std::size_t c = 0; c < nc; ++c) p[k * nc + c] = ptop + (*sg)[s.levels[k]] * (ps[c] * psToPa - ptop);
      }
      for (std::size_t c = 0; c < nc; ++c)
        if (!std::isfinite(ps[c]) || !(ps[c] > 0))
          return varError(f, vs.terms.at("ps"),
                          "surface pressure missing or not positive at row " + std::to_string(hz.rows[c / nx]) +
                              ", column " + std::to_string(hz.cols[c % nx]));
      out.fromVariable = vs.terms.at("ps").name;
      if (auto st = fromPressure(
              p, true,
              std::string(hybrid ? "hybrid sigma-pressure" : "sigma") + " levels " + coordName + " (" + terms + ")");
          !st)
        return st.forwardError();
      break;
    }
    case VerticalKind::HybridHeight: {
      auto a = readTerm(f, vs, "a");
      if (!a) return a.forwardError();
      auto b = readTerm(f, vs, "b");
      if (!b) return b.forwardError();
      std::vector<double> orog;
      if (auto st = readField(vs.terms.at("orog"), &orog); !st) return st.forwardError();
      const double k0 = vs.termToSi.at("orog");
      for (std::size_t c = 0; c < nc; ++c) {
        if (!std::isfinite(orog[c]))
          return varError(f, vs.terms.at("orog"),
                          "surface altitude missing or not finite at row " + std::to_string(hz.rows[c / nx]) +
                              ", column " + std::to_string(hz.cols[c % nx]));
        for (std::size_t k = 0; k < nz; ++k) out.h[k * nc + c] = (*a)[s.levels[k]] + (*b)[s.levels[k]] * orog[c] * k0;
      }
      out.note = "hybrid height levels " + coordName + ": z = a + b orog with '" + vs.terms.at("a").name + "', '" +
                 vs.terms.at("b").name + "', '" + vs.terms.at("orog").name + "' (above the geoid)";
      break;
    }
    case VerticalKind::WrfEta: {
      if (vs.znu) {
        Picks zp;
        for (std::size_t d = 0; d < vs.znu->dimIds.size(); ++d)
          zp.push_back(vs.znu->dimIds[d] == l.zDim
                           ? s.levels
                           : std::vector<std::size_t>{vs.znu->dimIds[d] == l.time.dimId ? s.time : 0});
        if (auto znu = readPicked<double>(f, *vs.znu, zp)) {
          out.levelValues = *znu;
          out.levelUnits = "eta";
        }
      }
      if (vs.ph) {
        std::vector<double> ph, phb;
        if (auto st = readField(*vs.ph, &ph); !st) return st.forwardError();
        if (auto st = readField(*vs.phb, &phb); !st) return st.forwardError();
        // (nz + 1) W levels -> nz mass levels.
        std::vector<double> w(ph.size());
        for (std::size_t i = 0; i < w.size(); ++i) w[i] = (ph[i] + phb[i]) / kWrfGravity;
        std::vector<std::size_t> shape = {nz + 1, nc};
        averageAdjacent(w, shape, 0);
        out.h = std::move(w);
        out.source = HeightSource::WrfGeopotential;
        out.fromVariable = vs.ph->name + "+" + vs.phb->name;
        out.note =
            "WRF eta levels: (PH+PHB)/9.81 on the W levels averaged to mass levels: geopotential height with WRF's "
            "constant g, which WRF takes as height above mean sea level (its terrain HGT is PHB/9.81 at the surface)";
      } else {
        std::vector<double> p, pb;
        if (auto st = readField(*vs.p, &p); !st) return st.forwardError();
        if (auto st = readField(*vs.pb, &pb); !st) return st.forwardError();
        for (std::size_t i = 0; i < p.size(); ++i) p[i] += pb[i];
        out.fromVariable = vs.p->name + "+" + vs.pb->name;
        if (auto st = fromPressure(p, true, "WRF eta levels without PH/PHB: pressure P+PB"); !st)
          return st.forwardError();
      }
      break;
    }
  }

  if (seaLevel) {
    if (useGeoid) {
      const Result<GeoidGrid>& geoid = defaultEgm96Grid();
      if (!geoid) return makeError(f.message(geoid.error()));
      std::vector<double> n(nc);
      for (std::size_t c = 0; c < nc; ++c) n[c] = geoid->undulationMeters(colLat[c], colLon[c]);
      for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t c = 0; c < nc; ++c) out.h[k * nc + c] += n[c];
      out.note += "; + EGM96 geoid undulation -> above the WGS84 ellipsoid";
    } else {
      out.note +=
          "; no geoid correction (geoid off): heights above sea level used as above the WGS84 ellipsoid, "
          "off by the undulation (-106..+85 m)";
    }
  }
  return out;
}

/// Heights must be finite and increase strictly upwards in every column (after float rounding).
Status checkHeights(const io::NetcdfFile& f, const Heights& h, const Selection& s, std::size_t nc) {
  const std::size_t nz = s.levels.size();
  const std::size_t nx = s.hz->cols.size();
  auto where = [&](std::size_t k, std::size_t c) {
    return "level " + std::to_string(s.levels[k]) + ", row " + std::to_string(s.hz->rows[c / nx]) + ", column " +
           std::to_string(s.hz->cols[c % nx]);
  };
  for (std::size_t k = 0; k < nz; ++k)  // level by level: contiguous memory
    for (std::size_t c = 0; c < nc; ++c) {
      const float z = static_cast<float>(h.h[k * nc + c]);
      if (!std::isfinite(z))
        return makeError(f.message("variable '" + h.fromVariable + "': height not finite at " + where(k, c) +
                                   " (a missing value in what the heights come from)"));
      if (k > 0 && !(z > static_cast<float>(h.h[(k - 1) * nc + c])))
        return makeError(f.message("variable '" + h.fromVariable + "': heights do not increase upwards at " +
                                   where(k, c) + " (" + num(h.h[(k - 1) * nc + c], 1) + " m below, " +
                                   num(h.h[k * nc + c], 1) + " m here)"));
    }
  return Ok{};
}

Result<std::size_t> resolveTime(const io::NetcdfFile& f, const grid::GridLayout& l, const GridReadOptions& o,
                                const std::vector<std::string>& times) {
  if (!o.timeIso8601.empty()) {
    if (l.time.dimId < 0) return varError(f, l.var, "has no time dimension; cannot select time " + o.timeIso8601);
    // Parsed in the axis's calendar: a 360_day file has 30 February.
    const char* calendar = l.time.parsed ? toString(l.time.parsed->calendar) : "standard";
    auto parsed = parseCfTimeUnits("seconds since " + o.timeIso8601, calendar);
    if (!parsed)
      return makeError(
          f.message("time '" + o.timeIso8601 + "' is not an ISO 8601 date-time of the " + calendar + " calendar"));
    const std::string want = parsed->referenceIso8601;
    for (std::size_t i = 0; i < times.size(); ++i)
      if (times[i] == want) return i;
    if (!l.time.unitsError.empty()) return makeError(l.time.unitsError);
    std::string axis = times.empty() ? std::string("none") : times.front() + " .. " + times.back();
    return varError(
        f, l.var,
        "no time step at " + want + " (the time axis has " + std::to_string(times.size()) + " steps: " + axis + ")");
  }
  const std::size_t n = l.time.dimId < 0 ? 1 : l.time.count;
  if (o.timeIndex >= n)
    return varError(f, l.var,
                    "time index " + std::to_string(o.timeIndex) + " is beyond its " + std::to_string(n) + " time step" +
                        (n == 1 ? "" : "s"));
  return o.timeIndex;
}

// The variable's layout; for an empty name, the default variable (or why there is none).
Result<GridLayout> layoutFor(const io::NetcdfFile& f, const FileKind& kind, const std::string& variable,
                             std::string* chosen) {
  if (!variable.empty()) {
    auto v = findGridVariable(f, variable);
    if (!v) return v.forwardError();
    *chosen = v->name;
    return analyse(f, kind, *v);
  }
  const std::vector<GridVariableInfo> vars = listVariables(f, kind);
  const std::string name = chooseDefaultGridVariable(vars);
  if (name.empty()) {
    // Say why the first variable with three or more dimensions is not a grid variable.
    for (int g : allGroups(f))
      for (const io::NcVar& v : f.variables(g))
        if (v.dimIds.size() >= 3 && io::ncTypeIsNumeric(v.type)) {
          auto why = analyse(f, kind, v);
          if (!why) return makeError(why.error() + " (no variable of the file is a 3-D grid this reader can read)");
        }
    return makeError(
        f.message("no variable with a vertical and two horizontal dimensions (latitude/longitude "
                  "coordinates) found: not a forecast grid"));
  }
  auto v = findGridVariable(f, name);
  if (!v) return v.forwardError();
  *chosen = v->name;
  return analyse(f, kind, *v);
}

}  // namespace

}  // namespace grid

std::string chooseDefaultGridVariable(const std::vector<GridVariableInfo>& variables) {
  auto shortName = [](const std::string& n) { return n.substr(n.rfind('/') + 1); };
  for (const char* want : {"REFL_10CM", "dbz", "DBZ", "reflectivity", "QCLOUD", "QRAIN", "clw", "cloud_water"})
    for (const auto& v : variables)
      if (v.onGrid && shortName(v.name) == want) return v.name;
  for (const char* want : {"equivalent_reflectivity_factor", "mass_fraction_of_cloud_liquid_water_in_air",
                           "cloud_liquid_water_mixing_ratio"})
    for (const auto& v : variables)
      if (v.onGrid && v.standardName == want) return v.name;
  for (const auto& v : variables)
    if (v.onGrid) return v.name;
  return {};
}

bool isGridFile(const std::string& path) {
  if (!io::hasNetcdfSignature(path)) return false;
  auto f = io::NetcdfFile::open(path);
  if (!f) return false;
  const int root = f->root();
  // Radar marks first: a CfRadial or ODIM file is not a grid even if it has 3-D variables.
  if (f->findVariable(root, "sweep_start_ray_index")) return false;
  const std::string conventions = grid::globalText(*f, "Conventions");
  if (conventions.rfind("ODIM_H5", 0) == 0 || conventions.find("Radial") != std::string::npos) return false;
  const grid::FileKind kind = grid::fileKind(*f);
  if (kind.wrf) return true;
  for (const GridVariableInfo& v : grid::listVariables(*f, kind))
    if (v.onGrid) return true;
  return false;
}

Result<GridVolume> readGridVolume(const std::string& path, const GridReadOptions& options) {
  auto opened = io::NetcdfFile::open(path);
  if (!opened) return opened.forwardError();
  const io::NetcdfFile& f = *opened;
  if (auto st = grid::checkCrop(f, options.crop); !st) return st.forwardError();
  const grid::FileKind kind = grid::fileKind(f);
  std::string name;
  auto layout = grid::layoutFor(f, kind, options.variable, &name);
  if (!layout) return layout.forwardError();
  const grid::GridLayout& l = *layout;

  auto times = grid::readTimes(f, l.time);
  if (!times) return times.forwardError();
  auto t = grid::resolveTime(f, l, options, *times);
  if (!t) return t.forwardError();
  auto hz = l.curvilinear ? grid::curvilinear(f, l, *t, options.crop, 1) : grid::rectilinear(f, l, options.crop, 1);
  if (!hz) return hz.forwardError();
  auto lv = grid::levelsOf(f, l);
  if (!lv) return lv.forwardError();
  auto levels = grid::levelPicks(f, l, *lv, options.crop);
  if (!levels) return levels.forwardError();
  grid::Selection sel{*t, *levels, &*hz};
  const std::size_t nz = sel.levels.size(), ny = hz->rows.size(), nx = hz->cols.size();

  // Values: the variable's own dimensions, staggered ones one longer, then averaged to mass points.
  grid::Picks picks;
  std::vector<std::size_t> stagAxes;
  for (std::size_t d = 0; d < l.var.dimIds.size(); ++d) {
    const int id = l.var.dimIds[d];
    auto extended = [&](std::vector<std::size_t> p) {
      stagAxes.push_back(d);
      p.push_back(p.back() + 1);  // contiguous ascending picks (WRF: no reversal, no wrap)
      return p;
    };
    if (id == l.time.dimId && l.time.dimId >= 0) picks.push_back({*t});
    else if (id == l.zDim) picks.push_back(sel.levels);
    else if (l.stagZ && id == l.zStagDim) picks.push_back(extended(sel.levels));
    else if (id == l.yDim) picks.push_back(hz->rows);
    else if (l.stagY && id == l.yStagDim) picks.push_back(extended(hz->rows));
    else if (id == l.xDim) picks.push_back(hz->cols);
    else if (l.stagX && id == l.xStagDim) picks.push_back(extended(hz->cols));
    else picks.push_back({0});
  }
  auto values = grid::readPicked<float>(f, l.var, picks);
  if (!values) return values.forwardError();
  std::vector<std::size_t> shape;
  for (const auto& p : picks) shape.push_back(p.size());
  for (std::size_t axis : stagAxes) grid::averageAdjacent(*values, shape, axis);

  auto heights = grid::computeHeights(f, l, *lv, sel, options.useGeoid);
  if (!heights) return heights.forwardError();
  if (auto st = grid::checkHeights(f, *heights, sel, ny * nx); !st) return st.forwardError();

  GridVolume g;
  g.path = path;
  g.format = kind.format;
  g.variable = name;
  g.units = l.units;
  g.standardName = l.standardName;
  g.longName = l.longName;
  g.curvilinear = l.curvilinear;
  g.nx = nx;
  g.ny = ny;
  g.nz = nz;
  g.latDeg = std::move(hz->latDeg);
  g.lonDeg = std::move(hz->lonDeg);
  g.wrapsLongitude = hz->wrapsLongitude;
  g.fileFirstRow = hz->rows.front();
  g.fileFirstColumn = hz->cols.front();
  g.fileFirstLevel = sel.levels.front();
  g.fileRowStep = hz->rowStep;
  g.fileColumnStep = hz->colStep;
  g.fileLevelStep = lv->upward ? 1 : -1;
  g.values = std::move(*values);
  for (float v : g.values) {
    if (!std::isfinite(v)) continue;
    if (!(v >= g.valueMin)) g.valueMin = v;  // NaN start: the first finite value
    if (!(v <= g.valueMax)) g.valueMax = v;
  }
  g.heightAboveEllipsoidMeters.resize(heights->h.size());
  for (std::size_t i = 0; i < heights->h.size(); ++i)
    g.heightAboveEllipsoidMeters[i] = static_cast<float>(heights->h[i]);  // float: see GridVolume.h
  g.verticalKind = l.vertical.kind;
  g.heightSource = heights->source;
  g.verticalVariable = l.wrf ? heights->fromVariable : (l.vertical.coordinate ? l.vertical.coordinate->name : "");
  g.heightNote = heights->note;
  g.approximateHeights = heights->approximate;
  g.levelValues = heights->levelValues;
  g.levelUnits = heights->levelUnits;
  g.times = std::move(*times);
  g.timeIndex = *t;
  g.validTime = l.time.dimId >= 0 && *t < g.times.size() ? g.times[*t] : std::string();
  g.bytesRead = f.dataBytesRead();
  return g;
}

// ------------------------------------------------------------------------------- describe

Result<GridFileInfo> describeGridFile(const std::string& path, const std::string& variable) {
  auto opened = io::NetcdfFile::open(path);
  if (!opened) return opened.forwardError();
  const io::NetcdfFile& f = *opened;
  const grid::FileKind kind = grid::fileKind(f);
  GridFileInfo info;
  info.path = path;
  info.format = kind.format;
  info.conventions = kind.conventions;
  for (int g : grid::allGroups(f)) {
    const io::NetcdfLock lock;
    int n = 0;
    if (nc_inq_dimids(g, &n, nullptr, 0) != NC_NOERR || n <= 0) continue;
    std::vector<int> ids(static_cast<std::size_t>(n));
    nc_inq_dimids(g, &n, ids.data(), 0);
    int nu = 0;
    std::vector<int> unlimited(NC_MAX_DIMS);
    nc_inq_unlimdims(g, &nu, unlimited.data());
    const std::string gp = f.groupPath(g);
    for (int id : ids) {
      GridDimensionInfo d;
      d.name = (gp == "/" ? "/" : gp + "/") + grid::dimensionName(g, id);
      nc_inq_dimlen(g, id, &d.length);
      d.unlimited = std::find(unlimited.begin(), unlimited.begin() + std::max(nu, 0), id) !=
                    unlimited.begin() + std::max(nu, 0);
      info.dimensions.push_back(std::move(d));
    }
  }
  info.variables = grid::listVariables(f, kind);
  std::string name;
  auto layout = grid::layoutFor(f, kind, variable, &name);
  if (!layout) return layout.forwardError();
  const grid::GridLayout& l = *layout;
  info.variable = name;
  info.curvilinear = l.curvilinear;
  info.nx = l.nx;
  info.ny = l.ny;
  info.nz = l.vertical.fileLevels;
  info.xDimension = grid::dimensionName(l.var.groupId, l.xDim);
  info.yDimension = grid::dimensionName(l.var.groupId, l.yDim);
  info.zDimension = grid::dimensionName(l.var.groupId, l.zDim);
  info.timeDimension = l.time.dimId >= 0 ? grid::dimensionName(l.var.groupId, l.time.dimId) : "";

  auto times = grid::readTimes(f, l.time);
  if (!times) return times.forwardError();
  info.times = *times;
  if (l.time.wrfTimes) {
    info.timeVariable = l.time.wrfTimes->name;
    info.timeUnits = "WRF Times strings (YYYY-MM-DD_hh:mm:ss)";
  } else if (l.time.coordinate) {
    info.timeVariable = l.time.coordinate->name;
    info.timeUnits = l.time.units;
    info.calendar = l.time.parsed ? toString(l.time.parsed->calendar) : l.time.calendar;
  }

  // Extent from the full coordinates; heights from a sample of at most ~64 x 64 columns.
  GridCrop all;
  auto full = l.curvilinear ? grid::curvilinear(f, l, 0, all, 1) : grid::rectilinear(f, l, all, 1);
  if (!full) return full.forwardError();
  info.southDeg = full->southDeg;
  info.northDeg = full->northDeg;
  info.westDeg = full->westDeg;
  info.eastDeg = full->eastDeg;
  info.wrapsLongitude = full->wrapsLongitude;
  {
    const std::size_t j = full->rows.size() / 2, i = full->cols.size() / 2;
    double sum = 0;
    int n = 0;
    const double la = full->latAt(j, i, l.curvilinear), lo = full->lonAt(j, i, l.curvilinear);
    if (i + 1 < full->cols.size()) {
      sum += globe::geodesicInverse(la, lo, full->latAt(j, i + 1, l.curvilinear), full->lonAt(j, i + 1, l.curvilinear))
                 .distanceMeters;
      ++n;
    }
    if (j + 1 < full->rows.size()) {
      sum += globe::geodesicInverse(la, lo, full->latAt(j + 1, i, l.curvilinear), full->lonAt(j + 1, i, l.curvilinear))
                 .distanceMeters;
      ++n;
    }
    info.meanSpacingKm = n ? sum / n / 1000.0 : 0.0;
  }
  const std::size_t stride = std::max<std::size_t>(1, (std::max(l.nx, l.ny) + 63) / 64);
  info.heightColumnStride = stride;
  auto sample = l.curvilinear ? grid::curvilinear(f, l, 0, all, stride) : grid::rectilinear(f, l, all, stride);
  if (!sample) return sample.forwardError();
  auto lv = grid::levelsOf(f, l);
  if (!lv) return lv.forwardError();
  auto levels = grid::levelPicks(f, l, *lv, all);
  if (!levels) return levels.forwardError();
  grid::Selection sel{0, *levels, &*sample};
  auto heights = grid::computeHeights(f, l, *lv, sel, true);
  if (!heights) return heights.forwardError();
  if (auto st = grid::checkHeights(f, *heights, sel, sample->rows.size() * sample->cols.size()); !st)
    return st.forwardError();
  info.verticalKind = l.vertical.kind;
  info.heightSource = heights->source;
  info.verticalVariable = l.wrf ? heights->fromVariable : (l.vertical.coordinate ? l.vertical.coordinate->name : "");
  info.heightNote = heights->note;
  info.approximateHeights = heights->approximate;
  info.levelValues = heights->levelValues;
  info.levelUnits = heights->levelUnits;
  const auto [mn, mx] = std::minmax_element(heights->h.begin(), heights->h.end());
  info.heightMinMeters = *mn;
  info.heightMaxMeters = *mx;
  info.bytesRead = f.dataBytesRead();
  return info;
}

Status selectGridTime(const std::string& text, GridReadOptions& read) {
  if (!text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    if (text.size() > 9) return makeError("time index " + text + " is too large");
    read.timeIndex = static_cast<std::size_t>(std::stoul(text));
    read.timeIso8601.clear();
  } else {
    read.timeIso8601 = text;
  }
  return Ok{};
}

}  // namespace atmoglobe::volume
