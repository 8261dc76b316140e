#pragma once
// The time axis of a scene and stepping along it (render --time-series, view's time keys).
//
// The axis is the time steps of the scene's first grid that has more than one, else the volumes
// of its first radar loop (SceneRendererGL::addRadar on a directory, glob or list holding several
// times of one site). Every other grid shows the step with the same valid time (to the second),
// or stays where it is when its file has no such time (said once per grid); every other radar
// loop shows its latest volume at or before the time (what a forecaster sees live). Between two
// steps a fraction in (0, 1) interpolates the grids linearly in time (radar volumes are not
// interpolated: the loop shows the volume of the step).
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Result.h>

#include <cstddef>
#include <string>
#include <vector>

namespace atmoglobe::engine {

struct SceneTimeAxis {
  std::vector<std::string> times;  ///< ISO 8601 UTC valid times of the steps
  bool leadIsRadar = false;        ///< the axis is a radar loop's
  std::size_t leadGrid = 0;        ///< the grid (or radar) whose axis this is
  std::string leadName;            ///< its path, for messages
  /// Per grid (scene order), per step: that grid's step index with the same time, or -1.
  std::vector<std::vector<long>> gridSteps;
  /// Per radar (renderer order), per step: the loop volume shown, or -1 (a single volume).
  std::vector<std::vector<long>> radarSteps;
  /// Grids with no step at some of the axis' times, one line each (for a warning).
  std::vector<std::string> notes;
};

/// The scene's time axis (metadata only: no field values read), for the layers `renderer` holds
/// (populated from `scene`). Errors: no grid with more than one time step and no radar loop (a
/// time series needs one), unreadable files.
Result<SceneTimeAxis> sceneTimeAxis(const SceneDescription& scene, const SceneRendererGL& renderer);

/// Shows step `step` (plus `fraction` of the way to step + 1) on every grid and radar loop of `renderer`
/// (in scene order, as populated from the same scene). The valid time shown is returned.
Result<std::string> showSceneTime(SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t step,
                                  double fraction = 0.0);

}  // namespace atmoglobe::engine
