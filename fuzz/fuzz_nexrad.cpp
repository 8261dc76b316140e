// NEXRAD Level II in every form: message 31 and legacy message-1 archives through the byte-buffer
// reader, and real-time chunk sets (the input split into files at "\nCHUNK\n") through
// readNexradChunks. Legacy files find their site in a small synthetic site list.
#include "FuzzCommon.h"

#include <atmoglobe/volume/NexradReader.h>

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  static const std::string sites = [] {
    const std::string csv = "id,lat,lon,elev\nKLBB,33.654,-101.814,993\nKTLX,35.333,-97.278,370\n";
    return fuzz::writeScratch("sites.csv", reinterpret_cast<const std::uint8_t*>(csv.data()), csv.size());
  }();
  volume::ReadOptions options;
  options.nexradSiteList = sites;
  const std::string label = "fuzz.ar2v";
  const std::vector<unsigned char> bytes(data, data + size);
  fuzz::checkError(volume::readNexradLevel2(label, bytes, options), label);
  options.loadValues = false;
  fuzz::checkError(volume::readNexradLevel2(label, bytes, options), label);

  // Chunk set: at most 4 pieces.
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  const std::string_view sep = "\nCHUNK\n";
  if (all.find(sep) == std::string_view::npos) return 0;
  std::vector<std::string> paths;
  std::size_t start = 0;
  while (paths.size() < 4) {
    const std::size_t at = all.find(sep, start);
    const std::size_t end = at == std::string_view::npos || paths.size() == 3 ? all.size() : at;
    paths.push_back(fuzz::writeScratch("chunk-" + std::to_string(paths.size() + 1), data + start, end - start));
    if (end == all.size()) break;
    start = end + sep.size();
  }
  options.loadValues = true;
  fuzz::checkError(volume::readNexradChunks(paths, "fuzz-chunks", options), "fuzz-chunks", fuzz::scratchDir().string());
  return 0;
}
