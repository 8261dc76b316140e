// A 2-D field layer's description and read (SurfaceLayer.h).
#include <atmoglobe/engine/SurfaceLayer.h>
#include <atmoglobe/volume/GridReader.h>

#include <atmoglobe/map/Contours.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace atmoglobe::engine {

Status validateSurfaceLayer(const SurfaceLayerDescription& d, const std::string& where) {
  if (d.path.empty()) return makeError(where + ": empty path");
  if (!(d.opacity >= 0.0 && d.opacity <= 1.0)) return makeError(where + ": opacity must be in 0..1");
  if (d.pressureHpa && !(*d.pressureHpa > 0.0 && *d.pressureHpa <= 1100.0))
    return makeError(where + ": pressure level must be in (0, 1100] hPa");
  if (d.valueRange &&
      !(std::isfinite(d.valueRange->x) && std::isfinite(d.valueRange->y) && d.valueRange->x < d.valueRange->y))
    return makeError(where + ": range must be two finite numbers, the first below the second");
  if (d.contourInterval && !(*d.contourInterval > 0.0 && std::isfinite(*d.contourInterval)))
    return makeError(where + ": contour interval must be a finite number > 0");
  for (double v : d.contourValues)
    if (!std::isfinite(v)) return makeError(where + ": contour values must be finite");
  if (d.level && *d.level < 0) return makeError(where + ": level must be 0 or more (0 = the lowest)");
  if (d.level && d.pressureHpa) return makeError(where + ": give a pressure level or a level, not both");
  if (d.contourInterval && !d.contourValues.empty())
    return makeError(where + ": give a contour interval or contour values, not both");
  if (!d.fill && !d.contourInterval && d.contourValues.empty() && d.wind.empty())
    return makeError(where + ": nothing to draw: no fill, no contours and no wind");
  if (!d.wind.empty() && d.wind != "auto") {
    const auto comma = d.wind.find(',');
    if (comma == std::string::npos || comma == 0 || comma + 1 == d.wind.size() ||
        d.wind.find(',', comma + 1) != std::string::npos)
      return makeError(where + ": wind \"" + d.wind + "\": expected auto or two variables U,V");
  }
  if (!(d.contourWidthPx >= 0.5f && d.contourWidthPx <= 16.0f))
    return makeError(where + ": contour width must be in 0.5..16 px");
  if (d.member >= 0 && !d.ensemble.empty())
    return makeError(where + ": give a member or an ensemble statistic, not both");
  if (!d.ensemble.empty())
    if (auto e = volume::parseEnsembleStatistic(d.ensemble); !e) return makeError(where + ": " + e.error());
  return Ok{};
}

namespace {
std::string lastPart(const std::string& name) {
  const auto slash = name.rfind('/');
  std::string n = slash == std::string::npos ? name : name.substr(slash + 1);
  return n.substr(0, n.find(':'));
}
}  // namespace

Result<std::pair<std::string, std::string>> windVariables(const std::string& path, const std::string& wind,
                                                          bool isobaric) {
  if (wind != "auto") {
    const auto comma = wind.find(',');
    if (comma == std::string::npos) return makeError(path + ": wind \"" + wind + "\": expected auto or U,V");
    return std::pair{wind.substr(0, comma), wind.substr(comma + 1)};
  }
  volume::GridReadOptions read;
  read.allowSingleLevel = true;
  auto info = volume::describeGridFile(path, read);
  if (!info) return makeError(info.error() + " (name the wind components: --surface-wind U,V)");
  const std::vector<volume::GridVariableInfo>& vars = info->variables;
  // GRIB keys carry their level type: on a pressure surface the isobaric pair, else another.
  auto suits = [&](const volume::GridVariableInfo& v) {
    if (!v.notReadable.empty()) return false;
    if (v.levelType.empty()) return true;
    return isobaric == (v.levelType.rfind("isobaric", 0) == 0);
  };
  auto find = [&](auto match) -> const volume::GridVariableInfo* {
    for (const auto& v : vars)
      if (suits(v) && match(v)) return &v;
    return nullptr;
  };
  // (Plain pairs, not structured bindings: clang cannot capture those in the lambdas below.)
  for (const auto& byStandardName :
       {std::pair{"eastward_wind", "northward_wind"}, std::pair{"grid_eastward_wind", "grid_northward_wind"},
        std::pair{"x_wind", "y_wind"}}) {
    const std::string us = byStandardName.first, vs = byStandardName.second;
    const auto* u = find([&](const auto& v) { return v.standardName == us; });
    const auto* v = find([&](const auto& x) { return x.standardName == vs; });
    if (u && v) return std::pair{u->name, v->name};
  }
  for (const auto& byName : {std::pair{"u", "v"}, std::pair{"10u", "10v"}, std::pair{"100u", "100v"},
                             std::pair{"U", "V"}, std::pair{"U10", "V10"}, std::pair{"u10", "v10"},
                             std::pair{"ua", "va"}, std::pair{"uwnd", "vwnd"}, std::pair{"UGRD", "VGRD"}}) {
    const std::string un = byName.first, vn = byName.second;
    const auto* u = find([&](const auto& v) { return lastPart(v.name) == un; });
    const auto* v = find([&](const auto& x) { return lastPart(x.name) == vn; });
    if (u && v) return std::pair{u->name, v->name};
  }
  return makeError(path +
                   ": no wind components found (by standard name eastward_wind / northward_wind, x_wind / "
                   "y_wind, or by name u/v, 10u/10v, U/V, U10/V10, ua/va" +
                   std::string(isobaric ? " on pressure levels" : "") + "); name them: --surface-wind U,V");
}

Result<SurfaceData> readSurfaceData(const SurfaceLayerDescription& d) {
  volume::GridReadOptions read;
  read.member = d.member;
  read.useGeoid = d.useGeoid;
  read.allowSingleLevel = true;  // surface and single-level fields are what a map shows
  read.keepPressure = d.pressureHpa.has_value();
  if (!d.ensemble.empty()) {
    auto e = volume::parseEnsembleStatistic(d.ensemble);
    if (!e) return makeError(d.path + ": " + e.error());
    read.ensemble = *e;
  }
  if (!d.time.empty())
    if (Status st = volume::selectGridTime(d.time, read); !st) return makeError(d.path + ": " + st.error());
  std::optional<double> pressurePa;
  if (d.pressureHpa) pressurePa = *d.pressureHpa * 100.0;
  auto fieldOf = [&](const std::string& variable) -> Result<volume::SurfaceField> {
    volume::GridReadOptions r = read;
    r.variable = variable;
    auto grid = volume::readGridVolume(d.path, r);
    if (!grid) return grid.forwardError();
    std::optional<std::size_t> level;
    if (d.level) level = static_cast<std::size_t>(*d.level);
    return volume::surfaceFieldOf(std::move(*grid), pressurePa, level);
  };
  SurfaceData out;
  std::optional<volume::SurfaceField> u;
  if (!d.wind.empty()) {
    auto names = windVariables(d.path, d.wind, pressurePa.has_value());
    if (!names) return names.forwardError();
    auto fu = fieldOf(names->first);
    if (!fu) return fu.forwardError();
    auto fv = fieldOf(names->second);
    if (!fv) return fv.forwardError();
    auto w = volume::earthRelativeWind(fu->grid, fv->grid);
    if (!w) return w.forwardError();
    out.wind = std::move(*w);
    out.windNote = "wind: " + lastPart(names->first) + ", " + lastPart(names->second) +
                   (fu->grid.vectorsRelativeToGrid ? " (along the grid's axes, turned east and north)" : "");
    out.windGrid = fu->grid;
    u = std::move(*fu);
  }
  if (d.variable.empty() && u) {
    // The fill of a wind layer without a variable: the speed.
    volume::SurfaceField speed = std::move(*u);
    for (std::size_t c = 0; c < speed.grid.values.size(); ++c)
      speed.grid.values[c] = std::hypot(out.wind.eastMps[c], out.wind.northMps[c]);
    volume::setValueRange(speed.grid);
    speed.name = "wind speed" + (pressurePa ? " at " + map::contourLabel(*pressurePa / 100.0) + " hPa"
                                 : d.level  ? " at level " + std::to_string(*d.level)
                                            : std::string());
    speed.grid.standardName = "wind_speed";
    out.field = std::move(speed);
    return out;
  }
  auto field = fieldOf(d.variable);
  if (!field) return field.forwardError();
  out.field = std::move(*field);
  if (read.ensemble) {
    // Each member on the same surface, for the readout (the statistic's own values are the
    // reader's, computed value by value before the surface is cut).
    volume::GridReadOptions which = read;
    which.ensemble.reset();
    which.variable = d.variable;
    auto members = volume::ensembleMemberSelections(d.path, which);
    if (!members) return members.forwardError();
    for (const volume::EnsembleMemberSelection& m : *members) {
      volume::GridReadOptions r = which;
      r.member = m.member;
      for (const auto& [dimension, index] : m.extraIndex) r.extraIndex[dimension] = index;
      auto grid = volume::readGridVolume(d.path, r);
      if (!grid) return grid.forwardError();
      // The member as the statistic lists it: GRIB's number, else the ensemble coordinate's value
      // (its index where it has none).
      const long label = volume::memberLabel(*grid, static_cast<long>(out.members.size()));
      std::optional<std::size_t> level;
      if (d.level) level = static_cast<std::size_t>(*d.level);
      auto one = volume::surfaceFieldOf(std::move(*grid), pressurePa, level);
      if (!one) return one.forwardError();
      out.members.emplace_back(label, std::move(*one));
    }
  }
  return out;
}

bool sameSurfaceData(const SurfaceLayerDescription& a, const SurfaceLayerDescription& b) {
  return a.path == b.path && a.variable == b.variable && a.time == b.time && a.member == b.member &&
         a.ensemble == b.ensemble && a.pressureHpa == b.pressureHpa && a.level == b.level && a.wind == b.wind &&
         a.useGeoid == b.useGeoid;
}

}  // namespace atmoglobe::engine
