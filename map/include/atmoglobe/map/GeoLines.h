#pragma once
// Geodetic polylines (longitude, latitude in degrees on WGS84) and their geometry: densified
// along the WGS84 geodesic, split at the antimeridian, range rings and azimuth spokes, and
// packed into GPU-ready line chunks (float32 relative to a double origin). GL-free.
#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace atmoglobe::map {

/// A polyline: x = longitude, y = latitude (degrees, WGS84). Segments are WGS84 geodesics.
struct GeoPolyline {
  std::vector<glm::dvec2> lonLatDeg;
};

/// Inserts points on the geodesic of every segment longer than maxSegmentMeters, so that no
/// segment is longer (each split into equal parts). Longitudes of inserted points are wrapped
/// to [-180, 180); given points are kept as they are.
GeoPolyline densifyGeodesic(const GeoPolyline& line, double maxSegmentMeters);

/// Splits a polyline where a segment crosses the antimeridian (a longitude step of more than
/// 180 degrees between neighbours): the crossing latitude is found on the segment's geodesic
/// (bisection to 1e-9 of its length), the piece before ends at +-180 and the next starts at
/// -+180 on the same latitude. Pieces with fewer than two points are dropped.
std::vector<GeoPolyline> splitAtAntimeridian(const GeoPolyline& line);

/// Range rings (geodesic circles every ringStepMeters up to maxRangeMeters, a point every
/// 1 degree of azimuth) and azimuth spokes (geodesics every spokeStepDeg from the site to
/// maxRangeMeters, clockwise from north) around a site.
std::vector<GeoPolyline> rangeRingsAndSpokes(double latDeg, double lonDeg, double maxRangeMeters,
                                             double ringStepMeters = 50000.0, double spokeStepDeg = 30.0);

/// How far (m) the chord of a surface arc of `segmentMeters` sags below the ellipsoid at most:
/// L^2 / (8 R) with R the smallest WGS84 radius of curvature (the meridian's at the equator,
/// 6335439 m).
double chordSagMeters(double segmentMeters);

/// A chunk of lines ready for the GPU: GL_LINES pairs of points on the ellipsoid (height 0),
/// each point as two float triples (hi, lo) whose sum is its offset from originEcef (m), so the
/// shader can subtract the eye's (hi, lo) and keep sub-millimetre precision at any distance.
struct LineChunk {
  glm::dvec3 originEcef{0.0};
  std::vector<float> vertices;  ///< per point: hi.xyz, lo.xyz; two points per segment
  double sagMeters = 0.0;       ///< largest chord sag of its segments below the ellipsoid
  glm::dvec3 sphereCenterEcef{0.0};
  double sphereRadiusMeters = 0.0;
  std::size_t segmentCount() const { return vertices.size() / 12; }
};

/// Densifies every line to maxSegmentMeters and packs it; the origin is the centre of the
/// points' bounding box.
LineChunk buildLineChunk(const std::vector<GeoPolyline>& lines, double maxSegmentMeters);

}  // namespace atmoglobe::map
