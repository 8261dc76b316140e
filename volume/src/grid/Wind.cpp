// Wind components east and north, barb parts (Wind.h).
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Wind.h>

#include <cmath>
#include <limits>

namespace atmoglobe::volume {

std::vector<double> gridColumnAngles(const GridVolume& g) {
  std::vector<double> out(g.nx * g.ny, 0.0);
  if (!g.curvilinear || g.nx < 2) return out;  // rows along parallels: the column direction is east
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      const std::size_t a = i > 0 ? i - 1 : i, b = i + 1 < g.nx ? i + 1 : i;
      const double lat = g.latDegAt(j, i), lon = g.lonDegAt(j, i);
      const auto axes = globe::enuAxes(lat, lon);
      const glm::dvec3 pa = globe::geodeticToEcef({g.latDegAt(j, a), g.lonDegAt(j, a), 0.0});
      const glm::dvec3 pb = globe::geodeticToEcef({g.latDegAt(j, b), g.lonDegAt(j, b), 0.0});
      const glm::dvec3 d = pb - pa;
      out[j * g.nx + i] = std::atan2(glm::dot(d, axes[1]), glm::dot(d, axes[0]));
    }
  return out;
}

Result<WindComponents> earthRelativeWind(const GridVolume& u, const GridVolume& v) {
  if (u.reduced() || v.reduced()) return makeError(u.path + ": wind on a reduced grid is not drawn yet");
  if (u.nx != v.nx || u.ny != v.ny || u.curvilinear != v.curvilinear || u.latDeg != v.latDeg || u.lonDeg != v.lonDeg)
    return makeError(u.path + ": '" + u.variable + "' and '" + v.variable + "' are not on the same grid");
  const std::size_t n = u.nx * u.ny;
  if (u.values.size() < n || v.values.size() < n) return makeError(u.path + ": wind components without values");
  WindComponents w;
  w.eastMps.assign(n, std::numeric_limits<float>::quiet_NaN());
  w.northMps = w.eastMps;
  const bool turn = u.vectorsRelativeToGrid || v.vectorsRelativeToGrid;
  const std::vector<double> alpha = turn ? gridColumnAngles(u) : std::vector<double>(n, 0.0);
  for (std::size_t c = 0; c < n; ++c) {
    const double uu = u.values[c], vv = v.values[c];
    if (!std::isfinite(uu) || !std::isfinite(vv)) continue;
    const double ca = std::cos(alpha[c]), sa = std::sin(alpha[c]);
    w.eastMps[c] = static_cast<float>(uu * ca - vv * sa);
    w.northMps[c] = static_cast<float>(uu * sa + vv * ca);
  }
  return w;
}

BarbParts barbParts(double speedKnots) {
  BarbParts p;
  if (!(speedKnots >= 2.5)) {
    p.calm = true;
    return p;
  }
  int rest = 5 * static_cast<int>(std::lround(speedKnots / 5.0));
  p.pennants = rest / 50;
  rest -= 50 * p.pennants;
  p.full = rest / 10;
  rest -= 10 * p.full;
  p.half = rest >= 5 ? 1 : 0;
  return p;
}

std::vector<std::vector<glm::dvec2>> barbPolylines(double eastMps, double northMps, bool southernHemisphere) {
  std::vector<std::vector<glm::dvec2>> out;
  const double speed = std::hypot(eastMps, northMps);
  const BarbParts parts = barbParts(speed * kKnotsPerMps);
  if (parts.calm) {
    std::vector<glm::dvec2> circle;
    for (int k = 0; k <= 16; ++k) {
      const double a = 2.0 * 3.14159265358979323846 * k / 16.0;
      circle.emplace_back(0.15 * std::cos(a), 0.15 * std::sin(a));
    }
    out.push_back(std::move(circle));
    return out;
  }
  const glm::dvec2 w = -glm::dvec2(eastMps, northMps) / speed;  // toward where the wind comes from
  const glm::dvec2 side = southernHemisphere ? glm::dvec2(-w.y, w.x) : glm::dvec2(w.y, -w.x);
  constexpr double kStep = 0.14, kBarb = 0.4;
  out.push_back({glm::dvec2(0.0), w});
  double t = 1.0;  // along the shaft, from its outer end inward
  for (int k = 0; k < parts.pennants; ++k, t -= kStep)
    out.push_back({t * w, t * w + kBarb * side, (t - kStep) * w, t * w});
  if (parts.pennants > 0) t -= 0.04;  // a gap after the pennants
  for (int k = 0; k < parts.full; ++k, t -= kStep) out.push_back({t * w, t * w + kBarb * side + 0.1 * w});
  if (parts.half) {
    if (parts.pennants == 0 && parts.full == 0) t -= kStep;  // alone: not at the end, not a full barb
    out.push_back({t * w, t * w + 0.5 * kBarb * side + 0.05 * w});
  }
  return out;
}

}  // namespace atmoglobe::volume
