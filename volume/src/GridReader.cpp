// The forecast-grid reader: region, levels and time step to hyperslab picks; values. Layout
// detection is in GridLayout.cpp, the vertical coordinates (heights above the WGS84 ellipsoid for
// every column and level) in GridHeights.cpp, the netCDF layer in GridNetcdf.cpp, the
// descriptions in GridDescribe.cpp.
#include "GridInternal.h"

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {

namespace grid {

namespace {

double mod360(double x) {
  double r = std::fmod(x, 360.0);
  if (r < 0) r += 360.0;
  return r;
}

double wrap180(double x) {  // [-180, 180)
  return mod360(x + 180.0) - 180.0;
}

// ------------------------------------------------------------------------------- horizontal

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
