#pragma once
// A volume image (premultiplied RGBA in double) and the image difference every error figure of
// the bench and the tests is measured with. GL-free.
#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace atmoglobe::volume {

/// Premultiplied RGBA in [0, 1] per pixel, row-major, row 0 = top of the image.
struct VolumeImage {
  int widthPx = 0;
  int heightPx = 0;
  std::vector<glm::dvec4> rgbaPremultiplied;
  const glm::dvec4& at(int x, int y) const {
    return rgbaPremultiplied[static_cast<std::size_t>(y) * static_cast<std::size_t>(widthPx) +
                             static_cast<std::size_t>(x)];
  }
};

/// Image difference for the bench and the tests: both images composited over black (the
/// premultiplied RGB, clamped to [0, 1]), quantised to 8 bits (round(255 c)), compared per RGB
/// channel. meanAbs / maxAbs in 8-bit steps (0..255); psnrDb = 10 log10(255^2 / MSE), +inf when
/// equal. Precondition (asserted): equal sizes.
struct ImageError {
  double meanAbs = 0.0;
  double maxAbs = 0.0;
  double psnrDb = 0.0;
};
ImageError compareImages(const VolumeImage& a, const VolumeImage& b);

}  // namespace atmoglobe::volume
