#pragma once
// A 3-D mosaic of a radar network: the network sampler (RadarNetwork.h: the coverage index and an
// overlap rule) evaluated on a regular longitude x latitude x altitude grid and written as a CF-1.8
// netCDF-4 grid (readable by the engine's grid reader, ncdump and any CF tool) or as NRRD
// (NrrdExport.h). `atmoglobe mosaic` is its front end.
//
// The netCDF file: dimensions time (1), altitude (nz), lat (ny), lon (nx); coordinate variables
// lon (degrees_east), lat (degrees_north), altitude (m above mean sea level, EGM96; standard_name
// altitude, positive up) and time (seconds since 1970-01-01, the latest radar's volume time; no
// time axis when no radar gives a time); the field as float (time, altitude, lat, lon) named after
// the radars' field, with its units, its CF standard_name where the field kind has one
// (reflectivity: equivalent_reflectivity_factor) and _FillValue NaN where no radar echoes (no echo
// and no data alike). Global attributes say what made it: the rule and its formula, and per
// contributing radar its site, position, time and file.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/NrrdExport.h>
#include <atmoglobe/volume/RadarNetwork.h>

#include <string>
#include <vector>

namespace atmoglobe::volume {

/// One radar of a mosaic, as its attributes list it.
struct MosaicRadar {
  std::string site;  ///< siteTitle: "KTLX" or "bewid (Wideumont)"
  std::string timeIso8601;
  std::string path;
  double latDeg = 0.0, lonDeg = 0.0;
};

struct MosaicMetadata {
  std::string field;  ///< the radars' field name (the variable is named after it)
  std::string units;
  FieldKind kind = FieldKind::Other;
  OverlapRule rule = OverlapRule::WeightedMean;
  std::vector<MosaicRadar> radars;
  /// Some radar file says SYNTHETIC: the mosaic's title and comment say so too.
  bool synthetic = false;
};

/// The one-line formula of a rule, as the attributes and docs give it.
std::string overlapRuleFormula(OverlapRule rule);

/// Writes `values` (spec.sampleCount() floats, x fastest, then y, then z; NaN: none) of a
/// geographic spec with heights above mean sea level as the CF netCDF file described above,
/// atomically. Errors: a spec that is not geographic above MSL, a size mismatch, the file
/// cannot be written (the message names the path).
Status writeMosaicNetcdf(const std::string& path, const RegularGridSpec& spec, const std::vector<float>& values,
                         const MosaicMetadata& meta);

}  // namespace atmoglobe::volume
