// `atmoglobe gates FILE [--field NAME] [--sweep K] [--model exact|fast] [--ke X] [--no-geoid]
//  [-o FILE.csv]`: one CSV row per gate with its WGS84 position, for users' own accuracy checks.
#include "Commands.h"

#include <atmoglobe/globe/AtomicFile.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GateCsv.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarLoad.h>

#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <system_error>

namespace atmoglobe::tools {

namespace {

struct GatesOptions {
  std::string file;
  std::string field;
  std::optional<int> sweep;
  std::string model = "exact";
  double ke = volume::kEffectiveEarthFactor;
  std::optional<double> earthRadiusMeters;
  bool noGeoid = false;
  std::string output;
};

int runGates(const GatesOptions& o) {
  const char* cmd = "gates";
  volume::BeamModel model;
  model.ke = o.ke;
  model.earthRadiusMeters = o.earthRadiusMeters;
  if (Status s = volume::validateBeamModel(model, "--ke/--earth-radius"); !s) return fail(cmd, s.error());

  volume::RadarLoadOptions load;
  load.fieldName = o.field;
  load.useGeoid = !o.noGeoid;
  Result<volume::LoadedRadar> loaded = volume::loadRadar(o.file, load);
  if (!loaded) return fail(cmd, loaded.error());
  const volume::RadarVolume& vol = loaded->volume;
  const volume::SiteResolution& site = loaded->site;
  if (o.sweep && (*o.sweep < 0 || static_cast<std::size_t>(*o.sweep) >= vol.sweeps.size())) {
    return fail(cmd, o.file + ": --sweep " + std::to_string(*o.sweep) + " out of range (the volume has " +
                         std::to_string(vol.sweeps.size()) + " sweeps with field " + vol.loadedField.name + ")");
  }
  char latLon[96];
  std::snprintf(latLon, sizeof latLon, "%.6f, %.6f", site.site.latDeg, site.site.lonDeg);
  std::cerr << "atmoglobe gates: " << o.file << ": site " << latLon << "; " << site.datumNote
            << "; heights in the CSV are above the WGS84 ellipsoid; model " << o.model << ", ke " << model.ke << ", R "
            << (model.earthRadiusMeters ? std::to_string(*model.earthRadiusMeters) + " m"
                                        : "WGS84 geocentric radius at the site")
            << "; field " << vol.loadedField.name
            << (vol.loadedField.units.empty() ? "" : " [" + vol.loadedField.units + "]") << "\n";

  // Output: stdout, or a file published whole once complete (globe/AtomicFile.h).
  std::optional<globe::AtomicFileWriter> file;
  if (!o.output.empty() && o.output != "-") {
    auto created = globe::AtomicFileWriter::create(o.output);
    if (!created) return fail(cmd, created.error());
    file.emplace(std::move(created.value()));
  }
  // Writes a block to the file or stdout; the file's errors name it.
  auto emit = [&](const std::string& block) -> Status {
    if (file) return file->write(block);
    if (std::fwrite(block.data(), 1, block.size(), stdout) != block.size()) return makeError("stdout: write error");
    return Ok{};
  };

  std::string line;
  line.reserve(1 << 16);
  line += volume::gateCsvHeader();
  std::vector<glm::dvec3> fast;
  for (std::size_t k = 0; k < vol.sweeps.size(); ++k) {
    if (o.sweep && static_cast<std::size_t>(*o.sweep) != k) continue;
    const volume::Sweep& sw = vol.sweeps[k];
    const bool useFast = o.model == "fast";
    if (useFast) volume::geolocateSweepFast(site.site, model, sw, &fast);
    for (std::size_t i = 0; i < sw.rayCount(); ++i) {
      for (std::uint32_t g = 0; g < sw.gateCount; ++g) {
        const double range = sw.gateRangeMeters(g);
        volume::GatePosition p;
        if (useFast) {
          p.ecef = fast[i * sw.gateCount + g];
          const globe::Geodetic geo = globe::ecefToGeodetic(p.ecef);
          p.latDeg = geo.latDeg, p.lonDeg = geo.lonDeg, p.heightMeters = geo.heightMeters;
        } else {
          p = volume::geolocateGateExact(site.site, model, sw.azimuthDeg[i], sw.elevationDeg[i], range);
        }
        const float* value = sw.values.empty() ? nullptr : &sw.values[i * sw.gateCount + g];
        volume::appendGateCsvRow(line, k, i, g, sw.azimuthDeg[i], sw.elevationDeg[i], range, p, value);
        if (line.size() > (1 << 16) - 512) {
          if (Status s = emit(line); !s) return fail(cmd, s.error());
          line.clear();
        }
      }
    }
  }
  if (Status s = emit(line); !s) return fail(cmd, s.error());
  if (!file) {
    std::fflush(stdout);
    return 0;
  }
  if (Status s = file->commit(); !s) return fail(cmd, s.error());
  return 0;
}

}  // namespace

Command addGatesCommand(CLI::App& root) {
  auto o = std::make_shared<GatesOptions>();
  Command c;
  c.app = root.add_subcommand(
      "gates",
      "One CSV row per gate with its WGS84 position.\n"
      "Columns: sweep,ray,gate,azimuth_deg,elevation_deg,range_m,lat_deg,lon_deg,height_m,ecef_x,ecef_y,ecef_z,value\n"
      "  sweep: index in the volume's sweep list (sorted by fixed angle, as `atmoglobe info` lists them);\n"
      "  range_m: slant range of the gate centre; height_m: above the WGS84 ellipsoid; ecef_*: metres.\n"
      "  value: the field in its units; EMPTY where there is no data (not measured, range folded);\n"
      "  the token -inf where the gate was measured but nothing was detected (below threshold).\n"
      "Model: effective Earth radius ke*R (Doviak & Zrnic 2.28), WGS84 geodesic from the site; the antenna\n"
      "height above mean sea level is converted with the EGM96 geoid (see stderr) unless --no-geoid.");
  c.app->add_option("file", o->file, "radar file (CfRadial, ODIM_H5, NEXRAD Level II)")->required();
  c.app->add_option("--field", o->field, "field to write (default: reflectivity)");
  c.app->add_option("--sweep", o->sweep, "only sweep K (0-based, as listed by `atmoglobe info`)");
  c.app->add_option("--model", o->model, "exact: one geodesic per gate; fast: per-ray Chebyshev series (<= 1 cm)")
      ->check(CLI::IsMember({"exact", "fast"}));
  c.app->add_option("--ke", o->ke, "effective Earth radius factor (default 4/3; 1 = no refraction)");
  c.app->add_option("--earth-radius", o->earthRadiusMeters,
                    "Earth radius R in metres (default: WGS84 geocentric radius at the site latitude)");
  c.app->add_flag("--no-geoid", o->noGeoid,
                  "use the file's antenna height as ellipsoidal height (no EGM96 conversion)");
  c.app->add_option("-o,--output", o->output, "CSV file to write (default: standard output)");
  c.run = [o] { return runGates(*o); };
  return c;
}

}  // namespace atmoglobe::tools
