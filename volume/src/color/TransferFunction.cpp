// Transfer function (TransferFunction.h).
#include <atmoglobe/volume/TransferFunction.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {

glm::dvec4 TransferFunction::classify(double value) const {
  if (!std::isfinite(value)) return glm::dvec4(0.0);
  const Rgba8 c = colors.map(static_cast<float>(value));
  if (opacityPoints.size() >= 2) {
    double a = 0.0;
    if (value > opacityZeroValue) {
      const auto next = std::upper_bound(opacityPoints.begin(), opacityPoints.end(), value,
                                         [](double v, const glm::dvec2& p) { return v < p.x; });
      if (next == opacityPoints.begin()) {
        a = next->y;
      } else if (next == opacityPoints.end()) {
        a = opacityPoints.back().y;
      } else {
        const glm::dvec2& p0 = *(next - 1);
        const glm::dvec2& p1 = *next;
        a = p0.y + (value - p0.x) / (p1.x - p0.x) * (p1.y - p0.y);
      }
    }
    return glm::dvec4(c.r / 255.0, c.g / 255.0, c.b / 255.0, a * (c.a / 255.0));
  }
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

TransferFunction withValueRange(const TransferFunction& tf, double lo, double hi) {
  const auto& stops = tf.colors.stops();
  if (stops.size() < 2 || !(lo < hi)) return tf;
  // The table's span in field units: table units u = v * scale + offset.
  const double scale = tf.colors.scale(), offset = tf.colors.offset();
  const double a = (stops.front().value - offset) / scale;
  const double b = (stops.back().value - offset) / scale;
  const double k = (b - a) / (hi - lo);  // old field units per new field unit
  TransferFunction out = tf;
  // New value v reads the old table at a + (v - lo) k: u = (a + (v - lo) k) scale + offset.
  out.colors = ColorTable(tf.colors.name(), tf.colors.units(), stops, k * scale, (a - lo * k) * scale + offset);
  out.opacityZeroValue = lo + (tf.opacityZeroValue - a) / k;
  out.opacityFullValue = lo + (tf.opacityFullValue - a) / k;
  if (tf.opacityZeroValue <= -1e30) out.opacityZeroValue = tf.opacityZeroValue;  // "everything" stays so
  for (glm::dvec2& p : out.opacityPoints) p.x = lo + (p.x - a) / k;
  return out;
}

TransferFunction withOpacityPoints(const TransferFunction& tf, std::vector<glm::dvec2> points) {
  TransferFunction out = tf;
  std::stable_sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x; });
  // Equal values: keep the last (a vertical step is two points a hair apart, not one value twice).
  std::vector<glm::dvec2> kept;
  for (glm::dvec2 p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    p.y = std::clamp(p.y, 0.0, 1.0);
    if (!kept.empty() && kept.back().x == p.x) {
      kept.back() = p;
    } else {
      kept.push_back(p);
    }
  }
  if (kept.size() < 2) {
    out.opacityPoints.clear();
    return out;
  }
  out.opacityPoints = kept;
  out.opacityZeroValue = -1e30;
  for (const glm::dvec2& p : kept) {
    if (p.y > 0.0) break;
    out.opacityZeroValue = p.x;
  }
  out.maxOpacity = 0.0;
  out.opacityFullValue = kept.back().x;
  for (const glm::dvec2& p : kept) {
    if (p.y > out.maxOpacity) {
      out.maxOpacity = p.y;
      out.opacityFullValue = p.x;
    }
  }
  return out;
}

std::vector<glm::dvec2> opacityCurveOf(const TransferFunction& tf) {
  if (tf.opacityPoints.size() >= 2) return tf.opacityPoints;
  return {glm::dvec2(tf.opacityZeroValue, 0.0), glm::dvec2(tf.opacityFullValue, tf.maxOpacity)};
}

TransferFunction withOpacityRamp(const TransferFunction& tf, const std::vector<double>& ramp) {
  TransferFunction out = tf;
  if (ramp.size() >= 2) {
    out.opacityPoints.clear();
    out.opacityZeroValue = ramp[0];
    out.opacityFullValue = ramp[1];
  }
  if (ramp.size() >= 3) out.maxOpacity = ramp[2];
  if (ramp.size() >= 4) out.opacityReferenceMeters = ramp[3];
  return out;
}

}  // namespace atmoglobe::volume
