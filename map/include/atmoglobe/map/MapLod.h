#pragma once
// The map context's level of detail (GL-free): which GSHHG resolution a pixel's footprint asks
// for, and how finely lines are densified along the geodesic at that level.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/map/GeoLines.h>
#include <atmoglobe/map/Gshhg.h>

#include <string>
#include <vector>

namespace atmoglobe::map {

/// Longest segment (m) lines are cut into along the geodesic at a level: 50 km, 20 km, 5 km,
/// 1 km, 250 m. The chord sag below the surface (GeoLines.h chordSagMeters: 49 m, 7.9 m, 0.49 m,
/// 2 cm, 1.2 mm) stays below 1e-5 of the eye's distance down to each level's nearest distance
/// (gshhgResolutionForScale at a focal length of 869 px, 1280x720 at 45 deg; 4e-5 at 200 px),
/// except full below 120 m (1.2 mm at 1 m): the renderer's depth lift (1 % of the distance)
/// covers it.
double maxSegmentMetersFor(GshhgResolution r);

}  // namespace atmoglobe::map

namespace atmoglobe::map {

/// The resolution for a flat map (a CAPPI picture) drawn at `metresPerPixel`: the coarsest whose
/// published point spacing (c 25 km, l 5 km, i 1 km, h 200 m, f 40 m) is at most two pixels.
GshhgResolution gshhgResolutionForScale(double metresPerPixel);

/// What a map of a box shows, by kind of line.
struct BoxMapLines {
  std::vector<GeoPolyline> coasts;    ///< shorelines and lake shores
  std::vector<GeoPolyline> borders;   ///< national boundaries
  std::vector<GeoPolyline> internal;  ///< states and provinces
  GshhgResolution resolution = GshhgResolution::Crude;
};

/// The GSHHG lines of every bin overlapping [south, north] x [west, east] (degrees; west > east
/// crosses the antimeridian) from `gshhgDir` at `resolution`. Errors name the file.
Result<BoxMapLines> readBoxMapLines(const std::string& gshhgDir, double southDeg, double northDeg, double westDeg,
                                    double eastDeg, GshhgResolution resolution);

}  // namespace atmoglobe::map
