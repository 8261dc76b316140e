// Shared geometry of the samplers (VolumeSampler.h).
#include <atmoglobe/volume/VolumeSampler.h>

#include <cmath>

namespace atmoglobe::volume {

RayInterval raySphereInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, const glm::dvec3& centreEcef,
                              double radiusMeters) {
  const glm::dvec3 oc = eyeEcef - centreEcef;
  const double b = glm::dot(oc, unitDirEcef);
  const glm::dvec3 perp = oc - b * unitDirEcef;
  const double disc = radiusMeters * radiusMeters - glm::dot(perp, perp);
  if (!(disc >= 0.0)) return {};
  const double h = std::sqrt(disc);
  return {-b - h, -b + h};
}

}  // namespace atmoglobe::volume
