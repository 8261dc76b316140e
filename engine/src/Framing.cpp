#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Framing.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GridReader.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace atmoglobe::engine {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
/// WGS84 mean radius (2a + b) / 3 (m): the framing is a matter of per cent, not of flattening.
constexpr double kMeanRadiusMeters = (2.0 * globe::kWgs84A + globe::kWgs84B) / 3.0;

glm::dvec3 unitOf(double latDeg, double lonDeg) {
  return {std::cos(latDeg * kDeg) * std::cos(lonDeg * kDeg), std::cos(latDeg * kDeg) * std::sin(lonDeg * kDeg),
          std::sin(latDeg * kDeg)};
}
double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) / kDeg;
}
}  // namespace

GeoCap capOfBox(double southDeg, double northDeg, double westDeg, double eastDeg) {
  double span = eastDeg - westDeg;
  if (span < 0.0) span += 360.0;  // crosses the antimeridian
  if (span >= 360.0) {
    if (southDeg > 0.0) return {90.0, 0.0, 90.0 - southDeg};
    if (northDeg < 0.0) return {-90.0, 0.0, northDeg + 90.0};
    return {0.0, 0.0, 180.0};
  }
  GeoCap cap;
  cap.latDeg = 0.5 * (southDeg + northDeg);
  cap.lonDeg = globe::wrapLongitudeDeg(westDeg + 0.5 * span);
  const glm::dvec3 c = unitOf(cap.latDeg, cap.lonDeg);
  // The farthest point of the box from its centre is on its edge: corners, edge midpoints and
  // points between (a wide box's edge bulges away from the centre), 8 per edge.
  for (int i = 0; i <= 8; ++i) {
    const double lon = westDeg + span * i / 8.0, lat = southDeg + (northDeg - southDeg) * i / 8.0;
    for (const glm::dvec3& p :
         {unitOf(southDeg, lon), unitOf(northDeg, lon), unitOf(lat, westDeg), unitOf(lat, westDeg + span)})
      cap.radiusDeg = std::max(cap.radiusDeg, angleDeg(c, p));
  }
  return cap;
}

Result<GeoCap> capOfCaps(const std::vector<GeoCap>& caps) {
  if (caps.empty()) return makeError("no volumes to frame");
  glm::dvec3 sum(0.0);
  for (const GeoCap& c : caps) sum += unitOf(c.latDeg, c.lonDeg);
  GeoCap out = caps.front();
  if (caps.size() == 1) return out;
  if (glm::length(sum) < 1e-9) return GeoCap{0.0, 0.0, 180.0};  // opposite sides of the Earth
  const glm::dvec3 centre = glm::normalize(sum);
  out.latDeg = std::asin(std::clamp(centre.z, -1.0, 1.0)) / kDeg;
  out.lonDeg = std::atan2(centre.y, centre.x) / kDeg;
  out.radiusDeg = 0.0;
  for (const GeoCap& c : caps)
    out.radiusDeg =
        std::min(180.0, std::max(out.radiusDeg, angleDeg(centre, unitOf(c.latDeg, c.lonDeg)) + c.radiusDeg));
  return out;
}

namespace {
constexpr double kTopMeters = 20e3;  // a volume's top, kept in the picture with its ground

void addOutlinePoint(std::vector<glm::dvec3>& out, double latDeg, double lonDeg) {
  for (double h : {0.0, kTopMeters}) out.push_back(globe::geodeticToEcef({latDeg, lonDeg, h}));
}
}  // namespace

FramingTarget framingTargetOfBox(double southDeg, double northDeg, double westDeg, double eastDeg) {
  FramingTarget t;
  t.cap = capOfBox(southDeg, northDeg, westDeg, eastDeg);
  double span = eastDeg - westDeg;
  if (span < 0.0) span += 360.0;
  span = std::min(span, 360.0);
  constexpr int kPerEdge = 32;
  for (int i = 0; i <= kPerEdge; ++i) {
    const double lon = westDeg + span * i / kPerEdge, lat = southDeg + (northDeg - southDeg) * i / kPerEdge;
    addOutlinePoint(t.outlineEcef, southDeg, lon);
    addOutlinePoint(t.outlineEcef, northDeg, lon);
    addOutlinePoint(t.outlineEcef, lat, westDeg);
    addOutlinePoint(t.outlineEcef, lat, westDeg + span);
  }
  return t;
}

FramingTarget framingTargetOfCap(const GeoCap& cap) {
  FramingTarget t;
  t.cap = cap;
  // The circle at the cap's angular radius: rotate the centre's direction about the axis
  // perpendicular to it and to each bearing (sphere; the camera's margin covers the flattening).
  const glm::dvec3 c = unitOf(cap.latDeg, cap.lonDeg);
  const glm::dvec3 east = glm::normalize(glm::length(glm::dvec3(-c.y, c.x, 0.0)) > 1e-12 ? glm::dvec3(-c.y, c.x, 0.0)
                                                                                         : glm::dvec3(0.0, 1.0, 0.0));
  const glm::dvec3 north = glm::cross(c, east);
  const double r = std::min(cap.radiusDeg, 180.0) * kDeg;
  for (int i = 0; i < 72; ++i) {
    const double bearing = 2.0 * std::numbers::pi * i / 72.0;
    const glm::dvec3 p = std::cos(r) * c + std::sin(r) * (std::cos(bearing) * north + std::sin(bearing) * east);
    addOutlinePoint(t.outlineEcef, std::asin(std::clamp(p.z, -1.0, 1.0)) / kDeg, std::atan2(p.y, p.x) / kDeg);
  }
  return t;
}

Result<FramingTarget> framingTargetOfTargets(const std::vector<FramingTarget>& targets) {
  std::vector<GeoCap> caps;
  FramingTarget all;
  for (const FramingTarget& t : targets) {
    caps.push_back(t.cap);
    all.outlineEcef.insert(all.outlineEcef.end(), t.outlineEcef.begin(), t.outlineEcef.end());
  }
  auto cap = capOfCaps(caps);
  if (!cap) return cap.forwardError();
  all.cap = *cap;
  return all;
}

CameraPose poseFraming(const FramingTarget& target, double fovYDeg, int widthPx, int heightPx) {
  constexpr double kFill = 0.85;
  const double halfY = 0.5 * fovYDeg * kDeg;
  const double halfX = std::atan(std::tan(halfY) * widthPx / std::max(1, heightPx));
  const double alpha = kFill * std::min(halfX, halfY);
  const double limb = globe::kWgs84A / std::sin(alpha) - globe::kWgs84A;
  CameraPose pose;
  pose.latDeg = target.cap.latDeg;
  pose.lonDeg = target.cap.lonDeg;
  pose.headingDeg = 0.0;
  pose.pitchDeg = -90.0;
  pose.rollDeg = 0.0;
  auto fits = [&](double heightMeters) {
    pose.heightMeters = heightMeters;
    const Camera camera(pose, fovYDeg, widthPx, heightPx);
    const glm::dvec3 eye = camera.eyeEcef();
    for (const glm::dvec3& p : target.outlineEcef) {
      // Behind the horizon: the eye is below the point's tangent plane (sphere through p).
      if (glm::dot(eye - p, glm::normalize(p)) <= 0.0) return false;
      auto px = camera.projectToPixel(p);
      if (!px) return false;
      if (std::abs(px->x - 0.5 * widthPx) > kFill * 0.5 * widthPx ||
          std::abs(px->y - 0.5 * heightPx) > kFill * 0.5 * heightPx)
        return false;
    }
    return true;
  };
  double lo = 20e3, hi = limb;
  if (target.cap.radiusDeg >= 90.0 || target.outlineEcef.empty() || !fits(hi)) {
    pose.heightMeters = limb;
    return pose;
  }
  if (fits(lo)) {
    pose.heightMeters = lo;
    return pose;
  }
  while (hi / lo > 1.001) {  // fits(hi), not fits(lo)
    const double mid = std::sqrt(lo * hi);
    (fits(mid) ? hi : lo) = mid;
  }
  pose.heightMeters = hi;
  return pose;
}

Result<FramingTarget> framingTargetOfVolumes(const SceneDescription& scene) {
  std::vector<FramingTarget> targets;
  for (const VolumeLayerDescription& d : scene.volumes) {
    if (d.kind == VolumeKind::Radar) {
      auto sphere = radarBoundingSphere(d.path, scene.verticalExaggeration);
      if (!sphere) return sphere.forwardError();
      const globe::Geodetic site = globe::ecefToGeodetic(sphere->centreEcef);
      targets.push_back(
          framingTargetOfCap({site.latDeg, site.lonDeg, sphere->radiusMeters / kMeanRadiusMeters / kDeg}));
      continue;
    }
    const volume::CropBox& crop = d.settings.crop;
    if (!crop.coversEveryLonLat()) {
      targets.push_back(framingTargetOfBox(crop.southDeg, crop.northDeg, crop.westDeg, crop.eastDeg));
      continue;
    }
    volume::GridReadOptions read;
    read.variable = d.field;
    read.member = d.member;
    read.ensemble = d.ensemble;
    read.extraIndex = d.gridIndex;
    // The step shown first: a moving nest's latitudes and longitudes change with time.
    if (auto st = volume::selectGridTime(d.time, read); !st) return makeError(d.path + ": " + st.error());
    auto info = volume::describeGridFile(d.path, read);
    if (!info) return info.forwardError();
    const double east = info->wrapsLongitude ? info->westDeg + 360.0 : info->eastDeg;
    targets.push_back(framingTargetOfBox(info->southDeg, info->northDeg, info->westDeg, east));
  }
  for (const SurfaceLayerDescription& d : scene.surfaces) {
    volume::GridReadOptions read;
    read.variable = d.variable;
    read.allowSingleLevel = true;
    if (auto st = volume::selectGridTime(d.time, read); !st) return makeError(d.path + ": " + st.error());
    auto info = volume::describeGridFile(d.path, read);
    if (!info) return info.forwardError();
    const double east = info->wrapsLongitude ? info->westDeg + 360.0 : info->eastDeg;
    targets.push_back(framingTargetOfBox(info->southDeg, info->northDeg, info->westDeg, east));
  }
  return framingTargetOfTargets(targets);
}

}  // namespace atmoglobe::engine
