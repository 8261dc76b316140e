#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/globe/Text.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include "SceneJsonFields.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace atmoglobe::engine {

namespace {

using json = nlohmann::json;
using scenejson::Object;

std::string resolvePath(const std::string& path, const std::string& baseDir, const std::string& dataDir) {
  if (path.rfind("@data", 0) == 0) return dataDir + path.substr(5);
  std::filesystem::path p(path);
  if (p.is_absolute() || baseDir.empty()) return path;
  return (std::filesystem::path(baseDir) / p).string();
}

// "range", "opacity", "crop", "crop_heights_m" of a radar or grid layer.
Status parseLayerSettings(const Object& o, VolumeLayerSettings& out) {
  std::vector<double> v;
  if (auto st = o.numbers("range", v, 2, 2, "[min, max] (field units)"); !st) return st;
  if (o.has("range")) out.valueRange = glm::dvec2(v[0], v[1]);
  if (auto st = o.numbers("opacity", out.opacity, 2, 4, "[zero, full[, max[, per_m]]]"); !st) return st;
  v.clear();
  if (auto st = o.numbers("crop", v, 4, 4, "[south, north, west, east] (deg)", -360.0, 360.0); !st) return st;
  if (o.has("crop")) {
    out.crop.southDeg = v[0];
    out.crop.northDeg = v[1];
    out.crop.westDeg = v[2];
    out.crop.eastDeg = v[3];
  }
  v.clear();
  if (auto st = o.numbers("crop_heights_m", v, 2, 2, "[bottom, top] (m above sea level)"); !st) return st;
  if (o.has("crop_heights_m")) {
    out.crop.bottomMeters = v[0];
    out.crop.topMeters = v[1];
  }
  // The viewer's edited opacity curve (written by "Save scene"): [[value, opacity], ...], values
  // increasing, opacity per reference length in 0..1.
  if (o.has("opacity_points")) {
    if (auto st = o.array("opacity_points"); !st) return st;
    const nlohmann::json& points = o.value().at("opacity_points");
    if (points.size() < 2) return o.error("opacity_points", "needs two or more [value, opacity] points");
    for (std::size_t i = 0; i < points.size(); ++i) {
      const nlohmann::json& p = points[i];
      const std::string at = o.where("opacity_points") + "/" + std::to_string(i);
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        return makeError(at + ": expected [value, opacity]");
      const glm::dvec2 point(p[0].get<double>(), p[1].get<double>());
      if (!std::isfinite(point.x) || !(point.y >= 0.0 && point.y <= 1.0))
        return makeError(at + ": a finite value and an opacity in 0..1");
      if (!out.opacityPoints.empty() && !(point.x > out.opacityPoints.back().x))
        return makeError(at + ": values must increase");
      out.opacityPoints.push_back(point);
    }
  }
  return Ok{};
}

// A colour table: a name (case ignored) or a .pal file (resolved like every path).
Status parseColors(const Object& o, std::string& out, std::initializer_list<const char*> names,
                   const std::string& baseDir, const std::string& dataDir) {
  if (auto st = o.string("colors", out); !st) return st;
  if (!o.has("colors")) return Ok{};
  const std::string lower = toLowerAscii(out);
  std::vector<std::string> known;
  for (const char* n : names) {
    if (lower == n) return Ok{};
    known.push_back(n);
  }
  if (lower.size() > 4 && lower.substr(lower.size() - 4) == ".pal") {
    out = resolvePath(out, baseDir, dataDir);
    return Ok{};
  }
  std::string message = std::string("\"").append(out).append("\" is neither a colour table (");
  for (std::size_t i = 0; i < known.size(); ++i) message += (i ? ", " : "") + known[i];
  message += ") nor a .pal file";
  if (const std::string hint = scenejson::closestKey(lower, known); !hint.empty())
    message.append(" (did you mean \"").append(hint).append("\"?)");
  return o.error("colors", message);
}

// A layer's "path": required, a string, resolved.
Status parsePath(const Object& o, const char* key, std::string& out, const char* what, const std::string& baseDir,
                 const std::string& dataDir) {
  if (auto st = o.require(key, what); !st) return st;
  if (auto st = o.string(key, out); !st) return st;
  if (out.empty()) return o.error(key, "empty path");
  out = resolvePath(out, baseDir, dataDir);
  return Ok{};
}

// Runs each check in order; the first error wins.
template <class... Checks>
Status all(Checks&&... checks) {
  Status result = Ok{};
  ((result ? (result = checks()) : result), ...);
  return result;
}

// A scene key naming one value of an enumerated setting (VolumeLayer.h's spellings).
template <class E>
Status parseEnum(const Object& o, const char* key, E& out) {
  if (!o.has(key)) return Ok{};
  std::string name = nameOf(out);
  std::vector<const char*> names;
  for (E value : allValues<E>()) names.push_back(nameOf(value));
  if (auto st = o.choice(key, name, names); !st) return st;
  out = *parseName<E>(name);
  return Ok{};
}

// One element of "radars" or "grids": the keys both kinds share, then each kind's own ("field",
// "iso_dbz", "beam", "label", "overlap", "window_minutes" for radars; "variable", "iso_value", "time", "member",
// "index" for grids).
Status parseVolumeLayer(const Object& r, VolumeKind kind, const std::string& baseDir, const std::string& dataDir,
                        VolumeLayerDescription& d) {
  d.kind = kind;
  const bool radar = kind == VolumeKind::Radar;
  std::vector<std::string> keys{"path",
                                "colors",
                                "mode",
                                "interpolation",
                                "step_m",
                                "samples_per_cell",
                                "image_scale",
                                "refine_threshold",
                                "classification",
                                "geoid",
                                "range",
                                "opacity",
                                "opacity_points",
                                "crop_heights_m",
                                "crop"};
  const char* fieldKey = radar ? "field" : "variable";
  const char* isoKey = radar ? "iso_dbz" : "iso_value";
  keys.insert(keys.end(), {fieldKey, isoKey});
  if (radar) {
    keys.insert(keys.end(), {"beam", "label", "overlap", "window_minutes", "far_field"});
  } else {
    keys.insert(keys.end(), {"time", "member", "ensemble", "index", "level_of_detail", "near_window"});
  }
  if (auto st = r.checkObject(keys); !st) return st;
  double iso = 0.0;
  Status st = all(
      [&] {
        return parsePath(r, "path", d.path,
                         radar ? "a radar file, directory, glob or comma list" : "a CF or WRF netCDF or a GRIB file",
                         baseDir, dataDir);
      },
      [&] { return r.string(fieldKey, d.field); },
      [&] {
        return parseColors(r, d.colors,
                           {"auto", "nws", "cividis", "velocity", "viridis", "turbo", "grayscale", "greens"}, baseDir,
                           dataDir);
      },
      [&] { return parseEnum(r, "mode", d.mode); }, [&] { return parseEnum(r, "interpolation", d.interpolation); },
      [&] { return parseEnum(r, "classification", d.classification); },
      [&] { return radar ? parseEnum(r, "beam", d.beam) : Status(Ok{}); },
      [&] {
        if (!radar || !r.has("far_field")) return Status(Ok{});
        FarField f = FarField::Off;
        if (auto parsed = parseEnum(r, "far_field", f); !parsed) return parsed;
        d.farField = f;
        return Status(Ok{});
      },
      [&] { return radar ? r.string("label", d.label) : r.string("time", d.time); },
      [&] {
        if (!radar || !r.has("overlap")) return Status(Ok{});
        std::string rule;
        if (Status s = r.choice("overlap", rule, {"mean", "lowest", "max", "integrate"}); !s) return s;
        d.overlap = *volume::parseOverlapRule(rule);
        return Status(Ok{});
      },
      [&] { return radar ? r.number("window_minutes", d.windowMinutes, 0.01, 1440.0, "min") : Status(Ok{}); },
      [&] { return radar ? Status(Ok{}) : r.integer("member", d.member, 0, 1000000); },
      [&] {
        if (radar || !r.has("ensemble")) return Status(Ok{});
        std::string text;
        if (Status s = r.string("ensemble", text); !s) return s;
        auto stat = volume::parseEnsembleStatistic(text);
        if (!stat) return r.error("ensemble", stat.error());
        if (d.member >= 0) return r.error("ensemble", "combines every member: not with \"member\"");
        d.ensemble = *stat;
        return Status(Ok{});
      },
      [&] { return radar ? Status(Ok{}) : r.indices("index", d.gridIndex, 1000000000); },
      [&] { return radar ? Status(Ok{}) : r.boolean("level_of_detail", d.levelOfDetail); },
      [&] { return radar ? Status(Ok{}) : r.boolean("near_window", d.nearWindow); },
      [&] { return r.number("step_m", d.stepMeters, 1.0, 1e6, "m"); },
      [&] {
        double n = 0.0;
        if (!r.has("samples_per_cell")) return Status(Ok{});
        Status s = r.number("samples_per_cell", n, 0.0, 64.0);
        if (s) d.samplesPerCell = n;
        return s;
      },
      [&] { return r.number("image_scale", d.imageScale, 0.05, 1.0); },
      [&] {
        if (!r.has("refine_threshold")) return Status(Ok{});
        return r.number("refine_threshold", d.refineThreshold, -1.0, 255.0, "(8-bit steps; -1: off)");
      },
      [&] { return r.number(isoKey, iso, -1e30, 1e30, radar ? "(field units)" : "(variable units)"); },
      [&] { return r.boolean("geoid", d.useGeoid); }, [&] { return parseLayerSettings(r, d.settings); });
  if (!st) return st;
  if (r.has(isoKey)) d.isoValue = iso;
  return validateVolumeLayer(d, r.where());
}

Status parseMarker(const Object& m, Marker& marker) {
  if (auto st = m.checkObject({"lat_deg", "lon_deg", "height_m", "label", "color", "size_px"}); !st) return st;
  return all([&] { return m.require("lat_deg", "latitude, deg"); },
             [&] { return m.require("lon_deg", "longitude, deg"); },
             [&] { return m.number("lat_deg", marker.latDeg, -90.0, 90.0, "deg"); },
             [&] { return m.number("lon_deg", marker.lonDeg, -360.0, 360.0, "deg"); },
             [&] { return m.number("height_m", marker.heightMeters, -1.2e4, 1e8, "m"); },
             [&] { return m.number("size_px", marker.sizePx, 1.0, 256.0, "px"); },
             [&] { return m.string("label", marker.label); }, [&] { return m.color("color", marker.color); });
}

}  // namespace

std::vector<VolumeLayerDescription> volumesOfKind(const SceneDescription& scene, VolumeKind kind) {
  std::vector<VolumeLayerDescription> out;
  for (const VolumeLayerDescription& d : scene.volumes)
    if (d.kind == kind) out.push_back(d);
  return out;
}

void setUnsetFarField(SceneDescription& scene, FarField farField) {
  for (VolumeLayerDescription& d : scene.volumes)
    if (d.kind == VolumeKind::Radar && !d.farField) d.farField = farField;
}

std::string layerOrigin(const std::vector<std::string>& origins, std::size_t index, const std::string& fallback) {
  return index < origins.size() && !origins[index].empty() ? origins[index] : fallback;
}

Status checkInputFile(const std::string& path, const std::string& where) {
  if (path.find_first_of("*?[,") != std::string::npos) return Ok{};  // a glob or a list: the reader says
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return makeError(where + ": file not found: " + path);
  return Ok{};
}

// One element of "surfaces": a grid's 2-D field on the globe (SurfaceLayer.h).
Status parseSurfaceLayer(const Object& o, const std::string& baseDir, const std::string& dataDir,
                         SurfaceLayerDescription& d) {
  std::vector<double> range;
  double pressure = 0.0, interval = 0.0;
  Status st = all(
      [&] {
        return o.checkObject({"path", "variable", "time", "member", "ensemble", "pressure_hpa", "level", "colors",
                              "range", "opacity", "fill", "contour_interval", "contour_values", "contour_color",
                              "contour_width_px", "contour_labels", "wind", "wind_color", "geoid"});
      },
      [&] { return parsePath(o, "path", d.path, "a CF or WRF netCDF or a GRIB file", baseDir, dataDir); },
      [&] { return o.string("variable", d.variable); }, [&] { return o.string("time", d.time); },
      [&] { return o.integer("member", d.member, 0, 1000000); }, [&] { return o.string("ensemble", d.ensemble); },
      [&] {
        Status s = o.number("pressure_hpa", pressure, 0.001, 1100.0, "hPa");
        if (s && o.has("pressure_hpa")) d.pressureHpa = pressure;
        return s;
      },
      [&] {
        int level = 0;
        Status s = o.integer("level", level, 0, 100000);
        if (s && o.has("level")) d.level = level;
        return s;
      },
      [&] { return o.string("colors", d.colors); },
      [&] {
        Status s = o.numbers("range", range, 2, 2, "[min, max] (field units)");
        if (s && o.has("range")) d.valueRange = glm::dvec2(range[0], range[1]);
        return s;
      },
      [&] { return o.number("opacity", d.opacity, 0.0, 1.0); }, [&] { return o.boolean("fill", d.fill); },
      [&] {
        Status s = o.number("contour_interval", interval, 1e-30, 1e30, "(field units)");
        if (s && o.has("contour_interval")) d.contourInterval = interval;
        return s;
      },
      [&] { return o.numbers("contour_values", d.contourValues, 1, 1000, "[value, ...] (field units)"); },
      [&] { return o.color("contour_color", d.contourColor); },
      [&] { return o.number("contour_width_px", d.contourWidthPx, 0.5, 16.0, "px"); },
      [&] { return o.boolean("contour_labels", d.contourLabels); }, [&] { return o.string("wind", d.wind); },
      [&] { return o.color("wind_color", d.windColor); }, [&] { return o.boolean("geoid", d.useGeoid); });
  if (!st) return st;
  return validateSurfaceLayer(d, o.where());
}

Result<SceneDescription> parseSceneJson(std::string_view text, const std::string& sourceName,
                                        const std::string& baseDir, const std::string& dataDir) {
  json root;
  try {
    root = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers beyond double (fuzz_scene)
    return makeError(sourceName + ": not valid JSON: " + e.what());
  }
  const Object top(root, sourceName, "");
  if (auto s = top.checkObject({"camera", "fov_deg", "size", "imagery", "markers", "radars", "grids", "stations",
                                "slices", "vertical_exaggeration", "map_context", "overlays", "range_rings",
                                "memory_budget_mb", "surfaces"});
      !s) {
    return s.forwardError();
  }
  SceneDescription scene;
  if (top.has("camera")) {
    const Object c = top.member("camera");
    CameraPose& p = scene.camera;
    if (auto st = all(
            [&] {
              return c.checkObject({"lat_deg", "lon_deg", "height_m", "heading_deg", "pitch_deg", "roll_deg"});
            },
            [&] { return c.number("lat_deg", p.latDeg, -90.0, 90.0, "deg"); },
            [&] { return c.number("lon_deg", p.lonDeg, -360.0, 360.0, "deg"); },
            [&] { return c.number("height_m", p.heightMeters, -6.3e6, 1e10, "m"); },
            [&] { return c.number("heading_deg", p.headingDeg, -360.0, 360.0, "deg"); },
            [&] { return c.number("pitch_deg", p.pitchDeg, -90.0, 90.0, "deg"); },
            [&] { return c.number("roll_deg", p.rollDeg, -180.0, 180.0, "deg"); });
        !st)
      return st.forwardError();
    if (auto s = validatePose(scene.camera); !s) return makeError(c.where() + ": " + s.error());
  }
  if (auto st = top.number("vertical_exaggeration", scene.verticalExaggeration, 0.1, 100.0); !st)
    return st.forwardError();
  if (auto st = volume::validateVerticalExaggeration(scene.verticalExaggeration, top.where("vertical_exaggeration"));
      !st)
    return st.forwardError();
  if (auto st = top.number("fov_deg", scene.fovYDeg, 0.0, 180.0, "deg"); !st) return st.forwardError();
  if (!(scene.fovYDeg > 0.0 && scene.fovYDeg < 180.0))
    return top.error("fov_deg", "must be above 0 and below 180 deg").forwardError();
  // MiB; 0: volume::defaultMemoryBudgetBytes() (docs/memory.md)
  if (auto st = top.number("memory_budget_mb", scene.memoryBudgetMb, 0.0, 1e9, "MiB"); !st) return st.forwardError();
  if (top.has("size")) {
    std::vector<double> v;
    if (auto st = top.numbers("size", v, 2, 2, "[width, height] (px)", 1.0, 16384.0); !st) return st.forwardError();
    for (std::size_t i = 0; i < 2; ++i)
      if (!root["size"][i].is_number_integer())
        return makeError(top.where("size") + "/" + std::to_string(i) + ": " +
                         scenejson::expected("an integer", root["size"][i]));
    scene.widthPx = static_cast<int>(v[0]);
    scene.heightPx = static_cast<int>(v[1]);
  }
  for (const char* key : {"imagery", "markers", "radars", "grids", "overlays", "slices", "surfaces"})
    if (auto st = top.array(key); !st) return st.forwardError();
  if (top.has("imagery")) {
    for (std::size_t i = 0; i < root["imagery"].size(); ++i) {
      const Object layer = top.element("imagery", i);
      ImageryLayerDescription d;
      std::string type = "pyramid";
      if (auto st = all(
              [&] {
                return layer.checkObject({"type", "path"});
              },
              [&] {
                return layer.choice("type", type, {"pyramid", "xyz"});
              },
              [&] { return parsePath(layer, "path", d.path, "an imagery directory", baseDir, dataDir); });
          !st)
        return st.forwardError();
      d.type = type == "xyz" ? ImageryLayerDescription::Type::Xyz : ImageryLayerDescription::Type::Pyramid;
      scene.imagery.push_back(d);
      scene.origins.imagery.push_back(layer.where());
    }
  }
  if (top.has("markers")) {
    for (std::size_t i = 0; i < root["markers"].size(); ++i) {
      Marker marker;
      if (auto st = parseMarker(top.element("markers", i), marker); !st) return st.forwardError();
      scene.markers.push_back(marker);
    }
  }
  if (top.has("stations")) {
    if (auto st = top.string("stations", scene.stationsPath); !st) return st.forwardError();
    if (scene.stationsPath.empty()) return top.error("stations", "empty path").forwardError();
    scene.stationsPath = resolvePath(scene.stationsPath, baseDir, dataDir);
    scene.origins.stations = top.where("stations");
  }
  for (const auto& [key, kind] : {std::pair{"radars", VolumeKind::Radar}, std::pair{"grids", VolumeKind::Grid}}) {
    if (!top.has(key)) continue;
    for (std::size_t i = 0; i < root[key].size(); ++i) {
      const Object r = top.element(key, i);
      VolumeLayerDescription d;
      if (auto st = parseVolumeLayer(r, kind, baseDir, dataDir, d); !st) return st.forwardError();
      scene.volumes.push_back(d);
      scene.origins.volumes.push_back(r.where());
    }
  }
  if (auto st = all([&] { return top.boolean("map_context", scene.mapContext); },
                    [&] { return top.boolean("range_rings", scene.rangeRings); });
      !st)
    return st.forwardError();
  if (top.has("overlays")) {
    for (std::size_t i = 0; i < root["overlays"].size(); ++i) {
      const Object o = top.element("overlays", i);
      MapOverlayDescription d;
      if (auto st = all(
              [&] {
                return o.checkObject({"path", "color", "width_px"});
              },
              [&] { return parsePath(o, "path", d.path, "a vector file", baseDir, dataDir); },
              [&] { return o.color("color", d.color); },
              [&] { return o.number("width_px", d.widthPx, 0.5, 16.0, "px"); });
          !st)
        return st.forwardError();
      scene.overlays.push_back(d);
      scene.origins.overlays.push_back(o.where());
    }
  }
  if (top.has("surfaces")) {
    for (std::size_t i = 0; i < root["surfaces"].size(); ++i) {
      const Object o = top.element("surfaces", i);
      SurfaceLayerDescription d;
      if (auto st = parseSurfaceLayer(o, baseDir, dataDir, d); !st) return st.forwardError();
      scene.surfaces.push_back(std::move(d));
      scene.origins.surfaces.push_back(o.where());
    }
  }
  if (top.has("slices")) {
    for (std::size_t i = 0; i < root["slices"].size(); ++i) {
      const Object o = top.element("slices", i);
      SliceLayerDescription d;
      if (auto st = parseSliceLayer(o, baseDir, dataDir, d); !st) return st.forwardError();
      scene.slices.push_back(std::move(d));
      scene.origins.slices.push_back(o.where());
    }
  }
  return scene;
}

Status validateMapOverlay(const MapOverlayDescription& d, const std::string& where) {
  for (int k = 0; k < 3; ++k)
    if (!(d.color[k] >= 0.0f && d.color[k] <= 1.0f)) return makeError(where + ": color components must be in 0..1");
  if (!(d.widthPx >= 0.5f && d.widthPx <= 16.0f)) return makeError(where + ": width_px must be in 0.5..16");
  return Ok{};
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
