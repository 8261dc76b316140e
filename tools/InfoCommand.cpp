// `atmoglobe info FILE [--json] [--variable NAME]`: what a radar file holds (format, site, time,
// sweeps, fields; metadata only: no field values are decoded) or what a forecast grid holds
// (dimensions, variables, grid, vertical coordinate and how heights were derived, height range,
// times, extent; coordinates and a sample of columns are read, no field values). Radar or grid
// is decided from the content (volume::isGridFile), never from the file name.
#include "Commands.h"

#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>

#include <nlohmann/json.hpp>

#include <iostream>
#include <map>
#include <memory>
#include <string>

namespace atmoglobe::tools {

Command addInfoCommand(CLI::App& root) {
  struct Options {
    std::string file;
    std::string variable;
    std::string nexradSites;
    bool json = false;
    std::map<std::string, std::size_t> gridIndex;
  };
  auto opts = std::make_shared<Options>();
  Command c;
  c.app = root.add_subcommand("info",
                              "Describe a radar file (CfRadial, ODIM_H5, NEXRAD Level II: format, site, "
                              "time, sweeps and fields) or a forecast grid (CF netCDF, WRF: dimensions, "
                              "variables, grid, vertical coordinate and heights, times, extent)");
  c.app
      ->add_option("FILE", opts->file,
                   "Radar file or forecast grid (netCDF, GRIB); or the files of radar volumes split over files: a "
                   "directory, a glob pattern (quoted: \"dir/*.h5\") or a comma-separated list (one entry per "
                   "assembled volume)")
      ->required();
  c.app->add_option(
      "--nexrad-sites", opts->nexradSites,
      "NEXRAD site list (CSV or JSON) giving the position of legacy NEXRAD Level II files, which "
      "hold only the ICAO id (default: $ATMOGLOBE_NEXRAD_SITES, else the built-in table of every WSR-88D site)");
  c.app->add_flag("--json", opts->json, "Print one JSON object instead of text");
  c.app->add_option("--variable", opts->variable,
                    "Grid files: the variable whose grid, vertical coordinate and heights are described "
                    "(default: the reader's default variable)");
  addGridIndexOption(c.app, opts->gridIndex);
  c.run = [opts] {
    // A grid first: a directory, pattern or list of GRIB files is one grid (a set of radar files
    // holds no GRIB file).
    if (volume::isGridFile(opts->file)) {
      volume::GridReadOptions read;
      read.variable = opts->variable;
      read.extraIndex = opts->gridIndex;
      auto info = volume::describeGridFile(opts->file, read);
      if (!info) return fail("info", info.error());
      std::cout << (opts->json ? volume::describeGridJson(*info) + "\n" : volume::describeGridText(*info));
      return 0;
    }
    if (volume::isRadarFileSet(opts->file)) {
      auto paths = volume::expandRadarPaths(opts->file);
      if (!paths) return fail("info", paths.error());
      volume::RadarSetOptions set;
      set.read.loadValues = false;  // metadata only
      set.read.nexradSiteList = opts->nexradSites;
      set.label = opts->file;
      auto volumes = volume::readRadarVolumeGroups(*paths, set);
      if (!volumes) return fail("info", volumes.error());
      if (opts->json) {
        nlohmann::ordered_json j;
        j["set"] = opts->file;
        j["files"] = paths->size();
        j["volumes"] = nlohmann::ordered_json::array();
        for (const volume::RadarVolume& v : *volumes)
          j["volumes"].push_back(nlohmann::ordered_json::parse(volume::describeVolumeJson(v)));
        std::cout << j.dump(2) << "\n";
      } else {
        std::cout << opts->file << ": " << paths->size() << " files, " << volumes->size() << " volume"
                  << (volumes->size() == 1 ? "" : "s") << "\n";
        for (std::size_t i = 0; i < volumes->size(); ++i)
          std::cout << "\n--- volume " << i + 1 << " of " << volumes->size() << "\n"
                    << volume::describeVolumeText((*volumes)[i]);
      }
      return 0;
    }
    if (!opts->variable.empty() || !opts->gridIndex.empty())
      return fail("info", opts->file + ": --variable (and --grid-index) applies to forecast grids only");
    volume::ReadOptions ro;
    ro.loadValues = false;  // metadata only: fast, no field array read
    ro.nexradSiteList = opts->nexradSites;
    auto vol = volume::readRadarVolume(opts->file, ro);
    if (!vol) {
      // Library messages start with the file name: "atmoglobe info: FILE: reason". A netCDF file
      // that is neither may be a broken grid: say what the grid reader found wrong too.
      if (io::hasNetcdfSignature(opts->file)) {
        auto grid = volume::describeGridFile(opts->file);
        if (!grid)
          return fail("info", vol.error() + " (read as a radar file); " + grid.error() + " (read as a forecast grid)");
      }
      return fail("info", vol.error());
    }
    std::cout << (opts->json ? volume::describeVolumeJson(*vol) + "\n" : volume::describeVolumeText(*vol));
    return 0;
  };
  return c;
}

}  // namespace atmoglobe::tools
