// GR/WCT .pal colour tables (volume/ColorTable.h parsePalText), and the parsed table mapping values.
#include "FuzzCommon.h"

#include <atmoglobe/volume/ColorTable.h>

#include <limits>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string label = "fuzz.pal";
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto table = volume::parsePalText(text, label);
  fuzz::checkError(table, label);
  if (!table) return 0;
  for (float v : {-1e30f, -30.0f, 0.0f, 12.5f, 45.0f, 80.0f, 1e30f, std::numeric_limits<float>::quiet_NaN(),
                  std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()}) {
    (void)table->map(v);
  }
  return 0;
}
