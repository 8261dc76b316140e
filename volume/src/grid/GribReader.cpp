// GRIB editions 1 and 2 as forecast grids, through ecCodes: the messages of a file's index
// (GribIndex.cpp) grouped into variables (shortName, typeOfLevel), one volume per variable, time
// (validity) and ensemble member, its levels stacked bottom first. Horizontal: regular_ll and
// regular_gg, normalised by the netCDF reader's rectilinear rules (GridHorizontal.cpp); reduced_gg /
// reduced_ll in their own rows (pl; grid::reducedAxes, the volume padded to the longest row:
// GridVolume.h); projected grids (rotated, Lambert, polar stereographic, Mercator) as curvilinear
// grids placed through PROJ (GribProjection.cpp). Heights by the netCDF rules too (GridHeights.cpp:
// geopotential field or standard atmosphere for pressure levels, lengths above ground or sea
// level, + EGM96), and here for the model levels only GRIB names: hybrid levels (the `pv`
// coefficients, the surface pressure, IFS's hydrostatic integration) and ICON/COSMO's generalised
// vertical levels (the half-level heights HHL). Only the messages of the selection and of its
// heights are decoded. Other grid and level types are listed by `info` and refused by the read,
// saying so.
#include "GribInternal.h"
#include "GridInternal.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/CfTime.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <eccodes.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

namespace atmoglobe::volume::grib {

namespace {

/// What ecCodes is told to put at bitmap-masked points, then turned into NaN: far beyond any
/// physical value a GRIB field holds (the largest float, as cfgrib uses).
constexpr double kMissingSentinel = 3.4028234663852886e38;

/// The most points one message may have: 2.5 x the 6.5 million of a global 0.1 degree grid
/// (ERA5-Land, IFS HRES), 128 MB per field in double; a read holds several such arrays (values,
/// latitudes, longitudes and their kept copies) at once.
constexpr std::size_t kMaxGridPoints = 16'000'000;

/// A variable: the messages sharing shortName and typeOfLevel.
struct Variable {
  std::string shortName, typeOfLevel, gridType, name, units;
  std::vector<std::size_t> messages;            ///< indices into the index, file order
  std::vector<double> levels;                   ///< distinct `level` values, bottom first
  std::vector<std::pair<long, long>> validity;  ///< distinct (validityDate, validityTime), ascending
  std::vector<long> members;                    ///< distinct `number`, ascending ({-1}: none)
  std::vector<std::string> steps;
  long ni = 0, nj = 0, points = 0;
  std::string notReadable;  ///< "" when the read handles it
  std::string key() const { return shortName + ":" + typeOfLevel; }
};

bool isPressureType(const std::string& t) { return t == "isobaricInhPa" || t == "isobaricInPa"; }
bool isGeneralVertical(const std::string& t) { return t == "generalVertical" || t == "generalVerticalLayer"; }
/// Levels numbered from the top (model levels: 1 = the highest), so bottom first is descending.
bool isModelLevelType(const std::string& t) { return t == "hybrid" || isGeneralVertical(t); }

/// Reduced grids: rows of different lengths (the pl array), each equally spaced in longitude.
bool isReduced(const std::string& gridType) { return gridType == "reduced_gg" || gridType == "reduced_ll"; }

/// The level type's factor to SI (Pa or m; 1 for model level numbers), or 0 when the read does
/// not handle it.
double levelToSi(const std::string& t) {
  if (t == "isobaricInhPa") return 100.0;
  if (t == "isobaricInPa") return 1.0;
  if (t == "heightAboveGround" || t == "heightAboveSea" || t == "surface" || t == "meanSea") return 1.0;
  if (isModelLevelType(t)) return 1.0;
  return 0.0;
}

/// IFS's constants of the geopotential on model levels (IFS documentation Part III, dynamics;
/// ECMWF's compute_geopotential_on_ml.py): the gas constant of dry air (J kg-1 K-1) and
/// Rv / Rd - 1 of the virtual temperature Tv = T (1 + 0.609133 q).
constexpr double kDryAirGasConstant = 287.06;
constexpr double kVirtualTemperatureFactor = 0.609133;
/// The surface pressure taken for hybrid levels when the file has none (Pa): the standard
/// atmosphere's sea-level pressure, said in the height note.
constexpr double kStandardSurfacePressurePa = 101325.0;

/// The units of GridVolume::levelValues for model levels: their numbers, 1 = top.
constexpr const char* kModelLevelUnits = "model level (1 = top)";

std::string iso(long date, long time) {
  char buf[128];  // room for any long: the compiler checks the worst case
  std::snprintf(buf, sizeof buf, "%04ld-%02ld-%02ldT%02ld:%02ld:00Z", date / 10000, (date / 100) % 100, date % 100,
                time / 100, time % 100);
  return buf;
}

std::string levelText(double v) { return grid::num(v, v == std::floor(v) ? 0 : 3); }

std::vector<Variable> groupVariables(const GribIndex& idx) {
  std::vector<Variable> vars;
  std::map<std::string, std::size_t> byKey;
  for (std::size_t i = 0; i < idx.messages.size(); ++i) {
    const GribMessage& m = idx.messages[i];
    const std::string key = m.shortName + ":" + m.typeOfLevel;
    auto [it, added] = byKey.emplace(key, vars.size());
    if (added) {
      Variable v;
      v.shortName = m.shortName;
      v.typeOfLevel = m.typeOfLevel;
      v.gridType = m.gridType;
      v.name = m.name;
      v.units = m.units;
      v.ni = m.ni;
      v.nj = m.nj;
      v.points = m.points;
      vars.push_back(std::move(v));
    }
    Variable& v = vars[it->second];
    v.messages.push_back(i);
    if (m.gridType != v.gridType || m.ni != v.ni || m.nj != v.nj || m.points != v.points)
      v.notReadable = "its messages are on different grids (" + v.gridType + " " + std::to_string(v.ni) + " x " +
                      std::to_string(v.nj) + " and " + m.gridType + " " + std::to_string(m.ni) + " x " +
                      std::to_string(m.nj) + ")";
  }
  bool hasHhl = false;  // ICON/COSMO's half-level heights, for generalVertical(Layer) variables
  for (const Variable& v : vars) hasHhl = hasHhl || (v.shortName == "HHL" && v.typeOfLevel == "generalVertical");
  for (Variable& v : vars) {
    std::set<double> levels;
    std::set<std::pair<long, long>> validity;
    std::set<long> members;
    std::set<std::string> steps;
    for (std::size_t i : v.messages) {
      const GribMessage& m = idx.messages[i];
      levels.insert(m.level);
      validity.insert({m.validityDate, m.validityTime});
      members.insert(m.number);
      steps.insert(m.stepRange);
    }
    v.levels.assign(levels.begin(), levels.end());
    // High pressure and high model level numbers are the bottom.
    if (isPressureType(v.typeOfLevel) || isModelLevelType(v.typeOfLevel))
      std::reverse(v.levels.begin(), v.levels.end());
    v.validity.assign(validity.begin(), validity.end());
    v.members.assign(members.begin(), members.end());
    v.steps.assign(steps.begin(), steps.end());
    std::sort(v.steps.begin(), v.steps.end(), [](const std::string& a, const std::string& b) {
      return a.size() != b.size() ? a.size() < b.size() : a < b;  // 3 before 12
    });
    if (!v.notReadable.empty()) continue;
    if (v.gridType != "regular_ll" && v.gridType != "regular_gg" && !isProjectedGrid(v.gridType) &&
        !isReduced(v.gridType))
      v.notReadable = "GRIB grid type " + v.gridType + " is not read yet";
    // A level type without heights is read when it has one level (a single-level field: cloud top,
    // the whole atmosphere's column ...), placed at mean sea level: a map, not a volume.
    else if (levelToSi(v.typeOfLevel) == 0.0 && v.levels.size() != 1)
      v.notReadable =
          "GRIB level type " + v.typeOfLevel + " with " + std::to_string(v.levels.size()) + " levels is not read yet";
    // IFS gives two surface fields on model level 1: they make the heights of hybrid levels, they
    // are no 3-D fields (z on model level 1 only: a file with z on several model levels holds the
    // geopotential of each).
    else if (v.typeOfLevel == "hybrid" && v.shortName == "lnsp")
      v.notReadable =
          "the log of the surface pressure (IFS gives it on model level 1): it makes the pressures of "
          "the hybrid levels, it is no 3-D field";
    else if (v.typeOfLevel == "hybrid" && v.shortName == "z" && v.levels == std::vector<double>{1})
      v.notReadable =
          "the surface geopotential (IFS gives it on model level 1): it starts the hydrostatic "
          "integration of the hybrid levels, it is no 3-D field";
    else if (isGeneralVertical(v.typeOfLevel) && !hasHhl)
      v.notReadable = "GRIB " + v.typeOfLevel +
                      " levels take their heights from the half-level heights HHL (ICON, COSMO), and the file has "
                      "no HHL on generalVertical levels";
    else if (isReduced(v.gridType) && (v.nj < 1 || v.points < 1))
      v.notReadable = "GRIB reduced grid without rows (Nj) or points";
    else if (!isReduced(v.gridType) && (v.ni < 1 || v.nj < 1)) v.notReadable = "GRIB grid without Ni x Nj points";
  }
  return vars;
}

std::string formatOf(const GribIndex& idx) {
  std::set<long> editions;
  for (const GribMessage& m : idx.messages) editions.insert(m.edition);
  std::string s = editions.size() == 1 ? "GRIB edition " : "GRIB editions ";
  bool first = true;
  for (long e : editions) {
    if (!first) s += " and ";
    s += std::to_string(e);
    first = false;
  }
  if (idx.compression != "none") s += " (" + idx.compression + ")";
  if (idx.files.size() > 1) s += ", " + std::to_string(idx.files.size()) + " files";
  return s;
}

/// The file's messages, decoded on demand, each at most once per read.
struct Context {
  const GribIndex& idx;
  GribContent content;
  std::vector<Variable> vars;
  std::string label;  ///< the file, for messages
};

/// Which vertical grid a message of model levels is on: hybrid levels carry their coefficients
/// (`pv`), generalised vertical levels (ICON, COSMO) the number and UUID of their grid
/// (numberOfVGridUsed, uuidOfVGrid; ecCodes reads the same bytes so, not as `pv`).
struct VerticalGrid {
  std::vector<double> pv;  ///< empty: PVPresent = 0
  std::string uuid;        ///< "grid N, uuid HEX"; empty for hybrid levels
  bool empty() const { return pv.empty() && uuid.empty(); }
  bool operator==(const VerticalGrid& o) const { return pv == o.pv && uuid == o.uuid; }
  bool operator!=(const VerticalGrid& o) const { return !(*this == o); }
  std::string text() const { return uuid.empty() ? "pv array of " + std::to_string(pv.size()) + " values" : uuid; }
};

/// One message decoded: its grid's axes (file rows and columns) and, when asked, its values.
struct Decoded {
  long ni = 0, nj = 0;
  bool jConsecutive = false;
  std::vector<double> latRows, lonCols;  ///< per file row / column (latitude/longitude grids)
  /// A projected grid: its points, row-major in file rows and columns (GribProjection.cpp).
  std::optional<ProjectedGrid> projected;
  // Reduced grids (axes): the points of each file row, every point's latitude and longitude
  // (message order).
  std::vector<long> pl;
  std::vector<double> pointLat, pointLon;
  std::vector<double> values;     ///< file order; NaN at missing points
  VerticalGrid vertical;          ///< when asked
  long bottomLevel = -1;          ///< key bottomLevel (when asked): a layer's lower surface
  bool uvRelativeToGrid = false;  ///< key uvRelativeToGrid: vector components along the grid's axes
  std::size_t at(std::size_t row, std::size_t col) const {
    return jConsecutive ? col * static_cast<std::size_t>(nj) + row : row * static_cast<std::size_t>(ni) + col;
  }
};

Error varError(const Context& c, const Variable& v, const std::string& what) {
  return makeError(c.label + ": variable " + v.key() + ": " + what);
}

/// `wantVertical`: its vertical grid and bottomLevel too (model levels). Without the guard of
/// ecCodes' internal checks (decode, below).
Result<Decoded> decodeUnguarded(Context& c, const Variable& v, const GribMessage& m, bool wantAxes, bool wantValues,
                                bool wantVertical) {
  auto bytes = c.content.read(m);
  if (!bytes) return bytes.forwardError();
  const std::lock_guard<std::mutex> lock(ecCodesLock());
  // A copy: setting missingValue below must not touch the bytes kept for another decode.
  std::unique_ptr<codes_handle, decltype(&codes_handle_delete)> h(
      codes_handle_new_from_message_copy(nullptr, (*bytes)->data(), (*bytes)->size()), &codes_handle_delete);
  const std::string where = "message at byte " + std::to_string(m.offset);
  if (!h) return varError(c, v, where + ": ecCodes cannot decode it");
  Decoded d;
  long jc = 0, alt = 0;
  const bool reduced = isReduced(v.gridType);
  codes_get_long(h.get(), "Ni", &d.ni);
  codes_get_long(h.get(), "Nj", &d.nj);
  codes_get_long(h.get(), "jPointsAreConsecutive", &jc);
  codes_get_long(h.get(), "alternativeRowScanning", &alt);
  long uvRelative = 0;
  if (codes_get_long(h.get(), "uvRelativeToGrid", &uvRelative) == CODES_SUCCESS) d.uvRelativeToGrid = uvRelative != 0;
  d.jConsecutive = jc != 0;
  if (alt != 0) return varError(c, v, where + ": alternative row scanning is not read yet");
  std::size_t n = 0;
  std::string gridText;
  if (reduced) {
    // Rows of pl[r] points each, one after the other (points along a row consecutive).
    if (d.jConsecutive) return varError(c, v, where + ": a reduced grid with consecutive points along meridians");
    long points = 0;
    codes_get_long(h.get(), "numberOfPoints", &points);
    if (d.nj != m.nj || d.nj < 1 || points != m.points || points < 1)
      return varError(c, v, where + ": its grid is not the index's (the file changed since it was indexed)");
    n = static_cast<std::size_t>(points);
    gridText = std::to_string(d.nj) + " rows of " + std::to_string(n) + " points";
    if (wantAxes) {
      std::size_t size = 0;
      if (codes_get_size(h.get(), "pl", &size) != CODES_SUCCESS || size != static_cast<std::size_t>(d.nj))
        return varError(c, v,
                        where + ": a reduced grid needs pl, the points of each of its " + std::to_string(d.nj) +
                            " rows (has " + std::to_string(size) + ")");
      d.pl.resize(size);
      if (int err = codes_get_long_array(h.get(), "pl", d.pl.data(), &size); err != CODES_SUCCESS)
        return varError(c, v, where + ": pl: " + codes_get_error_message(err));
      // Before ecCodes computes positions from it: pl must count the message's points.
      long long total = 0;
      for (std::size_t r = 0; r < d.pl.size(); ++r) {
        if (d.pl[r] < 0)
          return varError(c, v,
                          where + ": pl[" + std::to_string(r) + "] = " + std::to_string(d.pl[r]) + " is negative");
        total += d.pl[r];
      }
      if (total != static_cast<long long>(n))
        return varError(c, v,
                        where + ": the reduced grid's pl counts " + std::to_string(total) + " points in its " +
                            std::to_string(d.nj) + " rows, the message has " + std::to_string(n) +
                            " (pl inconsistent with the values, or a sub-area whose pl counts whole circles: not "
                            "read yet)");
    }
  } else {
    if (d.ni != m.ni || d.nj != m.nj || d.ni < 1 || d.nj < 1)
      return varError(c, v, where + ": its grid is not the index's (the file changed since it was indexed)");
    n = static_cast<std::size_t>(d.ni) * static_cast<std::size_t>(d.nj);
    gridText = std::to_string(d.ni) + " x " + std::to_string(d.nj) + " points";
    long dataPoints = 0;
    codes_get_long(h.get(), "numberOfDataPoints", &dataPoints);
    if (dataPoints < 0 || static_cast<std::size_t>(dataPoints) != n)
      return varError(c, v,
                      where + ": its grid has " + gridText + ", its data " + std::to_string(dataPoints) +
                          " points (numberOfDataPoints): a damaged message");
  }
  // Before anything the size of the grid is allocated: a message of constant values (0 bits per
  // value) declares any number of points in a few bytes.
  if (n > kMaxGridPoints)
    return varError(c, v,
                    where + ": a grid of " + std::to_string(n) + " points (" + gridText + ") is beyond the " +
                        std::to_string(kMaxGridPoints) + " points one message may have here");
  // Gaussian grids: ecCodes' iterator (latitudes, longitudes) writes out of bounds when the first
  // or last latitude lies outside the N Gaussian latitudes (a damaged message: found by fuzz_grib
  // with N = 1000 and a first latitude of 90). The outermost Gaussian latitude is about
  // 90 - 0.069 * 1000 / N deg; half an N-th of 45 deg lies between it and the pole.
  if (v.gridType == "regular_gg" || v.gridType == "reduced_gg") {
    long gaussN = 0;
    double latFirst = 0.0, latLast = 0.0;
    codes_get_long(h.get(), "N", &gaussN);
    codes_get_double(h.get(), "latitudeOfFirstGridPointInDegrees", &latFirst);
    codes_get_double(h.get(), "latitudeOfLastGridPointInDegrees", &latLast);
    const double limit = gaussN > 0 ? 90.0 - 22.5 / static_cast<double>(gaussN) : 0.0;
    if (gaussN < 1 || d.nj > 2 * gaussN || !(std::abs(latFirst) <= limit) || !(std::abs(latLast) <= limit))
      return varError(c, v,
                      where + ": a Gaussian grid of N = " + std::to_string(gaussN) + " with " + std::to_string(d.nj) +
                          " rows from latitude " + std::to_string(latFirst) + " to " + std::to_string(latLast) +
                          ": outside its Gaussian latitudes (a damaged message)");
  }
  auto array = [&](const char* key, std::vector<double>& out) -> Status {
    std::size_t size = 0;
    int err = codes_get_size(h.get(), key, &size);
    if (err == CODES_SUCCESS && size != n)
      return varError(c, v, where + ": " + std::to_string(size) + " " + key + " for " + gridText);
    out.resize(n);
    if (err == CODES_SUCCESS) err = codes_get_double_array(h.get(), key, out.data(), &size);
    if (err != CODES_SUCCESS) return varError(c, v, where + ": " + key + ": " + codes_get_error_message(err));
    return Ok{};
  };
  if (wantAxes && reduced) {
    if (auto st = array("latitudes", d.pointLat); !st) return st.forwardError();
    if (auto st = array("longitudes", d.pointLon); !st) return st.forwardError();
  } else if (wantAxes && isProjectedGrid(v.gridType)) {
    auto p = projectedGrid(h.get(), v.gridType, d.ni, d.nj, c.label + ": variable " + v.key() + ": " + where);
    if (!p) return p.forwardError();
    d.projected = std::move(*p);
  } else if (wantAxes) {
    std::vector<double> lat, lon;
    if (auto st = array("latitudes", lat); !st) return st.forwardError();
    if (auto st = array("longitudes", lon); !st) return st.forwardError();
    const std::size_t ni = static_cast<std::size_t>(d.ni), nj = static_cast<std::size_t>(d.nj);
    for (std::size_t r = 0; r < nj; ++r) d.latRows.push_back(lat[d.at(r, 0)]);
    for (std::size_t col = 0; col < ni; ++col) d.lonCols.push_back(lon[d.at(0, col)]);
  }
  if (wantVertical) {
    long pvPresent = 0;
    codes_get_long(h.get(), "PVPresent", &pvPresent);
    std::size_t size = 0;
    if (pvPresent && codes_get_size(h.get(), "pv", &size) == CODES_SUCCESS && size > 0) {
      std::vector<double>& pv = d.vertical.pv;
      pv.resize(size);
      if (const int err = codes_get_double_array(h.get(), "pv", pv.data(), &size); err != CODES_SUCCESS)
        return varError(c, v, where + ": pv: " + codes_get_error_message(err));
      pv.resize(size);
    }
    char uuid[128];
    std::size_t uuidLength = sizeof uuid;
    long grid = 0;
    if (codes_get_string(h.get(), "uuidOfVGrid", uuid, &uuidLength) == CODES_SUCCESS &&
        codes_get_long(h.get(), "numberOfVGridUsed", &grid) == CODES_SUCCESS)
      d.vertical.uuid = "vertical grid " + std::to_string(grid) + ", uuid " + std::string(uuid);
    codes_get_long(h.get(), "bottomLevel", &d.bottomLevel);
  }
  if (wantValues) {
    long bitmap = 0;
    codes_get_long(h.get(), "bitmapPresent", &bitmap);
    if (bitmap) codes_set_double(h.get(), "missingValue", kMissingSentinel);
    if (auto st = array("values", d.values); !st) return st.forwardError();
    if (bitmap)
      for (double& x : d.values)
        if (x == kMissingSentinel) x = std::numeric_limits<double>::quiet_NaN();
  }
  return d;
}

/// decodeUnguarded; a failed check inside ecCodes (EcCodesCheckFailed) is an error naming the
/// message instead of the end of the process.
Result<Decoded> decode(Context& c, const Variable& v, const GribMessage& m, bool wantAxes, bool wantValues,
                       bool wantVertical = false) {
  try {
    return decodeUnguarded(c, v, m, wantAxes, wantValues, wantVertical);
  } catch (const EcCodesCheckFailed& e) {
    return varError(c, v,
                    "message at byte " + std::to_string(m.offset) + ": ecCodes failed an internal check on it (" +
                        e.what() + "); the message is damaged");
  }
}

/// The messages of `v` at validity `t`, member `member`, one per level of `levels` (indices into
/// v.levels); several at one level (forecasts from different runs valid at once): the shortest
/// step. Error naming what is missing.
Result<std::vector<const GribMessage*>> pick(const Context& c, const Variable& v, std::size_t t, long member,
                                             const std::vector<std::size_t>& levels) {
  std::vector<const GribMessage*> out(levels.size(), nullptr);
  for (std::size_t i : v.messages) {
    const GribMessage& m = c.idx.messages[i];
    if (m.number != member || std::make_pair(m.validityDate, m.validityTime) != v.validity[t]) continue;
    for (std::size_t k = 0; k < levels.size(); ++k)
      if (m.level == v.levels[levels[k]] && (!out[k] || m.endStep < out[k]->endStep)) out[k] = &m;
  }
  for (std::size_t k = 0; k < levels.size(); ++k)
    if (!out[k])
      return varError(c, v,
                      "no message at level " + levelText(v.levels[levels[k]]) + " (" + v.typeOfLevel + ") valid at " +
                          iso(v.validity[t].first, v.validity[t].second) +
                          (member >= 0 ? " for member " + std::to_string(member) : std::string()));
  return out;
}

/// The variable a height rule takes from the file (geopotential, orography, surface pressure,
/// temperature ...): `shortName` on `typeOfLevel`, on the grid of `like` (same grid type and
/// size, so that its columns are those of `like`), or nullptr. `anyReadability`: also one the read
/// does not take as a volume (lnsp and z on model level 1).
const Variable* findVar(const Context& c, const std::string& shortName, const std::string& typeOfLevel,
                        const Variable& like, bool anyReadability = false) {
  for (const Variable& v : c.vars)
    if (v.shortName == shortName && v.typeOfLevel == typeOfLevel && (anyReadability || v.notReadable.empty()) &&
        v.gridType == like.gridType && v.ni == like.ni && v.nj == like.nj && v.points == like.points)
      return &v;
  return nullptr;
}

/// Where a field `g` feeding the heights of `v` (validity index t, member) is read: at the same
/// validity and member when `g` has them (`exact`), else at its first ones (fields given once,
/// such as the orography).
struct FieldTime {
  std::size_t t = 0;
  long member = -1;
  bool exact = false;
};
FieldTime fieldTime(const Variable& g, const Variable& v, std::size_t t, long member) {
  FieldTime ft;
  const auto at = std::find(g.validity.begin(), g.validity.end(), v.validity[t]);
  if (at != g.validity.end()) ft.t = static_cast<std::size_t>(at - g.validity.begin());
  const bool hasMember = std::find(g.members.begin(), g.members.end(), member) != g.members.end();
  ft.member = hasMember ? member : g.members.front();
  ft.exact = at != g.validity.end() && hasMember;
  return ft;
}

/// The index of level value `level` in g.levels, or nullopt.
std::optional<std::size_t> levelIndex(const Variable& g, double level) {
  const auto at = std::find(g.levels.begin(), g.levels.end(), level);
  if (at == g.levels.end()) return std::nullopt;
  return static_cast<std::size_t>(at - g.levels.begin());
}

/// What a read (or describe's sample) produces.
struct Selected {
  std::vector<double> latRows, lonCols;    ///< the file's axes (rectilinear)
  std::optional<ProjectedGrid> projected;  ///< the file's points (projected grids)
  grid::Horizontal hz;                     ///< the kept rows and columns (reduced: red.hz)
  bool reduced = false;
  grid::ReducedHorizontal red;  ///< a reduced grid's kept rows and points
  // A reduced grid's file axes: the points of each row, every point's latitude and longitude.
  std::vector<long> pl;
  std::vector<double> pointLat, pointLon;
  /// Every output column's latitude and longitude: rectilinear hz.rows x hz.cols, row-major; a
  /// reduced grid's kept points, packed (red.points).
  std::vector<double> colLat, colLon;
  std::vector<std::size_t> levels;  ///< indices into Variable::levels, bottom first
  VerticalGrid vertical;            ///< model levels: the vertical grid of the first message read
  long bottomLevel = -1;            ///< model levels: bottomLevel of that message
  std::uint64_t firstOffset = 0;    ///< that message's byte offset, for errors
  bool uvRelativeToGrid = false;    ///< the axes message's key uvRelativeToGrid
  grid::Heights heights;
  std::vector<float> values;  ///< nz x columns (empty unless asked)
  std::size_t columns() const { return colLat.size(); }
  /// Column c in messages: its file row and column (reduced: its point in the message).
  std::string columnName(std::size_t col) const {
    if (reduced)
      return "row " + std::to_string(hz.rows[red.pointRow[col]]) + " (latitude " + grid::num(colLat[col]) +
             "), point " + std::to_string(red.points[col]) + " of the message";
    const std::size_t nx = hz.cols.size();
    return "row " + std::to_string(hz.rows[col / nx]) + ", column " + std::to_string(hz.cols[col % nx]);
  }
};

/// The values of `msgs` at the selected columns, level-major (nz x columns). `sameGrid`: a message
/// of model levels must be on this vertical grid (a message that names none passes: sp, orog).
Result<std::vector<double>> columnValues(Context& c, const Variable& v, const std::vector<const GribMessage*>& msgs,
                                         const Selected& s, const VerticalGrid* sameGrid = nullptr) {
  std::vector<double> out;
  out.reserve(msgs.size() * s.columns());
  for (const GribMessage* m : msgs) {
    auto d = decode(c, v, *m, false, true, sameGrid != nullptr);
    if (!d) return d.forwardError();
    if (sameGrid && !d->vertical.empty() && d->vertical != *sameGrid)
      return varError(c, v,
                      "message at byte " + std::to_string(m->offset) + " (level " + levelText(m->level) +
                          ") is on another vertical grid than the levels read (its " + d->vertical.text() + ", not " +
                          sameGrid->text() + ")");
    if (s.reduced) {
      for (std::size_t p : s.red.points) out.push_back(d->values[p]);  // p < numberOfPoints: decode checked
      continue;
    }
    for (std::size_t r : s.hz.rows)
      for (std::size_t col : s.hz.cols) out.push_back(d->values[d->at(r, col)]);
  }
  return out;
}

/// Geopotential (m2 s-2) of an altitude above mean sea level (m) at latitude `latDeg`: the
/// inverse of geometricFromGeopotentialHeightMeters by fixed-point steps (dz/dH = g0 / gamma
/// within 0.3 % of 1: each step shrinks the error 300-fold; three reach far below 1 mm).
double geopotentialOfAltitude(double altitudeMeters, double latDeg) {
  const GeopotentialToGeometric toAltitude(latDeg);
  double h = altitudeMeters;
  for (int i = 0; i < 3; ++i) h -= toAltitude(h) - altitudeMeters;
  return h * kStandardGravity;
}

std::string joinText(const std::vector<std::string>& parts, const std::string& last) {
  std::string s;
  for (std::size_t i = 0; i < parts.size(); ++i)
    s.append(i == 0 ? "" : (i + 1 == parts.size() ? last : ", ")).append(parts[i]);
  return s;
}

/// GRIB hybrid (model) levels, IFS's rule (docs/grids.md, "GRIB"; REFERENCE: IFS documentation
/// Part III): `pv` = the half-level coefficients a (Pa) then b, NLEV + 1 each; model level k
/// (1 = top .. NLEV = bottom) lies between half levels k - 1/2 and k + 1/2 (pv index k - 1 and k),
/// p(k+1/2) = a(k+1/2) + b(k+1/2) ps, and its pressure is the mean of the two. ps: `sp` on the
/// surface or exp(`lnsp`) on model level 1, at the same validity and member. Heights: with ps,
/// the surface geopotential (z on model level 1 or on the surface, or orog) and t on every model
/// level from NLEV up to the highest read (q too when it is there), the geopotential of each
/// full level by hydrostatic integration upward from the surface as IFS does it; else the
/// standard atmosphere of the pressures (ps = 101325 Pa without one), approximate, the note
/// saying what was missing.
Status hybridHeights(Context& c, const Variable& v, std::size_t t, long member, bool useGeoid,
                     const std::vector<double>& lat, const std::vector<double>& lon, Selected& s) {
  const std::size_t nc = s.columns(), nz = s.levels.size();
  grid::Heights& out = s.heights;
  const std::vector<double>& pv = s.vertical.pv;
  const std::string where = "message at byte " + std::to_string(s.firstOffset);
  if (pv.empty())
    return varError(c, v, where + ": no pv array (PVPresent = 0): the coefficients of the hybrid levels are missing");
  if (pv.size() < 4 || pv.size() % 2 != 0)
    return varError(c, v,
                    where + ": its pv array has " + std::to_string(pv.size()) +
                        " values; hybrid levels need a and b at NLEV + 1 half levels: 2 (NLEV + 1) values");
  const std::size_t nlev = pv.size() / 2 - 1;
  for (std::size_t i = 0; i < pv.size(); ++i)
    if (!std::isfinite(pv[i])) return varError(c, v, where + ": pv value " + std::to_string(i) + " is not finite");
  // Half level i (0 = the top, nlev = the surface) at surface pressure ps (Pa).
  auto half = [&](std::size_t i, double ps) { return pv[i] + pv[nlev + 1 + i] * ps; };
  std::vector<std::size_t> modelLevel(nz);  // bottom first: descending
  for (std::size_t k = 0; k < nz; ++k) {
    const double l = v.levels[s.levels[k]];
    if (l != std::floor(l) || l < 1 || l > static_cast<double>(nlev))
      return varError(c, v,
                      "model level " + levelText(l) + " is not one of the levels 1 .. " + std::to_string(nlev) +
                          " that its pv array (" + std::to_string(pv.size()) + " values) defines");
    modelLevel[k] = static_cast<std::size_t>(l);
  }
  const std::size_t top = modelLevel.back();
  const std::string when = iso(v.validity[t].first, v.validity[t].second) +
                           (member >= 0 ? " for member " + std::to_string(member) : std::string());

  // The surface pressure (Pa) per column: sp on the surface, else exp(lnsp) on model level 1.
  std::vector<double> ps;
  std::string psFrom;
  if (const Variable* g = findVar(c, "sp", "surface", v); g && fieldTime(*g, v, t, member).exact) {
    auto msgs = pick(c, *g, fieldTime(*g, v, t, member).t, member, {0});
    if (!msgs) return msgs.forwardError();
    auto values = columnValues(c, *g, *msgs, s);
    if (!values) return values.forwardError();
    for (std::size_t col = 0; col < nc; ++col)
      if (!std::isfinite((*values)[col]) || !((*values)[col] > 0))
        return varError(c, *g, "surface pressure missing or not positive at " + s.columnName(col));
    ps = std::move(*values);
    psFrom = "'" + g->key() + "'";
  } else if (const Variable* l = findVar(c, "lnsp", "hybrid", v, true); l && fieldTime(*l, v, t, member).exact) {
    if (auto at = levelIndex(*l, 1)) {
      auto msgs = pick(c, *l, fieldTime(*l, v, t, member).t, member, {*at});
      if (!msgs) return msgs.forwardError();
      auto values = columnValues(c, *l, *msgs, s, &s.vertical);
      if (!values) return values.forwardError();
      for (std::size_t col = 0; col < nc; ++col) {
        const double x = (*values)[col];
        if (!std::isfinite(x) || !std::isfinite(std::exp(x)))
          return varError(c, *l,
                          "log of the surface pressure missing or not finite at " + s.columnName(col) +
                              " (model level 1, valid at " + when + ")");
      }
      for (double& x : *values) x = std::exp(x);
      ps = std::move(*values);
      psFrom = "exp('" + l->key() + "' on model level 1)";
    }
  }
  const bool havePs = !ps.empty();

  // The pressure of each level read (Pa, nz x nc); half levels must increase downwards.
  std::vector<double> p(nz * nc);
  auto checkHalves = [&](std::size_t level, double above, double below, std::size_t col) -> Status {
    if (above >= 0 && below > above) return Ok{};
    return varError(c, v,
                    "the half-level pressures a + b ps of its pv array do not increase downwards at model level " +
                        std::to_string(level) + " (" + grid::num(above, 3) + " Pa above, " + grid::num(below, 3) +
                        " Pa below, at " + s.columnName(col) + ")");
  };
  for (std::size_t col = 0; col < nc; ++col) {
    const double surface = havePs ? ps[col] : kStandardSurfacePressurePa;
    for (std::size_t k = 0; k < nz; ++k) {
      const double above = half(modelLevel[k] - 1, surface), below = half(modelLevel[k], surface);
      if (auto st = checkHalves(modelLevel[k], above, below, col); !st) return st;
      p[k * nc + col] = 0.5 * (above + below);
    }
  }
  const std::string what = "hybrid model levels (GRIB hybrid, " + std::to_string(nlev) +
                           " levels from pv): p = (p(k-1/2) + p(k+1/2)) / 2, p(k+1/2) = a + b ps with ps = " +
                           (havePs ? psFrom : std::string("101325 Pa (standard sea-level pressure)"));

  // What the hydrostatic integration needs: ps, t on model levels nlev .. top, the surface geopotential.
  std::vector<std::string> missing;
  if (!havePs) missing.push_back("a surface pressure (sp on the surface or lnsp on model level 1) valid at " + when);
  // The message of `g` on each model level from the bottom (nlev) up to `top`, at this validity
  // and member, or nullopt (with how many of those levels `g` has) when one is missing.
  auto fromBottom = [&](const Variable* g, std::size_t* have) -> std::optional<std::vector<const GribMessage*>> {
    *have = 0;
    if (!g || !fieldTime(*g, v, t, member).exact) return std::nullopt;
    std::vector<std::size_t> idx;
    for (std::size_t l = nlev; l >= top; --l)
      if (auto at = levelIndex(*g, static_cast<double>(l))) idx.push_back(*at);
    *have = idx.size();
    if (idx.size() != nlev - top + 1) return std::nullopt;
    auto msgs = pick(c, *g, fieldTime(*g, v, t, member).t, member, idx);
    if (!msgs) return std::nullopt;
    return *msgs;
  };
  const Variable* tVar = findVar(c, "t", "hybrid", v);
  std::size_t tHave = 0;
  const auto tMsgs = fromBottom(tVar, &tHave);
  if (!tMsgs)
    missing.push_back("t on every model level from " + std::to_string(nlev) + " (the bottom) up to " +
                      std::to_string(top) + " valid at " + when + " (it has " + std::to_string(tHave) + " of those " +
                      std::to_string(nlev - top + 1) + ")");
  // The surface geopotential: z on model level 1 (IFS), z on the surface, or orog (m).
  const Variable* surfaceZ = nullptr;
  for (const auto& [name, type] :
       {std::pair<const char*, const char*>{"z", "hybrid"}, {"z", "surface"}, {"orog", "surface"}}) {
    const Variable* g = findVar(c, name, type, v, true);
    if (g && (std::string(type) == "surface" || g->levels == std::vector<double>{1})) {
      surfaceZ = g;
      break;
    }
  }
  if (!surfaceZ) missing.push_back("the surface geopotential (z on model level 1 or on the surface, or orog)");
  if (!missing.empty()) {
    grid::heightsFromStandardAtmosphere(lat, nz, p, true, what, out);
    out.note = what +
               "; heights: the standard-atmosphere height of each pressure (APPROXIMATE: not integrated "
               "hydrostatically, the file lacks " +
               joinText(missing, " and ") + ") -> geometric height above mean sea level";
    if (havePs) out.pressurePa = p;
    return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
  }

  // The surface geopotential (m2 s-2) per column.
  const FieldTime zt = fieldTime(*surfaceZ, v, t, member);
  auto zMsgs = pick(c, *surfaceZ, zt.t, zt.member, {0});
  if (!zMsgs) return zMsgs.forwardError();
  auto phiHalf = columnValues(c, *surfaceZ, *zMsgs, s);
  if (!phiHalf) return phiHalf.forwardError();
  const bool orog = surfaceZ->shortName == "orog";
  for (std::size_t col = 0; col < nc; ++col) {
    double& x = (*phiHalf)[col];
    if (!std::isfinite(x)) return varError(c, *surfaceZ, "surface altitude missing at " + s.columnName(col));
    if (orog) x = geopotentialOfAltitude(x, lat[col]);
  }
  std::size_t qHave = 0;
  const Variable* qVar = findVar(c, "q", "hybrid", v);
  const auto qMsgs = fromBottom(qVar, &qHave);

  // Upward from the surface (IFS): at model level k, with Rd Tv(k),
  //   phi(k) = phi(k+1/2) + alpha(k) Rd Tv(k),  phi(k-1/2) = phi(k+1/2) + Rd Tv(k) ln(p(k+1/2) / p(k-1/2)),
  //   alpha(k) = 1 - p(k-1/2) / (p(k+1/2) - p(k-1/2)) ln(p(k+1/2) / p(k-1/2)), ln 2 where p(k-1/2) = 0 (the top).
  // One level's t and q at a time: their messages are decoded once and dropped.
  out.h.assign(nz * nc, std::numeric_limits<double>::quiet_NaN());
  std::size_t next = 0;  // the next level read, counted from the bottom
  for (std::size_t i = 0; i < tMsgs->size(); ++i) {
    const std::size_t level = nlev - i;
    auto temperature = columnValues(c, *tVar, {(*tMsgs)[i]}, s, &s.vertical);
    if (!temperature) return temperature.forwardError();
    c.content.forget(*(*tMsgs)[i]);
    std::vector<double> humidity;
    if (qMsgs) {
      auto q = columnValues(c, *qVar, {(*qMsgs)[i]}, s, &s.vertical);
      if (!q) return q.forwardError();
      c.content.forget(*(*qMsgs)[i]);
      humidity = std::move(*q);
    }
    const bool wanted = next < nz && modelLevel[next] == level;
    for (std::size_t col = 0; col < nc; ++col) {
      const double temp = (*temperature)[col], q = qMsgs ? humidity[col] : 0.0;
      if (!std::isfinite(temp) || !(temp > 0))
        return varError(
            c, *tVar,
            "temperature missing or not positive at model level " + std::to_string(level) + ", " + s.columnName(col));
      if (!std::isfinite(q))
        return varError(c, *qVar,
                        "humidity missing at model level " + std::to_string(level) + ", " + s.columnName(col));
      const double above = half(level - 1, ps[col]), below = half(level, ps[col]);
      if (auto st = checkHalves(level, above, below, col); !st) return st;
      const double rdTv = kDryAirGasConstant * temp * (1.0 + kVirtualTemperatureFactor * q);
      const double dlogP = above > 0 ? std::log(below / above) : 0.0;
      const double alpha = above > 0 ? 1.0 - above / (below - above) * dlogP : std::log(2.0);
      if (wanted) out.h[next * nc + col] = (*phiHalf)[col] + alpha * rdTv;
      (*phiHalf)[col] += rdTv * dlogP;
    }
    if (wanted) ++next;
  }
  for (double& x : out.h) x /= kStandardGravity;  // geopotential height
  grid::geopotentialToGeometricHeights(lat, out.h);
  out.source = HeightSource::HydrostaticIntegration;
  out.fromVariable = tVar->key();
  const std::string zText =
      "'" + surfaceZ->key() + "'" +
      (orog                                ? " (m, as geopotential)"
       : surfaceZ->typeOfLevel == "hybrid" ? " on model level 1"
                                           : "") +
      (zt.exact ? "" : " (valid at " + iso(surfaceZ->validity[zt.t].first, surfaceZ->validity[zt.t].second) + ")");
  const std::string tvText = qMsgs ? "Tv = T (1 + 0.609133 q) of '" + tVar->key() + "' and '" + qVar->key() + "'"
                                   : "Tv = T of '" + tVar->key() +
                                         "' (no q on all those levels: dry air, heights low by "
                                         "up to a few tens of metres in moist air)";
  out.note =
      what +
      "; geopotential by hydrostatic integration (IFS: Rd = 287.06 J kg-1 K-1) upward from the surface geopotential " +
      zText + " with " + tvText + " on model levels " + std::to_string(nlev) + " .. " + std::to_string(top) +
      ", / 9.80665 -> geometric height above mean sea level (WGS84 normal gravity)";
  if (havePs) out.pressurePa = p;
  return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
}

/// GRIB generalVertical / generalVerticalLayer levels (ICON, COSMO): numbered from the top, their
/// heights from the half-level heights `HHL` (geometric, above mean sea level; one more half level
/// than full levels): a generalVertical level's height is HHL's at the same level, a
/// generalVerticalLayer layer k's the mean of HHL's at half levels k and k + 1 (its bottomLevel).
/// HHL at the same validity and member when the file has it there, else its first (models write
/// it once).
Status generalVerticalHeights(Context& c, const Variable& v, std::size_t t, long member, bool useGeoid,
                              const std::vector<double>& lat, const std::vector<double>& lon, Selected& s) {
  const std::size_t nc = s.columns(), nz = s.levels.size();
  grid::Heights& out = s.heights;
  const Variable* hhl = findVar(c, "HHL", "generalVertical", v);
  if (!hhl)
    return varError(c, v,
                    "GRIB " + v.typeOfLevel +
                        " levels take their heights from the half-level heights HHL, and the file has none on this "
                        "grid");
  const bool layer = v.typeOfLevel == "generalVerticalLayer";
  const double firstLevel = v.levels[s.levels.front()];
  if (layer && s.bottomLevel != static_cast<long>(firstLevel) + 1)
    return varError(c, v,
                    "message at byte " + std::to_string(s.firstOffset) + ": layer " + levelText(firstLevel) +
                        " has its bottom at level " + std::to_string(s.bottomLevel) + ", not " +
                        levelText(firstLevel + 1) + ": only layers between half levels k and k + 1 are read");
  const FieldTime ft = fieldTime(*hhl, v, t, member);
  std::vector<std::size_t> idx;  // per level read: its half level(s)
  for (std::size_t k : s.levels) {
    const double l = v.levels[k];
    for (double h : layer ? std::vector<double>{l, l + 1} : std::vector<double>{l}) {
      auto at = levelIndex(*hhl, h);
      if (!at)
        return varError(c, v,
                        "'" + hhl->key() + "' has no half level " + levelText(h) + " (needed for " +
                            (layer ? "layer " : "level ") + levelText(l) + ")");
      idx.push_back(*at);
    }
  }
  auto msgs = pick(c, *hhl, ft.t, ft.member, idx);
  if (!msgs) return msgs.forwardError();
  auto halves = columnValues(c, *hhl, *msgs, s, &s.vertical);
  if (!halves) return halves.forwardError();
  for (std::size_t i = 0; i < halves->size(); ++i)
    if (!std::isfinite((*halves)[i]))
      return varError(
          c, *hhl,
          "half-level height missing at level " + levelText((*msgs)[i / nc]->level) + ", " + s.columnName(i % nc));
  const std::size_t per = layer ? 2 : 1;
  out.h.assign(nz * nc, 0.0);
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t col = 0; col < nc; ++col) {
      double sum = 0;
      for (std::size_t j = 0; j < per; ++j) sum += (*halves)[(k * per + j) * nc + col];
      out.h[k * nc + col] = sum / static_cast<double>(per);
    }
  out.source = HeightSource::HeightField;
  out.fromVariable = hhl->key();
  const std::string hhlText =
      "'" + hhl->key() + "'" +
      (ft.exact ? "" : " (valid at " + iso(hhl->validity[ft.t].first, hhl->validity[ft.t].second) + ")");
  out.note = layer ? "generalised vertical layers (GRIB generalVerticalLayer, ICON/COSMO): layer k at the mean of the "
                     "half-level heights k and k+1 of " +
                         hhlText + " (geometric, above mean sea level)"
                   : "generalised vertical levels (GRIB generalVertical, ICON/COSMO): the half-level heights of " +
                         hhlText + " at the same levels (geometric, above mean sea level)";
  return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
}

/// The heights of the selection by the level type (rules: docs/grids.md, "GRIB").
Status heightsOf(Context& c, const Variable& v, std::size_t t, long member, bool useGeoid, Selected& s) {
  const std::size_t nc = s.columns(), nz = s.levels.size();
  const std::vector<double>& lat = s.colLat;
  const std::vector<double>& lon = s.colLon;
  grid::Heights& out = s.heights;
  const double toSi = levelToSi(v.typeOfLevel);
  out.fromVariable = v.key();
  if (toSi == 0.0) {  // a single-level field of a level type without heights
    for (std::size_t k : s.levels) out.levelValues.push_back(v.levels[k]);
    out.levelUnits = v.typeOfLevel;
    out.h.assign(nz * nc, 0.0);
    out.note = "a single-level field (GRIB " + v.typeOfLevel + ", no height): placed at mean sea level";
    return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
  }
  for (std::size_t k : s.levels) out.levelValues.push_back(v.levels[k] * toSi);
  if (isModelLevelType(v.typeOfLevel)) {
    out.levelUnits = kModelLevelUnits;
    if (v.typeOfLevel == "hybrid") return hybridHeights(c, v, t, member, useGeoid, lat, lon, s);
    return generalVerticalHeights(c, v, t, member, useGeoid, lat, lon, s);
  }
  if (isPressureType(v.typeOfLevel)) {
    out.levelUnits = "Pa";
    const std::string what = "pressure levels (GRIB " + v.typeOfLevel + ")";
    // The geopotential of the same level type, time and member: z (m2 s-2) or gh (gpm).
    for (const char* name : {"z", "gh"}) {
      const Variable* g = findVar(c, name, v.typeOfLevel, v);
      if (!g || std::find(g->validity.begin(), g->validity.end(), v.validity[t]) == g->validity.end() ||
          std::find(g->members.begin(), g->members.end(), member) == g->members.end())
        continue;
      const std::size_t gt = static_cast<std::size_t>(std::find(g->validity.begin(), g->validity.end(), v.validity[t]) -
                                                      g->validity.begin());
      std::vector<std::size_t> gl;
      for (std::size_t k : s.levels) {
        auto at = std::find(g->levels.begin(), g->levels.end(), v.levels[k]);
        if (at == g->levels.end()) break;
        gl.push_back(static_cast<std::size_t>(at - g->levels.begin()));
      }
      if (gl.size() != nz) continue;
      auto msgs = pick(c, *g, gt, member, gl);
      if (!msgs) continue;
      auto values = columnValues(c, *g, *msgs, s);
      if (!values) return values.forwardError();
      const bool geopotential = std::string(name) == "z";
      if (geopotential)
        for (double& x : *values) x /= kStandardGravity;
      grid::heightsFromGeopotentialField(lat, std::move(*values), g->key(), geopotential, what, out);
      return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
    }
    grid::heightsFromStandardAtmosphere(lat, nz, out.levelValues, false, what, out);
    return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
  }
  // Lengths: above ground (surface: 0 m above ground) or above sea level.
  out.levelUnits = "m";
  out.h.assign(nz * nc, 0.0);
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t col = 0; col < nc; ++col) out.h[k * nc + col] = out.levelValues[k];
  if (v.typeOfLevel == "heightAboveSea" || v.typeOfLevel == "meanSea") {
    out.note = v.typeOfLevel == "meanSea" ? "mean sea level (GRIB meanSea: 0 m above mean sea level)"
                                          : "heights above mean sea level (GRIB heightAboveSea)";
    return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
  }
  // The surface altitude: orog (m) or the surface geopotential z (m2 s-2), at this time and member
  // or, failing that, the first such field (orography is often given once).
  const std::string datum = v.typeOfLevel == "surface" ? "the surface (GRIB surface: 0 m above ground)"
                                                       : "heights above ground (GRIB heightAboveGround)";
  for (const char* name : {"orog", "z"}) {
    const Variable* g = findVar(c, name, "surface", v);
    if (!g) continue;
    const FieldTime ft = fieldTime(*g, v, t, member);
    auto msgs = pick(c, *g, ft.t, ft.member, {0});
    if (!msgs) continue;
    auto surf = columnValues(c, *g, *msgs, s);
    if (!surf) return surf.forwardError();
    if (std::string(name) == "z") {
      for (double& x : *surf) x /= kStandardGravity;
      grid::geopotentialToGeometricHeights(lat, *surf);
    }
    for (std::size_t col = 0; col < nc; ++col)
      if (!std::isfinite((*surf)[col])) return varError(c, *g, "surface altitude missing at " + s.columnName(col));
    for (std::size_t k = 0; k < nz; ++k)
      for (std::size_t col = 0; col < nc; ++col) out.h[k * nc + col] += (*surf)[col];
    out.note = datum + " + the surface altitude '" + g->key() + "'" +
               (std::string(name) == "z" ? " (geopotential / 9.80665 -> geometric height)" : "") +
               " -> above mean sea level";
    return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
  }
  out.approximate = true;
  out.note = datum +
             "; the file has no surface altitude (orog or z on the surface), so the ground is taken at sea "
             "level (APPROXIMATE)";
  return grid::addGeoidUndulation(c.label, lat, lon, useGeoid, out);
}

/// The variable named `name` ("t" or "t:isobaricInhPa"; empty: the default). `readable`: only
/// one the read handles (else an error saying why not).
Result<const Variable*> findVariable(const Context& c, const std::string& name, bool readable) {
  const Variable* best = nullptr;
  auto better = [&](const Variable& v) {  // readable first, then the most levels, file order
    if (!best) return true;
    if (best->notReadable.empty() != v.notReadable.empty()) return v.notReadable.empty();
    return v.levels.size() > best->levels.size();
  };
  if (name.empty()) {
    // Default: the readable variable with the most levels, a geopotential (z, gh: the heights of
    // the others) only when there is nothing else, file order among equals.
    for (const Variable& v : c.vars) {
      if (!best) {
        best = &v;
        continue;
      }
      const bool vz = v.shortName == "z" || v.shortName == "gh", bz = best->shortName == "z" || best->shortName == "gh";
      if (best->notReadable.empty() != v.notReadable.empty()) {
        if (v.notReadable.empty()) best = &v;
      } else if (vz != bz) {
        if (!vz) best = &v;
      } else if (v.levels.size() > best->levels.size()) {
        best = &v;
      }
    }
  } else {
    const auto colon = name.find(':');
    for (const Variable& v : c.vars) {
      if (colon == std::string::npos ? v.shortName != name : v.key() != name) continue;
      if (better(v)) best = &v;
    }
    if (!best) {
      std::string list;
      for (const Variable& v : c.vars) list.append(list.empty() ? "" : ", ").append(v.key());
      return makeError(c.label + ": no variable '" + name + "' (grid variables: " + list + ")");
    }
  }
  if (readable && !best->notReadable.empty()) return varError(c, *best, best->notReadable);
  return best;
}

Result<std::size_t> resolveTime(const Context& c, const Variable& v, const GridReadOptions& o) {
  if (!o.timeIso8601.empty()) {
    auto parsed = parseCfTimeUnits("seconds since " + o.timeIso8601, "standard");
    if (!parsed) return makeError(c.label + ": time '" + o.timeIso8601 + "' is not an ISO 8601 date-time");
    for (std::size_t i = 0; i < v.validity.size(); ++i)
      if (iso(v.validity[i].first, v.validity[i].second) == parsed->referenceIso8601) return i;
    return varError(c, v,
                    "no time step at " + parsed->referenceIso8601 + " (the time axis has " +
                        std::to_string(v.validity.size()) +
                        " steps: " + iso(v.validity.front().first, v.validity.front().second) + " .. " +
                        iso(v.validity.back().first, v.validity.back().second) + ")");
  }
  if (o.timeIndex >= v.validity.size())
    return varError(c, v,
                    "time index " + std::to_string(o.timeIndex) + " is beyond its " +
                        std::to_string(v.validity.size()) + " time step" + (v.validity.size() == 1 ? "" : "s"));
  return o.timeIndex;
}

Result<long> resolveMember(const Context& c, const Variable& v, long member) {
  if (member < 0) return v.members.front();
  if (std::find(v.members.begin(), v.members.end(), member) != v.members.end()) return member;
  if (v.members.size() == 1 && v.members.front() < 0)
    return varError(c, v, "has no ensemble members; cannot select member " + std::to_string(member));
  std::string list;
  for (long m : v.members) list.append(list.empty() ? "" : ", ").append(std::to_string(m));
  return varError(c, v, "no ensemble member " + std::to_string(member) + " (members: " + list + ")");
}

/// The columns of `s`'s grid that the crop keeps, every `sample`-th: rectilinear for
/// latitude/longitude grids, curvilinear (a position per point) for projected ones.
Result<grid::Horizontal> horizontalOf(const Context& c, const Variable& v, const Selected& s, const GridCrop& crop,
                                      std::size_t sample) {
  auto error = [&](const std::string& what) { return varError(c, v, what); };
  if (s.projected)
    return grid::curvilinearAxes(s.projected->latDeg, s.projected->lonDeg, static_cast<std::size_t>(v.nj),
                                 static_cast<std::size_t>(v.ni), crop, sample, error, error);
  return grid::rectilinearAxes(s.latRows, s.lonCols, crop, sample, error, error);
}

/// The selection's columns, levels, heights and (`wantValues`) values.
Result<Selected> readSelection(Context& c, const Variable& v, std::size_t t, long member, const GridCrop& crop,
                               std::size_t sample, bool useGeoid, bool wantValues) {
  if (auto st = grid::checkCrop(c.label, crop); !st) return st.forwardError();
  Selected s;
  const std::size_t nLevels = v.levels.size();
  if (crop.firstLevel >= nLevels)
    return varError(c, v,
                    "crop: first level " + std::to_string(crop.firstLevel) + " is beyond its " +
                        std::to_string(nLevels) + " levels");
  for (std::size_t k = crop.firstLevel; k < nLevels && k - crop.firstLevel < crop.levelCount; ++k)
    s.levels.push_back(k);
  auto msgs = pick(c, v, t, member, s.levels);
  if (!msgs) return msgs.forwardError();
  const bool modelLevels = isModelLevelType(v.typeOfLevel);
  auto axes = decode(c, v, *msgs->front(), true, false, modelLevels);
  if (!axes) return axes.forwardError();
  const grid::CoordinateError error = [&](const std::string& what) { return varError(c, v, what); };
  if (isReduced(v.gridType)) {
    s.reduced = true;
    s.pl = std::move(axes->pl);
    s.pointLat = std::move(axes->pointLat);
    s.pointLon = std::move(axes->pointLon);
    auto red = grid::reducedAxes(s.pl, s.pointLat, s.pointLon, crop, sample, error);
    if (!red) return red.forwardError();
    s.red = std::move(*red);
    s.hz = s.red.hz;
    s.colLat = s.red.pointLatDeg;
    s.colLon = s.red.pointLonDeg;
  } else {
    s.latRows = std::move(axes->latRows);
    s.lonCols = std::move(axes->lonCols);
    s.projected = std::move(axes->projected);
    s.uvRelativeToGrid = axes->uvRelativeToGrid;
    auto hz = horizontalOf(c, v, s, crop, sample);
    if (!hz) return hz.forwardError();
    s.hz = std::move(*hz);
    if (s.projected) {  // curvilinear: a position per column already
      s.colLat = s.hz.latDeg;
      s.colLon = s.hz.lonDeg;
    } else {
      for (double la : s.hz.latDeg)
        for (double lo : s.hz.lonDeg) {
          s.colLat.push_back(la);
          s.colLon.push_back(lo);
        }
    }
  }
  s.vertical = std::move(axes->vertical);
  s.bottomLevel = axes->bottomLevel;
  s.firstOffset = msgs->front()->offset;
  if (wantValues) {
    auto values = columnValues(c, v, *msgs, s, modelLevels ? &s.vertical : nullptr);
    if (!values) return values.forwardError();
    s.values.resize(values->size());
    for (std::size_t i = 0; i < values->size(); ++i)
      s.values[i] = static_cast<float>((*values)[i]);  // as netCDF: float
  }
  if (auto st = heightsOf(c, v, t, member, useGeoid, s); !st) return st.forwardError();
  const grid::Selection sel{t, s.levels, &s.hz, {}, [&](std::size_t col) { return s.columnName(col); }};
  if (auto st = grid::checkHeights(c.label, s.heights, sel, s.columns()); !st) return st.forwardError();
  return s;
}

VerticalKind verticalKindOf(const std::string& typeOfLevel) {
  if (isPressureType(typeOfLevel)) return VerticalKind::Pressure;
  if (typeOfLevel == "hybrid") return VerticalKind::HybridSigmaPressure;
  if (isGeneralVertical(typeOfLevel)) return VerticalKind::GeneralVertical;
  if (typeOfLevel == "heightAboveSea" || typeOfLevel == "meanSea") return VerticalKind::HeightAboveSeaLevel;
  return VerticalKind::HeightAboveGround;
}

Result<Context> openContext(const std::string& path, const GribIndex& idx) {
  auto content = GribContent::open(idx);
  if (!content) return content.forwardError();
  return Context{idx, std::move(*content), groupVariables(idx), path};
}

std::vector<std::string> isoTimes(const Variable& v) {
  std::vector<std::string> out;
  for (const auto& [d, t] : v.validity) out.push_back(iso(d, t));
  return out;
}

}  // namespace

Result<GridVolume> readGribVolume(const std::string& path, const GridReadOptions& options) {
  auto idx = gribIndexOf(path);
  if (!idx) return idx.forwardError();
  auto ctx = openContext(path, *idx);
  if (!ctx) return ctx.forwardError();
  Context& c = *ctx;
  auto found = findVariable(c, options.variable, true);
  if (!found) return found.forwardError();
  const Variable& v = **found;
  auto t = resolveTime(c, v, options);
  if (!t) return t.forwardError();
  auto member = resolveMember(c, v, options.member);
  if (!member) return member.forwardError();
  auto s = readSelection(c, v, *t, *member, options.crop, 1, options.useGeoid, true);
  if (!s) return s.forwardError();

  GridVolume g;
  g.path = path;
  g.format = formatOf(*idx);
  g.variable = v.key();
  g.units = v.units;
  g.longName = v.name;
  g.nx = s->hz.cols.size();
  g.ny = s->hz.rows.size();
  g.nz = s->levels.size();
  g.latDeg = std::move(s->hz.latDeg);
  g.lonDeg = std::move(s->hz.lonDeg);
  g.wrapsLongitude = s->hz.wrapsLongitude;
  g.curvilinear = s->projected.has_value();
  if (s->projected) g.projection = s->projected->definition;
  g.vectorsRelativeToGrid = s->uvRelativeToGrid && s->projected.has_value();
  g.fileFirstRow = s->hz.rows.front();
  g.fileFirstColumn = s->hz.cols.empty() ? 0 : s->hz.cols.front();  // reduced: 0 (set below)
  g.fileFirstLevel = s->levels.front();
  g.fileRowStep = s->hz.rowStep;
  g.fileColumnStep = s->hz.colStep;
  g.fileLevelStep = 1;  // levels are indexed bottom first (Variable::levels)
  const grid::Heights& h = s->heights;
  if (s->reduced) {
    // Rows padded to the longest (GridVolume.h): the packed points spread over nx columns.
    const grid::ReducedHorizontal& red = s->red;
    g.nx = red.nx;
    g.fileFirstColumn = 0;
    g.rowLengthPoints = red.rowLength;
    g.rowFirstLonDeg = red.rowFirstLonDeg;
    g.rowSpacingDeg = red.rowSpacingDeg;
    const std::size_t points = s->columns(), plane = g.nx * g.ny;
    g.values.assign(g.nz * plane, std::numeric_limits<float>::quiet_NaN());
    g.heightAboveEllipsoidMeters.assign(g.nz * plane, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t k = 0; k < g.nz; ++k)
      for (std::size_t p = 0, j = 0; j < g.ny; ++j)
        for (std::size_t i = 0; i < red.rowLength[j]; ++i, ++p) {
          g.values[g.index(k, j, i)] = s->values[k * points + p];
          g.heightAboveEllipsoidMeters[g.index(k, j, i)] = static_cast<float>(h.h[k * points + p]);
        }
    if (options.keepPressure && !h.pressurePa.empty()) {
      g.pressurePa.assign(g.nz * plane, std::numeric_limits<float>::quiet_NaN());
      for (std::size_t k = 0; k < g.nz; ++k)
        for (std::size_t p = 0, j = 0; j < g.ny; ++j)
          for (std::size_t i = 0; i < red.rowLength[j]; ++i, ++p)
            g.pressurePa[g.index(k, j, i)] = static_cast<float>(h.pressurePa[k * points + p]);
    }
    if (auto st = finishReducedGrid(g); !st) return varError(c, v, "reduced grid: " + st.error());
  } else {
    g.values = std::move(s->values);
    g.heightAboveEllipsoidMeters.resize(h.h.size());
    for (std::size_t i = 0; i < h.h.size(); ++i)
      g.heightAboveEllipsoidMeters[i] = static_cast<float>(h.h[i]);  // float: see GridVolume.h
    if (options.keepPressure) g.pressurePa.assign(h.pressurePa.begin(), h.pressurePa.end());
  }
  setValueRange(g);
  g.verticalKind = verticalKindOf(v.typeOfLevel);
  g.heightSource = h.source;
  g.verticalVariable = v.typeOfLevel;
  g.heightNote = h.note;
  g.approximateHeights = h.approximate;
  g.levelValues = h.levelValues;
  g.levelUnits = h.levelUnits;
  g.times = isoTimes(v);
  g.timeIndex = *t;
  g.validTime = g.times[*t];
  g.member = *member;
  g.bytesRead = c.content.bytesRead();
  g.gribMessagesRead = c.content.reads();
  return g;
}

Result<GridFileInfo> describeGribFile(const std::string& path, const std::string& variable) {
  auto idx = gribIndexOf(path);
  if (!idx) return idx.forwardError();
  auto ctx = openContext(path, *idx);
  if (!ctx) return ctx.forwardError();
  Context& c = *ctx;
  GridFileInfo info;
  info.path = path;
  info.format = formatOf(*idx);
  info.messageCount = idx->messages.size();
  info.indexFile = idx->cacheFile;
  info.indexReused = idx->fromCache;
  info.warnings = idx->warnings;
  for (const Variable& v : c.vars) {
    GridVariableInfo vi;
    vi.name = v.key();
    vi.shortName = v.shortName;
    vi.levelType = v.typeOfLevel;
    vi.gridType = v.gridType;
    vi.units = v.units;
    vi.longName = v.name;
    vi.levels = v.levels;
    vi.gridNi = static_cast<std::size_t>(std::max(0L, v.ni));
    vi.gridNj = static_cast<std::size_t>(std::max(0L, v.nj));
    vi.gridPoints = static_cast<std::size_t>(std::max(0L, v.points));
    vi.timeCount = v.validity.size();
    vi.memberCount = v.members.front() < 0 ? 0 : v.members.size();
    vi.messageCount = v.messages.size();
    vi.notReadable = v.notReadable;
    vi.onGrid = v.notReadable.empty();
    info.variables.push_back(std::move(vi));
  }
  auto found = findVariable(c, variable, false);
  if (!found) return found.forwardError();
  const Variable& v = **found;
  info.variable = v.key();
  info.times = isoTimes(v);
  info.steps = v.steps;
  for (long m : v.members)
    if (m >= 0) info.members.push_back(m);
  info.nx = static_cast<std::size_t>(std::max(0L, v.ni));
  info.ny = static_cast<std::size_t>(std::max(0L, v.nj));
  info.nz = v.levels.size();
  info.zDimension = v.typeOfLevel;
  info.verticalKind = verticalKindOf(v.typeOfLevel);
  info.verticalVariable = v.typeOfLevel;
  if (!v.notReadable.empty()) {
    info.notReadable = v.notReadable;
    info.bytesRead = c.content.bytesRead();
    return info;
  }
  // Heights from a sample of at most ~64 x 64 columns at the first time and member, as netCDF.
  const std::size_t stride = std::max<std::size_t>(1, (static_cast<std::size_t>(std::max(v.ni, v.nj)) + 63) / 64);
  info.heightColumnStride = stride;
  auto s = readSelection(c, v, 0, v.members.front(), GridCrop{}, stride, true, false);
  if (!s) return s.forwardError();
  const grid::CoordinateError error = [&](const std::string& what) { return varError(c, v, what); };
  if (s->reduced) {
    auto full = grid::reducedAxes(s->pl, s->pointLat, s->pointLon, GridCrop{}, 1, error);
    if (!full) return full.forwardError();
    grid::describeExtent(full->hz, false, info);
    info.meanSpacingKm = full->meanSpacingKm();
    info.reduced = true;
    info.nx = full->nx;
    info.ny = full->rowLength.size();
    info.minRowLengthPoints = *std::min_element(full->rowLength.begin(), full->rowLength.end());
    info.maxRowLengthPoints = full->nx;
    info.gridPoints = full->points.size();
    info.emptyRowsLeftOut = full->emptyRowsDropped;
  } else {
    auto full = horizontalOf(c, v, *s, GridCrop{}, 1);
    if (!full) return full.forwardError();
    info.curvilinear = s->projected.has_value();
    if (s->projected) info.projection = s->projected->definition;
    grid::describeExtent(*full, info.curvilinear, info);
  }
  const grid::Heights& h = s->heights;
  info.heightSource = h.source;
  info.heightNote = h.note;
  info.approximateHeights = h.approximate;
  info.levelValues = h.levelValues;
  info.levelUnits = h.levelUnits;
  const auto [mn, mx] = std::minmax_element(h.h.begin(), h.h.end());
  info.heightMinMeters = *mn;
  info.heightMaxMeters = *mx;
  info.bytesRead = c.content.bytesRead();
  return info;
}

namespace {

std::string levelsText(const std::vector<double>& levels) {
  std::string s;
  for (double l : levels) s.append(s.empty() ? "" : " ").append(levelText(l));
  return s;
}

/// "120 x 61 points", or for reduced grids (Ni missing) "96 rows of different lengths, 13280 points".
std::string gridSize(const GridVariableInfo& v) {
  if (v.gridNi == 0)
    return std::to_string(v.gridNj) + " rows of different lengths" +
           (v.gridPoints > 0 ? ", " + std::to_string(v.gridPoints) + " points" : std::string());
  return std::to_string(v.gridNi) + " x " + std::to_string(v.gridNj) + " points";
}

std::string membersText(const std::vector<long>& members) {
  if (members.empty()) return "none";
  bool run = true;
  for (std::size_t i = 1; i < members.size(); ++i) run = run && members[i] == members[i - 1] + 1;
  if (run && members.size() > 2)
    return std::to_string(members.size()) + " (" + std::to_string(members.front()) + " .. " +
           std::to_string(members.back()) + ")";
  std::string s = std::to_string(members.size()) + " (";
  for (std::size_t i = 0; i < members.size(); ++i) s.append(i ? ", " : "").append(std::to_string(members[i]));
  return s + ")";
}

}  // namespace

std::string describeGribText(const GridFileInfo& g) {
  std::ostringstream os;
  os << "file:       " << g.path << "\n";
  os << "format:     forecast grid, " << g.format << ", " << g.messageCount << " message"
     << (g.messageCount == 1 ? "" : "s") << "\n";
  os << "index:      "
     << (g.indexFile.empty() ? std::string("not kept (the cache directory cannot be written)") : g.indexFile)
     << (g.indexReused ? " (reused)" : " (made now)") << "\n";
  const GridVariableInfo* v = nullptr;
  for (const auto& x : g.variables)
    if (x.name == g.variable) v = &x;
  os << "variable:   " << g.variable;
  if (v) os << " (" << v->longName << ")" << (v->units.empty() ? "" : " [" + v->units + "]");
  os << "\n";
  if (!g.notReadable.empty()) {
    os << "            NOT READ YET: " << g.notReadable << "\n";
    if (v) os << "grid:       " << v->gridType << ", " << gridSize(*v) << "\n";
    os << "levels:     " << g.nz << " (" << g.zDimension << ")" << (v ? ": " + levelsText(v->levels) : "") << "\n";
  } else {
    if (g.reduced) {
      os << "grid:       " << (v ? v->gridType : std::string()) << " (reduced: rows of different lengths), " << g.ny
         << " rows of " << g.minRowLengthPoints << " .. " << g.maxRowLengthPoints << " points (" << g.gridPoints
         << " points), ~" << grid::num(g.meanSpacingKm, 1) << " km apart\n";
      if (g.emptyRowsLeftOut > 0)
        os << "            " << g.emptyRowsLeftOut << " empty row" << (g.emptyRowsLeftOut == 1 ? "" : "s")
           << " (pl 0) at the grid's ends left out\n";
    } else {
      os << "grid:       " << (v ? v->gridType : std::string()) << (g.curvilinear ? " (curvilinear)" : " (rectilinear)")
         << ", " << g.nx << " x " << g.ny << " points, ~" << grid::num(g.meanSpacingKm, 1) << " km apart\n";
      if (!g.projection.empty()) os << "projection: " << g.projection << " (PROJ; points placed from it)\n";
    }
    os << "extent:     latitude " << grid::num(g.southDeg, 3) << " .. " << grid::num(g.northDeg, 3)
       << " deg, longitude " << grid::num(g.westDeg, 3) << " .. " << grid::num(g.eastDeg, 3) << " deg"
       << (g.wrapsLongitude ? " (global: wraps)" : "") << "\n";
    os << "vertical:   " << toString(g.verticalKind) << " (" << g.verticalVariable << "), " << g.nz << " level"
       << (g.nz == 1 ? "" : "s") << ", heights from " << toString(g.heightSource)
       << (g.approximateHeights ? ", APPROXIMATE" : "") << "\n";
    os << "            " << g.heightNote << "\n";
    os << "levels:     bottom first: " << (v ? levelsText(v->levels) : std::string()) << " (" << g.zDimension << ")\n";
    os << "heights:    " << grid::num(g.heightMinMeters, 1) << " .. " << grid::num(g.heightMaxMeters, 1)
       << " m above the WGS84 ellipsoid (first time step and member"
       << (g.heightColumnStride > 1 ? ", sampled every " + std::to_string(g.heightColumnStride) + " rows and columns"
                                    : "")
       << ")" << (g.approximateHeights ? " APPROXIMATE" : "") << "\n";
  }
  os << "times:      " << g.times.size() << " (validity)";
  if (!g.times.empty()) os << ": " << g.times.front() << (g.times.size() > 1 ? " .. " + g.times.back() : "");
  os << "\n";
  os << "steps:      ";
  for (std::size_t i = 0; i < g.steps.size(); ++i) os << (i ? " " : "") << g.steps[i];
  os << "\n";
  os << "members:    " << membersText(g.members) << "\n";
  os << "variables (shortName:typeOfLevel; * = read):\n";
  for (const auto& x : g.variables) {
    os << (x.onGrid ? "  * " : "    ") << x.name << "  " << x.longName << (x.units.empty() ? "" : " [" + x.units + "]")
       << ", " << x.gridType << " " << gridSize(x) << ", " << x.levels.size() << " level"
       << (x.levels.size() == 1 ? "" : "s") << " (" << levelsText(x.levels) << "), " << x.timeCount << " time"
       << (x.timeCount == 1 ? "" : "s") << ", " << x.memberCount << " member" << (x.memberCount == 1 ? "" : "s") << ", "
       << x.messageCount << " message" << (x.messageCount == 1 ? "" : "s") << "\n";
    if (!x.notReadable.empty()) os << "        not read yet: " << x.notReadable << "\n";
  }
  for (const auto& w : g.warnings) os << "warning:    " << w << "\n";
  os << "read:       " << g.bytesRead << " bytes of GRIB messages\n";
  return os.str();
}

std::string describeGribJson(const GridFileInfo& g) {
  using J = nlohmann::ordered_json;
  J j;
  j["kind"] = "grid";
  j["format"] = g.format;
  j["file"] = g.path;
  j["variable"] = g.variable;
  j["not_readable"] = g.notReadable;
  J vars = J::array();
  for (const auto& v : g.variables)
    vars.push_back({{"name", v.name},
                    {"short_name", v.shortName},
                    {"level_type", v.levelType},
                    {"levels_bottom_first", v.levels},
                    {"grid_type", v.gridType},
                    {"ni", v.gridNi},
                    {"nj", v.gridNj},
                    {"points", v.gridPoints},
                    {"times", v.timeCount},
                    {"members", v.memberCount},
                    {"messages", v.messageCount},
                    {"units", v.units},
                    {"long_name", v.longName},
                    {"on_grid", v.onGrid},
                    {"not_readable", v.notReadable}});
  j["variables"] = std::move(vars);
  if (g.notReadable.empty()) {
    j["grid"] = {{"horizontal", g.reduced       ? "reduced"
                                : g.curvilinear ? "curvilinear"
                                                : "rectilinear"},
                 {"projection", g.projection},
                 {"nx", g.nx},
                 {"ny", g.ny},
                 {"nz", g.nz},
                 {"south_deg", g.southDeg},
                 {"north_deg", g.northDeg},
                 {"west_deg", g.westDeg},
                 {"east_deg", g.eastDeg},
                 {"wraps_longitude", g.wrapsLongitude},
                 {"mean_spacing_km", g.meanSpacingKm}};
    if (g.reduced) {
      j["grid"]["rows"] = g.ny;
      j["grid"]["min_row_length_points"] = g.minRowLengthPoints;
      j["grid"]["max_row_length_points"] = g.maxRowLengthPoints;
      j["grid"]["points"] = g.gridPoints;
      j["grid"]["empty_rows_left_out"] = g.emptyRowsLeftOut;
    }
    j["vertical"] = grid::verticalJson(g);
  }
  j["time"] = {{"kind", "validity"}, {"values", g.times}};
  j["grib"] = {{"messages", g.messageCount},    {"steps", g.steps},
               {"members", g.members},          {"index_file", g.indexFile},
               {"index_reused", g.indexReused}, {"warnings", g.warnings}};
  j["bytes_read"] = g.bytesRead;
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace atmoglobe::volume::grib
