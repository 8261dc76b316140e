#pragma once
// The bench's volumes and its fixed views of them.
//
// Volumes: KLBB (NEXRAD Level II) and AU40 (ODIM_H5) of the shared sample data. Views per
// volume: *oblique*, 200 km from the antenna along a geodesic (KLBB from the south, AU40 from
// the south-west), 100 km up, looking at the antenna, fovY 50 deg; *down*, 400 km straight above
// the antenna, fovY 60 deg. The quick run: KLBB oblique only.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::bench {

struct BenchVolume {
  std::string key;  ///< short name (KLBB, AU40)
  std::string path;
  volume::PolarVolume polar;
  std::unique_ptr<engine::RadarVolumeGL> gl;  ///< null with --reference-only (no GL)
};

struct BenchView {
  std::string name;
  const BenchVolume* volume = nullptr;
  engine::CameraPose pose;
  double fovYDeg = 50.0;
};

/// A volume of the bench: key and path relative to the data directory.
struct BenchFile {
  std::string key;
  std::string relativePath;
};

/// KLBB then AU40; quick: KLBB only.
std::vector<BenchFile> benchFiles(bool quick);

/// The names of the views of `files`: KEY-oblique, and KEY-down unless quick.
std::vector<std::string> benchViewNames(const std::vector<BenchFile>& files, bool quick);

/// Reads, geolocates (EGM96 geoid) and lays out a volume through volume::loadRadar, default
/// field (reflectivity), no GL. Errors name the file.
Result<BenchVolume> loadBenchVolume(const std::string& key, const std::string& path);

/// Pose at `eye` looking at `targetEcef` (heading/pitch from the local ENU frame at the eye).
engine::CameraPose lookAtPose(const globe::Geodetic& eye, const glm::dvec3& targetEcef);

/// An oblique view: the camera `distanceMeters` from the site along the geodesic of
/// `bearingDeg`, `heightMeters` up (above the ellipsoid), looking at the antenna; fovY 50 deg.
BenchView obliqueView(const std::string& name, const BenchVolume& v, double bearingDeg, double distanceMeters,
                      double heightMeters);

/// Straight down from `heightMeters` above the antenna, north up; fovY 60 deg.
BenchView topDownView(const std::string& name, const BenchVolume& v, double heightMeters);

/// The standard views of `volumes` in order (oblique, then down unless quick, per volume).
std::vector<BenchView> standardViews(const std::vector<std::unique_ptr<BenchVolume>>& volumes, bool quick);

}  // namespace atmoglobe::bench
