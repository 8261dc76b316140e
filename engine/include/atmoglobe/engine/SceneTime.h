#pragma once
// The time axis of a scene and stepping along it (render --time-series, view's time keys).
//
// The axis is the time steps of the scene's first layer that matches times exactly
// (TimeMatching::SameValidTime: a grid) and has more than one, else those of its first layer with
// more than one (a radar loop: a directory, glob or list holding several times of one site). Every
// other layer follows by its own rule (VolumeSourceGL::timeMatching): a grid shows the step with
// the same valid time (to the second), or stays where it is when its file has no such time (said
// once per layer); a radar loop shows its latest volume at or before the time (what a forecaster
// sees live). Between two steps a fraction in (0, 1) interpolates the layers that interpolate in
// time (grids, linearly); the others show the step's own volume.
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
  std::size_t leadLayer = 0;       ///< the volume layer whose times these are
  std::string leadName;            ///< its path, for messages
  /// Per volume layer (renderer order), per step: the layer's own step shown then, or -1 (it stays
  /// where it is: no step at that time, or no time axis of its own).
  std::vector<std::vector<long>> layerSteps;
  /// Layers with no step at some of the axis' times, one line each (for a warning).
  std::vector<std::string> notes;
};

/// The scene's time axis (metadata only: no field values read), for the layers `renderer` holds.
/// Errors: no layer with more than one time step (a time series needs one), unreadable files.
Result<SceneTimeAxis> sceneTimeAxis(const SceneRendererGL& renderer);

/// Shows step `step` (plus `fraction` of the way to step + 1) on every layer of `renderer` with a time axis
/// (in scene order, as populated from the same scene). The valid time shown is returned.
Result<std::string> showSceneTime(SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t step,
                                  double fraction = 0.0);

/// The frames of a series: `steps` time steps with `substeps` frames each between consecutive
/// steps (the last step one frame): (steps - 1) * substeps + 1.
std::size_t seriesFrameCount(std::size_t steps, int substeps);

/// Frames [begin, end) of a series.
struct FrameRange {
  std::size_t begin = 0, end = 0;
  bool contains(std::size_t frame) const { return frame >= begin && frame < end; }
  std::size_t size() const { return end - begin; }
};
/// Shard `index` (0 to count - 1) of `count` of a series of `frames` frames, as Slurm array tasks
/// render it (docs/scale-out.md): frames [frames * index / count, frames * (index + 1) / count),
/// contiguous so that a shard's steps share what they read. The shards are disjoint and together
/// hold every frame once; a shard may be empty when there are more shards than frames. Errors:
/// count 0, index >= count (the message says which).
Result<FrameRange> seriesShard(std::size_t frames, std::size_t index, std::size_t count);

// --- Loading steps within a memory budget (docs/memory.md) ---
//
// Every step a layer shows goes through the renderer's volume::StepCache: its GPU volume (with
// its CPU twin; bytes = CPU arrays + textures) under stepKey(.., true), and, where a step was
// prepared ahead or is needed for interpolation, its CPU data under stepKey(.., false) (keys:
// VolumeSourceGL.h). Steps not shown are dropped least recently used when the budget is reached
// and read again when needed.

/// Loads the steps after the one shown on a worker thread (CPU side: file reading, cropping,
/// exaggeration) into the renderer's step cache, so stepping and playing find them ready and
/// only the GPU upload is left to the GL thread. It loads ahead only while what it loads fits the
/// budget beside the steps shown (StepCache::fitsBesidesInUse), so it never pushes those out.
/// Holds each layer's StepPreparer (copies of what it reads): build it after the renderer is populated.
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
  std::vector<std::unique_ptr<StepPreparer>> preparers_;  ///< per layer, renderer order
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
