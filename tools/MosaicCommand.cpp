// `atmoglobe mosaic RADARS... --box S,N,W,E --heights B,T --resolution DEG,M [--rule mean|lowest|max]
//  [--field F] -o OUT.nc|OUT.nrrd`: a 3-D mosaic of several radars on a regular longitude x latitude x
// altitude grid, each radar sampled in its own geometry through the network's coverage index and
// combined by an overlap rule (volume/RadarNetwork.h, volume/Mosaic.h).
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/globe/Progress.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/Mosaic.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/SliceSource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::tools {

namespace {

struct Options {
  std::vector<std::string> radars;
  std::string output, box, heights, resolution, field;
  std::string rule = "mean", interpolation = "linear";
  bool noGeoid = false;
  unsigned threads = 0;
};

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Samples from `first` by `step` up to `last` (the last one at or before it, within 1e-9 of a step).
std::size_t countAlong(double first, double last, double step) {
  return static_cast<std::size_t>(std::floor((last - first) / step + 1e-9)) + 1;
}

int run(const Options& o) {
  const char* cmd = "mosaic";
  const bool netcdf = endsWith(o.output, ".nc"), nrrd = endsWith(o.output, ".nrrd");
  if (!netcdf && !nrrd) return fail(cmd, "-o " + o.output + ": the output is a CF netCDF (.nc) or NRRD (.nrrd) file");
  auto rule = volume::parseOverlapRule(o.rule);
  if (!rule) return fail(cmd, "--rule: " + rule.error());
  auto box = parseNumbers(o.box, 4, 4, "--box");
  if (!box) return fail(cmd, box.error());
  auto heights = parseNumbers(o.heights, 2, 2, "--heights");
  if (!heights) return fail(cmd, heights.error());
  auto res = parseNumbers(o.resolution, 2, 2, "--resolution");
  if (!res) return fail(cmd, res.error());
  const double south = (*box)[0], north = (*box)[1], west = (*box)[2];
  double east = (*box)[3];
  const double degStep = (*res)[0], mStep = (*res)[1];
  if (!(degStep > 0.0 && degStep <= 10.0) || !(mStep > 0.0 && mStep <= 20000.0))
    return fail(cmd, "--resolution " + o.resolution + ": DEG in (0, 10] and M in (0, 20000]");
  if (!(south >= -90.0 && north <= 90.0 && south < north))
    return fail(cmd, "--box " + o.box + ": SOUTH < NORTH within -90..90");
  if (!(west >= -180.0 && west <= 360.0 && east >= -180.0 && east <= 360.0) || west == east)
    return fail(cmd, "--box " + o.box + ": WEST and EAST within -180..360 and different");
  if (east < west) east += 360.0;  // across the antimeridian
  if (!((*heights)[0] < (*heights)[1])) return fail(cmd, "--heights " + o.heights + ": BOTTOM < TOP");

  volume::RegularGridSpec spec;
  spec.kind = volume::RegularGridKind::Geographic;
  spec.datum = volume::HeightDatum::MeanSeaLevel;
  spec.westDeg = west;
  spec.southDeg = south;
  spec.bottomMeters = (*heights)[0];
  spec.nx = countAlong(west, east, degStep);
  spec.ny = countAlong(south, north, degStep);
  spec.nz = countAlong((*heights)[0], (*heights)[1], mStep);
  spec.eastDeg = west + degStep * static_cast<double>(spec.nx - 1);
  spec.northDeg = south + degStep * static_cast<double>(spec.ny - 1);
  spec.topMeters = spec.bottomMeters + mStep * static_cast<double>(spec.nz - 1);
  if (spec.nx < 2 || spec.ny < 2 || spec.nz < 1)
    return fail(cmd, "--box and --resolution give fewer than 2 longitudes or latitudes");
  constexpr std::size_t kMaxSamples = std::size_t{1} << 29;  // 2 GiB of floats
  if (Status s = volume::validateRegularGridSpec(spec, kMaxSamples); !s) return fail(cmd, s.error());

  // The radars, each with its render layout (its own geometry).
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<volume::LoadedRadar> loaded;
  volume::RadarLoadOptions load;
  load.fieldName = o.field;
  load.useGeoid = !o.noGeoid;
  load.buildRenderLayout = true;
  std::optional<volume::FieldKind> kind;
  std::string kindOf;
  {
    globe::Progress progress("reading radars", o.radars.size());
    for (const std::string& path : o.radars) {
      auto r = volume::loadRadar(path, load);
      if (!r) {
        progress.finish(true);
        return fail(cmd, r.error());
      }
      const volume::FieldKindEvidence k = volume::classifyField(r->volume.loadedField);
      if (kind && k.kind != *kind) {
        progress.finish(true);
        return fail(cmd, path + ": field " + r->volume.loadedField.name + " is " + volume::toString(k.kind) + ", " +
                             kindOf + " is " + volume::toString(*kind) +
                             ": a mosaic combines one quantity (choose it with --field)");
      }
      if (!kind) {
        kind = k.kind;
        kindOf = path + "'s field " + r->volume.loadedField.name;
      }
      loaded.push_back(std::move(*r));
      progress.advance(1, path);
    }
  }
  std::vector<const volume::PolarVolume*> layouts;
  volume::MosaicMetadata meta;
  meta.rule = *rule;
  meta.kind = *kind;
  meta.field = loaded.front().volume.loadedField.name;
  meta.units = loaded.front().volume.loadedField.units;
  for (const volume::LoadedRadar& r : loaded) {
    layouts.push_back(&*r.layout);
    meta.radars.push_back({volume::siteTitle(r.volume.site), r.volume.timeIso8601, r.volume.sourcePath,
                           r.site.site.latDeg, r.site.site.lonDeg});
    meta.synthetic = meta.synthetic || volume::fileSaysSynthetic(r.volume.sourcePath);
  }
  auto network = volume::makeRadarNetworkSampler(layouts, *rule, *kind);
  if (!network) return fail(cmd, network.error());
  const volume::CoverageIndex& index = (*network)->coverage();

  const volume::GeoidGrid* geoid = nullptr;
  const auto& egm = volume::defaultEgm96Grid();
  if (!egm) return fail(cmd, "heights above mean sea level need the EGM96 geoid: " + egm.error());
  geoid = &*egm;
  std::optional<globe::Progress> progress;
  std::mutex progressMutex;
  auto levelDone = [&](std::size_t done, std::size_t levels) {
    std::lock_guard<std::mutex> lock(progressMutex);
    if (!progress) progress.emplace("mosaic levels", levels);
    progress->update(done);
  };
  auto values = volume::resampleRegular(
      **network, spec, o.interpolation == "nearest" ? volume::Interpolation::Nearest : volume::Interpolation::Linear,
      geoid, o.threads, levelDone);
  if (progress) progress->finish(!values);
  if (!values) return fail(cmd, values.error());
  std::size_t withValue = 0;
  for (float v : *values) withValue += std::isfinite(v);

  if (netcdf) {
    if (Status s = volume::writeMosaicNetcdf(o.output, spec, *values, meta); !s) return fail(cmd, s.error());
  } else {
    volume::NrrdMetadata m;
    m.content = meta.field + " mosaic of " + std::to_string(meta.radars.size()) + " radars, rule " + o.rule;
    m.valueUnits = meta.units;
    m.keyValues.emplace_back("overlap_rule", o.rule);
    m.keyValues.emplace_back("overlap_rule_formula", volume::overlapRuleFormula(*rule));
    for (std::size_t k = 0; k < meta.radars.size(); ++k)
      m.keyValues.emplace_back("radar_" + std::to_string(k),
                               meta.radars[k].site + " " + meta.radars[k].timeIso8601 + " " + meta.radars[k].path);
    if (Status s = volume::writeNrrd(o.output, spec, *values, m); !s) return fail(cmd, s.error());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  char line[768];
  std::snprintf(line, sizeof line,
                "wrote %s: %s mosaic of %zu radars (rule %s), %zu x %zu x %zu (lon %.4f..%.4f, lat %.4f..%.4f, "
                "altitude %.0f..%.0f m above MSL), %zu samples with an echo, in %.1f s\n"
                "  coverage index: %d x %d cells of %.3f deg, at most %zu radars in a cell (%.2f on average where "
                "any)\n",
                o.output.c_str(), meta.field.c_str(), meta.radars.size(), o.rule.c_str(), spec.nx, spec.ny, spec.nz,
                spec.westDeg, spec.eastDeg, spec.southDeg, spec.northDeg, spec.bottomMeters, spec.topMeters, withValue,
                seconds, index.columns, index.rows, index.cellDeg, index.maxPerCell(), index.meanPerOccupiedCell());
  std::cout << line;
  return 0;
}

}  // namespace

Command addMosaicCommand(CLI::App& root) {
  auto opts = std::make_shared<Options>();
  Command c;
  c.app = root.add_subcommand("mosaic",
                              "Merge several radars into one 3-D grid (longitude x latitude x altitude above MSL), "
                              "each sampled in its own geometry and combined by an overlap rule; CF netCDF or NRRD");
  c.app->add_option("RADARS", opts->radars, "Radar files (any format `info` reads), one per site")->required();
  c.app->add_option("-o,--output", opts->output, "Output .nc (CF-1.8 netCDF-4) or .nrrd, written atomically")
      ->required();
  c.app->add_option("--box", opts->box, "SOUTH,NORTH,WEST,EAST (deg; WEST > EAST crosses the antimeridian)")
      ->required();
  c.app->add_option("--heights", opts->heights, "BOTTOM,TOP altitudes above mean sea level (m)")->required();
  c.app->add_option("--resolution", opts->resolution, "DEG,M: horizontal spacing (deg) and vertical spacing (m)")
      ->required();
  c.app
      ->add_option("--rule", opts->rule,
                   "Overlap rule: mean (weights exp(-(range/50 km)^2), as NOAA's MRMS), lowest (the radar whose "
                   "lowest beam passes lowest), max")
      ->capture_default_str();
  c.app->add_option("--field", opts->field, "Field to merge (default: each file's reflectivity)");
  c.app->add_option("--interpolation", opts->interpolation, "linear or nearest")
      ->check(CLI::IsMember({"linear", "nearest"}))
      ->capture_default_str();
  c.app->add_flag("--no-geoid", opts->noGeoid, "Read antenna heights above sea level as ellipsoidal (no EGM96)");
  c.app->add_option("--threads", opts->threads, "Worker threads (0: all)")->capture_default_str();
  addQuietOption(*c.app);
  c.run = [opts] { return run(*opts); };
  return c;
}

}  // namespace atmoglobe::tools
