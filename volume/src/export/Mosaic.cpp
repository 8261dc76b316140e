// The mosaic's CF netCDF file (Mosaic.h).
#include <atmoglobe/volume/Mosaic.h>

#include "NcWriter.h"

#include <atmoglobe/io/NetcdfLock.h>
#include <atmoglobe/volume/RadarReader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>

namespace atmoglobe::volume {

std::string overlapRuleFormula(OverlapRule rule) {
  switch (rule) {
    case OverlapRule::WeightedMean:
      return "sum_k w_k v_k / sum_k w_k over the radars with an echo, w_k = exp(-(r_k / 50 km)^2), r_k the slant range "
             "from radar k (Zhang, Howard and Gourley 2005, J. Atmos. Oceanic Technol. 22, 30-42); echo where the echo "
             "weight is at least half the weight of the radars that measured the point";
    case OverlapRule::LowestBeam:
      return "the value of the radar whose lowest sweep's beam centre passes lowest over the point (effective-Earth "
             "beam, ke = 4/3)";
    case OverlapRule::Maximum: return "the largest value of the radars that echo at the point";
    case OverlapRule::Integrate: return "extinctions add (rendering only)";
  }
  return "";
}

namespace {

// A netCDF variable name from a field name: letters, digits and underscores, starting with a letter.
std::string variableName(const std::string& field) {
  std::string v;
  for (char c : field) v += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (v.empty() || !std::isalpha(static_cast<unsigned char>(v[0]))) v = "field_" + v;
  if (v == "lon" || v == "lat" || v == "altitude" || v == "time") v += "_mosaic";
  return v;
}

const char* standardNameOf(FieldKind kind) {
  switch (kind) {
    case FieldKind::Reflectivity: return "equivalent_reflectivity_factor";
    case FieldKind::DifferentialReflectivity: return "log_differential_reflectivity_hv";
    case FieldKind::CorrelationCoefficient: return "cross_correlation_ratio_hv";
    case FieldKind::SpecificDifferentialPhase: return "specific_differential_phase_hv";
    default: return "";
  }
}

std::vector<double> axis(double first, double last, std::size_t n) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i)
    v[i] = n > 1 ? first + (last - first) * static_cast<double>(i) / static_cast<double>(n - 1) : first;
  return v;
}

}  // namespace

Status writeMosaicNetcdf(const std::string& path, const RegularGridSpec& spec, const std::vector<float>& values,
                         const MosaicMetadata& meta) {
  if (spec.kind != RegularGridKind::Geographic || spec.datum != HeightDatum::MeanSeaLevel)
    return makeError(path + ": a mosaic grid is geographic with heights above mean sea level");
  if (values.size() != spec.sampleCount())
    return makeError(path + ": " + std::to_string(values.size()) + " values for a grid of " +
                     std::to_string(spec.sampleCount()));
  // The latest radar time stamps the product.
  double latest = -std::numeric_limits<double>::infinity();
  std::string latestIso;
  for (const MosaicRadar& r : meta.radars) {
    const double t = iso8601ToEpochSeconds(r.timeIso8601);
    if (std::isfinite(t) && t > latest) {
      latest = t;
      latestIso = normalizeIso8601(r.timeIso8601);
    }
  }

  const io::NetcdfLock lock;  // from nc_create to nc_close (io/NetcdfLock.h)
  std::string temp;
  int ncid = -1;
  if (Status st = createTemporaryNetcdf(path, &temp, &ncid); !st) return st;
  NcWriter w(path, ncid);
  // A time axis only where the radars give times (a file's volume time may be missing).
  const bool hasTime = std::isfinite(latest);
  int dTime = -1, dAlt = -1, dLat = -1, dLon = -1;
  if (hasTime) w.check(nc_def_dim(ncid, "time", 1, &dTime), "time dimension");
  w.check(nc_def_dim(ncid, "altitude", spec.nz, &dAlt), "altitude dimension");
  w.check(nc_def_dim(ncid, "lat", spec.ny, &dLat), "lat dimension");
  w.check(nc_def_dim(ncid, "lon", spec.nx, &dLon), "lon dimension");
  const int vTime = hasTime ? w.var("time", NC_DOUBLE, {dTime}) : -1;
  if (hasTime) {
    w.text(vTime, "standard_name", "time");
    w.text(vTime, "units", "seconds since 1970-01-01 00:00:00");
    w.text(vTime, "calendar", "standard");
  }
  const int vAlt = w.var("altitude", NC_DOUBLE, {dAlt});
  w.text(vAlt, "standard_name", "altitude");
  w.text(vAlt, "long_name", "height above mean sea level (EGM96)");
  w.text(vAlt, "units", "m");
  w.text(vAlt, "positive", "up");
  w.text(vAlt, "axis", "Z");
  const int vLat = w.var("lat", NC_DOUBLE, {dLat});
  w.text(vLat, "standard_name", "latitude");
  w.text(vLat, "units", "degrees_north");
  w.text(vLat, "axis", "Y");
  const int vLon = w.var("lon", NC_DOUBLE, {dLon});
  w.text(vLon, "standard_name", "longitude");
  w.text(vLon, "units", "degrees_east");
  w.text(vLon, "axis", "X");
  const std::string name = variableName(meta.field);
  // Chunks of one level (or of up to 1024 x 1024 columns of it), deflated: a reader of a box
  // or of a level reads little.
  const int vField = hasTime ? w.var(name.c_str(), NC_FLOAT, {dTime, dAlt, dLat, dLon})
                             : w.var(name.c_str(), NC_FLOAT, {dAlt, dLat, dLon});
  const std::size_t chunks[4] = {1, 1, std::min<std::size_t>(spec.ny, 1024), std::min<std::size_t>(spec.nx, 1024)};
  const std::size_t* fieldChunks = hasTime ? chunks : chunks + 1;
  if (vField >= 0) {
    w.check(nc_def_var_chunking(ncid, vField, NC_CHUNKED, fieldChunks), "chunking");
    w.check(nc_def_var_deflate(ncid, vField, 1, 1, 2), "deflate");
    const float fill = std::numeric_limits<float>::quiet_NaN();
    w.check(nc_put_att_float(ncid, vField, "_FillValue", NC_FLOAT, 1, &fill), "_FillValue");
  }
  if (const char* sn = standardNameOf(meta.kind); *sn) w.text(vField, "standard_name", sn);
  w.text(vField, "long_name",
         meta.field + " mosaic of " + std::to_string(meta.radars.size()) + " radars, rule " + toString(meta.rule));
  if (!meta.units.empty()) w.text(vField, "units", meta.units);
  w.text(vField, "coordinates", hasTime ? "time altitude lat lon" : "altitude lat lon");
  w.text(vField, "comment", "NaN (_FillValue) where no radar echoes: no echo and no data alike");

  std::ostringstream sites, times, files, positions;
  for (std::size_t k = 0; k < meta.radars.size(); ++k) {
    const MosaicRadar& r = meta.radars[k];
    const char* sep = k ? ", " : "";
    sites << sep << r.site;
    times << sep << r.timeIso8601;
    files << sep << r.path;
    positions << sep << r.latDeg << " " << r.lonDeg;
  }
  w.text(NC_GLOBAL, "Conventions", "CF-1.8");
  w.text(NC_GLOBAL, "title",
         std::string(meta.synthetic ? "SYNTHETIC " : "") + "3-D radar mosaic of " + std::to_string(meta.radars.size()) +
             " radars (" + meta.field + ", rule " + toString(meta.rule) + ")");
  if (meta.synthetic)
    w.text(NC_GLOBAL, "comment", "SYNTHETIC: made from SYNTHETIC radar volumes (atmoglobe synth), not measurements");
  w.text(NC_GLOBAL, "source", "atmoglobe mosaic: each radar sampled in its own polar geometry (volume/PolarVolume.h)");
  w.text(NC_GLOBAL, "overlap_rule", toString(meta.rule));
  w.text(NC_GLOBAL, "overlap_rule_formula", overlapRuleFormula(meta.rule));
  w.text(NC_GLOBAL, "radar_sites", sites.str());
  w.text(NC_GLOBAL, "radar_times", times.str());
  w.text(NC_GLOBAL, "radar_files", files.str());
  w.text(NC_GLOBAL, "radar_positions_lat_lon_deg", positions.str());
  if (!latestIso.empty()) w.text(NC_GLOBAL, "time_coverage_end", latestIso);
  w.check(nc_enddef(ncid), "end of definitions");
  if (!w.ok()) return closeAndCommitNetcdf(path, temp, w);  // fails: removes the temporary

  if (hasTime) w.check(nc_put_var_double(ncid, vTime, &latest), "time");
  w.check(nc_put_var_double(ncid, vAlt, axis(spec.bottomMeters, spec.topMeters, spec.nz).data()), "altitude");
  w.check(nc_put_var_double(ncid, vLat, axis(spec.southDeg, spec.northDeg, spec.ny).data()), "lat");
  // Longitudes as the spec runs them (continuous; across the antimeridian above 180).
  w.check(nc_put_var_double(ncid, vLon, axis(spec.westDeg, spec.eastDeg, spec.nx).data()), "lon");
  w.check(nc_put_var_float(ncid, vField, values.data()), name);
  return closeAndCommitNetcdf(path, temp, w);
}

}  // namespace atmoglobe::volume
