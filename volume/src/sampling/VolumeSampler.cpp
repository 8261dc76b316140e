// Shared geometry of the samplers (VolumeSampler.h).
#include <atmoglobe/volume/VolumeSampler.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
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

namespace {

// The smallest sphere holding spheres a and b.
BoundingSphere enclose(const BoundingSphere& a, const BoundingSphere& b) {
  const glm::dvec3 d = b.centreEcef - a.centreEcef;
  const double dist = glm::length(d);
  if (dist + b.radiusMeters <= a.radiusMeters) return a;
  if (dist + a.radiusMeters <= b.radiusMeters) return b;
  const double r = 0.5 * (dist + a.radiusMeters + b.radiusMeters);
  // dist > 0 here (else one holds the other). The centre lies on the line of centres, r - ra
  // from a's centre; the radius grows by a millimetre so rounding cannot leave a point outside.
  return {a.centreEcef + d * ((r - a.radiusMeters) / dist), r + 1e-3};
}

bool meet(const BoundingSphere& a, const BoundingSphere& b) {
  return glm::length(b.centreEcef - a.centreEcef) <= a.radiusMeters + b.radiusMeters;
}

}  // namespace

std::vector<VolumeCluster> clusterBySphere(const std::vector<BoundingSphere>& spheres) {
  std::vector<VolumeCluster> clusters;
  for (std::size_t i = 0; i < spheres.size(); ++i) clusters.push_back({{i}, spheres[i]});
  // Merge any two that meet until none do (a handful of volumes: quadratic passes are fine).
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < clusters.size() && !merged; ++a)
      for (std::size_t b = a + 1; b < clusters.size() && !merged; ++b) {
        if (!meet(clusters[a].enclosing, clusters[b].enclosing)) continue;
        VolumeCluster& ca = clusters[a];
        ca.members.insert(ca.members.end(), clusters[b].members.begin(), clusters[b].members.end());
        std::sort(ca.members.begin(), ca.members.end());
        ca.enclosing = enclose(ca.enclosing, clusters[b].enclosing);
        clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(b));
        merged = true;
      }
  }
  return clusters;
}

void sortBackToFront(std::vector<VolumeCluster>& clusters, const glm::dvec3& eyeEcef) {
  auto power = [&](const VolumeCluster& c) {
    const glm::dvec3 d = eyeEcef - c.enclosing.centreEcef;
    return glm::dot(d, d) - c.enclosing.radiusMeters * c.enclosing.radiusMeters;
  };
  std::stable_sort(clusters.begin(), clusters.end(),
                   [&](const VolumeCluster& a, const VolumeCluster& b) { return power(a) > power(b); });
}

bool LonLatBox::contains(double latDeg, double lonDeg) const {
  if (!(latDeg >= southDeg && latDeg <= northDeg)) return false;
  if (spanDeg >= 360.0) return true;
  double d = std::fmod(lonDeg - westDeg, 360.0);
  if (d < 0.0) d += 360.0;
  return d <= spanDeg;
}

VolumeSample SamplerOutsideBox::sample(const glm::dvec3& ecef, Interpolation interpolation) const {
  const globe::Geodetic g = globe::ecefToGeodetic(ecef);
  if (hole_.contains(g.latDeg, g.lonDeg)) return VolumeSample{};
  return inner_.sample(ecef, interpolation);
}

}  // namespace atmoglobe::volume
