#pragma once
// A synthetic but realistic forecast grid, written as CF-1.8 netCDF-4: what `atmoglobe synth
// --grid` writes so that the default scene and the examples can show a grid beside the
// synthetic radar volume (SyntheticRadar.h) without any sample file.
//
// Labelled SYNTHETIC in the global `title`, `source` and `comment` attributes and in the field's
// `comment`.
//
// The grid, like the regional forecasts users bring: a regular latitude/longitude grid of
// 400 x 400 columns 5 km apart (at its centre) around KTLX, 35 levels of height above ground
// (standard_name height, 50 m to 18 km, stretched) over a surface altitude field `orog`
// (standard_name surface_altitude: the Great Plains rising towards the Rockies), 13 hourly
// steps from 2020-05-01 18:00Z. It is written the way GRIB-converted files often are: latitudes
// north to south, longitudes 0..360, so that the default scene exercises the reader's
// normalisation.
//
// The field `dbz` (simulated reflectivity, dBZ, standard_name equivalent_reflectivity_factor,
// short with scale_factor 0.01): the analytic supercell of the synthetic radar volume
// (syntheticStormDbz) moving east-north-east at 40 km/h, at the radar's position at 21Z (step 3,
// the radar volume's time), growing and then decaying, with new cells forming along a squall
// line to its north-east from 20Z on and a trailing stratiform region with a bright band behind
// the line. Clear air is -30 dBZ (the floor of models' simulated reflectivity), not missing.
// Chunks of (1 step, 7 levels, 100 x 100 columns), deflated with shuffle: a crop reads few chunks.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace atmoglobe::volume {

struct SyntheticGridOptions {
  double centerLatDeg = 35.33305555555556;  ///< grid centre (degrees): KTLX by default
  double centerLonDeg = -97.27777777777777;
  std::size_t nx = 400, ny = 400;  ///< columns (west-east) and rows (south-north)
  std::size_t levels = 35;
  std::size_t times = 13;
  double spacingKm = 5.0;                                 ///< column spacing at the centre (km), both directions
  double lowestLevelMeters = 50.0;                        ///< lowest level above ground (m)
  double topLevelMeters = 18000.0;                        ///< highest level above ground (m)
  std::string startTimeIso8601 = "2020-05-01T18:00:00Z";  ///< first step, "YYYY-MM-DDTHH:MM:SSZ"
  double stepHours = 1.0;
  /// The radar storm model and its site: the supercell is this one (stormEastKm/NorthKm give its
  /// place at `radarTimeIso8601`, relative to the radar site).
  SyntheticRadarOptions storm;
  std::string radarTimeIso8601 = "2020-05-01T21:00:00Z";
  double motionEastKmPerHour = 36.0;  ///< storm-system motion (km/h): ENE at 40 km/h
  double motionNorthKmPerHour = 18.0;
  int deflateLevel = 2;  ///< netCDF-4 zlib level 0..9 (0: none)
};

/// What writeSyntheticGrid wrote.
struct SyntheticGridSummary {
  std::size_t nx = 0, ny = 0, levels = 0, times = 0;
  std::size_t echoValues = 0;  ///< values at or above 5 dBZ, all steps
  double maxDbz = -std::numeric_limits<double>::infinity();
  std::uintmax_t fileBytes = 0;
};

/// Checks the options (sizes: nx, ny 2..2000, levels 2..200, times 1..1000, at most 2^31 values;
/// spacing 0.1..100 km, the grid inside +-85 degrees of latitude). Errors name the option.
Status validateSyntheticGridOptions(const SyntheticGridOptions& options);

/// Writes the grid to `path` atomically (temporary beside it, fsync, rename; AtomicFile.h).
/// Errors: invalid options, or the file cannot be written (message names the path). The default
/// takes under a second and makes a file of about 1.6 MB.
Status writeSyntheticGrid(const std::string& path, const SyntheticGridOptions& options,
                          SyntheticGridSummary* summary = nullptr);

/// A SYNTHETIC global forecast grid on pressure levels, laid out as ERA5's 0.25-degree pressure-level
/// files are: latitudes 90 .. -90 (north to south, both poles included), longitudes 0 .. 359.75,
/// the 37 ERA5 levels written top first (1 .. 1000 hPa), `z` geopotential (m2 s-2, standard_name
/// geopotential, float) so that the reader takes heights from it, and `dbz` simulated
/// reflectivity (short, scale 0.01) holding weather with structure at every scale: tropical
/// cyclones (eye, eyewall, spiral rain bands), mid-latitude frontal rain bands along wavy storm
/// tracks (with a bright band at the melting level) and scattered convective cells along the
/// ITCZ; clear air -30 dBZ. The geopotential is the standard atmosphere's, thicker in the tropics
/// and thinner towards the poles (+-4.5 %), with planetary waves in mid-latitudes. What the grid
/// bench draws as its global case (tools/bench, docs/grids.md "Benchmark").
struct SyntheticGlobalGridOptions {
  std::size_t nx = 1440, ny = 721;  ///< columns (0..360, exclusive) and rows (pole to pole, inclusive)
  std::size_t times = 1;
  std::string startTimeIso8601 = "2020-09-01T12:00:00Z";
  double stepHours = 6.0;
  int seed = 7;          ///< places the convective cells
  int deflateLevel = 1;  ///< netCDF-4 zlib level 0..9 (0: contiguous, uncompressed)
};

/// The 37 ERA5 pressure levels (hPa), top first as ERA5 writes them.
const std::vector<double>& era5PressureLevelsHpa();

/// The synthetic global field: reflectivity (dBZ) at geodetic latitude/longitude (deg) and
/// height above sea level `zMeters`, at `hours` after the start (the systems move); -30 in clear
/// air. The geopotential (m2 s-2) of pressure level `pressureHpa` there. Exposed for the tests.
double syntheticGlobalDbz(double latDeg, double lonDeg, double zMeters, double hours, int seed);
double syntheticGlobalGeopotential(double latDeg, double lonDeg, double pressureHpa);

/// Checks the options (nx 8..2880, ny 5..1441, times 1..100). Errors name the option.
Status validateSyntheticGlobalGridOptions(const SyntheticGlobalGridOptions& options);

/// Writes the global grid to `path` atomically. The default (1440 x 721 x 37, one step) takes a
/// few seconds and makes a file of about 100 MB (the geopotential is most of it).
Status writeSyntheticGlobalGrid(const std::string& path, const SyntheticGlobalGridOptions& options,
                                SyntheticGridSummary* summary = nullptr);

}  // namespace atmoglobe::volume
