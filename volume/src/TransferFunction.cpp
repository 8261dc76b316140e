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

double TransferFunction::extinctionPerMeter(double alpha) const {
  const double a = std::clamp(alpha, 0.0, 1.0 - 1e-6);
  return -std::log1p(-a) / opacityReferenceMeters;
}

std::vector<glm::dvec4> transferIntegralTable(const TransferFunction& tf, double lo, double hi, int bins) {
  std::vector<glm::dvec4> table(static_cast<std::size_t>(std::max(bins, 1)) + 1, glm::dvec4(0.0));
  const double width = (hi - lo) / bins;
  for (int k = 0; k < bins; ++k) {
    const glm::dvec4 c = tf.classify(lo + (k + 0.5) * width);
    const double sigma = tf.extinctionPerMeter(c.a);
    table[k + 1] = table[k] + glm::dvec4(glm::dvec3(c) * sigma * width, sigma * width);
  }
  return table;
}

TransferFunction defaultReflectivityTransfer() {
  TransferFunction tf;
  tf.colors = nwsReflectivityTable();
  return tf;
}

}  // namespace atmoglobe::volume
