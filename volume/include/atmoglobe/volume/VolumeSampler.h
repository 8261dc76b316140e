#pragma once
// The interface every kind of volume data implements for rendering (radar volumes in their
// polar geometry, analytic test volumes, forecast grids): GL-free, double precision, ECEF.
// The CPU reference renderer (ReferenceRenderer.h) draws any set of samplers; the GPU marcher
// has one GLSL twin per kind (engine/VolumeGL.h, shaders/sample_*.glsl).
//
// A sample is one of three states (the same distinction as the readers keep): Echo with a
// value, NoEcho (measured, nothing there: below the radar's noise level, a zero mixing
// ratio), NoData (not observed, outside the volume). The renderers draw only Echo samples.
#include <glm/glm.hpp>

#include <limits>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// How a sampler interpolates between its data points (each kind says what that means).
enum class Interpolation { Nearest, Linear };

struct VolumeSample {
  enum class State { NoData, NoEcho, Echo };
  State state = State::NoData;
  double value = 0.0;  ///< field units; valid when state == Echo
};

/// The interval [tEnterMeters, tExitMeters] of a ray eye + t dir (unit dir, t in metres) outside
/// which the volume has no data; empty when tExit < tEnter.
struct RayInterval {
  double tEnterMeters = 0.0;
  double tExitMeters = -1.0;
  bool empty() const { return !(tExitMeters >= tEnterMeters); }
};

/// Range of the measured (Echo) values, for transfer-function tables.
struct ValueRange {
  double minValue = 0.0;
  double maxValue = 0.0;
};

/// The interval of the ray eye + t dir (unit dir) inside the sphere |p - centre| <= radius
/// (all ECEF, m); empty if it misses. The centre's distance from the ray's line comes from the
/// perpendicular part of (eye - centre), which does not cancel when the eye is far away.
RayInterval raySphereInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, const glm::dvec3& centreEcef,
                              double radiusMeters);

/// A sphere (ECEF centre, radius in m).
struct BoundingSphere {
  glm::dvec3 centreEcef{0.0};
  double radiusMeters = 0.0;
};

/// Volumes that can be drawn apart: the members (indices into the input, ascending) and a
/// sphere enclosing all of their spheres.
struct VolumeCluster {
  std::vector<std::size_t> members;
  BoundingSphere enclosing;
};

/// Partitions volumes, given their bounding spheres, into clusters whose enclosing spheres are
/// pairwise disjoint: volumes whose spheres intersect or touch end in one cluster, and clusters
/// whose enclosing spheres meet are merged until none do. Along any ray, everything of one
/// cluster then lies wholly before or wholly after everything of another, so clusters can be
/// integrated separately and composited in order (clusterBackToFront) with the same result as one
/// integral of all volumes.
std::vector<VolumeCluster> clusterBySphere(const std::vector<BoundingSphere>& spheres);

/// Sorts clusters back to front as seen from `eyeEcef`: by decreasing power of the eye with
/// respect to the enclosing sphere, |eye - c|^2 - r^2. For disjoint spheres the radical plane
/// separates them and the eye lies on the side of the sphere of smaller power, so every ray
/// from the eye that meets both meets that one first: the order is exact for every pixel.
void sortBackToFront(std::vector<VolumeCluster>& clusters, const glm::dvec3& eyeEcef);

class VolumeSampler {
 public:
  virtual ~VolumeSampler() = default;

  /// Where along the ray the data can be: every point with an Echo or NoEcho sample lies in
  /// the interval (conservative: it may be larger). The renderers take samples only there.
  virtual RayInterval rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const = 0;

  /// The sample at an ECEF point (m), by the kind's sampling rule.
  virtual VolumeSample sample(const glm::dvec3& ecef, Interpolation interpolation) const = 0;

  /// Conservative emptiness: true only if sample(ecef, any interpolation) is NoData, and cheaper
  /// than sample(); false is always a correct answer. An acceleration only: the reference
  /// renderer's images do not depend on it (tested per kind).
  virtual bool provablyEmpty(const glm::dvec3& ecef) const {
    (void)ecef;
    return false;
  }

  /// The length of ray that crosses one of the kind's cells at `ecef` going along `unitDirEcef`
  /// (the step rule, StepRule.h). 0: the kind has no rule, its samples take the fixed step.
  virtual double cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const {
    (void)ecef;
    (void)unitDirEcef;
    return 0.0;
  }

  /// The range of Echo values (finite; min <= max).
  virtual ValueRange valueRange() const = 0;

  /// A sphere that holds every point with an Echo or NoEcho sample and every rayInterval
  /// (the renderers draw volumes whose spheres are disjoint apart: clusterBySphere).
  virtual BoundingSphere boundingSphere() const = 0;

  /// One line for messages ("KLBB REF from FILE", "uniform shell at ...").
  virtual std::string description() const = 0;
};

/// A latitude/longitude box: longitudes westDeg .. westDeg + spanDeg (taken modulo 360; span 360:
/// every longitude), latitudes southDeg .. northDeg, edges included.
struct LonLatBox {
  double westDeg = 0.0, spanDeg = 0.0, southDeg = 0.0, northDeg = 0.0;
  bool contains(double latDeg, double lonDeg) const;
};

/// A volume sampled everywhere except in a latitude/longitude box (at every height), where it has
/// no data: the far part of a grid drawn with a finer copy of the near part in the box
/// (engine::GridSourceGL; the GPU's twin is sample_grid.glsl's hole). Everything else is the
/// inner sampler's. Keeps a reference to `inner`.
class SamplerOutsideBox final : public VolumeSampler {
 public:
  SamplerOutsideBox(const VolumeSampler& inner, const LonLatBox& hole) : inner_(inner), hole_(hole) {}
  RayInterval rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const override {
    return inner_.rayInterval(eyeEcef, unitDirEcef);
  }
  VolumeSample sample(const glm::dvec3& ecef, Interpolation interpolation) const override;
  bool provablyEmpty(const glm::dvec3& ecef) const override { return inner_.provablyEmpty(ecef); }
  double cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const override {
    return inner_.cellCrossingMeters(ecef, unitDirEcef);
  }
  ValueRange valueRange() const override { return inner_.valueRange(); }
  BoundingSphere boundingSphere() const override { return inner_.boundingSphere(); }
  std::string description() const override { return inner_.description(); }
  const LonLatBox& hole() const { return hole_; }

 private:
  const VolumeSampler& inner_;
  LonLatBox hole_;
};

}  // namespace atmoglobe::volume
