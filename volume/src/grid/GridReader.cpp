// The forecast-grid reader: region, levels and time step to hyperslab picks; values. The
// format and the default variable are found in GridFormat.cpp, the variable's layout in
// GridLayout.cpp, the columns of a crop in GridHorizontal.cpp, the vertical coordinates (heights
// above the WGS84 ellipsoid for every column and level) in GridHeights.cpp, the netCDF layer in
// GridNetcdf.cpp, `info` (describeGridFile and its text) in GridDescribe.cpp. GRIB files go to
// GribReader.cpp (messages indexed in GribIndex.cpp).
#include "GribInternal.h"
#include "GridInternal.h"

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {

namespace grid {

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

/// WRF's diagnostics that forecasters read, named as wrf-python names them, from the fields
/// the model writes as perturbations about a base state (docs/grids.md, "WRF"): "z", the
/// geopotential PH + PHB at mass levels (m2 s-2, as GRIB's z), and "tk", the temperature
/// (T + 300) ((P + PB) / 1000 hPa)^(Rd/cp) with WRF's Rd/cp = 2/7 (K).
Result<GridVolume> readWrfDiagnostic(const std::string& path, const GridReadOptions& options) {
  const std::vector<std::string> parts = options.variable == "z" ? std::vector<std::string>{"PH", "PHB"}
                                                                 : std::vector<std::string>{"T", "P", "PB"};
  std::vector<GridVolume> read;
  for (std::size_t n = 0; n < parts.size(); ++n) {
    GridReadOptions o = options;
    o.variable = parts[n];
    o.keepPressure = n == 0 && options.keepPressure;
    auto g = readGridVolume(path, o);
    if (!g)
      return makeError(g.error() + " (WRF's '" + options.variable + "' is made from " +
                       (parts.size() == 2 ? "PH and PHB" : "T, P and PB") + ")");
    read.push_back(std::move(*g));
  }
  GridVolume out = std::move(read[0]);
  for (std::size_t n = 1; n < read.size(); ++n) {
    if (read[n].values.size() != out.values.size())
      return makeError(path + ": '" + parts[n] + "' and '" + parts[0] + "' differ in shape");
    out.bytesRead += read[n].bytesRead;
  }
  if (options.variable == "z") {
    for (std::size_t i = 0; i < out.values.size(); ++i) out.values[i] += read[1].values[i];
    out.units = "m2 s-2";
    out.standardName = "geopotential";
    out.longName = "geopotential (WRF's PH + PHB at mass levels)";
  } else {
    constexpr double kRdOverCp = 2.0 / 7.0;  // WRF's Rd / cp: 287 / 1004.5
    for (std::size_t i = 0; i < out.values.size(); ++i) {
      const double p = static_cast<double>(read[1].values[i]) + static_cast<double>(read[2].values[i]);
      out.values[i] = static_cast<float>((static_cast<double>(out.values[i]) + 300.0) * std::pow(p / 1.0e5, kRdOverCp));
    }
    out.units = "K";
    out.standardName = "air_temperature";
    out.longName = "temperature (from WRF's T + 300 K, P and PB)";
  }
  out.variable = "/" + options.variable;
  out.vectorsRelativeToGrid = false;
  setValueRange(out);
  return out;
}

}  // namespace grid

Result<GridVolume> readGridVolume(const std::string& path, const GridReadOptions& options) {
  if (options.ensemble) return grid::readGridEnsembleStatistic(path, options);
  if (grib::hasGribSignature(path) || grib::isGribSet(path)) {
    if (!options.extraIndex.empty())
      return makeError(path + ": an index along dimension '" + options.extraIndex.begin()->first +
                       "' asked for, but a GRIB file has no such dimensions (ensemble members: member)");
    return grib::readGribVolume(path, options);
  }
  auto opened = io::NetcdfFile::open(path);
  if (!opened) return opened.forwardError();
  const io::NetcdfFile& f = *opened;
  if (auto st = grid::checkCrop(f, options.crop); !st) return st.forwardError();
  const grid::FileKind kind = grid::fileKind(f);
  if (kind.wrf && (options.variable == "z" || options.variable == "tk") && !f.findVariable(f.root(), options.variable))
    return grid::readWrfDiagnostic(path, options);
  std::string name;
  auto layout = grid::layoutFor(f, kind, options.variable, &name, options.allowSingleLevel);
  if (!layout) return layout.forwardError();
  const grid::GridLayout& l = *layout;

  auto times = grid::readTimes(f, l.time);
  if (!times) return times.forwardError();
  auto t = grid::resolveTime(f, l, options, *times);
  if (!t) return t.forwardError();
  std::map<int, std::size_t> extraIndex;
  auto extras = grid::resolveExtraDimensions(f, l, options, &extraIndex);
  if (!extras) return extras.forwardError();
  auto hz = l.curvilinear ? grid::curvilinear(f, l, *t, options.crop, 1) : grid::rectilinear(f, l, options.crop, 1);
  if (!hz) return hz.forwardError();
  auto lv = grid::levelsOf(f, l);
  if (!lv) return lv.forwardError();
  auto levels = grid::levelPicks(f, l, *lv, options.crop);
  if (!levels) return levels.forwardError();
  grid::Selection sel{*t, *levels, &*hz, extraIndex, {}};
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
    else if (auto e = extraIndex.find(id); e != extraIndex.end()) picks.push_back({e->second});
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
  if (options.keepPressure)
    if (auto st = grid::wrfPressure(f, l, *lv, sel, *heights); !st) return st.forwardError();

  GridVolume g;
  g.path = path;
  g.format = kind.format;
  // Components along the grid's axes: a WRF model's U and V, CF's x_wind, grid_eastward_wind ...
  g.vectorsRelativeToGrid = (kind.wrf && (name == "/U" || name == "/V" || name == "/U10" || name == "/V10")) ||
                            l.standardName == "x_wind" || l.standardName == "y_wind" ||
                            l.standardName.rfind("grid_eastward", 0) == 0 ||
                            l.standardName.rfind("grid_northward", 0) == 0;
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
  setValueRange(g);
  g.heightAboveEllipsoidMeters.resize(heights->h.size());
  for (std::size_t i = 0; i < heights->h.size(); ++i)
    g.heightAboveEllipsoidMeters[i] = static_cast<float>(heights->h[i]);  // float: see GridVolume.h
  grid::setHeightFields(l, *heights, g);
  if (options.keepPressure && l.vertical.kind != VerticalKind::Pressure)
    g.pressurePa.assign(heights->pressurePa.begin(), heights->pressurePa.end());
  g.times = std::move(*times);
  g.timeIndex = *t;
  g.validTime = l.time.dimId >= 0 && *t < g.times.size() ? g.times[*t] : std::string();
  g.member = grid::memberOf(*extras);
  g.extraDimensions = std::move(*extras);
  g.bytesRead = f.dataBytesRead();
  return g;
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
