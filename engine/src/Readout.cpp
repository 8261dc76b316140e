#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/Geolocation.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace atmoglobe::engine {

namespace {

struct Hit {
  double t = 0.0;
  double value = 0.0;
  glm::dvec3 ecef{0.0};
};

// The first echo of `sampler` along eye + t dir, t in its ray interval up to tMax.
std::optional<Hit> firstEcho(const volume::VolumeSampler& sampler, const glm::dvec3& eye, const glm::dvec3& dir,
                             double tMax, double step, volume::Interpolation interpolation) {
  const volume::RayInterval span = sampler.rayInterval(eye, dir);
  const double t0 = std::max(span.tEnterMeters, 0.0), t1 = std::min(span.tExitMeters, tMax);
  if (!(t1 > t0)) return std::nullopt;
  const auto n = static_cast<long>(std::min(1e6, std::ceil((t1 - t0) / step)));
  for (long k = 0; k <= n; ++k) {
    const double t = std::min(t1, t0 + static_cast<double>(k) * step);
    const glm::dvec3 p = eye + t * dir;
    const volume::VolumeSample s = sampler.sample(p, interpolation);
    if (s.state == volume::VolumeSample::State::Echo) return Hit{t, s.value, p};
  }
  return std::nullopt;
}

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

/// Height above mean sea level (EGM96) of a geodetic point; the ellipsoidal height without the grid.
double seaLevelHeight(const globe::Geodetic& g) {
  const auto& geoid = volume::defaultEgm96Grid();
  return geoid ? g.heightMeters - geoid->undulationMeters(g.latDeg, g.lonDeg) : g.heightMeters;
}

}  // namespace

CursorReadout readoutAt(const SceneRendererGL& scene, const Camera& camera, double xPx, double yPx, double stepMeters) {
  CursorReadout out;
  const glm::dvec3 eye = camera.eyeEcef();
  const glm::dvec3 dir = camera.pixelRayDirection(xPx, yPx);
  double tGround = std::numeric_limits<double>::infinity();
  if (auto hit = globe::intersectRayEllipsoid(eye, dir)) {
    tGround = glm::length(*hit - eye);
    const globe::Geodetic g = globe::ecefToGeodetic(*hit);
    out.groundLatLonHeight = glm::dvec3(g.latDeg, g.lonDeg, g.heightMeters);
    out.seaLevelHeightMeters = seaLevelHeight(g);
  }
  for (const RadarLayerGL& r : scene.radars()) {
    if (!r.visible) continue;  // switched off in the panel
    // Radars: the first gate with an echo along the ray, read as stored (nearest-neighbour
    // sampling), so the value and the gate are those `atmoglobe gates` lists.
    const auto hit =
        firstEcho(r.volume->referenceSampler(), eye, dir, tGround, stepMeters, volume::Interpolation::Nearest);
    if (!hit) continue;
    const volume::PolarVolume& p = r.volume->polar();
    // Antenna coordinates of the true point (the drawn one mapped back under an exaggeration).
    glm::dvec3 trueEcef = hit->ecef;
    if (r.volume->exaggeration() != 1.0) {
      globe::Geodetic g = globe::ecefToGeodetic(hit->ecef);
      g.heightMeters /= r.volume->exaggeration();
      trueEcef = globe::geodeticToEcef(g);
    }
    const volume::AntennaCoordinates a = volume::antennaCoordinatesExact(p.site, p.beam, trueEcef);
    const auto gate = volume::nearestGate(p, a.rangeMeters, a.azimuthDeg, a.elevationDeg);
    if (!gate) continue;  // cannot happen for an echo sample; kept for safety
    const globe::Geodetic g = globe::ecefToGeodetic(trueEcef);
    out.lines.push_back((r.siteName.empty() ? std::string("radar") : r.siteName) + " " + p.fieldName + ": " +
                        format("%.1f ", static_cast<double>(gate->value)) + p.fieldUnits +
                        format("  (sweep %.2f deg, azimuth %.1f deg, range %.3f km, height %.0f m", gate->elevationDeg,
                               gate->azimuthDeg, gate->rangeMeters / 1000.0, g.heightMeters) +
                        format(" above the ellipsoid, %.0f m above sea level)", seaLevelHeight(g)));
  }
  for (const GridLayerGL& gl : scene.grids()) {
    if (!gl.visible) continue;
    const auto hit =
        firstEcho(gl.volume->referenceSampler(), eye, dir, tGround, stepMeters, volume::Interpolation::Linear);
    if (!hit) continue;
    const volume::GridVolume& v = gl.volume->grid();
    const globe::Geodetic g = globe::ecefToGeodetic(hit->ecef);
    std::string variable = v.variable;
    if (!variable.empty() && variable.front() == '/') variable.erase(0, 1);
    out.lines.push_back(
        variable + ": " + format("%.4g ", hit->value) + v.units +
        format("  (at %.3f, %.3f, drawn height %.0f m above the ellipsoid, ", g.latDeg, g.lonDeg, g.heightMeters) +
        format("%.0f m above sea level)", seaLevelHeight(g)));
  }
  if (out.groundLatLonHeight) {
    out.lines.push_back(format("ground %.4f, %.4f", out.groundLatLonHeight->x, out.groundLatLonHeight->y) +
                        format("  (ellipsoid 0 m = %.1f m above sea level)", out.seaLevelHeightMeters));
  } else {
    out.lines.push_back("sky");
  }
  return out;
}

}  // namespace atmoglobe::engine
