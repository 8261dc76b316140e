#pragma once
// Options shared by `render` and `view`: a scene file (or the embedded default scene)
// and command-line overrides of its camera, field of view, size and imagery.
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/ScenePopulate.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Result.h>

#include <CLI/CLI.hpp>

#include <map>
#include <string>
#include <vector>

namespace atmoglobe::tools {

struct SceneOptions {
  std::string sceneFile;
  std::string camera;           ///< "LAT,LON,HEIGHT,HEADING,PITCH,ROLL"
  double fovDeg = 0.0;          ///< 0: the scene's
  double exaggeration = 0.0;    ///< 0: the scene's vertical exaggeration
  double memoryBudgetMb = 0.0;  ///< 0: the scene's memory budget (docs/memory.md)
  std::string size;             ///< "WxH"
  std::vector<std::string> imageryDirs;
  std::vector<std::string> xyzDirs;
  std::vector<std::string> markers;  ///< "LAT,LON[,HEIGHT[,LABEL]]"
  std::string stations;              ///< station list file (CSV or JSON)
  std::vector<std::string> models;   ///< .glb cone exports to draw
  // Radar volumes: one entry per --radar; each per-radar option is given once (applies to
  // every radar) or once per radar, in order.
  std::vector<std::string> radars;
  std::vector<std::string> fields, colors, modes, interpolations, beams, classifications, overlaps, farFields;
  std::vector<double> windowMinutes;
  std::vector<double> steps, imageScales, refineThresholds, isoValues;
  bool noGeoid = false;
  // Forecast grids: one entry per --grid; --var/--time/--grid-colors/--grid-mode/--grid-step
  // once (every grid) or once per grid.
  std::vector<std::string> grids, variables, times, gridColors, gridModes;
  std::vector<int> members;
  std::vector<std::string> ensembles;            ///< --ensemble per grid: mean, spread, min, max, prob:>=V
  std::map<std::string, std::size_t> gridIndex;  ///< --grid-index NAME=I: every grid and slice
  std::vector<double> gridSteps;
  std::vector<double> gridSamplesPerCell;
  std::vector<double> gridImageScales, gridRefineThresholds;  ///< --grid-image-scale, --grid-refine-threshold
  std::vector<std::string> gridLod;                           ///< --grid-lod on|off
  std::vector<std::string> gridNearWindow;                    ///< --grid-near-window on|off
  std::vector<double> samplesPerCell;                         ///< radars' step rule
  /// --surface FILE and its settings, each once (all) or once per --surface.
  std::vector<std::string> surfaces, surfaceVars, surfaceTimes, surfaceEnsembles, surfaceColors, surfaceRanges,
      surfaceContourValues, surfaceWinds;
  std::vector<int> surfaceMembers, surfaceLevels;
  std::vector<double> surfacePressuresHpa, surfaceOpacities, surfaceContourIntervals;
  bool surfaceNoFill = false;
  /// Range, opacity ramp and crop of every volume layer (VolumeLayerSettings), as text:
  /// "MIN,MAX", "ZERO,FULL[,MAX[,PER_M]]", "SOUTH,NORTH,WEST,EAST", "BOTTOM,TOP".
  struct LayerSettingTexts {
    std::vector<std::string> ranges, opacities, crops, cropHeights;
    bool empty() const { return ranges.empty() && opacities.empty() && crops.empty() && cropHeights.empty(); }
  };
  LayerSettingTexts radarSettings, gridSettings;
  // Slices on the globe, of the scene's first radar (else its first grid): each is added.
  std::vector<double> sliceHeights;     ///< CAPPI heights (m above sea level)
  std::vector<std::string> slicePaths;  ///< cross-sections "LAT,LON;LAT,LON[;...]"
  // Map context (MapRendererGL.h).
  bool noMap = false;                 ///< --no-map: no GSHHG coastlines and borders
  std::vector<std::string> overlays;  ///< --overlay FILE (repeatable)
  bool rangeRings = false;            ///< --range-rings
};

/// Exit status of `render` when the picture was written but some inputs failed (each reported);
/// `--strict` makes the first failure fatal (exit 1) instead.
inline constexpr int kExitRenderedWithErrors = 3;

/// The scene options, and `--quiet` (no progress output: globe::setDefaultProgressStyle).
void addSceneOptions(CLI::App& command, SceneOptions& options);

/// `-q,--quiet` on a command: no progress bars or lines (globe/Progress.h).
void addQuietOption(CLI::App& command);

/// Directory of generated default data: $ATMOGLOBE_DATA_DIR, else the build's.
std::string dataDirectory();

/// The scene to render: the file (or the embedded default), then the overrides.
Result<engine::SceneDescription> resolveScene(const SceneOptions& options);

/// Loads what the scene needs beyond imagery into the renderer: radar volumes (their site
/// markers included), forecast grids, slices, overlays and the station list as markers (appended
/// to `markers`). Prints the vertical datum used for each radar to stderr, and progress when there
/// are several inputs (globe/Progress.h).
///
/// engine::populateScene (engine/ScenePopulate.h), as render and view call it.
using engine::populateScene;

Result<engine::CameraPose> parseCameraPose(const std::string& text);
Status parseSize(const std::string& text, int* widthPx, int* heightPx);
/// Comma-separated finite numbers, between minCount and maxCount of them; `what` names the
/// option in the message.
Result<std::vector<double>> parseNumbers(const std::string& text, std::size_t minCount, std::size_t maxCount,
                                         const std::string& what);

}  // namespace atmoglobe::tools
