// Station lists, CSV or JSON (volume/StationList.h parseStationList).
#include "FuzzCommon.h"

#include <atmoglobe/volume/StationList.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string label = "fuzz-stations";
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::checkError(volume::parseStationList(text, label), label);
  return 0;
}
