#include <atmoglobe/volume/SyntheticGrid.h>

#include "NcWriter.h"

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/AtomicFile.h>
#include <atmoglobe/volume/CfTime.h>

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
  auto tempName = temporaryPathBeside(path);
  if (!tempName) return tempName.forwardError();
  const std::string temp = *tempName;
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return makeError(path + ": cannot create file in its directory: " + std::strerror(errno));
  ::close(fd);
  int ncid = -1;
  if (const int st = nc_create(temp.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid); st != NC_NOERR) {
    ::unlink(temp.c_str());
    return makeError(path + ": cannot create netCDF-4 file: " + nc_strerror(st));
  }
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
  if (!w.ok()) {
    nc_close(ncid);
    ::unlink(temp.c_str());
    return makeError(w.error());
  }
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
  std::string err = w.ok() ? std::string() : w.error();
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
