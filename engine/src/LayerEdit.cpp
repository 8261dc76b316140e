// Layer edits of the viewer's control panel (LayerEdit.h).
#include <atmoglobe/engine/LayerEdit.h>

#include <algorithm>
#include <cstdio>
#include <tuple>

namespace atmoglobe::engine {

namespace {
bool sameCrop(const volume::CropBox& a, const volume::CropBox& b) {
  return std::tie(a.southDeg, a.northDeg, a.westDeg, a.eastDeg, a.bottomMeters, a.topMeters) ==
         std::tie(b.southDeg, b.northDeg, b.westDeg, b.eastDeg, b.bottomMeters, b.topMeters);
}
bool sameLook(const VolumeLayerSettings& a, const VolumeLayerSettings& b) {
  return a.valueRange == b.valueRange && a.opacity == b.opacity && a.opacityPoints == b.opacityPoints;
}
// Doubles compared so that NaN equals NaN (a grid's "middle of the range" iso value).
bool same(double a, double b) { return a == b || (a != a && b != b); }
}  // namespace

LayerChange radarLayerChange(const RadarLayerDescription& a, const RadarLayerDescription& b) {
  if (a.path != b.path || a.field != b.field || a.useGeoid != b.useGeoid || !sameCrop(a.settings.crop, b.settings.crop))
    return LayerChange::Reload;
  if (a.colors != b.colors || a.mode != b.mode || a.interpolation != b.interpolation ||
      !same(a.stepMeters, b.stepMeters) || !same(a.imageScale, b.imageScale) || !same(a.isoValue, b.isoValue) ||
      a.beam != b.beam || a.classification != b.classification || a.label != b.label ||
      !sameLook(a.settings, b.settings))
    return LayerChange::Options;
  return LayerChange::None;
}

LayerChange gridLayerChange(const GridLayerDescription& a, const GridLayerDescription& b) {
  if (a.path != b.path || a.variable != b.variable || a.time != b.time || a.useGeoid != b.useGeoid ||
      !sameCrop(a.settings.crop, b.settings.crop))
    return LayerChange::Reload;
  if (a.colors != b.colors || a.mode != b.mode || a.interpolation != b.interpolation ||
      !same(a.stepMeters, b.stepMeters) || !same(a.imageScale, b.imageScale) || !same(a.isoValue, b.isoValue) ||
      a.classification != b.classification || !sameLook(a.settings, b.settings))
    return LayerChange::Options;
  return LayerChange::None;
}

const std::vector<std::string>& colorTableChoices() {
  static const std::vector<std::string> choices{"auto",    "NWS",   "velocity",  "cividis",
                                                "viridis", "turbo", "grayscale", "greens"};
  return choices;
}

std::vector<std::size_t> moveInOrder(std::vector<std::size_t> order, std::size_t position, int delta) {
  if (position >= order.size()) return order;
  const auto last = static_cast<long>(order.size()) - 1;
  const auto to = static_cast<std::size_t>(std::clamp(static_cast<long>(position) + delta, 0L, last));
  const std::size_t moved = order[position];
  order.erase(order.begin() + static_cast<std::ptrdiff_t>(position));
  order.insert(order.begin() + static_cast<std::ptrdiff_t>(to), moved);
  return order;
}

std::string formatBytes(std::uint64_t bytes) {
  char text[32];
  const double b = static_cast<double>(bytes);
  if (bytes < 1024) {
    std::snprintf(text, sizeof text, "%llu B", static_cast<unsigned long long>(bytes));
  } else if (b < 1024.0 * 1024.0) {
    std::snprintf(text, sizeof text, "%.1f KiB", b / 1024.0);
  } else if (b < 1024.0 * 1024.0 * 1024.0) {
    std::snprintf(text, sizeof text, "%.1f MiB", b / (1024.0 * 1024.0));
  } else {
    std::snprintf(text, sizeof text, "%.2f GiB", b / (1024.0 * 1024.0 * 1024.0));
  }
  return text;
}

}  // namespace atmoglobe::engine
