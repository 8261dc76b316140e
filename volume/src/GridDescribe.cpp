// `atmoglobe info` for forecast grids: GridFileInfo as JSON and as text.
#include <atmoglobe/volume/GridReader.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace atmoglobe::volume {

namespace {

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

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

std::string describeGridJson(const GridFileInfo& g) {
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
  nlohmann::ordered_json levels = nlohmann::ordered_json::array();
  for (double v : g.levelValues) levels.push_back(finiteOrNull(v));
  j["vertical"] = {{"kind", toString(g.verticalKind)},
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
  j["time"] = {{"dimension", g.timeDimension},
               {"variable", g.timeVariable},
               {"units", g.timeUnits},
               {"calendar", g.calendar},
               {"values", g.times}};
  j["bytes_read"] = g.bytesRead;
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string describeGridText(const GridFileInfo& g) {
  std::ostringstream os;
  os << "file:       " << g.path << "\n";
  os << "format:     forecast grid, " << g.format << (g.conventions.empty() ? "" : ", " + g.conventions) << "\n";
  os << "variable:   " << g.variable << "\n";
  os << "grid:       "
     << (g.curvilinear ? "curvilinear (2-D latitude/longitude)" : "rectilinear (1-D latitude/longitude)") << ", "
     << g.nx << " x " << g.ny << " columns (" << g.xDimension << " x " << g.yDimension << "), " << g.nz << " levels ("
     << g.zDimension << "), ~" << fixed(g.meanSpacingKm, 1) << " km apart\n";
  os << "extent:     latitude " << fixed(g.southDeg, 3) << " .. " << fixed(g.northDeg, 3) << " deg, longitude "
     << fixed(g.westDeg, 3) << " .. " << fixed(g.eastDeg, 3) << " deg" << (g.wrapsLongitude ? " (global: wraps)" : "")
     << "\n";
  os << "vertical:   " << toString(g.verticalKind) << " (" << g.verticalVariable << "), heights from "
     << toString(g.heightSource) << (g.approximateHeights ? ", APPROXIMATE" : "") << "\n";
  os << "            " << g.heightNote << "\n";
  if (!g.levelValues.empty()) {
    os << "levels:     bottom first:";
    for (double v : g.levelValues) os << " " << fixed(v, std::fabs(v) < 10 ? 4 : 1);
    os << " " << g.levelUnits << "\n";
  }
  os << "heights:    " << fixed(g.heightMinMeters, 1) << " .. " << fixed(g.heightMaxMeters, 1)
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
  os << "read:       " << g.bytesRead << " bytes of variable data\n";
  return os.str();
}

}  // namespace atmoglobe::volume
