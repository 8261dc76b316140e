// GRIB editions 1 and 2 through ecCodes (volume/src/grid/Grib*.cpp): describeGridFile and
// readGridVolume of the default variable, with the message index written to and read back from a
// scratch cache directory (so the cache's JSON is parsed too). The reader takes a path: the input
// is written to a scratch file first.
#include "FuzzCommon.h"

#include <atmoglobe/volume/GridReader.h>

#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  static const bool cacheSet = ::setenv("ATMOGLOBE_CACHE_DIR", (fuzz::scratchDir() / "cache").string().c_str(), 1) == 0;
  (void)cacheSet;
  const std::string path = fuzz::writeScratch("grid.grib", data, size);
  fuzz::checkError(volume::describeGridFile(path), path);
  fuzz::checkError(volume::readGridVolume(path), path);  // first open: index built and cached
  fuzz::checkError(volume::readGridVolume(path), path);  // second: index from the cache
  return 0;
}
