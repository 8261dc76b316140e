#pragma once
// Slices through volumes, for radars and grids alike: a CAPPI (a horizontal slice at a constant
// height over a latitude/longitude box) and a vertical cross-section along a WGS84 geodesic path
// through two or more points. GL-free, double precision; the values come from the volumes' own
// samplers (VolumeSampler::sample), so a slice shows exactly what the renderers sample.
//
// Geometry (SliceGeometry): a raster of `columns` x `rows` pixels, row 0 at the top; continuous
// pixel coordinates (x, y), x in [0, columns] to the right, y in [0, rows] downwards, pixel
// (i, j) centred at (i + 0.5, j + 0.5) (the README's pixel convention).
//  - CAPPI: x runs linearly in longitude from the box's west edge to its east edge, y linearly
//    in latitude from its north edge to its south edge (an equirectangular raster); every point
//    is at the slice height above the datum.
//  - Cross-section: x runs linearly in distance along the path (0 at the first point, the path's
//    length at the last), y linearly in height from the top height down to the bottom one; the
//    path is the sequence of WGS84 geodesics between consecutive points (GeodesicPath).
// Heights are above a datum (SliceHeightDatum): mean sea level (the EGM96 geoid, Geoid.h: what
// radar users mean by a CAPPI height, and what the axes say) or the WGS84 ellipsoid.
//
// Values (SliceRaster): the project's sentinels, as RadarVolume.h: NaN = no data (outside every
// volume, or not observed), -infinity = no echo (measured, nothing there), finite = an echo's
// value in field units. Several samplers (a mosaic of radars of one field, say) combine by
// sampleVolumes: the largest Echo value; else no echo if any sampler measured no echo; else no
// data. With one sampler a pixel is exactly that sampler's sample at the pixel centre.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

class GeoidGrid;
struct GridVolume;
struct PolarVolume;

/// What a slice height is measured from.
enum class SliceHeightDatum {
  SeaLevel,   ///< above mean sea level: the ellipsoid + the EGM96 undulation at each point
  Ellipsoid,  ///< above the WGS84 ellipsoid
};
const char* toString(SliceHeightDatum d);  ///< "above sea level" / "above the WGS84 ellipsoid"

/// A latitude/longitude box (degrees). Longitudes continuous: westDeg < eastDeg, eastDeg may
/// exceed 180 for a box across the antimeridian (170 .. 190).
struct LatLonBox {
  double southDeg = 0.0, northDeg = 0.0, westDeg = 0.0, eastDeg = 0.0;
};
/// Checks a box: finite, -90 <= south < north <= 90, west < east, east - west <= 360. `what`
/// names it in the message.
Status validateBox(const LatLonBox& box, const std::string& what);

struct LatLon {
  double latDeg = 0.0, lonDeg = 0.0;
};

/// A path of WGS84 geodesics through two or more points (GeographicLib through globe/Ellipsoid.h).
class GeodesicPath {
 public:
  /// Errors: fewer than two points, a latitude outside [-90, 90] or a non-finite coordinate, two
  /// consecutive points less than 1 m apart (no direction), two consecutive points nearly
  /// antipodal (more than 19,900 km apart: the geodesic between them is not unique).
  static Result<GeodesicPath> create(const std::vector<LatLon>& points);

  /// The point at `distanceMeters` along the path (clamped to [0, lengthMeters()]) and the
  /// path's forward azimuth there (degrees clockwise from north).
  globe::GeodesicPoint at(double distanceMeters) const;
  double lengthMeters() const { return cumulativeMeters_.back(); }
  const std::vector<LatLon>& points() const { return points_; }
  /// Distance along the path of each point (m): 0 for the first, lengthMeters() for the last.
  const std::vector<double>& pointDistancesMeters() const { return cumulativeMeters_; }

 private:
  std::vector<LatLon> points_;
  std::vector<double> azimuthDeg_;        ///< initial azimuth of segment k (points k -> k + 1)
  std::vector<double> cumulativeMeters_;  ///< size points_.size()
};

/// A CAPPI: a horizontal slice at a constant height over a box.
struct CappiSpec {
  double heightMeters = 3000.0;  ///< above the datum (m)
  /// Set: an isobaric section instead (Pa): the surface where a pressure-level grid's pressure is
  /// this, sampled by samplePressureSection (SliceSource.h); heightMeters is then unused.
  std::optional<double> pressurePa;
  SliceHeightDatum datum = SliceHeightDatum::SeaLevel;
  LatLonBox box;
  int columns = 512, rows = 512;
};

/// A vertical cross-section along a geodesic path from bottomMeters to topMeters.
struct CrossSectionSpec {
  std::vector<LatLon> points;                      ///< two or more
  double bottomMeters = 0.0, topMeters = 15000.0;  ///< above the datum (m), bottom < top
  SliceHeightDatum datum = SliceHeightDatum::SeaLevel;
  int columns = 800, rows = 300;
};

/// Where a slice's pixels are (see the file comment).
class SliceGeometry {
 public:
  enum class Kind { Cappi, CrossSection };

  /// `geoid` is needed for SliceHeightDatum::SeaLevel (nullptr then: an error) and must outlive
  /// the geometry (defaultEgm96Grid() does). Errors: a bad box or path, a non-finite height,
  /// bottom >= top, columns or rows outside 1..16384.
  static Result<SliceGeometry> cappi(const CappiSpec& spec, const GeoidGrid* geoid);
  static Result<SliceGeometry> crossSection(const CrossSectionSpec& spec, const GeoidGrid* geoid);

  Kind kind() const { return kind_; }
  int columns() const { return columns_; }
  int rows() const { return rows_; }
  SliceHeightDatum datum() const { return datum_; }

  /// The axes' values at continuous pixel coordinates: CAPPI: x -> longitude (deg, continuous
  /// from the box's west edge), y -> latitude (deg); cross-section: x -> distance along the path
  /// (m), y -> height above the datum (m). Linear in x and y respectively.
  double xValue(double x) const { return x0_ + (x1_ - x0_) * x / columns_; }
  double yValue(double y) const { return y0_ + (y1_ - y0_) * y / rows_; }
  /// The axes' ranges: xValue(0), xValue(columns) and yValue(rows) (bottom), yValue(0) (top).
  double xFirst() const { return x0_; }
  double xLast() const { return x1_; }
  double yBottom() const { return y1_; }
  double yTop() const { return y0_; }

  /// Geodetic position (height above the WGS84 ellipsoid) of continuous pixel coordinates.
  globe::Geodetic geodeticAt(double x, double y) const;
  /// Its ECEF position (m).
  glm::dvec3 ecefAt(double x, double y) const;

  /// CAPPI: the slice height above its datum (m).
  double cappiHeightMeters() const { return cappiHeight_; }
  /// CAPPI: the pressure of an isobaric section (Pa; CappiSpec::pressurePa), else empty. Its
  /// geodeticAt heights are then not the surface's (the grid gives those per column).
  std::optional<double> pressurePa() const { return pressurePa_; }
  /// Cross-section: the path.
  const GeodesicPath& path() const { return path_; }

 private:
  SliceGeometry(Kind kind, int columns, int rows, SliceHeightDatum datum, const GeoidGrid* geoid)
      : kind_(kind), columns_(columns), rows_(rows), datum_(datum), geoid_(geoid) {}
  double ellipsoidalHeight(double latDeg, double lonDeg, double heightAboveDatum) const;

  Kind kind_;
  int columns_, rows_;
  SliceHeightDatum datum_;
  const GeoidGrid* geoid_;
  double x0_ = 0.0, x1_ = 1.0, y0_ = 0.0, y1_ = 1.0;
  double cappiHeight_ = 0.0;
  std::optional<double> pressurePa_;
  GeodesicPath path_;
};

/// A slice's values (see the file comment for the sentinels), row 0 at the top.
struct SliceRaster {
  int columns = 0, rows = 0;
  std::vector<float> values;  ///< rows x columns, row-major
  std::size_t echoCount = 0, noEchoCount = 0, noDataCount = 0;
  float minEcho = std::numeric_limits<float>::quiet_NaN();  ///< NaN when there is no echo
  float maxEcho = std::numeric_limits<float>::quiet_NaN();

  float at(int column, int row) const {
    return values[static_cast<std::size_t>(row) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(column)];
  }
};

/// Counts a raster's echo, no-echo and no-data values and sets its echo range (the samplers of
/// this file and SliceSource.h fill the values, this summarises them).
void summarizeSliceRaster(SliceRaster& raster);

/// The one rule combining several samplers at a point (file comment): the largest Echo; else
/// NoEcho if any sampler says NoEcho; else NoData. Samplers whose provablyEmpty(ecef) holds are
/// not asked (that changes nothing: VolumeSampler's contract).
VolumeSample sampleVolumes(const std::vector<const VolumeSampler*>& samplers, const glm::dvec3& ecef,
                           Interpolation interpolation);

/// Samples every pixel centre of `geometry` through sampleVolumes (threads: 0 = the hardware's
/// count). The result does not depend on the thread count.
SliceRaster sampleSlice(const std::vector<const VolumeSampler*>& samplers, const SliceGeometry& geometry,
                        Interpolation interpolation, int threads = 0);

/// The box a radar's data can cover: the geodesic circle of radius maxRangeMeters around the
/// site (its extreme latitudes and longitudes over 720 azimuths, widened by 0.1 % of the range).
LatLonBox polarExtent(const PolarVolume& volume);
/// A grid's horizontal extent: the smallest and largest latitude and (continuous) longitude of
/// its columns.
LatLonBox gridExtent(const GridVolume& grid);

}  // namespace atmoglobe::volume
