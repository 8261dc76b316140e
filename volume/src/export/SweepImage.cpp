#include <atmoglobe/volume/SweepImage.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

#include <atmoglobe/globe/Image.h>

namespace atmoglobe::volume {

namespace {
double wrap360(double a) {
  double w = std::fmod(a, 360.0);
  if (w < 0) w += 360.0;
  return w;
}
}  // namespace

SweepImage makeSweepImage(const Sweep& sweep, const ColorTable& table, std::uint32_t gateCount) {
  const std::size_t rays = sweep.rayCount();
  assert(rays > 0 && gateCount > 0 && gateCount <= sweep.gateCount);
  assert(sweep.values.size() == rays * sweep.gateCount);

  // Rays sorted by azimuth in [0, 360), duplicates dropped (first kept).
  std::vector<std::size_t> order(rays);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::vector<double> az(rays);
  for (std::size_t i = 0; i < rays; ++i) {
    assert(std::isfinite(sweep.azimuthDeg[i]));
    az[i] = wrap360(sweep.azimuthDeg[i]);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return az[a] < az[b]; });
  order.erase(std::unique(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return az[a] == az[b]; }),
              order.end());
  const std::size_t n = order.size();

  // Spacing to the next ray (circular) and its median.
  std::vector<double> gapToNext(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double next = k + 1 < n ? az[order[k + 1]] : az[order[0]] + 360.0;
    gapToNext[k] = next - az[order[k]];
  }
  double median = 1.0;  // a single ray: a 1 degree wide row
  if (n > 1) {
    std::vector<double> sorted = gapToNext;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2), sorted.end());
    median = sorted[n / 2];
  }
  const double gapLimit = 2.5 * median;
  auto halfAfter = [&](std::size_t k) { return gapToNext[k] > gapLimit ? 0.5 * median : 0.5 * gapToNext[k]; };

  SweepImage img;
  img.width = static_cast<int>(gateCount);
  img.firstGateRangeMeters = sweep.firstGateRangeMeters;
  img.gateSpacingMeters = sweep.gateSpacingMeters;
  const double firstStart = az[order[0]] - (gapToNext[n - 1] > gapLimit ? 0.5 * median : 0.5 * gapToNext[n - 1]);
  for (std::size_t k = 0; k < n; ++k) {
    const double a = az[order[k]];
    const double start = k == 0 ? firstStart : img.rowEndAzimuthDeg.back();
    const double end = a + halfAfter(k);
    img.rowStartAzimuthDeg.push_back(start);
    img.rowEndAzimuthDeg.push_back(end);
    img.rowRay.push_back(static_cast<int>(order[k]));
    const double nextStart = k + 1 < n ? az[order[k + 1]] - halfAfter(k) : firstStart + 360.0;
    if (nextStart > end + 1e-9) {  // gap row
      img.rowStartAzimuthDeg.push_back(end);
      img.rowEndAzimuthDeg.push_back(nextStart);
      img.rowRay.push_back(-1);
    }
  }
  img.rowEndAzimuthDeg.back() = firstStart + 360.0;  // close the turn exactly
  img.height = static_cast<int>(img.rowRay.size());

  img.rgba.assign(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) * 4, 0);
  for (int row = 0; row < img.height; ++row) {
    const int ray = img.rowRay[static_cast<std::size_t>(row)];
    if (ray < 0) continue;
    const float* values = sweep.values.data() + static_cast<std::size_t>(ray) * sweep.gateCount;
    std::uint8_t* out = img.rgba.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(img.width) * 4;
    for (std::uint32_t g = 0; g < gateCount; ++g) {
      const Rgba8 c = table.map(values[g]);
      out[4 * g + 0] = c.r;
      out[4 * g + 1] = c.g;
      out[4 * g + 2] = c.b;
      out[4 * g + 3] = c.a;
    }
  }
  return img;
}

double sweepImageV(const SweepImage& image, double azimuthDeg) {
  assert(image.height > 0);
  const double start = image.rowStartAzimuthDeg.front();
  double a = start + wrap360(azimuthDeg - start);
  // Row whose end is the first above a.
  const auto it = std::upper_bound(image.rowEndAzimuthDeg.begin(), image.rowEndAzimuthDeg.end(), a);
  if (it == image.rowEndAzimuthDeg.end()) return 1.0;
  const std::size_t row = static_cast<std::size_t>(it - image.rowEndAzimuthDeg.begin());
  const double lo = image.rowStartAzimuthDeg[row], hi = image.rowEndAzimuthDeg[row];
  const double t = hi > lo ? std::clamp((a - lo) / (hi - lo), 0.0, 1.0) : 0.0;
  return (static_cast<double>(row) + t) / image.height;
}

double sweepImageU(const SweepImage& image, double rangeMeters) {
  assert(image.width > 0 && image.gateSpacingMeters > 0);
  const double left = image.firstGateRangeMeters - 0.5 * image.gateSpacingMeters;
  return std::clamp((rangeMeters - left) / (image.width * image.gateSpacingMeters), 0.0, 1.0);
}

std::vector<std::uint8_t> encodeSweepImagePng(const SweepImage& image) {
  if (image.width <= 0 || image.height <= 0) return {};
  globe::ImageRGBA8 rgba{image.width, image.height, image.rgba};
  auto encoded = globe::encodePng(rgba, "sweep image");  // the one PNG encoder (libpng)
  return encoded ? std::move(*encoded) : std::vector<std::uint8_t>{};
}

}  // namespace atmoglobe::volume
