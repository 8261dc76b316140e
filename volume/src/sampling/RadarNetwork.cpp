// The coverage index and the overlap rules of a radar network (RadarNetwork.h).
#include <atmoglobe/volume/RadarNetwork.h>

#include <atmoglobe/globe/Angles.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace atmoglobe::volume {

const char* toString(OverlapRule rule) {
  switch (rule) {
    case OverlapRule::Integrate: return "integrate";
    case OverlapRule::WeightedMean: return "mean";
    case OverlapRule::LowestBeam: return "lowest";
    case OverlapRule::Maximum: return "max";
  }
  return "?";
}

Result<OverlapRule> parseOverlapRule(std::string_view text) {
  for (OverlapRule r :
       {OverlapRule::Integrate, OverlapRule::WeightedMean, OverlapRule::LowestBeam, OverlapRule::Maximum})
    if (text == toString(r)) return r;
  return makeError("overlap rule '" + std::string(text) +
                   "': expected integrate (extinctions add), mean (distance-weighted), lowest (lowest beam) or max");
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Geocentric latitude and longitude (deg) of the direction of a point from the Earth's centre.
void directionLatLonDeg(const glm::dvec3& p, double* latDeg, double* lonDeg) {
  *lonDeg = std::atan2(p.y, p.x) / kDeg;
  *latDeg = std::atan2(p.z, std::hypot(p.x, p.y)) / kDeg;
}

glm::dvec3 unitOf(double latDeg, double lonDeg) {
  const double cl = std::cos(latDeg * kDeg);
  return {cl * std::cos(lonDeg * kDeg), cl * std::sin(lonDeg * kDeg), std::sin(latDeg * kDeg)};
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  // atan2 of |a x b| and a . b: accurate at small and large angles alike.
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Angular distance (rad) from the unit direction u to the cell [lat0, lat1] x [lon0, lon1]
// (degrees; lon1 - lon0 < 360 and the cell given in a longitude frame where u's longitude is lonU).
double distanceToCell(const glm::dvec3& u, double latU, double lonU, double lat0, double lat1, double lon0,
                      double lon1) {
  // lonU brought into [lon0, lon0 + 360).
  double l = lonU;
  while (l < lon0) l += 360.0;
  while (l >= lon0 + 360.0) l -= 360.0;
  if (l <= lon1) {
    // Within the cell's longitudes: the nearest point is on u's meridian (a parallel's nearest
    // point to u is at u's longitude), at the latitude clamped into the cell.
    const double lat = std::clamp(latU, lat0, lat1);
    return std::fabs(latU - lat) * kDeg;
  }
  // Otherwise on one of the two meridian edges: the foot of the perpendicular on the half
  // meridian, clamped to the edge's latitudes (distance grows monotonically away from the foot).
  double best = kPi;
  for (double lonE : {lon0, lon1}) {
    const glm::dvec3 m{std::cos(lonE * kDeg), std::sin(lonE * kDeg), 0.0};
    const double latFoot = std::atan2(u.z, glm::dot(u, m)) / kDeg;
    const double lat = std::clamp(latFoot, lat0, lat1);
    best = std::min(best, angleBetween(u, unitOf(lat, lonE)));
  }
  return best;
}

struct Cap {
  glm::dvec3 unit{0.0};
  double latDeg = 0.0, lonDeg = 0.0, radiusDeg = 180.0;
};

}  // namespace

long CoverageIndex::cellOf(const glm::dvec3& ecef) const {
  if (columns <= 0 || rows <= 0) return -1;
  double latDeg = 0.0, lonDeg = 0.0;
  directionLatLonDeg(ecef, &latDeg, &lonDeg);
  double dl = lonDeg - lonOriginDeg;
  if (dl < 0.0) dl += 360.0;
  if (dl >= 360.0) dl -= 360.0;
  const double x = dl / cellDeg, y = (latDeg - latMinDeg) / cellDeg;
  if (!(x >= 0.0 && x < columns && y >= 0.0 && y < rows)) return -1;
  return static_cast<long>(std::floor(y)) * columns + static_cast<long>(std::floor(x));
}

std::pair<const std::uint32_t*, const std::uint32_t*> CoverageIndex::radarsAt(const glm::dvec3& ecef) const {
  const long c = cellOf(ecef);
  if (c < 0) return {nullptr, nullptr};
  return {members.data() + cellStart[static_cast<std::size_t>(c)],
          members.data() + cellStart[static_cast<std::size_t>(c) + 1]};
}

std::size_t CoverageIndex::maxPerCell() const {
  std::size_t m = 0;
  for (std::size_t c = 0; c + 1 < cellStart.size(); ++c) m = std::max<std::size_t>(m, cellStart[c + 1] - cellStart[c]);
  return m;
}

double CoverageIndex::meanPerOccupiedCell() const {
  std::size_t occupied = 0, total = 0;
  for (std::size_t c = 0; c + 1 < cellStart.size(); ++c) {
    const std::size_t n = cellStart[c + 1] - cellStart[c];
    occupied += n > 0;
    total += n;
  }
  return occupied ? static_cast<double>(total) / static_cast<double>(occupied) : 0.0;
}

CoverageIndex buildCoverageIndex(const std::vector<BoundingSphere>& spheres, double cellDeg) {
  CoverageIndex index;
  if (spheres.empty()) return index;
  std::vector<Cap> caps;
  double minRadiusDeg = 180.0;
  for (const BoundingSphere& s : spheres) {
    Cap cap;
    const double d = glm::length(s.centreEcef);
    cap.unit = d > 0.0 ? s.centreEcef / d : glm::dvec3(0.0, 0.0, 1.0);
    directionLatLonDeg(s.centreEcef, &cap.latDeg, &cap.lonDeg);
    cap.radiusDeg = (s.radiusMeters >= d ? 180.0 : std::asin(s.radiusMeters / d) / kDeg) + kCoverageMarginDeg;
    minRadiusDeg = std::min(minRadiusDeg, cap.radiusDeg);
    caps.push_back(cap);
  }
  // Latitudes and longitudes the caps reach. A cap of radius a around latitude p reaches
  // longitudes within asin(sin a / cos p) of its centre unless it holds a pole.
  double latMin = 90.0, latMax = -90.0;
  bool allLongitudes = false;
  std::vector<std::pair<double, double>> lonSpans;  // [start, end) in degrees, start in [-180, 180)
  for (const Cap& c : caps) {
    latMin = std::min(latMin, std::max(-90.0, c.latDeg - c.radiusDeg));
    latMax = std::max(latMax, std::min(90.0, c.latDeg + c.radiusDeg));
    if (c.radiusDeg >= 90.0 - std::fabs(c.latDeg)) {
      allLongitudes = true;
      continue;
    }
    const double half = std::asin(std::sin(c.radiusDeg * kDeg) / std::cos(c.latDeg * kDeg)) / kDeg;
    double start = c.lonDeg - half;
    if (start < -180.0) start += 360.0;
    lonSpans.emplace_back(start, start + 2.0 * half);
  }
  double lonOrigin = -180.0, lonSpan = 360.0;
  if (!allLongitudes) {
    // The smallest arc holding every span: the complement of the largest gap between them. Two
    // sweeps in order of start over the spans and their copies shifted by 360: the first carries
    // the covered end across the wrap, the second finds the gaps (each once).
    std::sort(lonSpans.begin(), lonSpans.end());
    double coverEnd = lonSpans.front().first, bestGap = 0.0;
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& s : lonSpans) {
        const double start = s.first + 360.0 * pass, end = s.second + 360.0 * pass;
        if (pass == 1 && start - coverEnd > bestGap) {
          bestGap = start - coverEnd;
          lonOrigin = s.first;
        }
        coverEnd = std::max(coverEnd, end);
      }
    lonSpan = 360.0 - bestGap;
    if (lonSpan >= 360.0) lonOrigin = -180.0;
  }
  if (cellDeg <= 0.0) cellDeg = std::clamp(0.5 * minRadiusDeg, 0.02, 2.0);
  const auto count = [&](double c) {
    return std::ceil(std::min(lonSpan, 360.0) / c) * std::ceil((latMax - latMin) / c);
  };
  while (count(cellDeg) > 4.0e6) cellDeg *= 1.5;
  index.cellDeg = cellDeg;
  index.lonOriginDeg = lonOrigin >= 180.0 ? lonOrigin - 360.0 : lonOrigin;
  index.latMinDeg = latMin;
  if (lonSpan + cellDeg >= 360.0) {
    // Whole circles of latitude: columns of 360 / n degrees, so no cell straddles the seam.
    lonSpan = 360.0;
    index.lonOriginDeg = -180.0;
    index.columns = static_cast<int>(std::ceil(360.0 / cellDeg));
    index.cellDeg = cellDeg = 360.0 / index.columns;
  } else {
    index.columns = std::max(1, static_cast<int>(std::ceil(lonSpan / cellDeg)));
  }
  index.rows = std::max(1, static_cast<int>(std::ceil((latMax - latMin) / cellDeg)));

  // Each cap into the cells it reaches: only the cells of its latitude/longitude box are tested.
  std::vector<std::vector<std::uint32_t>> lists(index.cellCount());
  for (std::size_t k = 0; k < caps.size(); ++k) {
    const Cap& c = caps[k];
    const int r0 = std::max(0, static_cast<int>(std::floor((c.latDeg - c.radiusDeg - latMin) / cellDeg)) - 1);
    const int r1 =
        std::min(index.rows - 1, static_cast<int>(std::floor((c.latDeg + c.radiusDeg - latMin) / cellDeg)) + 1);
    for (int row = r0; row <= r1; ++row) {
      const double lat0 = latMin + row * cellDeg, lat1 = std::min(90.0, lat0 + cellDeg);
      for (int col = 0; col < index.columns; ++col) {
        const double lon0 = index.lonOriginDeg + col * cellDeg;
        if (distanceToCell(c.unit, c.latDeg, c.lonDeg, lat0, lat1, lon0, lon0 + cellDeg) <= c.radiusDeg * kDeg)
          lists[static_cast<std::size_t>(row) * index.columns + col].push_back(static_cast<std::uint32_t>(k));
      }
    }
  }
  index.cellStart.reserve(lists.size() + 1);
  index.cellStart.push_back(0);
  for (const auto& l : lists) {
    index.members.insert(index.members.end(), l.begin(), l.end());
    index.cellStart.push_back(static_cast<std::uint32_t>(index.members.size()));
  }
  return index;
}

// ---------------------------------------------------------------------------------------------
struct RadarNetworkSampler::Combined {
  VolumeSample sample;
  std::optional<std::size_t> leader;
};

template <class It>
RadarNetworkSampler::Combined RadarNetworkSampler::combine(It first, It last, const glm::dvec3& ecef,
                                                           Interpolation interpolation) const {
  Combined out;
  bool measured = false, echo = false;
  double sumW = 0.0, sumWV = 0.0, echoW = 0.0, bestW = -1.0;
  double best = -std::numeric_limits<double>::infinity();
  double lowest = std::numeric_limits<double>::infinity();
  std::optional<std::size_t> leader, lowestLeader;
  VolumeSample lowestSample;
  for (It it = first; it != last; ++it) {
    const std::size_t k = *it;
    const PolarSampler& radar = *radars_[k];
    if (radar.provablyEmpty(ecef)) continue;
    const PolarVolume& v = radar.polar();
    const AntennaCoordinates ac = antennaCoordinatesExact(v.site, v.beam, ecef);
    const VolumeSample s = samplePolar(v, ac.rangeMeters, ac.azimuthDeg, ac.elevationDeg, interpolation);
    if (s.state == VolumeSample::State::NoData) continue;
    measured = true;
    switch (rule_) {
      case OverlapRule::WeightedMean: {
        const double q = ac.rangeMeters / kMosaicWeightLengthMeters;
        const double w = std::exp(-q * q);
        sumW += w;
        if (s.state == VolumeSample::State::Echo) {
          echo = true;
          echoW += w;
          sumWV += w * s.value;
        }
        if (w > bestW) {
          bestW = w;
          leader = k;
        }
        break;
      }
      case OverlapRule::Maximum:
        if (s.state == VolumeSample::State::Echo && s.value > best) {
          best = s.value;
          echo = true;
          leader = k;
        }
        if (!leader) leader = k;
        break;
      case OverlapRule::LowestBeam:
      case OverlapRule::Integrate: {
        // The lowest sweep's beam centre over the point's ground distance s = re g:
        // H = h0 + (re + h0) (cos e0 / cos(e0 + g) - 1), written without cancellation (the GPU's
        // float twin, sample_network.glsl, uses the same form).
        const double re = effectiveRadius_[k];
        const double h0 = v.site.antennaHeightEllipsoidMeters;
        const double el = ac.elevationDeg * kDeg;
        const double g = std::atan2(ac.rangeMeters * std::cos(el), ac.rangeMeters * std::sin(el) + re + h0);
        const double e0 = v.sweeps.front().elevationDeg * kDeg;
        const double lowBeam = h0 + (re + h0) * 2.0 * std::sin(e0 + 0.5 * g) * std::sin(0.5 * g) /
                                        std::cos(std::min(e0 + g, 0.5 * kPi - 1e-9));
        if (lowBeam < lowest) {
          lowest = lowBeam;
          lowestSample = s;
          lowestLeader = k;
        }
        break;
      }
    }
  }
  if (!measured) return out;
  switch (rule_) {
    case OverlapRule::WeightedMean:
      // Weights can underflow together far from every radar (exp(-(r/L)^2) < 1e-308 beyond
      // about 1330 km): the echo share is then undefined and the sample is taken as NoEcho.
      if (echo && sumW > 0.0 && echoW >= 0.5 * sumW) out.sample = {VolumeSample::State::Echo, sumWV / echoW};
      else out.sample = {VolumeSample::State::NoEcho, 0.0};
      out.leader = leader;
      break;
    case OverlapRule::Maximum:
      out.sample = echo ? VolumeSample{VolumeSample::State::Echo, best}
                        : VolumeSample{VolumeSample::State::NoEcho, 0.0};
      out.leader = leader;
      break;
    case OverlapRule::LowestBeam:
    case OverlapRule::Integrate:
      out.sample = lowestSample;
      out.leader = lowestLeader;
      break;
  }
  return out;
}

VolumeSample RadarNetworkSampler::sample(const glm::dvec3& ecef, Interpolation interpolation) const {
  const auto [first, last] = index_.radarsAt(ecef);
  if (first == last) return {};
  return combine(first, last, ecef, interpolation).sample;
}

VolumeSample RadarNetworkSampler::sampleEveryRadar(const glm::dvec3& ecef, Interpolation interpolation) const {
  std::vector<std::size_t> all(radars_.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = k;
  return combine(all.begin(), all.end(), ecef, interpolation).sample;
}

std::optional<std::size_t> RadarNetworkSampler::leadingRadar(const glm::dvec3& ecef,
                                                             Interpolation interpolation) const {
  const auto [first, last] = index_.radarsAt(ecef);
  if (first == last) return std::nullopt;
  return combine(first, last, ecef, interpolation).leader;
}

double RadarNetworkSampler::cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const {
  const auto [first, last] = index_.radarsAt(ecef);
  double best = std::numeric_limits<double>::infinity();
  for (auto it = first; it != last; ++it) {
    const PolarSampler& r = *radars_[*it];
    const BoundingSphere clip = r.boundingSphere();
    const glm::dvec3 d = ecef - clip.centreEcef;
    if (glm::dot(d, d) > clip.radiusMeters * clip.radiusMeters) continue;
    const double c = r.cellCrossingMeters(ecef, unitDirEcef);
    if (c > 0.0) best = std::min(best, c);
  }
  return std::isfinite(best) ? best : 0.0;
}

bool RadarNetworkSampler::provablyEmpty(const glm::dvec3& ecef) const {
  const auto [first, last] = index_.radarsAt(ecef);
  for (auto it = first; it != last; ++it)
    if (!radars_[*it]->provablyEmpty(ecef)) return false;
  return true;
}

RayInterval RadarNetworkSampler::rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const {
  RayInterval out;
  const RayInterval all = raySphereInterval(eyeEcef, unitDirEcef, enclosing_.centreEcef, enclosing_.radiusMeters);
  if (all.empty()) return out;
  out.tEnterMeters = std::numeric_limits<double>::infinity();
  out.tExitMeters = -std::numeric_limits<double>::infinity();
  for (const auto& r : radars_) {
    const RayInterval i = r->rayInterval(eyeEcef, unitDirEcef);
    if (i.empty()) continue;
    out.tEnterMeters = std::min(out.tEnterMeters, i.tEnterMeters);
    out.tExitMeters = std::max(out.tExitMeters, i.tExitMeters);
  }
  if (out.tExitMeters < out.tEnterMeters) return RayInterval{};
  return out;
}

ValueRange RadarNetworkSampler::valueRange() const {
  ValueRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const auto& s : radars_) {
    const ValueRange v = s->valueRange();
    r.minValue = std::min(r.minValue, v.minValue);
    r.maxValue = std::max(r.maxValue, v.maxValue);
  }
  return r;
}

BoundingSphere RadarNetworkSampler::boundingSphere() const { return enclosing_; }

std::string RadarNetworkSampler::description() const {
  std::ostringstream s;
  s << radars_.size() << " radars (" << radars_.front()->polar().fieldName << "), overlap rule " << toString(rule_);
  return s.str();
}

Result<std::unique_ptr<RadarNetworkSampler>> makeRadarNetworkSampler(const std::vector<const PolarVolume*>& radars,
                                                                     OverlapRule rule, FieldKind kind, double cellDeg) {
  if (radars.empty()) return makeError("a radar network needs at least one radar");
  if (rule == OverlapRule::Integrate)
    return makeError(
        "the overlap rule 'integrate' (extinctions add) is the renderers' rule and gives no single value; "
        "a network value needs mean, lowest or max");
  if (kind == FieldKind::Velocity || kind == FieldKind::DifferentialPhase)
    return makeError(std::string("a ") + toString(kind) +
                     " field is relative to each radar (the motion towards that antenna, that system's phase "
                     "offset): values from different sites cannot be combined; draw each radar on its own");
  std::unique_ptr<RadarNetworkSampler> n(new RadarNetworkSampler());
  n->rule_ = rule;
  std::vector<BoundingSphere> spheres;
  for (const PolarVolume* v : radars) {
    n->radars_.push_back(std::make_unique<PolarSampler>(*v));
    n->effectiveRadius_.push_back(effectiveEarthRadiusMeters(v->beam, v->site.latDeg));
    spheres.push_back(n->radars_.back()->boundingSphere());
  }
  n->index_ = buildCoverageIndex(spheres, cellDeg);
  // An enclosing sphere: around the mean centre, out to the farthest sphere's far side.
  glm::dvec3 c(0.0);
  for (const auto& s : spheres) c += s.centreEcef;
  c /= static_cast<double>(spheres.size());
  double r = 0.0;
  for (const auto& s : spheres) r = std::max(r, glm::length(s.centreEcef - c) + s.radiusMeters);
  n->enclosing_ = {c, r};
  return n;
}

}  // namespace atmoglobe::volume
