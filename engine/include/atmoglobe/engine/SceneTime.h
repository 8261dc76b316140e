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
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/StepCache.h>

#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
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

/// The scene's time axis (metadata only: no field values read), for the layers `renderer` holds.
/// Errors: no grid with more than one time step and no radar loop (a
/// time series needs one), unreadable files.
Result<SceneTimeAxis> sceneTimeAxis(const SceneRendererGL& renderer);

/// Shows step `step` (plus `fraction` of the way to step + 1) on every grid and radar loop of `renderer`
/// (in scene order, as populated from the same scene). The valid time shown is returned.
Result<std::string> showSceneTime(SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t step,
                                  double fraction = 0.0);

// --- Loading steps within a memory budget (docs/memory.md) ---
//
// Every step a layer shows goes through the renderer's volume::StepCache: its GPU volume (with
// its CPU twin; bytes = CPU arrays + textures) under stepKey(.., true), and, where a step was
// prepared ahead or is needed for interpolation, its CPU data under stepKey(.., false). Steps not
// shown are dropped least recently used when the budget is reached and read again when needed.

/// The cache key of a layer's step: "grid:3:17:gpu" ("radar:..."; `fraction` > 0: an interpolated
/// frame "grid:3:17+0.25:gpu").
std::string stepKey(bool radar, std::size_t layer, std::size_t step, bool gpu, double fraction = 0.0);
/// The start every key of one layer shares (StepCache::erasePrefix drops them all).
std::string stepKeyPrefix(bool radar, std::size_t layer);

/// A grid's step as the renderer draws it, CPU side only (no GL: safe on a worker thread; the
/// readers hold the netCDF library lock while they call netCDF-C, io/NetcdfLock.h, so the GL
/// thread's coastline reads and reloads never overlap them): read (variable, crop box columns),
/// cropped, vertically exaggerated by `exaggeration`.
Result<volume::GridVolume> prepareGridStep(const VolumeLayerDescription& description, std::size_t step,
                                           double exaggeration);

/// A radar loop's volume as the renderer draws it, CPU side only: read (`files`: one loop step),
/// cropped; its time and datum note.
struct RadarStepData {
  volume::PolarVolume layout;  ///< empty once `prepared` holds it
  std::string timeIso8601, datumNote;
  /// Ready for upload (RadarVolumeGL::prepare at the scene's exaggeration), made by the
  /// background loader; null: upload from `layout`.
  std::shared_ptr<const RadarVolumeGL::Prepared> prepared;
};
Result<RadarStepData> prepareRadarStep(const VolumeLayerDescription& description, const std::string& files);

/// Loads the steps after the one shown on a worker thread (CPU side: file reading, cropping,
/// exaggeration) into the renderer's step cache, so stepping and playing find them ready and
/// only the GPU upload is left to the GL thread. It loads ahead only while what it loads fits the
/// budget beside the steps shown (StepCache::fitsBesidesInUse), so it never pushes those out.
/// Holds copies of the layers' descriptions: build it after the renderer is populated.
class ScenePrefetcher {
 public:
  ScenePrefetcher(const SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t stepsAhead = 3);
  ~ScenePrefetcher();
  ScenePrefetcher(const ScenePrefetcher&) = delete;
  ScenePrefetcher& operator=(const ScenePrefetcher&) = delete;
  /// `step` is shown now: load steps step + 1 .. step + stepsAhead (wrapping; what play shows next).
  void request(std::size_t step);
  /// Blocks until the worker has nothing left to do for the last request (tests, benchmarks).
  void waitIdle();
  std::size_t stepsPrepared() const;

 private:
  void run();
  struct GridJob {
    VolumeLayerDescription description;
  };
  struct RadarJob {
    VolumeLayerDescription description;
    std::vector<std::string> loopFiles;
  };
  std::vector<GridJob> grids_;
  std::vector<RadarJob> radars_;
  double exaggeration_ = 1.0;
  SceneTimeAxis axis_;
  std::size_t ahead_;
  std::shared_ptr<volume::StepCache> cache_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  long wanted_ = -1;  ///< the step of the newest request (-1: none)
  std::uint64_t generation_ = 0, done_ = 0;
  bool stop_ = false;
  std::size_t prepared_ = 0;
  std::thread worker_;
};

/// "time steps: N changes, stall median X ms, max Y ms (prefetch on)": what stepping cost the
/// frame loop (view prints it at exit; docs/memory.md).
std::string stallSummary(std::vector<double> stallMs, bool prefetch);

}  // namespace atmoglobe::engine
