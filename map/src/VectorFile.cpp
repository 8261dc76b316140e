#include <atmoglobe/map/VectorFile.h>

#include "GdalLibrary.h"

#include <atmoglobe/io/NetcdfLock.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>

namespace atmoglobe::map {

namespace {

struct DatasetCloser {
  void operator()(void* ds) const { detail::gdal().GDALClose(ds); }
};
struct SrsDeleter {
  void operator()(void* s) const { detail::gdal().OSRDestroySpatialReference(static_cast<OGRSpatialReferenceH>(s)); }
};
struct TransformDeleter {
  void operator()(void* t) const {
    detail::gdal().OCTDestroyCoordinateTransformation(static_cast<OGRCoordinateTransformationH>(t));
  }
};

// GDAL's errors while the layers are read: kept (the first failure), not printed to stderr.
struct GdalErrors {
  std::string firstFailure;
  static void CPL_STDCALL handler(CPLErr type, CPLErrorNum, const char* message) {
    auto* self = static_cast<GdalErrors*>(detail::gdal().CPLGetErrorHandlerUserData());
    if (self && type >= CE_Failure && self->firstFailure.empty())
      self->firstFailure = message ? message : "(no message)";
  }
};
bool mentionsCrs(const std::string& message) {
  for (const char* key : {"proj_create", "CRS", "crs", "SRS", "coordinate system"})
    if (message.find(key) != std::string::npos) return true;
  return false;
}
struct ErrorHandlerScope {
  explicit ErrorHandlerScope(GdalErrors* e) { detail::gdal().CPLPushErrorHandlerEx(GdalErrors::handler, e); }
  ~ErrorHandlerScope() { detail::gdal().CPLPopErrorHandler(); }
  ErrorHandlerScope(const ErrorHandlerScope&) = delete;
  ErrorHandlerScope& operator=(const ErrorHandlerScope&) = delete;
};

// Appends the lines of `g` (line strings, polygon rings; recursing into collections).
Status collect(OGRGeometryH g, OGRCoordinateTransformationH transform, const std::string& path,
               VectorFileContents& out) {
  if (!g) return Ok{};
  const OGRwkbGeometryType type = detail::gdal().OGR_GT_Flatten(detail::gdal().OGR_G_GetGeometryType(g));
  switch (type) {
    case wkbPoint:
    case wkbMultiPoint:
      out.points += type == wkbPoint ? 1u : static_cast<std::size_t>(detail::gdal().OGR_G_GetGeometryCount(g));
      return Ok{};
    case wkbLineString:
    case wkbLinearRing: {
      const int n = detail::gdal().OGR_G_GetPointCount(g);
      if (n < 2) return Ok{};
      std::vector<double> x(static_cast<std::size_t>(n)), y(x.size());
      for (int i = 0; i < n; ++i) {
        x[static_cast<std::size_t>(i)] = detail::gdal().OGR_G_GetX(g, i);
        y[static_cast<std::size_t>(i)] = detail::gdal().OGR_G_GetY(g, i);
      }
      if (transform) {
        std::vector<int> ok(x.size(), 0);
        if (!detail::gdal().OCTTransformEx(transform, n, x.data(), y.data(), nullptr, ok.data()))
          return makeError(path + ": a geometry could not be transformed to WGS84");
        for (int v : ok)
          if (!v) return makeError(path + ": a point could not be transformed to WGS84");
      }
      GeoPolyline line;
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || std::abs(y[i]) > 90.0 + 1e-9 || std::abs(x[i]) > 540.0)
          return makeError(path + ": coordinate (" + std::to_string(x[i]) + ", " + std::to_string(y[i]) +
                           ") is not a longitude/latitude on the Earth (wrong CRS or a broken file)");
        const double lon = x[i] >= 180.0 || x[i] < -180.0 ? std::remainder(x[i], 360.0) : x[i];
        line.lonLatDeg.emplace_back(lon, std::clamp(y[i], -90.0, 90.0));
      }
      out.lines.push_back(std::move(line));
      ++(type == wkbLineString ? out.lineStrings : out.rings);
      return Ok{};
    }
    case wkbPolygon:
      for (int i = 0; i < detail::gdal().OGR_G_GetGeometryCount(g); ++i) {
        OGRGeometryH ring = detail::gdal().OGR_G_GetGeometryRef(g, i);
        // Rings report as line strings through the C API: count them as rings.
        const std::size_t before = out.lineStrings;
        if (auto st = collect(ring, transform, path, out); !st) return st;
        if (out.lineStrings > before) {
          out.lineStrings = before;
          ++out.rings;
        }
      }
      return Ok{};
    default: {
      const int n = detail::gdal().OGR_G_GetGeometryCount(g);
      if (n > 0) {
        for (int i = 0; i < n; ++i)
          if (auto st = collect(detail::gdal().OGR_G_GetGeometryRef(g, i), transform, path, out); !st) return st;
        return Ok{};
      }
      // Curves and other types: linearised.
      if (detail::gdal().OGR_GT_IsCurve(type) || detail::gdal().OGR_GT_IsSurface(type)) {
        OGRGeometryH linear = detail::gdal().OGR_G_GetLinearGeometry(g, 0.0, nullptr);
        Status st = collect(linear, transform, path, out);
        detail::gdal().OGR_G_DestroyGeometry(linear);
        return st;
      }
      return Ok{};
    }
  }
}

}  // namespace

const std::vector<std::string>& overlayDriverNames() {
  // The vector formats map overlays come in. Not GDAL's ~80 other vector drivers: their parsers
  // (DXF, AVC E00, OSM, GML with schema and xlink resolution, VRT naming other files or URLs,
  // network services) are not what an overlay needs, and each one is more surface for a damaged
  // or hostile file to hang or crash the process.
  static const std::vector<std::string> names = {"GeoJSON",        "GeoJSONSeq", "ESRIJSON",    "TopoJSON",
                                                 "ESRI Shapefile", "KML",        "LIBKML",      "GPKG",
                                                 "FlatGeobuf",     "GPX",        "OpenFileGDB", "MapInfo File"};
  return names;
}

Result<VectorFileContents> readVectorFile(const std::string& path) {
  if (auto loaded = detail::loadGdal(); !loaded) return makeError(path + ": " + loaded.error());
  if (!std::filesystem::exists(path)) return makeError(path + ": no such file");
  // GDAL's netCDF and HDF5 drivers (an overlay in a .nc or .h5 file) call netCDF-C and HDF5: the
  // whole read, the dataset's close included, holds the one library lock (io/NetcdfLock.h).
  const io::NetcdfLock lock;
  GdalErrors openErrors;
  std::unique_ptr<void, DatasetCloser> ds;
  std::vector<const char*> allowed;
  for (const std::string& name : overlayDriverNames()) allowed.push_back(name.c_str());
  allowed.push_back(nullptr);
  {
    ErrorHandlerScope quietOpen(&openErrors);
    ds.reset(
        detail::gdal().GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, allowed.data(), nullptr, nullptr));
  }
  const std::string& gdalMessage = openErrors.firstFailure;
  if (!ds) {
    // Another format GDAL knows (identified only, never opened): named, so the user can convert it.
    std::string other;
    {
      GdalErrors identifyErrors;
      ErrorHandlerScope quietIdentify(&identifyErrors);
      if (GDALDriverH d = detail::gdal().GDALIdentifyDriverEx(path.c_str(), GDAL_OF_VECTOR, nullptr, nullptr))
        other = std::string(detail::gdal().GDALGetDriverLongName(d)) + " (GDAL driver " +
                detail::gdal().GDALGetDriverShortName(d) + ")";
    }
    std::string formats;
    for (const std::string& name : overlayDriverNames()) formats.append(formats.empty() ? "" : ", ").append(name);
    if (!other.empty())
      return makeError(path + ": format " + other + ", which overlays do not read; they read " + formats +
                       " (convert it: ogr2ogr -f GeoJSON out.geojson " + path + ")");
    return makeError(path + ": not a vector file of a format overlays read (" + formats + ")" +
                     (gdalMessage.empty() ? std::string() : ": " + gdalMessage));
  }
  // A CRS that PROJ cannot resolve (an unknown EPSG code): GeoJSON's driver then falls back to
  // WGS 84 and the coordinates would be taken as longitude/latitude whatever they are.
  if (mentionsCrs(gdalMessage))
    return makeError(path + ": its CRS cannot be read (GDAL: " + gdalMessage +
                     "); the coordinates would be taken as WGS 84 longitude/latitude");
  const int layers = detail::gdal().GDALDatasetGetLayerCount(ds.get());
  if (layers <= 0) return makeError(path + ": no vector layer in the file");
  VectorFileContents out;
  std::unique_ptr<void, SrsDeleter> wgs84(detail::gdal().OSRNewSpatialReference(nullptr));
  detail::gdal().OSRImportFromEPSG(static_cast<OGRSpatialReferenceH>(wgs84.get()), 4326);
  detail::gdal().OSRSetAxisMappingStrategy(static_cast<OGRSpatialReferenceH>(wgs84.get()), OAMS_TRADITIONAL_GIS_ORDER);
  // A feature GDAL cannot read (a truncated or corrupt file) ends or skips the layer with an error
  // that GDAL would print: it is kept and the file refused instead of read in part.
  GdalErrors gdalErrors;
  ErrorHandlerScope quiet(&gdalErrors);
  for (int l = 0; l < layers; ++l) {
    OGRLayerH layer = detail::gdal().GDALDatasetGetLayer(ds.get(), l);
    OGRSpatialReferenceH srs = detail::gdal().OGR_L_GetSpatialRef(layer);
    if (mentionsCrs(gdalErrors.firstFailure))
      return makeError(path + ": layer " + detail::gdal().OGR_L_GetName(layer) + ": its CRS cannot be read (GDAL: " +
                       gdalErrors.firstFailure + "); the coordinates would be taken as WGS 84 longitude/latitude");
    std::unique_ptr<void, TransformDeleter> transform;
    if (srs) {
      out.layerCrs.push_back(detail::gdal().OSRGetName(srs) ? detail::gdal().OSRGetName(srs) : "(unnamed)");
      std::unique_ptr<void, SrsDeleter> source(detail::gdal().OSRClone(srs));
      detail::gdal().OSRSetAxisMappingStrategy(static_cast<OGRSpatialReferenceH>(source.get()),
                                               OAMS_TRADITIONAL_GIS_ORDER);
      detail::gdal().CPLPushErrorHandler(detail::gdal().CPLQuietErrorHandler);
      transform.reset(detail::gdal().OCTNewCoordinateTransformation(static_cast<OGRSpatialReferenceH>(source.get()),
                                                                    static_cast<OGRSpatialReferenceH>(wgs84.get())));
      const std::string msg = detail::gdal().CPLGetLastErrorMsg();
      detail::gdal().CPLPopErrorHandler();
      if (!transform)
        return makeError(path + ": layer " + detail::gdal().OGR_L_GetName(layer) + ": its CRS (" + out.layerCrs.back() +
                         ") cannot be transformed to WGS84" + (msg.empty() ? std::string() : ": " + msg));
    } else {
      out.layerCrs.push_back("(none: taken as WGS 84 longitude/latitude)");
    }
    detail::gdal().OGR_L_ResetReading(layer);
    while (OGRFeatureH f = detail::gdal().OGR_L_GetNextFeature(layer)) {
      ++out.features;
      Status st = collect(detail::gdal().OGR_F_GetGeometryRef(f),
                          static_cast<OGRCoordinateTransformationH>(transform.get()), path, out);
      detail::gdal().OGR_F_Destroy(f);
      if (!st) return st.forwardError();
      if (!gdalErrors.firstFailure.empty()) break;
    }
    if (!gdalErrors.firstFailure.empty())
      return makeError(path + ": layer " + detail::gdal().OGR_L_GetName(layer) + ": GDAL could not read feature " +
                       std::to_string(out.features + 1) +
                       " (the file is corrupt or truncated): " + gdalErrors.firstFailure);
  }
  if (out.lines.empty())
    return makeError(path + ": no line or polygon in " + std::to_string(out.features) + " features (" +
                     std::to_string(out.points) + " points, which are not drawn)");
  return out;
}

}  // namespace atmoglobe::map
