// `atmoglobe info FILE [--json]`: what a radar file holds (format, site, time, sweeps,
// fields). Reads metadata only: no field values are decoded.
#include "Commands.h"

#include <atmoglobe/volume/RadarReader.h>

#include <iostream>
#include <memory>
#include <string>

namespace atmoglobe::tools {

Command addInfoCommand(CLI::App& root) {
  struct Options {
    std::string file;
    bool json = false;
  };
  auto opts = std::make_shared<Options>();
  Command c;
  c.app = root.add_subcommand("info", "Describe a radar file (CfRadial, ODIM_H5, NEXRAD Level II): format, site, "
                                      "time, sweeps and fields");
  c.app->add_option("FILE", opts->file, "Radar file")->required();
  c.app->add_flag("--json", opts->json, "Print one JSON object instead of text");
  c.run = [opts] {
    volume::ReadOptions ro;
    ro.loadValues = false;  // metadata only: fast, no field array read
    auto vol = volume::readRadarVolume(opts->file, ro);
    if (!vol) {
      // Library messages start with the file name: "atmoglobe info: FILE: reason".
      return fail("info", vol.error());
    }
    std::cout << (opts->json ? volume::describeVolumeJson(*vol) + "\n" : volume::describeVolumeText(*vol));
    return 0;
  };
  return c;
}

}  // namespace atmoglobe::tools
