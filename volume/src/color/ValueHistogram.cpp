// Value histograms (ValueHistogram.h).
#include <atmoglobe/volume/ValueHistogram.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {

std::uint64_t ValueHistogram::largestCount() const {
  return counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());
}

ValueHistogram valueHistogram(std::span<const float> values, double lo, double hi, int bins) {
  ValueHistogram h;
  if (!(hi > lo)) hi = lo + 1.0;
  h.lo = lo;
  h.hi = hi;
  const int n = std::max(bins, 1);
  h.counts.assign(static_cast<std::size_t>(n), 0);
  const double perUnit = n / (hi - lo);
  for (float f : values) {
    if (std::isnan(f)) {
      ++h.noData;
    } else if (std::isinf(f)) {
      ++(f < 0 ? h.noEcho : h.above);
    } else if (f < lo) {
      ++h.below;
    } else if (f > hi) {
      ++h.above;
    } else {
      const int k = std::min(static_cast<int>((f - lo) * perUnit), n - 1);
      ++h.counts[static_cast<std::size_t>(k)];
    }
  }
  return h;
}

namespace {
ValueHistogram overRange(std::span<const float> values, double minValue, double maxValue, int bins) {
  if (!(minValue < maxValue)) {
    const double mid = std::isfinite(minValue) ? minValue : 0.0;
    return valueHistogram(values, mid - 0.5, mid + 0.5, bins);
  }
  return valueHistogram(values, minValue, maxValue, bins);
}
}  // namespace

ValueHistogram valueHistogram(const PolarVolume& volume, int bins) {
  return overRange(volume.values, volume.minValue, volume.maxValue, bins);
}

ValueHistogram valueHistogram(const GridVolume& grid, int bins) {
  return overRange(grid.values, grid.valueMin, grid.valueMax, bins);
}

}  // namespace atmoglobe::volume
