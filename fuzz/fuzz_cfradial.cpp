// CfRadial (netCDF classic or netCDF-4/HDF5) through netCDF-C's in-memory open.
#include "FuzzCommon.h"

#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/CfRadialReader.h>

#include <memory>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string label = "fuzz.nc";
  auto bytes = std::make_shared<std::vector<unsigned char>>(data, data + size);
  auto file = io::NetcdfFile::openMemory(label, bytes);
  fuzz::checkError(file, label);
  if (!file) return 0;
  volume::ReadOptions options;
  fuzz::checkError(volume::readCfRadial(*file, options), label);
  options.loadValues = false;
  fuzz::checkError(volume::readCfRadial(*file, options), label);
  return 0;
}
