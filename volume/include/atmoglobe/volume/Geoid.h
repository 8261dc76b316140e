#pragma once
// EGM96 geoid undulation from a PROJ .gtx grid (Debian proj-data: /usr/share/proj/egm96_15.gtx).
//
// Heights in radar files are above mean sea level (the geoid); geolocation needs heights above
// the WGS84 ellipsoid: h_ellipsoid = h_msl + N, with N the geoid undulation returned here.
//
// The .gtx format (NOAA VDatum): a 40-byte big-endian header -- lower-left latitude, lower-left
// longitude, latitude step, longitude step (float64, degrees), row count, column count (int32) --
// then rows of big-endian float32 values (metres), the southernmost row first, west to east.
// Values are bilinearly interpolated; longitudes wrap when the grid spans 360 degrees.
// Agreement with PROJ's own vgridshift on the same grid: better than 1 mm (GeoidTest).
#include <atmoglobe/globe/Result.h>

#include <string>
#include <vector>

namespace atmoglobe::volume {

/// Path of the EGM96 15' grid shipped by Debian proj-data.
inline constexpr const char* kDefaultEgm96GridPath = "/usr/share/proj/egm96_15.gtx";

class GeoidGrid {
 public:
  /// Reads a .gtx grid. Errors (missing file, short file, absurd header) name the file.
  static Result<GeoidGrid> load(const std::string& path);

  /// Geoid undulation N (m) at a geodetic latitude/longitude (degrees). Latitude is clamped to
  /// the grid; longitude wraps. Precondition: finite arguments.
  double undulationMeters(double latDeg, double lonDeg) const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  double lat0Deg_ = 0, lon0Deg_ = 0, dLatDeg_ = 0, dLonDeg_ = 0;
  int rows_ = 0, cols_ = 0;
  bool wrapsLongitude_ = false;
  std::vector<float> values_;  // row-major, south row first
};

/// The EGM96 grid at kDefaultEgm96GridPath, loaded once per process (thread-safe); the error
/// says how to get the file (Debian proj-data) or to turn the geoid conversion off.
const Result<GeoidGrid>& defaultEgm96Grid();

}  // namespace atmoglobe::volume
