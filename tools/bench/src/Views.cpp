#include <atmoglobe/bench/Views.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/RadarLoad.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::bench {

std::vector<BenchFile> benchFiles(bool quick) {
  std::vector<BenchFile> files = {{"KLBB", "radar_nexrad/KLBB20160601_150025_V06"},
                                  {"AU40", "radar_odim/40_20181220_060630.pvol.h5"}};
  if (quick) files.resize(1);
  return files;
}

std::vector<std::string> benchViewNames(const std::vector<BenchFile>& files, bool quick) {
  std::vector<std::string> names;
  for (const BenchFile& f : files) {
    names.push_back(f.key + "-oblique");
    if (!quick) names.push_back(f.key + "-down");
  }
  return names;
}

const volume::VolumeSampler& BenchVolume::referenceSampler() const {
  if (!sampler_) {
    if (kind == VolumeKind::Grid) sampler_ = std::make_shared<volume::GridSampler>(*grid);
    else sampler_ = std::make_shared<volume::PolarSampler>(polar);
  }
  return *sampler_;
}

Result<BenchVolume> loadBenchVolume(const std::string& key, const std::string& path) {
  volume::RadarLoadOptions load;
  load.buildRenderLayout = true;
  auto radar = volume::loadRadar(path, load);
  if (!radar) return radar.forwardError();
  BenchVolume v;
  v.key = key;
  v.path = path;
  v.polar = std::move(*radar->layout);
  return v;
}

engine::CameraPose lookAtPose(const globe::Geodetic& eye, const glm::dvec3& targetEcef) {
  const glm::dvec3 eyeEcef = globe::geodeticToEcef(eye);
  const glm::dmat3 enu = globe::enuAxes(eye.latDeg, eye.lonDeg);
  const glm::dvec3 d = glm::normalize(targetEcef - eyeEcef);
  const double e = glm::dot(d, enu[0]), n = glm::dot(d, enu[1]), u = glm::dot(d, enu[2]);
  engine::CameraPose p;
  p.latDeg = eye.latDeg;
  p.lonDeg = eye.lonDeg;
  p.heightMeters = eye.heightMeters;
  p.headingDeg = radiansToDegrees(std::atan2(e, n));
  p.pitchDeg = radiansToDegrees(std::asin(std::clamp(u, -1.0, 1.0)));
  return p;
}

BenchView obliqueView(const std::string& name, const BenchVolume& v, double bearingDeg, double distanceMeters,
                      double heightMeters) {
  const volume::GeolocationSite& s = v.polar.site;
  const globe::GeodesicPoint g = globe::geodesicDirect(s.latDeg, s.lonDeg, bearingDeg, distanceMeters);
  const glm::dvec3 site = globe::geodeticToEcef({s.latDeg, s.lonDeg, s.antennaHeightEllipsoidMeters});
  BenchView view;
  view.name = name;
  view.volume = &v;
  view.pose = lookAtPose({g.latDeg, g.lonDeg, heightMeters}, site);
  view.fovYDeg = 50.0;
  return view;
}

BenchView topDownView(const std::string& name, const BenchVolume& v, double heightMeters) {
  engine::CameraPose p;
  p.latDeg = v.polar.site.latDeg;
  p.lonDeg = v.polar.site.lonDeg;
  p.heightMeters = heightMeters;
  p.headingDeg = 0.0;
  p.pitchDeg = -90.0;
  BenchView view;
  view.name = name;
  view.volume = &v;
  view.pose = p;
  view.fovYDeg = 60.0;
  return view;
}

std::vector<BenchView> standardViews(const std::vector<std::unique_ptr<BenchVolume>>& volumes, bool quick) {
  // Oblique: 200 km out, 100 km up, looking at the antenna; down: 400 km straight above it.
  std::vector<BenchView> views;
  for (const auto& v : volumes) {
    const double bearing = v->key == "KLBB" ? 180.0 : 225.0;
    views.push_back(obliqueView(v->key + "-oblique", *v, bearing, 200e3, 100e3));
    if (!quick) views.push_back(topDownView(v->key + "-down", *v, 400e3));
  }
  return views;
}

}  // namespace atmoglobe::bench
