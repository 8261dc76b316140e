// Frame pacing while moving, frame-time summary (FramePacing.h).
#include <atmoglobe/engine/FramePacing.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace atmoglobe::engine {

void MovingImageScale::reportMovingFrame(double sceneMs) {
  if (!(sceneMs > 0.0) || !std::isfinite(sceneMs)) return;
  constexpr double kQuantum = 1.0 / 64.0;
  if (sceneMs > targetMs_) {
    // Down to the quantum below, at least one quantum lower: a step that rounds back to the same
    // scale would never reach the target.
    const double s = scale_ * std::max(0.5, std::sqrt(targetMs_ / sceneMs));
    scale_ = std::max(kMinScale, std::min(std::floor(s / kQuantum) * kQuantum, scale_ - kQuantum));
  } else if (sceneMs < 0.7 * targetMs_) {
    const double s = scale_ * std::min(1.25, std::sqrt(0.85 * targetMs_ / sceneMs));
    scale_ = std::min(kMaxScale, std::max(scale_, std::floor(s / kQuantum) * kQuantum));
  }
}

void MovingImageScale::seedFromFullMarch(double fullMarchMs) {
  if (!(fullMarchMs > 0.0) || !std::isfinite(fullMarchMs)) return;
  constexpr double kQuantum = 1.0 / 64.0;
  const double marchMs = std::max(targetMs_ - kFixedMsEstimate, 0.25 * targetMs_);
  const double s = std::sqrt(marchMs / fullMarchMs);
  scale_ = std::clamp(std::floor(s / kQuantum) * kQuantum, kMinScale, kMaxScale);
}

namespace {
void part(std::ostringstream& out, const char* name, std::vector<double> v) {
  if (v.empty()) return;
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) {
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
  };
  const double median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  if (out.tellp() > 0) out << "; ";
  out.setf(std::ios::fixed);
  out.precision(1);
  out << name << ": " << v.size() << " frame" << (v.size() == 1 ? "" : "s") << ", median " << median << " ms (p90 "
      << at(0.9) << ", max " << v.back() << ")";
}
}  // namespace

std::string FrameTimeSummary::text() const {
  std::ostringstream out;
  part(out, "moving", moving_);
  part(out, "at rest", rest_);
  return out.str();
}

}  // namespace atmoglobe::engine
