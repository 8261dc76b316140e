// The step rule (StepRule.h).
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/StepRule.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace atmoglobe::volume {
namespace {
double asFloat(double x) { return static_cast<double>(static_cast<float>(x)); }
}  // namespace

double approximateHeightMeters(const glm::dvec3& e) {
  const double r = glm::length(e);
  if (!(r > 0.0)) return -globe::kWgs84B;
  const double s = e.z / r;
  return r - globe::kWgs84B / std::sqrt(1.0 - globe::kWgs84E2 * (1.0 - s * s));
}

double cellCrossingMeters(const CellScale& c, const glm::dvec3& ecef, const glm::dvec3& dir) {
  if (c.levelSpacingMeters.empty()) return 0.0;
  const double r = glm::length(ecef);
  if (!(r > 0.0)) return 0.0;
  const double cosUp = std::min(1.0, std::abs(glm::dot(ecef, dir)) / r);
  const double sinUp = std::sqrt(std::max(0.0, 1.0 - cosUp * cosUp));
  const int n = static_cast<int>(c.levelSpacingMeters.size());
  const double x = std::floor((approximateHeightMeters(ecef) - c.minHeightMeters) * c.entriesPerMeter);
  const int e = static_cast<int>(std::clamp(x, 0.0, static_cast<double>(n - 1)));
  const double dz = c.levelSpacingMeters[static_cast<std::size_t>(e)];
  return std::min(dz / std::max(cosUp, 1e-6), c.columnSpacingMeters / std::max(sinUp, 1e-6));
}

double polarCellCrossingMeters(const PolarCellScale& c, const glm::dvec3& p, const glm::dvec3& dir) {
  if (!(c.gateMeters > 0.0) || !(c.acrossRad > 0.0)) return 0.0;
  const double r = glm::length(p);
  if (!(r > 0.0)) return 0.0;
  const double cosBeam = std::min(1.0, std::abs(glm::dot(p, dir)) / r);
  const double sinBeam = std::sqrt(std::max(0.0, 1.0 - cosBeam * cosBeam));
  return std::min(c.gateMeters / std::max(cosBeam, 1e-6), r * c.acrossRad / std::max(sinBeam, 1e-6));
}

int stepLevel(double crossingMeters, double stepMeters, double samplesPerCell) {
  if (!(samplesPerCell > 0.0) || !(crossingMeters > 0.0) || !(stepMeters > 0.0)) return 0;
  const double q = crossingMeters / (samplesPerCell * stepMeters);
  if (!(q >= 2.0)) return 0;
  return std::min(static_cast<int>(std::floor(std::log2(q))), kMaxStepLevel);
}

CellScale cellScaleFromLevels(const std::vector<double>& meanHeights, double minHeightMeters, double maxHeightMeters,
                              double columnSpacingMeters) {
  CellScale c;
  c.columnSpacingMeters = asFloat(columnSpacingMeters > 0.0 ? columnSpacingMeters : 1e12);
  std::vector<double> h;
  for (double m : meanHeights)
    if (std::isfinite(m)) h.push_back(h.empty() ? m : std::max(m, h.back()));
  if (h.size() < 2 || !(maxHeightMeters > minHeightMeters)) return c;  // one level: no rule
  const int n = CellScale::kEntries;
  c.minHeightMeters = asFloat(minHeightMeters);
  c.entriesPerMeter = asFloat(n / (maxHeightMeters - minHeightMeters));
  c.levelSpacingMeters.assign(n, std::numeric_limits<double>::infinity());
  const double binMeters = 1.0 / c.entriesPerMeter;
  for (int e = 0; e < n; ++e) {
    const double lo = c.minHeightMeters + e * binMeters, hi = lo + binMeters;
    double& s = c.levelSpacingMeters[static_cast<std::size_t>(e)];
    for (std::size_t k = 0; k + 1 < h.size(); ++k) {
      const double dz = h[k + 1] - h[k];
      if (dz > 0.0 && h[k + 1] >= lo && h[k] <= hi) s = std::min(s, dz);
    }
    // Below the lowest or above the highest reference level: the nearest interval's spacing.
    if (!std::isfinite(s)) {
      for (std::size_t k = 0; k + 1 < h.size(); ++k) {
        const std::size_t kk = hi < h.front() ? k : h.size() - 2 - k;
        if (h[kk + 1] - h[kk] > 0.0) {
          s = h[kk + 1] - h[kk];
          break;
        }
      }
    }
    if (!std::isfinite(s)) s = maxHeightMeters - minHeightMeters;  // every level at one height
    s = asFloat(s);
  }
  return c;
}

}  // namespace atmoglobe::volume
