// `atmoglobe synth -o FILE.nc [--site ID,LAT,LON[,M]] [--seed N] [--storm-east KM] [--storm-north KM] [--noise DB]
// [--time ISO]`: writes a SYNTHETIC CfRadial 1.4 volume (KTLX site, VCP 212 angles, an analytic supercell and
// stratiform area) for the default scene and for tests. See volume/SyntheticRadar.h.
// `atmoglobe synth --grid -o FILE.nc [--grid-size NX,NY,LEVELS,TIMES] [--spacing KM]`: a SYNTHETIC
// CF forecast grid around the same storm instead. See volume/SyntheticGrid.h.
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/volume/SyntheticGrid.h>
#include <atmoglobe/volume/SyntheticRadar.h>

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
  std::string site;  ///< --site ID,LAT,LON[,ANTENNA_M]
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
  c.run = [opts, spacing] {
    if (!opts->grid && (!opts->gridSize.empty() || spacing->count() > 0))
      return fail("synth", "--grid-size and --spacing need --grid");
    if (!opts->site.empty())
      if (auto st = applySite(opts->site, *opts); !st) return fail("synth", st.error());
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
