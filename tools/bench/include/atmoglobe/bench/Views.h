#pragma once
// The bench's volumes and its fixed views of them. A bench volume is a radar volume or a
// forecast grid (one bench, many kinds: the kind only changes how it is loaded and sampled).
//
// Radar volumes: KLBB (NEXRAD Level II) and AU40 (ODIM_H5) of the shared sample data. Views per
// volume: *oblique*, 200 km from the antenna along a geodesic (KLBB from the south, AU40 from
// the south-west), 100 km up, looking at the antenna, fovY 50 deg; *down*, 400 km straight above
// the antenna, fovY 60 deg. The quick run: KLBB oblique only.
//
// Forecast grids (GridViews.h): the built-in SYNTHETIC regional and global grids or a file; each
// view draws the crop of the grid it can see (visibleCrop), the reference the whole grid.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/TransferFunction.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::bench {

enum class VolumeKind { Radar, Grid };

struct BenchVolume {
  std::string key;  ///< short name (KLBB, AU40, regional, global)
  std::string path;
  VolumeKind kind = VolumeKind::Radar;
  /// What the reference cache keys the volume by; empty: the path (radars: keys unchanged).
  /// The built-in synthetic grids: their generator and version, wherever the file is.
  std::string identity;
  volume::PolarVolume polar;  ///< radar
  /// Grid: the whole grid at the time step (what the reference samples; views draw crops).
  std::shared_ptr<const volume::GridVolume> grid;
  volume::GridReadOptions gridRead;  ///< grid: variable and time step it was read with
  /// Grid: the variables the heights come from (read beside the variable: the I/O floor reads them too).
  std::vector<std::string> heightVariables;
  /// What every cell draws with: radars the default reflectivity table; grids by the variable
  /// (volume::transferForField, "auto").
  volume::TransferFunction transfer = volume::defaultReflectivityTransfer();
  std::unique_ptr<engine::VolumeGL> gl;  ///< radar, null with --reference-only (no GL); grids: per view

  std::string cacheIdentity() const { return identity.empty() ? path : identity; }
  std::string fieldName() const { return kind == VolumeKind::Radar ? polar.fieldName : grid ? grid->variable : ""; }
  /// The double-precision sampler the reference draws (a PolarSampler or a GridSampler over the
  /// whole grid); built on first use, so call it only once the volume has its final address.
  const volume::VolumeSampler& referenceSampler() const;

 private:
  mutable std::shared_ptr<volume::VolumeSampler> sampler_;
};

struct BenchView {
  std::string name;
  const BenchVolume* volume = nullptr;
  engine::CameraPose pose;
  double fovYDeg = 50.0;
  /// The globe hides what is behind it: the reference takes no sample beyond the ray's first hit
  /// of the WGS84 ellipsoid and the marcher gets the ellipsoid's depth (ellipsoidDepthGL). Grid
  /// views; radar views are volume only (false: their reference keys are unchanged).
  bool occludeByEllipsoid = false;
  /// The GPU volume this view draws (a grid's crop, GridViews.h); null: volume->gl.
  std::shared_ptr<engine::VolumeGL> gl;
  volume::GridCrop crop;  ///< grid: the crop gl holds
  std::uint64_t cropBytesRead = 0;

  engine::VolumeGL* glVolume() const { return gl ? gl.get() : volume ? volume->gl.get() : nullptr; }
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
