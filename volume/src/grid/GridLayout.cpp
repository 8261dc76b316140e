// What a grid variable is made of: its horizontal coordinates, vertical coordinate and time
// axis, found from CF attributes or WRF's names. Metadata only: no values are read here.
#include "GridInternal.h"

#include <atmoglobe/globe/Text.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace atmoglobe::volume::grid {

namespace {

bool contains(const std::string& s, const char* what) { return s.find(what) != std::string::npos; }

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream is(s);
  std::vector<std::string> out;
  for (std::string t; is >> t;) out.push_back(t);
  return out;
}

bool isLatUnits(const std::string& units) {
  const std::string u = toLowerAsciiWithoutBlanks(units);
  return u == "degrees_north" || u == "degree_north" || u == "degree_n" || u == "degrees_n" || u == "degreen" ||
         u == "degreesn";
}

bool isLonUnits(const std::string& units) {
  const std::string u = toLowerAsciiWithoutBlanks(units);
  return u == "degrees_east" || u == "degree_east" || u == "degree_e" || u == "degrees_e" || u == "degreee" ||
         u == "degreese";
}

enum class Role { None, Lat, Lon, Time, Vertical };

const std::vector<std::string>& verticalStandardNames() {
  static const std::vector<std::string> k = {"air_pressure",
                                             "altitude",
                                             "height",
                                             "height_above_mean_sea_level",
                                             "height_above_geoid",
                                             "height_above_reference_ellipsoid",
                                             "geopotential_height",
                                             "depth",
                                             "atmosphere_hybrid_sigma_pressure_coordinate",
                                             "atmosphere_sigma_coordinate",
                                             "atmosphere_hybrid_height_coordinate",
                                             "atmosphere_ln_pressure_coordinate",
                                             "atmosphere_sleve_coordinate",
                                             "model_level_number",
                                             "ocean_sigma_coordinate",
                                             "ocean_s_coordinate"};
  return k;
}

/// What a dimension that is neither horizontal, vertical nor time is, by its name or its
/// coordinate variable: an ensemble member (CF standard_name realization; names number,
/// realization, member, ensemble ...; a long_name mentioning an ensemble), another index users
/// choose (month, season ...), or neither (None: the dimension may still be a vertical one).
enum class IndexKind { None, Ensemble, Other };

IndexKind indexKindOf(const io::NetcdfFile& f, const std::string& dimName, const std::optional<io::NcVar>& c) {
  const std::string n = toLowerAscii(dimName);
  for (const char* e : {"number", "realization", "realisation", "member", "members", "ensemble", "ens",
                        "ensemble_member", "member_id", "ens_mem", "mem"})
    if (n == e) return IndexKind::Ensemble;
  if (c) {
    if (attrText(f, *c, "standard_name") == "realization") return IndexKind::Ensemble;
    if (contains(toLowerAscii(attrText(f, *c, "long_name")), "ensemble")) return IndexKind::Ensemble;
  }
  for (const char* o : {"month", "months", "season", "seasons", "quantile", "percentile"})
    if (n == o) return IndexKind::Other;
  return IndexKind::None;
}

Role roleOf(const io::NetcdfFile& f, const io::NcVar& c) {
  const std::string sn = attrText(f, c, "standard_name");
  const std::string units = attrText(f, c, "units");
  const std::string axis = toLowerAscii(attrText(f, c, "axis"));
  if (sn == "latitude" || isLatUnits(units)) return Role::Lat;
  if (sn == "longitude" || isLonUnits(units)) return Role::Lon;
  if (sn == "time" || axis == "t" || contains(toLowerAscii(units), " since ")) return Role::Time;
  if (axis == "z" || f.hasAttribute(c.groupId, c.varId, "positive") ||
      f.hasAttribute(c.groupId, c.varId, "formula_terms") || units == "hybrid_sigma_pressure" ||
      pressureUnitToPascal(units) || geopotentialHeightUnitToMeters(units) ||
      std::find(verticalStandardNames().begin(), verticalStandardNames().end(), sn) != verticalStandardNames().end())
    return Role::Vertical;
  // A length-valued coordinate with a vertical-sounding name (lev, level, height, z, alt...).
  if (lengthUnitToMeters(units)) {
    const std::string n = toLowerAscii(c.name.substr(c.name.rfind('/') + 1));
    for (const char* w : {"lev", "height", "alt", "z", "hgt", "depth", "elev"})
      if (n.rfind(w, 0) == 0) return Role::Vertical;
  }
  return Role::None;
}

/// The 1-D coordinate variable of dimension `dimId` of `v` (same name, one dimension, that one).
std::optional<io::NcVar> coordinateVariable(const io::NetcdfFile& f, const io::NcVar& v, int dimId) {
  auto c = findInScope(f, v.groupId, dimensionName(v.groupId, dimId));
  if (!c || c->dimIds.size() != 1 || c->dimIds[0] != dimId) return std::nullopt;
  return c;
}

std::string dimList(const io::NetcdfFile&, const io::NcVar& v) {
  std::string s;
  for (std::size_t d = 0; d < v.dimIds.size(); ++d) {
    if (d) s.append(", ");
    s.append(dimensionName(v.groupId, v.dimIds[d])).append(" ").append(std::to_string(v.shape[d]));
  }
  return s;
}

int positionOf(const io::NcVar& v, int dimId) {
  for (std::size_t d = 0; d < v.dimIds.size(); ++d)
    if (v.dimIds[d] == dimId) return static_cast<int>(d);
  return -1;
}

/// The whole of `v` could be read: its element count is within kMaxElementsPerRead and the file
/// can hold it (io::NetcdfFile::checkReadable). Run on every coordinate before its length sizes
/// anything, so a header claiming 2^28 levels is refused before an index list is built.
Status checkWhole(const io::NetcdfFile& f, const io::NcVar& v) {
  std::size_t n = 1;
  for (std::size_t d : v.shape) {
    if (d != 0 && n > io::kMaxElementsPerRead / d)
      return makeError(f.message("variable '" + v.name + "' claims more than " +
                                 std::to_string(io::kMaxElementsPerRead) + " values"));
    n *= d;
  }
  return f.checkReadable(v, n, std::max<std::size_t>(io::ncTypeSize(v.type), 1));
}

/// Checks that every dimension of `support` is one of `allowed` (dimension ids of the grid
/// variable) or has length 1, and that the allowed ones come in the grid variable's order.
Status checkSupportDims(const io::NetcdfFile& f, const io::NcVar& support, const io::NcVar& gridVar,
                        const std::vector<int>& allowed, const std::string& role) {
  int last = -1;
  for (std::size_t d = 0; d < support.dimIds.size(); ++d) {
    const int id = support.dimIds[d];
    const auto it = std::find(allowed.begin(), allowed.end(), id);
    if (it == allowed.end()) {
      if (support.shape[d] == 1) continue;
      return makeError(f.message("variable '" + support.name + "' (" + role + " of '" + gridVar.name +
                                 "') has dimension '" + dimensionName(support.groupId, id) + "' of length " +
                                 std::to_string(support.shape[d]) + ", which '" + gridVar.name +
                                 "' does not have: inconsistent sizes (" + dimList(f, support) + " against " +
                                 dimList(f, gridVar) + ")"));
    }
    const int pos = static_cast<int>(it - allowed.begin());
    if (pos < last)
      return makeError(f.message("variable '" + support.name + "' (" + role + " of '" + gridVar.name +
                                 "') orders its dimensions differently from '" + gridVar.name + "'"));
    last = pos;
  }
  return Ok{};
}

bool hasDims(const io::NcVar& v, std::initializer_list<int> ids) {
  for (int id : ids)
    if (id >= 0 && positionOf(v, id) < 0) return false;
  return true;
}

/// The dimensions of the grid variable a field it needs may have, in the variable's order: time,
/// the extra dimensions, the vertical one when `withLevels`, and the horizontal ones.
std::vector<int> supportDims(const GridLayout& l, bool withLevels) {
  std::vector<int> out;
  for (int id : l.var.dimIds) {
    const bool extra = std::any_of(l.extras.begin(), l.extras.end(), [id](const ExtraDim& e) { return e.dimId == id; });
    if ((id == l.time.dimId && id >= 0) || extra || (withLevels && id == l.zDim) || id == l.yDim || id == l.xDim)
      out.push_back(id);
  }
  return out;
}

/// A field on the grid variable's levels holding geopotential (m2 s-2) or geopotential height
/// (gpm / m): by standard_name, else by a usual name with fitting units. The grid variable
/// itself when it is one (the heights of a geopotential field are its own).
void findGeopotential(const io::NetcdfFile& f, const GridLayout& l, VerticalSpec& vs) {
  const std::vector<int> allowed = supportDims(l, true);
  std::optional<int> g = l.var.groupId;
  while (g) {
    for (const io::NcVar& c : f.variables(*g)) {
      if (!hasDims(c, {l.zDim, l.yDim, l.xDim})) continue;
      if (!checkSupportDims(f, c, l.var, allowed, "geopotential")) continue;
      const std::string sn = attrText(f, c, "standard_name");
      const std::string units = attrText(f, c, "units");
      const std::string n = c.name.substr(c.name.rfind('/') + 1);
      const bool geoName = n == "z" || n == "Z" || n == "phi" || n == "PHI" || n == "geopotential" || n == "FI";
      const bool heightName = n == "zg" || n == "gh" || n == "hgt" || n == "HGT" || n == "gph" || n == "GH" ||
                              n == "geopotential_height" || n == "z_g";
      if (const auto k = geopotentialUnitToSi(units); (sn == "geopotential" || geoName) && k) {
        vs.geopotential = c;
        vs.geopotentialToGpm = *k / kStandardGravity;
        return;
      }
      if (sn == "geopotential_height" ||
          (heightName && (geopotentialHeightUnitToMeters(units) || lengthUnitToMeters(units)))) {
        auto k = geopotentialHeightUnitToMeters(units);
        if (!k) k = lengthUnitToMeters(units);
        if (!k) continue;
        vs.geopotential = c;
        vs.geopotentialToGpm = *k;
        return;
      }
    }
    g = parentGroup(*g);
  }
}

/// The surface altitude (m above sea level) for heights above ground.
void findSurfaceAltitude(const io::NetcdfFile& f, const GridLayout& l, VerticalSpec& vs) {
  const std::vector<int> allowed = supportDims(l, false);
  std::optional<int> g = l.var.groupId;
  while (g) {
    for (const io::NcVar& c : f.variables(*g)) {
      if (!hasDims(c, {l.yDim, l.xDim})) continue;
      if (!checkSupportDims(f, c, l.var, allowed, "surface altitude")) continue;
      const std::string sn = attrText(f, c, "standard_name");
      const auto k = lengthUnitToMeters(attrText(f, c, "units"));
      const std::string n = c.name.substr(c.name.rfind('/') + 1);
      const bool named = n == "orog" || n == "HGT" || n == "hsurf" || n == "HSURF" || n == "topo" ||
                         n == "surface_altitude";
      if ((sn == "surface_altitude" || named) && k) {
        vs.surfaceAltitude = c;
        vs.surfaceToMeters = *k;
        return;
      }
    }
    g = parentGroup(*g);
  }
}

/// Checks the terms of `vs.terms` (required and optional ones, `source` describing where they
/// were named, for messages): units to SI (termToSi) and shapes.
Status checkTerms(const io::NetcdfFile& f, const GridLayout& l, const io::NcVar& coord, VerticalSpec& vs,
                  const std::vector<std::string>& required, const std::vector<std::string>& optional,
                  const std::string& source) {
  for (const std::string& r : required)
    if (!vs.terms.count(r)) return varError(f, coord, source + " lacks the term '" + r + "'");
  for (const auto& [term, v] : vs.terms) {
    if (std::find(required.begin(), required.end(), term) == required.end() &&
        std::find(optional.begin(), optional.end(), term) == optional.end())
      return varError(f, coord, source + ": unexpected term '" + term + "'");
    const std::string units = attrText(f, v, "units");
    if (term == "ps" || term == "p0" || term == "ap" || term == "ptop") {
      if (units.empty()) {
        vs.termToSi[term] = 1.0;  // CF requires units; hybrid coefficient files often omit them on ap: Pa assumed
      } else if (auto k = pressureUnitToPascal(units)) {
        vs.termToSi[term] = *k;
      } else {
        return makeError(f.message("variable '" + v.name + "' (term '" + term + "' of '" + coord.name + "'): units '" +
                                   units + "' are not a pressure unit"));
      }
    } else if (term == "orog" || (term == "a" && vs.kind == VerticalKind::HybridHeight)) {
      const auto k = units.empty() ? std::optional<double>(1.0) : lengthUnitToMeters(units);
      if (!k)
        return makeError(f.message("variable '" + v.name + "' (term '" + term + "' of '" + coord.name + "'): units '" +
                                   units + "' are not a length unit"));
      vs.termToSi[term] = *k;
    } else {
      vs.termToSi[term] = 1.0;
    }
    // Shapes: coefficients on the levels, surface fields on the columns, constants scalar.
    if (term == "a" || term == "b" || term == "ap" || term == "sigma") {
      if (v.shape.size() != 1 || v.shape[0] != vs.fileLevels)
        return makeError(f.message("variable '" + v.name + "' (term '" + term + "' of '" + coord.name + "') has " +
                                   (v.shape.size() == 1 ? std::to_string(v.shape[0]) + " values"
                                                        : std::to_string(v.shape.size()) + " dimensions") +
                                   ", expected one per level (" + std::to_string(vs.fileLevels) +
                                   "): inconsistent sizes"));
    } else if (term == "p0" || term == "ptop") {
      if (v.elementCount() != 1)
        return makeError(f.message("variable '" + v.name + "' (term '" + term + "' of '" + coord.name +
                                   "') must hold one value: inconsistent sizes"));
    } else {  // ps, orog
      if (!hasDims(v, {l.yDim, l.xDim}))
        return makeError(f.message("variable '" + v.name + "' (term '" + term + "' of '" + coord.name +
                                   "') is not on the columns of '" + l.var.name + "' (" + dimList(f, v) + " against " +
                                   dimList(f, l.var) + "): inconsistent sizes"));
      if (auto st = checkSupportDims(f, v, l.var, supportDims(l, false), "term '" + term + "'"); !st) return st;
    }
  }
  return Ok{};
}

/// The terms named by the coordinate's formula_terms ("term: variable" pairs), checked.
Status parseFormulaTerms(const io::NetcdfFile& f, const GridLayout& l, const io::NcVar& coord, VerticalSpec& vs,
                         const std::vector<std::string>& required, const std::vector<std::string>& optional) {
  const std::string ft = attrText(f, coord, "formula_terms");
  const std::vector<std::string> t = tokens(ft);
  if (t.empty() || t.size() % 2 != 0)
    return varError(f, coord, "formula_terms '" + ft + "' is not a list of 'term: variable' pairs");
  for (std::size_t i = 0; i + 1 < t.size(); i += 2) {
    if (t[i].size() < 2 || t[i].back() != ':')
      return varError(f, coord, "formula_terms '" + ft + "' is not a list of 'term: variable' pairs");
    const std::string term = t[i].substr(0, t[i].size() - 1);
    auto v = findInScope(f, coord.groupId, t[i + 1]);
    if (!v)
      return varError(
          f, coord,
          "formula_terms names variable '" + t[i + 1] + "' for term '" + term + "', which is not in the file");
    vs.terms[term] = *v;
  }
  return checkTerms(f, l, coord, vs, required, optional, "formula_terms '" + ft + "'");
}

/// CAM/NCL hybrid sigma-pressure levels: the coordinate names its coefficients and surface
/// pressure in the attributes A_var, B_var, PS_var and P0_var instead of formula_terms
/// (p = A P0 + B PS). P0_var absent, or naming a variable the file lacks: CAM's reference
/// pressure P0 = 100000 Pa, said in the height note.
Status camHybridTerms(const io::NetcdfFile& f, const GridLayout& l, const io::NcVar& coord, VerticalSpec& vs) {
  vs.termsSource = "attributes A_var, B_var, P0_var, PS_var";
  std::vector<std::string> lacking;
  for (const auto& [attr, term] :
       {std::pair<const char*, const char*>{"A_var", "a"}, {"B_var", "b"}, {"PS_var", "ps"}}) {
    const std::string name = attrText(f, coord, attr);
    if (name.empty()) {
      lacking.push_back(attr);
      continue;
    }
    auto v = findInScope(f, coord.groupId, name);
    if (!v)
      return varError(f, coord,
                      std::string("attribute ") + attr + " names variable '" + name + "' (term '" + term +
                          "' of p = A P0 + B PS), which is not in the file");
    vs.terms[term] = *v;
  }
  if (!lacking.empty()) {
    std::string s;
    for (const auto& a : lacking) s.append(s.empty() ? "" : ", ").append(a);
    return varError(f, coord,
                    "hybrid sigma-pressure levels without formula_terms need the attributes A_var, B_var and "
                    "PS_var (CAM's form); missing: " +
                        s);
  }
  const std::string p0Name = attrText(f, coord, "P0_var");
  std::optional<io::NcVar> p0 = p0Name.empty() ? std::nullopt : findInScope(f, coord.groupId, p0Name);
  if (p0) {
    vs.terms["p0"] = *p0;
  } else {
    vs.defaultP0Pa = 100000.0;
    vs.defaultP0Reason = p0Name.empty() ? std::string("no P0_var attribute")
                                        : "P0_var names '" + p0Name + "', which is not in the file";
  }
  return checkTerms(f, l, coord, vs, {"a", "b", "ps"}, {"p0"}, vs.termsSource);
}

/// The vertical coordinate of a CF variable from its coordinate variable's attributes.
Status cfVertical(const io::NetcdfFile& f, GridLayout& l, const io::NcVar& coord) {
  VerticalSpec& vs = l.vertical;
  vs.coordinate = coord;
  vs.fileLevels = coord.shape[0];
  const std::string sn = attrText(f, coord, "standard_name");
  const std::string units = attrText(f, coord, "units");
  const std::string positive = toLowerAscii(attrText(f, coord, "positive"));
  const std::string longName = toLowerAscii(attrText(f, coord, "long_name"));
  vs.coordinateUnits = units;
  vs.positiveDown = positive == "down";
  const bool formulaTerms = f.hasAttribute(coord.groupId, coord.varId, "formula_terms");
  const bool camHybrid =
      !formulaTerms && (units == "hybrid_sigma_pressure" || sn == "atmosphere_hybrid_sigma_pressure_coordinate") &&
      (f.hasAttribute(coord.groupId, coord.varId, "A_var") || f.hasAttribute(coord.groupId, coord.varId, "B_var") ||
       f.hasAttribute(coord.groupId, coord.varId, "PS_var") || units == "hybrid_sigma_pressure");
  if (camHybrid) {
    vs.kind = VerticalKind::HybridSigmaPressure;
    if (auto st = camHybridTerms(f, l, coord, vs); !st) return st;
    findGeopotential(f, l, vs);
    return Ok{};
  }
  const bool parametric = formulaTerms || sn == "atmosphere_hybrid_sigma_pressure_coordinate" ||
                          sn == "atmosphere_sigma_coordinate" || sn == "atmosphere_hybrid_height_coordinate" ||
                          sn == "atmosphere_ln_pressure_coordinate" || sn == "atmosphere_sleve_coordinate" ||
                          sn == "ocean_sigma_coordinate" || sn == "ocean_s_coordinate";
  if (parametric) {
    if (!f.hasAttribute(coord.groupId, coord.varId, "formula_terms"))
      return varError(f, coord,
                      "standard_name '" + sn + "' needs a formula_terms attribute to give heights" +
                          (sn == "atmosphere_hybrid_sigma_pressure_coordinate"
                               ? std::string(" (or CAM's attributes A_var, B_var, PS_var)")
                               : std::string()));
    if (sn == "atmosphere_hybrid_sigma_pressure_coordinate") {
      vs.kind = VerticalKind::HybridSigmaPressure;
      if (auto st = parseFormulaTerms(f, l, coord, vs, {"b", "ps"}, {"a", "p0", "ap"}); !st) return st;
      const bool aForm = vs.terms.count("a") && vs.terms.count("p0");
      if (!aForm && !vs.terms.count("ap"))
        return varError(f, coord, "formula_terms needs 'a' and 'p0' or 'ap' (p = a p0 + b ps or ap + b ps)");
    } else if (sn == "atmosphere_sigma_coordinate") {
      vs.kind = VerticalKind::Sigma;
      if (auto st = parseFormulaTerms(f, l, coord, vs, {"sigma", "ps", "ptop"}, {}); !st) return st;
    } else if (sn == "atmosphere_hybrid_height_coordinate") {
      vs.kind = VerticalKind::HybridHeight;
      if (auto st = parseFormulaTerms(f, l, coord, vs, {"a", "b", "orog"}, {}); !st) return st;
    } else {
      return varError(f, coord,
                      "unknown vertical coordinate: parametric coordinate '" +
                          (sn.empty() ? std::string("(no standard_name)") : sn) +
                          "' is not supported (supported: atmosphere_hybrid_sigma_pressure_coordinate, "
                          "atmosphere_sigma_coordinate, atmosphere_hybrid_height_coordinate)");
    }
    if (vs.kind != VerticalKind::HybridHeight) findGeopotential(f, l, vs);
    return Ok{};
  }
  if (sn == "air_pressure" || pressureUnitToPascal(units)) {
    const auto k = pressureUnitToPascal(units);
    if (!k) return varError(f, coord, "pressure coordinate with units '" + units + "', not a pressure unit");
    vs.kind = VerticalKind::Pressure;
    vs.toSi = *k;
    findGeopotential(f, l, vs);
    return Ok{};
  }
  if (sn == "geopotential_height" || geopotentialHeightUnitToMeters(units)) {
    auto k = geopotentialHeightUnitToMeters(units);
    if (!k) k = lengthUnitToMeters(units);
    if (!k) return varError(f, coord, "geopotential height coordinate with units '" + units + "', not gpm or m");
    vs.kind = VerticalKind::GeopotentialHeight;
    vs.toSi = *k;
    return Ok{};
  }
  if (const auto k = lengthUnitToMeters(units)) {
    vs.toSi = *k;
    if (sn == "height_above_reference_ellipsoid") {
      vs.datum = LengthDatum::Ellipsoid;
      vs.datumReason = "standard_name " + sn;
    } else if (sn == "altitude" || sn == "height_above_mean_sea_level" || sn == "height_above_geoid") {
      vs.datum = LengthDatum::SeaLevel;
      vs.datumReason = "standard_name " + sn;
    } else if (sn == "depth") {
      vs.datum = LengthDatum::SeaLevel;
      vs.positiveDown = true;
      vs.datumReason = "standard_name depth (below sea level)";
    } else if (sn == "height") {
      vs.datum = LengthDatum::Ground;
      vs.datumReason = "standard_name height (above the surface)";
    } else if (contains(longName, "ellipsoid")) {
      vs.datum = LengthDatum::Ellipsoid;
      vs.datumReason = "long_name '" + longName + "'";
    } else if (contains(longName, "ground") || contains(longName, "surface") || contains(longName, "agl")) {
      vs.datum = LengthDatum::Ground;
      vs.datumReason = "long_name '" + longName + "'";
    } else if (contains(longName, "sea level") || contains(longName, "msl") || contains(longName, "altitude") ||
               contains(longName, "geoid")) {
      vs.datum = LengthDatum::SeaLevel;
      vs.datumReason = "long_name '" + longName + "'";
    } else {
      vs.datum = LengthDatum::Unknown;
      vs.datumReason = "no standard_name or long_name says above what";
    }
    vs.kind = vs.datum == LengthDatum::Ellipsoid ? VerticalKind::HeightAboveEllipsoid
              : vs.datum == LengthDatum::Ground  ? VerticalKind::HeightAboveGround
                                                 : VerticalKind::HeightAboveSeaLevel;
    if (vs.datum == LengthDatum::Ground) findSurfaceAltitude(f, l, vs);
    return Ok{};
  }
  return varError(f, coord,
                  "unknown vertical coordinate: units '" + units + "'" +
                      (sn.empty() ? std::string() : ", standard_name '" + sn + "'") +
                      " give neither a pressure, a length nor a parametric formula (formula_terms)" +
                      (unitDatabaseProblem().empty() ? std::string() : " (" + unitDatabaseProblem() + ")"));
}

Status timeSpecFromCoordinate(const io::NetcdfFile& f, TimeSpec& t, const io::NcVar& c) {
  t.coordinate = c;
  t.units = attrText(f, c, "units");
  t.calendar = attrText(f, c, "calendar");
  auto parsed = parseCfTimeUnits(t.units, t.calendar);
  if (parsed) t.parsed = *parsed;
  else t.unitsError = f.message("variable '" + c.name + "': " + parsed.error());
  return Ok{};
}

/// A WRF variable's time axis: the Times strings, else XTIME; and the variable must hold a byte
/// per step.
Status wrfTimeSpec(const io::NetcdfFile& f, GridLayout& l, int tDim) {
  const int root = f.root();
  if (l.time.dimId >= 0) {
    if (auto times = f.findVariable(root, "Times");
        times && times->type == NC_CHAR && times->dimIds.size() == 2 && times->dimIds[0] == tDim) {
      if (auto st = checkWhole(f, *times); !st) return st;
      l.time.wrfTimes = *times;
    } else if (auto xtime = f.findVariable(root, "XTIME");
               xtime && xtime->dimIds.size() == 1 && xtime->dimIds[0] == tDim) {
      if (auto st = timeSpecFromCoordinate(f, l.time, *xtime); !st) return st;
    }
  }
  if (l.time.dimId >= 0)
    if (auto st = f.checkReadable(l.var, l.time.count, 1); !st) return st;
  return Ok{};
}

Result<GridLayout> analyseWrf(const io::NetcdfFile& f, const io::NcVar& v, bool allowSingleLevel) {
  GridLayout l;
  l.var = v;
  l.wrf = true;
  const int root = f.root();
  int tDim = -1;
  const auto nT = f.dimensionLength(root, "Time", &tDim);
  const auto nz = f.dimensionLength(root, "bottom_top", &l.zDim);
  const auto ny = f.dimensionLength(root, "south_north", &l.yDim);
  const auto nx = f.dimensionLength(root, "west_east", &l.xDim);
  const auto nzs = f.dimensionLength(root, "bottom_top_stag", &l.zStagDim);
  const auto nys = f.dimensionLength(root, "south_north_stag", &l.yStagDim);
  const auto nxs = f.dimensionLength(root, "west_east_stag", &l.xStagDim);
  if (!ny || !nx) return makeError(f.message("WRF file without the dimensions south_north and west_east"));
  l.nx = *nx;
  l.ny = *ny;
  int tPos = -1, zPos = -1, yPos = -1, xPos = -1;
  for (std::size_t d = 0; d < v.dimIds.size(); ++d) {
    const int id = v.dimIds[d];
    const int p = static_cast<int>(d);
    if (id == tDim) tPos = p;
    else if (id == l.zDim || id == l.zStagDim) {
      zPos = p;
      l.stagZ = id == l.zStagDim;
    } else if (id == l.yDim || id == l.yStagDim) {
      yPos = p;
      l.stagY = id == l.yStagDim;
    } else if (id == l.xDim || id == l.xStagDim) {
      xPos = p;
      l.stagX = id == l.xStagDim;
    } else if (v.shape[d] != 1)
      return varError(f, v,
                      "dimension '" + dimensionName(v.groupId, id) +
                          "' is not one of WRF's atmospheric grid dimensions (Time, bottom_top[_stag], "
                          "south_north[_stag], west_east[_stag])");
  }
  if (yPos < 0 || xPos < 0) return varError(f, v, "not on the horizontal grid (dimensions: " + dimList(f, v) + ")");
  if (zPos < 0 && !allowSingleLevel)
    return varError(f, v,
                    "has no vertical dimension (dimensions: " + dimList(f, v) +
                        "): a 2-D field, not a volume (draw it as a map: --surface FILE --surface-var NAME)");
  // A 2-D field (T2, PSFC, U10 ...): one level at mean sea level, for the maps on the globe.
  l.singleLevel = zPos < 0;
  if (l.singleLevel ? !(tPos < yPos && yPos < xPos) : !(tPos < zPos && zPos < yPos && yPos < xPos))
    return varError(f, v,
                    "dimension order (" + dimList(f, v) + ") is not (Time, " + (l.singleLevel ? "" : "bottom_top, ") +
                        "south_north, west_east)");
  if (!nz && !l.singleLevel) return makeError(f.message("WRF file without the dimension bottom_top"));
  if (*nx == 0 || *ny == 0 || (!l.singleLevel && *nz == 0))
    return varError(f, v, "has an empty dimension (" + dimList(f, v) + ")");
  if (!l.singleLevel && (l.stagZ || nzs) && nzs && *nzs != *nz + 1)
    return makeError(f.message("dimension bottom_top_stag has length " + std::to_string(*nzs) +
                               ", expected bottom_top + 1 = " + std::to_string(*nz + 1) + ": inconsistent sizes"));
  if (l.stagY && *nys != *ny + 1)
    return makeError(f.message("dimension south_north_stag has length " + std::to_string(*nys) +
                               ", expected south_north + 1 = " + std::to_string(*ny + 1) + ": inconsistent sizes"));
  if (l.stagX && *nxs != *nx + 1)
    return makeError(f.message("dimension west_east_stag has length " + std::to_string(*nxs) +
                               ", expected west_east + 1 = " + std::to_string(*nx + 1) + ": inconsistent sizes"));
  if (tPos >= 0) {
    l.time.dimId = tDim;
    l.time.count = *nT;
  }
  // Horizontal: the mass-point XLAT / XLONG.
  auto lat = f.findVariable(root, "XLAT");
  auto lon = f.findVariable(root, "XLONG");
  if (!lat) return makeError(f.message("WRF file without the variable 'XLAT' (latitude of the mass points)"));
  if (!lon) return makeError(f.message("WRF file without the variable 'XLONG' (longitude of the mass points)"));
  for (const io::NcVar* c : {&*lat, &*lon}) {
    const std::size_t r = c->dimIds.size();
    if (r < 2 || c->dimIds[r - 2] != l.yDim || c->dimIds[r - 1] != l.xDim || (r == 3 && c->dimIds[0] != tDim) || r > 3)
      return makeError(f.message("variable '" + c->name + "' is not on (Time,) south_north, west_east (" +
                                 dimList(f, *c) + "): inconsistent sizes"));
  }
  l.curvilinear = true;
  l.lat = *lat;
  l.lon = *lon;
  for (const io::NcVar* c : {&l.lat, &l.lon})
    if (auto st = checkWhole(f, *c); !st) return st.forwardError();
  // The time axis and the variable's own attributes: the end of either kind of layout.
  auto finish = [&]() -> Result<GridLayout> {
    if (auto st = wrfTimeSpec(f, l, tDim); !st) return st.forwardError();
    l.units = attrText(f, v, "units");
    l.standardName = attrText(f, v, "standard_name");
    l.longName = attrText(f, v, "long_name");
    if (l.longName.empty()) l.longName = attrText(f, v, "description");
    return l;
  };
  if (l.singleLevel) {
    l.vertical.kind = VerticalKind::HeightAboveSeaLevel;
    l.vertical.fileLevels = 1;
    return finish();
  }
  // Vertical: geopotential on the W levels, else pressure.
  VerticalSpec& vs = l.vertical;
  vs.kind = VerticalKind::WrfEta;
  vs.fileLevels = *nz;
  vs.upward = true;  // WRF counts levels from the surface up
  auto onGrid = [&](const char* name, int zId) -> Result<std::optional<io::NcVar>> {
    auto c = f.findVariable(root, name);
    if (!c) return std::optional<io::NcVar>();
    const std::vector<int> want = {tDim, zId, l.yDim, l.xDim};
    std::vector<int> have;
    for (int id : c->dimIds) have.push_back(id);
    if (have != want && !(have.size() == 3 && std::vector<int>(want.begin() + 1, want.end()) == have))
      return makeError(f.message("variable '" + c->name + "' is not on (Time, " + dimensionName(root, zId) +
                                 ", south_north, west_east) (" + dimList(f, *c) + "): inconsistent sizes"));
    return std::optional<io::NcVar>(*c);
  };
  if (l.zStagDim >= 0) {
    auto ph = onGrid("PH", l.zStagDim);
    if (!ph) return ph.forwardError();
    auto phb = onGrid("PHB", l.zStagDim);
    if (!phb) return phb.forwardError();
    vs.ph = *ph;
    vs.phb = *phb;
  }
  if (!vs.ph || !vs.phb) {
    vs.ph.reset();
    vs.phb.reset();
  }
  // The pressure P + PB: the heights when there is no PH/PHB, else the isobaric surfaces' pressure
  // (then a P or PB on other dimensions only leaves the file without isobaric surfaces).
  auto p = onGrid("P", l.zDim);
  auto pb = onGrid("PB", l.zDim);
  if (vs.ph && (!p || !pb)) {
    p = std::optional<io::NcVar>();
    pb = std::optional<io::NcVar>();
  }
  if (!p) return p.forwardError();
  if (!pb) return pb.forwardError();
  if (*p && *pb) {
    vs.p = *p;
    vs.pb = *pb;
  } else if (!vs.ph) {
    return makeError(f.message("variable '" + v.name +
                               "': unknown vertical coordinate: the WRF file has neither PH and PHB "
                               "(geopotential) nor P and PB (pressure)"));
  }
  for (const auto* c : {&vs.ph, &vs.phb, &vs.p, &vs.pb})
    if (*c)
      if (auto st = checkWhole(f, **c); !st) return st.forwardError();
  if (auto znu = f.findVariable(root, "ZNU")) {
    if (znu->shape.size() >= 1 && znu->dimIds.back() == l.zDim) vs.znu = *znu;
  }
  return finish();
}

Result<GridLayout> analyseCf(const io::NetcdfFile& f, const io::NcVar& v, bool allowSingleLevel) {
  GridLayout l;
  l.var = v;
  if (v.type == NC_CHAR || v.type == NC_STRING) return varError(f, v, "holds text, not numbers");
  if (v.dimIds.size() < (allowSingleLevel ? 2u : 3u))
    return varError(
        f, v,
        "has " + std::to_string(v.dimIds.size()) +
            " dimensions; a grid volume needs a vertical and two horizontal ones" +
            (v.dimIds.size() == 2 ? " (a 2-D field: draw it as a map, --surface FILE --surface-var NAME)" : ""));
  // 1. Curvilinear: 2-D latitude/longitude named in `coordinates`. Every variable it names must
  // be in the file.
  std::optional<io::NcVar> lat2, lon2;
  std::vector<std::string> missing;
  for (const std::string& name : tokens(attrText(f, v, "coordinates")))
    if (!findInScope(f, v.groupId, name)) missing.push_back("'" + name + "'");
  if (!missing.empty()) {
    std::string s;
    for (const auto& m : missing) s.append(s.empty() ? "" : ", ").append(m);
    return varError(f, v,
                    "its coordinates attribute ('" + attrText(f, v, "coordinates") + "') names " +
                        (missing.size() == 1 ? "variable " : "variables ") + s + ", which the file lacks");
  }
  for (const std::string& name : tokens(attrText(f, v, "coordinates"))) {
    auto c = findInScope(f, v.groupId, name);
    if (!c || c->dimIds.size() < 2) continue;
    const Role r = roleOf(f, *c);
    if (r == Role::Lat && !lat2) lat2 = c;
    if (r == Role::Lon && !lon2) lon2 = c;
  }
  if (lat2.has_value() != lon2.has_value())
    return varError(f, v,
                    "its coordinates attribute names a 2-D " + std::string(lat2 ? "latitude" : "longitude") +
                        " but no 2-D " + (lat2 ? "longitude" : "latitude"));
  if (lat2) {
    if (lat2->dimIds != lon2->dimIds)
      return makeError(f.message("variables '" + lat2->name + "' and '" + lon2->name +
                                 "' (2-D latitude and longitude of '" + v.name +
                                 "') have different dimensions: inconsistent sizes"));
    const std::size_t r = lat2->dimIds.size();
    l.yDim = lat2->dimIds[r - 2];
    l.xDim = lat2->dimIds[r - 1];
    if (positionOf(v, l.yDim) < 0 || positionOf(v, l.xDim) < 0)
      return makeError(f.message("variable '" + lat2->name + "' (latitude of '" + v.name + "') is on " +
                                 dimList(f, *lat2) + ", which are not dimensions of '" + v.name + "' (" +
                                 dimList(f, v) + "): inconsistent sizes"));
    l.curvilinear = true;
    l.lat = *lat2;
    l.lon = *lon2;
    l.ny = lat2->shape[r - 2];
    l.nx = lat2->shape[r - 1];
  }
  // 2. The role of every dimension from its coordinate variable. A dimension named or marked
  // as an ensemble or another index (month ...) is never the vertical one; the others that are
  // neither horizontal, vertical nor time are read at one index (extras).
  std::optional<io::NcVar> zCoord;
  int tPos = -1, zPos = -1;
  struct Other {
    int id = -1;
    std::size_t length = 0;
    std::string name, description;
    std::optional<io::NcVar> coordinate;
    IndexKind kind = IndexKind::None;
  };
  std::vector<Other> others;
  for (std::size_t d = 0; d < v.dimIds.size(); ++d) {
    const int id = v.dimIds[d];
    const int p = static_cast<int>(d);
    if (id == l.xDim || id == l.yDim) continue;
    auto c = coordinateVariable(f, v, id);
    const std::string dn = dimensionName(v.groupId, id);
    const IndexKind index = indexKindOf(f, dn, c);
    const Role r = c && index == IndexKind::None ? roleOf(f, *c) : Role::None;
    if (!l.curvilinear && r == Role::Lat && l.yDim < 0) {
      l.yDim = id;
      l.lat = *c;
      l.ny = v.shape[d];
    } else if (!l.curvilinear && r == Role::Lon && l.xDim < 0) {
      l.xDim = id;
      l.lon = *c;
      l.nx = v.shape[d];
    } else if (tPos < 0 && (r == Role::Time || (!c && (dn == "time" || dn == "Time" || dn == "t" || dn == "TIME")))) {
      tPos = p;
      l.time.dimId = id;
      l.time.count = v.shape[d];
      if (c) {
        if (auto st = timeSpecFromCoordinate(f, l.time, *c); !st) return st.forwardError();
      }
    } else if (r == Role::Vertical) {
      // A second vertical coordinate of length 1 (a single height) is read at its one index.
      if (zPos >= 0 && v.shape[d] == 1) continue;
      if (zPos >= 0 && v.shape[static_cast<std::size_t>(zPos)] != 1)
        return varError(f, v,
                        "dimensions '" + dimensionName(v.groupId, l.zDim) + "' and '" + dn +
                            "' are both vertical coordinates: which one the levels are is ambiguous");
      zPos = p;
      l.zDim = id;
      zCoord = c;
    } else if (v.shape[d] != 1 || index != IndexKind::None) {
      Other o;
      o.id = id;
      o.length = v.shape[d];
      o.name = dn;
      o.kind = index;
      if (c && io::ncTypeIsNumeric(c->type)) o.coordinate = c;
      o.description =
          c ? "dimension '" + dn + "' (coordinate variable '" + c->name + "', units '" + attrText(f, *c, "units") + "')"
            : "dimension '" + dn + "' (no coordinate variable)";
      others.push_back(std::move(o));
    }
  }
  if (l.yDim < 0 || l.xDim < 0)
    return varError(f, v,
                    "no latitude/longitude: neither 1-D coordinate variables with units degrees_north / "
                    "degrees_east (or standard_name latitude / longitude) among its dimensions (" +
                        dimList(f, v) + "), nor 2-D ones named in a coordinates attribute");
  if (zPos < 0) {
    // No vertical dimension: one of the others may be a vertical coordinate of a kind this reader
    // does not know; say so unless every one of them is a named index.
    std::string s;
    for (const Other& o : others)
      if (o.kind == IndexKind::None && o.length != 1) s.append(s.empty() ? "" : "; ").append(o.description);
    if (!s.empty())
      return varError(f, v,
                      "unknown vertical coordinate: " + s +
                          " is not a vertical coordinate this reader knows (a pressure, a length, "
                          "geopotential metres, or a parametric coordinate with formula_terms)" +
                          (unitDatabaseProblem().empty() ? std::string() : " (" + unitDatabaseProblem() + ")"));
    if (!allowSingleLevel)
      return varError(f, v,
                      "has no vertical dimension (dimensions: " + dimList(f, v) +
                          "): a 2-D field, not a volume (draw it as a map: --surface FILE --surface-var NAME)");
    l.singleLevel = true;
  }
  for (const Other& o : others) {
    if (o.length == 0) return varError(f, v, "has an empty dimension (" + dimList(f, v) + ")");
    ExtraDim e;
    e.dimId = o.id;
    e.name = o.name;
    e.length = o.length;
    e.coordinate = o.coordinate;
    e.ensemble = o.kind == IndexKind::Ensemble;
    if (e.coordinate)
      if (auto st = checkWhole(f, *e.coordinate); !st) return st.forwardError();
    l.extras.push_back(std::move(e));
  }
  const int yPos = positionOf(v, l.yDim), xPos = positionOf(v, l.xDim);
  if (l.singleLevel) {
    if (!(tPos < yPos && yPos < xPos))
      return varError(
          f, v, "dimension order (" + dimList(f, v) + ") is not supported: expected (time,) latitude/y, longitude/x");
    if (l.nx == 0 || l.ny == 0) return varError(f, v, "has an empty dimension (" + dimList(f, v) + ")");
    for (const io::NcVar* c : {&l.lat, &l.lon})
      if (auto st = checkWhole(f, *c); !st) return st.forwardError();
    if (l.time.coordinate) {
      if (auto st = checkWhole(f, *l.time.coordinate); !st) return st.forwardError();
    } else if (l.time.dimId >= 0) {
      if (auto st = f.checkReadable(v, l.time.count, 1); !st) return st.forwardError();
    }
    if (l.curvilinear)
      if (auto st = checkSupportDims(f, l.lat, v, {l.time.dimId, l.yDim, l.xDim}, "latitude"); !st)
        return st.forwardError();
    l.vertical.kind = VerticalKind::HeightAboveSeaLevel;
    l.vertical.fileLevels = 1;
    l.units = attrText(f, v, "units");
    l.standardName = attrText(f, v, "standard_name");
    l.longName = attrText(f, v, "long_name");
    return l;
  }
  if (!(tPos < zPos && zPos < yPos && yPos < xPos))
    return varError(
        f, v,
        "dimension order (" + dimList(f, v) + ") is not supported: expected (time,) level, latitude/y, longitude/x");
  if (l.nx == 0 || l.ny == 0 || v.shape[static_cast<std::size_t>(zPos)] == 0)
    return varError(f, v, "has an empty dimension (" + dimList(f, v) + ")");
  for (const io::NcVar* c : {&l.lat, &l.lon, &*zCoord})
    if (auto st = checkWhole(f, *c); !st) return st.forwardError();
  if (l.time.coordinate) {
    if (auto st = checkWhole(f, *l.time.coordinate); !st) return st.forwardError();
  } else if (l.time.dimId >= 0) {
    // No coordinate to check: the variable must at least hold one byte per time step.
    if (auto st = f.checkReadable(v, l.time.count, 1); !st) return st.forwardError();
  }
  if (auto st = cfVertical(f, l, *zCoord); !st) return st.forwardError();
  for (const auto& [term, tv] : l.vertical.terms)
    if (auto st = checkWhole(f, tv); !st) return st.forwardError();
  // Curvilinear coordinates may carry the time dimension too (moving grids), nothing else.
  if (l.curvilinear) {
    if (auto st = checkSupportDims(f, l.lat, v, {l.time.dimId, l.yDim, l.xDim}, "latitude"); !st)
      return st.forwardError();
  }
  l.units = attrText(f, v, "units");
  l.standardName = attrText(f, v, "standard_name");
  l.longName = attrText(f, v, "long_name");
  return l;
}

}  // namespace

Result<GridLayout> analyse(const io::NetcdfFile& f, const FileKind& kind, const io::NcVar& v, bool allowSingleLevel) {
  return kind.wrf ? analyseWrf(f, v, allowSingleLevel) : analyseCf(f, v, allowSingleLevel);
}

Result<io::NcVar> findGridVariable(const io::NetcdfFile& f, const std::string& name) {
  if (name.find('/') != std::string::npos) {
    std::vector<std::string> parts;
    std::string cur;
    for (char c : name) {
      if (c == '/') {
        if (!cur.empty()) parts.push_back(cur);
        cur.clear();
      } else {
        cur.push_back(c);
      }
    }
    if (!cur.empty()) parts.push_back(cur);
    int g = f.root();
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      auto child = f.findGroup(g, parts[i]);
      if (!child) return makeError(f.message("no group '" + parts[i] + "' on the path of variable '" + name + "'"));
      g = *child;
    }
    if (parts.empty()) return makeError(f.message("empty variable name"));
    return f.variable(g, parts.back());
  }
  std::vector<io::NcVar> found;
  for (int g : allGroups(f))
    if (auto v = f.findVariable(g, name)) found.push_back(*v);
  if (found.size() == 1) return found.front();
  if (found.size() > 1) {
    std::string s;
    for (const auto& v : found) s.append(s.empty() ? "" : ", ").append(v.name);
    return makeError(f.message("variable name '" + name + "' is ambiguous (" + s + "): give the full path"));
  }
  std::string s;
  for (const GridVariableInfo& v : listVariables(f, fileKind(f)))
    if (v.onGrid) s.append(s.empty() ? "" : ", ").append(v.name);
  return makeError(f.message("no variable '" + name + "' (grid variables: " + (s.empty() ? "none" : s) + ")"));
}

std::vector<GridVariableInfo> listVariables(const io::NetcdfFile& f, const FileKind& kind) {
  std::vector<GridVariableInfo> out;
  for (int g : allGroups(f)) {
    for (const io::NcVar& v : f.variables(g)) {
      GridVariableInfo info;
      info.name = v.name;
      for (int id : v.dimIds) info.dimensions.push_back(dimensionName(g, id));
      info.shape = v.shape;
      info.type = typeName(v.type);
      info.units = attrText(f, v, "units");
      info.standardName = attrText(f, v, "standard_name");
      info.longName = attrText(f, v, "long_name");
      if (info.longName.empty() && kind.wrf) info.longName = attrText(f, v, "description");
      info.packed = f.hasAttribute(g, v.varId, "scale_factor") || f.hasAttribute(g, v.varId, "add_offset");
      info.onGrid = v.dimIds.size() >= 3 && static_cast<bool>(analyse(f, kind, v));
      out.push_back(std::move(info));
    }
  }
  return out;
}

Result<std::vector<GridExtraDimension>> resolveExtraDimensions(const io::NetcdfFile& f, const GridLayout& l,
                                                               const GridReadOptions& read,
                                                               std::map<int, std::size_t>* dimIndex) {
  auto listExtras = [&] {
    std::string s;
    for (const ExtraDim& e : l.extras)
      s.append(s.empty() ? "" : ", ").append("'" + e.name + "' (" + std::to_string(e.length) + ")");
    return s.empty() ? std::string("none") : s;
  };
  for (const auto& chosen : read.extraIndex) {
    const std::string& name = chosen.first;  // not a structured binding: lambdas capture it (clang)
    if (std::none_of(l.extras.begin(), l.extras.end(), [&](const ExtraDim& e) { return e.name == name; }))
      return varError(f, l.var,
                      "no dimension '" + name +
                          "' to choose an index along (its dimensions that are neither horizontal, vertical nor "
                          "time: " +
                          listExtras() + ")");
  }
  const bool hasEnsemble = std::any_of(l.extras.begin(), l.extras.end(), [](const ExtraDim& e) { return e.ensemble; });
  if (read.member >= 0 && !hasEnsemble)
    return varError(f, l.var,
                    "has no ensemble dimension; cannot select member " + std::to_string(read.member) +
                        " (its dimensions that are neither horizontal, vertical nor time: " + listExtras() + ")");
  std::vector<GridExtraDimension> out;
  for (const ExtraDim& e : l.extras) {
    GridExtraDimension x;
    x.name = e.name;
    x.length = e.length;
    x.ensemble = e.ensemble;
    std::vector<double> values;
    if (e.coordinate) {
      auto v = readPicked<double>(f, *e.coordinate, {iota(0, e.length)});
      if (!v) return v.forwardError();
      values = std::move(*v);
      x.units = attrText(f, *e.coordinate, "units");
    }
    if (auto it = read.extraIndex.find(e.name); it != read.extraIndex.end()) {
      if (it->second >= e.length)
        return varError(f, l.var,
                        "index " + std::to_string(it->second) + " along dimension '" + e.name + "' is beyond its " +
                            std::to_string(e.length) + (e.length == 1 ? " value" : " values"));
      x.index = it->second;
    } else if (e.ensemble && read.member >= 0) {
      // The member as the file numbers it: its coordinate value, else its index.
      bool found = false;
      for (std::size_t i = 0; i < e.length && !found; ++i) {
        const double want = static_cast<double>(read.member);
        if (values.empty() ? static_cast<double>(i) == want : values[i] == want) {
          x.index = i;
          found = true;
        }
      }
      if (!found) {
        std::string list;
        const std::size_t shown = std::min<std::size_t>(e.length, 20);
        for (std::size_t i = 0; i < shown; ++i)
          list.append(i ? ", " : "").append(values.empty() ? std::to_string(i) : num(values[i], 0));
        if (shown < e.length) list.append(", ...");
        return varError(f, l.var,
                        "no ensemble member " + std::to_string(read.member) + " along dimension '" + e.name +
                            "' (members: " + list + ")");
      }
    }
    if (!values.empty()) x.value = values[x.index];
    if (dimIndex) (*dimIndex)[e.dimId] = x.index;
    out.push_back(std::move(x));
  }
  return out;
}

long memberOf(const std::vector<GridExtraDimension>& extras) {
  for (const GridExtraDimension& e : extras) {
    if (!e.ensemble) continue;
    if (std::isfinite(e.value) && e.value == std::floor(e.value) && std::fabs(e.value) < 1e15)
      return static_cast<long>(e.value);
    return static_cast<long>(e.index);
  }
  return -1;
}

Result<std::vector<std::string>> readTimes(const io::NetcdfFile& f, const TimeSpec& t) {
  std::vector<std::string> out(t.dimId < 0 ? 0 : t.count);
  if (t.dimId < 0) return out;
  if (t.wrfTimes) {
    for (std::size_t i = 0; i < t.count; ++i) {
      auto s = f.readText(*t.wrfTimes, i);
      if (!s) return s.forwardError();
      std::string x = *s;
      if (x.size() > 10 && x[10] == '_') x[10] = 'T';
      out[i] = normalizeIso8601(x);
    }
    return out;
  }
  if (t.coordinate && t.parsed) {
    auto values = readPicked<double>(f, *t.coordinate, {iota(0, t.count)});
    if (!values) return values.forwardError();
    for (std::size_t i = 0; i < t.count; ++i) out[i] = cfTimeToIso8601(*t.parsed, (*values)[i]);
  }
  return out;
}

}  // namespace atmoglobe::volume::grid
