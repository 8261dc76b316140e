#pragma once
// A synthetic but realistic radar volume, written as CfRadial 1.4 (netCDF-4).
//
// What it is for: the default scene (which must work without any sample radar file) and tests
// that need a volume whose truth is known everywhere. The file is labelled SYNTHETIC in its global
// `title`, `source` and `comment` attributes and in the DBZ variable's `comment`.
//
// Scan strategy: NEXRAD VCP 212 elevations (the angles of VCP 12: NOAA Warning Decision Training
// Branch, Distance Learning Operations Course, topic 3 lesson 1, fig. 17), 360 rays of 1 deg (ray
// centres at k + 0.5 deg; each sweep starts at a different azimuth, as real sweeps do), 250 m gates
// from 2125 m (the WSR-88D first gate) to 230 km. Beam width 0.95 deg (same source).
//
// Site: KTLX (Oklahoma City / Twin Lakes WSR-88D), from
// the OURadar station list (nexrad-locations.json of github.com/OURadar/radar-data):
//   latitude 35.33305555555556, longitude -97.27777777777777 (deg, WGS84),
//   ground elevation 369.7224 m (1213 ft) + tower height 15.0 m -> antenna 384.7224 m above MSL.
//
// The storm: an analytic 3-D reflectivity model (syntheticStormDbz) evaluated at each gate's
// beam centre: a tilted supercell core (~64 dBZ, echo top ~13 km), a forward-flank precipitation area, a bounded
// weak-echo region and a low-level hook on the updraft side, an anvil spreading downwind at 9-12 km (15-25 dBZ), and a
// stratiform area (20-35 dBZ) with a bright band at the 0 C level (3.8 km), plus Gaussian noise. Components add in
// linear reflectivity (mm^6 m^-3), as echoes do.
//
// "No echo": CfRadial 1.x has no code for "measured, nothing detected", so gates below
// minEchoDbz are written as the DBZ _FillValue (our reader turns them into kNoData), as
// most CfRadial writers do for below-threshold gates. The file's DBZ `comment` says so.
#include <atmoglobe/globe/Result.h>

#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::volume {

/// NEXRAD VCP 12/212 elevation angles (degrees), lowest first (NOAA WDTB Distance Learning
/// Operations Course, topic 3 lesson 1, fig. 17).
inline const std::vector<double>& vcp212ElevationsDeg() {
  static const std::vector<double> kAngles = {0.5, 0.9, 1.3, 1.8, 2.4, 3.1, 4.0, 5.1, 6.4, 8.0, 10.0, 12.5, 15.6, 19.5};
  return kAngles;
}

/// A storm of a network field (SyntheticRadarOptions::networkStorms): the supercell model of
/// syntheticStormDbz centred on (latDeg, lonDeg) at the field's start time, in the
/// azimuthal-equidistant plane of that point, with its own seed.
struct SyntheticNetworkStorm {
  double latDeg = 0.0, lonDeg = 0.0;
  std::uint64_t seed = 1;
};

struct SyntheticRadarOptions {
  // --- site (default KTLX; see the file comment for the source) ---
  std::string siteId = "KTLX";
  double siteLatDeg = 35.33305555555556;       ///< WGS84 latitude (degrees)
  double siteLonDeg = -97.27777777777777;      ///< WGS84 longitude (degrees)
  double antennaAltitudeMslMeters = 384.7224;  ///< antenna (feedhorn) height above mean sea level (m)

  // --- storm ---
  /// Storm (low-level core) centre relative to the site, in the site-centred azimuthal-
  /// equidistant plane (km): east = s sin(az), north = s cos(az) for the geodesic of length s
  /// and initial azimuth az from the site. Default: 62 km from KTLX, to the south-west.
  double stormEastKm = -50.0;
  double stormNorthKm = -36.0;
  std::uint64_t seed = 1;   ///< noise and texture phases
  double noiseDbz = 1.0;    ///< standard deviation of the gate noise (dB); 0: none
  double minEchoDbz = 5.0;  ///< weaker gates -> _FillValue ("no echo", see above)

  // --- scan ---
  std::vector<double> elevationsDeg = vcp212ElevationsDeg();  ///< one PPI per angle (degrees)
  int raysPerSweep = 360;                                     ///< rays of 360/raysPerSweep deg
  double firstGateRangeMeters = 2125.0;                       ///< centre of the first gate (m)
  double gateSpacingMeters = 250.0;                           ///< m
  double maxRangeMeters = 230000.0;                           ///< last gate centre <= this (m)
  double beamWidthDeg = 0.95;                                 ///< half-power beam width, both planes (degrees)
  double sweepSeconds = 18.0;                                 ///< duration of one sweep (time variable)
  std::string startTimeIso8601 = "2020-05-01T21:00:00Z";      ///< volume start, UTC, "YYYY-MM-DDTHH:MM:SSZ"

  // --- network field (`synth --sites`) ---
  /// When not empty, the gates hold one storm field shared by every radar of a network instead of
  /// the storm at stormEastKm/stormNorthKm: the sum (in linear reflectivity) of these storms, each
  /// evaluated in its own plane (stormEastKm = stormNorthKm = 0 there) at the point's position
  /// relative to its centre, moved by the motion since networkStartIso8601. Radars that overlap
  /// see the same field (syntheticNetworkDbz is its exact value).
  std::vector<SyntheticNetworkStorm> networkStorms;
  std::string networkStartIso8601 = "2020-05-01T21:00:00Z";
  double networkMotionEastKmPerHour = 36.0;  ///< ENE at 40 km/h, as the synthetic grid's storms
  double networkMotionNorthKmPerHour = 18.0;
  // --- velocity (`synth --velocity`) ---
  /// Also write VEL: at every gate with echo, the radial velocity (m/s, positive away from the
  /// radar) of a uniform wind equal to the network motion above (10 m/s east, 5 m/s north by
  /// default): (u sin(azimuth) + v cos(azimuth)) cos(elevation) in the site's local frame. Radars
  /// at different sites see the same wind along different beams, so their values differ where
  /// they overlap: what a network must not average.
  bool radialVelocity = false;
  // --- encoding ---
  int deflateLevel = 4;  ///< netCDF-4 zlib level 0..9 (0: none)
};

/// What writeSyntheticCfRadial wrote.
struct SyntheticRadarSummary {
  std::size_t sweeps = 0;
  std::size_t raysPerSweep = 0;
  std::size_t gatesPerRay = 0;
  std::size_t echoGates = 0;                                 ///< gates at or above minEchoDbz (the rest are _FillValue)
  double maxDbz = -std::numeric_limits<double>::infinity();  ///< largest value written (dBZ)
  double maxEastKm = 0.0, maxNorthKm = 0.0, maxHeightMslMeters = 0.0;  ///< where (site-centred plane)
  std::uintmax_t fileBytes = 0;
};

/// Checks the options a user can set (site, angles, gate geometry, counts). Errors name the
/// option and value. The gate count is capped at 4096 and rays at 3600 per sweep.
Status validateSyntheticRadarOptions(const SyntheticRadarOptions& options);

/// The storm model without noise: reflectivity (dBZ) at a point given in the site-centred
/// azimuthal-equidistant plane (eastMeters, northMeters; see stormEastKm) at `heightMslMeters`
/// above mean sea level. Returns -infinity where the model has no echo at all. Values below
/// options.minEchoDbz are returned as computed (the writer applies the threshold).
/// Deterministic for a given options.seed (the seed sets the phases of the cell texture).
double syntheticStormDbz(const SyntheticRadarOptions& options, double eastMeters, double northMeters,
                         double heightMslMeters);

/// The storms of the SYNTHETIC network field of `seed` that can reach radars at the given sites
/// (latitude, longitude in degrees) within `reachKm` of a site: one storm in 70 % of the cells of
/// a fixed 3 x 3 degree latitude/longitude lattice, at a place in the cell and with a seed drawn
/// from (seed, cell). The lattice does not depend on the sites, so every set of sites sees the same
/// storms where it looks.
std::vector<SyntheticNetworkStorm> syntheticNetworkStorms(const std::vector<std::pair<double, double>>& sitesLatLonDeg,
                                                          double reachKm, std::uint64_t seed);

/// The network field of options.networkStorms (without noise) at a geographic point and time,
/// computed exactly (one geodesic per storm): dBZ, -infinity where no storm has echo.
double syntheticNetworkDbz(const SyntheticRadarOptions& options, double latDeg, double lonDeg, double heightMslMeters,
                           const std::string& timeIso8601);

/// How far (m) the writer's positions in a storm's plane may be from the exact ones: it maps each
/// ray's gates through geodesics at nodes every kNetworkNodeSpacingMeters of ground distance and
/// interpolates linearly between them (the map is smooth: the error is about spacing^2 / (8 R)).
inline constexpr double kNetworkNodeSpacingMeters = 10000.0;

/// Writes the volume to `path` as CfRadial 1.4 in netCDF-4 (deflated DBZ, short with
/// scale_factor 0.01 dB). Atomic: written to a hidden temporary in the same directory, closed,
/// fsynced and renamed; on any failure the temporary is removed and `path` is untouched.
///
/// Gate positions: beam-centre height and ground distance from the 4/3 effective-Earth model
/// (beamHeightAndGroundDistance, WGS84 radius at the site) with the MSL antenna height, so
/// heights are above MSL; the horizontal position is (s sin az, s cos az) in the site-centred
/// azimuthal-equidistant plane, which is exactly where geolocateGateExact's geodesic lands
/// (checked by SyntheticRadarTest). Errors: invalid options, or the file cannot be written
/// (message names the path and netCDF-C's or the OS's reason). Takes ~0.5 s for the default.
Status writeSyntheticCfRadial(const std::string& path, const SyntheticRadarOptions& options,
                              SyntheticRadarSummary* summary = nullptr);

}  // namespace atmoglobe::volume
