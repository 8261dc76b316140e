#pragma once
// Forecast-grid reader: netCDF (classic or netCDF-4, groups included) model output following
// the CF conventions, WRF output, and GRIB editions 1 and 2 (through ecCodes: regular_ll,
// regular_gg, reduced_gg and reduced_ll grids, pressure and height levels; docs/grids.md, "GRIB").
// Format from content,
// never from the file name.
//
// Horizontal: rectilinear grids (1-D latitude and longitude coordinate variables, longitudes in
// 0..360 or -180..180, regional or global, latitudes north-to-south or south-to-north) and
// curvilinear ones (2-D latitude/longitude named by the variable's `coordinates` attribute, or
// WRF XLAT/XLONG; WRF variables staggered in x, y or z are averaged to mass points).
// Values: scale_factor / add_offset, _FillValue, missing_value, valid_min / valid_max /
// valid_range and _Unsigned applied; missing -> NaN.
// Time: the CF time coordinate (units "UNIT since DATE", any CF calendar: CfTime.h) or WRF's
// Times strings. Any other dimension (ensemble member, month ...) is read at one index
// (GridReadOptions::extraIndex, member); it is never taken for the vertical one.
// Vertical: every coordinate ends as heights above the WGS84 ellipsoid per column and level;
// how (and whether approximately) is said in GridVolume::heightNote / approximateHeights. The
// rules are in docs/grids.md.
//
// Lazy: readGridVolume reads only the variable, the time step, the levels and the columns it
// is asked for (netCDF hyperslabs), plus the coordinates of that region; GridVolume::bytesRead
// says how much. describeGridFile reads metadata, the coordinate variables and a sample of
// columns for the height range.
//
// Errors: Result errors that start with the file name and name the variable and what is wrong;
// sizes are checked against the file before anything is allocated (io::NetcdfFile::checkReadable).
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridVolume.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// A region to read. Longitudes go east from westDeg to eastDeg (eastDeg < westDeg: across the
/// antimeridian, e.g. 170 .. -170); a span of 360 or more keeps every column. The crop keeps
/// the grid points inside the box and one more on each side, strictly outside it, where there is
/// one: the kept cells cover the box, and a point on its edge (a box edge on a grid line, after
/// the rounding of a round trip through ECEF) lies between kept points. Levels count from the
/// bottom (0 = lowest after ordering).
struct GridCrop {
  double southDeg = -90.0, northDeg = 90.0;
  double westDeg = -180.0, eastDeg = 180.0;
  std::size_t firstLevel = 0;
  std::size_t levelCount = std::numeric_limits<std::size_t>::max();  ///< max(): up to the top
};

/// A statistic over the members of an ensemble, computed value by value (GridEnsemble.cpp,
/// docs/grids.md "Ensembles"): each value of the result is that of the members' values at the
/// same grid point; a point missing (NaN) in any member is missing in the result.
struct EnsembleStatistic {
  enum class Kind {
    Mean,         ///< sum / N
    Spread,       ///< standard deviation about the mean, sqrt(sum (x - mean)^2 / N)
    Minimum,      ///< smallest member value
    Maximum,      ///< largest member value
    Probability,  ///< percentage of the members whose value passes `comparison threshold`
  };
  Kind kind = Kind::Mean;
  std::string comparison;  ///< Probability: ">=", ">", "<=" or "<"
  double threshold = 0.0;  ///< Probability: in the variable's units
};
/// Parses "mean", "spread", "min", "max" or "prob:OPVALUE" (OP one of >=, >, <=, <; e.g.
/// "prob:>=273.15"). Errors name the text and list the forms.
Result<EnsembleStatistic> parseEnsembleStatistic(const std::string& text);
/// "mean", "spread", "min", "max", "prob:>=273.15": as parsed (scenes write it back).
std::string toString(const EnsembleStatistic& statistic);

struct GridReadOptions {
  /// Variable to read: its name ("QCLOUD") or full path ("/forecast/t"); GRIB: the shortName
  /// ("t": its level type with the most levels) or shortName:typeOfLevel ("t:isobaricInhPa").
  /// Empty: the default (chooseDefaultGridVariable; GRIB: docs/grids.md).
  std::string variable;
  /// Time step by index on the file's time axis...
  std::size_t timeIndex = 0;
  /// ...or by ISO 8601 UTC time ("2005-08-28T15:00:00Z", "2005-08-28 15:00"), matched exactly
  /// (to the second) to the time axis; non-empty overrides timeIndex.
  std::string timeIso8601;
  /// Ensemble member to read; -1: the first the variable has. GRIB: the `number` key. netCDF:
  /// the value of the variable's ensemble dimension's coordinate (a dimension named number,
  /// realization, member, ensemble ... or with standard_name realization; docs/grids.md), or
  /// its index where that dimension has no coordinate variable. Files without members accept
  /// only -1.
  long member = -1;
  /// netCDF: the index to read along each dimension that is neither horizontal, vertical nor
  /// time (an ensemble member, a month of a climatology ...), by dimension name ("month": 6).
  /// A dimension not named here is read at index 0 (an ensemble dimension: at `member` when
  /// that is set). A name that is not such a dimension of the variable, or an index beyond it,
  /// is an error. GRIB files accept only an empty map.
  std::map<std::string, std::size_t> extraIndex;
  /// Set: not one member but this statistic over every member of the variable (GRIB `number`s;
  /// netCDF: every index of the ensemble dimension), read one member at a time (memory: one
  /// member plus the statistic's sums, in double). The grid's coordinates and heights are those
  /// of the first member. Errors: with `member` or an index along the ensemble dimension also
  /// set; a variable without members (fewer than two).
  std::optional<EnsembleStatistic> ensemble;
  GridCrop crop;
  /// Heights above mean sea level -> above the ellipsoid with the EGM96 undulation (Geoid.h).
  /// false: they are used as heights above the ellipsoid (errors of -106..+85 m; the note says so).
  bool useGeoid = true;
  /// netCDF: a variable without a vertical dimension ((time,) latitude/y, longitude/x: a surface
  /// or single-level field) is read as one level at mean sea level instead of refused (the maps
  /// on the globe, engine/SurfaceLayer.h). GRIB reads single-level fields always.
  bool allowSingleLevel = false;
  /// Keep the pressure of every value of a grid on terrain-following pressure levels
  /// (GridVolume::pressurePa: hybrid sigma-pressure and sigma levels from their surface pressure,
  /// GRIB hybrid levels from `pv` and sp/lnsp, WRF eta levels as P + PB), for isobaric surfaces
  /// and sections. Costs one float per value; pressure levels and height levels ignore it.
  bool keepPressure = false;
};

/// Sets the time step of `read` from a user's text: an index ("3": timeIndex) or an ISO 8601
/// UTC time (timeIso8601); empty leaves the first step. Error: an index of more than 9 digits.
Status selectGridTime(const std::string& text, GridReadOptions& read);

/// A dimension of the file (every group), for `atmoglobe info`.
struct GridDimensionInfo {
  std::string name;  ///< full path ("/lat", "/forecast/level")
  std::size_t length = 0;
  bool unlimited = false;
};

/// A variable of the file, for `atmoglobe info`.
struct GridVariableInfo {
  std::string name;                     ///< full path
  std::vector<std::string> dimensions;  ///< dimension names, file order
  std::vector<std::size_t> shape;
  std::string type;  ///< "float", "short" ...
  std::string units, standardName, longName;
  bool packed = false;  ///< has scale_factor or add_offset
  bool onGrid = false;  ///< a 3-D variable readGridVolume can read

  // GRIB only (name is shortName:typeOfLevel; the netCDF fields above stay empty but units and
  // longName): what the variable's messages share and span.
  std::string shortName, levelType, gridType;  ///< keys shortName, typeOfLevel, gridType
  std::vector<double> levels;                  ///< `level` values, bottom first (hPa, Pa, m as the level type says)
  std::size_t gridNi = 0, gridNj = 0;          ///< points along a parallel / a meridian (0: not regular)
  std::size_t gridPoints = 0;                  ///< numberOfPoints (every grid type)
  std::size_t timeCount = 0, memberCount = 0, messageCount = 0;
  std::string notReadable;  ///< why readGridVolume does not read it yet ("" when it does)
};

/// What describeGridFile finds: the file and, for one variable (the default or the one asked
/// for), its grid, vertical coordinate, height range and times.
struct GridFileInfo {
  std::string path;
  std::string format;       ///< as GridVolume::format
  std::string conventions;  ///< the Conventions attribute, or the WRF TITLE
  std::vector<GridDimensionInfo> dimensions;
  std::vector<GridVariableInfo> variables;

  std::string variable;  ///< the variable described below
  /// Its dimensions that are neither horizontal, vertical nor time, and the index described.
  std::vector<GridExtraDimension> extraDimensions;
  bool curvilinear = false;
  std::size_t nx = 0, ny = 0, nz = 0;
  std::string xDimension, yDimension, zDimension, timeDimension;  ///< names ("" for none)
  double southDeg = 0, northDeg = 0, westDeg = 0, eastDeg = 0;    ///< extent (eastDeg may exceed 180)
  bool wrapsLongitude = false;
  /// The time step whose coordinates and heights are described (read.timeIndex / timeIso8601;
  /// 0 by default), and whether the latitudes/longitudes change with time (a moving nest: the
  /// extent is then that step's).
  std::size_t describedTimeIndex = 0;
  bool coordinatesVaryWithTime = false;
  double meanSpacingKm = 0;  ///< mean distance between neighbouring columns (km)
  /// A GRIB reduced grid (rows of different lengths; nx is then its longest row, ny its rows with
  /// points): its shortest and longest row, its points, and the rows of no point (pl 0) at its
  /// ends that the reader leaves out.
  bool reduced = false;
  std::size_t minRowLengthPoints = 0, maxRowLengthPoints = 0, gridPoints = 0, emptyRowsLeftOut = 0;

  VerticalKind verticalKind = VerticalKind::HeightAboveSeaLevel;
  HeightSource heightSource = HeightSource::Coordinate;
  std::string verticalVariable, heightNote;
  bool approximateHeights = false;
  std::vector<double> levelValues;  ///< bottom first, as GridVolume::levelValues
  std::string levelUnits;
  double heightMinMeters = 0, heightMaxMeters = 0;  ///< above the WGS84 ellipsoid, first time step
  std::size_t heightColumnStride = 1;               ///< the range comes from every Nth row and column

  std::vector<std::string> times;  ///< ISO 8601 UTC
  std::string timeVariable, timeUnits, calendar;

  std::uint64_t bytesRead = 0;  ///< variable data read to describe the file

  // GRIB only.
  std::vector<std::string> steps;     ///< the variable's forecast steps (stepRange, file units), sorted
  std::vector<long> members;          ///< the variable's ensemble members (`number`), sorted
  std::size_t messageCount = 0;       ///< messages in the file
  std::string indexFile;              ///< the message index in the cache ("" when it could not be written)
  bool indexReused = false;           ///< the index came from the cache (no pass over the file)
  std::vector<std::string> warnings;  ///< what the reader skipped (damaged messages)
  /// A projected grid (rotated, Lambert, polar stereographic ...): the PROJ definition its points
  /// were placed by ("" for latitude/longitude grids).
  std::string projection;
  /// The described variable is not read yet (a grid or level type of a later stage): why. Its
  /// grid, heights and times are then not filled in.
  std::string notReadable;
};

/// True when `path` is a GRIB file (its content, unwrapped from gzip/bzip2, starts with "GRIB"),
/// or a netCDF file holding a forecast grid: a WRF file (TITLE mentioning WRF,
/// or XLAT/XLONG with bottom_top) or a file with a variable that has a vertical dimension and
/// latitude/longitude (1-D coordinate variables or 2-D ones named in `coordinates`) and no
/// radar marks (sweep_start_ray_index, ODIM_H5). False (not an error) for anything else,
/// including files that are not netCDF or cannot be opened.
bool isGridFile(const std::string& path);

/// Describes the file (see GridFileInfo) for `variable` (empty: the default variable).
Result<GridFileInfo> describeGridFile(const std::string& path, const std::string& variable = {});
/// The same for `read.variable`; netCDF: at `read.member` / `read.extraIndex` (GRIB: its first
/// member, as above); curvilinear coordinates and heights at `read`'s time step. The rest of
/// `read` is not used.
Result<GridFileInfo> describeGridFile(const std::string& path, const GridReadOptions& read);

/// Reads one variable at one time over a region (see GridReadOptions).
Result<GridVolume> readGridVolume(const std::string& path, const GridReadOptions& options = {});

/// One member of an ensemble as GridReadOptions select it: netCDF an index along the ensemble
/// dimension (extraIndex), GRIB a `number` (member).
struct EnsembleMemberSelection {
  long member = -1;
  std::map<std::string, std::size_t> extraIndex;
};
/// Every member of `read.variable` (metadata only: describeGridFile), in file order. Errors: the
/// reader's, fewer than two members, an index along the ensemble dimension already chosen.
Result<std::vector<EnsembleMemberSelection>> ensembleMemberSelections(const std::string& path,
                                                                      const GridReadOptions& read);

/// The variable read when none is named: among the variables readGridVolume can read, the first
/// of (by name) REFL_10CM, dbz, DBZ, reflectivity, QCLOUD, QRAIN, clw, cloud_water, or (by
/// standard_name) equivalent_reflectivity_factor, mass_fraction_of_cloud_liquid_water_in_air,
/// cloud_liquid_water_mixing_ratio; else the first in file order (groups depth-first). Empty
/// when there is none.
std::string chooseDefaultGridVariable(const std::vector<GridVariableInfo>& variables);

/// `atmoglobe info` output for a grid: one JSON object / text.
std::string describeGridJson(const GridFileInfo& info);
std::string describeGridText(const GridFileInfo& info);

}  // namespace atmoglobe::volume
