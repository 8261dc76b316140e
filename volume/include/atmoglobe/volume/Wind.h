#pragma once
// Wind on a map: u and v components turned east and north where the grid gives them along its own
// axes, and the parts of a wind barb. GL-free (the engine draws the barbs, engine/SurfaceFieldGL.h).
//
// Grid-relative components (GridVolume::vectorsRelativeToGrid: GRIB uvRelativeToGrid on a
// projected grid, WRF, CF x_wind): the grid's column direction at a point makes an angle alpha
// with east (counterclockwise), measured from the grid's own geometry (its neighbours along the
// row, in the point's local east-north plane on the WGS84 ellipsoid, central differences; one-sided
// at the edges); the grid is taken as conformal (its row direction alpha + 90 deg: Lambert
// conformal, polar stereographic, Mercator, rotated latitude/longitude), so
//   east = u cos(alpha) - v sin(alpha),   north = u sin(alpha) + v cos(alpha).
// For a Lambert conformal grid alpha = -n (lon - lon0) (n the cone constant, lon0 the central
// meridian): the rotation NCEP's and WMO's grid-relative winds are documented with.
//
// Barbs: the speed in knots rounded to the nearest 5; a pennant for every 50, a full barb for
// every 10 left, a half barb for 5 left; below 2.5 knots calm (a circle). The shaft points to
// where the wind comes from, the barbs at its outer end, on the side of lower pressure (to the
// right of the shaft seen from the station in the northern hemisphere, to the left in the
// southern).
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridVolume.h>
#include <glm/glm.hpp>

#include <vector>

namespace atmoglobe::volume {

/// The angle (rad, counterclockwise from east) of the grid's column direction at each grid point
/// (ny x nx). A rectilinear latitude/longitude grid: 0 everywhere.
std::vector<double> gridColumnAngles(const GridVolume& grid);

struct WindComponents {
  std::vector<float> eastMps, northMps;  ///< ny x nx, NaN where u or v is missing
};

/// East and north components from u and v on the same grid (first level of each); turned by
/// gridColumnAngles where `u.vectorsRelativeToGrid`. Errors: different grids, a reduced grid.
Result<WindComponents> earthRelativeWind(const GridVolume& u, const GridVolume& v);

struct BarbParts {
  int pennants = 0, full = 0, half = 0;
  bool calm = false;
};
BarbParts barbParts(double speedKnots);

/// A barb as lines in the east-north plane in units of its shaft's length, the station at (0, 0):
/// the shaft to (the unit vector toward where the wind comes from), then from its outer end
/// inward the pennants (closed triangles on the shaft, apex 0.4 out), full barbs (0.4 out,
/// leaning 0.1 outward) and the half barb (half as long; alone, one step in from the end), on the
/// right of the shaft (its left in the southern hemisphere). Calm: a circle of radius 0.15.
std::vector<std::vector<glm::dvec2>> barbPolylines(double eastMps, double northMps, bool southernHemisphere);

inline constexpr double kKnotsPerMps = 3600.0 / 1852.0;

}  // namespace atmoglobe::volume
