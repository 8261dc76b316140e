#pragma once
// A slice (volume/Slice.h) as a picture a forecaster reads: the raster coloured through the same
// colour table as the 3-D view, axes with ticks and labels (CAPPI: longitude and latitude;
// cross-section: distance along the path and height, in km), the path's points marked, a colour
// key with the field's units, a title (site or grid, field, height or path, valid time in UTC),
// "no echo" and "no data" told apart (white; grey with hatching), and a red SYNTHETIC DATA mark
// when the data are synthetic. GL-free; text through TextRaster (DejaVu Sans, with a halo).
//
// Colours: an Echo value takes the table's RGB (its alpha, the 3-D view's opacity, is not used:
// a slice is opaque); values the table leaves transparent (below its first stop) are drawn as
// "no echo", and the key says so.
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/TextRaster.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/map/Contours.h>
#include <atmoglobe/map/GeoLines.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/Slice.h>
#include <atmoglobe/volume/SliceSource.h>

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace atmoglobe::engine {

/// Marks drawn on a CAPPI (a radar site, a city): a cross and a label.
struct SlicePlotMarker {
  double latDeg = 0.0, lonDeg = 0.0;
  std::string label;
};

/// Lines drawn over a CAPPI's raster, clipped to the plot area (coastlines, borders, overlays):
/// longitude/latitude polylines, antialiased, `widthPx` wide.
struct SlicePlotLines {
  std::vector<map::GeoPolyline> lines;
  glm::u8vec4 color{0, 0, 0, 255};
  double widthPx = 1.0;
};

/// Contour lines over a CAPPI's raster (map/Contours.h), drawn after the map lines; each line
/// long enough on the plot (100 px) carries its value at its middle, labels kept apart.
struct SlicePlotContours {
  std::vector<map::ContourLine> lines;
  glm::u8vec4 color{0, 0, 0, 255};
  double widthPx = 1.4;
  bool labelled = true;  ///< false: lines only (spaghetti: one set per ensemble member)
};

struct SlicePlotOptions {
  int widthPx = 1000, heightPx = 640;  ///< the whole image
  std::string title;                   ///< line 1 (what and where)
  std::string subtitle;                ///< line 2 (valid time, path points)
  std::string units;                   ///< the field's units (colour key)
  bool synthetic = false;              ///< draws the SYNTHETIC DATA mark
  volume::ColorTable colors;
  std::vector<SlicePlotMarker> markers;     ///< CAPPI only
  std::vector<SlicePlotLines> mapLines;     ///< CAPPI only (addSliceMapLines); drawn in order
  std::vector<SlicePlotContours> contours;  ///< CAPPI only; drawn after the map lines
  glm::u8vec4 noEchoColor{255, 255, 255, 255};
  glm::u8vec4 noDataColor{218, 218, 218, 255};
  glm::u8vec4 noDataHatchColor{182, 182, 182, 255};
};

/// The options a slice of `source` on `geometry` is drawn with: title (name, field, CAPPI height
/// or path letters and length), subtitle (the time: a radar's volume start or a grid's valid time,
/// in UTC; the path's points; approximate grid heights), the field's units, the SYNTHETIC mark,
/// `transfer`'s colour table and, on a radar CAPPI, the site.
SlicePlotOptions slicePlotOptionsFor(const volume::SliceSource& source, const volume::SliceGeometry& geometry,
                                     const volume::TransferFunction& transfer, int widthPx, int heightPx);

/// "2020-05-01T21:00:00Z" -> "2020-05-01 21:00:00 UTC" (other text unchanged; "" -> "time unknown").
std::string utcLabel(const std::string& iso8601);

/// Where the raster goes in the image (pixels, inclusive-exclusive: [left, right) x [top,
/// bottom)). A CAPPI's area keeps the box's shape at its middle latitude (a degree of longitude
/// is cos(latitude) of a degree of latitude), centred in the room left by the margins.
struct SlicePlotLayout {
  int left = 0, top = 0, right = 0, bottom = 0;
  int width() const { return right - left; }
  int height() const { return bottom - top; }
};

/// The plot area for a slice of this kind and axes on a widthPx x heightPx image. Sample the
/// slice at width() x height() for one raster pixel per image pixel. Error: an image too small
/// for the margins (below 320 x 240) or a degenerate box.
Result<SlicePlotLayout> layoutSlicePlot(const volume::SliceGeometry& geometry, int widthPx, int heightPx);

/// A CAPPI's map: GSHHG coastlines (dark), national borders (dark red) and state/province lines
/// (grey) from `gshhgDir` at the resolution the plot's scale asks for (map/MapLod.h
/// gshhgResolutionForScale: metres per pixel across the box at its middle latitude), as on the
/// globe (docs/map-context.md). A cross-section gets none. Errors name the file;
/// `resolutionOut` (if given) gets the letter of the GSHHG resolution read.
Status addSliceCoastlines(SlicePlotOptions& options, const volume::SliceGeometry& geometry,
                          const SlicePlotLayout& layout, const std::string& gshhgDir, char* resolutionOut = nullptr);
/// The lines of each GDAL/OGR vector file (map/VectorFile.h) over a CAPPI (blue). Errors name the file.
Status addSliceOverlays(SlicePlotOptions& options, const std::vector<std::string>& overlayPaths);

/// A CAPPI's natural image size for a given width: the box's shape at its middle latitude plus
/// the margins (height clamped to 240..4096).
int cappiImageHeightFor(const volume::LatLonBox& box, int widthPx);

/// Draws the plot. The raster must have been sampled on `geometry` (any size: each plot pixel
/// takes the raster pixel under its centre). Errors: no font (Font::dejaVuSans's), layout's.
Result<globe::ImageRGBA8> drawSlicePlot(const volume::SliceRaster& raster, const volume::SliceGeometry& geometry,
                                        const SlicePlotOptions& options);

/// The RGBA colour of one slice value as the plot draws it (echo: the table's RGB, opaque; no
/// echo and values below the table: noEchoColor; no data: noDataColor). The on-globe slice uses
/// the same rule with no echo and no data transparent.
glm::u8vec4 slicePixelColor(const volume::ColorTable& colors, float value, glm::u8vec4 noEchoColor,
                            glm::u8vec4 noDataColor);

/// Latitude / longitude labels: "35.5°N", "97°W" (decimals as the step needs).
std::string latitudeLabel(double latDeg, int decimals);
std::string longitudeLabel(double lonDeg, int decimals);

}  // namespace atmoglobe::engine
