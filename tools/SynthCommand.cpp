// `atmoglobe synth -o FILE.nc [--seed N] [--storm-east KM] [--storm-north KM] [--noise DB]`:
// writes a SYNTHETIC CfRadial 1.4 volume (KTLX site, VCP 212 angles, an analytic supercell and
// stratiform area) for the default scene and for tests. See volume/SyntheticRadar.h.
#include "Commands.h"

#include <atmoglobe/volume/SyntheticRadar.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

namespace atmoglobe::tools {

Command addSynthCommand(CLI::App& root) {
  struct Options {
    std::string output;
    volume::SyntheticRadarOptions synth;
  };
  auto opts = std::make_shared<Options>();
  Command c;
  c.app = root.add_subcommand("synth", "Write a SYNTHETIC CfRadial radar volume (KTLX, VCP 212 angles, an analytic "
                                       "supercell with anvil and a stratiform area with a bright band)");
  c.app->add_option("-o,--output", opts->output, "Output file (CfRadial 1.4, netCDF-4)")->required();
  c.app->add_option("--seed", opts->synth.seed, "Seed of the noise and texture")->capture_default_str();
  c.app->add_option("--storm-east", opts->synth.stormEastKm, "Storm centre east of the site (km)")->capture_default_str();
  c.app->add_option("--storm-north", opts->synth.stormNorthKm, "Storm centre north of the site (km)")->capture_default_str();
  c.app->add_option("--noise", opts->synth.noiseDbz, "Gate noise standard deviation (dB)")->capture_default_str();
  c.run = [opts] {
    const auto t0 = std::chrono::steady_clock::now();
    volume::SyntheticRadarSummary s;
    if (auto st = volume::writeSyntheticCfRadial(opts->output, opts->synth, &s); !st) return fail("synth", st.error());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& o = opts->synth;
    char line[512];
    std::snprintf(line, sizeof line,
                  "wrote %s: SYNTHETIC CfRadial 1.4 (netCDF-4), %.1f MB in %.2f s\n"
                  "  site %s %.5f %.5f, antenna %.1f m above MSL; VCP 212 angles: %zu sweeps x %zu rays x %zu gates "
                  "(%.0f m from %.0f m)\n"
                  "  field DBZ: %zu echo gates (>= %.0f dBZ; the rest _FillValue), max %.1f dBZ at %.1f km E %.1f km N, "
                  "%.0f m MSL; seed %llu\n",
                  opts->output.c_str(), static_cast<double>(s.fileBytes) / 1e6, seconds, o.siteId.c_str(), o.siteLatDeg,
                  o.siteLonDeg, o.antennaAltitudeMslMeters, s.sweeps, s.raysPerSweep, s.gatesPerRay, o.gateSpacingMeters,
                  o.firstGateRangeMeters, s.echoGates, o.minEchoDbz, s.maxDbz, s.maxEastKm, s.maxNorthKm,
                  s.maxHeightMslMeters, static_cast<unsigned long long>(o.seed));
    std::cout << line;
    return 0;
  };
  return c;
}

}  // namespace atmoglobe::tools
