// Vector overlays through GDAL/OGR (map/VectorFile.h readVectorFile): the reader takes a path, so
// the input is written to a scratch file first, named .kml when it looks like KML (GDAL's KML
// drivers want the extension) and .geojson otherwise (GDAL picks the driver from the content).
#include "FuzzCommon.h"

#include <atmoglobe/map/VectorFile.h>

#include <cstring>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const bool kml = text.find("<kml") != std::string_view::npos || text.find("<Placemark") != std::string_view::npos;
  const std::string path = fuzz::writeScratch(kml ? "overlay.kml" : "overlay.geojson", data, size);
  fuzz::checkError(map::readVectorFile(path), path);
  return 0;
}
