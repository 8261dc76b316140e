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

Status parseRadar(const Object& r, const std::string& baseDir, const std::string& dataDir, RadarLayerDescription& d) {
  if (auto st =
          r.checkObject({"path", "field", "colors", "mode", "interpolation", "step_m", "image_scale", "iso_dbz", "beam",
                         "classification", "label", "geoid", "range", "opacity", "crop", "crop_heights_m"});
      !st)
    return st;
  Status st =
      all([&] { return parsePath(r, "path", d.path, "a radar file, directory, glob or comma list", baseDir, dataDir); },
          [&] { return r.string("field", d.field); },
          [&] {
            return parseColors(r, d.colors,
                               {"auto", "nws", "cividis", "velocity", "viridis", "turbo", "grayscale", "greens"},
                               baseDir, dataDir);
          },
          [&] {
            return r.choice("mode", d.mode, {"dvr", "mip", "iso"});
          },
          [&] {
            return r.choice("interpolation", d.interpolation, {"nearest", "linear"});
          },
          [&] {
            return r.choice("beam", d.beam, {"4/3", "straight"});
          },
          [&] {
            return r.choice("classification", d.classification, {"point", "preintegrated"});
          },
          [&] { return r.string("label", d.label); }, [&] { return r.number("step_m", d.stepMeters, 1.0, 1e5, "m"); },
          [&] { return r.number("image_scale", d.imageScale, 0.05, 1.0); },
          [&] { return r.number("iso_dbz", d.isoValue, -1e30, 1e30, "(field units)"); },
          [&] { return r.boolean("geoid", d.useGeoid); }, [&] { return parseLayerSettings(r, d.settings); });
  if (!st) return st;
  return validateRadarLayer(d, r.where());
}

Status parseGrid(const Object& r, const std::string& baseDir, const std::string& dataDir, GridLayerDescription& d) {
  if (auto st = r.checkObject({"path", "variable", "time", "colors", "mode", "interpolation", "step_m", "image_scale",
                               "iso_value", "classification", "geoid", "range", "opacity", "crop", "crop_heights_m"});
      !st)
    return st;
  Status st = all([&] { return parsePath(r, "path", d.path, "a CF or WRF netCDF file", baseDir, dataDir); },
                  [&] { return r.string("variable", d.variable); }, [&] { return r.string("time", d.time); },
                  [&] {
                    return parseColors(
                        r, d.colors, {"auto", "nws", "cividis", "viridis", "turbo", "grayscale", "greens", "velocity"},
                        baseDir, dataDir);
                  },
                  [&] {
                    return r.choice("mode", d.mode, {"dvr", "mip", "iso"});
                  },
                  [&] {
                    return r.choice("interpolation", d.interpolation, {"nearest", "linear"});
                  },
                  [&] {
                    return r.choice("classification", d.classification, {"point", "preintegrated"});
                  },
                  [&] { return r.number("step_m", d.stepMeters, 1.0, 1e6, "m"); },
                  [&] { return r.number("image_scale", d.imageScale, 0.05, 1.0); },
                  [&] { return r.number("iso_value", d.isoValue, -1e30, 1e30, "(variable units)"); },
                  [&] { return r.boolean("geoid", d.useGeoid); }, [&] { return parseLayerSettings(r, d.settings); });
  if (!st) return st;
  return validateGridLayer(d, r.where());
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

std::string layerOrigin(const std::vector<std::string>& origins, std::size_t index, const std::string& fallback) {
  return index < origins.size() && !origins[index].empty() ? origins[index] : fallback;
}

Status checkInputFile(const std::string& path, const std::string& where) {
  if (path.find_first_of("*?[,") != std::string::npos) return Ok{};  // a glob or a list: the reader says
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return makeError(where + ": file not found: " + path);
  return Ok{};
}

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
  const Object top(root, sourceName, "");
  if (auto s =
          top.checkObject({"camera", "fov_deg", "size", "imagery", "markers", "radars", "grids", "stations", "slices",
                           "vertical_exaggeration", "map_context", "overlays", "range_rings", "memory_budget_mb"});
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
  for (const char* key : {"imagery", "markers", "radars", "grids", "overlays", "slices"})
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
  if (top.has("radars")) {
    for (std::size_t i = 0; i < root["radars"].size(); ++i) {
      const Object r = top.element("radars", i);
      RadarLayerDescription d;
      if (auto st = parseRadar(r, baseDir, dataDir, d); !st) return st.forwardError();
      scene.radars.push_back(d);
      scene.origins.radars.push_back(r.where());
    }
  }
  if (top.has("grids")) {
    for (std::size_t i = 0; i < root["grids"].size(); ++i) {
      const Object r = top.element("grids", i);
      GridLayerDescription d;
      if (auto st = parseGrid(r, baseDir, dataDir, d); !st) return st.forwardError();
      scene.grids.push_back(d);
      scene.origins.grids.push_back(r.where());
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
