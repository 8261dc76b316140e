// Sigmet/IRIS RAW through the byte-buffer reader.
#include "FuzzCommon.h"

#include <atmoglobe/volume/SigmetReader.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string label = "fuzz.raw";
  const std::vector<unsigned char> bytes(data, data + size);
  volume::ReadOptions options;
  fuzz::checkError(volume::readSigmetIris(label, bytes, options), label);
  options.loadValues = false;
  fuzz::checkError(volume::readSigmetIris(label, bytes, options), label);
  return 0;
}
