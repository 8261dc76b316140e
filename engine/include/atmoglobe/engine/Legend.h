#pragma once
// What every rendered picture carries: a colour key per volume with the field's
// units, a title (site or grid, field, elevation or height, valid time in UTC), a scale bar,
// and the SYNTHETIC mark where the data are synthetic. GL-free: drawn into an RGBA8 image
// with TextRaster (DejaVu Sans, with a halo so it reads over imagery and data). The colour key
// is the one the slice plots draw (drawColorKey), so a key means the same everywhere.
#include <atmoglobe/engine/TextRaster.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/ColorTable.h>

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace atmoglobe::engine {

// --- small raster helpers shared by the plots (straight-alpha "over", clipped) ---
void fillRect(globe::ImageRGBA8& img, int x0, int y0, int x1, int y1, glm::u8vec4 c);
void hLine(globe::ImageRGBA8& img, int x0, int x1, int y, glm::u8vec4 c);
void vLine(globe::ImageRGBA8& img, int x, int y0, int y1, glm::u8vec4 c);
/// A one-pixel frame just outside [x0, x1) x [y0, y1).
void frame(globe::ImageRGBA8& img, int x0, int y0, int x1, int y1, glm::u8vec4 c);
/// Decimals that show `step` exactly (up to 4).
int decimalsFor(double step);
/// `v` with `decimals` decimals ("-0" printed as "0").
std::string fixed(double v, int decimals);
/// "Nice" tick values (1, 2, 2.5 or 5 x 10^k apart) inside [lo, hi], about `target` of them.
std::vector<double> niceTicks(double lo, double hi, int target);

/// A vertical colour key in [x0, x1) x [y0, y1): the table from its first to its last value
/// (a stepped table one band more), highest on top, ticks and labels right of it, the units
/// above it. Text in `tickStyle`/`unitsStyle`.
void drawColorKey(globe::ImageRGBA8& img, const Font& font, const volume::ColorTable& colors, const std::string& units,
                  int x0, int y0, int x1, int y1, const TextStyle& tickStyle, const TextStyle& unitsStyle);

/// One volume's entry in a frame's legend.
struct LegendKey {
  std::string title;  ///< "KTLX DBZ", "synthetic_grid.nc /dbz"
  std::string units;
  volume::ColorTable colors;
};

/// What a rendered frame is annotated with.
struct FrameLegend {
  std::string title;                   ///< line 1: what (sites / grids, fields)
  std::vector<std::string> subtitles;  ///< further lines: valid times in UTC, heights
  std::vector<LegendKey> keys;         ///< one colour key per volume layer, right side
  double metersPerPixel = 0.0;         ///< at the image centre; 0: no scale bar
  bool synthetic = false;              ///< draws SYNTHETIC DATA
};

/// The keys with layers of the same table and units merged into one (titles joined by ", ").
std::vector<LegendKey> mergeLegendKeys(const std::vector<LegendKey>& keys);

/// The value range a key shows (field units): the table's first to last value (a stepped table
/// one band more), low first.
glm::dvec2 colorKeyRange(const volume::ColorTable& colors);

/// The scale bar of an image `widthPx` wide at `metersPerPixel` (at its centre): a round length
/// (1, 2, 5 x 10^k m) of at most a fifth of the width, its length in pixels and its label
/// ("20 km", "500 m"). meters 0: none (metersPerPixel not positive and finite). The PNG legend and
/// the viewer draw this same bar.
struct ScaleBar {
  double meters = 0.0;
  int lengthPx = 0;
  std::string label;
};
ScaleBar scaleBarFor(double metersPerPixel, int widthPx);

/// Draws `legend` over `image`: title and subtitles top left, keys along the right edge (side
/// by side when several), the scale bar bottom left (a round length of about a fifth of the
/// width), SYNTHETIC DATA top right in red. Errors: the font's.
Status drawFrameLegend(globe::ImageRGBA8& image, const FrameLegend& legend);

}  // namespace atmoglobe::engine
