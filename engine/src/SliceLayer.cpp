// Slices on the globe: the scene's description (SliceLayer.h).
#include <atmoglobe/engine/SliceLayer.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <set>

namespace atmoglobe::engine {
namespace {

using json = nlohmann::json;

std::string resolve(const std::string& path, const std::string& baseDir, const std::string& dataDir) {
  if (path.rfind("@data", 0) == 0) return dataDir + path.substr(5);
  const std::filesystem::path p(path);
  if (p.is_absolute() || baseDir.empty()) return path;
  return (std::filesystem::path(baseDir) / p).string();
}

// [a, b, ...] of `count` finite numbers.
Result<std::vector<double>> numbers(const json& v, std::size_t count, const std::string& what) {
  if (!v.is_array() || v.size() != count)
    return makeError(what + " must be an array of " + std::to_string(count) + " numbers");
  std::vector<double> out;
  for (const json& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) return makeError(what + " must hold finite numbers");
    out.push_back(x.get<double>());
  }
  return out;
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

Result<std::vector<SliceLayerDescription>> parseSliceLayersJson(std::string_view text, const std::string& where,
                                                                const std::string& baseDir,
                                                                const std::string& dataDir) {
  json root;
  try {
    root = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers beyond double (fuzz_scene)
    return makeError(where + ": not valid JSON: " + e.what());
  }
  if (!root.is_array()) return makeError(where + " must be an array");
  std::vector<SliceLayerDescription> out;
  int index = 0;
  for (const json& r : root) {
    const std::string at = where + "[" + std::to_string(index++) + "]";
    if (!r.is_object()) return makeError(at + ": expected a JSON object");
    static const std::set<std::string> kKeys{"radar",    "grid",  "field",   "variable",      "time",
                                             "height_m", "path",  "box",     "heights_m",     "datum",
                                             "colors",   "range", "opacity", "resolution_px", "geoid"};
    for (auto it = r.begin(); it != r.end(); ++it) {
      if (!kKeys.count(it.key())) return makeError(at + ": unknown key \"" + it.key() + "\"");
    }
    SliceLayerDescription d;
    for (auto [key, kind] : {std::pair{"radar", volume::SliceSourceOptions::Kind::Radar},
                             std::pair{"grid", volume::SliceSourceOptions::Kind::Grid}}) {
      if (!r.contains(key)) continue;
      if (!r[key].is_string()) return makeError(at + ": \"" + key + "\" must be a file name");
      if (!d.source.path.empty()) return makeError(at + ": give \"radar\" or \"grid\", not both");
      d.source.kind = kind;
      d.source.path = resolve(r[key].get<std::string>(), baseDir, dataDir);
    }
    for (auto [key, target] : {std::pair<const char*, std::string*>{"field", &d.source.field},
                               {"variable", &d.source.field},
                               {"time", &d.source.time},
                               {"colors", &d.colors}}) {
      if (!r.contains(key)) continue;
      if (!r[key].is_string()) return makeError(at + ": \"" + key + "\" must be a string");
      *target = r[key].get<std::string>();
    }
    if (d.colors.size() > 4 && d.colors.substr(d.colors.size() - 4) == ".pal")
      d.colors = resolve(d.colors, baseDir, dataDir);
    if (r.contains("height_m") == r.contains("path")) {
      return makeError(at + ": give \"height_m\" (a CAPPI) or \"path\" (a cross-section), one of them");
    }
    if (r.contains("height_m")) {
      if (!r["height_m"].is_number()) return makeError(at + ": \"height_m\" must be a number");
      d.request.cappi = true;
      d.request.heightMeters = r["height_m"].get<double>();
    } else {
      d.request.cappi = false;
      if (!r["path"].is_array()) return makeError(at + ": \"path\" must be an array of [lat, lon] points");
      for (const json& p : r["path"]) {
        auto v = numbers(p, 2, at + ": each \"path\" point");
        if (!v) return v.forwardError();
        d.request.path.push_back({(*v)[0], (*v)[1]});
      }
    }
    if (r.contains("box")) {
      auto v = numbers(r["box"], 4, at + ": \"box\" ([south, north, west, east])");
      if (!v) return v.forwardError();
      volume::LatLonBox b{(*v)[0], (*v)[1], (*v)[2], (*v)[3]};
      if (b.eastDeg < b.westDeg) b.eastDeg += 360.0;
      if (auto st = volume::validateBox(b, at + ": box"); !st) return st.forwardError();
      d.request.box = b;
    }
    if (r.contains("heights_m")) {
      auto v = numbers(r["heights_m"], 2, at + ": \"heights_m\" ([bottom, top])");
      if (!v) return v.forwardError();
      d.request.bottomMeters = (*v)[0];
      d.request.topMeters = (*v)[1];
    }
    if (r.contains("range")) {
      auto v = numbers(r["range"], 2, at + ": \"range\" ([min, max])");
      if (!v) return v.forwardError();
      d.range = volume::ValueRange{(*v)[0], (*v)[1]};
    }
    if (r.contains("datum")) {
      const std::string datum = r["datum"].is_string() ? r["datum"].get<std::string>() : "";
      if (datum != "msl" && datum != "ellipsoid") return makeError(at + ": \"datum\" must be \"msl\" or \"ellipsoid\"");
      d.request.datum = datum == "msl" ? volume::SliceHeightDatum::SeaLevel : volume::SliceHeightDatum::Ellipsoid;
    }
    if (r.contains("opacity")) {
      if (!r["opacity"].is_number()) return makeError(at + ": \"opacity\" must be a number");
      d.opacity = r["opacity"].get<double>();
    }
    if (r.contains("resolution_px")) {
      if (!r["resolution_px"].is_number_integer()) return makeError(at + ": \"resolution_px\" must be an integer");
      d.resolutionPx = r["resolution_px"].get<int>();
    }
    if (r.contains("geoid")) {
      if (!r["geoid"].is_boolean()) return makeError(at + ": \"geoid\" must be true or false");
      d.source.useGeoid = r["geoid"].get<bool>();
    }
    if (auto st = validateSliceLayer(d, at); !st) return st.forwardError();
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace atmoglobe::engine
