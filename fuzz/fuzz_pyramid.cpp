// Imagery pyramid metadata (globe/ImageryPyramid.h readPyramidInfo of DIR/pyramid.json).
#include "FuzzCommon.h"

#include <atmoglobe/globe/ImageryPyramid.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string path = fuzz::writeScratch("pyramid.json", data, size);
  fuzz::checkError(globe::readPyramidInfo(fuzz::scratchDir().string()), "pyramid.json");
  (void)path;
  return 0;
}
