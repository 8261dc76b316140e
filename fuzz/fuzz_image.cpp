// Imagery tiles: image decoding (globe/Image.h decodeImageMemory: PNG, JPEG ... with a pixel limit).
#include "FuzzCommon.h"

#include <atmoglobe/globe/Image.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string label = "fuzz-tile";
  fuzz::checkError(globe::decodeImageMemory(data, size, label), label);
  return 0;
}
