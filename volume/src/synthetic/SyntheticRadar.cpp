#include <atmoglobe/volume/SyntheticRadar.h>

#include "../export/NcWriter.h"

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/io/NetcdfLock.h>
#include <atmoglobe/volume/AtomicFile.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarReader.h>

#include <netcdf.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <limits>

namespace atmoglobe::volume {

namespace {

constexpr double kDbzScale = 0.01;  // DBZ scale_factor (dB per count)
constexpr short kDbzFill = -32768;  // DBZ _FillValue
constexpr double kVelScale = 0.01;  // VEL scale_factor (m/s per count); fill as DBZ's
constexpr int kMaxGates = 4096;
constexpr int kMaxRays = 3600;

// SplitMix64 (Steele, Lea & Flood 2014): a counter-based generator, so each gate's noise depends
// only on (seed, gate index) and not on evaluation order.
std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

double unitFromBits(std::uint64_t bits) {  // (0, 1]
  return (static_cast<double>(bits >> 11) + 1.0) * (1.0 / 9007199254740992.0);
}

// Standard normal from two hashed uniforms (Box-Muller); portable, unlike std::normal_distribution.
double gaussian(std::uint64_t seed, std::uint64_t index) {
  const double u1 = unitFromBits(splitMix64(seed ^ splitMix64(2 * index)));
  const double u2 = unitFromBits(splitMix64(seed ^ splitMix64(2 * index + 1)));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// Adds a component given in dBZ to a linear reflectivity sum (mm^6 m^-3). Components below
// -20 dBZ change the total by < 0.01 dB wherever anything visible is present: skipped.
void addDbz(double& linearZ, double dbz) {
  if (dbz > -20.0) linearZ += std::pow(10.0, dbz / 10.0);
}

// Texture phases for the stratiform region, from the seed.
struct Texture {
  double phase[3];
};

Texture textureFor(std::uint64_t seed) {
  Texture t{};
  for (int i = 0; i < 3; ++i)
    t.phase[i] = 2.0 * kPi * unitFromBits(splitMix64(seed * 7919u + static_cast<std::uint64_t>(i)));
  return t;
}

// The storm model in km (x east, y north, relative to the site; z above MSL). See the header.
double stormDbzKm(const SyntheticRadarOptions& o, const Texture& tex, double x, double y, double z) {
  const double cx = o.stormEastKm, cy = o.stormNorthKm;
  // Shear / storm-motion direction: towards bearing 60 deg (ENE), typical of southern Plains supercells.
  const double ux = std::sin(degreesToRadians(60.0)), uy = std::cos(degreesToRadians(60.0));
  // Inflow side (updraft, weak-echo region): bearing 135 deg (SE) from the core.
  const double vx = std::sin(degreesToRadians(135.0)), vy = std::cos(degreesToRadians(135.0));
  double linearZ = 0.0;

  // 1. Core, tilted downshear by 0.35 km per km above 1 km; ~64 dBZ at the surface, slowly
  //    weakening to 7 km, then quickly: 18 dBZ at ~12.8 km, 5 dBZ at ~13.5 km (echo top).
  //    Horizontal: -22 dB at 6 km from the axis (50 dBZ within ~4.8 km, echo within ~10 km).
  const double tilt = 0.35 * std::max(z - 1.0, 0.0);
  const double kx = cx + tilt * ux, ky = cy + tilt * uy;
  const double dCore = std::hypot(x - kx, y - ky);
  {
    const double zc = std::max(z, 0.0);
    const double vert = zc < 7.0 ? -0.6 * zc : -4.2 - 1.3 * (zc - 7.0) * (zc - 7.0);
    double core = 64.0 + vert - 22.0 * (dCore / 6.0) * (dCore / 6.0);
    // 2. Bounded weak-echo region: the updraft 5 km to the SE of the core axis at each height,
    //    a hole of up to 30 dB, 2.5 km across, between ~1.5 and 7 km (under the overhang).
    const double wx = kx + 5.0 * vx, wy = ky + 5.0 * vy;
    const double dUp = std::hypot(x - wx, y - wy);
    if (dUp < 8.0) {
      const double zw = (z - 4.0) / 2.0;
      core -= 30.0 * std::exp(-(dUp / 2.5) * (dUp / 2.5)) * std::exp(-zw * zw);
    }
    addDbz(linearZ, core);

    // 3. Hook: below ~3 km, a spiral arc around the low-level updraft from its west (bearing
    //    270) cyclonically through south to bearing 150, radius 4.5 -> 3 km, 52 -> 40 dBZ.
    if (z < 5.0 && dUp < 10.0) {
      double bearing = radiansToDegrees(std::atan2(x - wx, y - wy));  // degrees clockwise from north
      if (bearing < 0) bearing += 360.0;
      const double b = std::clamp(bearing, 150.0, 270.0);
      const double f = (270.0 - b) / 120.0;  // 0 at the root, 1 at the tip
      const double arcR = 4.5 - 1.5 * f;
      const double ax = wx + arcR * std::sin(degreesToRadians(b)), ay = wy + arcR * std::cos(degreesToRadians(b));
      const double dArc = std::hypot(x - ax, y - ay);
      const double zh = std::max(z - 2.0, 0.0);
      addDbz(linearZ, 52.0 - 12.0 * f - 10.0 * dArc * dArc - 6.0 * zh * zh);
    }
  }

  // 3b. Forward-flank precipitation: from the core towards bearing 45 for ~35 km, 45 -> 30 dBZ,
  //     widening from 5 km, below ~7 km (the classic supercell's comma head).
  {
    const double fx = std::sin(degreesToRadians(45.0)), fy = std::cos(degreesToRadians(45.0));
    const double a = (x - cx) * fx + (y - cy) * fy;
    const double c = -(x - cx) * fy + (y - cy) * fx;
    if (a > -10.0 && a < 80.0 && std::fabs(c) < 40.0) {
      const double w = 5.0 + 0.15 * std::max(a, 0.0);
      const double zt = std::max(z - 6.0, 0.0);
      double ffd = 45.0 - 15.0 * std::max(a, 0.0) / 35.0 - 20.0 * (c / w) * (c / w) - 2.0 * zt * zt;
      if (a < 0) ffd -= 1.0 * a * a;
      addDbz(linearZ, ffd);
    }
  }

  // 4. Anvil: from the core top downwind (bearing 60) for ~80 km at 9-12 km, widening
  //    from 6 km; 24 dBZ near the core, 15 dBZ at 80 km.
  {
    const double ox = cx + 0.35 * 11.0 * ux, oy = cy + 0.35 * 11.0 * uy;
    const double a = (x - ox) * ux + (y - oy) * uy;
    const double c = -(x - ox) * uy + (y - oy) * ux;
    const double w = 6.0 + 0.35 * std::max(a, 0.0);
    const double zv = (z - 10.5) / 1.3;
    double anvil = 24.0 - 9.0 * std::max(a, 0.0) / 80.0 - 12.0 * (c / w) * (c / w) - 10.0 * zv * zv;
    if (a < 0) anvil -= 2.0 * a * a;
    addDbz(linearZ, anvil);
  }

  // 5. Stratiform area north of the storm (centre +(-5, +45) km), an ellipse 40 x 22 km along
  //    bearing 30, 20-35 dBZ with cellular texture; bright band at the 0 C level (3.8 km).
  {
    const double sx = cx - 5.0, sy = cy + 45.0;
    const double px = std::sin(degreesToRadians(30.0)), py = std::cos(degreesToRadians(30.0));
    const double a = ((x - sx) * px + (y - sy) * py) / 40.0;
    const double c = (-(x - sx) * py + (y - sy) * px) / 22.0;
    const double q2 = a * a + c * c;
    if (q2 < 3.0) {
      const double texture = 2.0 * std::sin(x / 9.0 * 2.0 * kPi + tex.phase[0]) +
                             1.5 * std::sin(y / 13.0 * 2.0 * kPi + tex.phase[1]) +
                             1.0 * std::sin((x + y) / 17.0 * 2.0 * kPi + tex.phase[2]);
      const double base = 31.0 - 11.0 * q2 + texture;
      constexpr double kZeroCKm = 3.8;
      const double dz = z - kZeroCKm;
      double strat = base + 8.0 * std::exp(-(dz / 0.22) * (dz / 0.22));                     // bright band
      if (dz > 0) strat += (-7.0 - 3.5 * dz) * (1.0 - std::exp(-(dz / 0.3) * (dz / 0.3)));  // snow above
      addDbz(linearZ, strat);
    }
  }
  return linearZ > 0.0 ? 10.0 * std::log10(linearZ) : -std::numeric_limits<double>::infinity();
}

std::string dbText(double v) {  // "5", "7.5": as a person writes it
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string osError(const std::string& path, const char* what, int err) {
  return path + ": " + what + ": " + std::strerror(err);
}

bool parseIsoUtc(const std::string& s, std::tm* out) {
  int y, mo, d, h, mi, sec;
  char tail = 0;
  if (s.size() != 20 || std::sscanf(s.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c", &y, &mo, &d, &h, &mi, &sec, &tail) != 7 ||
      tail != 'Z')
    return false;
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || sec > 60 || y < 1900) return false;
  *out = std::tm{};
  out->tm_year = y - 1900;
  out->tm_mon = mo - 1;
  out->tm_mday = d;
  out->tm_hour = h;
  out->tm_min = mi;
  out->tm_sec = sec;
  return true;
}

std::string isoPlusSeconds(const std::string& iso, double seconds) {
  std::tm t{};
  if (!parseIsoUtc(iso, &t)) return iso;
  const std::time_t base = timegm(&t);
  const std::time_t end = base + static_cast<std::time_t>(std::lround(seconds));
  std::tm e{};
  gmtime_r(&end, &e);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &e);
  return buf;
}

std::size_t gateCountFor(const SyntheticRadarOptions& o) {
  return static_cast<std::size_t>(
             std::floor((o.maxRangeMeters - o.firstGateRangeMeters) / o.gateSpacingMeters + 1e-9)) +
         1;
}

struct Geometry {
  std::size_t nSweep, nRay, nGate;
};

// Writes everything to an open netCDF-4 file. Returns the error text or "".
std::string writeContents(NcWriter& w, const SyntheticRadarOptions& o, const Geometry& g, const std::vector<short>& dbz,
                          const std::vector<float>& az, const std::vector<float>& el,
                          const std::vector<double>& timeSec) {
  const int nc = w.ncid();
  const std::size_t nTime = g.nSweep * g.nRay;
  const std::string endTime = isoPlusSeconds(o.startTimeIso8601, static_cast<double>(g.nSweep) * o.sweepSeconds);

  // --- global attributes (CfRadial 1.4 format document, NCAR/UCAR: global attributes) ---
  const std::string synthetic =
      "SYNTHETIC data generated by atmoglobe (atmoglobe synth): an analytic supercell and stratiform "
      "reflectivity model sampled at real gate positions; not a measurement.";
  w.text(NC_GLOBAL, "Conventions", "CF/Radial instrument_parameters");
  w.text(NC_GLOBAL, "version", "1.4");
  w.text(NC_GLOBAL, "title", "SYNTHETIC radar volume (atmoglobe), " + o.siteId + " VCP 212 geometry");
  w.text(NC_GLOBAL, "institution", "atmoglobe (synthetic data)");
  w.text(NC_GLOBAL, "references", "CfRadial 1.4 (NCAR/EOL); NEXRAD VCP 212 elevation angles");
  w.text(NC_GLOBAL, "source", synthetic);
  w.text(NC_GLOBAL, "history", "written by atmoglobe synth, seed " + std::to_string(o.seed));
  w.text(NC_GLOBAL, "comment",
         synthetic + " Gates below " + dbText(o.minEchoDbz) +
             " dBZ (no echo) are stored as the DBZ _FillValue: CfRadial 1.x has no code for "
             "'measured, nothing detected'.");
  w.text(NC_GLOBAL, "instrument_name", o.siteId);
  w.text(NC_GLOBAL, "site_name", o.siteId);
  w.text(NC_GLOBAL, "scan_name", "VCP 212 (synthetic)");
  int scanId = 212;
  w.check(nc_put_att_int(nc, NC_GLOBAL, "scan_id", NC_INT, 1, &scanId), "scan_id");
  w.text(NC_GLOBAL, "platform_is_mobile", "false");
  w.text(NC_GLOBAL, "n_gates_vary", "false");
  w.text(NC_GLOBAL, "ray_times_increase", "true");
  w.text(NC_GLOBAL, "field_names", o.radialVelocity ? "DBZ,VEL" : "DBZ");
  w.text(NC_GLOBAL, "time_coverage_start", o.startTimeIso8601);
  w.text(NC_GLOBAL, "time_coverage_end", endTime);

  // --- dimensions ---
  int dTime = -1, dRange = -1, dSweep = -1, dStr = -1;
  constexpr std::size_t kStrLen = 32;
  w.check(nc_def_dim(nc, "time", nTime, &dTime), "dimension time");
  w.check(nc_def_dim(nc, "range", g.nGate, &dRange), "dimension range");
  w.check(nc_def_dim(nc, "sweep", g.nSweep, &dSweep), "dimension sweep");
  w.check(nc_def_dim(nc, "string_length", kStrLen, &dStr), "dimension string_length");
  if (!w.ok()) return w.error();

  // --- variables ---
  const int vVolume = w.var("volume_number", NC_INT, {});
  w.text(vVolume, "long_name", "data_volume_index_number");
  const int vPlatform = w.var("platform_type", NC_CHAR, {dStr});
  w.text(vPlatform, "long_name", "platform_type");
  const int vInstType = w.var("instrument_type", NC_CHAR, {dStr});
  w.text(vInstType, "long_name", "type_of_instrument");
  const int vAxis = w.var("primary_axis", NC_CHAR, {dStr});
  w.text(vAxis, "long_name", "primary_axis_of_rotation");
  const int vTcs = w.var("time_coverage_start", NC_CHAR, {dStr});
  w.text(vTcs, "long_name", "data_volume_start_time_utc");
  w.text(vTcs, "comment", "ray times are relative to start time in secs");
  const int vTce = w.var("time_coverage_end", NC_CHAR, {dStr});
  w.text(vTce, "long_name", "data_volume_end_time_utc");

  const int vLat = w.var("latitude", NC_DOUBLE, {});
  w.text(vLat, "long_name", "latitude");
  w.text(vLat, "units", "degrees_north");
  w.text(vLat, "standard_name", "latitude");
  const int vLon = w.var("longitude", NC_DOUBLE, {});
  w.text(vLon, "long_name", "longitude");
  w.text(vLon, "units", "degrees_east");
  w.text(vLon, "standard_name", "longitude");
  const int vAlt = w.var("altitude", NC_DOUBLE, {});
  w.text(vAlt, "long_name", "altitude");
  w.text(vAlt, "units", "meters");
  w.text(vAlt, "positive", "up");
  w.text(vAlt, "comment", "antenna (feedhorn) height above mean sea level");

  const int vSweepNum = w.var("sweep_number", NC_INT, {dSweep});
  w.text(vSweepNum, "long_name", "sweep_index_number_0_based");
  const int vSweepMode = w.var("sweep_mode", NC_CHAR, {dSweep, dStr});
  w.text(vSweepMode, "long_name", "scan_mode_for_sweep");
  w.text(
      vSweepMode, "options",
      "sector, coplane, rhi, vertical_pointing, idle, azimuth_surveillance, elevation_surveillance, sunscan, pointing, manual_ppi, manual_rhi");
  const int vFixed = w.var("fixed_angle", NC_FLOAT, {dSweep});
  w.text(vFixed, "long_name", "ray_target_fixed_angle");
  w.text(vFixed, "units", "degrees");
  const int vStart = w.var("sweep_start_ray_index", NC_INT, {dSweep});
  w.text(vStart, "long_name", "index_of_first_ray_in_sweep");
  const int vEnd = w.var("sweep_end_ray_index", NC_INT, {dSweep});
  w.text(vEnd, "long_name", "index_of_last_ray_in_sweep");

  const int vTime = w.var("time", NC_DOUBLE, {dTime});
  w.text(vTime, "standard_name", "time");
  w.text(vTime, "long_name", "time_in_seconds_since_volume_start");
  w.text(vTime, "units", "seconds since " + o.startTimeIso8601);
  w.text(vTime, "calendar", "gregorian");
  const int vRange = w.var("range", NC_FLOAT, {dRange});
  w.text(vRange, "long_name", "range_to_center_of_measurement_volume");
  w.text(vRange, "standard_name", "projection_range_coordinate");
  w.text(vRange, "units", "meters");
  w.text(vRange, "axis", "radial_range_coordinate");
  w.text(vRange, "spacing_is_constant", "true");
  const float firstGate = static_cast<float>(o.firstGateRangeMeters), spacing = static_cast<float>(o.gateSpacingMeters);
  w.check(nc_put_att_float(nc, vRange, "meters_to_center_of_first_gate", NC_FLOAT, 1, &firstGate), "range attributes");
  w.check(nc_put_att_float(nc, vRange, "meters_between_gates", NC_FLOAT, 1, &spacing), "range attributes");
  const int vAz = w.var("azimuth", NC_FLOAT, {dTime});
  w.text(vAz, "long_name", "ray_azimuth_angle");
  w.text(vAz, "units", "degrees");
  const int vEl = w.var("elevation", NC_FLOAT, {dTime});
  w.text(vEl, "long_name", "ray_elevation_angle");
  w.text(vEl, "units", "degrees");
  w.text(vEl, "positive", "up");

  const int vBwH = w.var("radar_beam_width_h", NC_FLOAT, {});
  w.text(vBwH, "long_name", "half_power_radar_beam_width_h_channel");
  w.text(vBwH, "units", "degrees");
  w.text(vBwH, "meta_group", "radar_parameters");
  const int vBwV = w.var("radar_beam_width_v", NC_FLOAT, {});
  w.text(vBwV, "long_name", "half_power_radar_beam_width_v_channel");
  w.text(vBwV, "units", "degrees");
  w.text(vBwV, "meta_group", "radar_parameters");

  const int vDbz = w.var("DBZ", NC_SHORT, {dTime, dRange});
  w.text(vDbz, "long_name", "equivalent_reflectivity_factor");
  w.text(vDbz, "standard_name", "equivalent_reflectivity_factor");
  w.text(vDbz, "units", "dBZ");
  const float scale = static_cast<float>(kDbzScale), offset = 0.0f;
  w.check(nc_put_att_float(nc, vDbz, "scale_factor", NC_FLOAT, 1, &scale), "DBZ scale_factor");
  w.check(nc_put_att_float(nc, vDbz, "add_offset", NC_FLOAT, 1, &offset), "DBZ add_offset");
  short fill = kDbzFill;
  w.check(nc_def_var_fill(nc, vDbz, 0, &fill), "DBZ _FillValue");
  w.text(vDbz, "coordinates", "elevation azimuth range");
  w.text(vDbz, "comment",
         "SYNTHETIC (atmoglobe analytic storm model, seed " + std::to_string(o.seed) +
             "). _FillValue marks gates below " + dbText(o.minEchoDbz) +
             " dBZ: no echo (CfRadial cannot say 'no echo' otherwise).");
  if (o.deflateLevel > 0) {
    w.check(nc_def_var_chunking(nc, vDbz, NC_CHUNKED, std::vector<std::size_t>{g.nRay, g.nGate}.data()),
            "DBZ chunking");
    w.check(nc_def_var_deflate(nc, vDbz, 1, 1, o.deflateLevel), "DBZ deflate");
  }
  int vVel = -1;
  if (o.radialVelocity) {
    vVel = w.var("VEL", NC_SHORT, {dTime, dRange});
    w.text(vVel, "long_name", "radial_velocity_of_scatterers_away_from_instrument");
    w.text(vVel, "standard_name", "radial_velocity_of_scatterers_away_from_instrument");
    w.text(vVel, "units", "m/s");
    const float velScale = static_cast<float>(kVelScale);
    w.check(nc_put_att_float(nc, vVel, "scale_factor", NC_FLOAT, 1, &velScale), "VEL scale_factor");
    w.check(nc_put_att_float(nc, vVel, "add_offset", NC_FLOAT, 1, &offset), "VEL add_offset");
    w.check(nc_def_var_fill(nc, vVel, 0, &fill), "VEL _FillValue");
    w.text(vVel, "coordinates", "elevation azimuth range");
    w.text(vVel, "comment",
           "SYNTHETIC: the radial component of a uniform wind (the storms' motion) at gates with echo; "
           "_FillValue elsewhere.");
    if (o.deflateLevel > 0) {
      w.check(nc_def_var_chunking(nc, vVel, NC_CHUNKED, std::vector<std::size_t>{g.nRay, g.nGate}.data()),
              "VEL chunking");
      w.check(nc_def_var_deflate(nc, vVel, 1, 1, o.deflateLevel), "VEL deflate");
    }
  }
  w.check(nc_enddef(nc), "end of definitions");
  if (!w.ok()) return w.error();

  // --- data ---
  auto putText = [&](int varid, std::size_t row, bool is2d, const std::string& s) {
    std::string padded = s.substr(0, kStrLen);
    padded.resize(kStrLen, '\0');
    if (is2d) {
      const std::size_t start[2] = {row, 0}, count[2] = {1, kStrLen};
      w.check(nc_put_vara_text(nc, varid, start, count, padded.data()), "text variable");
    } else {
      const std::size_t start[1] = {0}, count[1] = {kStrLen};
      w.check(nc_put_vara_text(nc, varid, start, count, padded.data()), "text variable");
    }
  };
  int volumeNumber = 0;
  w.check(nc_put_var_int(nc, vVolume, &volumeNumber), "volume_number");
  putText(vPlatform, 0, false, "fixed");
  putText(vInstType, 0, false, "radar");
  putText(vAxis, 0, false, "axis_z");
  putText(vTcs, 0, false, o.startTimeIso8601);
  putText(vTce, 0, false, endTime);
  w.check(nc_put_var_double(nc, vLat, &o.siteLatDeg), "latitude");
  w.check(nc_put_var_double(nc, vLon, &o.siteLonDeg), "longitude");
  w.check(nc_put_var_double(nc, vAlt, &o.antennaAltitudeMslMeters), "altitude");
  std::vector<int> sweepNumber(g.nSweep), starts(g.nSweep), ends(g.nSweep);
  std::vector<float> fixed(g.nSweep);
  for (std::size_t s = 0; s < g.nSweep; ++s) {
    sweepNumber[s] = static_cast<int>(s);
    starts[s] = static_cast<int>(s * g.nRay);
    ends[s] = static_cast<int>((s + 1) * g.nRay - 1);
    fixed[s] = static_cast<float>(o.elevationsDeg[s]);
    putText(vSweepMode, s, true, "azimuth_surveillance");
  }
  w.check(nc_put_var_int(nc, vSweepNum, sweepNumber.data()), "sweep_number");
  w.check(nc_put_var_float(nc, vFixed, fixed.data()), "fixed_angle");
  w.check(nc_put_var_int(nc, vStart, starts.data()), "sweep_start_ray_index");
  w.check(nc_put_var_int(nc, vEnd, ends.data()), "sweep_end_ray_index");
  w.check(nc_put_var_double(nc, vTime, timeSec.data()), "time");
  std::vector<float> range(g.nGate);
  for (std::size_t k = 0; k < g.nGate; ++k)
    range[k] = static_cast<float>(o.firstGateRangeMeters + static_cast<double>(k) * o.gateSpacingMeters);
  w.check(nc_put_var_float(nc, vRange, range.data()), "range");
  w.check(nc_put_var_float(nc, vAz, az.data()), "azimuth");
  w.check(nc_put_var_float(nc, vEl, el.data()), "elevation");
  const float bw = static_cast<float>(o.beamWidthDeg);
  w.check(nc_put_var_float(nc, vBwH, &bw), "radar_beam_width_h");
  w.check(nc_put_var_float(nc, vBwV, &bw), "radar_beam_width_v");
  w.check(nc_put_var_short(nc, vDbz, dbz.data()), "DBZ");
  if (o.radialVelocity) {
    // The wind's radial component where there is echo (a velocity needs scatterers).
    const double u = o.networkMotionEastKmPerHour / 3.6, v = o.networkMotionNorthKmPerHour / 3.6;
    std::vector<short> vel(dbz.size(), kDbzFill);
    for (std::size_t ray = 0; ray < nTime; ++ray) {
      const double a = degreesToRadians(static_cast<double>(az[ray]));
      const double e = degreesToRadians(static_cast<double>(el[ray]));
      const double radial = (u * std::sin(a) + v * std::cos(a)) * std::cos(e);
      const short stored = static_cast<short>(std::clamp(std::round(radial / kVelScale), -32767.0, 32767.0));
      for (std::size_t k = 0; k < g.nGate; ++k)
        if (dbz[ray * g.nGate + k] != kDbzFill) vel[ray * g.nGate + k] = stored;
    }
    w.check(nc_put_var_short(nc, vVel, vel.data()), "VEL");
  }
  return w.ok() ? std::string() : w.error();
}

// --- the network field (SyntheticRadarOptions::networkStorms) --------------------------------
constexpr double kStormReachKm = 250.0;  // no component of the storm model reaches farther
constexpr double kLatticeDeg = 3.0;      // syntheticNetworkStorms: one cell per storm at most
constexpr double kStormChance = 0.7;

struct NetworkStorm {
  SyntheticRadarOptions options;  // the model centred at the origin of the storm's plane
  Texture tex;
  double latDeg, lonDeg;
};

std::vector<NetworkStorm> networkStormsOf(const SyntheticRadarOptions& o) {
  std::vector<NetworkStorm> out;
  for (const SyntheticNetworkStorm& s : o.networkStorms) {
    NetworkStorm n{o, textureFor(s.seed), s.latDeg, s.lonDeg};
    n.options.stormEastKm = 0.0;
    n.options.stormNorthKm = 0.0;
    n.options.seed = s.seed;
    n.options.networkStorms.clear();
    out.push_back(std::move(n));
  }
  return out;
}

double hoursFromNetworkStart(const SyntheticRadarOptions& o, const std::string& timeIso8601) {
  const double a = iso8601ToEpochSeconds(o.networkStartIso8601), b = iso8601ToEpochSeconds(timeIso8601);
  return std::isfinite(a) && std::isfinite(b) ? (b - a) / 3600.0 : 0.0;
}

// Adds storm n's reflectivity at (x, y) km of its plane, z km above MSL, `hours` after the start.
void addStorm(double& linearZ, const NetworkStorm& n, const SyntheticRadarOptions& o, double x, double y, double z,
              double hours) {
  if (x * x + y * y > kStormReachKm * kStormReachKm) return;
  const double v = stormDbzKm(n.options, n.tex, x - o.networkMotionEastKmPerHour * hours,
                              y - o.networkMotionNorthKmPerHour * hours, z);
  if (std::isfinite(v)) addDbz(linearZ, v);
}

double dbzOf(double linearZ) {
  return linearZ > 0.0 ? 10.0 * std::log10(linearZ) : -std::numeric_limits<double>::infinity();
}

}  // namespace

Status validateSyntheticRadarOptions(const SyntheticRadarOptions& o) {
  auto bad = [](const std::string& what) { return makeError("synthetic radar: " + what); };
  if (o.siteId.empty() || o.siteId.size() > 31) return bad("site id must have 1..31 characters");
  if (!(o.siteLatDeg >= -90.0 && o.siteLatDeg <= 90.0))
    return bad("site latitude " + std::to_string(o.siteLatDeg) + " is outside [-90, 90]");
  if (!(o.siteLonDeg >= -180.0 && o.siteLonDeg <= 180.0))
    return bad("site longitude " + std::to_string(o.siteLonDeg) + " is outside [-180, 180]");
  if (!(std::fabs(o.antennaAltitudeMslMeters) <= 10000.0)) return bad("antenna altitude must be within +-10000 m");
  if (!(std::fabs(o.stormEastKm) <= 1000.0 && std::fabs(o.stormNorthKm) <= 1000.0))
    return bad("storm offset must be within +-1000 km");
  if (!(o.noiseDbz >= 0.0 && o.noiseDbz <= 20.0)) return bad("noise must be in [0, 20] dB");
  if (!(o.minEchoDbz >= -30.0 && o.minEchoDbz <= 60.0)) return bad("minimum echo must be in [-30, 60] dBZ");
  if (o.elevationsDeg.empty() || o.elevationsDeg.size() > 64) return bad("1..64 elevation angles needed");
  for (double e : o.elevationsDeg)
    if (!(e >= -2.0 && e <= 90.0)) return bad("elevation " + std::to_string(e) + " deg is outside [-2, 90]");
  if (o.raysPerSweep < 1 || o.raysPerSweep > kMaxRays) return bad("rays per sweep must be in [1, 3600]");
  if (!(o.firstGateRangeMeters >= 0.0 && o.gateSpacingMeters >= 1.0 && o.maxRangeMeters > o.firstGateRangeMeters &&
        o.maxRangeMeters <= 1.0e6))
    return bad("gate geometry: need first gate >= 0, spacing >= 1 m, first < max range <= 1000 km");
  if (gateCountFor(o) > static_cast<std::size_t>(kMaxGates)) return bad("more than 4096 gates per ray");
  if (!(o.beamWidthDeg > 0.0 && o.beamWidthDeg <= 10.0)) return bad("beam width must be in (0, 10] deg");
  if (!(o.sweepSeconds > 0.0 && o.sweepSeconds <= 3600.0)) return bad("sweep duration must be in (0, 3600] s");
  std::tm t{};
  if (!parseIsoUtc(o.startTimeIso8601, &t))
    return bad("start time '" + o.startTimeIso8601 + "' is not YYYY-MM-DDTHH:MM:SSZ");
  if (o.deflateLevel < 0 || o.deflateLevel > 9) return bad("deflate level must be 0..9");
  return Ok{};
}

double syntheticStormDbz(const SyntheticRadarOptions& options, double eastMeters, double northMeters,
                         double heightMslMeters) {
  return stormDbzKm(options, textureFor(options.seed), eastMeters / 1000.0, northMeters / 1000.0,
                    heightMslMeters / 1000.0);
}

std::vector<SyntheticNetworkStorm> syntheticNetworkStorms(const std::vector<std::pair<double, double>>& sitesLatLonDeg,
                                                          double reachKm, std::uint64_t seed) {
  std::vector<SyntheticNetworkStorm> out;
  if (sitesLatLonDeg.empty()) return out;
  // Candidate cells: those within the sites' reach plus a cell, by latitude/longitude bounds.
  const double reachDeg = reachKm / 111.0 + kLatticeDeg;
  const int rows = static_cast<int>(180.0 / kLatticeDeg), cols = static_cast<int>(360.0 / kLatticeDeg);
  std::vector<char> taken(static_cast<std::size_t>(rows) * cols, 0);
  for (const auto& [lat, lon] : sitesLatLonDeg) {
    const double lonReach = std::min(
        180.0, reachDeg / std::max(0.05, std::cos(degreesToRadians(std::min(89.0, std::fabs(lat) + reachDeg)))));
    const int r0 = std::max(0, static_cast<int>(std::floor((lat - reachDeg + 90.0) / kLatticeDeg)));
    const int r1 = std::min(rows - 1, static_cast<int>(std::floor((lat + reachDeg + 90.0) / kLatticeDeg)));
    const int c0 = static_cast<int>(std::floor((lon - lonReach + 180.0) / kLatticeDeg));
    const int c1 = static_cast<int>(std::floor((lon + lonReach + 180.0) / kLatticeDeg));
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) {
        const int cw = ((c % cols) + cols) % cols;
        char& t = taken[static_cast<std::size_t>(r) * cols + cw];
        if (t) continue;
        t = 1;
        const std::uint64_t cell = static_cast<std::uint64_t>(r) * 1000u + static_cast<std::uint64_t>(cw);
        const std::uint64_t h = splitMix64(seed * 0x2545F4914F6CDD1Dull ^ splitMix64(cell));
        if (unitFromBits(h) > kStormChance) continue;
        SyntheticNetworkStorm s;
        s.latDeg = -90.0 + kLatticeDeg * (r + 0.15 + 0.7 * unitFromBits(splitMix64(h + 1)));
        s.lonDeg = -180.0 + kLatticeDeg * (cw + 0.15 + 0.7 * unitFromBits(splitMix64(h + 2)));
        s.seed = splitMix64(h + 3) % 1000000u + 1u;
        // Kept when within reach of a site (exact distance).
        bool near = false;
        for (const auto& [la, lo] : sitesLatLonDeg)
          if (globe::geodesicInverse(la, lo, s.latDeg, s.lonDeg).distanceMeters <= reachKm * 1000.0) {
            near = true;
            break;
          }
        if (near) out.push_back(s);
      }
  }
  return out;
}

double syntheticNetworkDbz(const SyntheticRadarOptions& o, double latDeg, double lonDeg, double heightMslMeters,
                           const std::string& timeIso8601) {
  const double hours = hoursFromNetworkStart(o, timeIso8601);
  double linearZ = 0.0;
  for (const NetworkStorm& n : networkStormsOf(o)) {
    const globe::GeodesicLine g = globe::geodesicInverse(n.latDeg, n.lonDeg, latDeg, lonDeg);
    const double a = degreesToRadians(g.azimuth1Deg), d = g.distanceMeters / 1000.0;
    addStorm(linearZ, n, o, d * std::sin(a), d * std::cos(a), heightMslMeters / 1000.0, hours);
  }
  return dbzOf(linearZ);
}

Status writeSyntheticCfRadial(const std::string& path, const SyntheticRadarOptions& o, SyntheticRadarSummary* summary) {
  if (auto st = validateSyntheticRadarOptions(o); !st) return st;
  const Geometry g{o.elevationsDeg.size(), static_cast<std::size_t>(o.raysPerSweep), gateCountFor(o)};
  const std::size_t nTime = g.nSweep * g.nRay;

  // --- rays: angles and times; each sweep starts 37 rays further round (real sweeps start anywhere) ---
  std::vector<float> az(nTime), el(nTime);
  std::vector<double> timeSec(nTime);
  const double rayDeg = 360.0 / static_cast<double>(g.nRay);
  for (std::size_t s = 0; s < g.nSweep; ++s) {
    const std::size_t startRay = (s * 37) % g.nRay;
    for (std::size_t k = 0; k < g.nRay; ++k) {
      const std::size_t i = s * g.nRay + k;
      az[i] = static_cast<float>((static_cast<double>((startRay + k) % g.nRay) + 0.5) * rayDeg);
      el[i] = static_cast<float>(o.elevationsDeg[s]);
      timeSec[i] =
          o.sweepSeconds * (static_cast<double>(s) + (static_cast<double>(k) + 0.5) / static_cast<double>(g.nRay));
    }
  }

  // --- values: beam-centre height and ground distance per (sweep, gate), position per ray ---
  BeamModel model;  // 4/3, WGS84 radius at the site latitude
  const double re = effectiveEarthRadiusMeters(model, o.siteLatDeg);
  const Texture tex = textureFor(o.seed);
  std::vector<short> dbz(nTime * g.nGate, kDbzFill);
  SyntheticRadarSummary sum;
  sum.sweeps = g.nSweep;
  sum.raysPerSweep = g.nRay;
  sum.gatesPerRay = g.nGate;
  std::vector<double> heightKm(g.nGate), groundKm(g.nGate);
  // Network field: the storms that can reach this radar, and per ray their planes' coordinates at
  // ground-distance nodes (interpolated linearly to the gates).
  std::vector<NetworkStorm> storms;
  const double maxGroundMeters = o.maxRangeMeters + 1000.0;
  for (NetworkStorm& n : networkStormsOf(o))
    if (globe::geodesicInverse(o.siteLatDeg, o.siteLonDeg, n.latDeg, n.lonDeg).distanceMeters <=
        maxGroundMeters + kStormReachKm * 1000.0)
      storms.push_back(std::move(n));
  const std::size_t nodes = static_cast<std::size_t>(std::ceil(maxGroundMeters / kNetworkNodeSpacingMeters)) + 2;
  std::vector<double> nodeXy(storms.size() * nodes * 2);
  const double hours = hoursFromNetworkStart(o, o.startTimeIso8601);
  for (std::size_t s = 0; s < g.nSweep; ++s) {
    for (std::size_t k = 0; k < g.nGate; ++k) {
      double h = 0, sd = 0;
      // Uses the stored (float) angle, so the file's geometry and the values agree exactly.
      beamHeightAndGroundDistance(o.firstGateRangeMeters + static_cast<double>(k) * o.gateSpacingMeters,
                                  static_cast<double>(el[s * g.nRay]), o.antennaAltitudeMslMeters, re, &h, &sd);
      heightKm[k] = h / 1000.0;
      groundKm[k] = sd / 1000.0;
    }
    for (std::size_t r = 0; r < g.nRay; ++r) {
      const std::size_t ray = s * g.nRay + r;
      const double a = degreesToRadians(static_cast<double>(az[ray]));
      const double sa = std::sin(a), ca = std::cos(a);
      if (!storms.empty()) {
        // Network field: each node's position in each storm's plane, exactly (two geodesics).
        for (std::size_t j = 0; j < nodes; ++j) {
          const globe::GeodesicPoint p = globe::geodesicDirect(o.siteLatDeg, o.siteLonDeg, static_cast<double>(az[ray]),
                                                               kNetworkNodeSpacingMeters * static_cast<double>(j));
          for (std::size_t i = 0; i < storms.size(); ++i) {
            const globe::GeodesicLine gl =
                globe::geodesicInverse(storms[i].latDeg, storms[i].lonDeg, p.latDeg, p.lonDeg);
            const double b = degreesToRadians(gl.azimuth1Deg), d = gl.distanceMeters / 1000.0;
            nodeXy[(i * nodes + j) * 2] = d * std::sin(b);
            nodeXy[(i * nodes + j) * 2 + 1] = d * std::cos(b);
          }
        }
      }
      for (std::size_t k = 0; k < g.nGate; ++k) {
        const double x = groundKm[k] * sa, y = groundKm[k] * ca;
        double v;
        if (storms.empty()) {
          v = stormDbzKm(o, tex, x, y, heightKm[k]);
        } else {
          const double t = groundKm[k] * 1000.0 / kNetworkNodeSpacingMeters;
          const std::size_t j = std::min(static_cast<std::size_t>(t), nodes - 2);
          const double f = t - static_cast<double>(j);
          double linearZ = 0.0;
          for (std::size_t i = 0; i < storms.size(); ++i) {
            const double* n0 = &nodeXy[(i * nodes + j) * 2];
            addStorm(linearZ, storms[i], o, n0[0] + f * (n0[2] - n0[0]), n0[1] + f * (n0[3] - n0[1]), heightKm[k],
                     hours);
          }
          v = dbzOf(linearZ);
        }
        if (!std::isfinite(v)) continue;
        const std::size_t idx = ray * g.nGate + k;
        if (o.noiseDbz > 0) v += o.noiseDbz * gaussian(o.seed, idx);
        if (v < o.minEchoDbz) continue;
        const double raw = std::clamp(std::round(v / kDbzScale), -32767.0, 32767.0);
        dbz[idx] = static_cast<short>(raw);
        ++sum.echoGates;
        const double stored = raw * kDbzScale;
        if (stored > sum.maxDbz) {
          sum.maxDbz = stored;
          sum.maxEastKm = x;
          sum.maxNorthKm = y;
          sum.maxHeightMslMeters = heightKm[k] * 1000.0;
        }
      }
    }
  }

  // --- atomic write: hidden temporary beside the target, then rename (AtomicFile.h) ---
  auto tempName = temporaryPathBeside(path);
  if (!tempName) return tempName.forwardError();
  const std::string temp = *tempName;
  // Create it ourselves first: the OS reason (permission, missing directory) is clearer than HDF5's.
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return makeError(osError(path, "cannot create file in its directory", errno));
  ::close(fd);
  const io::NetcdfLock lock;  // from nc_create to nc_close (io/NetcdfLock.h)
  int ncid = -1;
  if (const int st = nc_create(temp.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid); st != NC_NOERR) {
    ::unlink(temp.c_str());
    return makeError(path + ": cannot create netCDF-4 file: " + nc_strerror(st));
  }
  NcWriter w(path, ncid);
  std::string err = writeContents(w, o, g, dbz, az, el, timeSec);
  if (const int st = nc_close(ncid); st != NC_NOERR && err.empty())
    err = path + ": netCDF close failed: " + nc_strerror(st);
  if (!err.empty()) {
    ::unlink(temp.c_str());
    return makeError(err);
  }
  if (Status st = commitTemporary(temp, path); !st) return st;
  std::error_code ec;
  sum.fileBytes = std::filesystem::file_size(path, ec);
  if (summary) *summary = sum;
  return Ok{};
}

}  // namespace atmoglobe::volume
