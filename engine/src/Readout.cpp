#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/volume/Geoid.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace atmoglobe::engine {

std::optional<RayValue> firstValueAlong(const volume::VolumeSampler& sampler, const glm::dvec3& eye,
                                        const glm::dvec3& dir, double tMax, double step,
                                        volume::Interpolation interpolation) {
  const volume::RayInterval span = sampler.rayInterval(eye, dir);
  const double t0 = std::max(span.tEnterMeters, 0.0), t1 = std::min(span.tExitMeters, tMax);
  if (!(t1 > t0)) return std::nullopt;
  const auto n = static_cast<long>(std::min(1e6, std::ceil((t1 - t0) / step)));
  for (long k = 0; k <= n; ++k) {
    const double t = std::min(t1, t0 + static_cast<double>(k) * step);
    const glm::dvec3 p = eye + t * dir;
    const volume::VolumeSample s = sampler.sample(p, interpolation);
    if (s.state == volume::VolumeSample::State::Echo) return RayValue{t, s.value, p};
  }
  return std::nullopt;
}

double seaLevelHeightMeters(const globe::Geodetic& g) {
  const auto& geoid = volume::defaultEgm96Grid();
  return geoid ? g.heightMeters - geoid->undulationMeters(g.latDeg, g.lonDeg) : g.heightMeters;
}

std::string memberValuesLine(const std::vector<std::pair<long, double>>& members) {
  std::string line = "  members (" + std::to_string(members.size()) + "):";
  for (std::size_t m = 0; m < members.size(); ++m) {
    if (m == kReadoutMembers) {
      line += " ...";
      break;
    }
    char value[48];
    std::snprintf(value, sizeof value, " %ld: %.4g", members[m].first, members[m].second);
    line += value;
  }
  return line;
}

CursorReadout readoutAt(const SceneRendererGL& scene, const Camera& camera, double xPx, double yPx, double stepMeters) {
  CursorReadout out;
  const glm::dvec3 eye = camera.eyeEcef();
  const glm::dvec3 dir = camera.pixelRayDirection(xPx, yPx);
  double tGround = std::numeric_limits<double>::infinity();
  if (auto hit = globe::intersectRayEllipsoid(eye, dir)) {
    tGround = glm::length(*hit - eye);
    const globe::Geodetic g = globe::ecefToGeodetic(*hit);
    out.groundLatLonHeight = glm::dvec3(g.latDeg, g.lonDeg, g.heightMeters);
    out.seaLevelHeightMeters = seaLevelHeightMeters(g);
  }
  for (std::size_t i = 0; i < scene.volumeLayerCount(); ++i) {
    const VolumeSourceGL& layer = scene.layer(i);
    if (!layer.visible) continue;  // switched off in the panel
    if (auto line = layer.readoutAt(eye, dir, tGround, stepMeters)) out.lines.push_back(std::move(*line));
  }
  // Each map's value where the ray meets the ground (the field's own interpolation, as drawn).
  if (out.groundLatLonHeight)
    for (const auto& surface : scene.surfaces()) {
      if (!surface->visible) continue;
      const double latDeg = out.groundLatLonHeight->x, lonDeg = out.groundLatLonHeight->y;
      const double v = surface->sampler().valueAt(latDeg, lonDeg);
      if (!std::isfinite(v)) continue;
      const volume::GridVolume& g = surface->field().grid;
      char line[240];
      std::snprintf(line, sizeof line, "%s: %.4g %s%s", surface->field().name.c_str(), v, g.units.c_str(),
                    g.ensembleStatistic.empty() ? "" : (" (" + g.ensembleStatistic + ")").c_str());
      out.lines.push_back(line);
      // An ensemble statistic: every member's value there too.
      if (const auto members = surface->memberValuesAt(latDeg, lonDeg); !members.empty())
        out.lines.push_back(memberValuesLine(members));
    }
  if (out.groundLatLonHeight) {
    char line[160];
    std::snprintf(line, sizeof line, "ground %.4f, %.4f  (ellipsoid 0 m = %.1f m above sea level)",
                  out.groundLatLonHeight->x, out.groundLatLonHeight->y, out.seaLevelHeightMeters);
    out.lines.push_back(line);
  } else {
    out.lines.push_back("sky");
  }
  return out;
}

}  // namespace atmoglobe::engine
