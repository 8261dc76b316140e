#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace atmoglobe::engine {

namespace {

using json = nlohmann::json;

Status checkKeys(const json& object, const std::set<std::string>& allowed, const std::string& where) {
  if (!object.is_object()) return makeError(where + ": expected a JSON object");
  for (auto it = object.begin(); it != object.end(); ++it) {
    if (!allowed.count(it.key())) return makeError(where + ": unknown key \"" + it.key() + "\"");
  }
  return Ok{};
}

Result<double> number(const json& object, const char* key, double fallback, const std::string& where) {
  if (!object.contains(key)) return fallback;
  const json& v = object.at(key);
  if (!v.is_number()) return makeError(where + ": \"" + key + "\" must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) return makeError(where + ": \"" + key + "\" must be finite");
  return d;
}

std::string resolvePath(const std::string& path, const std::string& baseDir, const std::string& dataDir) {
  if (path.rfind("@data", 0) == 0) return dataDir + path.substr(5);
  std::filesystem::path p(path);
  if (p.is_absolute() || baseDir.empty()) return path;
  return (std::filesystem::path(baseDir) / p).string();
}

}  // namespace

namespace {
// "range", "opacity", "crop", "crop_heights_m" of a radar or grid layer.
Status parseLayerSettings(const json& r, const std::string& where, VolumeLayerSettings& out) {
  auto numbers = [&](const char* key, std::size_t lo, std::size_t hi, const char* form) -> Result<std::vector<double>> {
    const json& a = r[key];
    if (!a.is_array() || a.size() < lo || a.size() > hi) return makeError(where + ": \"" + key + "\" must be " + form);
    std::vector<double> v;
    for (const json& x : a) {
      if (!x.is_number()) return makeError(where + ": \"" + key + "\" must be " + form);
      v.push_back(x.get<double>());
    }
    return v;
  };
  if (r.contains("range")) {
    auto v = numbers("range", 2, 2, "[min, max] in the field's units");
    if (!v) return v.forwardError();
    out.valueRange = glm::dvec2((*v)[0], (*v)[1]);
  }
  if (r.contains("opacity")) {
    auto v = numbers("opacity", 2, 4, "[zero, full] or [zero, full, max] or [zero, full, max, per_m]");
    if (!v) return v.forwardError();
    out.opacity = *v;
  }
  if (r.contains("crop")) {
    auto v = numbers("crop", 4, 4, "[south, north, west, east] in degrees");
    if (!v) return v.forwardError();
    out.crop.southDeg = (*v)[0];
    out.crop.northDeg = (*v)[1];
    out.crop.westDeg = (*v)[2];
    out.crop.eastDeg = (*v)[3];
  }
  if (r.contains("crop_heights_m")) {
    auto v = numbers("crop_heights_m", 2, 2, "[bottom, top] in metres above sea level");
    if (!v) return v.forwardError();
    out.crop.bottomMeters = (*v)[0];
    out.crop.topMeters = (*v)[1];
  }
  return Ok{};
}
}  // namespace

Status validateVolumeLayerSettings(const VolumeLayerSettings& s, const std::string& where) {
  if (s.valueRange &&
      !(std::isfinite(s.valueRange->x) && std::isfinite(s.valueRange->y) && s.valueRange->x < s.valueRange->y))
    return makeError(where + ": range must be finite with min < max");
  if (!s.opacity.empty()) {
    const auto& o = s.opacity;
    if (o.size() < 2 || o.size() > 4 || !std::all_of(o.begin(), o.end(), [](double x) { return std::isfinite(x); }))
      return makeError(where + ": opacity must be 2 to 4 finite numbers: zero, full[, max[, per_m]]");
    if (!(o[0] < o[1])) return makeError(where + ": opacity zero value must be below the full value");
    if (o.size() > 2 && !(o[2] >= 0.0 && o[2] <= 1.0)) return makeError(where + ": opacity max must be in 0..1");
    if (o.size() > 3 && !(o[3] > 0.0)) return makeError(where + ": opacity per_m must be > 0");
  }
  return volume::validateCropBox(s.crop, where);
}

Result<SceneDescription> parseSceneJson(std::string_view text, const std::string& sourceName,
                                        const std::string& baseDir, const std::string& dataDir) {
  json root;
  try {
    root = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers beyond double (fuzz_scene)
    return makeError(sourceName + ": not valid JSON: " + e.what());
  }
  if (auto s = checkKeys(root,
                         {"camera", "fov_deg", "size", "imagery", "markers", "radars", "grids", "stations", "slices",
                          "vertical_exaggeration", "map_context", "overlays", "range_rings", "memory_budget_mb"},
                         sourceName);
      !s) {
    return s.forwardError();
  }
  SceneDescription scene;
  if (root.contains("camera")) {
    const json& c = root["camera"];
    const std::string where = sourceName + ": camera";
    if (auto s = checkKeys(c, {"lat_deg", "lon_deg", "height_m", "heading_deg", "pitch_deg", "roll_deg"}, where); !s) {
      return s.forwardError();
    }
    const std::pair<const char*, double*> fields[] = {
        {"lat_deg", &scene.camera.latDeg},        {"lon_deg", &scene.camera.lonDeg},
        {"height_m", &scene.camera.heightMeters}, {"heading_deg", &scene.camera.headingDeg},
        {"pitch_deg", &scene.camera.pitchDeg},    {"roll_deg", &scene.camera.rollDeg}};
    for (auto [key, out] : fields) {
      auto v = number(c, key, *out, where);
      if (!v) return v.forwardError();
      *out = *v;
    }
    if (auto s = validatePose(scene.camera); !s) return makeError(sourceName + ": " + s.error());
  }
  {
    auto exaggeration = number(root, "vertical_exaggeration", scene.verticalExaggeration, sourceName);
    if (!exaggeration) return exaggeration.forwardError();
    scene.verticalExaggeration = *exaggeration;
    if (auto st = volume::validateVerticalExaggeration(scene.verticalExaggeration, sourceName); !st)
      return st.forwardError();
    auto fov = number(root, "fov_deg", scene.fovYDeg, sourceName);
    if (!fov) return fov.forwardError();
    if (*fov <= 0.0 || *fov >= 180.0) return makeError(sourceName + ": fov_deg must be in (0, 180)");
    scene.fovYDeg = *fov;
    auto budget = number(root, "memory_budget_mb", scene.memoryBudgetMb, sourceName);
    if (!budget) return budget.forwardError();
    if (!(*budget >= 0.0 && *budget <= 1.0e9))
      return makeError(sourceName + ": memory_budget_mb must be in [0, 1e9] (MiB; 0: the default)");
    scene.memoryBudgetMb = *budget;
  }
  if (root.contains("size")) {
    const json& s = root["size"];
    if (!s.is_array() || s.size() != 2 || !s[0].is_number_integer() || !s[1].is_number_integer() ||
        s[0].get<long long>() < 1 || s[1].get<long long>() < 1 || s[0].get<long long>() > 16384 ||
        s[1].get<long long>() > 16384) {
      return makeError(sourceName + ": size must be [width, height] with integers in 1..16384");
    }
    scene.widthPx = s[0].get<int>();
    scene.heightPx = s[1].get<int>();
  }
  if (root.contains("imagery")) {
    if (!root["imagery"].is_array()) return makeError(sourceName + ": imagery must be an array");
    int i = 0;
    for (const json& layer : root["imagery"]) {
      const std::string where = sourceName + ": imagery[" + std::to_string(i++) + "]";
      if (auto s = checkKeys(layer, {"type", "path"}, where); !s) return s.forwardError();
      if (!layer.contains("path") || !layer["path"].is_string()) return makeError(where + ": needs a \"path\" string");
      ImageryLayerDescription d;
      const std::string type = layer.value("type", std::string("pyramid"));
      if (type == "pyramid") d.type = ImageryLayerDescription::Type::Pyramid;
      else if (type == "xyz") d.type = ImageryLayerDescription::Type::Xyz;
      else return makeError(where + ": type must be \"pyramid\" or \"xyz\", not \"" + type + "\"");
      d.path = resolvePath(layer["path"].get<std::string>(), baseDir, dataDir);
      scene.imagery.push_back(d);
    }
  }
  if (root.contains("markers")) {
    if (!root["markers"].is_array()) return makeError(sourceName + ": markers must be an array");
    int i = 0;
    for (const json& m : root["markers"]) {
      const std::string where = sourceName + ": markers[" + std::to_string(i++) + "]";
      if (auto s = checkKeys(m, {"lat_deg", "lon_deg", "height_m", "label", "color", "size_px"}, where); !s) {
        return s.forwardError();
      }
      if (!m.contains("lat_deg") || !m.contains("lon_deg")) return makeError(where + ": needs lat_deg and lon_deg");
      Marker marker;
      auto lat = number(m, "lat_deg", 0, where), lon = number(m, "lon_deg", 0, where),
           h = number(m, "height_m", 0, where), size = number(m, "size_px", marker.sizePx, where);
      for (auto* r : {&lat, &lon, &h, &size}) {
        if (!*r) return makeError(r->error());
      }
      marker.latDeg = *lat;
      marker.lonDeg = *lon;
      marker.heightMeters = *h;
      marker.sizePx = static_cast<float>(*size);
      if (auto s = globe::validateGeodetic({marker.latDeg, marker.lonDeg, marker.heightMeters}, where.c_str()); !s) {
        return s.forwardError();
      }
      if (marker.sizePx < 1.0f || marker.sizePx > 256.0f) return makeError(where + ": size_px must be in 1..256");
      if (m.contains("label")) {
        if (!m["label"].is_string()) return makeError(where + ": label must be a string");
        marker.label = m["label"].get<std::string>();
      }
      if (m.contains("color")) {
        const json& c = m["color"];
        if (!c.is_array() || c.size() != 3 || !c[0].is_number() || !c[1].is_number() || !c[2].is_number()) {
          return makeError(where + ": color must be [r, g, b] with numbers in 0..1");
        }
        marker.color = glm::vec3(c[0].get<float>(), c[1].get<float>(), c[2].get<float>());
      }
      scene.markers.push_back(marker);
    }
  }
  if (root.contains("stations")) {
    if (!root["stations"].is_string()) return makeError(sourceName + ": stations must be a file path");
    scene.stationsPath = resolvePath(root["stations"].get<std::string>(), baseDir, dataDir);
  }
  if (root.contains("radars")) {
    if (!root["radars"].is_array()) return makeError(sourceName + ": radars must be an array");
    int i = 0;
    for (const json& r : root["radars"]) {
      const std::string where = sourceName + ": radars[" + std::to_string(i++) + "]";
      if (auto s = checkKeys(r,
                             {"path", "field", "colors", "mode", "interpolation", "step_m", "image_scale", "iso_dbz",
                              "beam", "classification", "label", "geoid", "range", "opacity", "crop", "crop_heights_m"},
                             where);
          !s) {
        return s.forwardError();
      }
      RadarLayerDescription d;
      if (!r.contains("path") || !r["path"].is_string()) return makeError(where + ": needs a \"path\" string");
      d.path = resolvePath(r["path"].get<std::string>(), baseDir, dataDir);
      for (auto [key, out] : {std::pair<const char*, std::string*>{"field", &d.field},
                              {"colors", &d.colors},
                              {"mode", &d.mode},
                              {"interpolation", &d.interpolation},
                              {"beam", &d.beam},
                              {"classification", &d.classification},
                              {"label", &d.label}}) {
        if (!r.contains(key)) continue;
        if (!r[key].is_string()) return makeError(where + ": \"" + key + "\" must be a string");
        *out = r[key].get<std::string>();
      }
      if (r.contains("colors") && d.colors.size() > 4 && d.colors.substr(d.colors.size() - 4) == ".pal") {
        d.colors = resolvePath(d.colors, baseDir, dataDir);
      }
      for (auto [key, out] : {std::pair<const char*, double*>{"step_m", &d.stepMeters},
                              {"image_scale", &d.imageScale},
                              {"iso_dbz", &d.isoValue}}) {
        auto v = number(r, key, *out, where);
        if (!v) return v.forwardError();
        *out = *v;
      }
      if (r.contains("geoid")) {
        if (!r["geoid"].is_boolean()) return makeError(where + ": \"geoid\" must be true or false");
        d.useGeoid = r["geoid"].get<bool>();
      }
      if (auto st = parseLayerSettings(r, where, d.settings); !st) return st.forwardError();
      if (auto s = validateRadarLayer(d, where); !s) return s.forwardError();
      scene.radars.push_back(d);
    }
  }
  if (root.contains("grids")) {
    if (!root["grids"].is_array()) return makeError(sourceName + ": grids must be an array");
    int i = 0;
    for (const json& r : root["grids"]) {
      const std::string where = sourceName + ": grids[" + std::to_string(i++) + "]";
      if (auto s = checkKeys(r,
                             {"path", "variable", "time", "colors", "mode", "interpolation", "step_m", "image_scale",
                              "iso_value", "classification", "geoid", "range", "opacity", "crop", "crop_heights_m"},
                             where);
          !s) {
        return s.forwardError();
      }
      GridLayerDescription d;
      if (!r.contains("path") || !r["path"].is_string()) return makeError(where + ": needs a \"path\" string");
      d.path = resolvePath(r["path"].get<std::string>(), baseDir, dataDir);
      for (auto [key, out] : {std::pair<const char*, std::string*>{"variable", &d.variable},
                              {"time", &d.time},
                              {"colors", &d.colors},
                              {"mode", &d.mode},
                              {"interpolation", &d.interpolation},
                              {"classification", &d.classification}}) {
        if (!r.contains(key)) continue;
        if (!r[key].is_string()) return makeError(where + ": \"" + key + "\" must be a string");
        *out = r[key].get<std::string>();
      }
      if (r.contains("colors") && d.colors.size() > 4 && d.colors.substr(d.colors.size() - 4) == ".pal") {
        d.colors = resolvePath(d.colors, baseDir, dataDir);
      }
      for (auto [key, out] : {std::pair<const char*, double*>{"step_m", &d.stepMeters},
                              {"image_scale", &d.imageScale},
                              {"iso_value", &d.isoValue}}) {
        auto v = number(r, key, *out, where);
        if (!v) return v.forwardError();
        *out = *v;
      }
      if (r.contains("geoid")) {
        if (!r["geoid"].is_boolean()) return makeError(where + ": \"geoid\" must be true or false");
        d.useGeoid = r["geoid"].get<bool>();
      }
      if (auto st = parseLayerSettings(r, where, d.settings); !st) return st.forwardError();
      if (auto s = validateGridLayer(d, where); !s) return s.forwardError();
      scene.grids.push_back(d);
    }
  }
  for (auto [key, out] :
       {std::pair<const char*, bool*>{"map_context", &scene.mapContext}, {"range_rings", &scene.rangeRings}}) {
    if (!root.contains(key)) continue;
    if (!root[key].is_boolean()) return makeError(sourceName + ": \"" + key + "\" must be true or false");
    *out = root[key].get<bool>();
  }
  if (root.contains("overlays")) {
    if (!root["overlays"].is_array()) return makeError(sourceName + ": overlays must be an array");
    int i = 0;
    for (const json& o : root["overlays"]) {
      const std::string where = sourceName + ": overlays[" + std::to_string(i++) + "]";
      if (auto s = checkKeys(o, {"path", "color", "width_px"}, where); !s) return s.forwardError();
      if (!o.contains("path") || !o["path"].is_string()) return makeError(where + ": needs a \"path\" string");
      MapOverlayDescription d;
      d.path = resolvePath(o["path"].get<std::string>(), baseDir, dataDir);
      if (o.contains("color")) {
        const json& c = o["color"];
        if (!c.is_array() || c.size() != 3 || !c[0].is_number() || !c[1].is_number() || !c[2].is_number())
          return makeError(where + ": color must be [r, g, b] with numbers in 0..1");
        d.color = glm::vec3(c[0].get<float>(), c[1].get<float>(), c[2].get<float>());
      }
      auto width = number(o, "width_px", d.widthPx, where);
      if (!width) return width.forwardError();
      d.widthPx = static_cast<float>(*width);
      if (auto st = validateMapOverlay(d, where); !st) return st.forwardError();
      scene.overlays.push_back(d);
    }
  }
  if (root.contains("slices")) {
    auto slices = parseSliceLayersJson(root["slices"].dump(), sourceName + ": slices", baseDir, dataDir);
    if (!slices) return slices.forwardError();
    scene.slices = std::move(*slices);
  }
  return scene;
}

Status validateMapOverlay(const MapOverlayDescription& d, const std::string& where) {
  for (int k = 0; k < 3; ++k)
    if (!(d.color[k] >= 0.0f && d.color[k] <= 1.0f)) return makeError(where + ": color components must be in 0..1");
  if (!(d.widthPx >= 0.5f && d.widthPx <= 16.0f)) return makeError(where + ": width_px must be in 0.5..16");
  return Ok{};
}

Status validateGridLayer(const GridLayerDescription& d, const std::string& where) {
  if (d.mode != "dvr" && d.mode != "mip" && d.mode != "iso") {
    return makeError(where + ": mode must be dvr, mip or iso, not \"" + d.mode + "\"");
  }
  if (d.interpolation != "nearest" && d.interpolation != "linear") {
    return makeError(where + ": interpolation must be nearest or linear, not \"" + d.interpolation + "\"");
  }
  if (d.classification != "point" && d.classification != "preintegrated") {
    return makeError(where + ": classification must be point or preintegrated, not \"" + d.classification + "\"");
  }
  if (!(d.stepMeters >= 1.0 && d.stepMeters <= 1e6)) return makeError(where + ": step must be in 1..1000000 m");
  if (!(d.imageScale >= 0.05 && d.imageScale <= 1.0)) return makeError(where + ": image scale must be in 0.05..1");
  if (std::isinf(d.isoValue)) return makeError(where + ": iso value must be finite");
  return validateVolumeLayerSettings(d.settings, where);
}

Status validateRadarLayer(const RadarLayerDescription& d, const std::string& where) {
  if (d.mode != "dvr" && d.mode != "mip" && d.mode != "iso") {
    return makeError(where + ": mode must be dvr, mip or iso, not \"" + d.mode + "\"");
  }
  if (d.interpolation != "nearest" && d.interpolation != "linear") {
    return makeError(where + ": interpolation must be nearest or linear, not \"" + d.interpolation + "\"");
  }
  if (d.beam != "4/3" && d.beam != "straight") {
    return makeError(where + ": beam must be \"4/3\" or \"straight\", not \"" + d.beam + "\"");
  }
  if (d.classification != "point" && d.classification != "preintegrated") {
    return makeError(where + ": classification must be point or preintegrated, not \"" + d.classification + "\"");
  }
  if (!(d.stepMeters >= 1.0 && d.stepMeters <= 1e5)) return makeError(where + ": step must be in 1..100000 m");
  if (!(d.imageScale >= 0.05 && d.imageScale <= 1.0)) return makeError(where + ": image scale must be in 0.05..1");
  if (!std::isfinite(d.isoValue)) return makeError(where + ": iso value must be finite");
  return validateVolumeLayerSettings(d.settings, where);
}

Result<SceneDescription> loadSceneFile(const std::string& path, const std::string& dataDir) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open scene file");
  std::ostringstream s;
  s << in.rdbuf();
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parseSceneJson(s.str(), path, base, dataDir);
}

}  // namespace atmoglobe::engine
