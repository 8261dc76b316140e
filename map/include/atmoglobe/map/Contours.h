#pragma once
// Contour lines of a field sampled on a latitude/longitude raster, through GDAL's contour
// generator (GDALContourGenerateEx: marching squares between pixel centres, lines joined across
// cells), as geodetic polylines for the slice plots and the globe.
//
// The raster: `columns` x `rows` values, row 0 at the north, value (i, j) at the centre of its
// pixel, longitude westDeg + (i + 0.5) dxDeg, latitude northDeg - (j + 0.5) dyDeg (the slice
// rasters' convention, volume/Slice.h). NaN and infinite values are missing: no line crosses a
// cell with a missing corner.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/map/GeoLines.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::map {

struct ContourRaster {
  const float* values = nullptr;
  int columns = 0, rows = 0;
  double westDeg = 0.0, northDeg = 0.0;  ///< the raster's outer edges
  double dxDeg = 1.0, dyDeg = 1.0;       ///< a pixel's size (both > 0)
};

/// Which values to draw: a list, or every multiple of intervalValue (from baseValue) within the
/// field's range.
struct ContourLevels {
  std::vector<double> values;
  std::optional<double> interval;
  double base = 0.0;
};

/// Parses "--contour-interval"-style text: "5" (an interval) or "5400,5500,5600" (values, two or
/// more, or one value followed by a comma: "0,"). Errors name the text.
Result<ContourLevels> parseContourLevels(const std::string& intervalText, const std::string& valuesText);

struct ContourLine {
  double value = 0.0;
  GeoPolyline line;  ///< longitude, latitude (deg)
};

/// The contour lines of `raster` at `levels`. Errors: a bad raster or levels (interval not > 0
/// and finite), more than 1000 levels within the range, GDAL's error.
Result<std::vector<ContourLine>> contourLines(const ContourRaster& raster, const ContourLevels& levels);

/// Contour lines of values on any structured grid (`columns` x `rows`, row-major, NaN missing),
/// found in the grid's index space (GDAL's generator over the values as they lie) and placed by
/// `lonLatAt(i, j)`: the longitude and latitude (deg) of the fractional column i and row j (an
/// integer is a grid point). A line point between two grid points is where the value crosses
/// the level linearly between them, mapped through the grid's geometry, so lines of a projected
/// or curvilinear grid follow its cells. Errors: as contourLines.
Result<std::vector<ContourLine>> contourLinesOnGrid(const float* values, int columns, int rows,
                                                    const ContourLevels& levels,
                                                    const std::function<glm::dvec2(double i, double j)>& lonLatAt);

/// A contour value as a label: up to 6 significant digits, no trailing zeros ("5640", "-2.5").
std::string contourLabel(double value);

}  // namespace atmoglobe::map
