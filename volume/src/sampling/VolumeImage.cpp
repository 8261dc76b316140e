// Image difference (VolumeImage.h).
#include <atmoglobe/volume/VolumeImage.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace atmoglobe::volume {

ImageError compareImages(const VolumeImage& a, const VolumeImage& b) {
  assert(a.widthPx == b.widthPx && a.heightPx == b.heightPx);
  assert(a.rgbaPremultiplied.size() == b.rgbaPremultiplied.size());
  auto q = [](double c) { return std::round(255.0 * std::clamp(std::isfinite(c) ? c : 0.0, 0.0, 1.0)); };
  double sumAbs = 0.0, sumSq = 0.0, maxAbs = 0.0;
  const std::size_t n = a.rgbaPremultiplied.size();
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::abs(q(a.rgbaPremultiplied[i][c]) - q(b.rgbaPremultiplied[i][c]));
      sumAbs += d;
      sumSq += d * d;
      maxAbs = std::max(maxAbs, d);
    }
  ImageError e;
  const double count = 3.0 * static_cast<double>(n);
  e.meanAbs = n ? sumAbs / count : 0.0;
  e.maxAbs = maxAbs;
  const double mse = n ? sumSq / count : 0.0;
  e.psnrDb = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
  return e;
}

}  // namespace atmoglobe::volume
