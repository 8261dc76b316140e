// `atmoglobe convert FILE [--var NAME] [--time T] [--crop S,N,W,E] [--heights BOTTOM,TOP]
//  [--size NX,NY,NZ] [--grid geographic|cartesian] [--datum msl|ellipsoid] [--raw] -o OUT.nrrd`:
// a forecast-grid variable or a radar field resampled onto a regular grid and written as NRRD
// (volume/NrrdExport.h).
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/globe/Progress.h>
#include <atmoglobe/volume/NrrdExport.h>

#include <array>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace atmoglobe::tools {

Command addConvertCommand(CLI::App& root) {
  struct Options {
    std::string file, output, variable, time, crop, heights, size;
    std::string grid = "geographic", datum = "msl", interpolation = "linear";
    bool raw = false, noGeoid = false;
    long member = -1;
    std::string ensemble;
    std::map<std::string, std::size_t> gridIndex;
  };
  auto opts = std::make_shared<Options>();
  Command c;
  c.app = root.add_subcommand("convert",
                              "Resample a forecast-grid variable or a radar field onto a regular "
                              "(longitude, latitude, height) or local Cartesian grid and write it as NRRD");
  c.app->add_option("FILE", opts->file, "Forecast grid (CF or WRF netCDF, GRIB 1 or 2) or radar file")->required();
  c.app->add_option("-o,--output", opts->output, "Output .nrrd file (written atomically)")->required();
  c.app->add_option("--var,--field", opts->variable, "Grid variable or radar field (default: the file's default)");
  c.app->add_option("--time", opts->time, "Grids: time step as an index or an ISO 8601 UTC time (default: the first)");
  c.app
      ->add_option("--member", opts->member,
                   "Grids: the ensemble member (GRIB `number`, listed by `atmoglobe info`; default: the first)")
      ->check(CLI::NonNegativeNumber);
  c.app->add_option("--ensemble", opts->ensemble,
                    "Grids: a statistic over every ensemble member instead of one: mean, spread (standard deviation), "
                    "min, max, or prob:>=VALUE (also >, <=, <; the percentage of members passing)");
  addGridIndexOption(c.app, opts->gridIndex);
  c.app->add_option("--crop", opts->crop,
                    "Box SOUTH,NORTH,WEST,EAST (deg; west > east crosses the antimeridian); grids read only it");
  c.app->add_option("--heights", opts->heights, "BOTTOM,TOP (m above the datum; cartesian: the z range)");
  c.app->add_option("--size", opts->size,
                    "NX,NY,NZ samples (default: the data's own horizontal spacing, 250 m levels)");
  c.app->add_option("--grid", opts->grid, "geographic (lon, lat, height) or cartesian (east, north, up in m)")
      ->check(CLI::IsMember({"geographic", "cartesian"}));
  c.app->add_option("--datum", opts->datum, "Geographic heights above msl (EGM96) or the WGS84 ellipsoid")
      ->check(CLI::IsMember({"msl", "ellipsoid"}));
  c.app->add_option("--interpolation", opts->interpolation, "linear or nearest")
      ->check(CLI::IsMember({"linear", "nearest"}));
  c.app->add_flag("--raw", opts->raw, "Raw encoding instead of gzip");
  c.app->add_flag("--no-geoid", opts->noGeoid, "Read heights above sea level as ellipsoidal (no EGM96)");
  addQuietOption(*c.app);
  c.run = [opts] {
    volume::NrrdExportOptions o;
    o.inputPath = opts->file;
    o.outputPath = opts->output;
    o.variable = opts->variable;
    o.time = opts->time;
    o.member = opts->member;
    o.gridIndex = opts->gridIndex;
    if (!opts->ensemble.empty()) {
      auto stat = volume::parseEnsembleStatistic(opts->ensemble);
      if (!stat) return fail("convert", "--ensemble: " + stat.error());
      o.ensemble = *stat;
    }
    if (!opts->crop.empty()) {
      auto v = parseNumbers(opts->crop, 4, 4, "--crop");
      if (!v) return fail("convert", v.error());
      o.cropSouthNorthWestEastDeg = std::array<double, 4>{(*v)[0], (*v)[1], (*v)[2], (*v)[3]};
    }
    if (!opts->heights.empty()) {
      auto v = parseNumbers(opts->heights, 2, 2, "--heights");
      if (!v) return fail("convert", v.error());
      o.heightRangeMeters = std::array<double, 2>{(*v)[0], (*v)[1]};
    }
    if (!opts->size.empty()) {
      auto v = parseNumbers(opts->size, 3, 3, "--size");
      if (!v) return fail("convert", v.error());
      std::array<std::size_t, 3> n{};
      for (std::size_t i = 0; i < 3; ++i) {
        const double d = (*v)[i];
        if (!(d >= 1.0 && d <= 1e6) || d != static_cast<double>(static_cast<std::size_t>(d)))
          return fail("convert", "--size: each count must be a whole number from 1 to 1000000");
        n[i] = static_cast<std::size_t>(d);
      }
      o.size = n;
    }
    o.kind = opts->grid == "cartesian" ? volume::RegularGridKind::LocalCartesian : volume::RegularGridKind::Geographic;
    o.datum = opts->datum == "ellipsoid" ? volume::HeightDatum::Ellipsoid : volume::HeightDatum::MeanSeaLevel;
    o.interpolation = opts->interpolation == "nearest" ? volume::Interpolation::Nearest : volume::Interpolation::Linear;
    o.gzip = !opts->raw;
    o.useGeoid = !opts->noGeoid;
    // Height levels resampled (reported from the worker threads; the total comes with the first).
    std::optional<globe::Progress> progress;
    std::mutex progressMutex;
    o.progress = [&](std::size_t done, std::size_t levels) {
      std::lock_guard<std::mutex> lock(progressMutex);
      if (!progress) progress.emplace("resampling levels", levels);
      progress->update(done);
    };
    auto report = volume::exportNrrd(o);
    if (progress) progress->finish(!report);
    if (!report) return fail("convert", report.error());
    const auto& s = report->spec;
    std::cerr << "atmoglobe convert: " << o.outputPath << ": " << report->kindText << " " << report->field
              << (report->units.empty() ? "" : " [" + report->units + "]")
              << (report->validTime.empty() ? "" : " at " + report->validTime) << ", " << s.nx << " x " << s.ny << " x "
              << s.nz << " "
              << (s.kind == volume::RegularGridKind::Geographic
                      ? std::string("lon/lat/height (above ") +
                            (s.datum == volume::HeightDatum::MeanSeaLevel ? "mean sea level" : "the WGS84 ellipsoid") +
                            ")"
                      : std::string("east/north/up"))
              << ", " << report->finiteValues << " samples with a value"
              << (report->bytesRead ? ", " + std::to_string(report->bytesRead) + " bytes read" : "")
              << (report->approximateHeights ? "; heights APPROXIMATE: " + report->heightNote : "") << "\n";
    return 0;
  };
  return c;
}

}  // namespace atmoglobe::tools
