#pragma once
// A small GL-free scatter plot drawn straight into an RGBA8 image (for `atmoglobe bench`):
// axes with ticks and tick labels (stb_easy_font glyphs), a linear or logarithmic x axis,
// points, polylines and short text labels. Not a general plotting library: just enough to
// show a speed/accuracy trade as a PNG without a Python or gnuplot dependency.
#include <atmoglobe/globe/Image.h>

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace atmoglobe::engine {

struct PlotPoint {
  double x = 0.0;  ///< data units (x > 0 on a log axis; others are skipped)
  double y = 0.0;
  glm::u8vec4 color{0, 0, 0, 255};
  int radiusPx = 3;   ///< filled disc radius (pixels)
  bool ring = false;  ///< also draw a ring of radius radiusPx + 3 around it (highlight)
  std::string label;  ///< drawn right of the point when not empty
};

struct PlotLine {
  std::vector<glm::dvec2> points;  ///< data units, drawn in order
  glm::u8vec4 color{0, 0, 0, 255};
};

struct PlotLegendEntry {
  std::string text;
  glm::u8vec4 color{0, 0, 0, 255};
};

struct ScatterPlot {
  std::string title;
  std::string xLabel;
  std::string yLabel;
  bool logX = false;  ///< base-10 logarithmic x axis (ticks at 1, 2, 5 x 10^k)
  std::vector<PlotPoint> points;
  std::vector<PlotLine> lines;
  std::vector<PlotLegendEntry> legend;  ///< top-right box
};

/// Where data coordinates land in the image (pixels, origin top-left, y down), for tests.
struct PlotFrame {
  double xMin = 0.0, xMax = 1.0, yMin = 0.0, yMax = 1.0;  ///< data range of the axes
  int left = 0, top = 0, right = 0, bottom = 0;           ///< plot area, pixels (inclusive)
  bool logX = false;
  /// Pixel position of a data point (x > 0 on a log axis).
  glm::dvec2 toPixel(double x, double y) const;
};

/// The axes' data range and plot area for `plot` on a widthPx x heightPx image: data range =
/// the points' and lines' extent widened to "nice" tick values (log axis: whole 1-2-5 steps).
/// Precondition: widthPx >= 200, heightPx >= 150.
PlotFrame layoutPlot(const ScatterPlot& plot, int widthPx, int heightPx);

/// Draws `plot` on a white widthPx x heightPx image. Exact pixel placement: a point at data
/// (x, y) is centred on the pixel containing layoutPlot(...).toPixel(x, y).
globe::ImageRGBA8 drawScatterPlot(const ScatterPlot& plot, int widthPx, int heightPx);

/// Width in pixels of `text` drawn at `scale` (stb_easy_font metrics; scale 1 = ~6 px/char).
int plotTextWidthPx(const std::string& text, int scale);

}  // namespace atmoglobe::engine
