#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridVolume.h>

#include <algorithm>

namespace atmoglobe::engine {

Result<SceneTimeAxis> sceneTimeAxis(const SceneDescription& scene, const SceneRendererGL& renderer) {
  SceneTimeAxis axis;
  std::vector<std::vector<std::string>> times;
  for (const GridLayerDescription& g : scene.grids) {
    auto info = volume::describeGridFile(g.path, g.variable);
    if (!info) return info.forwardError();
    times.push_back(info->times);
  }
  const auto& radars = renderer.radars();
  const auto lead = std::find_if(times.begin(), times.end(), [](const auto& t) { return t.size() > 1; });
  if (lead != times.end()) {
    axis.leadGrid = static_cast<std::size_t>(lead - times.begin());
    axis.times = *lead;
    axis.leadName = scene.grids[axis.leadGrid].path;
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
      axis.notes.push_back(scene.grids[g].path + ": no step at " + std::to_string(missing) + " of the " +
                           std::to_string(axis.times.size()) + " times of " + axis.leadName +
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

}  // namespace atmoglobe::engine
