#include <atmoglobe/engine/ViewCulling.h>

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Horizon.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace atmoglobe::engine {

bool sphereMayBeVisible(const Camera& camera, const volume::BoundingSphere& s) {
  const globe::ViewState view = camera.viewState();
  for (const glm::dvec4& p : view.frustumPlanesEcef)
    if (glm::dot(glm::dvec3(p), s.centreEcef) + p.w < -s.radiusMeters) return false;
  // Horizon: in scaled space (ECEF / (a, a, b)) the sphere lies within a ball of radius r / b
  // about c. For a point P of that ball outside the unit sphere, angle(P, c) <= asin(r'/|c|) and
  // acos(1/|P|) <= acos(1/(|c| + r')), so Q = m c/|c| with m = 1/cos(sum) hides all of them
  // when it is hidden (Horizon.h's rule); points inside the unit sphere are inside the Earth.
  const glm::dvec3 c = globe::ecefToScaledSpace(s.centreEcef);
  const double len = glm::length(c), r = s.radiusMeters / globe::kWgs84B;
  if (len <= r || len + r <= 1.0) return true;
  const double angle = std::asin(r / len) + std::acos(1.0 / (len + r));
  if (angle >= 0.5 * std::numbers::pi - 1e-9) return true;
  const glm::dvec3 q = c / len / std::cos(angle);
  return !globe::isScaledSpacePointOccluded(globe::ecefToScaledSpace(camera.eyeEcef()), q);
}

Result<RadarFootprint> radarFootprint(const std::string& path, double verticalExaggeration) {
  std::string file = path;
  if (volume::isRadarFileSet(path)) {
    auto files = volume::expandRadarPaths(path);
    if (!files) return files.forwardError();
    if (files->empty()) return makeError(path + ": no radar files");
    file = files->front();
  }
  volume::ReadOptions o;
  o.loadValues = false;
  auto v = volume::readRadarVolume(file, o);
  if (!v) return v.forwardError();
  double rangeMeters = 0.0;
  for (const volume::Sweep& s : v->sweeps) {
    if (s.gateCount == 0) continue;
    const double last = s.gateRangeMeters(s.gateCount - 1) + 0.5 * s.gateSpacingMeters;
    const double halfBeamRad = 0.5 * (v->beamWidthDeg > 0.0 ? v->beamWidthDeg : 2.0) * std::numbers::pi / 180.0;
    rangeMeters = std::max(rangeMeters, last + last * std::sin(halfBeamRad));
  }
  if (!(rangeMeters > 0.0)) rangeMeters = 500e3;
  RadarFootprint f;
  f.latDeg = v->site.latDeg;
  f.lonDeg = v->site.lonDeg;
  f.siteName = volume::siteTitle(v->site);
  volume::BoundingSphere& b = f.sphere;
  b.centreEcef = globe::geodeticToEcef({v->site.latDeg, v->site.lonDeg, v->site.antennaHeightMeters});
  // The geoid (|N| < 110 m) and the antenna's own height under exaggeration: a margin of 1 km.
  b.radiusMeters = rangeMeters * std::max(1.0, verticalExaggeration) + 1000.0 +
                   std::abs(v->site.antennaHeightMeters) * std::max(0.0, verticalExaggeration - 1.0);
  return f;
}

Result<volume::BoundingSphere> radarBoundingSphere(const std::string& path, double verticalExaggeration) {
  auto f = radarFootprint(path, verticalExaggeration);
  if (!f) return f.forwardError();
  return f->sphere;
}

std::vector<DeferredRadar> deferRadarsOutsideView(SceneDescription& scene, const Camera& camera) {
  std::vector<DeferredRadar> deferred;
  std::vector<VolumeLayerDescription> kept;
  std::vector<std::string> keptOrigins;
  for (std::size_t i = 0; i < scene.volumes.size(); ++i) {
    const VolumeLayerDescription& d = scene.volumes[i];
    const std::string origin = i < scene.origins.volumes.size() ? scene.origins.volumes[i] : std::string();
    if (d.kind == VolumeKind::Radar) {
      auto footprint = radarFootprint(d.path, scene.verticalExaggeration);
      if (footprint && !sphereMayBeVisible(camera, footprint->sphere)) {
        deferred.push_back(DeferredRadar{d, origin, std::move(*footprint)});
        continue;
      }
    }
    kept.push_back(d);
    if (i < scene.origins.volumes.size()) keptOrigins.push_back(origin);
  }
  scene.volumes = std::move(kept);
  scene.origins.volumes = std::move(keptOrigins);
  return deferred;
}

CullOutcome cullRadarsOutsideView(SceneDescription& scene, const Camera& camera) {
  CullOutcome out;
  for (DeferredRadar& d : deferRadarsOutsideView(scene, camera)) out.culled.push_back(std::move(d.description.path));
  for (const VolumeLayerDescription& d : scene.volumes) out.kept += d.kind == VolumeKind::Radar ? 1 : 0;
  return out;
}

}  // namespace atmoglobe::engine
