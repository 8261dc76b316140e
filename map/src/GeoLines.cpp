#include <atmoglobe/map/GeoLines.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::map {

GeoPolyline densifyGeodesic(const GeoPolyline& line, double maxSegmentMeters) {
  GeoPolyline out;
  if (line.lonLatDeg.empty()) return out;
  out.lonLatDeg.push_back(line.lonLatDeg.front());
  for (std::size_t i = 1; i < line.lonLatDeg.size(); ++i) {
    const glm::dvec2 a = line.lonLatDeg[i - 1], b = line.lonLatDeg[i];
    const globe::GeodesicLine g = globe::geodesicInverse(a.y, a.x, b.y, b.x);
    const double n = std::ceil(g.distanceMeters / maxSegmentMeters);
    if (n > 1.0 && std::isfinite(n)) {
      const int parts = static_cast<int>(std::min(n, 1e6));
      for (int k = 1; k < parts; ++k) {
        const globe::GeodesicPoint p = globe::geodesicDirect(a.y, a.x, g.azimuth1Deg, g.distanceMeters * k / parts);
        out.lonLatDeg.emplace_back(globe::wrapLongitudeDeg(p.lonDeg), p.latDeg);
      }
    }
    out.lonLatDeg.push_back(b);
  }
  return out;
}

std::vector<GeoPolyline> splitAtAntimeridian(const GeoPolyline& line) {
  std::vector<GeoPolyline> pieces;
  GeoPolyline current;
  const auto& p = line.lonLatDeg;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (i > 0 && std::abs(p[i].x - p[i - 1].x) > 180.0) {
      // The geodesic from p[i-1] to p[i] crosses +-180: bisect on it for the crossing.
      const glm::dvec2 a = p[i - 1], b = p[i];
      const globe::GeodesicLine g = globe::geodesicInverse(a.y, a.x, b.y, b.x);
      const double eastSide = a.x > 0.0 ? 1.0 : -1.0;  // a's side of the antimeridian
      double lo = 0.0, hi = 1.0, latDeg = 0.5 * (a.y + b.y);
      for (int it = 0; it < 60 && hi - lo > 1e-9; ++it) {
        const double t = 0.5 * (lo + hi);
        const globe::GeodesicPoint q = globe::geodesicDirect(a.y, a.x, g.azimuth1Deg, g.distanceMeters * t);
        latDeg = q.latDeg;
        const double lon = globe::wrapLongitudeDeg(q.lonDeg);
        // Still on a's side when the longitude has a's sign (near 180, not near 0).
        const bool onASide = eastSide > 0.0 ? lon > 0.0 : lon < 0.0;
        (onASide ? lo : hi) = t;
      }
      current.lonLatDeg.emplace_back(180.0 * eastSide, latDeg);
      if (current.lonLatDeg.size() >= 2) pieces.push_back(std::move(current));
      current = GeoPolyline{};
      current.lonLatDeg.emplace_back(-180.0 * eastSide, latDeg);
    }
    current.lonLatDeg.push_back(p[i]);
  }
  if (current.lonLatDeg.size() >= 2) pieces.push_back(std::move(current));
  return pieces;
}

std::vector<GeoPolyline> rangeRingsAndSpokes(double latDeg, double lonDeg, double maxRangeMeters, double ringStepMeters,
                                             double spokeStepDeg) {
  std::vector<GeoPolyline> lines;
  if (ringStepMeters > 0.0) {
    for (double r = ringStepMeters; r <= maxRangeMeters * (1.0 + 1e-9); r += ringStepMeters) {
      GeoPolyline ring;
      for (int az = 0; az <= 360; ++az) {
        const globe::GeodesicPoint q = globe::geodesicDirect(latDeg, lonDeg, az, r);
        ring.lonLatDeg.emplace_back(globe::wrapLongitudeDeg(q.lonDeg), q.latDeg);
      }
      lines.push_back(std::move(ring));
    }
  }
  if (spokeStepDeg > 0.0) {
    for (double az = 0.0; az < 360.0 - 1e-9; az += spokeStepDeg) {
      GeoPolyline spoke;
      const int parts = std::max(1, static_cast<int>(std::ceil(maxRangeMeters / 10000.0)));
      for (int k = 0; k <= parts; ++k) {
        const globe::GeodesicPoint q = globe::geodesicDirect(latDeg, lonDeg, az, maxRangeMeters * k / parts);
        spoke.lonLatDeg.emplace_back(globe::wrapLongitudeDeg(q.lonDeg), q.latDeg);
      }
      lines.push_back(std::move(spoke));
    }
  }
  return lines;
}

double chordSagMeters(double segmentMeters) {
  constexpr double kMinRadiusOfCurvature = 6335439.0;  // WGS84 meridian radius at the equator
  return segmentMeters * segmentMeters / (8.0 * kMinRadiusOfCurvature);
}

namespace {
// x - hi, narrowed. Not inlined: GCC 12's SLP vectorizer at -O2/-O3 turns the inlined
// float(x - double(float(x))) of the y and z lanes into 0 (seen on Debian 12's g++ 12.2; the
// GeoLines.ChunkPoints test catches it).
[[gnu::noinline]] float lowPart(double x, float hi) { return static_cast<float>(x - static_cast<double>(hi)); }

void pushPoint(LineChunk& c, const glm::dvec3& ecef) {
  const glm::dvec3 d = ecef - c.originEcef;
  float hi[3], lo[3];
  for (int k = 0; k < 3; ++k) {
    hi[k] = static_cast<float>(d[k]);
    lo[k] = lowPart(d[k], hi[k]);
  }
  c.vertices.insert(c.vertices.end(), {hi[0], hi[1], hi[2], lo[0], lo[1], lo[2]});
}
}  // namespace

LineChunk buildLineChunk(const std::vector<GeoPolyline>& lines, double maxSegmentMeters) {
  LineChunk c;
  std::vector<std::vector<glm::dvec3>> ecef;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const GeoPolyline& l : lines) {
    const GeoPolyline dense = densifyGeodesic(l, maxSegmentMeters);
    std::vector<glm::dvec3> pts;
    pts.reserve(dense.lonLatDeg.size());
    for (const glm::dvec2& p : dense.lonLatDeg) {
      pts.push_back(globe::geodeticToEcef({std::clamp(p.y, -90.0, 90.0), p.x, 0.0}));
      lo = glm::min(lo, pts.back());
      hi = glm::max(hi, pts.back());
    }
    for (std::size_t i = 1; i < pts.size(); ++i)
      c.sagMeters = std::max(c.sagMeters, chordSagMeters(glm::distance(pts[i - 1], pts[i])));
    ecef.push_back(std::move(pts));
  }
  if (hi.x < lo.x) return c;
  c.originEcef = 0.5 * (lo + hi);
  c.sphereCenterEcef = c.originEcef;
  for (const auto& pts : ecef) {
    for (std::size_t i = 1; i < pts.size(); ++i) {
      pushPoint(c, pts[i - 1]);
      pushPoint(c, pts[i]);
    }
    for (const glm::dvec3& p : pts)
      c.sphereRadiusMeters = std::max(c.sphereRadiusMeters, glm::distance(p, c.sphereCenterEcef));
  }
  return c;
}

}  // namespace atmoglobe::map
