#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridVolume.h>

#include <algorithm>
#include <cstdio>

namespace atmoglobe::engine {

Result<SceneTimeAxis> sceneTimeAxis(const SceneRendererGL& renderer) {
  SceneTimeAxis axis;
  std::vector<std::vector<std::string>> times;
  for (const GridLayerGL& layer : renderer.grids()) {
    const VolumeLayerDescription& g = layer.description;
    auto info = volume::describeGridFile(g.path, g.field);
    if (!info) return info.forwardError();
    times.push_back(info->times);
  }
  const auto& radars = renderer.radars();
  const auto lead = std::find_if(times.begin(), times.end(), [](const auto& t) { return t.size() > 1; });
  if (lead != times.end()) {
    axis.leadGrid = static_cast<std::size_t>(lead - times.begin());
    axis.times = *lead;
    axis.leadName = renderer.grids()[axis.leadGrid].description.path;
  } else {
    const auto loop =
        std::find_if(radars.begin(), radars.end(), [](const RadarLayerGL& r) { return r.loopTimes.size() > 1; });
    if (loop == radars.end())
      return makeError(
          "a time series needs a forecast grid with more than one time step (--grid) or a radar loop "
          "(--radar DIR, a glob or a list holding several times of one site)");
    axis.leadIsRadar = true;
    axis.leadGrid = static_cast<std::size_t>(loop - radars.begin());
    axis.times = loop->loopTimes;
    axis.leadName = loop->description.path;
  }
  for (std::size_t g = 0; g < times.size(); ++g) {
    std::vector<long> steps;
    std::size_t missing = 0;
    for (const std::string& t : axis.times) {
      const auto it = std::find(times[g].begin(), times[g].end(), t);
      steps.push_back(t.empty() || it == times[g].end() ? -1 : static_cast<long>(it - times[g].begin()));
      missing += steps.back() < 0 ? 1 : 0;
    }
    if (!axis.leadIsRadar && g == axis.leadGrid) {
      for (std::size_t s = 0; s < steps.size(); ++s) steps[s] = static_cast<long>(s);
    } else if (missing > 0) {
      axis.notes.push_back(renderer.grids()[g].description.path + ": no step at " + std::to_string(missing) +
                           " of the " + std::to_string(axis.times.size()) + " times of " + axis.leadName +
                           "; it stays at its last step shown there");
    }
    axis.gridSteps.push_back(std::move(steps));
  }
  for (std::size_t r = 0; r < radars.size(); ++r) {
    std::vector<long> steps;
    const auto& loopTimes = radars[r].loopTimes;
    for (std::size_t s = 0; s < axis.times.size(); ++s) {
      if (axis.leadIsRadar && r == axis.leadGrid) {
        steps.push_back(static_cast<long>(s));
        continue;
      }
      // The latest volume at or before the time (ISO 8601 UTC texts compare as times).
      long pick = -1;
      for (std::size_t k = 0; k < loopTimes.size(); ++k)
        if (loopTimes[k] <= axis.times[s]) pick = static_cast<long>(k);
      steps.push_back(loopTimes.size() > 1 ? pick : -1);
    }
    axis.radarSteps.push_back(std::move(steps));
  }
  return axis;
}

Result<std::string> showSceneTime(SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t step,
                                  double fraction) {
  if (step >= axis.times.size()) return makeError("time step " + std::to_string(step) + " is beyond the axis");
  if (step + 1 == axis.times.size()) fraction = 0.0;
  auto& grids = renderer.grids();
  for (std::size_t g = 0; g < grids.size() && g < axis.gridSteps.size(); ++g) {
    const long own = axis.gridSteps[g][step];
    if (own < 0) continue;
    // Interpolate only where this grid has the next time too, as its next step.
    const bool next = fraction > 0.0 && axis.gridSteps[g][step + 1] == own + 1;
    if (auto st = renderer.setGridStep(g, static_cast<std::size_t>(own), next ? fraction : 0.0); !st)
      return st.forwardError();
  }
  auto& radars = renderer.radars();
  for (std::size_t r = 0; r < radars.size() && r < axis.radarSteps.size(); ++r) {
    const long own = axis.radarSteps[r][step];
    if (own < 0) continue;
    if (auto st = renderer.setRadarStep(r, static_cast<std::size_t>(own)); !st) return st.forwardError();
  }
  if (fraction > 0.0) return volume::interpolateIsoTime(axis.times[step], axis.times[step + 1], fraction);
  return axis.times[step];
}

std::string stallSummary(std::vector<double> stallMs, bool prefetch) {
  if (stallMs.empty()) return "time steps: none shown";
  std::sort(stallMs.begin(), stallMs.end());
  const double median = stallMs.size() % 2 == 1 ? stallMs[stallMs.size() / 2]
                                                : 0.5 * (stallMs[stallMs.size() / 2 - 1] + stallMs[stallMs.size() / 2]);
  char line[160];
  std::snprintf(line, sizeof line, "time steps: %zu changes, stall median %.1f ms, max %.1f ms (prefetch %s)",
                stallMs.size(), median, stallMs.back(), prefetch ? "on" : "off");
  return line;
}

std::string stepKeyPrefix(bool radar, std::size_t layer) {
  std::string key = radar ? "radar:" : "grid:";
  key += std::to_string(layer);
  key += ':';
  return key;
}

std::string stepKey(bool radar, std::size_t layer, std::size_t step, bool gpu, double fraction) {
  std::string key = radar ? "radar:" : "grid:";
  key += std::to_string(layer);
  key += ':';
  key += std::to_string(step);
  if (fraction > 0.0) {
    char f[32];
    std::snprintf(f, sizeof f, "+%.6f", fraction);
    key += f;
  }
  key += gpu ? ":gpu" : ":cpu";
  return key;
}

ScenePrefetcher::ScenePrefetcher(const SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t stepsAhead)
    : exaggeration_(renderer.verticalExaggeration()), axis_(axis), ahead_(stepsAhead),
      cache_(renderer.sharedStepCache()) {
  for (const GridLayerGL& g : renderer.grids()) grids_.push_back({g.description});
  for (const RadarLayerGL& r : renderer.radars()) radars_.push_back({r.description, r.loopFiles});
  worker_ = std::thread([this] { run(); });
}

ScenePrefetcher::~ScenePrefetcher() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void ScenePrefetcher::request(std::size_t step) {
  {
    std::lock_guard lock(mutex_);
    wanted_ = static_cast<long>(step);
    ++generation_;
  }
  wake_.notify_all();
}

void ScenePrefetcher::waitIdle() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return done_ == generation_ || stop_; });
}

std::size_t ScenePrefetcher::stepsPrepared() const {
  std::lock_guard lock(mutex_);
  return prepared_;
}

void ScenePrefetcher::run() {
  const std::size_t n = axis_.times.size();
  std::uint64_t lastStepBytes = 0;  // bytes of the last step loaded: the estimate of the next
  for (;;) {
    long from = 0;
    std::uint64_t generation = 0;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || done_ != generation_; });
      if (stop_) return;
      from = wanted_;
      generation = generation_;
    }
    auto superseded = [&] {
      std::lock_guard lock(mutex_);
      return stop_ || generation_ != generation;
    };
    bool full = false;
    for (std::size_t d = 1; d <= ahead_ && d < n && !full && !superseded(); ++d) {
      const std::size_t s = (static_cast<std::size_t>(from) + d) % n;
      for (std::size_t g = 0; g < grids_.size() && g < axis_.gridSteps.size() && !full; ++g) {
        const long own = axis_.gridSteps[g][s];
        if (own < 0) continue;
        const auto step = static_cast<std::size_t>(own);
        if (cache_->contains(stepKey(false, g, step, true)) || cache_->contains(stepKey(false, g, step, false)))
          continue;
        // Twice the estimate: the GPU volume and its twin come on top when the step is shown.
        if (!cache_->fitsBesidesInUse(2 * lastStepBytes)) {
          full = true;
          break;
        }
        auto grid = prepareGridStep(grids_[g].description, step, exaggeration_);
        if (!grid || !GridVolumeGL::checkDrawable(*grid)) continue;  // the GL thread reads it again, says why
        auto prepared = GridVolumeGL::prepare(*grid);                // texels, lookup tables, empty-space grid
        lastStepBytes = prepared->bytes();
        cache_->put(stepKey(false, g, step, false), std::move(prepared), lastStepBytes);
        std::lock_guard lock(mutex_);
        ++prepared_;
      }
      for (std::size_t r = 0; r < radars_.size() && r < axis_.radarSteps.size() && !full; ++r) {
        const long own = axis_.radarSteps[r][s];
        if (own < 0 || static_cast<std::size_t>(own) >= radars_[r].loopFiles.size()) continue;
        const auto step = static_cast<std::size_t>(own);
        if (cache_->contains(stepKey(true, r, step, true)) || cache_->contains(stepKey(true, r, step, false))) continue;
        if (!cache_->fitsBesidesInUse(2 * lastStepBytes)) {
          full = true;
          break;
        }
        auto data = prepareRadarStep(radars_[r].description, radars_[r].loopFiles[step]);
        if (!data || !RadarVolumeGL::checkDrawable(data->layout)) continue;    // the GL thread says why
        data->prepared = RadarVolumeGL::prepare(data->layout, exaggeration_);  // layers, tables, empty-space grid
        data->layout = volume::PolarVolume{};
        auto shared = std::make_shared<const RadarStepData>(std::move(*data));
        lastStepBytes = shared->prepared->bytes();
        cache_->put(stepKey(true, r, step, false), std::move(shared), lastStepBytes);
        std::lock_guard lock(mutex_);
        ++prepared_;
      }
    }
    {
      std::lock_guard lock(mutex_);
      if (generation_ == generation) done_ = generation;
    }
    idle_.notify_all();
  }
}

}  // namespace atmoglobe::engine
