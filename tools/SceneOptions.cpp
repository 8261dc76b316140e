#include "SceneOptions.h"

#include <atmoglobe/volume/VerticalExaggeration.h>

#include "Commands.h"

#include <atmoglobe/engine/Framing.h>
#include <atmoglobe/map/Contours.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/StationList.h>

#include <atmoglobe/globe/Progress.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <type_traits>

namespace atmoglobe::tools {

namespace {
// --range/--opacity/--crop/--crop-heights (prefix "--") or their --grid- twins.
void addLayerSettingOptions(CLI::Option_group& g, const std::string& prefix, SceneOptions::LayerSettingTexts& t,
                            const std::string& cropNote) {
  g.add_option(prefix + "range", t.ranges,
               "Colour table span MIN,MAX (field units; the table is stretched to it, its opacity ramp too)");
  g.add_option(prefix + "opacity", t.opacities,
               "Opacity ramp ZERO,FULL[,MAX[,PER_M]]: none at and below ZERO, MAX (0..1 per PER_M metres) at and "
               "above FULL");
  g.add_option(prefix + "crop", t.crops,
               "Crop box SOUTH,NORTH,WEST,EAST (deg; west > east crosses the antimeridian); " + cropNote);
  g.add_option(prefix + "crop-heights", t.cropHeights, "Crop heights BOTTOM,TOP (m above mean sea level)");
}

// Layer i's settings from the texts (each given once for all layers or once per layer).
template <typename Pick>
Status pickLayerSettings(const SceneOptions::LayerSettingTexts& t, const std::string& prefix, Pick pick, std::size_t i,
                         engine::VolumeLayerSettings& out) {
  std::string range, opacity, crop, heights;
  for (const Status& st :
       {pick(t.ranges, (prefix + "range").c_str(), i, range),
        pick(t.opacities, (prefix + "opacity").c_str(), i, opacity), pick(t.crops, (prefix + "crop").c_str(), i, crop),
        pick(t.cropHeights, (prefix + "crop-heights").c_str(), i, heights)}) {
    if (!st) return st;
  }
  if (!range.empty()) {
    auto v = parseNumbers(range, 2, 2, prefix + "range");
    if (!v) return v.forwardError();
    out.valueRange = glm::dvec2((*v)[0], (*v)[1]);
  }
  if (!opacity.empty()) {
    auto v = parseNumbers(opacity, 2, 4, prefix + "opacity");
    if (!v) return v.forwardError();
    out.opacity = *v;
  }
  if (!crop.empty()) {
    auto v = parseNumbers(crop, 4, 4, prefix + "crop");
    if (!v) return v.forwardError();
    out.crop.southDeg = (*v)[0];
    out.crop.northDeg = (*v)[1];
    out.crop.westDeg = (*v)[2];
    out.crop.eastDeg = (*v)[3];
  }
  if (!heights.empty()) {
    auto v = parseNumbers(heights, 2, 2, prefix + "crop-heights");
    if (!v) return v.forwardError();
    out.crop.bottomMeters = (*v)[0];
    out.crop.topMeters = (*v)[1];
  }
  return Ok{};
}
}  // namespace

void addQuietOption(CLI::App& c) {
  c.add_flag_callback(
      "-q,--quiet", [] { globe::setDefaultProgressStyle(globe::ProgressStyle::Quiet); },
      "No progress output (a bar on a terminal, plain lines otherwise)");
}

void addSceneOptions(CLI::App& c, SceneOptions& o) {
  addQuietOption(c);
  c.add_option("scene", o.sceneFile, "Scene file (JSON; see README). Default: the embedded default scene");
  c.add_option("--camera", o.camera,
               "Camera LAT,LON,HEIGHT,HEADING,PITCH,ROLL: degrees, metres above the WGS84 ellipsoid, "
               "heading clockwise from north, pitch 0 = horizontal, -90 = down (use --camera=-33,... "
               "when the first value is negative)");
  c.add_option("--fov", o.fovDeg, "Vertical field of view (degrees)");
  c.add_option("--memory-budget", o.memoryBudgetMb,
               "Memory budget of time steps and loop volumes, MiB (CPU data and GPU textures; steps not shown are "
               "dropped least recently used and read again; default a quarter of RAM; docs/memory.md)");
  c.add_option("--exaggeration", o.exaggeration,
               "Vertical exaggeration of radars, grids, slices and markers alike (0.1..100; 1 = true scale)");
  c.add_option("--size", o.size, "Image size WxH in pixels (e.g. 1280x720)");
  c.add_option("--imagery", o.imageryDirs,
               "Imagery pyramid directory made by `atmoglobe tiles` (replaces the scene's layers; repeatable)");
  c.add_option("--xyz", o.xyzDirs,
               "XYZ (slippy map, web mercator) directory {z}/{x}/{y}.png|jpg drawn over "
               "the base imagery where it has data (repeatable)");
  c.add_option("--marker", o.markers, "Marker LAT,LON[,HEIGHT[,LABEL]] (repeatable)");
  c.add_option("--stations", o.stations,
               "Station list to draw as markers: CSV (header with id, lat, lon[, elevation]) "
               "or JSON (array of objects, or id -> object)");
  c.add_option("--cones", o.models,
               "A cone export (.glb from `atmoglobe export-cones`) to draw at its place (repeatable)");
  auto* mg = c.add_option_group("Map context", "Coastlines and borders (GSHHG, Debian gmt-gshhg), vector overlays");
  mg->add_flag("--no-map", o.noMap, "No coastlines, country or state borders (drawn by default)");
  mg->add_option("--overlay", o.overlays,
                 "Vector file drawn as map lines: GeoJSON, shapefile, KML/KMZ, GeoPackage, ... (GDAL/OGR; any CRS; "
                 "repeatable)");
  mg->add_flag("--range-rings", o.rangeRings,
               "Range rings every 50 km and azimuth spokes every 30 deg around each radar");
  auto* gg =
      c.add_option_group("Forecast grids", "Each option below is given once (all grids) or once per --grid, in order");
  gg->add_option("--grid", o.grids,
                 "Forecast grid to ray-march (CF or WRF netCDF, GRIB 1 or 2; repeatable; replaces the scene's grids)");
  gg->add_option("--var", o.variables, "Grid variable (default: the file's default, see `atmoglobe info`)");
  gg->add_option("--time", o.times, "Grid time step: an index (0 = first) or an ISO 8601 UTC time");
  gg->add_option("--member", o.members,
                 "Grid ensemble member (GRIB `number`, listed by `atmoglobe info`; default: the first)")
      ->check(CLI::NonNegativeNumber);
  gg->add_option("--ensemble", o.ensembles,
                 "Grid: a statistic over every ensemble member instead of one member: mean, spread (standard "
                 "deviation), min, max, or prob:>=VALUE (also >, <=, <; the percentage of members passing)");
  addGridIndexOption(gg, o.gridIndex);
  gg->add_option(
      "--grid-colors", o.gridColors,
      "Grid colour table: auto (by the variable: NWS for dBZ, turbo for temperature, greens for humidity, grayscale for cloud, viridis otherwise), viridis, turbo, grayscale, greens, cividis, NWS or a .pal file");
  gg->add_option("--grid-mode", o.gridModes, "Grid rendering: dvr, mip or iso");
  addLayerSettingOptions(*gg, "--grid-", o.gridSettings, "only its columns are read");
  gg->add_option("--grid-step", o.gridSteps,
                 "Grid ray-march step (m; the radars' step integrates both where they overlap)");
  gg->add_option("--grid-samples-per-cell", o.gridSamplesPerCell,
                 "Grid step that follows the cells: about this many samples per cell crossed, never shorter than "
                 "--grid-step (0: the fixed step; docs/volume-rendering.md, \"The step rule\")");
  gg->add_option("--grid-image-scale", o.gridImageScales,
                 "Grid volume image resolution relative to the frame, 0.05..1 (default 1)");
  gg->add_option("--grid-refine-threshold", o.gridRefineThresholds,
                 "With --grid-image-scale < 1: march again at full resolution every pixel whose neighbourhood in the "
                 "small image varies by more than this many 8-bit steps (0..255; default -1: off; docs/grids.md, "
                 "\"Adaptive refinement\")");
  gg->add_option("--grid-lod", o.gridLod,
                 "Grid level of detail: on (default: a coarser copy of the grid where a pixel spans several of its "
                 "columns, docs/grids.md \"Level of detail\") or off (always the grid itself)")
      ->check(CLI::IsMember({"on", "off"}));
  gg->add_option("--grid-near-window", o.gridNearWindow,
                 "A grid too large for the GPU, drawn coarser than its own resolution: the columns nearest the eye at "
                 "full resolution with the rest (on, default; docs/grids.md \"Near and far in one frame\") or one "
                 "resolution throughout (off)")
      ->check(CLI::IsMember({"on", "off"}));
  auto* sf = c.add_option_group(
      "Surface fields (maps)",
      "A grid's 2-D field draped on the globe, filled and/or contoured; each option below is given once (all) or "
      "once per --surface, in order");
  sf->add_option("--surface", o.surfaces,
                 "Grid file (CF or WRF netCDF, GRIB 1 or 2) whose 2-D field to drape on the globe (repeatable; "
                 "replaces the scene's surfaces)");
  sf->add_option("--surface-var", o.surfaceVars, "Its variable (a 2-D one, or a 3-D one with --surface-pressure-hpa)");
  sf->add_option("--surface-time", o.surfaceTimes, "Its time step: an index (0 = first) or an ISO 8601 UTC time");
  sf->add_option("--surface-member", o.surfaceMembers, "Its ensemble member (GRIB `number`)");
  sf->add_option("--surface-ensemble", o.surfaceEnsembles,
                 "A statistic over every member: mean, spread, min, max or prob:>=V (as --ensemble)");
  sf->add_option(
      "--surface-pressure-hpa", o.surfacePressuresHpa,
      "A 3-D variable's isobaric surface at this pressure (hPa; grids on pressure, hybrid, sigma or WRF eta levels)");
  sf->add_option("--surface-level", o.surfaceLevels, "A 3-D variable's level (0 = the lowest; model levels too)");
  sf->add_option("--surface-colors", o.surfaceColors, "Colour table (as --grid-colors; default auto)");
  sf->add_option("--surface-range", o.surfaceRanges, "Colour table span MIN,MAX (field units)");
  sf->add_option("--surface-opacity", o.surfaceOpacities, "Opacity of the fill, 0..1 (default 0.75; 0: contours only)");
  sf->add_option("--surface-contour-interval", o.surfaceContourIntervals,
                 "Contour lines every this many field units, labelled (e.g. 400 for geopotential in m2 s-2; 0: none)");
  sf->add_option("--surface-contour-values", o.surfaceContourValues,
                 "Contour lines at these values, e.g. 5400,5700 (one value: \"5400,\")");
  sf->add_flag("--surface-no-fill", o.surfaceNoFill, "Contours only, no colour fill (every --surface)");
  sf->add_option("--surface-wind", o.surfaceWinds,
                 "Wind barbs from the file's u and v: auto (by standard name or name: u/v, 10u/10v, U/V ...) or "
                 "U,V; with no --surface-var the fill is the wind speed; none: no barbs");
  auto* sl = c.add_option_group("Slices", "Drawn on the globe, of the scene's first radar (else its first grid)");
  sl->add_option("--slice-height-m", o.sliceHeights, "A CAPPI at this height above sea level (m; repeatable)");
  sl->add_option("--slice-path", o.slicePaths,
                 "A vertical cross-section along geodesics through \"LAT,LON;LAT,LON[;...]\" (repeatable)");
  auto* g =
      c.add_option_group("Radar volumes", "Each option below is given once (all radars) or once per --radar, in order");
  g->add_option(
      "--radar", o.radars,
      "Radar file to ray-march (CfRadial, ODIM_H5, NEXRAD Level II; repeatable; replaces the scene's radars); "
      "or ONE volume split over files: a directory, a quoted glob (\"dir/*.h5\") or a comma-separated list");
  g->add_option("--field", o.fields, "Field to render (default: reflectivity)");
  g->add_option(
      "--colors", o.colors,
      "Colour table: auto (by the field's kind: NWS for reflectivity, a diverging table over +-Nyquist for velocity, ...), NWS, cividis, velocity or a GR/WCT .pal file");
  g->add_option("--mode", o.modes, "dvr (volume rendering), mip (maximum intensity) or iso (isosurface)");
  g->add_option("--step", o.steps, "Ray-march step (m); default 250");
  g->add_option("--samples-per-cell", o.samplesPerCell,
                "Radar step that follows the gates and the beam's width: about this many samples per cell crossed, "
                "never shorter than --step (default 0: the fixed step; docs/volume-rendering.md, \"The step rule\")");
  g->add_option("--interpolation", o.interpolations, "nearest or linear (default)");
  g->add_option("--image-scale", o.imageScales, "Volume image resolution relative to the frame, 0.05..1 (default 1)");
  g->add_option("--refine-threshold", o.refineThresholds,
                "With --image-scale < 1: march again at full resolution every pixel whose neighbourhood in the small "
                "image varies by more than this many 8-bit steps (0..255; default -1: off; docs/volume-rendering.md, "
                "\"Adaptive refinement\")");
  g->add_option("--iso", o.isoValues, "Isosurface value (field units; default 40)");
  g->add_option("--beam", o.beams, "Beam model: 4/3 (default) or straight");
  g->add_option("--overlap", o.overlaps,
                "A --radar set holding several sites is a network drawn as one volume: where radars overlap, mean "
                "(default; weights exp(-(range/50 km)^2)), lowest (the lowest beam's radar) or max (docs/networks.md)");
  g->add_option("--window-minutes", o.windowMinutes,
                "Networks: at each time, every site's latest volume at most this old (default 10)");
  g->add_option("--classification", o.classifications,
                "DVR between samples: point (default; each sample over one step) or preintegrated (neighbouring "
                "samples as a linear segment: lower error at any step for 5-12 % more time)");
  g->add_option("--far-field", o.farFields,
                "Networks seen from far away (every pixel over them 2 km or wider): auto draws them from slabs "
                "integrated down the vertical once instead of a march per pixel; off always marches. Default: "
                "auto in view (the slabs are made over frames), off in render (its one frame would pay for "
                "making them) (docs/networks.md, \"The far field\")");
  addLayerSettingOptions(*g, "--", o.radarSettings, "gates outside are not drawn");
  g->add_flag("--no-geoid", o.noGeoid, "Take antenna heights as ellipsoidal (no EGM96 conversion)");
}

std::string dataDirectory() {
  if (const char* d = std::getenv("ATMOGLOBE_DATA_DIR"); d && *d) return d;
  return ATMOGLOBE_DATA_DIR;
}

Result<std::vector<double>> parseNumbers(const std::string& text, std::size_t minCount, std::size_t maxCount,
                                         const std::string& what) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || errno != 0 || !std::isfinite(v)) {
      return makeError(what + ": \"" + item + "\" is not a finite number");
    }
    values.push_back(v);
  }
  if (values.size() < minCount || values.size() > maxCount) {
    return makeError(what + ": expected " + std::to_string(minCount) +
                     (minCount == maxCount ? "" : ".." + std::to_string(maxCount)) + " comma-separated numbers, got " +
                     std::to_string(values.size()));
  }
  return values;
}

namespace {
std::string keyAt(const std::string& origin, const char* key, const std::string& option) {
  return engine::sceneKeyAt(origin, key, option);
}

// A per-layer option given once (every layer) or once per layer: layer i's value into `out`
// (untouched when the option is not given).
template <class V, class T>
Status pickPerLayer(const std::vector<V>& values, const char* name, const char* layerOption, std::size_t layers,
                    std::size_t i, T& out) {
  if (values.empty()) return Ok{};
  if (values.size() != 1 && values.size() != layers) {
    return makeError(std::string(name) + ": give it once or once per " + layerOption + " (" + std::to_string(layers) +
                     ")");
  }
  out = values.size() == 1 ? values[0] : values[i];
  return Ok{};
}
}  // namespace

Result<engine::CameraPose> parseCameraPose(const std::string& text) {
  auto v = parseNumbers(text, 3, 6, "--camera");
  if (!v) return v.forwardError();
  engine::CameraPose pose;
  pose.latDeg = (*v)[0];
  pose.lonDeg = (*v)[1];
  pose.heightMeters = (*v)[2];
  pose.headingDeg = v->size() > 3 ? (*v)[3] : 0.0;
  pose.pitchDeg = v->size() > 4 ? (*v)[4] : -90.0;
  pose.rollDeg = v->size() > 5 ? (*v)[5] : 0.0;
  if (auto s = engine::validatePose(pose); !s) return makeError("--camera: " + s.error());
  return pose;
}

Status parseSize(const std::string& text, int* widthPx, int* heightPx) {
  const auto x = text.find('x');
  char* end1 = nullptr;
  char* end2 = nullptr;
  if (x == std::string::npos) return makeError("--size: expected WxH, e.g. 1280x720, got \"" + text + "\"");
  const std::string ws = text.substr(0, x), hs = text.substr(x + 1);
  const long w = std::strtol(ws.c_str(), &end1, 10), h = std::strtol(hs.c_str(), &end2, 10);
  if (ws.empty() || hs.empty() || *end1 || *end2 || w < 1 || h < 1 || w > 16384 || h > 16384) {
    return makeError("--size: expected WxH with integers in 1..16384, got \"" + text + "\"");
  }
  *widthPx = static_cast<int>(w);
  *heightPx = static_cast<int>(h);
  return Ok{};
}

Result<engine::SceneDescription> resolveScene(const SceneOptions& o) {
  Result<engine::SceneDescription> scene = makeError("no scene");
  if (o.sceneFile.empty()) {
    auto text = embeddedAsset("default_scene.json");
    if (!text) return makeError("the default scene is not embedded in this build");
    scene = engine::parseSceneJson(*text, "default scene", "", dataDirectory());
  } else {
    scene = engine::loadSceneFile(o.sceneFile, dataDirectory());
  }
  if (!scene) return scene;
  if (!o.camera.empty()) {
    auto pose = parseCameraPose(o.camera);
    if (!pose) return pose.forwardError();
    scene->camera = *pose;
  }
  if (o.exaggeration != 0.0) {
    if (auto st = volume::validateVerticalExaggeration(o.exaggeration, "--exaggeration"); !st) return st.forwardError();
    scene->verticalExaggeration = o.exaggeration;
  }
  if (o.memoryBudgetMb != 0.0) {
    if (!(o.memoryBudgetMb > 0.0 && o.memoryBudgetMb <= 1.0e9))
      return makeError("--memory-budget: must be in (0, 1e9] MiB");
    scene->memoryBudgetMb = o.memoryBudgetMb;
  }
  if (o.fovDeg != 0.0) {
    if (!(o.fovDeg > 0.0 && o.fovDeg < 180.0)) return makeError("--fov: must be in (0, 180) degrees");
    scene->fovYDeg = o.fovDeg;
  }
  if (!o.size.empty()) {
    if (auto s = parseSize(o.size, &scene->widthPx, &scene->heightPx); !s) return s.forwardError();
  }
  auto& origins = scene->origins;
  if (!o.imageryDirs.empty()) {
    scene->imagery.clear();
    origins.imagery.clear();
    for (const std::string& d : o.imageryDirs) {
      scene->imagery.push_back({engine::ImageryLayerDescription::Type::Pyramid, d});
      origins.imagery.push_back("--imagery");
    }
  }
  origins.imagery.resize(scene->imagery.size());
  for (const std::string& d : o.xyzDirs) {
    scene->imagery.push_back({engine::ImageryLayerDescription::Type::Xyz, d});
    origins.imagery.push_back("--xyz");
  }
  for (const std::string& m : o.markers) {
    // LAT,LON[,HEIGHT[,LABEL]]: the label is everything after the third comma.
    std::string numbers = m, label;
    std::size_t commas = 0, pos = 0;
    for (; pos < m.size(); ++pos) {
      if (m[pos] == ',' && ++commas == 3) break;
    }
    if (commas == 3) {
      numbers = m.substr(0, pos);
      label = m.substr(pos + 1);
    }
    auto v = parseNumbers(numbers, 2, 3, "--marker");
    if (!v) return v.forwardError();
    engine::Marker marker;
    marker.latDeg = (*v)[0];
    marker.lonDeg = (*v)[1];
    marker.heightMeters = v->size() > 2 ? (*v)[2] : 0.0;
    marker.label = label;
    if (auto s = globe::validateGeodetic({marker.latDeg, marker.lonDeg, marker.heightMeters}, "--marker"); !s) {
      return s.forwardError();
    }
    scene->markers.push_back(marker);
  }
  if (!o.stations.empty()) {
    scene->stationsPath = o.stations;
    origins.stations = "--stations";
  }
  if (o.noMap) scene->mapContext = false;
  if (o.rangeRings) scene->rangeRings = true;
  origins.overlays.resize(scene->overlays.size());
  for (const std::string& path : o.overlays) {
    engine::MapOverlayDescription d;
    d.path = path;
    scene->overlays.push_back(d);
    origins.overlays.push_back("--overlay");
  }
  for (const std::string& m : o.models) scene->models.push_back(m);
  // --surface replaces the scene's surfaces; each setting once (all) or once per --surface.
  const std::size_t ns = o.surfaces.size();
  if (ns == 0 &&
      (!o.surfaceVars.empty() || !o.surfaceTimes.empty() || !o.surfaceMembers.empty() || !o.surfaceEnsembles.empty() ||
       !o.surfacePressuresHpa.empty() || !o.surfaceColors.empty() || !o.surfaceRanges.empty() ||
       !o.surfaceOpacities.empty() || !o.surfaceContourIntervals.empty() || !o.surfaceContourValues.empty() ||
       o.surfaceNoFill || !o.surfaceWinds.empty() || !o.surfaceLevels.empty()))
    return makeError("--surface-* options need a --surface");
  if (ns > 0) {
    scene->surfaces.clear();
    origins.surfaces.clear();
  }
  for (std::size_t i = 0; i < ns; ++i) {
    engine::SurfaceLayerDescription d;
    d.path = o.surfaces[i];
    d.useGeoid = !o.noGeoid;
    d.fill = !o.surfaceNoFill;
    std::string range, values;
    double pressure = 0.0, interval = 0.0;
    int level = 0;
    auto pickS = [&](const auto& v, const char* name, auto& out) {
      return pickPerLayer(v, name, "--surface", ns, i, out);
    };
    for (const Status& st :
         {pickS(o.surfaceVars, "--surface-var", d.variable), pickS(o.surfaceTimes, "--surface-time", d.time),
          pickS(o.surfaceMembers, "--surface-member", d.member),
          pickS(o.surfaceEnsembles, "--surface-ensemble", d.ensemble),
          pickS(o.surfacePressuresHpa, "--surface-pressure-hpa", pressure),
          pickS(o.surfaceColors, "--surface-colors", d.colors), pickS(o.surfaceRanges, "--surface-range", range),
          pickS(o.surfaceOpacities, "--surface-opacity", d.opacity),
          pickS(o.surfaceContourIntervals, "--surface-contour-interval", interval),
          pickS(o.surfaceContourValues, "--surface-contour-values", values),
          pickS(o.surfaceWinds, "--surface-wind", d.wind), pickS(o.surfaceLevels, "--surface-level", level)}) {
      if (!st) return st.forwardError();
    }
    if (!o.surfacePressuresHpa.empty()) d.pressureHpa = pressure;
    if (d.wind == "none") d.wind.clear();
    if (!o.surfaceLevels.empty()) d.level = level;
    if (!o.surfaceContourIntervals.empty() && interval != 0.0) d.contourInterval = interval;  // 0: none
    if (!o.surfaceOpacities.empty() && d.opacity == 0.0) d.fill = false;
    if (!range.empty()) {
      auto r = parseNumbers(range, 2, 2, "--surface-range");
      if (!r) return r.forwardError();
      d.valueRange = glm::dvec2((*r)[0], (*r)[1]);
    }
    if (!values.empty()) {
      auto levels = map::parseContourLevels("", values);
      if (!levels) return makeError("--surface-contour-values: " + levels.error());
      d.contourValues = levels->values;
    }
    if (auto st = engine::validateSurfaceLayer(d, "--surface " + d.path); !st) return st.forwardError();
    scene->surfaces.push_back(std::move(d));
    origins.surfaces.push_back("--surface");
  }
  // Data named on the command line is what the user wants to see: over the embedded default scene
  // (no scene file) it replaces the default's SYNTHETIC radar whatever its kind, so a grid named
  // alone is drawn alone.
  if (o.sceneFile.empty() && (!o.radars.empty() || !o.grids.empty() || !o.surfaces.empty())) {
    scene->volumes.clear();
    origins.volumes.clear();
  }
  // --radar and --grid each replace the scene's layers of their kind (like --imagery); the radars
  // stay first, as the scene file lists them.
  auto replaceKind = [&](engine::VolumeKind kind, std::vector<engine::VolumeLayerDescription> layers,
                         const char* option) {
    std::vector<engine::VolumeLayerDescription> volumes;
    std::vector<std::string> volumeOrigins;
    origins.volumes.resize(scene->volumes.size());
    for (std::size_t i = 0; i < scene->volumes.size(); ++i) {
      if (scene->volumes[i].kind == kind) continue;
      volumes.push_back(scene->volumes[i]);
      volumeOrigins.push_back(origins.volumes[i]);
    }
    const auto at = kind == engine::VolumeKind::Radar ? 0 : static_cast<std::ptrdiff_t>(volumes.size());
    volumes.insert(volumes.begin() + at, layers.begin(), layers.end());
    volumeOrigins.insert(volumeOrigins.begin() + at, layers.size(), option);
    scene->volumes = std::move(volumes);
    origins.volumes = std::move(volumeOrigins);
  };
  // An enumerated setting given as text (VolumeLayer.h's spellings).
  auto pickEnum = [](const std::vector<std::string>& values, const char* name, const char* layerOption,
                     std::size_t layers, std::size_t i, auto& out) -> Status {
    using E = std::decay_t<decltype(out)>;
    std::string text = engine::nameOf(out);
    if (auto st = pickPerLayer(values, name, layerOption, layers, i, text); !st) return st;
    const auto value = engine::parseName<E>(text);
    if (!value) return makeError(std::string(name) + ": \"" + text + "\" is not one of " + engine::quotedNames<E>());
    out = *value;
    return Ok{};
  };
  const std::size_t nr = o.radars.size();
  auto pick = [&](const auto& values, const char* name, std::size_t i, auto& out) {
    return pickPerLayer(values, name, "--radar", nr, i, out);
  };
  if (nr == 0 &&
      (!o.fields.empty() || !o.colors.empty() || !o.modes.empty() || !o.steps.empty() || !o.interpolations.empty() ||
       !o.beams.empty() || !o.classifications.empty() || !o.overlaps.empty() || !o.farFields.empty() ||
       !o.windowMinutes.empty() || !o.imageScales.empty() || !o.refineThresholds.empty() || !o.isoValues.empty() ||
       !o.radarSettings.empty() || !o.samplesPerCell.empty())) {
    return makeError(
        "--field/--colors/--mode/--step/--samples-per-cell/--interpolation/--beam/--classification/--overlap/--far-field/"
        "--window-minutes/"
        "--image-scale/--refine-threshold/--iso/--range/--opacity/"
        "--crop/--crop-heights need a --radar");
  }
  std::vector<engine::VolumeLayerDescription> radars;
  for (std::size_t i = 0; i < nr; ++i) {
    engine::VolumeLayerDescription d;
    d.kind = engine::VolumeKind::Radar;
    d.path = o.radars[i];
    d.useGeoid = !o.noGeoid;
    double iso = 0.0;
    engine::FarField farField = engine::FarField::Off;
    for (const Status& st :
         {pick(o.fields, "--field", i, d.field), pick(o.colors, "--colors", i, d.colors),
          pickEnum(o.modes, "--mode", "--radar", nr, i, d.mode),
          pickEnum(o.interpolations, "--interpolation", "--radar", nr, i, d.interpolation),
          pickEnum(o.beams, "--beam", "--radar", nr, i, d.beam),
          pickEnum(o.classifications, "--classification", "--radar", nr, i, d.classification),
          pickEnum(o.farFields, "--far-field", "--radar", nr, i, farField), pick(o.steps, "--step", i, d.stepMeters),
          pick(o.samplesPerCell, "--samples-per-cell", i, d.samplesPerCell),
          pick(o.imageScales, "--image-scale", i, d.imageScale),
          pick(o.refineThresholds, "--refine-threshold", i, d.refineThreshold), pick(o.isoValues, "--iso", i, iso),
          pick(o.windowMinutes, "--window-minutes", i, d.windowMinutes)}) {
      if (!st) return st.forwardError();
    }
    if (!o.overlaps.empty()) {
      std::string rule;
      if (auto st = pick(o.overlaps, "--overlap", i, rule); !st) return st.forwardError();
      auto parsed = volume::parseOverlapRule(rule);
      if (!parsed) return makeError("--overlap: " + parsed.error());
      d.overlap = *parsed;
    }
    if (!o.isoValues.empty()) d.isoValue = iso;
    if (!o.farFields.empty()) d.farField = farField;  // else the command's default (engine::setUnsetFarField)
    if (auto st = pickLayerSettings(o.radarSettings, "--", pick, i, d.settings); !st) return st.forwardError();
    if (auto st = engine::validateVolumeLayer(d, "--radar"); !st) return st.forwardError();
    if (d.refineThreshold >= 0.0 && d.imageScale >= 1.0)
      return makeError("--refine-threshold refines an image marched at --image-scale below 1; give one");
    radars.push_back(d);
  }
  if (nr > 0) replaceKind(engine::VolumeKind::Radar, std::move(radars), "--radar");
  const std::size_t ng = o.grids.size();
  auto pickGrid = [&](const auto& values, const char* name, std::size_t i, auto& out) {
    return pickPerLayer(values, name, "--grid", ng, i, out);
  };
  if (ng == 0 && (!o.variables.empty() || !o.times.empty() || !o.members.empty() || !o.ensembles.empty() ||
                  !o.gridIndex.empty() || !o.gridColors.empty() || !o.gridModes.empty() || !o.gridSteps.empty() ||
                  !o.gridSettings.empty() || !o.gridLod.empty() || !o.gridNearWindow.empty() ||
                  !o.gridSamplesPerCell.empty() || !o.gridImageScales.empty() || !o.gridRefineThresholds.empty())) {
    return makeError(
        "--var/--time/--member/--ensemble/--grid-index/--grid-colors/--grid-mode/--grid-step/--grid-samples-per-cell/"
        "--grid-image-scale/--grid-refine-threshold/--grid-lod/--grid-near-window/--grid-range/--grid-opacity/--grid-crop/--grid-crop-heights "
        "need a --grid");
  }
  std::vector<engine::VolumeLayerDescription> grids;
  for (std::size_t i = 0; i < ng; ++i) {
    engine::VolumeLayerDescription d;
    d.kind = engine::VolumeKind::Grid;
    d.path = o.grids[i];
    d.useGeoid = !o.noGeoid;
    d.gridIndex = o.gridIndex;
    for (const Status& st :
         {pickGrid(o.variables, "--var", i, d.field), pickGrid(o.times, "--time", i, d.time),
          pickGrid(o.members, "--member", i, d.member), pickGrid(o.gridColors, "--grid-colors", i, d.colors),
          pickEnum(o.gridModes, "--grid-mode", "--grid", ng, i, d.mode),
          pickGrid(o.gridSteps, "--grid-step", i, d.stepMeters),
          pickGrid(o.gridSamplesPerCell, "--grid-samples-per-cell", i, d.samplesPerCell),
          pickGrid(o.gridImageScales, "--grid-image-scale", i, d.imageScale),
          pickGrid(o.gridRefineThresholds, "--grid-refine-threshold", i, d.refineThreshold)}) {
      if (!st) return st.forwardError();
    }
    std::string ensemble;
    if (auto st = pickGrid(o.ensembles, "--ensemble", i, ensemble); !st) return st.forwardError();
    if (!ensemble.empty()) {
      auto stat = volume::parseEnsembleStatistic(ensemble);
      if (!stat) return makeError("--ensemble: " + stat.error());
      if (d.member >= 0) return makeError("--ensemble combines every member: not with --member");
      d.ensemble = *stat;
    }
    std::string lod;
    if (auto st = pickGrid(o.gridLod, "--grid-lod", i, lod); !st) return st.forwardError();
    if (!lod.empty()) d.levelOfDetail = lod == "on";
    std::string nearWindow;
    if (auto st = pickGrid(o.gridNearWindow, "--grid-near-window", i, nearWindow); !st) return st.forwardError();
    if (!nearWindow.empty()) d.nearWindow = nearWindow == "on";
    if (auto st = pickLayerSettings(o.gridSettings, "--grid-", pickGrid, i, d.settings); !st) return st.forwardError();
    if (auto st = engine::validateVolumeLayer(d, "--grid"); !st) return st.forwardError();
    if (d.refineThreshold >= 0.0 && d.imageScale >= 1.0)
      return makeError("--grid-refine-threshold refines an image marched at --grid-image-scale below 1; give one");
    grids.push_back(d);
  }
  if (ng > 0) replaceKind(engine::VolumeKind::Grid, std::move(grids), "--grid");
  if (!o.sliceHeights.empty() || !o.slicePaths.empty()) {
    engine::SliceLayerDescription base;
    // The first radar, else the first grid.
    auto first = std::find_if(scene->volumes.begin(), scene->volumes.end(),
                              [](const auto& v) { return v.kind == engine::VolumeKind::Radar; });
    if (first == scene->volumes.end()) first = scene->volumes.begin();
    if (first != scene->volumes.end()) {
      const bool radar = first->kind == engine::VolumeKind::Radar;
      base.source = {radar ? volume::SliceSourceOptions::Kind::Radar : volume::SliceSourceOptions::Kind::Grid,
                     first->path,
                     first->field,
                     first->time,
                     first->useGeoid,
                     first->member,
                     first->gridIndex,
                     first->ensemble};
    } else {
      return makeError("--slice-height-m/--slice-path need a radar or a grid in the scene");
    }
    for (double h : o.sliceHeights) {
      engine::SliceLayerDescription d = base;
      d.request.heightMeters = h;
      scene->slices.push_back(d);
    }
    for (const std::string& p : o.slicePaths) {
      auto points = volume::parsePathText(p);
      if (!points) return makeError("--slice-path: " + points.error());
      engine::SliceLayerDescription d = base;
      d.request.cappi = false;
      d.request.path = *points;
      scene->slices.push_back(d);
    }
  }
  // Data named over the default scene without --camera: the camera frames that data
  // (engine/Framing.h), not the default scene's place. A file whose metadata cannot be read
  // leaves the camera as it is (loading it reports the error).
  if (o.sceneFile.empty() && o.camera.empty() && (!o.radars.empty() || !o.grids.empty() || !o.surfaces.empty())) {
    if (auto target = engine::framingTargetOfVolumes(*scene)) {
      scene->camera = engine::poseFraming(*target, scene->fovYDeg, scene->widthPx, scene->heightPx);
      char line[200];
      std::snprintf(line, sizeof line,
                    "camera framing the named data: above %.3f, %.3f at %.0f km, looking down (--camera sets it)",
                    scene->camera.latDeg, scene->camera.lonDeg, scene->camera.heightMeters / 1000.0);
      std::cerr << "atmoglobe: " << line << "\n";
    }
  }
  // A missing imagery directory leaves that layer out (said in inputErrors: the rest renders).
  std::vector<engine::ImageryLayerDescription> present;
  std::vector<std::string> presentOrigins;
  for (std::size_t i = 0; i < scene->imagery.size(); ++i) {
    const auto& layer = scene->imagery[i];
    const std::string origin = engine::layerOrigin(origins.imagery, i, "--imagery");
    if (!std::filesystem::exists(layer.path)) {
      std::string hint;
      if (layer.path.rfind(dataDirectory(), 0) == 0) {
        hint =
            " (the default imagery is built by ./run.sh, or: atmoglobe tiles "
            "/usr/share/xplanet/images/earth.jpg -o " +
            dataDirectory() + "/earth)";
      }
      scene->inputErrors.push_back(keyAt(origin, "path", origin) + ": imagery directory not found: " + layer.path +
                                   hint);
      continue;
    }
    present.push_back(layer);
    presentOrigins.push_back(origin);
  }
  scene->imagery = std::move(present);
  origins.imagery = std::move(presentOrigins);
  return scene;
}

}  // namespace atmoglobe::tools
