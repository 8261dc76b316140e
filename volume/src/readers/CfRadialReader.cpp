#include <atmoglobe/volume/CfRadialReader.h>

#include <atmoglobe/globe/Text.h>
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/io/PageAllocator.h>
#include <atmoglobe/volume/RadarReader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>

namespace atmoglobe::volume {

namespace {

/// The variable's _FillValue (or nullopt), read as double.
std::optional<double> fillValue(const io::NetcdfFile& f, const io::NcVar& v, const char* name = "_FillValue") {
  if (!f.hasAttribute(v.groupId, v.varId, name)) return std::nullopt;
  auto r = f.attributeDouble(v.groupId, v.varId, name);
  if (!r) return std::nullopt;
  return *r;
}

bool isFillOrNaN(double x, const std::optional<double>& fill) { return !std::isfinite(x) || (fill && x == *fill); }

/// A per-sweep integer/float variable of length nSweep.
template <class T>
Result<std::vector<T>> readPerSweep(const io::NetcdfFile& f, const std::string& name, std::size_t nSweep,
                                    int sweepDim) {
  auto v = f.variable(f.root(), name);
  if (!v) return v.forwardError();
  if (v->shape.size() != 1 || v->dimIds[0] != sweepDim)
    return makeError(f.message("variable '" + name + "' must have the single dimension 'sweep'"));
  if (v->shape[0] != nSweep) return makeError(f.message("variable '" + name + "' has the wrong length"));
  return f.readAll<T>(*v);
}

/// latitude/longitude/altitude: scalar or per ray (moving platforms); returns the value
/// for ray `ray`.
Result<double> readSiteValue(const io::NetcdfFile& f, const std::string& name, int timeDim, std::size_t ray) {
  auto v = f.variable(f.root(), name);
  if (!v) return v.forwardError();
  double x = 0.0;
  if (v->shape.empty()) {
    if (auto st = f.readSlab<double>(*v, {}, {}, &x); !st) return st.forwardError();
  } else if (v->shape.size() == 1 && v->dimIds[0] == timeDim) {
    if (auto st = f.readSlab<double>(*v, {ray}, {1}, &x); !st) return st.forwardError();
  } else {
    return makeError(f.message("variable '" + name + "' must be a scalar or have the dimension 'time'"));
  }
  if (isFillOrNaN(x, fillValue(f, *v)))
    return makeError(f.message("variable '" + name + "' holds no value (NaN, infinite or _FillValue)"));
  return x;
}

SweepMode modeFromText(const std::string& text) {
  const std::string t = toLowerAscii(text);
  if (t == "rhi" || t == "manual_rhi" || t == "elevation_surveillance") return SweepMode::Rhi;
  if (t == "azimuth_surveillance" || t == "sector" || t == "manual_ppi" || t == "ppi") return SweepMode::Ppi;
  return SweepMode::Other;
}

double normalizeAzimuthDeg(double az) {
  double a = std::fmod(az, 360.0);
  if (a < 0) a += 360.0;
  if (a >= 360.0) a -= 360.0;
  return a;
}

/// Decodes one raw value (as double) to its physical float: _FillValue, missing_value and
/// NaN -> kNoData, else raw * scale + offset. An absent fill/missing value is NaN here,
/// which no raw value compares equal to.
struct CfDecoder {
  double scale = 1.0, offset = 0.0, fill = std::numeric_limits<double>::quiet_NaN(),
         missing = std::numeric_limits<double>::quiet_NaN();
  float operator()(double r) const {
    if (r == fill || r == missing || std::isnan(r)) return kNoData;
    return static_cast<float>(r * scale + offset);  // narrowing to the model's float storage
  }
};

std::string readTimeText(const io::NetcdfFile& f) {
  if (auto v = f.findVariable(f.root(), "time_coverage_start")) {
    if (auto t = f.readText(*v, 0)) {
      const std::string iso = normalizeIso8601(*t);
      if (!iso.empty()) return iso;
    }
  }
  for (const char* attr : {"time_coverage_start", "start_datetime", "start_time"}) {
    if (f.hasAttribute(f.root(), NC_GLOBAL, attr)) {
      if (auto t = f.attributeString(f.root(), NC_GLOBAL, attr)) {
        const std::string iso = normalizeIso8601(*t);
        if (!iso.empty()) return iso;
      }
    }
  }
  if (auto v = f.findVariable(f.root(), "time")) {
    if (auto u = f.attributeString(v->groupId, v->varId, "units")) {
      const auto pos = u->find("since ");
      if (pos != std::string::npos) return normalizeIso8601(u->substr(pos + 6));
    }
  }
  return {};
}

}  // namespace

Result<RadarVolume> readCfRadial(const std::string& path, const ReadOptions& options) {
  auto opened = io::NetcdfFile::open(path);
  if (!opened) return opened.forwardError();
  return readCfRadial(*opened, options);
}

Result<RadarVolume> readCfRadial(const io::NetcdfFile& f, const ReadOptions& options) {
  const std::string& path = f.path();
  const int root = f.root();

  // --- dimensions ---
  int timeDim = -1, rangeDim = -1, sweepDim = -1;
  const auto nTime = f.dimensionLength(root, "time", &timeDim);
  const auto nRange = f.dimensionLength(root, "range", &rangeDim);
  const auto nSweep = f.dimensionLength(root, "sweep", &sweepDim);
  if (!nTime || !nRange || !nSweep) {
    if (f.dimensionLength(root, "n_points") || f.findVariable(root, "ray_n_gates"))
      return makeError(f.message("ragged CfRadial (n_points/ray_n_gates) is not supported"));
    if (!f.childGroupNames(root).empty() && !nSweep && f.hasAttribute(root, NC_GLOBAL, "Conventions"))
      return makeError(
          f.message("no 'time', 'range' or 'sweep' dimension (CfRadial 2 with one group per sweep is not supported)"));
    return makeError(f.message(std::string("not a CfRadial file: missing dimension '") +
                               (!nTime    ? "time"
                                : !nRange ? "range"
                                          : "sweep") +
                               "'"));
  }
  if (*nSweep == 0) return makeError(f.message("the file holds no sweeps (sweep dimension is 0)"));
  if (*nTime == 0) return makeError(f.message("the file holds no rays (time dimension is 0)"));
  if (f.findVariable(root, "ray_n_gates") && f.dimensionLength(root, "n_points"))
    return makeError(f.message("ragged CfRadial (n_points/ray_n_gates) is not supported"));

  // --- sweep table ---
  auto starts = readPerSweep<long long>(f, "sweep_start_ray_index", *nSweep, sweepDim);
  if (!starts) return starts.forwardError();
  auto ends = readPerSweep<long long>(f, "sweep_end_ray_index", *nSweep, sweepDim);
  if (!ends) return ends.forwardError();
  auto fixed = readPerSweep<double>(f, "fixed_angle", *nSweep, sweepDim);
  if (!fixed) return fixed.forwardError();
  const auto fixedFill = fillValue(f, *f.findVariable(root, "fixed_angle"));
  for (std::size_t s = 0; s < *nSweep; ++s) {
    const long long a = (*starts)[s], b = (*ends)[s];
    if (a < 0 || b < a || static_cast<std::size_t>(b) >= *nTime)
      return makeError(f.message("sweep " + std::to_string(s) + ": ray index range [" + std::to_string(a) + ", " +
                                 std::to_string(b) + "] is outside the " + std::to_string(*nTime) + " rays"));
    if (isFillOrNaN((*fixed)[s], fixedFill))
      return makeError(f.message("sweep " + std::to_string(s) + ": fixed_angle is NaN, infinite or _FillValue"));
  }

  // --- per-ray angles ---
  auto azVar = f.variable(root, "azimuth");
  if (!azVar) return azVar.forwardError();
  auto elVar = f.variable(root, "elevation");
  if (!elVar) return elVar.forwardError();
  for (const io::NcVar* v : {&*azVar, &*elVar}) {
    if (v->shape.size() != 1 || v->dimIds[0] != timeDim)
      return makeError(f.message("variable '" + v->name + "' must have the single dimension 'time'"));
  }
  auto az = f.readAll<double>(*azVar);
  if (!az) return az.forwardError();
  auto el = f.readAll<double>(*elVar);
  if (!el) return el.forwardError();
  const auto azFill = fillValue(f, *azVar), elFill = fillValue(f, *elVar);

  // --- gate geometry ---
  auto rangeVar = f.variable(root, "range");
  if (!rangeVar) return rangeVar.forwardError();
  if (rangeVar->shape.size() != 1 || rangeVar->dimIds[0] != rangeDim)
    return makeError(f.message("variable 'range' must have the single dimension 'range'"));
  auto range = f.readAll<double>(*rangeVar);
  if (!range) return range.forwardError();
  if (range->empty()) return makeError(f.message("the range dimension is 0: no gates"));
  const auto rangeFill = fillValue(f, *rangeVar);
  for (std::size_t g = 0; g < range->size(); ++g) {
    if (isFillOrNaN((*range)[g], rangeFill))
      return makeError(f.message("range of gate " + std::to_string(g) + " is NaN, infinite or _FillValue"));
  }
  double spacing = 0.0;
  if (range->size() > 1) {
    spacing = (range->back() - range->front()) / static_cast<double>(range->size() - 1);
    const double tol = std::max(0.01 * std::fabs(spacing), 0.5);
    for (std::size_t g = 1; g < range->size(); ++g) {
      if (std::fabs(((*range)[g] - (*range)[g - 1]) - spacing) > tol)
        return makeError(f.message("range spacing is not uniform (gate " + std::to_string(g) +
                                   "): non-uniform gates are not supported"));
    }
    if (spacing <= 0) return makeError(f.message("range does not increase"));
  } else if (f.hasAttribute(rangeVar->groupId, rangeVar->varId, "meters_between_gates")) {
    if (auto m = f.attributeDouble(rangeVar->groupId, rangeVar->varId, "meters_between_gates")) spacing = *m;
  }

  RadarVolume vol;
  vol.format = "CfRadial";
  vol.sourcePath = path;

  // --- site ---
  const std::size_t firstRay = static_cast<std::size_t>((*starts)[0]);
  auto lat = readSiteValue(f, "latitude", timeDim, firstRay);
  if (!lat) return lat.forwardError();
  auto lon = readSiteValue(f, "longitude", timeDim, firstRay);
  if (!lon) return lon.forwardError();
  auto alt = readSiteValue(f, "altitude", timeDim, firstRay);
  if (!alt) return alt.forwardError();
  if (*lat < -90.0 || *lat > 90.0)
    return makeError(f.message("latitude " + std::to_string(*lat) + " is outside [-90, 90]"));
  if (*lon < -540.0 || *lon > 540.0)
    return makeError(f.message("longitude " + std::to_string(*lon) + " is outside [-540, 540]"));
  vol.site.latDeg = *lat;
  vol.site.lonDeg = std::remainder(*lon, 360.0);  // to [-180, 180]
  vol.site.antennaHeightMeters = *alt;
  vol.site.heightDatum = HeightDatum::MeanSeaLevel;
  // The instrument names the radar, the site where it stands (CfRadial 1.4, section 4.1).
  for (const char* attr : {"instrument_name", "site_name"}) {
    if (f.hasAttribute(root, NC_GLOBAL, attr)) {
      if (auto s = f.attributeString(root, NC_GLOBAL, attr); s && !s->empty()) {
        if (vol.site.name.empty()) vol.site.name = *s;
        else if (*s != vol.site.name) vol.site.placeName = *s;
      }
    }
  }
  vol.timeIso8601 = readTimeText(f);
  // Nyquist velocity per ray (CfRadial 1.4 instrument_parameters): the largest valid value.
  if (auto ny = f.findVariable(root, "nyquist_velocity"); ny && ny->shape.size() == 1) {
    if (auto values = f.readAll<double>(*ny)) {
      const auto fill = fillValue(f, *ny);
      for (double x : *values)
        if (!isFillOrNaN(x, fill) && x > 0.0 && x < 200.0 && !(x <= vol.nyquistVelocityMps)) vol.nyquistVelocityMps = x;
    }
  }
  if (auto bw = f.findVariable(root, "radar_beam_width_h"); bw && bw->shape.empty()) {
    double x = 0;
    if (f.readSlab<double>(*bw, {}, {}, &x) && !isFillOrNaN(x, fillValue(f, *bw)) && x > 0) vol.beamWidthDeg = x;
  }

  // --- fields: numeric (time, range) variables ---
  std::vector<io::NcVar> fieldVars;
  for (io::NcVar& v : f.variables(root)) {
    if (v.shape.size() == 2 && v.dimIds[0] == timeDim && v.dimIds[1] == rangeDim && io::ncTypeIsNumeric(v.type)) {
      FieldInfo fi;
      fi.name = v.name.substr(v.name.rfind('/') + 1);
      if (f.hasAttribute(v.groupId, v.varId, "units")) {
        if (auto u = f.attributeString(v.groupId, v.varId, "units")) fi.units = *u;
      }
      if (f.hasAttribute(v.groupId, v.varId, "standard_name")) {
        if (auto sn = f.attributeString(v.groupId, v.varId, "standard_name")) fi.standardName = *sn;
      }
      vol.fields.push_back(fi);
      fieldVars.push_back(std::move(v));
    }
  }

  // --- sweeps ---
  auto modeVar = f.findVariable(root, "sweep_mode");
  for (std::size_t s = 0; s < *nSweep; ++s) {
    Sweep sw;
    sw.indexInFile = static_cast<int>(s);
    sw.fixedAngleDeg = (*fixed)[s];
    sw.firstGateRangeMeters = range->front();
    sw.gateSpacingMeters = spacing;
    sw.gateCount = static_cast<std::uint32_t>(*nRange);
    const auto a = static_cast<std::size_t>((*starts)[s]), b = static_cast<std::size_t>((*ends)[s]);
    sw.azimuthDeg.reserve(b - a + 1);
    sw.elevationDeg.reserve(b - a + 1);
    double azMin = 1e9, azMax = -1e9, elMin = 1e9, elMax = -1e9;
    for (std::size_t r = a; r <= b; ++r) {
      if (isFillOrNaN((*az)[r], azFill) || isFillOrNaN((*el)[r], elFill))
        return makeError(f.message("ray " + std::to_string(r) + " (sweep " + std::to_string(s) +
                                   ") has no azimuth/elevation (NaN, infinite or _FillValue)"));
      sw.azimuthDeg.push_back(static_cast<float>(normalizeAzimuthDeg((*az)[r])));
      sw.elevationDeg.push_back(static_cast<float>((*el)[r]));
      azMin = std::min(azMin, (*az)[r]);
      azMax = std::max(azMax, (*az)[r]);
      elMin = std::min(elMin, (*el)[r]);
      elMax = std::max(elMax, (*el)[r]);
    }
    std::string modeText;
    if (modeVar) {
      if (auto t = f.readText(*modeVar, s)) modeText = *t;
    }
    if (!modeText.empty()) {
      sw.mode = modeFromText(modeText);
    } else {
      sw.mode = (elMax - elMin) > (azMax - azMin) ? SweepMode::Rhi : SweepMode::Ppi;
    }
    vol.sweeps.push_back(std::move(sw));
  }

  // --- the one field asked for ---
  if (!vol.fields.empty()) {
    auto selected = selectField(vol.fields, options.fieldName);
    if (!selected) return makeError(f.message(selected.error()));
    const auto it = vol.fields.begin() + static_cast<std::ptrdiff_t>(*selected);
    vol.loadedField = *it;
    if (options.loadValues) {
      const io::NcVar& var = fieldVars[static_cast<std::size_t>(it - vol.fields.begin())];
      double scale = 1.0, offset = 0.0;
      for (auto [attr, dst] : {std::pair<const char*, double*>{"scale_factor", &scale}, {"add_offset", &offset}}) {
        if (!f.hasAttribute(var.groupId, var.varId, attr)) continue;
        auto r = f.attributeDouble(var.groupId, var.varId, attr);
        if (!r) return r.forwardError();
        if (!std::isfinite(*r)) return makeError(f.message("variable '" + var.name + "': " + attr + " is not finite"));
        *dst = *r;
      }
      CfDecoder decoder;
      decoder.scale = scale;
      decoder.offset = offset;
      if (const auto fill = fillValue(f, var)) decoder.fill = *fill;
      if (const auto missing = fillValue(f, var, "missing_value")) decoder.missing = *missing;
      // Everything the sweeps read, checked against what the file can hold before allocating.
      std::size_t total = 0;
      for (const Sweep& sw : vol.sweeps) total += sw.rayCount() * sw.gateCount;
      if (auto ok = f.checkReadable(var, total, io::ncTypeSize(var.type)); !ok) return ok.forwardError();
      // One read per sweep, decoded in place in the sweep's values (no raw buffer); chunks
      // that straddle two sweeps come from netCDF-C's chunk cache the second time.
      Status st = io::visitNumericType(var.type, [&](auto tag) -> Status {
        using T = decltype(tag);
        const io::RawDecoder<T, CfDecoder> rawDecoder(decoder, total);
        for (Sweep& sw : vol.sweeps) {
          const std::size_t n = sw.rayCount() * sw.gateCount;
          io::assignPopulated(sw.values, n, 0.0f);
          const auto a = static_cast<std::size_t>((*starts)[static_cast<std::size_t>(sw.indexInFile)]);
          if (auto r =
                  io::readSlabDecoded(f, var, {a, 0}, {sw.rayCount(), sw.gateCount}, rawDecoder, sw.values.data(), n);
              !r)
            return r;
        }
        return Ok{};
      });
      if (!st) return st.forwardError();
    }
  } else if (!options.fieldName.empty()) {
    return makeError(f.message("no field '" + options.fieldName + "': the file holds no (time, range) fields"));
  } else if (options.loadValues) {
    // Values asked for and nothing to decode: say so, naming any (time, range) variable of a
    // non-numeric type (a wrong type, e.g. char), rather than return a volume without values.
    std::string wrongType;
    for (const io::NcVar& v : f.variables(root))
      if (v.shape.size() == 2 && v.dimIds[0] == timeDim && v.dimIds[1] == rangeDim)
        wrongType += (wrongType.empty() ? "" : ", ") + v.name.substr(v.name.rfind('/') + 1);
    return makeError(
        f.message("no numeric (time, range) field to read" +
                  (wrongType.empty() ? std::string() : std::string(" (not numeric: ").append(wrongType).append(")"))));
  }

  // Rays outside every sweep's index range (antenna transitions between sweeps) are not read.
  std::size_t inSweeps = 0;
  for (const Sweep& sw : vol.sweeps) inSweeps += sw.rayCount();
  if (inSweeps < *nTime) {
    vol.warnings.push_back(std::to_string(*nTime - inSweeps) + " of the file's " + std::to_string(*nTime) +
                           " rays lie outside every sweep's ray index range (antenna transitions) and are left out");
  }
  sortSweepsByAngle(vol);
  return vol;
}

}  // namespace atmoglobe::volume
