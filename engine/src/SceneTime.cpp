#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridVolume.h>

#include <algorithm>
#include <cstdio>
#include <optional>

namespace atmoglobe::engine {

Result<SceneTimeAxis> sceneTimeAxis(const SceneRendererGL& renderer) {
  SceneTimeAxis axis;
  const std::size_t n = renderer.volumeLayerCount();
  std::vector<std::vector<std::string>> times;
  for (std::size_t l = 0; l < n; ++l) {
    auto own = renderer.layer(l).times();
    if (!own) return own.forwardError();
    times.push_back(std::move(*own));
  }
  // The lead: the first layer matching valid times exactly with several, else the first with several.
  std::optional<std::size_t> lead;
  for (std::size_t l = 0; l < n && !lead; ++l)
    if (times[l].size() > 1 && renderer.layer(l).timeMatching() == TimeMatching::SameValidTime) lead = l;
  for (std::size_t l = 0; l < n && !lead; ++l)
    if (times[l].size() > 1) lead = l;
  if (!lead)
    return makeError(
        "a time series needs a forecast grid with more than one time step (--grid) or a radar loop "
        "(--radar DIR, a glob or a list holding several times of one site)");
  axis.leadLayer = *lead;
  axis.times = times[*lead];
  axis.leadName = renderer.layer(*lead).description().path;
  for (std::size_t l = 0; l < n; ++l) {
    std::vector<long> steps;
    const std::vector<std::string>& own = times[l];
    std::size_t missing = 0;
    const bool exact = renderer.layer(l).timeMatching() == TimeMatching::SameValidTime;
    for (std::size_t s = 0; s < axis.times.size(); ++s) {
      const std::string& t = axis.times[s];
      long pick = -1;
      if (l == *lead) {
        pick = static_cast<long>(s);
      } else if (exact) {
        const auto it = std::find(own.begin(), own.end(), t);
        pick = t.empty() || it == own.end() ? -1 : static_cast<long>(it - own.begin());
        missing += pick < 0 ? 1 : 0;
      } else if (own.size() > 1) {
        // The latest step at or before the time (ISO 8601 UTC texts compare as times).
        for (std::size_t k = 0; k < own.size(); ++k)
          if (own[k] <= t) pick = static_cast<long>(k);
      }
      steps.push_back(pick);
    }
    if (missing > 0)
      axis.notes.push_back(renderer.layer(l).description().path + ": no step at " + std::to_string(missing) +
                           " of the " + std::to_string(axis.times.size()) + " times of " + axis.leadName +
                           "; it stays at its last step shown there");
    axis.layerSteps.push_back(std::move(steps));
  }
  return axis;
}

std::size_t seriesFrameCount(std::size_t steps, int substeps) {
  if (steps == 0) return 0;
  return (steps - 1) * static_cast<std::size_t>(std::max(1, substeps)) + 1;
}

Result<FrameRange> seriesShard(std::size_t frames, std::size_t index, std::size_t count) {
  if (count == 0) return makeError("shard: the number of shards must be at least 1");
  if (index >= count)
    return makeError("shard " + std::to_string(index) + " of " + std::to_string(count) + ": shards are numbered 0 to " +
                     std::to_string(count - 1));
  // floor(frames * k / count) without forming frames * k: (frames % count) * k < count^2.
  const auto at = [&](std::size_t k) { return frames / count * k + frames % count * k / count; };
  return FrameRange{at(index), at(index + 1)};
}

Result<std::string> showSceneTime(SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t step,
                                  double fraction) {
  if (step >= axis.times.size()) return makeError("time step " + std::to_string(step) + " is beyond the axis");
  if (step + 1 == axis.times.size()) fraction = 0.0;
  for (std::size_t l = 0; l < renderer.volumeLayerCount() && l < axis.layerSteps.size(); ++l) {
    const long own = axis.layerSteps[l][step];
    if (own < 0) continue;
    // Interpolate only layers that do, and only where the layer has the next time too, as its next step.
    const bool next = fraction > 0.0 && renderer.layer(l).interpolatesInTime() &&
                      axis.layerSteps[l][step + 1] == own + 1;
    if (auto st = renderer.setLayerStep(l, static_cast<std::size_t>(own), next ? fraction : 0.0); !st)
      return st.forwardError();
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

ScenePrefetcher::ScenePrefetcher(const SceneRendererGL& renderer, const SceneTimeAxis& axis, std::size_t stepsAhead)
    : axis_(axis), ahead_(stepsAhead), cache_(renderer.sharedStepCache()) {
  for (std::size_t l = 0; l < renderer.volumeLayerCount(); ++l)
    preparers_.push_back(renderer.layer(l).preparer(renderer.verticalExaggeration()));
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
      for (std::size_t l = 0; l < preparers_.size() && l < axis_.layerSteps.size() && !full; ++l) {
        const long own = axis_.layerSteps[l][s];
        if (own < 0) continue;
        const auto step = static_cast<std::size_t>(own);
        if (cache_->contains(stepKey(l, step, true)) || cache_->contains(stepKey(l, step, false))) continue;
        // Twice the estimate: the GPU volume and its twin come on top when the step is shown.
        if (!cache_->fitsBesidesInUse(2 * lastStepBytes)) {
          full = true;
          break;
        }
        // Read, cropped, exaggerated, texels and tables.
        auto prepared = preparers_[l]->prepare(step, PrepareContext{*cache_, l});
        if (!prepared) continue;  // the GL thread reads it again, says why
        if (prepared->bytes > 0) lastStepBytes = prepared->bytes;
        if (prepared->data) cache_->put(stepKey(l, step, false), std::move(prepared->data), prepared->bytes);
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
