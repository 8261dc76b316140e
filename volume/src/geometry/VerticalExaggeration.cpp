#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <cmath>

namespace atmoglobe::volume {

Status validateVerticalExaggeration(double factor, const std::string& where) {
  if (!(std::isfinite(factor) && factor >= 0.1 && factor <= 100.0))
    return makeError(where + ": vertical exaggeration must be a number from 0.1 to 100");
  return Ok{};
}

void exaggerateGrid(GridVolume& grid, double factor) {
  if (factor == 1.0) return;
  for (float& h : grid.heightAboveEllipsoidMeters) h = static_cast<float>(static_cast<double>(h) * factor);
}

ExaggeratedSampler::ExaggeratedSampler(const VolumeSampler& inner, double factor) : inner_(inner), factor_(factor) {
  const BoundingSphere s = inner.boundingSphere();
  // No point of the inner volume is higher than the far side of its sphere above the ellipsoid's
  // smallest radius, nor lower than its near side below the largest: |h| <= that bound, and a
  // point moves by |e - 1| |h| along its normal.
  const double centreRadius = glm::length(s.centreEcef);
  const double maxAbsHeight = std::max(centreRadius + s.radiusMeters - globe::kWgs84B,
                                       globe::kWgs84A - std::max(0.0, centreRadius - s.radiusMeters));
  sphere_ = {s.centreEcef, s.radiusMeters + std::abs(factor - 1.0) * std::max(0.0, maxAbsHeight)};
}

glm::dvec3 ExaggeratedSampler::trueEcef(const glm::dvec3& ecef) const {
  globe::Geodetic g = globe::ecefToGeodetic(ecef);
  g.heightMeters /= factor_;
  return globe::geodeticToEcef(g);
}

RayInterval ExaggeratedSampler::rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const {
  return raySphereInterval(eyeEcef, unitDirEcef, sphere_.centreEcef, sphere_.radiusMeters);
}

VolumeSample ExaggeratedSampler::sample(const glm::dvec3& ecef, Interpolation interpolation) const {
  return inner_.sample(factor_ == 1.0 ? ecef : trueEcef(ecef), interpolation);
}

bool ExaggeratedSampler::provablyEmpty(const glm::dvec3& ecef) const {
  return inner_.provablyEmpty(factor_ == 1.0 ? ecef : trueEcef(ecef));
}

std::string ExaggeratedSampler::description() const {
  return inner_.description() + " (vertical exaggeration " + std::to_string(factor_) + ")";
}

}  // namespace atmoglobe::volume
