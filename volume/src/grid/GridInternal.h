#pragma once
// Internals of the forecast-grid reader shared by its source files (not a public header).
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/CfTime.h>
#include <atmoglobe/volume/GridReader.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume::grid {

// ---------------------------------------------------------------- netCDF helpers (GridNetcdf.cpp)

/// Every group of the file, depth-first from the root.
std::vector<int> allGroups(const io::NetcdfFile& f);
/// The parent of a group, or nullopt for the root.
std::optional<int> parentGroup(int group);
/// Name of a dimension (by id; visible from `group`).
std::string dimensionName(int group, int dimId);
/// A text attribute of a variable ("" when absent or not text).
std::string attrText(const io::NetcdfFile& f, const io::NcVar& v, const char* name);
/// A global text attribute of the root group ("" when absent or not text).
std::string globalText(const io::NetcdfFile& f, const char* name);
/// A variable called `name` in `group` or, failing that, its ancestors (CF: coordinate and
/// formula-term variables may sit in an enclosing group).
std::optional<io::NcVar> findInScope(const io::NetcdfFile& f, int group, const std::string& name);
/// "float", "short" ...
const char* typeName(nc_type t);
/// An error naming the file and the variable: "FILE: variable 'NAME': WHAT".
Error varError(const io::NetcdfFile& f, const io::NcVar& v, const std::string& what);
/// `v` with `decimals` decimals, for messages.
std::string num(double v, int decimals = 3);

/// How stored values become physical ones (CF section 2.5 and 8.1).
struct Packing {
  double scale = 1.0, offset = 0.0;
  bool hasFill = false;
  double fill = 0.0;
  std::vector<double> missing;
  double validMin = -std::numeric_limits<double>::infinity();
  double validMax = std::numeric_limits<double>::infinity();
  bool isUnsigned = false;        ///< _Unsigned = "true" on a signed integer type
  double unsignedWrap = 0;        ///< 2^bits of the type
  bool defaultFloatFill = false;  ///< float/double without _FillValue: the netCDF default fill means missing
  double defaultFill = 0;
  bool packed() const { return scale != 1.0 || offset != 0.0; }
};
Result<Packing> packingOf(const io::NetcdfFile& f, const io::NcVar& v);

/// For each dimension of a variable, the file indices to read, in output order. The result of
/// readPicked is dense, in the variable's dimension order, each dimension as long as its picks.
using Picks = std::vector<std::vector<std::size_t>>;

/// Reads the picked elements, decoded (Packing) to Out; missing -> NaN. Reads each maximal
/// arithmetic run of indices as one hyperslab (nc_get_vars), so a contiguous crop is one read,
/// a crop across the seam of a global grid two. Checks the element count against the file
/// (io::NetcdfFile::checkReadable) before allocating.
template <class Out>
Result<std::vector<Out>> readPicked(const io::NetcdfFile& f, const io::NcVar& v, const Picks& picks);

/// The numbers 0..n-1 / first..first+n-1.
std::vector<std::size_t> iota(std::size_t first, std::size_t n);

/// Replaces a dense array of `shape` by the means of neighbours along `axis` (length L -> L-1):
/// WRF staggered variables to mass points.
template <class T>
void averageAdjacent(std::vector<T>& a, std::vector<std::size_t>& shape, std::size_t axis);

// ---------------------------------------------------------------- the layout of one variable (GridLayout.cpp)

enum class LengthDatum { Ellipsoid, SeaLevel, Ground, Unknown };

struct VerticalSpec {
  VerticalKind kind = VerticalKind::HeightAboveSeaLevel;
  std::optional<io::NcVar> coordinate;  ///< the 1-D coordinate variable (CF)
  std::string coordinateUnits;
  double toSi = 1.0;          ///< coordinate units -> Pa (pressure) or m (lengths, gpm)
  bool positiveDown = false;  ///< lengths counted downwards (depth)
  LengthDatum datum = LengthDatum::SeaLevel;
  std::string datumReason;                 ///< why that datum ("standard_name altitude" ...)
  std::map<std::string, io::NcVar> terms;  ///< formula_terms (a, b, ap, p0, ps, ptop, sigma, orog)
  std::map<std::string, double> termToSi;  ///< unit factor of each term
  /// Hybrid sigma-pressure levels whose p0 is no variable of the file (CAM's A_var/B_var form
  /// without P0): the p0 used (Pa) and why, said in the height note.
  std::optional<double> defaultP0Pa;
  std::string defaultP0Reason;
  /// Where the terms come from ("formula_terms", or the A_var/B_var/P0_var/PS_var attributes).
  std::string termsSource = "formula_terms";
  std::optional<io::NcVar> geopotential;     ///< level geopotential (or geopotential height) field
  double geopotentialToGpm = 1.0;            ///< factor to geopotential metres (1/g0 for m2 s-2)
  std::optional<io::NcVar> surfaceAltitude;  ///< for heights above ground
  double surfaceToMeters = 1.0;
  // WRF
  std::optional<io::NcVar> ph, phb, p, pb, znu;
  /// File level index increases upwards.
  bool upward = true;
  std::size_t fileLevels = 0;  ///< levels in the file (mass levels for WRF)
};

struct TimeSpec {
  int dimId = -1;  ///< -1: the variable has no time dimension
  std::size_t count = 1;
  std::optional<io::NcVar> coordinate;  ///< CF time coordinate
  std::optional<io::NcVar> wrfTimes;    ///< WRF Times (char)
  std::string units, calendar;
  std::optional<CfTimeUnits> parsed;
  std::string unitsError;  ///< why the units could not be parsed ("" if they could)
};

/// A dimension of the grid variable that is neither horizontal, vertical nor time: read at one
/// index (GridReadOptions::extraIndex / member).
struct ExtraDim {
  int dimId = -1;
  std::string name;
  std::size_t length = 0;
  std::optional<io::NcVar> coordinate;  ///< its 1-D coordinate variable, if numeric
  bool ensemble = false;                ///< an ensemble member dimension (member picks it)
};

struct GridLayout {
  io::NcVar var;
  std::vector<ExtraDim> extras;  ///< in the variable's dimension order
  bool wrf = false;
  // dimension ids of the roles (-1: none). For WRF the mass dimensions; the variable may use
  // the staggered ones instead (stagX/Y/Z).
  int xDim = -1, yDim = -1, zDim = -1;
  int xStagDim = -1, yStagDim = -1, zStagDim = -1;
  bool stagX = false, stagY = false, stagZ = false;
  std::size_t nx = 0, ny = 0;  ///< mass columns / rows in the file
  bool curvilinear = false;
  /// No vertical dimension (GridReadOptions::allowSingleLevel): one level at mean sea level.
  bool singleLevel = false;
  io::NcVar lat, lon;  ///< 1-D (rectilinear) or 2-D/3-D (curvilinear)
  VerticalSpec vertical;
  TimeSpec time;
  std::string units, standardName, longName;
};

/// What the file is, shared by every variable's analysis (GridFormat.cpp).
struct FileKind {
  bool wrf = false;
  std::string format, conventions;
};
FileKind fileKind(const io::NetcdfFile& f);

/// The variable's layout; for an empty name, the default variable (chooseDefaultGridVariable), or
/// why there is none. `chosen`: the variable's name (GridFormat.cpp).
Result<GridLayout> layoutFor(const io::NetcdfFile& f, const FileKind& kind, const std::string& variable,
                             std::string* chosen, bool allowSingleLevel = false);

/// The layout of variable `v`, or an error saying why it is not a grid variable this reader
/// can read (naming the file and the variable).
Result<GridLayout> analyse(const io::NetcdfFile& f, const FileKind& kind, const io::NcVar& v,
                           bool allowSingleLevel = false);

/// The variable named `name` (name or full path), or an error listing what there is.
Result<io::NcVar> findGridVariable(const io::NetcdfFile& f, const std::string& name);

/// Every variable of the file with its metadata and whether analyse() accepts it.
std::vector<GridVariableInfo> listVariables(const io::NetcdfFile& f, const FileKind& kind);

/// The index of every extra dimension of `l` asked for by `read` (extraIndex by name, member for
/// an ensemble dimension, else 0), with the coordinate value there; errors name the file, the
/// variable and what there is to choose from. `dimIndex` (dimension id -> index) for Selection.
Result<std::vector<GridExtraDimension>> resolveExtraDimensions(const io::NetcdfFile& f, const GridLayout& l,
                                                               const GridReadOptions& read,
                                                               std::map<int, std::size_t>* dimIndex);
/// The ensemble member of the extra dimensions read (the coordinate value, else the index), or
/// -1 when there is no ensemble dimension.
long memberOf(const std::vector<GridExtraDimension>& extras);

/// The time axis as ISO strings ("" for a step whose time is unknown).
Result<std::vector<std::string>> readTimes(const io::NetcdfFile& f, const TimeSpec& t);
/// The step `o` asks for (timeIso8601 matched exactly to `times`, else timeIndex), checked
/// against the axis (GridReader.cpp).
Result<std::size_t> resolveTime(const io::NetcdfFile& f, const GridLayout& l, const GridReadOptions& o,
                                const std::vector<std::string>& times);

// ---------------------------------------------------------------- the columns of a crop (GridHorizontal.cpp)

/// The columns to read and their coordinates, in output order.
struct Horizontal {
  std::vector<std::size_t> rows, cols;  ///< file indices (mass points for WRF)
  std::vector<double> latDeg, lonDeg;   ///< 1-D (rectilinear) or rows x cols (curvilinear)
  bool wrapsLongitude = false;
  int rowStep = 1, colStep = 1;
  double southDeg = 90, northDeg = -90, westDeg = 0, eastDeg = 0;  ///< extent of what is kept
  double latAt(std::size_t j, std::size_t i, bool curvilinear) const {
    return curvilinear ? latDeg[j * cols.size() + i] : latDeg[j];
  }
  double lonAt(std::size_t j, std::size_t i, bool curvilinear) const {
    return curvilinear ? lonDeg[j * cols.size() + i] : lonDeg[i];
  }
  /// The mean of the geodesic distances from the middle column to its east and north
  /// neighbours (km; 0 for a single column): the spacing `info` reports.
  double meanSpacingKm(bool curvilinear) const;
};

/// Sets the extent (south, north, west, east, wrap) and mean spacing of `info` from the full
/// horizontal grid `full` (describe's rule for every format).
void describeExtent(const Horizontal& full, bool curvilinear, GridFileInfo& info);
/// The "vertical" object of `info --json` (every format): kind, source, levels, height range.
nlohmann::ordered_json verticalJson(const GridFileInfo& info);

/// The crop's bounds are finite, ordered latitudes and it keeps at least one level. `label`
/// opens the message (the file).
Status checkCrop(const io::NetcdfFile& f, const GridCrop& c);
Status checkCrop(const std::string& label, const GridCrop& c);
/// An error about a coordinate, naming the file and where the coordinate comes from.
using CoordinateError = std::function<Error(const std::string& what)>;
/// The rows and columns of a rectilinear grid whose file gives latitudes `lat` (per file row)
/// and longitudes `lon` (per file column) that the crop keeps, every `sample`-th (and the last):
/// the one normalisation of every rectilinear grid (netCDF 1-D coordinates, GRIB regular_ll and
/// regular_gg): rows ascending, longitudes continuous, global grids wrapping.
Result<Horizontal> rectilinearAxes(const std::vector<double>& lat, const std::vector<double>& lon, const GridCrop& crop,
                                   std::size_t sample, const CoordinateError& latError,
                                   const CoordinateError& lonError);
/// What a crop keeps of a reduced grid (GRIB reduced_gg / reduced_ll: rows of different lengths,
/// each equally spaced in longitude; GridVolume.h).
struct ReducedHorizontal {
  /// rows (file rows kept, output order: ascending latitudes), latDeg (per row), rowStep,
  /// wrapsLongitude, the extent; lonDeg the reference axis (GridVolume::reducedWestDeg,
  /// reducedSpacingDeg; nx values); cols empty.
  Horizontal hz;
  std::size_t nx = 0;  ///< the longest kept row
  std::vector<std::size_t> rowLength;
  std::vector<double> rowFirstLonDeg, rowSpacingDeg;
  /// Every kept point, row by row (packed, no padding): its index in the message's values, and
  /// its latitude and longitude.
  std::vector<std::size_t> points;
  std::vector<double> pointLatDeg, pointLonDeg;
  std::vector<std::size_t> pointRow;  ///< the output row of each kept point
  std::size_t emptyRowsDropped = 0;   ///< rows of no point (pl 0) at the grid's ends, left out
  /// The mean of the distances from the middle row's middle point to its east neighbour and to
  /// the next row at its longitude (km): the spacing `info` reports.
  double meanSpacingKm() const;
};
/// A reduced grid whose file rows hold pl[r] points each (sum = the values' count), every point's
/// latitude and longitude given in the message's order (`lat`, `lon`; a row may run east or west):
/// the rows the crop keeps (inside the box and one beyond each edge, as
/// rectilinearAxes) and in each the points inside the box and one beyond each edge, every
/// `sample`-th row and point. Rows of no point at the grid's ends are left out; one between rows
/// with points, points of a row at different latitudes or not equally spaced in longitude, a row
/// spanning more than 360 degrees are errors.
Result<ReducedHorizontal> reducedAxes(const std::vector<long>& pl, const std::vector<double>& lat,
                                      const std::vector<double>& lon, const GridCrop& crop, std::size_t sample,
                                      const CoordinateError& error);
/// The rows and columns of a rectilinear grid the crop keeps, every `sample`-th (and the last).
Result<Horizontal> rectilinear(const io::NetcdfFile& f, const GridLayout& l, const GridCrop& crop, std::size_t sample);
/// The rows and columns of a curvilinear grid (a latitude and a longitude per point, `ny` rows of
/// `nx`, row-major) that the crop keeps, every `sample`-th (and the last), with one more on each
/// side: the one normalisation of every curvilinear grid (netCDF 2-D coordinates, WRF, GRIB's
/// projected grids): longitudes continuous across the grid (within 180 degrees of the centre
/// point's), shifted so that the westernmost kept one lies in [-180, 180).
Result<Horizontal> curvilinearAxes(std::vector<double> lat, std::vector<double> lon, std::size_t ny, std::size_t nx,
                                   const GridCrop& crop, std::size_t sample, const CoordinateError& latError,
                                   const CoordinateError& lonError);
/// The same for a curvilinear grid, its coordinates read at time step `timeIndex`.
Result<Horizontal> curvilinear(const io::NetcdfFile& f, const GridLayout& l, std::size_t timeIndex,
                               const GridCrop& crop, std::size_t sample);

/// What to read: the time step, levels (file indices, bottom first) and columns.
struct Selection {
  std::size_t time = 0;
  std::vector<std::size_t> levels;
  const Horizontal* hz = nullptr;
  std::map<int, std::size_t> extraIndex;  ///< dimension id -> index, for the layout's extra dimensions
  /// Names column c (of the heights' columns) in messages; unset: "row R, column C" from hz (a
  /// GRIB reduced grid's columns are its kept points, which hz's rows x cols do not describe).
  std::function<std::string(std::size_t)> columnName;
};

// ---------------------------------------------------------------- vertical coordinates (GridHeights.cpp)

/// Level direction and the coordinate's own values (SI units), file order.
struct Levels {
  std::vector<double> valuesSi;  ///< per file level (empty when the file gives none)
  std::string units;             ///< of valuesSi
  bool upward = true;
};

/// The coordinate's levels: values (SI) and direction, checked finite and strictly monotonic.
Result<Levels> levelsOf(const io::NetcdfFile& f, const GridLayout& l);

/// File level indices, bottom first, for the crop.
Result<std::vector<std::size_t>> levelPicks(const io::NetcdfFile& f, const GridLayout& l, const Levels& lv,
                                            const GridCrop& crop);

/// Heights above the WGS84 ellipsoid of every selected column and level, and how they were made.
struct Heights {
  std::vector<double> h;  ///< nz x ny x nx, above the ellipsoid
  HeightSource source = HeightSource::Coordinate;
  std::string note;
  bool approximate = false;
  std::string fromVariable;  ///< named in errors about the heights
  std::vector<double> levelValues;
  std::string levelUnits;
  /// Terrain-following pressure coordinates: the pressure (Pa) of each level and column, as the
  /// heights were made from (empty for other coordinates).
  std::vector<double> pressurePa;
};

/// The heights of the selection from the variable's vertical coordinate, one function per kind
/// (`useGeoid` false: heights above sea level taken as above the ellipsoid).
Result<Heights> computeHeights(const io::NetcdfFile& f, const GridLayout& l, const Levels& lv, const Selection& s,
                               bool useGeoid);

/// WRF eta levels: the pressure P + PB of each level and column into out.pressurePa, when the
/// heights came from PH/PHB (without them it is there already); other coordinates: nothing.
Status wrfPressure(const io::NetcdfFile& f, const GridLayout& l, const Levels& lv, const Selection& s, Heights& out);

/// Heights must be finite and increase strictly upwards in every column (after float rounding).
Status checkHeights(const io::NetcdfFile& f, const Heights& h, const Selection& s, std::size_t nc);
Status checkHeights(const std::string& label, const Heights& h, const Selection& s, std::size_t nc);

// The pieces of the height rules that need no file, shared by the netCDF and GRIB readers.
// Columns are given by their latitudes (and longitudes), row-major; heights are nz x nc,
// level-major, bottom first.

/// Geopotential heights (gpm) -> geometric heights above mean sea level in place, with each
/// column's WGS84 normal gravity (geometricFromGeopotentialHeightMeters).
void geopotentialToGeometricHeights(const std::vector<double>& latDeg, std::vector<double>& h);
/// Heights above mean sea level from a geopotential field already read and scaled to
/// geopotential metres (`fromGeopotential`: it was m2 s-2, divided by g0); `field` names it,
/// `what` opens the note.
void heightsFromGeopotentialField(const std::vector<double>& latDeg, std::vector<double> gpm, const std::string& field,
                                  bool fromGeopotential, const std::string& what, Heights& out);
/// Heights above mean sea level of pressures (Pa; one per level, or per level and column when
/// `perColumn`) in the standard atmosphere: approximate, said in the note.
void heightsFromStandardAtmosphere(const std::vector<double>& latDeg, std::size_t nz,
                                   const std::vector<double>& pressurePa, bool perColumn, const std::string& what,
                                   Heights& out);
/// Heights above mean sea level -> above the WGS84 ellipsoid: + the EGM96 undulation of each
/// column, or (`useGeoid` false) as they are, said in the note. `label` opens errors.
Status addGeoidUndulation(const std::string& label, const std::vector<double>& latDeg,
                          const std::vector<double>& lonDeg, bool useGeoid, Heights& out);

/// How the heights were made, into a GridVolume or a GridFileInfo (fields of the same names).
template <class Out>
void setHeightFields(const GridLayout& l, const Heights& h, Out& out) {
  out.verticalKind = l.vertical.kind;
  out.heightSource = h.source;
  out.verticalVariable = l.wrf ? h.fromVariable : (l.vertical.coordinate ? l.vertical.coordinate->name : "");
  out.heightNote = h.note;
  out.approximateHeights = h.approximate;
  out.levelValues = h.levelValues;
  out.levelUnits = h.levelUnits;
}

/// readGridVolume with GridReadOptions::ensemble set (GridEnsemble.cpp).
Result<GridVolume> readGridEnsembleStatistic(const std::string& path, const GridReadOptions& options);

}  // namespace atmoglobe::volume::grid
