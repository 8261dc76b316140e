// `atmoglobe info` for forecast grids: GridFileInfo gathered from the file (dimensions, variables,
// the variable's axes, extent, spacing and a sample of its heights), as JSON and as text.
#include "GribInternal.h"
#include "GridInternal.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GridReader.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace atmoglobe::volume {

namespace {

std::string joinDims(const GridVariableInfo& v) {
  std::string s;
  for (std::size_t d = 0; d < v.dimensions.size(); ++d) {
    if (d) s.append(", ");
    s.append(v.dimensions[d]);
  }
  return s;
}

nlohmann::ordered_json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

}  // namespace

Result<GridFileInfo> describeGridFile(const std::string& path, const std::string& variable) {
  GridReadOptions read;
  read.variable = variable;
  return describeGridFile(path, read);
}

Result<GridFileInfo> describeGridFile(const std::string& path, const GridReadOptions& read) {
  const std::string& variable = read.variable;
  if (grib::hasGribSignature(path) || grib::isGribSet(path)) {
    if (!read.extraIndex.empty())
      return makeError(path + ": an index along dimension '" + read.extraIndex.begin()->first +
                       "' asked for, but a GRIB file has no such dimensions (ensemble members: member)");
    return grib::describeGribFile(path, variable);
  }
  auto opened = io::NetcdfFile::open(path);
  if (!opened) return opened.forwardError();
  const io::NetcdfFile& f = *opened;
  const grid::FileKind kind = grid::fileKind(f);
  // WRF's diagnostics (readGridVolume): described on the field they are made from, by their name.
  if (kind.wrf && (variable == "tk" || variable == "z") && !f.findVariable(f.root(), variable)) {
    GridReadOptions base = read;
    base.variable = variable == "tk" ? "T" : "PH";
    auto info = describeGridFile(path, base);
    if (!info) return info.forwardError();
    info->variable = "/" + variable;
    return info;
  }
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
  auto layout = grid::layoutFor(f, kind, variable, &name, read.allowSingleLevel);
  if (!layout) return layout.forwardError();
  const grid::GridLayout& l = *layout;
  info.variable = name;
  info.curvilinear = l.curvilinear;
  info.nx = l.nx;
  info.ny = l.ny;
  info.nz = l.vertical.fileLevels;
  info.xDimension = grid::dimensionName(l.var.groupId, l.xDim);
  info.yDimension = grid::dimensionName(l.var.groupId, l.yDim);
  info.zDimension = l.zDim >= 0 ? grid::dimensionName(l.var.groupId, l.zDim) : "";
  info.timeDimension = l.time.dimId >= 0 ? grid::dimensionName(l.var.groupId, l.time.dimId) : "";
  std::map<int, std::size_t> extraIndex;
  auto extras = grid::resolveExtraDimensions(f, l, read, &extraIndex);
  if (!extras) return extras.forwardError();
  info.extraDimensions = *extras;

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

  // Extent from the full coordinates (curvilinear ones at the step `read` names: a moving nest's
  // change with time); heights from a sample of at most ~64 x 64 columns.
  auto step = grid::resolveTime(f, l, read, *times);
  if (!step) return step.forwardError();
  info.describedTimeIndex = *step;
  info.coordinatesVaryWithTime =
      l.curvilinear && l.time.dimId >= 0 &&
      (std::find(l.lat.dimIds.begin(), l.lat.dimIds.end(), l.time.dimId) != l.lat.dimIds.end() ||
       std::find(l.lon.dimIds.begin(), l.lon.dimIds.end(), l.time.dimId) != l.lon.dimIds.end());
  GridCrop all;
  auto full = l.curvilinear ? grid::curvilinear(f, l, *step, all, 1) : grid::rectilinear(f, l, all, 1);
  if (!full) return full.forwardError();
  grid::describeExtent(*full, l.curvilinear, info);
  const std::size_t stride = std::max<std::size_t>(1, (std::max(l.nx, l.ny) + 63) / 64);
  info.heightColumnStride = stride;
  auto sample = l.curvilinear ? grid::curvilinear(f, l, *step, all, stride) : grid::rectilinear(f, l, all, stride);
  if (!sample) return sample.forwardError();
  auto lv = grid::levelsOf(f, l);
  if (!lv) return lv.forwardError();
  auto levels = grid::levelPicks(f, l, *lv, all);
  if (!levels) return levels.forwardError();
  grid::Selection sel{*step, *levels, &*sample, extraIndex, {}};
  auto heights = grid::computeHeights(f, l, *lv, sel, true);
  if (!heights) return heights.forwardError();
  if (auto st = grid::checkHeights(f, *heights, sel, sample->rows.size() * sample->cols.size()); !st)
    return st.forwardError();
  grid::setHeightFields(l, *heights, info);
  const auto [mn, mx] = std::minmax_element(heights->h.begin(), heights->h.end());
  info.heightMinMeters = *mn;
  info.heightMaxMeters = *mx;
  info.bytesRead = f.dataBytesRead();
  return info;
}

nlohmann::ordered_json grid::verticalJson(const GridFileInfo& g) {
  nlohmann::ordered_json levels = nlohmann::ordered_json::array();
  for (double v : g.levelValues) levels.push_back(finiteOrNull(v));
  return {{"kind", toString(g.verticalKind)},
          {"variable", g.verticalVariable},
          {"height_source", toString(g.heightSource)},
          {"approximate", g.approximateHeights},
          {"note", g.heightNote},
          {"levels_bottom_first", std::move(levels)},
          {"level_units", g.levelUnits},
          {"height_datum", "WGS84 ellipsoid"},
          {"height_min_m", finiteOrNull(g.heightMinMeters)},
          {"height_max_m", finiteOrNull(g.heightMaxMeters)},
          {"height_range_column_stride", g.heightColumnStride}};
}

std::string describeGridJson(const GridFileInfo& g) {
  if (g.format.rfind("GRIB", 0) == 0) return grib::describeGribJson(g);
  nlohmann::ordered_json j;
  j["kind"] = "grid";
  j["format"] = g.format;
  j["file"] = g.path;
  j["conventions"] = g.conventions;
  nlohmann::ordered_json dims = nlohmann::ordered_json::array();
  for (const auto& d : g.dimensions)
    dims.push_back({{"name", d.name}, {"length", d.length}, {"unlimited", d.unlimited}});
  j["dimensions"] = std::move(dims);
  nlohmann::ordered_json vars = nlohmann::ordered_json::array();
  for (const auto& v : g.variables)
    vars.push_back({{"name", v.name},
                    {"dimensions", v.dimensions},
                    {"shape", v.shape},
                    {"type", v.type},
                    {"units", v.units},
                    {"standard_name", v.standardName},
                    {"long_name", v.longName},
                    {"packed", v.packed},
                    {"on_grid", v.onGrid}});
  j["variables"] = std::move(vars);
  j["variable"] = g.variable;
  nlohmann::ordered_json extras = nlohmann::ordered_json::array();
  for (const auto& e : g.extraDimensions)
    extras.push_back({{"name", e.name},
                      {"length", e.length},
                      {"index", e.index},
                      {"value", finiteOrNull(e.value)},
                      {"units", e.units},
                      {"ensemble", e.ensemble}});
  j["extra_dimensions"] = std::move(extras);
  j["grid"] = {{"horizontal", g.curvilinear ? "curvilinear" : "rectilinear"},
               {"nx", g.nx},
               {"ny", g.ny},
               {"nz", g.nz},
               {"x_dimension", g.xDimension},
               {"y_dimension", g.yDimension},
               {"z_dimension", g.zDimension},
               {"south_deg", g.southDeg},
               {"north_deg", g.northDeg},
               {"west_deg", g.westDeg},
               {"east_deg", g.eastDeg},
               {"wraps_longitude", g.wrapsLongitude},
               {"mean_spacing_km", g.meanSpacingKm}};
  j["vertical"] = grid::verticalJson(g);
  j["time"] = {{"dimension", g.timeDimension},
               {"variable", g.timeVariable},
               {"units", g.timeUnits},
               {"calendar", g.calendar},
               {"values", g.times}};
  j["bytes_read"] = g.bytesRead;
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string describeGridText(const GridFileInfo& g) {
  if (g.format.rfind("GRIB", 0) == 0) return grib::describeGribText(g);
  std::ostringstream os;
  os << "file:       " << g.path << "\n";
  os << "format:     forecast grid, " << g.format << (g.conventions.empty() ? "" : ", " + g.conventions) << "\n";
  os << "variable:   " << g.variable << "\n";
  for (const auto& e : g.extraDimensions) {
    // One line per dimension read at one index: its size, what it is, the index described.
    os << "index dim:  " << e.name << " (" << e.length << (e.ensemble ? " ensemble members" : " values")
       << "): described at index " << e.index;
    if (std::isfinite(e.value))
      os << " (" << grid::num(e.value, e.value == std::floor(e.value) ? 0 : 3) << (e.units.empty() ? "" : " " + e.units)
         << ")";
    os << "; choose with " << (e.ensemble ? "--member N or " : "") << "--grid-index " << e.name << "=I\n";
  }
  os << "grid:       "
     << (g.curvilinear ? "curvilinear (2-D latitude/longitude)" : "rectilinear (1-D latitude/longitude)") << ", "
     << g.nx << " x " << g.ny << " columns (" << g.xDimension << " x " << g.yDimension << "), " << g.nz << " levels ("
     << g.zDimension << "), ~" << grid::num(g.meanSpacingKm, 1) << " km apart\n";
  os << "extent:     latitude " << grid::num(g.southDeg, 3) << " .. " << grid::num(g.northDeg, 3) << " deg, longitude "
     << grid::num(g.westDeg, 3) << " .. " << grid::num(g.eastDeg, 3) << " deg"
     << (g.wrapsLongitude ? " (global: wraps)" : "")
     << (g.coordinatesVaryWithTime ? " at time step " + std::to_string(g.describedTimeIndex) +
                                         " (the latitudes and longitudes change with time: a moving domain)"
                                   : std::string())
     << "\n";
  os << "vertical:   " << toString(g.verticalKind) << " (" << g.verticalVariable << "), heights from "
     << toString(g.heightSource) << (g.approximateHeights ? ", APPROXIMATE" : "") << "\n";
  os << "            " << g.heightNote << "\n";
  if (!g.levelValues.empty()) {
    os << "levels:     bottom first:";
    for (double v : g.levelValues) os << " " << grid::num(v, std::fabs(v) < 10 ? 4 : 1);
    os << " " << g.levelUnits << "\n";
  }
  os << "heights:    " << grid::num(g.heightMinMeters, 1) << " .. " << grid::num(g.heightMaxMeters, 1)
     << " m above the WGS84 ellipsoid (first time step"
     << (g.heightColumnStride > 1 ? ", sampled every " + std::to_string(g.heightColumnStride) + " rows and columns"
                                  : "")
     << ")" << (g.approximateHeights ? " APPROXIMATE" : "") << "\n";
  if (g.times.empty()) {
    os << "times:      (no time dimension)\n";
  } else {
    os << "times:      " << g.times.size() << " (" << g.timeVariable << (g.timeUnits.empty() ? "" : ": " + g.timeUnits)
       << (g.calendar.empty() ? "" : ", calendar " + g.calendar)
       << "): " << (g.times.front().empty() ? "?" : g.times.front());
    if (g.times.size() > 1) os << " .. " << (g.times.back().empty() ? "?" : g.times.back());
    os << "\n";
  }
  os << "dimensions:";
  for (const auto& d : g.dimensions) os << " " << d.name << "=" << d.length << (d.unlimited ? " (unlimited)" : "");
  os << "\n";
  os << "variables (* = 3-D on the grid):\n";
  for (const auto& v : g.variables) {
    os << (v.onGrid ? "  * " : "    ") << v.name << " (" << joinDims(v) << ") " << v.type;
    if (!v.units.empty()) os << " [" << v.units << "]";
    if (v.packed) os << " packed";
    if (!v.longName.empty()) os << "  " << v.longName;
    os << "\n";
  }
  // WRF's diagnostics made from its perturbation fields (readGridVolume), where the file has none.
  if (g.format.rfind("WRF", 0) == 0) {
    auto has = [&](const std::string& name) {
      return std::any_of(g.variables.begin(), g.variables.end(),
                         [&](const GridVariableInfo& v) { return v.name == "/" + name; });
    };
    if (!has("tk") && has("T") && has("P") && has("PB")) os << "  * tk  (made from T, P, PB) [K]  temperature\n";
    if (!has("z") && has("PH") && has("PHB"))
      os << "  * z  (made from PH, PHB) [m2 s-2]  geopotential at mass levels\n";
  }
  os << "read:       " << g.bytesRead << " bytes of variable data\n";
  return os.str();
}

}  // namespace atmoglobe::volume
