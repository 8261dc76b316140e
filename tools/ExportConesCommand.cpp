// `atmoglobe export-cones FILE [--field NAME] [--colors auto|NWS|cividis|velocity|FILE.pal] [--sweeps LIST]
//  [--max-range KM] [--straight] [--ke X] [--no-geoid] -o OUT(.glb|.gltf|.dae|.kml|.kmz)
//  [--tileset DIR]`: each PPI sweep as a georeferenced, textured cone (see volume/ConeExport.h).
#include "Commands.h"

#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/ConeExport.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarLoad.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::tools {

namespace {

struct ExportConesOptions {
  std::string file;
  std::string field;
  std::string colors = "auto";
  std::string sweeps;
  std::optional<double> maxRangeKm;
  bool straight = false;
  double ke = volume::kEffectiveEarthFactor;
  bool noGeoid = false;
  std::string output;
  std::string tileset;
};

// "0,2,5-7" -> {0, 2, 5, 6, 7}. Errors name the bad item.
Result<std::vector<int>> parseSweepList(const std::string& text) {
  std::vector<int> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? text.size() + 1 : comma + 1;
    auto num = [](const std::string& s, int* v) {
      const auto r = std::from_chars(s.data(), s.data() + s.size(), *v);
      return r.ec == std::errc() && r.ptr == s.data() + s.size() && *v >= 0;
    };
    const std::size_t dash = item.find('-');
    int a = 0, b = 0;
    if (dash == std::string::npos) {
      if (!num(item, &a)) return makeError("--sweeps: '" + item + "' is not a sweep index (use e.g. 0,2,5-7)");
      b = a;
    } else if (!num(item.substr(0, dash), &a) || !num(item.substr(dash + 1), &b) || b < a || b - a > 10000) {
      return makeError("--sweeps: '" + item + "' is not a range of sweep indices (use e.g. 5-7)");
    }
    for (int k = a; k <= b; ++k) out.push_back(k);
  }
  return out;
}

int runExportCones(const ExportConesOptions& o) {
  const char* cmd = "export-cones";
  if (o.output.empty() && o.tileset.empty())
    return fail(cmd, "give -o OUT(.glb|.gltf|.dae|.kml|.kmz) and/or --tileset DIR");
  if (!o.output.empty()) {
    if (Result<volume::ConeFormat> f = volume::coneFormatFromPath(o.output); !f) return fail(cmd, f.error());
  }
  volume::ConeExportOptions opt;
  if (!o.sweeps.empty()) {
    Result<std::vector<int>> list = parseSweepList(o.sweeps);
    if (!list) return fail(cmd, list.error());
    opt.sweepIndices = *list;
  }
  if (o.maxRangeKm) {
    if (!std::isfinite(*o.maxRangeKm) || *o.maxRangeKm <= 0)
      return fail(cmd, "--max-range must be a positive number of km");
    opt.maxRangeMeters = *o.maxRangeKm * 1000.0;
  }
  opt.mesh.straight = o.straight;
  opt.mesh.beam.ke = o.ke;

  volume::RadarLoadOptions load;
  load.fieldName = o.field;
  load.useGeoid = !o.noGeoid;
  Result<volume::LoadedRadar> loaded = volume::loadRadar(o.file, load);
  if (!loaded) return fail(cmd, loaded.error());
  // Colours by the field's kind unless a table is named (the value range for "other" fields).
  volume::ValueRange range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const volume::Sweep& sw : loaded->volume.sweeps)
    for (float v : sw.values)
      if (std::isfinite(v)) range = {std::min(range.minValue, double(v)), std::max(range.maxValue, double(v))};
  Result<volume::TransferFunction> transfer =
      volume::transferForField(o.colors, loaded->volume.loadedField, loaded->volume.nyquistVelocityMps, range);
  if (!transfer) return fail(cmd, transfer.error());
  const volume::ColorTable& colors = transfer->colors;
  Result<volume::ConeScene> scene = volume::buildConeScene(loaded->volume, loaded->site, colors, opt);
  if (!scene) return fail(cmd, scene.error());

  std::size_t triangles = 0;
  for (const volume::Cone& c : scene->cones) triangles = std::max(triangles, c.mesh.triangleCount());
  std::cerr << "atmoglobe export-cones: " << o.file << ": " << scene->cones.size() << " sweeps, field "
            << loaded->volume.loadedField.name << ", colours " << colors.name() << ", "
            << (o.straight ? "straight cones" : "beams bent (ke " + std::to_string(o.ke) + ")") << ", at most "
            << triangles << " triangles per cone; " << scene->site.datumNote << "\n";
  if (!o.output.empty()) {
    Result<std::vector<std::string>> files = volume::exportCones(*scene, o.output);
    if (!files) return fail(cmd, files.error());
    for (const std::string& f : *files) std::cout << f << "\n";
  }
  if (!o.tileset.empty()) {
    Result<std::vector<std::string>> files = volume::exportConesTileset(*scene, o.tileset);
    if (!files) return fail(cmd, files.error());
    for (const std::string& f : *files) std::cout << f << "\n";
  }
  return 0;
}

}  // namespace

Command addExportConesCommand(CLI::App& root) {
  auto opts = std::make_shared<ExportConesOptions>();
  CLI::App* app = root.add_subcommand(
      "export-cones", "Export radar sweeps as georeferenced textured cones (glTF, COLLADA, KML/KMZ, 3D Tiles)");
  app->add_option("file", opts->file, "Radar volume (CfRadial, ODIM_H5, NEXRAD Level II)")->required();
  app->add_option("--field", opts->field, "Field to draw (default: reflectivity)");
  app->add_option(
      "--colors", opts->colors,
      "Colour table: auto (by the field's kind), NWS (stepped, dBZ), cividis, velocity (+-Nyquist), or a GR/WCT .pal file");
  app->add_option("--sweeps", opts->sweeps, "Sweep indices, e.g. 0,2,5-7 (default: every PPI sweep)");
  app->add_option("--max-range", opts->maxRangeKm, "Last gate drawn (km)");
  app->add_flag("--straight", opts->straight,
                "Straight cones (no refraction, no Earth curvature) as old viewers drew them");
  app->add_option("--ke", opts->ke, "Effective Earth radius factor of the beam model (default 4/3)");
  app->add_flag("--no-geoid", opts->noGeoid, "Use the file's sea-level antenna height as ellipsoidal (no EGM96)");
  app->add_option("-o,--output", opts->output, "Output: .glb, .gltf, .dae, .kml or .kmz");
  app->add_option("--tileset", opts->tileset,
                  "Also write DIR/tileset.json + DIR/cones.glb (3D Tiles 1.1) for CesiumJS");
  return Command{app, [opts] { return runExportCones(*opts); }};
}

}  // namespace atmoglobe::tools
