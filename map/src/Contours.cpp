// Contour lines through GDAL (Contours.h).
#include <atmoglobe/map/Contours.h>

#include "GdalLibrary.h"

#include <atmoglobe/globe/Text.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>

namespace atmoglobe::map {

namespace {

constexpr std::size_t kMaxLevels = 1000;
constexpr double kMissing = -1.0e30;  // GDAL's NODATA for the raster handed over (NaN is not portable)

struct DatasetCloser {
  void operator()(void* ds) const {
    if (ds) detail::gdal().GDALClose(static_cast<GDALDatasetH>(ds));
  }
};

std::optional<double> parseNumber(std::string text) {
  text.erase(std::remove(text.begin(), text.end(), ' '), text.end());
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

Result<ContourLevels> parseContourLevels(const std::string& intervalText, const std::string& valuesText) {
  ContourLevels levels;
  if (!intervalText.empty() && !valuesText.empty())
    return makeError("contours: give an interval or a list of values, not both");
  if (!intervalText.empty()) {
    const auto v = parseNumber(intervalText);
    if (!v || !(*v > 0.0)) return makeError("contour interval '" + intervalText + "': expected a number > 0");
    levels.interval = *v;
    return levels;
  }
  std::stringstream list(valuesText);
  std::string item;
  while (std::getline(list, item, ',')) {
    if (item.empty()) continue;
    const auto v = parseNumber(item);
    if (!v) return makeError("contour values '" + valuesText + "': '" + item + "' is not a finite number");
    levels.values.push_back(*v);
  }
  if (levels.values.empty())
    return makeError("contour values '" + valuesText + "': expected numbers separated by commas, e.g. 5400,5520");
  std::sort(levels.values.begin(), levels.values.end());
  levels.values.erase(std::unique(levels.values.begin(), levels.values.end()), levels.values.end());
  return levels;
}

std::string contourLabel(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

Result<std::vector<ContourLine>> contourLines(const ContourRaster& r, const ContourLevels& levels) {
  if (!r.values || r.columns < 2 || r.rows < 2) return makeError("contours: the raster needs at least 2 x 2 values");
  if (!(r.dxDeg > 0.0) || !(r.dyDeg > 0.0) || !std::isfinite(r.westDeg) || !std::isfinite(r.northDeg))
    return makeError("contours: the raster's pixel size must be positive and its corner finite");
  if (levels.interval && !(*levels.interval > 0.0 && std::isfinite(*levels.interval)))
    return makeError("contours: the interval must be a finite number > 0");
  if (!levels.interval && levels.values.empty()) return makeError("contours: no values and no interval given");
  // The values as GDAL takes them, and the range (to bound the number of levels).
  const std::size_t n = static_cast<std::size_t>(r.columns) * static_cast<std::size_t>(r.rows);
  std::vector<float> values(r.values, r.values + n);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (float& v : values) {
    if (!std::isfinite(v)) {
      v = static_cast<float>(kMissing);
      continue;
    }
    lo = std::min(lo, static_cast<double>(v));
    hi = std::max(hi, static_cast<double>(v));
  }
  std::vector<ContourLine> out;
  if (!(lo <= hi)) return out;  // nothing to contour
  std::vector<double> fixed = levels.values;
  if (levels.interval) {
    const double first = std::ceil((lo - levels.base) / *levels.interval);
    const double last = std::floor((hi - levels.base) / *levels.interval);
    if (last - first + 1.0 > static_cast<double>(kMaxLevels))
      return makeError("contours: an interval of " + numberText(*levels.interval) + " gives " +
                       numberText(last - first + 1.0) + " lines over the field's range " + numberText(lo) + " .. " +
                       numberText(hi) + "; at most " + std::to_string(kMaxLevels));
    for (double k = first; k <= last; k += 1.0) fixed.push_back(levels.base + k * *levels.interval);
  }
  if (fixed.size() > kMaxLevels)
    return makeError("contours: " + std::to_string(fixed.size()) + " values; at most " + std::to_string(kMaxLevels));
  if (fixed.empty()) return out;

  if (auto loaded = detail::loadGdal(); !loaded) return makeError("contours: " + loaded.error());
  GDALDriverH memRaster = detail::gdal().GDALGetDriverByName("MEM");
  GDALDriverH memVector = detail::gdal().GDALGetDriverByName("Memory");
  if (!memRaster || !memVector) return makeError("contours: GDAL's MEM and Memory drivers are not available");
  std::unique_ptr<void, DatasetCloser> raster(
      detail::gdal().GDALCreate(memRaster, "", r.columns, r.rows, 1, GDT_Float32, nullptr));
  if (!raster) return makeError("contours: GDAL could not make a raster of " + std::to_string(n) + " values");
  double transform[6] = {r.westDeg, r.dxDeg, 0.0, r.northDeg, 0.0, -r.dyDeg};
  detail::gdal().GDALSetGeoTransform(raster.get(), transform);
  GDALRasterBandH band = detail::gdal().GDALGetRasterBand(raster.get(), 1);
  if (detail::gdal().GDALRasterIO(band, GF_Write, 0, 0, r.columns, r.rows, values.data(), r.columns, r.rows,
                                  GDT_Float32, 0, 0) != CE_None)
    return makeError(std::string("contours: GDAL: ") + detail::gdal().CPLGetLastErrorMsg());
  detail::gdal().GDALSetRasterNoDataValue(band, kMissing);
  std::unique_ptr<void, DatasetCloser> vector(detail::gdal().GDALCreate(memVector, "", 0, 0, 0, GDT_Unknown, nullptr));
  if (!vector) return makeError("contours: GDAL could not make a vector dataset");
  OGRLayerH layer = detail::gdal().GDALDatasetCreateLayer(vector.get(), "contours", nullptr, wkbLineString, nullptr);
  OGRFieldDefnH field = detail::gdal().OGR_Fld_Create("value", OFTReal);
  detail::gdal().OGR_L_CreateField(layer, field, TRUE);
  detail::gdal().OGR_Fld_Destroy(field);

  std::string list = "FIXED_LEVELS=";
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    char v[40];
    std::snprintf(v, sizeof v, "%.17g", fixed[i]);
    if (i) list.push_back(',');
    list.append(v);
  }
  char nodata[40];
  std::snprintf(nodata, sizeof nodata, "NODATA=%.17g", kMissing);
  const char* options[] = {list.c_str(), nodata, "ELEV_FIELD=0", nullptr};
  if (detail::gdal().GDALContourGenerateEx(band, layer, const_cast<char**>(options), nullptr, nullptr) != CE_None)
    return makeError(std::string("contours: GDAL: ") + detail::gdal().CPLGetLastErrorMsg());

  detail::gdal().OGR_L_ResetReading(layer);
  while (OGRFeatureH feature = detail::gdal().OGR_L_GetNextFeature(layer)) {
    ContourLine line;
    line.value = detail::gdal().OGR_F_GetFieldAsDouble(feature, 0);
    OGRGeometryH g = detail::gdal().OGR_F_GetGeometryRef(feature);
    const int points = g ? detail::gdal().OGR_G_GetPointCount(g) : 0;
    for (int i = 0; i < points; ++i)
      line.line.lonLatDeg.emplace_back(detail::gdal().OGR_G_GetX(g, i), detail::gdal().OGR_G_GetY(g, i));
    detail::gdal().OGR_F_Destroy(feature);
    if (line.line.lonLatDeg.size() >= 2) out.push_back(std::move(line));
  }
  return out;
}

Result<std::vector<ContourLine>> contourLinesOnGrid(const float* values, int columns, int rows,
                                                    const ContourLevels& levels,
                                                    const std::function<glm::dvec2(double i, double j)>& lonLatAt) {
  // The index space as a raster of unit pixels whose centres are (i, -j): longitude i, latitude -j.
  ContourRaster r;
  r.values = values;
  r.columns = columns;
  r.rows = rows;
  r.westDeg = -0.5;
  r.northDeg = 0.5;
  r.dxDeg = r.dyDeg = 1.0;
  auto lines = contourLines(r, levels);
  if (!lines) return lines.forwardError();
  for (ContourLine& line : *lines)
    for (glm::dvec2& p : line.line.lonLatDeg) p = lonLatAt(p.x, -p.y);
  return lines;
}

}  // namespace atmoglobe::map
