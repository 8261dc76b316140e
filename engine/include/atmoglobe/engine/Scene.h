#pragma once
// A scene description: what to draw and from where. GL-free (parsed and validated on the
// CPU; the GL renderers consume it).
//
// JSON form (every key optional; unknown keys are errors, so typos do not pass silently):
// {
//   "camera":  {"lat_deg": 47, "lon_deg": 8, "height_m": 2e6,
//               "heading_deg": 0, "pitch_deg": -90, "roll_deg": 0},
//   "fov_deg": 60,
//   "vertical_exaggeration": 1,
//   "size":    [1280, 720],
//   "imagery": [{"type": "pyramid", "path": "@data/earth"},      // bottom layer first
//               {"type": "xyz", "path": "my_xyz_tiles"}],
//   "markers": [{"lat_deg": 33.65, "lon_deg": -101.81, "height_m": 1000,
//                "label": "KLBB", "color": [1, 0.2, 0.1], "size_px": 14}],
//   "stations": "stations.csv",                                // CSV or JSON station list
//   "radars":  [{"path": "KLBB.ar2v", "field": "REF", "colors": "NWS", "mode": "dvr",
//                "interpolation": "linear", "step_m": 250, "image_scale": 1.0,
//                "iso_dbz": 40, "beam": "4/3", "classification": "point", "label": "KLBB"}],
//   "slices":  [{"radar": "KLBB.ar2v", "height_m": 3000}],    // keys: SliceLayer.h
//   "map_context": true,                                       // GSHHG coastlines and borders
//   "overlays": [{"path": "counties.shp", "color": [1, 0.8, 0.2], "width_px": 1.5}],
//   "range_rings": false                                       // every 50 km, spokes every 30 deg
// }
// Relative paths are relative to the scene file's directory; "@data/" stands for the
// directory of generated default data (ATMOGLOBE_DATA_DIR).
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/SliceLayer.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/Crop.h>

#include <glm/glm.hpp>

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::engine {

struct Marker {
  double latDeg = 0.0;
  double lonDeg = 0.0;
  double heightMeters = 0.0;  ///< above the WGS84 ellipsoid (m)
  glm::vec3 color{1.0f, 0.2f, 0.1f};
  float sizePx = 14.0f;  ///< sprite diameter (pixels)
  std::string label;
};

struct ImageryLayerDescription {
  enum class Type { Pyramid, Xyz };
  Type type = Type::Pyramid;
  std::string path;  ///< resolved (absolute or relative to the working directory)
};

/// What users set on any volume layer, radar or grid (JSON keys "range", "opacity", "crop",
/// "crop_heights_m"; CLI --range/--opacity/--crop/--crop-heights and their --grid- twins).
struct VolumeLayerSettings {
  /// The colour table's span (min, max; field units). Empty: the kind's default (reflectivity
  /// -10..70 dBZ, velocity +-Nyquist, model variables their values' range).
  std::optional<glm::dvec2> valueRange;
  /// Opacity ramp: [zero, full] values (field units): opacity 0 at and below zero, the maximum
  /// at and above full; optionally [.., max] (0..1, per reference length) and [.., .., .., per_m]
  /// (the reference length, m). Empty: the kind's default ramp.
  std::vector<double> opacity;
  /// Crop box: latitude/longitude and heights above sea level; outside it nothing is drawn
  /// (grids read only its columns). Default: everything.
  volume::CropBox crop;
};

/// Checks the settings (range min < max, opacity 2..4 finite numbers with zero != full, max in
/// [0, 1], per_m > 0, the crop box). `where` starts the message.
Status validateVolumeLayerSettings(const VolumeLayerSettings& settings, const std::string& where);

/// A radar volume to ray-march (see VolumeRendererGL.h and RadarVolumeGL.h for the knobs).
struct RadarLayerDescription {
  std::string path;                      ///< radar file (CfRadial, ODIM_H5, NEXRAD Level II)
  std::string field;                     ///< empty: the reflectivity field
  std::string colors = "auto";           ///< "auto" (by the field's kind), "NWS", "cividis", "velocity" or a .pal file
  std::string mode = "dvr";              ///< dvr | mip | iso
  std::string interpolation = "linear";  ///< nearest | linear
  double stepMeters = 250.0;
  double imageScale = 1.0;
  double isoValue = 40.0;
  std::string beam = "4/3";              ///< "4/3" (effective Earth) or "straight"
  std::string classification = "point";  ///< DVR: "point" or "preintegrated" (VolumeRenderOptions::classification)
  std::string label;                     ///< site marker label; empty: the site name from the file
  bool useGeoid = true;
  VolumeLayerSettings settings;
};

/// A forecast grid to ray-march (GridVolumeGL.h; the reader: volume/GridReader.h).
struct GridLayerDescription {
  std::string path;             ///< NetCDF file (CF or WRF)
  std::string variable;         ///< empty: the file's default variable
  std::string time;             ///< empty: the first step; an index ("3") or an ISO 8601 UTC time
  std::string colors = "auto";  ///< "auto" (cividis over the variable's range), "cividis", "NWS" or a .pal file
  std::string mode = "dvr";     ///< dvr | mip | iso
  std::string interpolation = "linear";  ///< nearest | linear
  double stepMeters = 250.0;             ///< as radars: volumes of one step are integrated together where they overlap
  double imageScale = 1.0;
  double isoValue = std::numeric_limits<double>::quiet_NaN();  ///< NaN: the middle of the value range
  std::string classification = "point";
  bool useGeoid = true;
  /// Range, opacity ramp and crop box. The crop's latitude/longitude box is also what is read
  /// (the reader keeps one more column on each side so the cells cover the box).
  VolumeLayerSettings settings;
};

/// A user vector file drawn as map lines (JSON "overlays", CLI --overlay; MapRendererGL.h).
struct MapOverlayDescription {
  std::string path;                    ///< GeoJSON, shapefile, KML/KMZ, GeoPackage, ... (GDAL/OGR)
  glm::vec3 color{1.0f, 0.85f, 0.2f};  ///< 0..1
  float widthPx = 1.5f;                ///< 0.5..16
};

/// Checks an overlay's colour (0..1) and width (0.5..16 px).
Status validateMapOverlay(const MapOverlayDescription& overlay, const std::string& where);

/// Checks a grid layer's enumerated fields and numbers (as validateRadarLayer).
Status validateGridLayer(const GridLayerDescription& grid, const std::string& where);

struct SceneDescription {
  CameraPose camera;
  double fovYDeg = 60.0;
  int widthPx = 1280;
  int heightPx = 720;
  std::vector<ImageryLayerDescription> imagery;  ///< bottom layer first
  std::vector<Marker> markers;
  std::vector<RadarLayerDescription> radars;
  std::vector<GridLayerDescription> grids;
  std::vector<SliceLayerDescription> slices;  ///< CAPPIs and cross-sections on the globe (SliceLayer.h)
  std::string stationsPath;                   ///< station list drawn as markers (empty: none)
  std::vector<std::string> models;            ///< georeferenced .glb files (cone exports) to draw
  /// Heights above the ellipsoid drawn this many times higher, for every volume, slice and
  /// marker alike (JSON "vertical_exaggeration", CLI --exaggeration; 0.1..100, 1 = true scale).
  double verticalExaggeration = 1.0;
  /// Map context: GSHHG coastlines, country and state borders (JSON "map_context", CLI --no-map).
  bool mapContext = true;
  std::vector<MapOverlayDescription> overlays;  ///< user vector files (JSON "overlays", CLI --overlay)
  bool rangeRings =
      false;  ///< range rings and azimuth spokes around each radar (JSON "range_rings", CLI --range-rings)
  /// Memory budget of time steps and loop volumes, MiB (JSON "memory_budget_mb", CLI
  /// --memory-budget; 0: volume::defaultMemoryBudgetBytes(), a quarter of RAM). docs/memory.md.
  double memoryBudgetMb = 0.0;
};

/// Checks the enumerated fields of a radar layer (mode, interpolation, beam, classification, step, scale).
Status validateRadarLayer(const RadarLayerDescription& radar, const std::string& where);

/// Parses and validates a JSON scene. `sourceName` names it in messages; `baseDir`
/// resolves relative paths; `dataDir` replaces a leading "@data".
Result<SceneDescription> parseSceneJson(std::string_view json, const std::string& sourceName,
                                        const std::string& baseDir, const std::string& dataDir);

/// Reads and parses a scene file.
Result<SceneDescription> loadSceneFile(const std::string& path, const std::string& dataDir);

}  // namespace atmoglobe::engine
