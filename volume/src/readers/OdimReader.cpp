#include <atmoglobe/volume/OdimReader.h>

#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/io/PageAllocator.h>
#include <atmoglobe/volume/RadarReader.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>

namespace atmoglobe::volume {

namespace {

/// Largest ray and bin counts accepted from attributes before they are compared with the
/// data array's real shape (real radars: <= 1440 rays, <= 8000 bins).
constexpr double kMaxRays = 100000.0;
constexpr double kMaxBins = 1.0e6;

/// Groups searched in order for an attribute (ODIM inheritance: most specific first).
using GroupChain = std::vector<int>;

std::optional<int> findAttrGroup(const io::NetcdfFile& f, const GroupChain& chain, const std::string& name) {
  for (int g : chain) {
    if (g >= 0 && f.hasAttribute(g, NC_GLOBAL, name)) return g;
  }
  return std::nullopt;
}

Result<double> requiredDouble(const io::NetcdfFile& f, const GroupChain& chain, const std::string& name,
                              const std::string& where) {
  const auto g = findAttrGroup(f, chain, name);
  if (!g) return makeError(f.message(where + ": required ODIM attribute '" + name + "' not found"));
  auto v = f.attributeDouble(*g, NC_GLOBAL, name);
  if (!v) return v.forwardError();
  if (!std::isfinite(*v)) return makeError(f.message(where + ": attribute '" + name + "' is not finite"));
  return *v;
}

std::optional<double> optionalDouble(const io::NetcdfFile& f, const GroupChain& chain, const std::string& name) {
  const auto g = findAttrGroup(f, chain, name);
  if (!g) return std::nullopt;
  auto v = f.attributeDouble(*g, NC_GLOBAL, name);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return *v;
}

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

/// A count attribute (nbins, nrays): an integer in [1, maxValue].
Result<std::size_t> requiredCount(const io::NetcdfFile& f, const GroupChain& chain, const std::string& name,
                                  const std::string& where, double maxValue) {
  auto v = requiredDouble(f, chain, name, where);
  if (!v) return v.forwardError();
  if (*v < 1.0 || *v > maxValue || std::floor(*v) != *v)
    return makeError(f.message(where + ": attribute '" + name + "' = " + formatNumber(*v) + " is not a count in [1, " +
                               std::to_string(static_cast<long long>(maxValue)) + "]"));
  return static_cast<std::size_t>(*v);
}

/// Numbered child groups "<prefix>N" of `parent`, sorted by N.
std::vector<std::pair<int, std::string>> numberedGroups(const io::NetcdfFile& f, int parent,
                                                        const std::string& prefix) {
  std::vector<std::pair<int, std::string>> out;
  for (const std::string& name : f.childGroupNames(parent)) {
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.size() > 6 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    out.emplace_back(std::stoi(digits), name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

int childOr(const io::NetcdfFile& f, int parent, const char* name) {
  if (parent < 0) return -1;
  return f.findGroup(parent, name).value_or(-1);
}

/// The site's name and place from ODIM /what/source: "KEY:value" pairs separated by ',' (ODIM_H5
/// 2.2, Table 3; some writers use ';'). The node (NOD) names the radar best, then the radar (RAD),
/// the place (PLC), WMO; the place is PLC. A source with no pairs is the name as it stands.
std::pair<std::string, std::string> siteNameAndPlace(const std::string& source) {
  std::map<std::string, std::string> kv;
  std::size_t pos = 0;
  while (pos <= source.size()) {
    const std::size_t comma = std::min(source.find_first_of(",;", pos), source.size());
    const std::string item = source.substr(pos, comma - pos);
    const std::size_t colon = item.find(':');
    if (colon != std::string::npos) kv[item.substr(0, colon)] = item.substr(colon + 1);
    pos = comma + 1;
  }
  std::string place;
  if (auto it = kv.find("PLC"); it != kv.end()) place = it->second;
  for (const char* key : {"NOD", "RAD", "PLC", "WMO"}) {
    if (auto it = kv.find(key); it != kv.end() && !it->second.empty())
      return {it->second, place == it->second ? std::string() : place};
  }
  return {source, {}};
}

/// Decodes one raw value (as double): nodata -> kNoData, undetect -> kNoEcho (nodata wins
/// when they are equal), NaN -> kNoData, else gain * raw + offset. An absent nodata/undetect
/// is NaN here, which no raw value compares equal to.
struct OdimDecoder {
  double gain = 1.0, offset = 0.0, nodata = std::numeric_limits<double>::quiet_NaN(),
         undetect = std::numeric_limits<double>::quiet_NaN();
  float operator()(double r) const {
    if (r == nodata) return kNoData;
    if (r == undetect) return kNoEcho;
    if (std::isnan(r)) return kNoData;
    return static_cast<float>(gain * r + offset);  // narrowing to the model's float storage
  }
};

/// "YYYY-MM-DDTHH:MM:SSZ" from an ODIM date (YYYYMMDD) and time (HHMMSS) attribute pair found
/// in `chain`; empty when either is absent or malformed.
std::string odimDateTime(const io::NetcdfFile& f, const GroupChain& chain, const std::string& dateName,
                         const std::string& timeName) {
  const auto dg = findAttrGroup(f, chain, dateName);
  const auto tg = findAttrGroup(f, chain, timeName);
  if (!dg || !tg) return {};
  auto d = f.attributeString(*dg, NC_GLOBAL, dateName);
  auto t = f.attributeString(*tg, NC_GLOBAL, timeName);
  if (!d || !t || d->size() != 8 || t->size() < 6) return {};
  return normalizeIso8601(d->substr(0, 4) + "-" + d->substr(4, 2) + "-" + d->substr(6, 2) + "T" + t->substr(0, 2) +
                          ":" + t->substr(2, 2) + ":" + t->substr(4, 2) + "Z");
}

double wrap360(double a) {
  double x = std::fmod(a, 360.0);
  if (x < 0) x += 360.0;
  if (x >= 360.0) x -= 360.0;
  return x;
}

struct DataGroup {
  int groupId = -1;  ///< dataM
  int whatId = -1;   ///< dataM/what
  std::string quantity;
  std::string path;  ///< "/datasetN/dataM" for messages
};

/// dataM/data, checked to be a numeric array shaped (nrays, nbins) as /datasetN/where says.
Result<io::NcVar> dataArray(const io::NetcdfFile& f, const DataGroup& dg, const Sweep& sw,
                            const std::string& datasetPath) {
  auto var = f.variable(dg.groupId, "data");
  if (!var) return var.forwardError();
  if (var->shape.size() != 2 || var->shape[0] != sw.rayCount() || var->shape[1] != sw.gateCount) {
    std::string shape;
    for (std::size_t d : var->shape) shape += (shape.empty() ? "" : " x ") + std::to_string(d);
    return makeError(f.message("'" + var->name + "' is " + shape + " but " + datasetPath + "/where says nrays = " +
                               std::to_string(sw.rayCount()) + ", nbins = " + std::to_string(sw.gateCount)));
  }
  if (!io::ncTypeIsNumeric(var->type)) return makeError(f.message("'" + var->name + "' is not numeric"));
  return var;
}

}  // namespace

std::string odimQuantityUnits(const std::string& q) {
  static const std::map<std::string, std::string> units = {
      {"TH", "dBZ"},   {"TV", "dBZ"},    {"DBZH", "dBZ"},   {"DBZV", "dBZ"},   {"DBZH_CLEAN", "dBZ"},
      {"VRAD", "m/s"}, {"VRADH", "m/s"}, {"VRADV", "m/s"},  {"VRADDH", "m/s"}, {"VRADDV", "m/s"},
      {"WRAD", "m/s"}, {"WRADH", "m/s"}, {"WRADV", "m/s"},  {"ZDR", "dB"},     {"LDR", "dB"},
      {"RHOHV", "1"},  {"PHIDP", "deg"}, {"KDP", "deg/km"}, {"SQI", "1"},      {"SNR", "dB"},
      {"SNRH", "dB"},  {"SNRV", "dB"},   {"CCOR", "dB"},    {"CCORH", "dB"},   {"RATE", "mm/h"},
      {"ACRR", "mm"},  {"HGHT", "km"},   {"CLASS", "1"},    {"QCFLAGS", "1"},
  };
  auto it = units.find(q);
  return it == units.end() ? std::string() : it->second;
}

Result<RadarVolume> readOdimH5(const std::string& path, const ReadOptions& options) {
  auto opened = io::NetcdfFile::open(path);
  if (!opened) return opened.forwardError();
  return readOdimH5(*opened, options);
}

Result<RadarVolume> readOdimH5(const io::NetcdfFile& f, const ReadOptions& options) {
  const std::string& path = f.path();
  const int root = f.root();

  const int rootWhat = childOr(f, root, "what");
  const int rootWhere = childOr(f, root, "where");
  const int rootHow = childOr(f, root, "how");
  if (rootWhat < 0) return makeError(f.message("not an ODIM_H5 file: no /what group"));
  if (rootWhere < 0) return makeError(f.message("ODIM_H5: no /where group (radar position)"));
  auto object = f.attributeString(rootWhat, NC_GLOBAL, "object");
  if (!object) return object.forwardError();
  if (*object != "PVOL" && *object != "SCAN")
    return makeError(f.message("ODIM object '" + *object + "' is not a polar volume (PVOL) or scan (SCAN)"));

  RadarVolume vol;
  vol.format = "ODIM_H5";
  vol.sourcePath = path;
  vol.singleScanFile = *object == "SCAN";
  auto lat = requiredDouble(f, {rootWhere}, "lat", "/where");
  if (!lat) return lat.forwardError();
  auto lon = requiredDouble(f, {rootWhere}, "lon", "/where");
  if (!lon) return lon.forwardError();
  auto height = requiredDouble(f, {rootWhere}, "height", "/where");
  if (!height) return height.forwardError();
  if (*lat < -90.0 || *lat > 90.0)
    return makeError(f.message("/where/lat " + std::to_string(*lat) + " is outside [-90, 90]"));
  if (*lon < -540.0 || *lon > 540.0)
    return makeError(f.message("/where/lon " + std::to_string(*lon) + " is outside [-540, 540]"));
  vol.site.latDeg = *lat;
  vol.site.lonDeg = std::remainder(*lon, 360.0);
  vol.site.antennaHeightMeters = *height;
  vol.site.heightDatum = HeightDatum::MeanSeaLevel;  // ODIM: height above sea level
  if (f.hasAttribute(rootWhat, NC_GLOBAL, "source")) {
    if (auto s = f.attributeString(rootWhat, NC_GLOBAL, "source"))
      std::tie(vol.site.name, vol.site.placeName) = siteNameAndPlace(*s);
  }
  if (f.hasAttribute(rootWhat, NC_GLOBAL, "date") && f.hasAttribute(rootWhat, NC_GLOBAL, "time")) {
    auto d = f.attributeString(rootWhat, NC_GLOBAL, "date");
    auto t = f.attributeString(rootWhat, NC_GLOBAL, "time");
    if (d && t && d->size() == 8 && t->size() >= 6) {
      vol.timeIso8601 = normalizeIso8601(d->substr(0, 4) + "-" + d->substr(4, 2) + "-" + d->substr(6, 2) + "T" +
                                         t->substr(0, 2) + ":" + t->substr(2, 2) + ":" + t->substr(4, 2) + "Z");
    }
  }
  if (auto bw = optionalDouble(f, {rootHow}, "beamwH"); bw && *bw > 0) vol.beamWidthDeg = *bw;
  else if (auto bw2 = optionalDouble(f, {rootHow}, "beamwidth"); bw2 && *bw2 > 0) vol.beamWidthDeg = *bw2;

  const auto datasets = numberedGroups(f, root, "dataset");
  if (datasets.empty()) return makeError(f.message("ODIM_H5: no /datasetN groups (no sweeps)"));

  std::vector<std::vector<DataGroup>> dataBySweep;
  for (const auto& [number, dsName] : datasets) {
    const int ds = *f.findGroup(root, dsName);
    const int dsWhat = childOr(f, ds, "what"), dsWhere = childOr(f, ds, "where"), dsHow = childOr(f, ds, "how");
    const std::string where = "/" + dsName;
    if (dsWhere < 0) return makeError(f.message(where + ": no 'where' group (sweep geometry)"));
    // Nyquist interval (ODIM how/NI, m/s), the dataset's or the volume's: the largest.
    if (auto ni = optionalDouble(f, {dsHow, rootHow}, "NI");
        ni && *ni > 0.0 && *ni < 200.0 && !(*ni <= vol.nyquistVelocityMps))
      vol.nyquistVelocityMps = *ni;

    auto nbins = requiredCount(f, {dsWhere}, "nbins", where + "/where", kMaxBins);
    if (!nbins) return nbins.forwardError();
    auto nrays = requiredCount(f, {dsWhere}, "nrays", where + "/where", kMaxRays);
    if (!nrays) return nrays.forwardError();
    auto elangle = requiredDouble(f, {dsWhere}, "elangle", where + "/where");
    if (!elangle) return elangle.forwardError();
    auto rstart = requiredDouble(f, {dsWhere}, "rstart", where + "/where");
    if (!rstart) return rstart.forwardError();
    auto rscale = requiredDouble(f, {dsWhere}, "rscale", where + "/where");
    if (!rscale) return rscale.forwardError();
    if (*elangle < -90.0 || *elangle > 90.0)
      return makeError(f.message(where + "/where: elangle " + std::to_string(*elangle) + " is outside [-90, 90]"));
    if (*rscale <= 0.0) return makeError(f.message(where + "/where: rscale must be positive"));
    if (*rstart < 0.0) return makeError(f.message(where + "/where: rstart must not be negative"));

    Sweep sw;
    sw.indexInFile = static_cast<int>(dataBySweep.size());
    sw.startTimeIso8601 = odimDateTime(f, {dsWhat}, "startdate", "starttime");
    sw.endTimeIso8601 = odimDateTime(f, {dsWhat}, "enddate", "endtime");
    sw.fixedAngleDeg = *elangle;
    sw.mode = SweepMode::Ppi;
    sw.firstGateRangeMeters = *rstart * 1000.0 + *rscale / 2.0;  // rstart (km) is the start of bin 0
    sw.gateSpacingMeters = *rscale;
    sw.gateCount = static_cast<std::uint32_t>(*nbins);
    const std::size_t nr = *nrays;

    // Ray azimuths: startazA/stopazA midpoints, else uniform centres from astart.
    sw.azimuthDeg.resize(nr);
    bool haveAz = false;
    if (dsHow >= 0 && f.hasAttribute(dsHow, NC_GLOBAL, "startazA") && f.hasAttribute(dsHow, NC_GLOBAL, "stopazA")) {
      auto a = f.attributeDoubles(dsHow, NC_GLOBAL, "startazA", nr);
      auto b = f.attributeDoubles(dsHow, NC_GLOBAL, "stopazA", nr);
      if (!a) return a.forwardError();
      if (!b) return b.forwardError();
      if (a->size() != nr || b->size() != nr)
        return makeError(
            f.message(where + "/how: startazA/stopazA do not hold nrays = " + std::to_string(nr) + " values"));
      for (std::size_t i = 0; i < nr; ++i) {
        if (!std::isfinite((*a)[i]) || !std::isfinite((*b)[i]))
          return makeError(f.message(where + "/how: startazA/stopazA of ray " + std::to_string(i) + " is not finite"));
        double d = wrap360((*b)[i] - (*a)[i]);  // stop may have wrapped past 360
        sw.azimuthDeg[i] = static_cast<float>(wrap360((*a)[i] + d / 2.0));
      }
      haveAz = true;
    }
    if (!haveAz) {
      const double astart = optionalDouble(f, {dsHow}, "astart").value_or(0.0);
      const double step = 360.0 / static_cast<double>(nr);
      for (std::size_t i = 0; i < nr; ++i)
        sw.azimuthDeg[i] = static_cast<float>(wrap360(astart + (static_cast<double>(i) + 0.5) * step));
    }
    sw.elevationDeg.assign(nr, static_cast<float>(*elangle));
    if (dsHow >= 0 && f.hasAttribute(dsHow, NC_GLOBAL, "elangles")) {
      auto e = f.attributeDoubles(dsHow, NC_GLOBAL, "elangles", nr);
      if (!e) return e.forwardError();
      if (e->size() != nr)
        return makeError(f.message(where + "/how: elangles does not hold nrays = " + std::to_string(nr) + " values"));
      for (std::size_t i = 0; i < nr; ++i) {
        if (!std::isfinite((*e)[i]))
          return makeError(f.message(where + "/how: elangles of ray " + std::to_string(i) + " is not finite"));
        sw.elevationDeg[i] = static_cast<float>((*e)[i]);
      }
    }

    // Quantities: every dataM with a 'data' array shaped (nrays, nbins).
    std::vector<DataGroup> groups;
    for (const auto& [m, dataName] : numberedGroups(f, ds, "data")) {
      DataGroup dg;
      dg.groupId = *f.findGroup(ds, dataName);
      dg.whatId = childOr(f, dg.groupId, "what");
      const auto qg = findAttrGroup(f, {dg.whatId, dsWhat}, "quantity");
      if (!qg) return makeError(f.message(where + "/" + dataName + ": no 'quantity' attribute"));
      auto q = f.attributeString(*qg, NC_GLOBAL, "quantity");
      if (!q) return q.forwardError();
      dg.quantity = *q;
      dg.path = where + "/" + dataName;
      if (std::none_of(vol.fields.begin(), vol.fields.end(),
                       [&](const FieldInfo& fi) { return fi.name == dg.quantity; }))
        vol.fields.push_back(FieldInfo{dg.quantity, odimQuantityUnits(dg.quantity), {}});
      groups.push_back(std::move(dg));
    }
    dataBySweep.push_back(std::move(groups));
    vol.sweeps.push_back(std::move(sw));
  }

  if (!vol.fields.empty()) {
    auto selected = selectField(vol.fields, options.fieldName, "quantity");
    if (!selected) return makeError(f.message(selected.error()));
    const auto it = vol.fields.begin() + static_cast<std::ptrdiff_t>(*selected);
    vol.loadedField = *it;
    // The arrays of the chosen quantity are checked against the sweep geometry even for a
    // metadata-only read (cheap: no data is read); the others are never touched.
    std::string withoutQuantity, sameCodes;
    for (std::size_t s = 0; s < vol.sweeps.size(); ++s) {
      Sweep& sw = vol.sweeps[s];
      const std::size_t n = sw.rayCount() * sw.gateCount;
      const auto dg = std::find_if(dataBySweep[s].begin(), dataBySweep[s].end(),
                                   [&](const DataGroup& d) { return d.quantity == it->name; });
      if (dg == dataBySweep[s].end()) {
        if (options.loadValues) sw.values.assign(n, kNoData);  // this sweep did not measure the quantity
        withoutQuantity += (withoutQuantity.empty() ? "" : ", ") + std::string("/") + datasets[s].second + " (" +
                           formatNumber(sw.fixedAngleDeg) + " deg)";
        continue;
      }
      auto var = dataArray(f, *dg, sw, "/" + datasets[s].second);
      if (!var) return var.forwardError();
      if (!options.loadValues) continue;
      if (auto ok = f.checkReadable(*var, n, io::ncTypeSize(var->type)); !ok) return ok.forwardError();
      const int dsId = *f.findGroup(root, datasets[s].second);
      const GroupChain chain{dg->whatId, childOr(f, dsId, "what"), rootWhat};
      OdimDecoder decoder;
      decoder.gain = optionalDouble(f, chain, "gain").value_or(1.0);
      decoder.offset = optionalDouble(f, chain, "offset").value_or(0.0);
      if (const auto nodata = optionalDouble(f, chain, "nodata")) decoder.nodata = *nodata;
      if (const auto undetect = optionalDouble(f, chain, "undetect")) decoder.undetect = *undetect;
      if (decoder.nodata == decoder.undetect && sameCodes.empty()) {
        sameCodes = dg->path + " (nodata = undetect = " + formatNumber(decoder.nodata) + ")";
      }
      io::assignPopulated(sw.values, n, 0.0f);
      Status st = io::visitNumericType(var->type, [&](auto tag) -> Status {
        using T = decltype(tag);
        const io::RawDecoder<T, OdimDecoder> rawDecoder(decoder, n);
        return io::readSlabDecoded(f, *var, {0, 0}, {sw.rayCount(), sw.gateCount}, rawDecoder, sw.values.data(), n);
      });
      if (!st) return st.forwardError();
    }
    if (!withoutQuantity.empty()) {
      vol.warnings.push_back("sweeps " + withoutQuantity + " hold no " + it->name + ": they are kept as no data");
    }
    if (!sameCodes.empty()) {
      vol.warnings.push_back("nodata and undetect are the same code in " + sameCodes +
                             ": such gates cannot be told apart and are read as no data (not as no echo)");
    }
  } else if (!options.fieldName.empty()) {
    return makeError(f.message("no quantity '" + options.fieldName + "': the file holds no dataM groups"));
  }

  sortSweepsByAngle(vol);
  return vol;
}

}  // namespace atmoglobe::volume
