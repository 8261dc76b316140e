// Transfer function (TransferFunction.h).
#include <atmoglobe/volume/TransferFunction.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {

glm::dvec4 TransferFunction::classify(double value) const {
  if (!std::isfinite(value)) return glm::dvec4(0.0);
  const Rgba8 c = colors.map(static_cast<float>(value));
  double ramp = 0.0;
  if (value >= opacityFullValue) {
    ramp = 1.0;
  } else if (value > opacityZeroValue) {
    ramp = (value - opacityZeroValue) / (opacityFullValue - opacityZeroValue);
  }
  return glm::dvec4(c.r / 255.0, c.g / 255.0, c.b / 255.0, ramp * maxOpacity * (c.a / 255.0));
}

double TransferFunction::correctedOpacity(double alpha, double stepMeters) const {
  const double a = std::clamp(alpha, 0.0, 1.0);
  if (a >= 1.0) return 1.0;
  return 1.0 - std::pow(1.0 - a, stepMeters / opacityReferenceMeters);
}

TransferFunction defaultReflectivityTransfer() {
  TransferFunction tf;
  tf.colors = nwsReflectivityTable();
  return tf;
}

}  // namespace atmoglobe::volume
