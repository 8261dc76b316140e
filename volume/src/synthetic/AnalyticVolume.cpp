// The analytic uniform shell (AnalyticVolume.h).
#include <atmoglobe/volume/AnalyticVolume.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace atmoglobe::volume {

UniformShellSampler::UniformShellSampler(const UniformShell& shell)
    : shell_(shell), centreEcef_(globe::geodeticToEcef(shell.centre)) {}

RayInterval UniformShellSampler::rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const {
  return raySphereInterval(eyeEcef, unitDirEcef, centreEcef_, shell_.outerRadiusMeters);
}

bool UniformShellSampler::provablyEmpty(const glm::dvec3& ecef) const {
  return glm::length(ecef - centreEcef_) > shell_.outerRadiusMeters;
}

VolumeSample UniformShellSampler::sample(const glm::dvec3& ecef, Interpolation) const {
  const double r = glm::length(ecef - centreEcef_);
  if (r > shell_.outerRadiusMeters) return {};
  if (r < shell_.innerRadiusMeters) return {VolumeSample::State::NoEcho, 0.0};
  return {VolumeSample::State::Echo, shell_.value};
}

std::string UniformShellSampler::description() const {
  std::ostringstream s;
  s << "uniform shell " << shell_.value << " at " << shell_.centre.latDeg << ", " << shell_.centre.lonDeg << ", "
    << shell_.centre.heightMeters << " m (radii " << shell_.innerRadiusMeters << ".." << shell_.outerRadiusMeters
    << " m)";
  return s.str();
}

double UniformShellSampler::pathLengthInside(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, double tMin,
                                             double tMax) const {
  auto chord = [&](double radius) {
    if (!(radius > 0.0)) return 0.0;
    const RayInterval i = raySphereInterval(eyeEcef, unitDirEcef, centreEcef_, radius);
    if (i.empty()) return 0.0;
    return std::max(0.0, std::min(i.tExitMeters, tMax) - std::max(i.tEnterMeters, tMin));
  };
  return chord(shell_.outerRadiusMeters) - chord(shell_.innerRadiusMeters);
}

glm::dvec4 uniformShellDvrClosedForm(const TransferFunction& transfer, double value, double pathLengthMeters) {
  const glm::dvec4 c = transfer.classify(value);
  const double alpha = 1.0 - std::exp(-transfer.extinctionPerMeter(c.a) * pathLengthMeters);
  return glm::dvec4(glm::dvec3(c) * alpha, alpha);
}

}  // namespace atmoglobe::volume
