#pragma once
// Vertical exaggeration, one rule for every volume kind: a point at geodetic (lat, lon, h) is
// drawn at (lat, lon, e h), h above the WGS84 ellipsoid, e > 0 (1 = true scale). The globe
// (h = 0) does not move, so radars, grids, slices and markers stay aligned with each other and
// with the ground.
//
// How each kind applies it (each exact in its reference path):
//   - grids: every level's height times e (exaggerateGrid): the grid's own geometry, so the GPU
//     and the reference sample the same exaggerated grid;
//   - radars: the sampler maps a drawn point back to (lat, lon, h / e) before the beam model
//     (ExaggeratedSampler, exact, in double: ecefToGeodetic / geodeticToEcef); the GPU does the
//     same on its local sphere (LocalSphereBeam::unexaggerateEnu; error: (1 - 1/e) times the
//     local sphere's height error, measured against this double path in the tests);
//   - slices and markers: heights times e where they are placed.
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <memory>
#include <string>

namespace atmoglobe::volume {

/// Checks a factor from a user: finite, 0.1 .. 100.
Status validateVerticalExaggeration(double factor, const std::string& where);

/// Every level height of `grid` times `factor`.
void exaggerateGrid(GridVolume& grid, double factor);

/// A sampler seen through a vertical exaggeration: sample(p) = inner.sample(p mapped to height
/// h / e). The ray interval is that of the bounding sphere grown by |e - 1| times the largest
/// height the inner volume can reach (conservative; only an acceleration bound).
class ExaggeratedSampler final : public VolumeSampler {
 public:
  /// Keeps a reference to `inner` (must outlive this).
  ExaggeratedSampler(const VolumeSampler& inner, double factor);
  RayInterval rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const override;
  VolumeSample sample(const glm::dvec3& ecef, Interpolation interpolation) const override;
  bool provablyEmpty(const glm::dvec3& ecef) const override;
  /// The inner rule at the point as drawn (the GPU's too): its cells are as tall or taller there.
  double cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const override {
    return inner_.cellCrossingMeters(ecef, unitDirEcef);
  }
  ValueRange valueRange() const override { return inner_.valueRange(); }
  BoundingSphere boundingSphere() const override { return sphere_; }
  std::string description() const override;
  double factor() const { return factor_; }
  /// The point drawn at `ecef` in the inner volume's true geometry.
  glm::dvec3 trueEcef(const glm::dvec3& ecef) const;

 private:
  const VolumeSampler& inner_;
  double factor_;
  BoundingSphere sphere_;
};

}  // namespace atmoglobe::volume
