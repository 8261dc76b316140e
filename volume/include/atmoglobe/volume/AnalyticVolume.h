#pragma once
// An analytic volume: a uniform spherical shell at a geodetic place. Its emission-absorption
// integral has a closed form, so it checks both renderers (CPU reference and GPU marcher) against
// mathematics rather than against each other. GL-free.
//
// Field: `value` (Echo) for inner <= |p - c| <= outer, NoEcho for |p - c| < inner, NoData
// outside (c = the centre's ECEF). Interpolation does not apply (the field is piecewise constant).
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/TransferFunction.h>
#include <atmoglobe/volume/VolumeSampler.h>

namespace atmoglobe::volume {

struct UniformShell {
  globe::Geodetic centre;              ///< WGS84 latitude, longitude (deg), height above the ellipsoid (m)
  double innerRadiusMeters = 0.0;      ///< >= 0 (0: a ball)
  double outerRadiusMeters = 10000.0;  ///< > inner
  double value = 40.0;                 ///< field units
};

class UniformShellSampler final : public VolumeSampler {
 public:
  explicit UniformShellSampler(const UniformShell& shell);
  RayInterval rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const override;
  VolumeSample sample(const glm::dvec3& ecef, Interpolation interpolation) const override;
  bool provablyEmpty(const glm::dvec3& ecef) const override;
  ValueRange valueRange() const override { return {shell_.value, shell_.value}; }
  BoundingSphere boundingSphere() const override { return {centreEcef_, shell_.outerRadiusMeters}; }
  std::string description() const override;
  const UniformShell& shell() const { return shell_; }
  const glm::dvec3& centreEcef() const { return centreEcef_; }

  /// Length (m) of the ray eye + t dir (unit dir), tMin <= t <= tMax, inside the shell: the chord of
  /// the outer sphere minus that of the inner one. Exact.
  double pathLengthInside(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, double tMin, double tMax) const;

 private:
  UniformShell shell_;
  glm::dvec3 centreEcef_{0.0};
};

/// The closed form of DVR through the shell: premultiplied RGBA of a ray that spends L metres in
/// it, with the transfer function's colour c and extinction k of the shell's value:
/// alpha = 1 - exp(-k L), rgb = c * alpha (Max 1995, "Optical models for direct volume
/// rendering", emission-absorption with constant coefficients).
glm::dvec4 uniformShellDvrClosedForm(const TransferFunction& transfer, double value, double pathLengthMeters);

}  // namespace atmoglobe::volume
