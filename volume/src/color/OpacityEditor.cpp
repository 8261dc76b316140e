// Opacity control-point editing (OpacityEditor.h).
#include <atmoglobe/volume/OpacityEditor.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {

std::size_t addOpacityPoint(std::vector<glm::dvec2>& points, glm::dvec2 point) {
  point.y = std::clamp(point.y, 0.0, 1.0);
  const auto at =
      std::lower_bound(points.begin(), points.end(), point.x, [](const glm::dvec2& p, double v) { return p.x < v; });
  if (at != points.end() && at->x == point.x) {
    *at = point;
    return static_cast<std::size_t>(at - points.begin());
  }
  const auto inserted = points.insert(at, point);  // may reallocate: begin() only after it
  return static_cast<std::size_t>(inserted - points.begin());
}

bool moveOpacityPoint(std::vector<glm::dvec2>& points, std::size_t index, glm::dvec2 to, double minGap) {
  if (index >= points.size()) return false;
  double lo = -INFINITY, hi = INFINITY;
  if (index > 0) lo = points[index - 1].x + minGap;
  if (index + 1 < points.size()) hi = points[index + 1].x - minGap;
  if (lo > hi) lo = hi = points[index].x;  // neighbours closer than two gaps: the value stays
  points[index] = glm::dvec2(std::clamp(to.x, lo, hi), std::clamp(to.y, 0.0, 1.0));
  return true;
}

bool deleteOpacityPoint(std::vector<glm::dvec2>& points, std::size_t index) {
  if (index >= points.size() || points.size() <= 2) return false;
  points.erase(points.begin() + static_cast<std::ptrdiff_t>(index));
  return true;
}

std::optional<std::size_t> pickOpacityPoint(const std::vector<glm::dvec2>& points, glm::dvec2 at,
                                            glm::dvec2 unitsPerPixel, double radiusPx) {
  std::optional<std::size_t> best;
  double bestPx = radiusPx;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::dvec2 d = (points[i] - at) / unitsPerPixel;
    const double px = std::hypot(d.x, d.y);
    if (px <= bestPx) {
      bestPx = px;
      best = i;
    }
  }
  return best;
}

}  // namespace atmoglobe::volume
