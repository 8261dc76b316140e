// `atmoglobe synth -o FILE.nc [--site ID,LAT,LON[,M]] [--seed N] [--storm-east KM] [--storm-north KM] [--noise DB]
// [--time ISO]`: writes a SYNTHETIC CfRadial 1.4 volume (KTLX site, VCP 212 angles, an analytic supercell and
// stratiform area) for the default scene and for tests. See volume/SyntheticRadar.h.
// `atmoglobe synth --sites ICAO,ICAO,...|all|FILE -o DIR [--time T] [--steps N] [--interval MIN]`: SYNTHETIC
// volumes at many sites of one storm field (volume/SyntheticRadar.h, networkStorms).
// `atmoglobe synth --grid -o FILE.nc [--grid-size NX,NY,LEVELS,TIMES] [--spacing KM]`: a SYNTHETIC
// CF forecast grid around the same storm instead. See volume/SyntheticGrid.h.
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/globe/Progress.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/StationList.h>
#include <atmoglobe/volume/SyntheticGrid.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <atomic>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <thread>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::tools {

namespace {
struct Options {
  std::string output;
  volume::SyntheticRadarOptions synth;
  bool grid = false;
  std::vector<std::size_t> gridSize;
  volume::SyntheticGridOptions gridOptions;
  std::string site;   ///< --site ID,LAT,LON[,ANTENNA_M]
  std::string sites;  ///< --sites ICAO,ICAO,...|all|FILE
  std::size_t steps = 1;
  double intervalMinutes = 5.0;
};

// --site ID,LAT,LON[,ANTENNA_M]: the radar (and the grid's centre) at another place.
Status applySite(const std::string& text, Options& o) {
  const std::size_t comma = text.find(',');
  const std::string id = text.substr(0, comma);
  const auto bad = [&](const std::string& why) {
    return makeError("--site " + text + ": " + why +
                     " (expected ID,LAT,LON[,ANTENNA_M], e.g. KLIX,30.3367,-89.8256,38)");
  };
  if (comma == std::string::npos) return bad("no latitude and longitude");
  if (id.empty() || id.size() > 32) return bad("the site id must have 1 to 32 characters");
  auto v = parseNumbers(text.substr(comma + 1), 2, 3, "--site " + text);
  if (!v) return v.forwardError();
  const double latDeg = (*v)[0], lonDeg = (*v)[1], antennaMeters = v->size() == 3 ? (*v)[2] : 0.0;
  if (std::fabs(latDeg) > 90.0) return bad("latitude outside -90..90");
  if (lonDeg < -180.0 || lonDeg > 360.0) return bad("longitude outside -180..360");
  if (std::fabs(antennaMeters) > 9000.0) return bad("antenna height outside -9000..9000 m");
  o.synth.siteId = id;
  o.synth.siteLatDeg = latDeg;
  o.synth.siteLonDeg = lonDeg > 180.0 ? lonDeg - 360.0 : lonDeg;
  o.synth.antennaAltitudeMslMeters = antennaMeters;
  o.gridOptions.centerLatDeg = o.synth.siteLatDeg;
  o.gridOptions.centerLonDeg = o.synth.siteLonDeg;
  return Ok{};
}

int writeGrid(Options& o) {
  volume::SyntheticGridOptions& g = o.gridOptions;
  if (!o.gridSize.empty()) {
    g.nx = o.gridSize[0];
    g.ny = o.gridSize[1];
    g.levels = o.gridSize[2];
    g.times = o.gridSize[3];
  }
  g.storm = o.synth;  // the same storm as the radar volume (seed, position)
  const auto t0 = std::chrono::steady_clock::now();
  volume::SyntheticGridSummary s;
  if (auto st = volume::writeSyntheticGrid(o.output, g, &s); !st) return fail("synth", st.error());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  char line[512];
  std::snprintf(line, sizeof line,
                "wrote %s: SYNTHETIC CF forecast grid (netCDF-4), %.1f MB in %.2f s\n"
                "  %zu x %zu columns %.1f km apart around %.5f %.5f, %zu levels above ground (%.0f .. %.0f m), "
                "%zu steps of %.1f h from %s\n"
                "  field dbz: %zu values >= 5 dBZ, max %.1f dBZ; seed %llu\n",
                o.output.c_str(), static_cast<double>(s.fileBytes) / 1e6, seconds, s.nx, s.ny, g.spacingKm,
                g.centerLatDeg, g.centerLonDeg, s.levels, g.lowestLevelMeters, g.topLevelMeters, s.times, g.stepHours,
                g.startTimeIso8601.c_str(), s.echoValues, s.maxDbz, static_cast<unsigned long long>(o.synth.seed));
  std::cout << line;
  return 0;
}
// --sites: the stations named (ICAO ids in the user's list or the built-in table), every built-in
// one ("all"), or every one of a station-list file.
Result<std::vector<volume::Station>> resolveSites(const std::string& text) {
  if (text == "all") return volume::builtinNexradSites();
  std::error_code ec;
  if (std::filesystem::is_regular_file(text, ec)) {
    auto list = volume::readStationList(text);
    if (!list) return makeError("--sites " + text + ": " + list.error());
    if (list->empty()) return makeError("--sites " + text + ": the list holds no station");
    return list;
  }
  std::vector<volume::Station> userList;
  std::string listName = volume::kBuiltinNexradSiteTable;
  if (const char* env = std::getenv("ATMOGLOBE_NEXRAD_SITES"); env && *env) {
    auto l = volume::readStationList(env);
    if (!l) return makeError("--sites: $ATMOGLOBE_NEXRAD_SITES: " + l.error());
    userList = std::move(*l);
    listName = std::string("the NEXRAD site list ") + env;
  }
  const std::vector<volume::Station>& table = userList.empty() ? volume::builtinNexradSites() : userList;
  std::vector<volume::Station> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string id = text.substr(start, comma - start);
    if (id.empty()) return makeError("--sites " + text + ": an empty site id (expected ICAO,ICAO,..., all or a FILE)");
    const volume::Station* s = volume::findStation(table, id);
    if (!s)
      return makeError("--sites: '" + id + "' is neither a file nor a site of " + listName +
                       " (for a radar elsewhere use --site ID,LAT,LON)");
    if (std::none_of(out.begin(), out.end(), [&](const volume::Station& o) { return o.id == s->id; }))
      out.push_back(*s);
    start = comma + 1;
  }
  return out;
}

std::string isoAt(double epochSeconds) {
  const auto t = static_cast<std::time_t>(std::llround(epochSeconds));
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

int writeNetwork(Options& o) {
  auto sites = resolveSites(o.sites);
  if (!sites) return fail("synth", sites.error());
  if (o.steps < 1 || o.steps > 1000) return fail("synth", "--steps: 1 to 1000 volumes per site");
  if (!(o.intervalMinutes > 0.0 && o.intervalMinutes <= 1440.0))
    return fail("synth", "--interval: minutes between volumes, in (0, 1440]");
  const double start = volume::iso8601ToEpochSeconds(o.synth.startTimeIso8601);
  if (!std::isfinite(start))
    return fail("synth", "--time " + o.synth.startTimeIso8601 + ": not a UTC time YYYY-MM-DDTHH:MM:SSZ");
  std::error_code ec;
  std::filesystem::create_directories(o.output, ec);
  if (ec || !std::filesystem::is_directory(o.output))
    return fail("synth", "-o " + o.output + ": with --sites the output is a directory, and it cannot be made: " +
                             (ec ? ec.message() : std::string("not a directory")));
  std::vector<std::pair<double, double>> latLon;
  for (const volume::Station& s : *sites) latLon.emplace_back(s.latDeg, s.lonDeg);
  // Storms that can reach any radar during the series (their motion included).
  const double travelKm = std::hypot(o.synth.networkMotionEastKmPerHour, o.synth.networkMotionNorthKmPerHour) *
                          o.intervalMinutes * static_cast<double>(o.steps - 1) / 60.0;
  o.synth.networkStorms =
      volume::syntheticNetworkStorms(latLon, o.synth.maxRangeMeters / 1000.0 + 250.0 + travelKm, o.synth.seed);
  o.synth.networkStartIso8601 = isoAt(start);

  struct Job {
    volume::SyntheticRadarOptions options;
    std::string path;
  };
  std::vector<Job> jobs;
  for (std::size_t t = 0; t < o.steps; ++t) {
    const std::string time = isoAt(start + 60.0 * o.intervalMinutes * static_cast<double>(t));
    for (const volume::Station& s : *sites) {
      Job j{o.synth, {}};
      j.options.siteId = s.id;
      j.options.siteLatDeg = s.latDeg;
      j.options.siteLonDeg = s.lonDeg;
      j.options.antennaAltitudeMslMeters = s.elevationMeters + s.towerHeightMeters.value_or(0.0);
      j.options.startTimeIso8601 = time;
      std::string stamp = time.substr(0, 4) + time.substr(5, 2) + time.substr(8, 2) + "_" + time.substr(11, 2) +
                          time.substr(14, 2) + time.substr(17, 2);
      j.path = (std::filesystem::path(o.output) / (s.id + "_" + stamp + ".nc")).string();
      jobs.push_back(std::move(j));
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::atomic<std::size_t> next{0}, bytes{0};
  std::mutex mutex;
  std::string firstError;
  globe::Progress progress("synthetic volumes", jobs.size());
  const unsigned workers =
      std::max(1u, std::min<unsigned>(std::thread::hardware_concurrency(), static_cast<unsigned>(jobs.size())));
  std::vector<std::thread> pool;
  for (unsigned w = 0; w < workers; ++w)
    pool.emplace_back([&] {
      for (std::size_t i = next++; i < jobs.size(); i = next++) {
        volume::SyntheticRadarSummary sum;
        Status st = volume::writeSyntheticCfRadial(jobs[i].path, jobs[i].options, &sum);
        std::lock_guard<std::mutex> lock(mutex);
        if (!st) {
          if (firstError.empty()) firstError = st.error();
          next = jobs.size();
          return;
        }
        bytes += sum.fileBytes;
        progress.advance(1, jobs[i].path);
      }
    });
  for (auto& t : pool) t.join();
  progress.finish(!firstError.empty());
  if (!firstError.empty()) return fail("synth", firstError);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  char line[512];
  std::snprintf(line, sizeof line,
                "wrote %zu SYNTHETIC CfRadial volumes to %s: %zu sites x %zu times (%.1f min apart from %s), one "
                "storm field of %zu storms moving ENE at 40 km/h; %.1f MB in %.1f s\n",
                jobs.size(), o.output.c_str(), sites->size(), o.steps, o.intervalMinutes,
                o.synth.networkStartIso8601.c_str(), o.synth.networkStorms.size(), static_cast<double>(bytes) / 1e6,
                seconds);
  std::cout << line;
  return 0;
}
}  // namespace

Command addSynthCommand(CLI::App& root) {
  auto opts = std::make_shared<Options>();
  Command c;
  c.app = root.add_subcommand("synth",
                              "Write a SYNTHETIC CfRadial radar volume (KTLX, VCP 212 angles, an analytic "
                              "supercell with anvil and a stratiform area with a bright band), or with "
                              "--grid a SYNTHETIC CF forecast grid of the same storm");
  c.app->add_option("-o,--output", opts->output, "Output file (CfRadial 1.4 or, with --grid, CF-1.8; netCDF-4)")
      ->required();
  c.app->add_option("--seed", opts->synth.seed, "Seed of the noise and texture")->capture_default_str();
  c.app->add_option("--storm-east", opts->synth.stormEastKm, "Storm centre east of the site (km)")
      ->capture_default_str();
  c.app->add_option("--storm-north", opts->synth.stormNorthKm, "Storm centre north of the site (km)")
      ->capture_default_str();
  c.app->add_option("--noise", opts->synth.noiseDbz, "Gate noise standard deviation (dB)")->capture_default_str();
  c.app
      ->add_option("--gate-spacing", opts->synth.gateSpacingMeters,
                   "Radar volumes: gate spacing (m; coarser gates make smaller volumes, e.g. 1000 for a network of "
                   "every site)")
      ->capture_default_str();
  c.app->add_flag("--velocity", opts->synth.radialVelocity,
                  "Radar volumes: also write VEL, the radial velocity of a uniform wind (the storms' motion, 10 m/s "
                  "east and 5 m/s north) at gates with echo");
  c.app->add_option("--time", opts->synth.startTimeIso8601, "Volume start time, UTC (YYYY-MM-DDTHH:MM:SSZ)")
      ->capture_default_str();
  c.app->add_option("--site", opts->site,
                    "Radar site ID,LAT,LON[,ANTENNA_M] (degrees, m above MSL; default KTLX); with --grid the grid's "
                    "centre, the storm placed as from that site");
  c.app->add_flag("--grid", opts->grid,
                  "Write a SYNTHETIC CF forecast grid instead (netCDF-4): simulated reflectivity of the same storm "
                  "moving ENE with a squall line, 400 x 400 columns 5 km apart around KTLX, 35 levels above ground "
                  "to 18 km, 13 hourly steps from 2020-05-01 18Z (about 1.6 MB, under a second)");
  c.app->add_option("--grid-size", opts->gridSize, "With --grid: NX,NY,LEVELS,TIMES (default 400,400,35,13)")
      ->delimiter(',')
      ->expected(4);
  CLI::Option* spacing = c.app->add_option("--spacing", opts->gridOptions.spacingKm, "With --grid: column spacing (km)")
                             ->capture_default_str();
  c.app->add_option("--sites", opts->sites,
                    "Write one storm field over a network: a volume per site (ICAO ids of the built-in NEXRAD table or "
                    "$ATMOGLOBE_NEXRAD_SITES, comma-separated; `all`; or a station-list FILE) into the directory -o, "
                    "consistent where radars overlap");
  CLI::Option* steps =
      c.app->add_option("--steps", opts->steps, "With --sites: volumes per site (a loop)")->capture_default_str();
  CLI::Option* interval =
      c.app->add_option("--interval", opts->intervalMinutes, "With --sites: minutes between volumes")
          ->capture_default_str();
  c.run = [opts, spacing, steps, interval] {
    if (!opts->grid && (!opts->gridSize.empty() || spacing->count() > 0))
      return fail("synth", "--grid-size and --spacing need --grid");
    if (opts->sites.empty() && (steps->count() > 0 || interval->count() > 0))
      return fail("synth", "--steps and --interval need --sites");
    if (!opts->sites.empty()) {
      if (opts->grid || !opts->site.empty())
        return fail("synth", "--sites writes radar volumes: not with --grid or --site");
      return writeNetwork(*opts);
    }
    if (!opts->site.empty())
      if (auto st = applySite(opts->site, *opts); !st) return fail("synth", st.error());
    if (opts->grid && opts->synth.radialVelocity) return fail("synth", "--velocity is a radar field: not with --grid");
    if (opts->grid) return writeGrid(*opts);
    const auto t0 = std::chrono::steady_clock::now();
    volume::SyntheticRadarSummary s;
    if (auto st = volume::writeSyntheticCfRadial(opts->output, opts->synth, &s); !st) return fail("synth", st.error());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& o = opts->synth;
    char line[512];
    std::snprintf(
        line, sizeof line,
        "wrote %s: SYNTHETIC CfRadial 1.4 (netCDF-4), %.1f MB in %.2f s\n"
        "  site %s %.5f %.5f, antenna %.1f m above MSL; VCP 212 angles: %zu sweeps x %zu rays x %zu gates "
        "(%.0f m from %.0f m)\n"
        "  field DBZ: %zu echo gates (>= %.0f dBZ; the rest _FillValue), max %.1f dBZ at %.1f km E %.1f km N, "
        "%.0f m MSL; seed %llu\n",
        opts->output.c_str(), static_cast<double>(s.fileBytes) / 1e6, seconds, o.siteId.c_str(), o.siteLatDeg,
        o.siteLonDeg, o.antennaAltitudeMslMeters, s.sweeps, s.raysPerSweep, s.gatesPerRay, o.gateSpacingMeters,
        o.firstGateRangeMeters, s.echoGates, o.minEchoDbz, s.maxDbz, s.maxEastKm, s.maxNorthKm, s.maxHeightMslMeters,
        static_cast<unsigned long long>(o.seed));
    std::cout << line;
    return 0;
  };
  return c;
}

}  // namespace atmoglobe::tools
