#pragma once
// User vector files (GeoJSON, ESRI shapefile, KML/KMZ, GeoPackage and the other formats of
// overlayDriverNames, read through GDAL/OGR) as
// geodetic polylines: line strings and polygon rings of every layer, multi-geometries and
// collections flattened, transformed from the layer's CRS to WGS84 longitude/latitude through
// OGR's coordinate transformation (traditional GIS axis order). Points are counted, not drawn.
// GL-free.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/map/GeoLines.h>

#include <cstddef>
#include <string>
#include <vector>

namespace atmoglobe::map {

struct VectorFileContents {
  std::vector<GeoPolyline> lines;  ///< line strings and polygon rings (closed: first point repeated)
  std::size_t features = 0;
  std::size_t lineStrings = 0;
  std::size_t rings = 0;
  std::size_t points = 0;             ///< point geometries (not drawn)
  std::vector<std::string> layerCrs;  ///< each layer's CRS name ("WGS 84", "(none: taken as WGS 84)")
};

/// The GDAL drivers overlays are read with (GDAL short names); files of other formats are refused
/// with their format named.
const std::vector<std::string>& overlayDriverNames();

/// Reads every layer of `path`. Errors name the file: not of a format of overlayDriverNames, no layer, a CRS
/// that cannot be transformed to WGS84, coordinates that come out non-finite or off the Earth,
/// or no line or polygon at all.
Result<VectorFileContents> readVectorFile(const std::string& path);

}  // namespace atmoglobe::map
