#include <atmoglobe/volume/SyntheticGrid.h>

#include "../export/NcWriter.h"

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/io/NetcdfLock.h>
#include <atmoglobe/volume/AtomicFile.h>
#include <atmoglobe/volume/CfTime.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <netcdf.h>

#include <fcntl.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

namespace atmoglobe::volume {

namespace {

constexpr double kDbzScale = 0.01;  // dbz scale_factor (dB per count)
constexpr short kDbzFill = -32768;  // dbz _FillValue (never written: nothing is missing)
constexpr double kClearAirDbz = -30.0;
constexpr double kEchoDbz = 5.0;  // what the summary counts as echo

/// Hours from `a` to `b` (ISO 8601 UTC), through the CF time parser.
double hoursBetween(const std::string& a, const std::string& b) {
  auto ta = parseCfTimeUnits("seconds since " + a, "standard");
  auto tb = parseCfTimeUnits("seconds since " + b, "standard");
  return static_cast<double>(tb->referenceSeconds - ta->referenceSeconds) / 3600.0;
}

void addDbz(double& linearZ, double dbz) {
  if (dbz > -20.0) linearZ += std::pow(10.0, dbz / 10.0);
}

/// Convective cell profile (dBZ) at height zKm above MSL and distance rKm from its axis: the
/// shape of the radar model's core (SyntheticRadar.cpp), core value `core` near the ground.
double cellDbz(double core, double zKm, double rKm) {
  const double vert = zKm < 7.0 ? -0.6 * std::max(zKm, 0.0) : -4.2 - 1.3 * (zKm - 7.0) * (zKm - 7.0);
  return core + vert - 22.0 * (rKm / 5.0) * (rKm / 5.0);
}

/// Surface altitude (m): the Great Plains rising west towards the Rockies, with gentle ripples.
double orography(double latDeg, double lonDeg) {
  const double rise = 1700.0 / (1.0 + std::exp((lonDeg + 104.0) / 2.8));
  const double ripple = 40.0 * std::sin(degreesToRadians(lonDeg * 37.0)) * std::sin(degreesToRadians(latDeg * 53.0));
  return 200.0 + rise + ripple;
}

struct Column {
  double xKm, yKm;  // east / north of the radar site in its azimuthal-equidistant plane
  double orogMeters;
};

}  // namespace

Status validateSyntheticGridOptions(const SyntheticGridOptions& o) {
  auto bad = [](const std::string& what) { return makeError("synthetic grid: " + what); };
  if (o.nx < 2 || o.nx > 2000 || o.ny < 2 || o.ny > 2000) return bad("nx and ny must be in 2..2000");
  if (o.levels < 2 || o.levels > 200) return bad("levels must be in 2..200");
  if (o.times < 1 || o.times > 1000) return bad("times must be in 1..1000");
  if (static_cast<double>(o.nx) * static_cast<double>(o.ny) * static_cast<double>(o.levels) *
          static_cast<double>(o.times) >
      2147483648.0)
    return bad("more than 2^31 values");
  if (!(o.spacingKm >= 0.1 && o.spacingKm <= 100.0)) return bad("spacing must be in 0.1..100 km");
  if (!(o.lowestLevelMeters >= 0.0 && o.topLevelMeters > o.lowestLevelMeters && o.topLevelMeters <= 80000.0))
    return bad("levels: need 0 <= lowest < top <= 80000 m");
  if (!(std::fabs(o.centerLatDeg) <= 80.0) || !(std::fabs(o.centerLonDeg) <= 360.0))
    return bad("centre latitude must be within +-80 deg, longitude within +-360 deg");
  const double halfLatDeg = radiansToDegrees(o.spacingKm * 1000.0 * static_cast<double>(o.ny - 1) / 2.0 /
                                             globe::meridionalRadiusMeters(o.centerLatDeg));
  if (std::fabs(o.centerLatDeg) + halfLatDeg > 85.0) return bad("the grid reaches beyond +-85 degrees of latitude");
  if (!(o.stepHours > 0.0 && o.stepHours <= 240.0)) return bad("step must be in (0, 240] hours");
  if (!(std::fabs(o.motionEastKmPerHour) <= 200.0 && std::fabs(o.motionNorthKmPerHour) <= 200.0))
    return bad("storm motion must be within +-200 km/h");
  if (o.deflateLevel < 0 || o.deflateLevel > 9) return bad("deflate level must be 0..9");
  for (const std::string* t : {&o.startTimeIso8601, &o.radarTimeIso8601})
    if (!parseCfTimeUnits("seconds since " + *t, "standard")) return bad("time '" + *t + "' is not ISO 8601");
  if (auto st = validateSyntheticRadarOptions(o.storm); !st) return bad(st.error());
  return Ok{};
}

Status writeSyntheticGrid(const std::string& path, const SyntheticGridOptions& o, SyntheticGridSummary* summary) {
  if (auto st = validateSyntheticGridOptions(o); !st) return st;
  const std::size_t nx = o.nx, ny = o.ny, nz = o.levels, nt = o.times, nc = nx * ny;

  // --- geometry: latitudes north to south, longitudes 0..360, as GRIB-converted files write them ---
  const double dLatDeg = radiansToDegrees(o.spacingKm * 1000.0 / globe::meridionalRadiusMeters(o.centerLatDeg));
  const double dLonDeg =
      radiansToDegrees(o.spacingKm * 1000.0 /
                       (globe::primeVerticalRadiusMeters(o.centerLatDeg) * std::cos(degreesToRadians(o.centerLatDeg))));
  std::vector<double> lat(ny), lon(nx);
  for (std::size_t r = 0; r < ny; ++r)
    lat[r] = o.centerLatDeg + (static_cast<double>(ny - 1) / 2.0 - static_cast<double>(r)) * dLatDeg;
  for (std::size_t i = 0; i < nx; ++i) {
    double x = o.centerLonDeg + (static_cast<double>(i) - static_cast<double>(nx - 1) / 2.0) * dLonDeg;
    x = std::fmod(x, 360.0);
    lon[i] = x < 0 ? x + 360.0 : x;
  }
  // Levels above ground: 50 m .. 18 km, spacing growing from ~90 m to ~1 km (quadratic stretch).
  std::vector<float> levels(nz);
  for (std::size_t k = 0; k < nz; ++k) {
    const double s = static_cast<double>(k) / static_cast<double>(nz - 1);
    levels[k] =
        static_cast<float>(o.lowestLevelMeters + (o.topLevelMeters - o.lowestLevelMeters) * (0.15 * s + 0.85 * s * s));
  }
  std::vector<Column> cols(nc);
  std::vector<float> orog(nc);
  for (std::size_t r = 0; r < ny; ++r)
    for (std::size_t i = 0; i < nx; ++i) {
      const globe::GeodesicLine g = globe::geodesicInverse(o.storm.siteLatDeg, o.storm.siteLonDeg, lat[r], lon[i]);
      const double az = degreesToRadians(g.azimuth1Deg);
      Column& c = cols[r * nx + i];
      c.xKm = g.distanceMeters / 1000.0 * std::sin(az);
      c.yKm = g.distanceMeters / 1000.0 * std::cos(az);
      c.orogMeters = orography(lat[r], lon[i]);
      orog[r * nx + i] = static_cast<float>(c.orogMeters);
    }

  // --- the weather, step by step (hours relative to the radar volume's time) ---
  const double radarHours = hoursBetween(o.startTimeIso8601, o.radarTimeIso8601);
  const double lineBearing = degreesToRadians(40.0);  // the squall line runs NE from the supercell
  const double lx = std::sin(lineBearing), ly = std::cos(lineBearing);
  SyntheticGridSummary sum;
  sum.nx = nx;
  sum.ny = ny;
  sum.levels = nz;
  sum.times = nt;
  std::vector<double> zMslKm(nz);
  // Fills `out` (levels x rows x columns, file order) with step t.
  auto generateStep = [&](std::size_t t, std::vector<short>& out) {
    std::fill(out.begin(), out.end(), static_cast<short>(std::lround(kClearAirDbz / kDbzScale)));
    const double h = static_cast<double>(t) * o.stepHours - radarHours;  // hours after the radar time
    SyntheticRadarOptions storm = o.storm;
    storm.stormEastKm += o.motionEastKmPerHour * h;
    storm.stormNorthKm += o.motionNorthKmPerHour * h;
    const double cx = storm.stormEastKm, cy = storm.stormNorthKm;
    // Supercell life: grows from 3 h before the radar time, mature 1 h before to 4 h after, then decays.
    const double superGainDb = h < -1.0 ? std::max(-30.0, 10.0 * (h + 1.0)) : h > 4.0 ? -4.0 * (h - 4.0) : 0.0;
    // Squall-line cells: cell n (1..8) 30 + 25 (n-1) km NE of the supercell, born at h = -1 + 0.6 (n-1).
    struct Cell {
      double x, y, core;
    };
    std::vector<Cell> cells;
    for (int n = 1; n <= 8; ++n) {
      const double age = h - (-1.0 + 0.6 * (n - 1));
      if (age <= 0.0) continue;
      const double d = 30.0 + 25.0 * (n - 1);
      double core = 50.0 + 5.0 * std::sin(1.7 * n + static_cast<double>(o.storm.seed));
      core -= age < 1.0 ? 25.0 * (1.0 - age) : age > 6.0 ? 3.0 * (age - 6.0) : 0.0;
      cells.push_back({cx + d * lx, cy + d * ly, core});
    }
    const double lineKm = cells.empty() ? 0.0 : 30.0 + 25.0 * static_cast<double>(cells.size() - 1);
    const double stratGain = std::clamp((h - 1.0) / 3.0, 0.0, 1.0);  // trailing stratiform grows over 3 h
    for (std::size_t c = 0; c < nc; ++c) {
      const Column& col = cols[c];
      const double dx = col.xKm - cx, dy = col.yKm - cy;
      // The radar model's anvil reaches ~200 km downwind before it fades below -20 dBZ.
      const bool nearSupercell = std::fabs(dx) < 260.0 && std::fabs(dy) < 260.0;
      const double along = dx * lx + dy * ly, across = dx * ly - dy * lx;  // across > 0: SE (ahead)
      const bool nearLine = !cells.empty() && along > -30.0 && along < lineKm + 30.0 && across > -110.0 &&
                            across < 30.0;
      if (!nearSupercell && !nearLine) continue;
      for (std::size_t k = 0; k < nz; ++k) zMslKm[k] = (static_cast<double>(levels[k]) + col.orogMeters) / 1000.0;
      for (std::size_t k = 0; k < nz; ++k) {
        const double z = zMslKm[k];
        double linearZ = 0.0;
        if (nearSupercell && superGainDb > -30.0) {
          const double v = syntheticStormDbz(storm, col.xKm * 1000.0, col.yKm * 1000.0, z * 1000.0);
          if (std::isfinite(v)) addDbz(linearZ, v + superGainDb);
        }
        if (nearLine) {
          for (const Cell& cell : cells) {
            const double r = std::hypot(col.xKm - cell.x, col.yKm - cell.y);
            if (r < 20.0) addDbz(linearZ, cellDbz(cell.core, z, r));
          }
          if (stratGain > 0.0) {
            // Trailing stratiform: 20-31 dBZ 10-80 km behind the line, fading towards its ends and
            // ahead of it, bright band at 3.8 km.
            const double q = (across + 45.0) / 35.0;
            const double u = (along - lineKm / 2.0) / (lineKm / 2.0 + 15.0);
            double strat = 31.0 - 11.0 * q * q - 25.0 * u * u * u * u +
                           2.0 * std::sin(along / 23.0 + static_cast<double>(o.storm.seed));
            const double dz = z - 3.8;
            strat += 8.0 * std::exp(-(dz / 0.22) * (dz / 0.22));
            if (dz > 0) strat += (-7.0 - 3.5 * dz) * (1.0 - std::exp(-(dz / 0.3) * (dz / 0.3)));
            addDbz(linearZ, strat + 10.0 * std::log10(std::max(stratGain, 1e-3)));
          }
        }
        if (linearZ <= 0.0) continue;
        const double dbz = std::max(10.0 * std::log10(linearZ), kClearAirDbz);
        const double raw = std::clamp(std::round(dbz / kDbzScale), -32767.0, 32767.0);
        out[k * nc + c] = static_cast<short>(raw);
        const double stored = raw * kDbzScale;
        if (stored >= kEchoDbz) ++sum.echoValues;
        sum.maxDbz = std::max(sum.maxDbz, stored);
      }
    }
  };

  // --- the file, written atomically ---
  const io::NetcdfLock lock;  // from nc_create to nc_close (io/NetcdfLock.h)
  std::string temp;
  int ncid = -1;
  if (Status st = createTemporaryNetcdf(path, &temp, &ncid); !st) return st;
  NcWriter w(path, ncid);
  const std::string synthetic =
      "SYNTHETIC data generated by atmoglobe (atmoglobe synth --grid): an analytic supercell, squall line and "
      "trailing stratiform region sampled on a forecast-like grid; not a model run.";
  w.text(NC_GLOBAL, "Conventions", "CF-1.8");
  w.text(NC_GLOBAL, "title", "SYNTHETIC forecast grid (atmoglobe): simulated reflectivity around " + o.storm.siteId);
  w.text(NC_GLOBAL, "institution", "atmoglobe (synthetic data)");
  w.text(NC_GLOBAL, "source", synthetic);
  w.text(NC_GLOBAL, "history", "written by atmoglobe synth --grid, seed " + std::to_string(o.storm.seed));
  w.text(NC_GLOBAL, "comment",
         synthetic +
             " Latitudes run north to south and longitudes 0..360 on purpose (as in GRIB-converted "
             "files). The supercell is the one of atmoglobe's synthetic radar volume, at its place at " +
             o.radarTimeIso8601 + ".");
  int dT = -1, dZ = -1, dY = -1, dX = -1;
  w.check(nc_def_dim(ncid, "time", nt, &dT), "dimension time");
  w.check(nc_def_dim(ncid, "height", nz, &dZ), "dimension height");
  w.check(nc_def_dim(ncid, "lat", ny, &dY), "dimension lat");
  w.check(nc_def_dim(ncid, "lon", nx, &dX), "dimension lon");
  if (!w.ok()) return closeAndCommitNetcdf(path, temp, w);  // fails: removes the temporary
  const int vT = w.var("time", NC_DOUBLE, {dT});
  w.text(vT, "standard_name", "time");
  w.text(vT, "units", "hours since " + o.startTimeIso8601.substr(0, 10) + " " + o.startTimeIso8601.substr(11, 8));
  w.text(vT, "calendar", "standard");
  w.text(vT, "axis", "T");
  const int vZ = w.var("height", NC_FLOAT, {dZ});
  w.text(vZ, "standard_name", "height");
  w.text(vZ, "long_name", "height above ground");
  w.text(vZ, "units", "m");
  w.text(vZ, "positive", "up");
  w.text(vZ, "axis", "Z");
  const int vY = w.var("lat", NC_DOUBLE, {dY});
  w.text(vY, "standard_name", "latitude");
  w.text(vY, "units", "degrees_north");
  w.text(vY, "axis", "Y");
  const int vX = w.var("lon", NC_DOUBLE, {dX});
  w.text(vX, "standard_name", "longitude");
  w.text(vX, "units", "degrees_east");
  w.text(vX, "axis", "X");
  const int vO = w.var("orog", NC_FLOAT, {dY, dX});
  w.text(vO, "standard_name", "surface_altitude");
  w.text(vO, "long_name", "surface altitude above mean sea level (SYNTHETIC)");
  w.text(vO, "units", "m");
  const int vD = w.var("dbz", NC_SHORT, {dT, dZ, dY, dX});
  w.text(vD, "standard_name", "equivalent_reflectivity_factor");
  w.text(vD, "long_name", "simulated radar reflectivity (SYNTHETIC)");
  w.text(vD, "units", "dBZ");
  const float scale = static_cast<float>(kDbzScale), offset = 0.0f;
  w.check(nc_put_att_float(ncid, vD, "scale_factor", NC_FLOAT, 1, &scale), "dbz scale_factor");
  w.check(nc_put_att_float(ncid, vD, "add_offset", NC_FLOAT, 1, &offset), "dbz add_offset");
  short fill = kDbzFill;
  w.check(nc_def_var_fill(ncid, vD, 0, &fill), "dbz _FillValue");
  w.text(vD, "coordinates", "time height lat lon");
  w.text(vD, "comment",
         "SYNTHETIC (atmoglobe analytic storm model, seed " + std::to_string(o.storm.seed) +
             "). Clear air is -30 dBZ, the floor of simulated reflectivity; nothing is missing.");
  if (o.deflateLevel > 0) {
    const std::vector<std::size_t> chunk = {1, std::min<std::size_t>(nz, 7), std::min<std::size_t>(ny, 100),
                                            std::min<std::size_t>(nx, 100)};
    w.check(nc_def_var_chunking(ncid, vD, NC_CHUNKED, chunk.data()), "dbz chunking");
    w.check(nc_def_var_deflate(ncid, vD, 1, 1, o.deflateLevel), "dbz deflate");
    w.check(nc_def_var_deflate(ncid, vO, 1, 1, o.deflateLevel), "orog deflate");
  }
  w.check(nc_enddef(ncid), "end of definitions");
  std::vector<double> hours(nt);
  for (std::size_t t = 0; t < nt; ++t) hours[t] = static_cast<double>(t) * o.stepHours;
  w.check(nc_put_var_double(ncid, vT, hours.data()), "time");
  w.check(nc_put_var_float(ncid, vZ, levels.data()), "height");
  w.check(nc_put_var_double(ncid, vY, lat.data()), "lat");
  w.check(nc_put_var_double(ncid, vX, lon.data()), "lon");
  w.check(nc_put_var_float(ncid, vO, orog.data()), "orog");
  std::vector<short> step(nz * nc);  // one step at a time: 11 MB for the default, not 145
  for (std::size_t t = 0; t < nt && w.ok(); ++t) {
    generateStep(t, step);
    const std::size_t start[4] = {t, 0, 0, 0}, count[4] = {1, nz, ny, nx};
    w.check(nc_put_vara_short(ncid, vD, start, count, step.data()), "dbz");
  }
  if (Status st = closeAndCommitNetcdf(path, temp, w); !st) return st;
  std::error_code ec;
  sum.fileBytes = std::filesystem::file_size(path, ec);
  if (summary) *summary = sum;
  return Ok{};
}

// --- the global grid -------------------------------------------------------------------------

namespace {

/// Great-circle distance (km, mean Earth radius) and initial bearing (rad, clockwise from north)
/// from (lat0, lon0) to (lat, lon), degrees: the synthetic weather needs shapes, not geodesy.
void distanceBearing(double lat0, double lon0, double lat, double lon, double* km, double* bearing) {
  const double p0 = degreesToRadians(lat0), p1 = degreesToRadians(lat), dl = degreesToRadians(lon - lon0);
  const double a = std::sin((p1 - p0) / 2) * std::sin((p1 - p0) / 2) +
                   std::cos(p0) * std::cos(p1) * std::sin(dl / 2) * std::sin(dl / 2);
  *km = 2.0 * 6371.0 * std::asin(std::min(1.0, std::sqrt(a)));
  *bearing =
      std::atan2(std::sin(dl) * std::cos(p1), std::cos(p0) * std::sin(p1) - std::sin(p0) * std::cos(p1) * std::cos(dl));
}

/// A small integer hash in [0, 1).
double hash01(int a, int b, int c) {
  std::uint32_t h = static_cast<std::uint32_t>(a) * 374761393u + static_cast<std::uint32_t>(b) * 668265263u +
                    static_cast<std::uint32_t>(c) * 2246822519u;
  h = (h ^ (h >> 13)) * 1274126177u;
  h ^= h >> 16;
  return static_cast<double>(h) / 4294967296.0;
}

struct Cyclone {
  double lat, lon, latPerHour, lonPerHour, coreDbz, rmwKm, hemisphere;
};
// Four tropical cyclones (north Atlantic, west Pacific, south Indian Ocean, east Pacific).
constexpr Cyclone kCyclones[] = {{19.0, -62.0, 0.05, -0.2, 52.0, 35.0, 1.0},
                                 {22.0, 134.0, 0.06, -0.15, 55.0, 28.0, 1.0},
                                 {-16.0, 76.0, -0.04, -0.12, 50.0, 40.0, -1.0},
                                 {15.0, -116.0, 0.03, -0.18, 48.0, 30.0, 1.0}};

}  // namespace

const std::vector<double>& era5PressureLevelsHpa() {
  static const std::vector<double> levels = {1,   2,   3,   5,   7,   10,  20,  30,  50,  70,  100, 125, 150,
                                             175, 200, 225, 250, 300, 350, 400, 450, 500, 550, 600, 650, 700,
                                             750, 775, 800, 825, 850, 875, 900, 925, 950, 975, 1000};
  return levels;
}

double syntheticGlobalGeopotential(double latDeg, double lonDeg, double pressureHpa) {
  const double h = standardAtmosphereGeopotentialHeightMeters(pressureHpa * 100.0);
  // Thicker (warmer) tropics, thinner poles; planetary waves (wavenumber 5) in mid-latitudes.
  const double lat = degreesToRadians(latDeg);
  const double wave =
      std::sin(degreesToRadians(5.0 * lonDeg)) * std::exp(-std::pow((std::fabs(latDeg) - 50.0) / 15.0, 2));
  return 9.80665 * h * (1.0 + 0.045 * std::cos(2.0 * lat) + 0.01 * wave);
}

namespace {

/// The weather of one column of the global field: horizontal parts (dBZ) each with its vertical
/// profile, so a column costs its trigonometry once and each level a few exponentials.
struct GlobalColumn {
  enum class Profile { Cyclone, Front, Cell };
  struct Part {
    double dbz;
    Profile profile;
  };
  std::vector<Part> parts;

  GlobalColumn(double latDeg, double lonDeg, double hours, int seed) {
    // Tropical cyclones: a clear eye, the eyewall at the radius of maximum wind, two logarithmic
    // spiral rain bands out to ~600 km; convective profiles, echo tops near 15 km.
    for (const Cyclone& c : kCyclones) {
      double rKm = 0.0, bearing = 0.0;
      distanceBearing(c.lat + c.latPerHour * hours, c.lon + c.lonPerHour * hours, latDeg, lonDeg, &rKm, &bearing);
      if (rKm > 700.0) continue;
      const double x = (rKm - c.rmwKm) / (0.45 * c.rmwKm);
      double eyewall = c.coreDbz - 12.0 * x * x;
      if (rKm < 0.6 * c.rmwKm) eyewall -= 30.0;  // the eye
      parts.push_back({eyewall, Profile::Cyclone});
      const double phase = c.hemisphere * bearing + 1.6 * std::log(std::max(rKm, 1.0) / c.rmwKm);
      const double band = std::cos(2.0 * phase);
      if (band > 0.2 && rKm > c.rmwKm) {
        const double q = rKm / 600.0;
        parts.push_back({30.0 + 12.0 * (band - 0.2) - 14.0 * q * q, Profile::Cyclone});
      }
    }
    // Frontal rain bands along wavy storm tracks in both hemispheres: stratiform, with a bright
    // band at the melting level (2.5 km) and tops at 8-9 km.
    for (double hemi : {1.0, -1.0}) {
      const double track = hemi * (47.0 + 7.0 * std::sin(degreesToRadians(4.0 * lonDeg + 30.0 * hemi + 10.0 * hours)) +
                                   3.0 * std::sin(degreesToRadians(7.0 * lonDeg)));
      const double d = latDeg - track;
      if (std::fabs(d) > 4.0) continue;
      const double active = 0.5 + 0.5 * std::sin(degreesToRadians(3.0 * lonDeg + 50.0 * hemi));
      if (active < 0.2) continue;
      parts.push_back({34.0 - 12.0 * (d / 2.0) * (d / 2.0) + 3.0 * std::sin(degreesToRadians(40.0 * lonDeg)) +
                           10.0 * std::log10(active),
                       Profile::Front});
    }
    // ITCZ: convective cells on a jittered lattice (1.5 deg in longitude, three rows 2.5 deg
    // apart) along a wavy band north of the equator; 60 % of the sites hold a cell.
    const double itcz = 6.0 + 3.0 * std::sin(degreesToRadians(2.0 * lonDeg));
    if (std::fabs(latDeg - itcz) < 5.5) {
      const int n0 = static_cast<int>(std::floor(lonDeg / 1.5));
      for (int n = n0 - 1; n <= n0 + 1; ++n)
        for (int m = -1; m <= 1; ++m) {
          if (hash01(n, m, seed) > 0.6) continue;
          const double cLat = itcz + 2.5 * m + 1.6 * (hash01(n, m, seed + 1) - 0.5);
          const double cLon = 1.5 * n + 1.2 * (hash01(n, m, seed + 2) - 0.5);
          const double radiusKm = 12.0 + 14.0 * hash01(n, m, seed + 3);
          const double core = 42.0 + 13.0 * hash01(n, m, seed + 4);
          const double dyKm = (latDeg - cLat) * 111.0;
          const double dxKm = (lonDeg - cLon) * 111.0 * std::cos(degreesToRadians(latDeg));
          const double r = std::hypot(dxKm, dyKm) * 5.0 / radiusKm;
          if (r < 10.0) parts.push_back({core + 4.0 - 22.0 * (r / 5.0) * (r / 5.0), Profile::Cell});
        }
    }
  }

  double dbz(double zMeters) const {
    const double zKm = zMeters / 1000.0;
    double linearZ = 0.0;
    for (const Part& p : parts) {
      double v = p.dbz;
      if (p.profile == Profile::Cyclone) {
        if (zKm > 16.0) continue;
        v += zKm < 5.0 ? -0.5 * zKm : -2.5 - 0.75 * (zKm - 5.0) * (zKm - 5.0);
      } else if (p.profile == Profile::Front) {
        if (zKm > 10.0) continue;
        const double dz = zKm - 2.5;
        v += 7.0 * std::exp(-(dz / 0.25) * (dz / 0.25));
        if (dz > 0) v -= 4.5 * dz * (1.0 - std::exp(-(dz / 0.3) * (dz / 0.3)));
      } else {
        if (zKm > 17.0) continue;
        v = cellDbz(p.dbz, zKm * 0.85, 0.0);  // the radial part is in p.dbz already
      }
      addDbz(linearZ, v);
    }
    return linearZ > 0.0 ? std::max(10.0 * std::log10(linearZ), kClearAirDbz) : kClearAirDbz;
  }
};

}  // namespace

double syntheticGlobalDbz(double latDeg, double lonDeg, double zMeters, double hours, int seed) {
  return GlobalColumn(latDeg, lonDeg, hours, seed).dbz(zMeters);
}

Status validateSyntheticGlobalGridOptions(const SyntheticGlobalGridOptions& o) {
  auto bad = [](const std::string& what) { return makeError("synthetic global grid: " + what); };
  if (o.nx < 8 || o.nx > 2880) return bad("nx must be in 8..2880");
  if (o.ny < 5 || o.ny > 1441) return bad("ny must be in 5..1441");
  if (o.times < 1 || o.times > 100) return bad("times must be in 1..100");
  if (!(o.stepHours > 0.0 && o.stepHours <= 240.0)) return bad("step must be in (0, 240] hours");
  if (o.deflateLevel < 0 || o.deflateLevel > 9) return bad("deflate level must be 0..9");
  if (!parseCfTimeUnits("seconds since " + o.startTimeIso8601, "standard"))
    return bad("time '" + o.startTimeIso8601 + "' is not ISO 8601");
  return Ok{};
}

Status writeSyntheticGlobalGrid(const std::string& path, const SyntheticGlobalGridOptions& o,
                                SyntheticGridSummary* summary) {
  if (auto st = validateSyntheticGlobalGridOptions(o); !st) return st;
  const std::vector<double>& plev = era5PressureLevelsHpa();
  const std::size_t nx = o.nx, ny = o.ny, nz = plev.size(), nt = o.times;
  std::vector<double> lat(ny), lon(nx);
  for (std::size_t r = 0; r < ny; ++r)
    lat[r] = 90.0 - 180.0 * static_cast<double>(r) / static_cast<double>(ny - 1);  // north to south, as ERA5
  for (std::size_t i = 0; i < nx; ++i) lon[i] = 360.0 * static_cast<double>(i) / static_cast<double>(nx);

  // From nc_create to nc_close (io/NetcdfLock.h); the values are computed band by band between the
  // writes, under it too: a bench's writer, with no other thread reading beside it.
  const io::NetcdfLock lock;
  std::string temp;
  int ncid = -1;
  if (Status st = createTemporaryNetcdf(path, &temp, &ncid); !st) return st;
  NcWriter w(path, ncid);
  const std::string synthetic =
      "SYNTHETIC data generated by atmoglobe (the grid bench's global case): analytic tropical cyclones, frontal "
      "rain bands and ITCZ convection on an ERA5-like 0.25 degree pressure-level grid; not a model run.";
  w.text(NC_GLOBAL, "Conventions", "CF-1.8");
  w.text(NC_GLOBAL, "title", "SYNTHETIC global forecast grid (atmoglobe): simulated reflectivity on pressure levels");
  w.text(NC_GLOBAL, "institution", "atmoglobe (synthetic data)");
  w.text(NC_GLOBAL, "source", synthetic);
  w.text(NC_GLOBAL, "history", "written by atmoglobe (writeSyntheticGlobalGrid), seed " + std::to_string(o.seed));
  w.text(NC_GLOBAL, "comment",
         synthetic + " Latitudes run north to south, longitudes 0..360 and levels top first, as in ERA5 files.");
  int dT = -1, dZ = -1, dY = -1, dX = -1;
  w.check(nc_def_dim(ncid, "time", nt, &dT), "dimension time");
  w.check(nc_def_dim(ncid, "level", nz, &dZ), "dimension level");
  w.check(nc_def_dim(ncid, "latitude", ny, &dY), "dimension latitude");
  w.check(nc_def_dim(ncid, "longitude", nx, &dX), "dimension longitude");
  if (!w.ok()) return closeAndCommitNetcdf(path, temp, w);  // fails: removes the temporary
  const int vT = w.var("time", NC_DOUBLE, {dT});
  w.text(vT, "standard_name", "time");
  w.text(vT, "units", "hours since " + o.startTimeIso8601.substr(0, 10) + " " + o.startTimeIso8601.substr(11, 8));
  w.text(vT, "calendar", "gregorian");
  const int vZ = w.var("level", NC_DOUBLE, {dZ});
  w.text(vZ, "standard_name", "air_pressure");
  w.text(vZ, "long_name", "pressure level");
  w.text(vZ, "units", "millibars");
  w.text(vZ, "positive", "down");
  const int vY = w.var("latitude", NC_DOUBLE, {dY});
  w.text(vY, "standard_name", "latitude");
  w.text(vY, "units", "degrees_north");
  const int vX = w.var("longitude", NC_DOUBLE, {dX});
  w.text(vX, "standard_name", "longitude");
  w.text(vX, "units", "degrees_east");
  const int vG = w.var("z", NC_FLOAT, {dT, dZ, dY, dX});
  w.text(vG, "standard_name", "geopotential");
  w.text(vG, "long_name", "Geopotential (SYNTHETIC)");
  w.text(vG, "units", "m**2 s**-2");
  const int vD = w.var("dbz", NC_SHORT, {dT, dZ, dY, dX});
  w.text(vD, "standard_name", "equivalent_reflectivity_factor");
  w.text(vD, "long_name", "simulated radar reflectivity (SYNTHETIC)");
  w.text(vD, "units", "dBZ");
  const float scale = static_cast<float>(kDbzScale), offset = 0.0f;
  w.check(nc_put_att_float(ncid, vD, "scale_factor", NC_FLOAT, 1, &scale), "dbz scale_factor");
  w.check(nc_put_att_float(ncid, vD, "add_offset", NC_FLOAT, 1, &offset), "dbz add_offset");
  short fill = kDbzFill;
  w.check(nc_def_var_fill(ncid, vD, 0, &fill), "dbz _FillValue");
  w.text(vD, "comment",
         "SYNTHETIC (atmoglobe analytic global weather, seed " + std::to_string(o.seed) +
             "). Clear air is -30 dBZ; nothing is missing.");
  // Chunks of every level over 91 x 180 columns: a view's crop reads the chunks under it.
  const std::size_t rowsPerChunk = std::min<std::size_t>(ny, 91), colsPerChunk = std::min<std::size_t>(nx, 180);
  if (o.deflateLevel > 0) {
    const std::vector<std::size_t> chunk = {1, nz, rowsPerChunk, colsPerChunk};
    for (int v : {vD, vG}) {
      w.check(nc_def_var_chunking(ncid, v, NC_CHUNKED, chunk.data()), "chunking");
      w.check(nc_def_var_deflate(ncid, v, 1, 1, o.deflateLevel), "deflate");
    }
  }
  w.check(nc_enddef(ncid), "end of definitions");
  std::vector<double> hours(nt), levels(plev.begin(), plev.end());
  for (std::size_t t = 0; t < nt; ++t) hours[t] = static_cast<double>(t) * o.stepHours;
  w.check(nc_put_var_double(ncid, vT, hours.data()), "time");
  w.check(nc_put_var_double(ncid, vZ, levels.data()), "level");
  w.check(nc_put_var_double(ncid, vY, lat.data()), "latitude");
  w.check(nc_put_var_double(ncid, vX, lon.data()), "longitude");

  SyntheticGridSummary sum;
  sum.nx = nx, sum.ny = ny, sum.levels = nz, sum.times = nt;
  // One band of chunk rows at a time (all levels): the chunks are written whole.
  std::vector<short> dbz;
  std::vector<float> geo;
  for (std::size_t t = 0; t < nt && w.ok(); ++t) {
    for (std::size_t r0 = 0; r0 < ny && w.ok(); r0 += rowsPerChunk) {
      const std::size_t rows = std::min(rowsPerChunk, ny - r0), n = nz * rows * nx;
      dbz.assign(n, 0);
      geo.assign(n, 0.0f);
      for (std::size_t r = 0; r < rows; ++r) {
        const double la = lat[r0 + r];
        const GeopotentialToGeometric toGeometric(la);
        for (std::size_t i = 0; i < nx; ++i) {
          const GlobalColumn column(la, lon[i], hours[t], o.seed);
          for (std::size_t k = 0; k < nz; ++k) {
            const double phi = syntheticGlobalGeopotential(la, lon[i], plev[k]);
            const std::size_t idx = (k * rows + r) * nx + i;
            geo[idx] = static_cast<float>(phi);
            const double z = toGeometric(phi / 9.80665);
            const double raw = std::clamp(std::round(column.dbz(z) / kDbzScale), -32767.0, 32767.0);
            dbz[idx] = static_cast<short>(raw);
            const double stored = raw * kDbzScale;
            if (stored >= kEchoDbz) ++sum.echoValues;
            sum.maxDbz = std::max(sum.maxDbz, stored);
          }
        }
      }
      const std::size_t start[4] = {t, 0, r0, 0}, count[4] = {1, nz, rows, nx};
      w.check(nc_put_vara_float(ncid, vG, start, count, geo.data()), "z");
      w.check(nc_put_vara_short(ncid, vD, start, count, dbz.data()), "dbz");
    }
  }
  if (Status st = closeAndCommitNetcdf(path, temp, w); !st) return st;
  std::error_code ec;
  sum.fileBytes = std::filesystem::file_size(path, ec);
  if (summary) *summary = sum;
  return Ok{};
}

}  // namespace atmoglobe::volume
