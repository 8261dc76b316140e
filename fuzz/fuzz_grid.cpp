// Forecast grids (CF netCDF, WRF): describeGridFile and readGridVolume of the default variable.
// The grid reader takes a path: the input is written to a scratch file first.
#include "FuzzCommon.h"

#include <atmoglobe/volume/GridReader.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string path = fuzz::writeScratch("grid.nc", data, size);
  fuzz::checkError(volume::describeGridFile(path), path);
  fuzz::checkError(volume::readGridVolume(path), path);
  return 0;
}
