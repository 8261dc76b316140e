#pragma once
// A crop box for any volume: a latitude/longitude box and a height range above mean sea level.
// Applied to the data before rendering (GPU and CPU reference alike): a value whose cell centre
// (grid) or gate centre (radar) lies outside becomes "no data", so what is drawn near the box's
// faces follows the kind's own sampling rule, and the empty-space grid skips what was cut.
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <cstddef>
#include <limits>

namespace atmoglobe::volume {

class GeoidGrid;

struct CropBox {
  double southDeg = -90.0, northDeg = 90.0;
  double westDeg = -180.0, eastDeg = 180.0;                        ///< west > east crosses the antimeridian
  double bottomMeters = -std::numeric_limits<double>::infinity();  ///< above mean sea level (m)
  double topMeters = std::numeric_limits<double>::infinity();
  bool coversEveryLonLat() const { return southDeg <= -90.0 && northDeg >= 90.0 && eastDeg - westDeg >= 360.0; }
  bool coversEveryHeight() const { return std::isinf(bottomMeters) && std::isinf(topMeters); }
  /// True when (latDeg, lonDeg) is inside the box (longitudes compared modulo 360).
  bool containsLonLat(double latDeg, double lonDeg) const;
};

/// Checks a box from a user: -90 <= south < north <= 90, finite longitudes in -360..360,
/// bottom < top. `where` starts the message.
Status validateCropBox(const CropBox& box, const std::string& where);

/// Grid values outside the box become NaN (no data); valueMin/valueMax are recomputed. Heights
/// above sea level are the grid's ellipsoidal heights minus the EGM96 undulation of the column
/// (`geoid`; null: heights are taken as ellipsoidal). Returns the number of values cut.
std::size_t cropGrid(GridVolume& grid, const CropBox& box, const GeoidGrid* geoid);

/// Radar gates whose centre (exact beam model: Geolocation.h's closed-form height and ground
/// distance, one WGS84 geodesic per gate when the box cuts the range circle) lies outside the
/// box become no data. Heights above sea level use the undulation at the site (its change within
/// a radar's range is a few metres). Returns the number of gates cut; minValue/maxValue recomputed.
std::size_t cropPolar(PolarVolume& radar, const CropBox& box, const GeoidGrid* geoid);

}  // namespace atmoglobe::volume
