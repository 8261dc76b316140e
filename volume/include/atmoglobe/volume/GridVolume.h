#pragma once
// The forecast-grid data model: one variable at one time on a 3-D model grid, what the grid
// reader (GridReader.h) hands to samplers and renderers. GL-free.
//
// Layout: nz levels x ny rows x nx columns, level-major, bottom level first:
//   index(k, j, i) = (k * ny + j) * nx + i.
// Every level has a height above the WGS84 ellipsoid per column (terrain-following and pressure
// levels are not flat), increasing strictly with k in every column.
// Horizontal geometry: rectilinear grids give 1-D latitudes (ascending: row 0 is the southern
// row) and longitudes (strictly increasing, continuous: they may run past 180, e.g. 170..190 for
// a region across the antimeridian); curvilinear grids (WRF XLAT/XLONG, CF 2-D lat/lon) give a
// latitude and a longitude per column (ny x nx, row-major), longitudes made continuous across
// the grid (no jump of 360 between neighbours).
// Reduced grids (GRIB reduced_gg, reduced_ll: a different number of points on each row) are
// stored padded: nx is the longest row, row j holds its rowLengthPoints[j] points in columns
// 0 .. rowLengthPoints[j] - 1, equally spaced in longitude from rowFirstLonDeg[j] by
// rowSpacingDeg[j], and NaN values and heights in the columns beyond (padding: never a grid
// point, never sampled). latDeg gives one latitude per row (ascending) as for rectilinear grids;
// lonDegAt(j, i) is the longitude of point i of row j. index(k, j, i) keeps its meaning.
#include <atmoglobe/globe/Result.h>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::volume {

/// How the file gives the vertical coordinate (the rules: docs/grids.md).
enum class VerticalKind {
  HeightAboveEllipsoid,  ///< lengths above the WGS84 ellipsoid (standard_name height_above_reference_ellipsoid)
  HeightAboveSeaLevel,   ///< lengths above mean sea level / the geoid (altitude, height_above_mean_sea_level, depth)
  HeightAboveGround,     ///< lengths above the surface (standard_name height): surface altitude added
  GeopotentialHeight,    ///< levels in geopotential metres (gpm; standard_name geopotential_height)
  Pressure,              ///< isobaric levels (units Pa, hPa ... or standard_name air_pressure)
  HybridSigmaPressure,   ///< CF atmosphere_hybrid_sigma_pressure_coordinate: p = a p0 + b ps or ap + b ps; GRIB
                         ///< hybrid (model) levels: p = a + b ps from the `pv` coefficients
  Sigma,                 ///< CF atmosphere_sigma_coordinate: p = ptop + sigma (ps - ptop)
  HybridHeight,          ///< CF atmosphere_hybrid_height_coordinate: z = a + b orog
  WrfEta,                ///< WRF terrain-following eta levels (bottom_top)
  GeneralVertical,       ///< GRIB generalVertical(Layer) (ICON, COSMO): heights from the half-level height field HHL
};
const char* toString(VerticalKind k);

/// Where the heights came from.
enum class HeightSource {
  Coordinate,          ///< the coordinate values themselves (lengths), possibly plus a surface altitude
  GeopotentialField,   ///< a geopotential (or geopotential height) field of the file on the same levels
  WrfGeopotential,     ///< WRF (PH + PHB) / 9.81 on the staggered W levels, averaged to mass levels
  StandardAtmosphere,  ///< pressure converted by the standard atmosphere: approximate
  /// Hydrostatic integration upward from the surface geopotential with the file's temperature
  /// (and humidity) on every model level below (GRIB hybrid levels, as IFS computes them)
  HydrostaticIntegration,
  HeightField,  ///< a field of heights of the file on the same levels (ICON/COSMO HHL, half levels averaged)
};
const char* toString(HeightSource s);

/// A dimension of a grid variable that is neither horizontal, vertical nor time (an ensemble
/// member, a month of a climatology ...): the variable is read at one index along it.
struct GridExtraDimension {
  std::string name;  ///< the dimension's name
  std::size_t length = 0;
  std::size_t index = 0;  ///< the index read (or described)
  /// The coordinate variable's value at `index` (NaN: the dimension has no numeric coordinate
  /// variable) and its units.
  double value = std::numeric_limits<double>::quiet_NaN();
  std::string units;
  bool ensemble = false;  ///< an ensemble dimension: `index` is chosen by GridReadOptions::member too
};

struct GridVolume {
  std::string path;    ///< the file read
  std::string format;  ///< "CF netCDF-4", "WRF (netCDF-4)", "CF netCDF classic" ...

  // --- the variable ---
  std::string variable;  ///< full name in the file ("/QCLOUD", "/forecast/t")
  std::string units, standardName, longName;

  // --- horizontal geometry ---
  bool curvilinear = false;  ///< false: 1-D lonDeg (nx) and latDeg (ny); true: both ny x nx
  std::size_t nx = 0, ny = 0, nz = 0;
  std::vector<double> lonDeg, latDeg;  ///< see the file comment (degrees, WGS84)
  /// Rectilinear grid covering all longitudes: column nx-1 neighbours column 0 (a sampler
  /// interpolates across the seam). False for any crop narrower than the globe. Reduced grid:
  /// every row covers all longitudes, its last point neighbouring its first.
  bool wrapsLongitude = false;
  /// A GRIB projected grid (curvilinear): the PROJ definition its points were placed by; "" else.
  std::string projection;
  /// A vector component (wind u or v) given along the grid's axes rather than east and north:
  /// GRIB uvRelativeToGrid on a projected grid, WRF's U and V, CF x_wind / grid_eastward_wind.
  /// volume/Wind.h turns such components east and north.
  bool vectorsRelativeToGrid = false;
  /// Reduced grids only (empty otherwise, see the file comment): per row (ny values) the number
  /// of its points (>= 1, <= nx), the longitude of its first point (degrees, continuous with the
  /// other rows: a crop's rows start within one of their spacings west of its west edge) and the
  /// spacing of its points (degrees east, > 0; a wrapping row has rowLengthPoints x
  /// rowSpacingDeg = 360). For a reduced grid `lonDeg` holds nx longitudes spaced by
  /// reducedSpacingDeg() from reducedWestDeg(): the axis GridSampler measures a reduced grid's
  /// column index on (not the longitudes of any row's points in general; see lonDegAt).
  std::vector<std::size_t> rowLengthPoints;
  std::vector<double> rowFirstLonDeg, rowSpacingDeg;
  /// Index in the file of output row 0 / column 0 / level 0 and the direction (+1 or -1) in
  /// which the file index runs with the output index (rows of a north-to-south file run -1);
  /// for a crop across the antimeridian of a global grid the column index wraps modulo the
  /// file's column count. For tests and messages.
  std::size_t fileFirstColumn = 0, fileFirstRow = 0, fileFirstLevel = 0;
  int fileColumnStep = 1, fileRowStep = 1, fileLevelStep = 1;

  // --- values ---
  std::vector<float> values;  ///< nz x ny x nx, NaN = missing (fill, missing_value, outside valid range)
  float valueMin = std::numeric_limits<float>::quiet_NaN();  ///< smallest finite value (NaN if none)
  float valueMax = std::numeric_limits<float>::quiet_NaN();  ///< largest finite value (NaN if none)

  // --- vertical ---
  /// Height of each value's centre above the WGS84 ellipsoid (m), same layout as values,
  /// strictly increasing with k in every column. Stored as float: 2 mm resolution at 20 km,
  /// far below what any model level means, and half the memory of double.
  std::vector<float> heightAboveEllipsoidMeters;
  VerticalKind verticalKind = VerticalKind::HeightAboveSeaLevel;
  HeightSource heightSource = HeightSource::Coordinate;
  std::string verticalVariable;     ///< the coordinate variable (or "PH+PHB" for WRF)
  std::string heightNote;           ///< one line: how heights were derived and from what
  bool approximateHeights = false;  ///< true: the heights are an estimate (standard atmosphere, datum guessed)
  /// The vertical coordinate's own value for each level read, bottom first (Pa for pressure
  /// levels, m for heights, the dimensionless coordinate for hybrid/sigma/eta; GRIB hybrid and
  /// generalVertical levels: the model level number, 1 = top, units "model level"; empty when
  /// the file has no 1-D coordinate values, e.g. WRF without ZNU) and its units.
  std::vector<double> levelValues;
  std::string levelUnits;
  /// Terrain-following pressure levels (hybrid sigma-pressure, sigma, WRF eta, GRIB hybrid) read
  /// with GridReadOptions::keepPressure: the pressure of each value (Pa), same layout as values,
  /// so that an isobaric surface can be cut through them (isobaricColumnValues). Empty otherwise
  /// (pressure levels give theirs in levelValues).
  std::vector<float> pressurePa;

  // --- time ---
  std::vector<std::string> times;  ///< the file's time axis, ISO 8601 UTC (empty strings if it has none)
  std::size_t timeIndex = 0;       ///< which one was read
  std::string validTime;           ///< times[timeIndex] ("" when the variable has no time dimension)
  long member = -1;                ///< ensemble member read (GRIB `number`, see GridReadOptions::member); -1: none
  /// A statistic over members (GridReadOptions::ensemble): what it is, as written by
  /// toString(EnsembleStatistic) ("mean", "prob:>=273.15"), and the members it combined (GRIB
  /// `number`s, netCDF the ensemble coordinate's values or indices). Empty: one member or none.
  std::string ensembleStatistic;
  std::vector<long> ensembleMembers;
  /// The variable's dimensions that are neither horizontal, vertical nor time, and the index read.
  std::vector<GridExtraDimension> extraDimensions;

  // --- cost ---
  /// Bytes of variable data read from the file for this volume (values, coordinates, heights;
  /// elements x stored size, before decompression). See io::NetcdfFile::dataBytesRead.
  std::uint64_t bytesRead = 0;
  /// GRIB: the messages read for this volume (the file, byte offset and length in its content,
  /// after gzip/bzip2), in reading order: what `bytesRead` counts (the bench decodes the same
  /// messages with plain ecCodes for its floor). Empty for netCDF.
  struct GribMessageRead {
    std::string path;
    std::uint64_t offset = 0, length = 0;
    bool compressed = false;  ///< the file is gzip/bzip2: the offset is in its unwrapped content
  };
  std::vector<GribMessageRead> gribMessagesRead;

  std::size_t index(std::size_t k, std::size_t j, std::size_t i) const { return (k * ny + j) * nx + i; }
  float value(std::size_t k, std::size_t j, std::size_t i) const { return values[index(k, j, i)]; }
  float heightMeters(std::size_t k, std::size_t j, std::size_t i) const {
    return heightAboveEllipsoidMeters[index(k, j, i)];
  }
  double latDegAt(std::size_t j, std::size_t i) const { return curvilinear ? latDeg[j * nx + i] : latDeg[j]; }
  /// The longitude of column i of row j (a reduced grid: of point i of row j; for a padding column,
  /// where the row would put it).
  double lonDegAt(std::size_t j, std::size_t i) const {
    if (curvilinear) return lonDeg[j * nx + i];
    if (reduced()) return rowFirstLonDeg[j] + static_cast<double>(i) * rowSpacingDeg[j];
    return lonDeg[i];
  }
  /// A reduced grid (rows of different lengths, see the file comment).
  bool reduced() const { return !rowLengthPoints.empty(); }
  /// Points in row j: rowLengthPoints[j] for a reduced grid, else nx.
  std::size_t rowLength(std::size_t j) const { return reduced() ? rowLengthPoints[j] : nx; }
  /// A reduced grid's reference longitude axis (lonDeg): its westernmost row start, and its finest
  /// row spacing (360 / nx when it wraps: the longest row's). NaN for other grids.
  double reducedWestDeg() const;
  double reducedSpacingDeg() const;
  /// A reduced grid's easternmost point (the westernmost start + 360 - reducedSpacingDeg() when
  /// it wraps, as a wrapping rectilinear grid's last column). NaN for other grids.
  double reducedEastDeg() const;
};

/// Checks a reduced grid's description (row tables of ny entries, lengths 1..nx with nx the
/// longest, finite first longitudes, positive finite spacings, wrapping rows covering 360
/// degrees) and sets lonDeg to its reference axis. Error: what is wrong, for messages.
Status finishReducedGrid(GridVolume& g);

/// The indices read along the grid's extra dimensions that are not its ensemble member (shown by
/// `member`), for titles: "month 3 (index 2)", "month index 2" without a coordinate value, joined
/// by ", "; empty when there is none.
std::string extraIndexText(const GridVolume& grid);

/// What of an ensemble the grid holds, for titles and legends: "member 3", "mean of 10 members",
/// "prob:>=273.15 of 10 members"; empty for a grid without members.
std::string memberText(const GridVolume& grid);
/// The member a grid read as one member is, as a statistic lists its members (ensembleMembers):
/// GRIB's `number`, else the netCDF ensemble coordinate's value (its index where it has none);
/// `fallback` for a grid without members.
long memberLabel(const GridVolume& grid, long fallback);

/// Sets valueMin and valueMax to the smallest and largest finite value (NaN when there is none).
void setValueRange(GridVolume& grid);

/// A grid between two time steps of one variable and region: values and heights linear in time,
/// value = (1 - fraction) a + fraction b (NaN where either is NaN: no value is invented where a
/// step has none), heights the same way (they stay strictly increasing per column: a convex
/// combination of two increasing sequences is increasing). validTime is the interpolated time
/// (ISO 8601, to the second). Errors: different shapes, coordinates or variables, fraction
/// outside [0, 1].
Result<GridVolume> interpolateGridSteps(const GridVolume& a, const GridVolume& b, double fraction);

/// The ISO 8601 time a `fraction` of the way from `fromIso` to `toIso` (both "YYYY-MM-DDTHH:MM:SSZ"
/// on the proleptic Gregorian calendar), rounded to the second; empty if either does not parse.
std::string interpolateIsoTime(const std::string& fromIso, const std::string& toIso, double fraction);

}  // namespace atmoglobe::volume
