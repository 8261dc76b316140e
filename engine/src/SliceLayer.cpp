// Slices on the globe: the scene's description (SliceLayer.h).
#include <atmoglobe/engine/SliceLayer.h>

#include <nlohmann/json.hpp>

#include "SceneJsonFields.h"

#include <cmath>
#include <filesystem>

namespace atmoglobe::engine {
namespace {

std::string resolve(const std::string& path, const std::string& baseDir, const std::string& dataDir) {
  if (path.rfind("@data", 0) == 0) return dataDir + path.substr(5);
  const std::filesystem::path p(path);
  if (p.is_absolute() || baseDir.empty()) return path;
  return (std::filesystem::path(baseDir) / p).string();
}

}  // namespace

Status validateSliceLayer(const SliceLayerDescription& s, const std::string& where) {
  if (s.source.path.empty()) return makeError(where + ": needs a \"radar\" or a \"grid\" file");
  if (s.request.cappi && !std::isfinite(s.request.heightMeters)) return makeError(where + ": height must be finite");
  if (!s.request.cappi && s.request.path.size() < 2) {
    return makeError(where + ": a cross-section path needs at least two points");
  }
  if (!(s.opacity >= 0.0 && s.opacity <= 1.0)) return makeError(where + ": opacity must be in 0..1");
  if (s.resolutionPx < 64 || s.resolutionPx > 4096) return makeError(where + ": resolution_px must be in 64..4096");
  if (s.range && !(s.range->minValue < s.range->maxValue))
    return makeError(where + ": range must be [min, max], min < max");
  return Ok{};
}

Status parseSliceLayer(const scenejson::Object& r, const std::string& baseDir, const std::string& dataDir,
                       SliceLayerDescription& d) {
  if (auto st =
          r.checkObject({"radar", "grid", "field", "variable", "time", "member", "ensemble", "index", "height_m",
                         "path", "box", "heights_m", "datum", "colors", "range", "opacity", "resolution_px", "geoid"});
      !st)
    return st;
  for (auto [key, kind] : {std::pair{"radar", volume::SliceSourceOptions::Kind::Radar},
                           std::pair{"grid", volume::SliceSourceOptions::Kind::Grid}}) {
    if (!r.has(key)) continue;
    if (!d.source.path.empty()) return r.error("give \"radar\" or \"grid\", not both");
    std::string path;
    if (auto st = r.string(key, path); !st) return st;
    if (path.empty()) return r.error(key, "empty path");
    d.source.kind = kind;
    d.source.path = resolve(path, baseDir, dataDir);
  }
  if (d.source.path.empty()) return r.error("needs a \"radar\" or a \"grid\" file");
  for (auto [key, target] : {std::pair<const char*, std::string*>{"field", &d.source.field},
                             {"variable", &d.source.field},
                             {"time", &d.source.time},
                             {"colors", &d.colors}}) {
    if (auto st = r.string(key, *target); !st) return st;
  }
  if (r.has("member")) {
    if (d.source.kind != volume::SliceSourceOptions::Kind::Grid) return r.error("member", "is for a \"grid\"");
    int member = -1;
    if (auto st = r.integer("member", member, 0, 1000000); !st) return st;
    d.source.member = member;
  }
  if (r.has("ensemble")) {
    if (d.source.kind != volume::SliceSourceOptions::Kind::Grid) return r.error("ensemble", "is for a \"grid\"");
    std::string text;
    if (auto st = r.string("ensemble", text); !st) return st;
    auto stat = volume::parseEnsembleStatistic(text);
    if (!stat) return r.error("ensemble", stat.error());
    if (d.source.member >= 0) return r.error("ensemble", "combines every member: not with \"member\"");
    d.source.ensemble = *stat;
  }
  if (r.has("index")) {
    if (d.source.kind != volume::SliceSourceOptions::Kind::Grid) return r.error("index", "is for a \"grid\"");
    if (auto st = r.indices("index", d.source.gridIndex, 1000000000); !st) return st;
  }
  if (d.colors.size() > 4 && d.colors.substr(d.colors.size() - 4) == ".pal")
    d.colors = resolve(d.colors, baseDir, dataDir);
  if (r.has("height_m") == r.has("path"))
    return r.error("give \"height_m\" (a CAPPI) or \"path\" (a cross-section), one of them");
  if (r.has("height_m")) {
    d.request.cappi = true;
    if (auto st = r.number("height_m", d.request.heightMeters, -1e4, 1e5, "m"); !st) return st;
  } else {
    d.request.cappi = false;
    if (auto st = r.array("path"); !st) return st;
    const nlohmann::json& points = r.value().at("path");
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::string at = r.where("path") + std::string("/").append(std::to_string(i));
      const nlohmann::json& p = points[i];
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        return makeError(at + ": expected [lat, lon] (deg), got " +
                         (p.is_array() ? std::to_string(p.size()) + " elements" : scenejson::typeName(p)));
      const double lat = p[0].get<double>(), lon = p[1].get<double>();
      if (!(std::isfinite(lat) && lat >= -90.0 && lat <= 90.0 && std::isfinite(lon) && lon >= -360.0 && lon <= 360.0))
        return makeError(at + ": latitude must be in -90..90 and longitude in -360..360 deg");
      d.request.path.push_back({lat, lon});
    }
  }
  std::vector<double> v;
  if (auto st = r.numbers("box", v, 4, 4, "[south, north, west, east] (deg)", -360.0, 360.0); !st) return st;
  if (r.has("box")) {
    volume::LatLonBox b{v[0], v[1], v[2], v[3]};
    if (b.eastDeg < b.westDeg) b.eastDeg += 360.0;
    if (auto st = volume::validateBox(b, r.where("box")); !st) return st;
    d.request.box = b;
  }
  v.clear();
  if (auto st = r.numbers("heights_m", v, 2, 2, "[bottom, top] (m)"); !st) return st;
  if (r.has("heights_m")) {
    d.request.bottomMeters = v[0];
    d.request.topMeters = v[1];
  }
  v.clear();
  if (auto st = r.numbers("range", v, 2, 2, "[min, max] (field units)"); !st) return st;
  if (r.has("range")) d.range = volume::ValueRange{v[0], v[1]};
  std::string datum = d.request.datum == volume::SliceHeightDatum::SeaLevel ? "msl" : "ellipsoid";
  if (auto st = r.choice("datum", datum, {"msl", "ellipsoid"}); !st) return st;
  d.request.datum = datum == "msl" ? volume::SliceHeightDatum::SeaLevel : volume::SliceHeightDatum::Ellipsoid;
  if (auto st = r.number("opacity", d.opacity, 0.0, 1.0); !st) return st;
  if (auto st = r.integer("resolution_px", d.resolutionPx, 64, 4096, "px"); !st) return st;
  if (auto st = r.boolean("geoid", d.source.useGeoid); !st) return st;
  return validateSliceLayer(d, r.where());
}

Result<std::vector<SliceLayerDescription>> parseSliceLayersJson(std::string_view text, const std::string& where,
                                                                const std::string& baseDir,
                                                                const std::string& dataDir) {
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text.begin(), text.end());
  } catch (
      const nlohmann::json::exception& e) {  // parse_error, and out_of_range for numbers beyond double (fuzz_scene)
    return makeError(where + ": not valid JSON: " + e.what());
  }
  if (!root.is_array()) return makeError(where + ": " + scenejson::expected("an array", root));
  std::vector<SliceLayerDescription> out;
  for (std::size_t i = 0; i < root.size(); ++i) {
    SliceLayerDescription d;
    if (auto st = parseSliceLayer(scenejson::Object(root[i], where, std::string("/").append(std::to_string(i))),
                                  baseDir, dataDir, d);
        !st)
      return st.forwardError();
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace atmoglobe::engine
