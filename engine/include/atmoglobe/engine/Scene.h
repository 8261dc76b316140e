#pragma once
// A scene description: what to draw and from where. GL-free (parsed and validated on the
// CPU; the GL renderers consume it).
//
// JSON form: docs/scenes.md (every key, its type, units, default and range; examples in
// assets/scenes/). Validation is strict: unknown keys (with the closest known key as a hint),
// wrong types and out-of-range values are errors naming the JSON pointer, e.g.
//   scene.json: /camera/height_m: expected a number, got string
// Relative paths are relative to the scene file's directory; "@data/" stands for the
// directory of generated default data (ATMOGLOBE_DATA_DIR). Whether input files exist is
// checked when they are loaded (checkInputFile), one layer at a time, so that one bad file
// does not stop the others.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/SliceLayer.h>
#include <atmoglobe/engine/SurfaceLayer.h>
#include <atmoglobe/engine/VolumeLayer.h>
#include <atmoglobe/globe/Result.h>

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

/// A user vector file drawn as map lines (JSON "overlays", CLI --overlay; MapRendererGL.h).
struct MapOverlayDescription {
  std::string path;                    ///< GeoJSON, shapefile, KML/KMZ, GeoPackage, ... (GDAL/OGR)
  glm::vec3 color{1.0f, 0.85f, 0.2f};  ///< 0..1
  float widthPx = 1.5f;                ///< 0.5..16
};

/// Checks an overlay's colour (0..1) and width (0.5..16 px).
Status validateMapOverlay(const MapOverlayDescription& overlay, const std::string& where);

struct SceneDescription {
  CameraPose camera;
  double fovYDeg = 60.0;
  int widthPx = 1280;
  int heightPx = 720;
  std::vector<ImageryLayerDescription> imagery;  ///< bottom layer first
  std::vector<Marker> markers;
  /// Radars and grids, in one list (JSON "radars" then "grids"; CLI --radar then --grid): the
  /// order volume layers are added and, by default, handed to the marcher.
  std::vector<VolumeLayerDescription> volumes;
  std::vector<SliceLayerDescription> slices;  ///< CAPPIs and cross-sections on the globe (SliceLayer.h)
  /// Grids' 2-D fields draped on the globe with contours (JSON "surfaces", CLI --surface; SurfaceLayer.h).
  std::vector<SurfaceLayerDescription> surfaces;
  std::string stationsPath;         ///< station list drawn as markers (empty: none)
  std::vector<std::string> models;  ///< georeferenced .glb files (cone exports) to draw
  /// Heights above the ellipsoid drawn this many times higher, for every volume, slice and
  /// marker alike (JSON "vertical_exaggeration", CLI --exaggeration; 0.1..100, 1 = true scale).
  double verticalExaggeration = 1.0;
  /// Map context: GSHHG coastlines, country and state borders (JSON "map_context", CLI --no-map).
  bool mapContext = true;
  std::vector<MapOverlayDescription> overlays;  ///< user vector files (JSON "overlays", CLI --overlay)
  bool rangeRings =
      false;  ///< range rings and azimuth spokes around each radar (JSON "range_rings", CLI --range-rings)
  /// Where each layer was given, for messages: "scene.json: /radars/2" (a JSON pointer) or a CLI
  /// option ("--radar"); parallel to the vectors above (layerOrigin() tolerates missing entries).
  struct Origins {
    std::vector<std::string> imagery, volumes, slices, overlays, surfaces;
    std::string stations;
  } origins;
  /// Input problems found before loading (a missing imagery directory): the layer is left out
  /// and the message kept here, "ORIGIN/KEY: file not found: PATH".
  std::vector<std::string> inputErrors;
  /// Memory budget of time steps and loop volumes, MiB (JSON "memory_budget_mb", CLI
  /// --memory-budget; 0: volume::defaultMemoryBudgetBytes(), a quarter of RAM). docs/memory.md.
  double memoryBudgetMb = 0.0;
};

/// The scene's volume layers of one kind, in order.
std::vector<VolumeLayerDescription> volumesOfKind(const SceneDescription& scene, VolumeKind kind);

/// Sets the far field of every radar layer that leaves it unset (no "far_field" key, no
/// --far-field) to `farField`: the viewer's default, auto (it makes the slabs over frames; 159
/// radars at 1280x720 then draw in tens of milliseconds a frame instead of seconds). `render`
/// leaves them unset, which draws them marched (VolumeLayerDescription::farField).
void setUnsetFarField(SceneDescription& scene, FarField farField);

/// origins[index], or `fallback` when there is none.
std::string layerOrigin(const std::vector<std::string>& origins, std::size_t index, const std::string& fallback);

/// Checks that an input file or directory exists: else "WHERE: file not found: PATH". Radar paths
/// holding a glob ("*?[") or a comma list are left to the reader.
Status checkInputFile(const std::string& path, const std::string& where);

/// Parses and validates a JSON scene. `sourceName` names it in messages; `baseDir`
/// resolves relative paths; `dataDir` replaces a leading "@data".
/// The scene as scene JSON (SceneJsonWrite.cpp): every key parseSceneJson reads, paths resolved
/// (absolute), so that parsing it again describes the same scene (`view`'s "Save scene"; test
/// SceneJson.WrittenScenesReadBackTheSame). Layers given on the command line are written as scene
/// layers; CLI-only inputs (--model) are not part of a scene.
std::string sceneToJson(const SceneDescription& scene);

Result<SceneDescription> parseSceneJson(std::string_view json, const std::string& sourceName,
                                        const std::string& baseDir, const std::string& dataDir);

/// Reads and parses a scene file.
Result<SceneDescription> loadSceneFile(const std::string& path, const std::string& dataDir);

}  // namespace atmoglobe::engine
