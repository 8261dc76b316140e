// A scene description back to the scene JSON that parseSceneJson reads (Scene.h sceneToJson).
// Every key parseSceneJson takes is written when it differs from the default a parse would give,
// so that parse(write(scene)) describes the same scene; paths are written as resolved (absolute
// or relative to the working directory where the scene was loaded), numbers as JSON doubles
// (nlohmann writes the shortest text that reads back to the same double).
#include <atmoglobe/engine/Scene.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace atmoglobe::engine {

namespace {

using json = nlohmann::ordered_json;

std::string absolute(const std::string& path) {
  if (path.empty() || path.find_first_of("*?[,") != std::string::npos) return path;  // globs and lists as given
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::absolute(path, ec);
  return ec ? path : p.lexically_normal().string();
}

json colorOf(const glm::vec3& c) { return json::array({c.r, c.g, c.b}); }

json surfaceJson(const SurfaceLayerDescription& s) {
  const SurfaceLayerDescription d;
  json j;
  j["path"] = absolute(s.path);
  if (!s.variable.empty()) j["variable"] = s.variable;
  if (!s.time.empty()) j["time"] = s.time;
  if (s.member >= 0) j["member"] = s.member;
  if (!s.ensemble.empty()) j["ensemble"] = s.ensemble;
  if (s.pressureHpa) j["pressure_hpa"] = *s.pressureHpa;
  if (s.level) j["level"] = *s.level;
  if (s.colors != d.colors) j["colors"] = s.colors;
  if (s.valueRange) j["range"] = {s.valueRange->x, s.valueRange->y};
  if (s.opacity != d.opacity) j["opacity"] = s.opacity;
  if (s.fill != d.fill) j["fill"] = s.fill;
  if (s.contourInterval) j["contour_interval"] = *s.contourInterval;
  if (!s.contourValues.empty()) j["contour_values"] = s.contourValues;
  if (s.contourColor != d.contourColor) j["contour_color"] = colorOf(s.contourColor);
  if (s.contourWidthPx != d.contourWidthPx) j["contour_width_px"] = s.contourWidthPx;
  if (s.contourLabels != d.contourLabels) j["contour_labels"] = s.contourLabels;
  if (!s.wind.empty()) j["wind"] = s.wind;
  if (s.windColor != d.windColor) j["wind_color"] = colorOf(s.windColor);
  if (s.useGeoid != d.useGeoid) j["geoid"] = s.useGeoid;
  return j;
}

void writeSettings(json& j, const VolumeLayerSettings& s) {
  if (s.valueRange) j["range"] = {s.valueRange->x, s.valueRange->y};
  if (!s.opacity.empty()) j["opacity"] = s.opacity;
  if (s.opacityPoints.size() >= 2) {
    json points = json::array();
    for (const glm::dvec2& p : s.opacityPoints) points.push_back({p.x, p.y});
    j["opacity_points"] = points;
  }
  if (!s.crop.coversEveryLonLat()) j["crop"] = {s.crop.southDeg, s.crop.northDeg, s.crop.westDeg, s.crop.eastDeg};
  if (!s.crop.coversEveryHeight()) j["crop_heights_m"] = {s.crop.bottomMeters, s.crop.topMeters};
}

json volumeLayerJson(const VolumeLayerDescription& d) {
  const VolumeLayerDescription defaults;
  const bool radar = d.kind == VolumeKind::Radar;
  json j;
  j["path"] = absolute(d.path);
  if (!d.field.empty()) j[radar ? "field" : "variable"] = d.field;
  if (!d.colors.empty() && d.colors != "auto") {
    const bool pal = d.colors.size() > 4 && d.colors.substr(d.colors.size() - 4) == ".pal";
    j["colors"] = pal ? absolute(d.colors) : d.colors;
  }
  j["mode"] = nameOf(d.mode);
  j["interpolation"] = nameOf(d.interpolation);
  j["classification"] = nameOf(d.classification);
  j["step_m"] = d.stepMeters;
  if (d.samplesPerCell) j["samples_per_cell"] = *d.samplesPerCell;
  if (d.kind == VolumeKind::Grid && !d.levelOfDetail) j["level_of_detail"] = false;
  if (d.kind == VolumeKind::Grid && !d.nearWindow) j["near_window"] = false;
  j["image_scale"] = d.imageScale;
  if (d.refineThreshold >= 0.0) j["refine_threshold"] = d.refineThreshold;
  if (d.isoValue) j[radar ? "iso_dbz" : "iso_value"] = *d.isoValue;
  j["geoid"] = d.useGeoid;
  if (radar) {
    j["beam"] = nameOf(d.beam);
    if (!d.label.empty()) j["label"] = d.label;
    if (d.overlap) j["overlap"] = volume::toString(*d.overlap);
    if (d.farField) j["far_field"] = nameOf(*d.farField);
    if (d.windowMinutes != defaults.windowMinutes) j["window_minutes"] = d.windowMinutes;
  } else {
    if (!d.time.empty()) j["time"] = d.time;
    if (d.member >= 0) j["member"] = d.member;
    if (d.ensemble) j["ensemble"] = volume::toString(*d.ensemble);
    if (!d.gridIndex.empty()) {
      json index = json::object();
      for (const auto& [name, i] : d.gridIndex) index[name] = i;
      j["index"] = index;
    }
  }
  writeSettings(j, d.settings);
  return j;
}

json sliceJson(const SliceLayerDescription& d) {
  json j;
  const bool radar = d.source.kind == volume::SliceSourceOptions::Kind::Radar;
  j[radar ? "radar" : "grid"] = absolute(d.source.path);
  if (!d.source.field.empty()) j[radar ? "field" : "variable"] = d.source.field;
  if (!radar) {
    if (!d.source.time.empty()) j["time"] = d.source.time;
    if (d.source.member >= 0) j["member"] = d.source.member;
    if (d.source.ensemble) j["ensemble"] = volume::toString(*d.source.ensemble);
    if (!d.source.gridIndex.empty()) {
      json index = json::object();
      for (const auto& [name, i] : d.source.gridIndex) index[name] = i;
      j["index"] = index;
    }
  }
  if (d.request.cappi) {
    j["height_m"] = d.request.heightMeters;
    if (d.request.box) {
      const volume::LatLonBox& b = *d.request.box;
      // parseSliceLayer adds 360 to an east below west: write east within 360 of west as read.
      j["box"] = {b.southDeg, b.northDeg, b.westDeg, b.eastDeg > 360.0 ? b.eastDeg - 360.0 : b.eastDeg};
    }
  } else {
    json path = json::array();
    for (const volume::LatLon& p : d.request.path) path.push_back({p.latDeg, p.lonDeg});
    j["path"] = path;
    if (d.request.bottomMeters && d.request.topMeters) j["heights_m"] = {*d.request.bottomMeters, *d.request.topMeters};
  }
  j["datum"] = d.request.datum == volume::SliceHeightDatum::SeaLevel ? "msl" : "ellipsoid";
  if (!d.colors.empty() && d.colors != "auto") j["colors"] = d.colors;
  if (d.range) j["range"] = {d.range->minValue, d.range->maxValue};
  j["opacity"] = d.opacity;
  j["resolution_px"] = d.resolutionPx;
  j["geoid"] = d.source.useGeoid;
  return j;
}

}  // namespace

std::string sceneToJson(const SceneDescription& scene) {
  json j;
  const CameraPose& c = scene.camera;
  j["camera"] = {{"lat_deg", c.latDeg},         {"lon_deg", c.lonDeg},     {"height_m", c.heightMeters},
                 {"heading_deg", c.headingDeg}, {"pitch_deg", c.pitchDeg}, {"roll_deg", c.rollDeg}};
  j["fov_deg"] = scene.fovYDeg;
  j["size"] = {scene.widthPx, scene.heightPx};
  j["vertical_exaggeration"] = scene.verticalExaggeration;
  if (scene.memoryBudgetMb > 0.0) j["memory_budget_mb"] = scene.memoryBudgetMb;
  j["map_context"] = scene.mapContext;
  j["range_rings"] = scene.rangeRings;
  json imagery = json::array();
  for (const ImageryLayerDescription& l : scene.imagery)
    imagery.push_back(
        {{"type", l.type == ImageryLayerDescription::Type::Xyz ? "xyz" : "pyramid"}, {"path", absolute(l.path)}});
  j["imagery"] = imagery;
  json markers = json::array();
  for (const Marker& m : scene.markers) {
    json mj = {{"lat_deg", m.latDeg},
               {"lon_deg", m.lonDeg},
               {"height_m", m.heightMeters},
               {"color", colorOf(m.color)},
               {"size_px", m.sizePx}};
    if (!m.label.empty()) mj["label"] = m.label;
    markers.push_back(mj);
  }
  if (!markers.empty()) j["markers"] = markers;
  if (!scene.stationsPath.empty()) j["stations"] = absolute(scene.stationsPath);
  json radars = json::array(), grids = json::array();
  for (const VolumeLayerDescription& d : scene.volumes)
    (d.kind == VolumeKind::Radar ? radars : grids).push_back(volumeLayerJson(d));
  if (!radars.empty()) j["radars"] = radars;
  if (!grids.empty()) j["grids"] = grids;
  json overlays = json::array();
  for (const MapOverlayDescription& o : scene.overlays)
    overlays.push_back({{"path", absolute(o.path)}, {"color", colorOf(o.color)}, {"width_px", o.widthPx}});
  if (!overlays.empty()) j["overlays"] = overlays;
  json slices = json::array();
  for (const SliceLayerDescription& s : scene.slices) slices.push_back(sliceJson(s));
  if (!slices.empty()) j["slices"] = slices;
  json surfaces = json::array();
  for (const SurfaceLayerDescription& s : scene.surfaces) surfaces.push_back(surfaceJson(s));
  if (!surfaces.empty()) j["surfaces"] = surfaces;
  return j.dump(2) + "\n";
}

}  // namespace atmoglobe::engine
