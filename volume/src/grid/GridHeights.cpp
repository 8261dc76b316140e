// The vertical coordinates of forecast grids: each kind's levels in the file (values, direction,
// the crop's picks) and, one function per kind, the heights above the WGS84 ellipsoid of every
// column and level of a selection (rules and sources: docs/grids.md, "Vertical coordinates").
// The kinds are found from the file's metadata in GridLayout.cpp.
#include "GridInternal.h"

#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <cmath>
#include <limits>

namespace atmoglobe::volume {

const char* toString(VerticalKind k) {
  switch (k) {
    case VerticalKind::HeightAboveEllipsoid: return "height above ellipsoid";
    case VerticalKind::HeightAboveSeaLevel: return "height above sea level";
    case VerticalKind::HeightAboveGround: return "height above ground";
    case VerticalKind::GeopotentialHeight: return "geopotential height";
    case VerticalKind::Pressure: return "pressure";
    case VerticalKind::HybridSigmaPressure: return "hybrid sigma-pressure";
    case VerticalKind::Sigma: return "sigma";
    case VerticalKind::HybridHeight: return "hybrid height";
    case VerticalKind::WrfEta: return "WRF eta";
    case VerticalKind::GeneralVertical: return "generalised vertical (ICON/COSMO)";
  }
  return "?";
}

const char* toString(HeightSource s) {
  switch (s) {
    case HeightSource::Coordinate: return "coordinate";
    case HeightSource::GeopotentialField: return "geopotential field";
    case HeightSource::WrfGeopotential: return "WRF geopotential (PH+PHB)";
    case HeightSource::StandardAtmosphere: return "standard atmosphere";
    case HeightSource::HydrostaticIntegration: return "hydrostatic integration";
    case HeightSource::HeightField: return "height field";
  }
  return "?";
}

namespace grid {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A formula term (formula_terms) read whole, in SI units (termToSi); every value must be finite.
Result<std::vector<double>> readTerm(const io::NetcdfFile& f, const VerticalSpec& vs, const std::string& term) {
  const io::NcVar& v = vs.terms.at(term);
  Picks p;
  for (std::size_t d = 0; d < v.shape.size(); ++d) p.push_back(iota(0, v.shape[d]));
  auto r = readPicked<double>(f, v, p);
  if (!r) return r.forwardError();
  const double k = vs.termToSi.count(term) ? vs.termToSi.at(term) : 1.0;
  for (std::size_t i = 0; i < r->size(); ++i) {
    if (!std::isfinite((*r)[i]))
      return varError(f, v, "value " + std::to_string(i) + " is missing or not finite (term '" + term + "')");
    (*r)[i] *= k;
  }
  return r;
}

/// The reference pressure p0 (Pa) of hybrid sigma-pressure levels in the a p0 + b ps form: the
/// term 'p0', or the default the layout chose (CAM's 100000 Pa) when the file has none.
Result<double> referencePressurePa(const io::NetcdfFile& f, const VerticalSpec& vs) {
  if (vs.defaultP0Pa) return *vs.defaultP0Pa;
  auto p0 = readTerm(f, vs, "p0");
  if (!p0) return p0.forwardError();
  return p0->front();
}

/// Picks for a variable on (some of) the grid variable's dimensions. `zStagger`: the variable
/// is on WRF's W levels (levels k and k+1 of each mass level k are read).
Result<Picks> supportPicks(const io::NetcdfFile& f, const GridLayout& l, const Selection& s, const io::NcVar& v) {
  Picks p;
  for (std::size_t d = 0; d < v.dimIds.size(); ++d) {
    const int id = v.dimIds[d];
    if (id == l.time.dimId && l.time.dimId >= 0) p.push_back({s.time});
    else if (id == l.zDim) p.push_back(s.levels);
    else if (id == l.zStagDim && l.zStagDim >= 0) {
      std::vector<std::size_t> z = s.levels;
      z.push_back(s.levels.back() + 1);
      p.push_back(std::move(z));
    } else if (id == l.yDim) p.push_back(s.hz->rows);
    else if (id == l.xDim) p.push_back(s.hz->cols);
    else if (auto e = s.extraIndex.find(id); e != s.extraIndex.end()) p.push_back({e->second});
    else if (v.shape[d] == 1) p.push_back({0});
    else
      return varError(f, v,
                      "dimension '" + dimensionName(v.groupId, id) + "' is not a dimension of '" + l.var.name +
                          "': inconsistent sizes");
  }
  return p;
}

/// What every kind's height function works from: the file, the variable's layout, its levels,
/// the selection and the position of each selected column.
struct HeightInput {
  const io::NetcdfFile& f;
  const GridLayout& l;
  const Levels& lv;
  const Selection& s;
  std::size_t nz = 0, nx = 0, nc = 0;  ///< levels, columns per row, columns
  std::vector<double> latDeg, lonDeg;  ///< per column, row-major
  std::string coordName;               ///< "'NAME'" of the vertical coordinate ("" without one)

  HeightInput(const io::NetcdfFile& file, const GridLayout& layout, const Levels& levels, const Selection& selection)
      : f(file), l(layout), lv(levels), s(selection) {
    const Horizontal& hz = *s.hz;
    nz = s.levels.size();
    nx = hz.cols.size();
    nc = hz.rows.size() * nx;
    coordName = l.vertical.coordinate ? "'" + l.vertical.coordinate->name + "'" : std::string();
    latDeg.resize(nc);
    lonDeg.resize(nc);
    for (std::size_t j = 0; j < hz.rows.size(); ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        latDeg[j * nx + i] = hz.latAt(j, i, l.curvilinear);
        lonDeg[j * nx + i] = hz.lonAt(j, i, l.curvilinear);
      }
  }

  /// A field on (some of) the grid variable's dimensions, read over the selection.
  Status readField(const io::NcVar& v, std::vector<double>* values) const {
    auto p = supportPicks(f, l, s, v);
    if (!p) return p.forwardError();
    auto r = readPicked<double>(f, v, *p);
    if (!r) return r.forwardError();
    *values = std::move(*r);
    return Ok{};
  }
  /// Geopotential heights (gpm, nz x nc) -> geometric heights (m) in place.
  void toGeometric(std::vector<double>& geopotentialHeight) const {
    geopotentialToGeometricHeights(latDeg, geopotentialHeight);
  }
  /// "row R, column C" of column c, in file indices (for errors).
  std::string rowColumn(std::size_t c) const {
    return "row " + std::to_string(s.hz->rows[c / nx]) + ", column " + std::to_string(s.hz->cols[c % nx]);
  }
  /// The coordinate value (SI) of selected level k (counted from the bottom).
  double levelValueSi(std::size_t k) const { return lv.valuesSi[s.levels[k]]; }
};

constexpr const char* kStandardAtmosphereNote =
    "standard-atmosphere height of each pressure (APPROXIMATE: a real pressure level lies up to a few hundred "
    "metres away)";

/// Pressure (Pa) per level (`perColumn` false: nz values) or per level and column (nz x nc) ->
/// heights above mean sea level: from the file's geopotential field if it has one, else the
/// standard atmosphere (approximate). `what` opens the note.
Status pressureToHeights(const HeightInput& in, const std::vector<double>& pressurePa, bool perColumn,
                         const std::string& what, Heights& out) {
  const VerticalSpec& vs = in.l.vertical;
  if (vs.geopotential) {
    std::vector<double> g;
    if (auto st = in.readField(*vs.geopotential, &g); !st) return st;
    for (double& x : g) x *= vs.geopotentialToGpm;
    heightsFromGeopotentialField(in.latDeg, std::move(g), vs.geopotential->name, vs.geopotentialToGpm != 1.0, what,
                                 out);
    return Ok{};
  }
  heightsFromStandardAtmosphere(in.latDeg, in.nz, pressurePa, perColumn, what, out);
  return Ok{};
}

/// Lengths above the surface altitude of each column (heights above ground); without a surface
/// altitude in the file, the ground at sea level (approximate).
Status addSurfaceAltitude(const HeightInput& in, Heights& out) {
  const VerticalSpec& vs = in.l.vertical;
  if (!vs.surfaceAltitude) {
    out.approximate = true;
    out.note = "heights above ground from " + in.coordName + " (" + vs.datumReason +
               "); the file has no surface altitude, so the ground is taken at sea level (APPROXIMATE)";
    return Ok{};
  }
  std::vector<double> surf;
  if (auto st = in.readField(*vs.surfaceAltitude, &surf); !st) return st.forwardError();
  for (std::size_t c = 0; c < in.nc; ++c) {
    if (!std::isfinite(surf[c]))
      return varError(in.f, *vs.surfaceAltitude, "surface altitude missing or not finite at " + in.rowColumn(c));
    surf[c] *= vs.surfaceToMeters;
  }
  for (std::size_t k = 0; k < in.nz; ++k)
    for (std::size_t c = 0; c < in.nc; ++c) out.h[k * in.nc + c] += surf[c];
  out.note = "heights above ground from " + in.coordName + " (" + vs.datumReason + ") + the surface altitude '" +
             vs.surfaceAltitude->name + "' -> above mean sea level";
  return Ok{};
}

/// Heights above the ellipsoid, sea level or ground (CF height, altitude, depth): the coordinate's
/// lengths (sign-flipped when counted downwards) from the datum the layout found.
Status lengthHeights(const HeightInput& in, Heights& out) {
  const VerticalSpec& vs = in.l.vertical;
  const double sign = vs.positiveDown ? -1.0 : 1.0;
  for (std::size_t k = 0; k < in.nz; ++k)
    for (std::size_t c = 0; c < in.nc; ++c) out.h[k * in.nc + c] = sign * in.levelValueSi(k);
  switch (vs.datum) {
    case LengthDatum::Ellipsoid:
      out.note = "heights above the WGS84 ellipsoid from " + in.coordName + " (" + vs.datumReason + ")";
      return Ok{};
    case LengthDatum::Ground: return addSurfaceAltitude(in, out);
    case LengthDatum::Unknown:
      out.approximate = true;
      out.note = "lengths from " + in.coordName + " whose datum the file does not state (" + vs.datumReason +
                 "), taken as heights above mean sea level (APPROXIMATE)";
      return Ok{};
    case LengthDatum::SeaLevel:
      out.note = "heights above mean sea level from " + in.coordName + " (" + vs.datumReason + ")";
      return Ok{};
  }
  return Ok{};
}

/// Geopotential height levels (gpm) -> geometric heights above mean sea level.
Status geopotentialHeights(const HeightInput& in, Heights& out) {
  for (std::size_t k = 0; k < in.nz; ++k)
    for (std::size_t c = 0; c < in.nc; ++c) out.h[k * in.nc + c] = in.levelValueSi(k);
  in.toGeometric(out.h);
  out.note = "geopotential heights from " + in.coordName +
             " (about heights above mean sea level) -> geometric heights (WGS84 normal gravity)";
  return Ok{};
}

/// Pressure levels: one pressure per level for every column.
Status pressureHeights(const HeightInput& in, Heights& out) {
  std::vector<double> p(in.nz);
  for (std::size_t k = 0; k < in.nz; ++k) p[k] = in.levelValueSi(k);
  return pressureToHeights(in, p, false, "pressure levels " + in.coordName, out);
}

/// The surface pressure of a terrain-following pressure coordinate (the term 'ps') over the
/// selection, in the file's units (checked once the pressures are made), and its factor to Pa.
struct SurfacePressure {
  std::vector<double> values;
  double toPa = 1.0;
};

Result<SurfacePressure> readSurfacePressure(const HeightInput& in) {
  SurfacePressure ps;
  if (auto st = in.readField(in.l.vertical.terms.at("ps"), &ps.values); !st) return st.forwardError();
  ps.toPa = in.l.vertical.termToSi.at("ps");
  return ps;
}

/// Terrain-following pressure levels -> heights: the pressure (Pa) of each selected level and
/// column is `pressurePa(file level, the column's surface pressure in file units)`; the surface
/// pressure must be finite and positive everywhere.
template <class PressureOf>
Status columnPressureToHeights(const HeightInput& in, const SurfacePressure& ps, const PressureOf& pressurePa,
                               const std::string& what, Heights& out) {
  std::vector<double> p(in.nz * in.nc);
  for (std::size_t k = 0; k < in.nz; ++k)
    for (std::size_t c = 0; c < in.nc; ++c) p[k * in.nc + c] = pressurePa(in.s.levels[k], ps.values[c]);
  const io::NcVar& psVar = in.l.vertical.terms.at("ps");
  for (std::size_t c = 0; c < in.nc; ++c)
    if (!std::isfinite(ps.values[c]) || !(ps.values[c] > 0))
      return varError(in.f, psVar, "surface pressure missing or not positive at " + in.rowColumn(c));
  out.fromVariable = psVar.name;
  auto st = pressureToHeights(in, p, true, what, out);
  out.pressurePa = std::move(p);
  return st;
}

/// Hybrid sigma-pressure levels (CF atmosphere_hybrid_sigma_pressure_coordinate):
/// p = a p0 + b ps, or ap + b ps.
Status hybridSigmaPressureHeights(const HeightInput& in, Heights& out) {
  const VerticalSpec& vs = in.l.vertical;
  auto ps = readSurfacePressure(in);
  if (!ps) return ps.forwardError();
  std::string terms;
  auto b = readTerm(in.f, vs, "b");
  if (!b) return b.forwardError();
  std::vector<double> a;
  double p0 = 1.0;
  if (vs.terms.count("ap")) {
    auto ap = readTerm(in.f, vs, "ap");
    if (!ap) return ap.forwardError();
    a = *ap;
    terms = "p = ap + b ps with '" + vs.terms.at("ap").name + "', '" + vs.terms.at("b").name + "', '" +
            vs.terms.at("ps").name + "'";
  } else {
    auto aa = readTerm(in.f, vs, "a");
    if (!aa) return aa.forwardError();
    a = *aa;
    auto pp = referencePressurePa(in.f, vs);
    if (!pp) return pp.forwardError();
    p0 = *pp;
    const std::string p0Text = vs.defaultP0Pa ? "p0 = " + num(p0, 0) + " Pa (CAM's default: " + vs.defaultP0Reason + ")"
                                              : "'" + vs.terms.at("p0").name + "'";
    terms = "p = a p0 + b ps with '" + vs.terms.at("a").name + "', " + p0Text + ", '" + vs.terms.at("b").name + "', '" +
            vs.terms.at("ps").name + "'";
  }
  if (vs.termsSource != "formula_terms") terms += ", named by the " + vs.termsSource;
  const double psToPa = ps->toPa;
  return columnPressureToHeights(
      in, *ps, [&](std::size_t level, double surface) { return a[level] * p0 + (*b)[level] * surface * psToPa; },
      "hybrid sigma-pressure levels " + in.coordName + " (" + terms + ")", out);
}

/// Sigma levels (CF atmosphere_sigma_coordinate): p = ptop + sigma (ps - ptop).
Status sigmaHeights(const HeightInput& in, Heights& out) {
  const VerticalSpec& vs = in.l.vertical;
  auto ps = readSurfacePressure(in);
  if (!ps) return ps.forwardError();
  auto sg = readTerm(in.f, vs, "sigma");
  if (!sg) return sg.forwardError();
  auto pt = readTerm(in.f, vs, "ptop");
  if (!pt) return pt.forwardError();
  const double ptop = pt->front();
  const std::string terms = "p = ptop + sigma (ps - ptop) with '" + vs.terms.at("ptop").name + "', '" +
                            vs.terms.at("sigma").name + "', '" + vs.terms.at("ps").name + "'";
  const double psToPa = ps->toPa;
  return columnPressureToHeights(
      in, *ps, [&](std::size_t level, double surface) { return ptop + (*sg)[level] * (surface * psToPa - ptop); },
      "sigma levels " + in.coordName + " (" + terms + ")", out);
}

/// Hybrid height levels (CF atmosphere_hybrid_height_coordinate): z = a + b orog, above the geoid.
Status hybridHeightHeights(const HeightInput& in, Heights& out) {
  const VerticalSpec& vs = in.l.vertical;
  auto a = readTerm(in.f, vs, "a");
  if (!a) return a.forwardError();
  auto b = readTerm(in.f, vs, "b");
  if (!b) return b.forwardError();
  std::vector<double> orog;
  if (auto st = in.readField(vs.terms.at("orog"), &orog); !st) return st.forwardError();
  const double k0 = vs.termToSi.at("orog");
  const std::vector<std::size_t>& levels = in.s.levels;
  for (std::size_t c = 0; c < in.nc; ++c) {
    if (!std::isfinite(orog[c]))
      return varError(in.f, vs.terms.at("orog"), "surface altitude missing or not finite at " + in.rowColumn(c));
    for (std::size_t k = 0; k < in.nz; ++k) out.h[k * in.nc + c] = (*a)[levels[k]] + (*b)[levels[k]] * orog[c] * k0;
  }
  out.note = "hybrid height levels " + in.coordName + ": z = a + b orog with '" + vs.terms.at("a").name + "', '" +
             vs.terms.at("b").name + "', '" + vs.terms.at("orog").name + "' (above the geoid)";
  return Ok{};
}

/// WRF eta levels: (PH + PHB) / 9.81 on the W levels averaged to mass levels (WRF's height above
/// sea level); without PH/PHB, the pressure P + PB. The level values are ZNU when present.
Status wrfEtaHeights(const HeightInput& in, Heights& out) {
  const VerticalSpec& vs = in.l.vertical;
  const GridLayout& l = in.l;
  if (vs.znu) {
    Picks zp;
    for (std::size_t d = 0; d < vs.znu->dimIds.size(); ++d)
      zp.push_back(vs.znu->dimIds[d] == l.zDim
                       ? in.s.levels
                       : std::vector<std::size_t>{vs.znu->dimIds[d] == l.time.dimId ? in.s.time : 0});
    if (auto znu = readPicked<double>(in.f, *vs.znu, zp)) {
      out.levelValues = *znu;
      out.levelUnits = "eta";
    }
  }
  if (!vs.ph) {
    std::vector<double> p, pb;
    if (auto st = in.readField(*vs.p, &p); !st) return st.forwardError();
    if (auto st = in.readField(*vs.pb, &pb); !st) return st.forwardError();
    for (std::size_t i = 0; i < p.size(); ++i) p[i] += pb[i];
    out.fromVariable = vs.p->name + "+" + vs.pb->name;
    auto st = pressureToHeights(in, p, true, "WRF eta levels without PH/PHB: pressure P+PB", out);
    out.pressurePa = std::move(p);
    return st;
  }
  std::vector<double> ph, phb;
  if (auto st = in.readField(*vs.ph, &ph); !st) return st.forwardError();
  if (auto st = in.readField(*vs.phb, &phb); !st) return st.forwardError();
  // (nz + 1) W levels -> nz mass levels.
  std::vector<double> w(ph.size());
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = (ph[i] + phb[i]) / kWrfGravity;
  std::vector<std::size_t> shape = {in.nz + 1, in.nc};
  averageAdjacent(w, shape, 0);
  out.h = std::move(w);
  out.source = HeightSource::WrfGeopotential;
  out.fromVariable = vs.ph->name + "+" + vs.phb->name;
  out.note =
      "WRF eta levels: (PH+PHB)/9.81 on the W levels averaged to mass levels: geopotential height with WRF's "
      "constant g, which WRF takes as height above mean sea level (its terrain HGT is PHB/9.81 at the surface)";
  return Ok{};
}

/// Heights above mean sea level -> above the WGS84 ellipsoid: + the EGM96 undulation of each
/// column, or (geoid off) as they are, said in the note.
Status seaLevelToEllipsoid(const HeightInput& in, bool useGeoid, Heights& out) {
  return addGeoidUndulation(in.f.path(), in.latDeg, in.lonDeg, useGeoid, out);
}

}  // namespace

void geopotentialToGeometricHeights(const std::vector<double>& latDeg, std::vector<double>& h) {
  const std::size_t nc = latDeg.size();
  std::vector<GeopotentialToGeometric> conv;
  conv.reserve(nc);
  for (std::size_t c = 0; c < nc; ++c) conv.emplace_back(latDeg[c]);
  for (std::size_t k = 0; nc > 0 && k < h.size() / nc; ++k) {
    double* hk = h.data() + k * nc;
    for (std::size_t c = 0; c < nc; ++c) hk[c] = conv[c](hk[c]);
  }
}

void heightsFromGeopotentialField(const std::vector<double>& latDeg, std::vector<double> gpm, const std::string& field,
                                  bool fromGeopotential, const std::string& what, Heights& out) {
  geopotentialToGeometricHeights(latDeg, gpm);
  out.h = std::move(gpm);
  out.source = HeightSource::GeopotentialField;
  out.fromVariable = field;
  out.note = what + " with the geopotential field '" + field + "'" +
             (fromGeopotential ? " (m2 s-2 / 9.80665 = geopotential height)" : " (geopotential height)") +
             " -> geometric height above mean sea level (WGS84 normal gravity)";
}

void heightsFromStandardAtmosphere(const std::vector<double>& latDeg, std::size_t nz,
                                   const std::vector<double>& pressurePa, bool perColumn, const std::string& what,
                                   Heights& out) {
  const std::size_t nc = latDeg.size();
  out.h.assign(nz * nc, kNaN);
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t c = 0; c < nc; ++c) {
      const double p = perColumn ? pressurePa[k * nc + c] : pressurePa[k];
      out.h[k * nc + c] = p > 0 ? standardAtmosphereGeopotentialHeightMeters(p) : kNaN;
    }
  geopotentialToGeometricHeights(latDeg, out.h);
  out.source = HeightSource::StandardAtmosphere;
  out.approximate = true;
  out.note =
      what + " without a geopotential field: " + kStandardAtmosphereNote + " -> geometric height above mean sea level";
}

Status addGeoidUndulation(const std::string& label, const std::vector<double>& latDeg,
                          const std::vector<double>& lonDeg, bool useGeoid, Heights& out) {
  if (!useGeoid) {
    out.note +=
        "; no geoid correction (geoid off): heights above sea level used as above the WGS84 ellipsoid, "
        "off by the undulation (-106..+85 m)";
    return Ok{};
  }
  const Result<GeoidGrid>& geoid = defaultEgm96Grid();
  if (!geoid) return makeError(label + ": " + geoid.error());
  const std::size_t nc = latDeg.size();
  std::vector<double> n(nc);
  for (std::size_t c = 0; c < nc; ++c) n[c] = geoid->undulationMeters(latDeg[c], lonDeg[c]);
  for (std::size_t k = 0; nc > 0 && k < out.h.size() / nc; ++k)
    for (std::size_t c = 0; c < nc; ++c) out.h[k * nc + c] += n[c];
  out.note += "; + EGM96 geoid undulation -> above the WGS84 ellipsoid";
  return Ok{};
}

Status wrfPressure(const io::NetcdfFile& f, const GridLayout& l, const Levels& lv, const Selection& s, Heights& out) {
  if (!out.pressurePa.empty() || l.vertical.kind != VerticalKind::WrfEta) return Ok{};
  const VerticalSpec& vs = l.vertical;
  if (!vs.p || !vs.pb) return makeError(f.path() + ": a WRF file without P and PB: no pressure on its eta levels");
  const HeightInput in(f, l, lv, s);
  std::vector<double> p, pb;
  if (auto st = in.readField(*vs.p, &p); !st) return st.forwardError();
  if (auto st = in.readField(*vs.pb, &pb); !st) return st.forwardError();
  for (std::size_t i = 0; i < p.size(); ++i) p[i] += pb[i];
  out.pressurePa = std::move(p);
  return Ok{};
}

Result<Heights> computeHeights(const io::NetcdfFile& f, const GridLayout& l, const Levels& lv, const Selection& s,
                               bool useGeoid) {
  const VerticalSpec& vs = l.vertical;
  const HeightInput in(f, l, lv, s);

  Heights out;
  out.h.assign(in.nz * in.nc, kNaN);
  out.fromVariable = vs.coordinate ? vs.coordinate->name : l.var.name;
  for (std::size_t k = 0; k < in.nz && !lv.valuesSi.empty(); ++k) out.levelValues.push_back(in.levelValueSi(k));
  out.levelUnits = lv.units;

  Status st = Ok{};
  bool seaLevel = true;  // the kind's heights are above sea level (the geoid); else above the ellipsoid
  if (l.singleLevel) {
    out.h.assign(in.nz * in.nc, 0.0);
    out.note = "a single-level field (no vertical dimension): placed at mean sea level";
    if (auto g = seaLevelToEllipsoid(in, useGeoid, out); !g) return g.forwardError();
    return out;
  }
  switch (vs.kind) {
    case VerticalKind::HeightAboveEllipsoid:
    case VerticalKind::HeightAboveSeaLevel:
    case VerticalKind::HeightAboveGround:
      st = lengthHeights(in, out);
      seaLevel = vs.datum != LengthDatum::Ellipsoid;
      break;
    case VerticalKind::GeopotentialHeight: st = geopotentialHeights(in, out); break;
    case VerticalKind::Pressure: st = pressureHeights(in, out); break;
    case VerticalKind::HybridSigmaPressure: st = hybridSigmaPressureHeights(in, out); break;
    case VerticalKind::Sigma: st = sigmaHeights(in, out); break;
    case VerticalKind::HybridHeight: st = hybridHeightHeights(in, out); break;
    case VerticalKind::WrfEta: st = wrfEtaHeights(in, out); break;
    case VerticalKind::GeneralVertical:  // GRIB only (GribReader.cpp): no netCDF layout has it
      st = makeError(f.path() + ": variable '" + l.var.name + "': generalised vertical levels are read from GRIB only");
      break;
  }
  if (!st) return st.forwardError();
  if (seaLevel)
    if (auto g = seaLevelToEllipsoid(in, useGeoid, out); !g) return g.forwardError();
  return out;
}

Result<Levels> levelsOf(const io::NetcdfFile& f, const GridLayout& l) {
  const VerticalSpec& vs = l.vertical;
  Levels lv;
  if (l.singleLevel) {  // a 2-D field: one level at mean sea level
    lv.valuesSi = {0.0};
    lv.units = "m";
    return lv;
  }
  const std::size_t n = vs.fileLevels;
  if (l.wrf) {
    lv.upward = true;
    return lv;  // eta values (ZNU) are read per time step with the heights
  }
  auto c = readPicked<double>(f, *vs.coordinate, {iota(0, n)});
  if (!c) return c.forwardError();
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite((*c)[i]))
      return varError(f, *vs.coordinate, "level " + std::to_string(i) + " is missing or not finite (NaN coordinate)");
  std::vector<double> ref(n);  // a quantity that increases upwards, for the direction
  switch (vs.kind) {
    case VerticalKind::Pressure:
      for (std::size_t i = 0; i < n; ++i) {
        lv.valuesSi.push_back((*c)[i] * vs.toSi);
        if (!(lv.valuesSi[i] > 0))
          return varError(f, *vs.coordinate,
                          "pressure level " + std::to_string(i) + " is " + num((*c)[i]) + " " + vs.coordinateUnits +
                              ": pressures must be positive");
        ref[i] = -lv.valuesSi[i];
      }
      lv.units = "Pa";
      break;
    case VerticalKind::HybridSigmaPressure:
    case VerticalKind::Sigma: {
      // Direction from the pressure of each level over a column whose surface is at 1000 hPa.
      lv.valuesSi = *c;
      lv.units = vs.coordinateUnits.empty() ? "1" : vs.coordinateUnits;
      std::vector<double> a, b;
      double p0 = 0, ptop = 0;
      if (vs.kind == VerticalKind::HybridSigmaPressure) {
        auto bb = readTerm(f, vs, "b");
        if (!bb) return bb.forwardError();
        b = *bb;
        if (vs.terms.count("ap")) {
          auto aa = readTerm(f, vs, "ap");
          if (!aa) return aa.forwardError();
          a = *aa;
          p0 = 1.0;
        } else {
          auto aa = readTerm(f, vs, "a");
          if (!aa) return aa.forwardError();
          a = *aa;
          auto pp = referencePressurePa(f, vs);
          if (!pp) return pp.forwardError();
          p0 = *pp;
        }
        for (std::size_t i = 0; i < n; ++i) ref[i] = -(a[i] * p0 + b[i] * 1.0e5);
      } else {
        auto s = readTerm(f, vs, "sigma");
        if (!s) return s.forwardError();
        auto pt = readTerm(f, vs, "ptop");
        if (!pt) return pt.forwardError();
        ptop = pt->front();
        for (std::size_t i = 0; i < n; ++i) ref[i] = -(ptop + (*s)[i] * (1.0e5 - ptop));
      }
      break;
    }
    case VerticalKind::HybridHeight: {
      lv.valuesSi = *c;
      lv.units = vs.coordinateUnits;
      auto a = readTerm(f, vs, "a");
      if (!a) return a.forwardError();
      ref = *a;
      break;
    }
    default:  // lengths, geopotential metres
      for (std::size_t i = 0; i < n; ++i) {
        lv.valuesSi.push_back((*c)[i] * vs.toSi);
        ref[i] = vs.positiveDown ? -lv.valuesSi[i] : lv.valuesSi[i];
      }
      lv.units = vs.kind == VerticalKind::GeopotentialHeight ? "gpm" : "m";
      break;
  }
  if (n >= 2) {
    lv.upward = ref[n - 1] > ref[0];
    for (std::size_t i = 1; i < n; ++i)
      if (!(lv.upward ? ref[i] > ref[i - 1] : ref[i] < ref[i - 1]))
        return varError(
            f, *vs.coordinate,
            "levels are not strictly monotonic (levels " + std::to_string(i - 1) + " and " + std::to_string(i) + ")");
  }
  return lv;
}

Result<std::vector<std::size_t>> levelPicks(const io::NetcdfFile& f, const GridLayout& l, const Levels& lv,
                                            const GridCrop& crop) {
  const std::size_t n = l.vertical.fileLevels;
  if (crop.firstLevel >= n)
    return varError(
        f, l.var,
        "crop: first level " + std::to_string(crop.firstLevel) + " is beyond its " + std::to_string(n) + " levels");
  const std::size_t count = std::min(crop.levelCount, n - crop.firstLevel);
  std::vector<std::size_t> p(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t b = crop.firstLevel + k;  // counted from the bottom
    p[k] = lv.upward ? b : n - 1 - b;
  }
  return p;
}

Status checkHeights(const io::NetcdfFile& f, const Heights& h, const Selection& s, std::size_t nc) {
  return checkHeights(f.path(), h, s, nc);
}

Status checkHeights(const std::string& label, const Heights& h, const Selection& s, std::size_t nc) {
  const std::size_t nz = s.levels.size();
  const std::size_t nx = s.hz->cols.size();
  auto where = [&](std::size_t k, std::size_t c) {
    if (s.columnName) return "level " + std::to_string(s.levels[k]) + ", " + s.columnName(c);
    return "level " + std::to_string(s.levels[k]) + ", row " + std::to_string(s.hz->rows[c / nx]) + ", column " +
           std::to_string(s.hz->cols[c % nx]);
  };
  for (std::size_t k = 0; k < nz; ++k)  // level by level: contiguous memory
    for (std::size_t c = 0; c < nc; ++c) {
      const float z = static_cast<float>(h.h[k * nc + c]);
      if (!std::isfinite(z))
        return makeError(label + ": variable '" + h.fromVariable + "': height not finite at " + where(k, c) +
                         " (a missing value in what the heights come from)");
      if (k > 0 && !(z > static_cast<float>(h.h[(k - 1) * nc + c])))
        return makeError(label + ": variable '" + h.fromVariable + "': heights do not increase upwards at " +
                         where(k, c) + " (" + num(h.h[(k - 1) * nc + c], 1) + " m below, " + num(h.h[k * nc + c], 1) +
                         " m here)");
    }
  return Ok{};
}

}  // namespace grid

}  // namespace atmoglobe::volume
