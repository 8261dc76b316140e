// Rainbow 5 volume through the byte-buffer reader.
#include "FuzzCommon.h"

#include <atmoglobe/volume/RainbowReader.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string label = "fuzz.vol";
  const std::vector<unsigned char> bytes(data, data + size);
  volume::ReadOptions options;
  fuzz::checkError(volume::readRainbow5(label, bytes, options), label);
  options.loadValues = false;
  fuzz::checkError(volume::readRainbow5(label, bytes, options), label);
  return 0;
}
