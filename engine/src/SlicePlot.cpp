// Slice plots (SlicePlot.h).
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/globe/Text.h>
#include <atmoglobe/map/MapLod.h>
#include <atmoglobe/map/VectorFile.h>

#include <atmoglobe/engine/Legend.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace atmoglobe::engine {
namespace {

// Margins (px) around the plot area: title and subtitle (and the path's point letters) above,
// tick labels and the axis label below and left, the colour key right.
constexpr int kTop = 84, kBottom = 54, kLeft = 78, kRight = 150;
constexpr int kMinWidth = 320, kMinHeight = 240;
constexpr double kTitlePx = 17.0, kSubtitlePx = 13.0, kTickPx = 12.0, kAxisPx = 13.0;
const glm::u8vec4 kBlack{0, 0, 0, 255}, kWhite{255, 255, 255, 255}, kGridLine{0, 0, 0, 45};

double mid(double a, double b) { return 0.5 * (a + b); }

// The shape (width / height) of a CAPPI box at its middle latitude.
double cappiAspect(const volume::LatLonBox& b) {
  const double cosLat = std::cos(mid(b.southDeg, b.northDeg) * M_PI / 180.0);
  return (b.eastDeg - b.westDeg) * std::max(cosLat, 0.05) / (b.northDeg - b.southDeg);
}

std::string pointLetter(std::size_t k) {
  if (k < 26) return std::string(1, static_cast<char>('A' + k));
  return std::string("P").append(std::to_string(k + 1));
}

}  // namespace

std::string latitudeLabel(double latDeg, int decimals) {
  const std::string n = fixed(std::abs(latDeg), decimals);
  if (n == fixed(0.0, decimals)) return n + "°";
  return n + (latDeg > 0 ? std::string("°N") : std::string("°S"));
}

std::string longitudeLabel(double lonDeg, int decimals) {
  double l = std::fmod(lonDeg, 360.0);
  if (l > 180.0) l -= 360.0;
  if (l <= -180.0) l += 360.0;
  const std::string n = fixed(std::abs(l), decimals);
  if (n == fixed(0.0, decimals) || n == fixed(180.0, decimals)) return n + "°";
  return n + (l > 0 ? std::string("°E") : std::string("°W"));
}

glm::u8vec4 slicePixelColor(const volume::ColorTable& colors, float value, glm::u8vec4 noEchoColor,
                            glm::u8vec4 noDataColor) {
  if (std::isnan(value)) return noDataColor;
  if (std::isinf(value)) return noEchoColor;
  const volume::Rgba8 c = colors.map(value);
  if (c.a == 0) return noEchoColor;
  return {c.r, c.g, c.b, 255};
}

int cappiImageHeightFor(const volume::LatLonBox& box, int widthPx) {
  const double plotWidth = std::max(1, widthPx - kLeft - kRight);
  const double h = plotWidth / cappiAspect(box) + kTop + kBottom;
  return std::clamp(static_cast<int>(std::lround(h)), kMinHeight, 4096);
}

Result<SlicePlotLayout> layoutSlicePlot(const volume::SliceGeometry& g, int widthPx, int heightPx) {
  if (widthPx < kMinWidth || heightPx < kMinHeight) {
    return makeError("slice plot size " + std::to_string(widthPx) + "x" + std::to_string(heightPx) +
                     " is too small: at least " + std::to_string(kMinWidth) + "x" + std::to_string(kMinHeight));
  }
  SlicePlotLayout l{kLeft, kTop, widthPx - kRight, heightPx - kBottom};
  if (g.kind() == volume::SliceGeometry::Kind::Cappi) {
    const volume::LatLonBox box{g.yBottom(), g.yTop(), g.xFirst(), g.xLast()};
    const double aspect = cappiAspect(box);
    if (!(aspect > 0.0) || !std::isfinite(aspect)) return makeError("CAPPI box has no area");
    const int roomW = l.width(), roomH = l.height();
    int w = roomW, h = static_cast<int>(std::lround(roomW / aspect));
    if (h > roomH) {
      h = roomH;
      w = std::max(1, static_cast<int>(std::lround(roomH * aspect)));
    }
    h = std::max(h, 1);
    l.left += (roomW - w) / 2;
    l.right = l.left + w;
    l.top += (roomH - h) / 2;
    l.bottom = l.top + h;
  }
  return l;
}

namespace {
/// An antialiased segment `widthPx` wide from a to b (pixel coordinates; a pixel's centre is at
/// +0.5), drawn only inside the layout's area: each pixel's coverage from its centre's distance
/// to the segment.
void drawClippedSegment(globe::ImageRGBA8& img, glm::dvec2 a, glm::dvec2 b, glm::u8vec4 color, double widthPx,
                        const SlicePlotLayout& L) {
  const double reach = 0.5 * widthPx + 0.5;
  const int x0 = std::max(L.left, static_cast<int>(std::floor(std::min(a.x, b.x) - reach)));
  const int x1 = std::min(L.right - 1, static_cast<int>(std::ceil(std::max(a.x, b.x) + reach)));
  const int y0 = std::max(L.top, static_cast<int>(std::floor(std::min(a.y, b.y) - reach)));
  const int y1 = std::min(L.bottom - 1, static_cast<int>(std::ceil(std::max(a.y, b.y) + reach)));
  if (x0 > x1 || y0 > y1) return;
  if ((x1 - x0 + 1.0) * (y1 - y0 + 1.0) > 4.0e6) return;  // a wild segment (a line across the wrap): skip it
  const glm::dvec2 d = b - a;
  const double len2 = glm::dot(d, d);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const glm::dvec2 c{x + 0.5, y + 0.5};
      const double t = len2 > 0.0 ? std::clamp(glm::dot(c - a, d) / len2, 0.0, 1.0) : 0.0;
      const double dist = glm::length(c - (a + t * d));
      const double coverage = std::clamp(reach - dist, 0.0, 1.0);
      if (coverage > 0.0) blendPixel(img, x, y, color, static_cast<std::uint8_t>(std::lround(coverage * 255.0)));
    }
}
}  // namespace

Result<globe::ImageRGBA8> drawSlicePlot(const volume::SliceRaster& raster, const volume::SliceGeometry& g,
                                        const SlicePlotOptions& o) {
  const auto& fontResult = Font::dejaVuSans();
  if (!fontResult) return fontResult.forwardError();
  const Font& font = **fontResult;
  auto layout = layoutSlicePlot(g, o.widthPx, o.heightPx);
  if (!layout) return layout.forwardError();
  const SlicePlotLayout L = *layout;
  if (raster.columns < 1 || raster.rows < 1) return makeError("slice plot: empty raster");
  globe::ImageRGBA8 img = globe::ImageRGBA8::filled(o.widthPx, o.heightPx, kWhite);
  const bool cappi = g.kind() == volume::SliceGeometry::Kind::Cappi;

  // --- the raster: one raster pixel under each plot pixel's centre ---
  for (int py = L.top; py < L.bottom; ++py) {
    const int row = std::min(raster.rows - 1, static_cast<int>((py - L.top + 0.5) * raster.rows / L.height()));
    for (int px = L.left; px < L.right; ++px) {
      const int col = std::min(raster.columns - 1, static_cast<int>((px - L.left + 0.5) * raster.columns / L.width()));
      const float v = raster.at(col, row);
      glm::u8vec4 c = slicePixelColor(o.colors, v, o.noEchoColor, o.noDataColor);
      if (std::isnan(v) && (px + py) % 8 < 2) c = o.noDataHatchColor;  // diagonal hatching
      img.set(px, py, c);
    }
  }

  // Data value -> pixel along each axis.
  auto xPixel = [&](double xv) { return L.left + (xv - g.xFirst()) / (g.xLast() - g.xFirst()) * L.width(); };
  auto yPixel = [&](double yv) { return L.bottom - (yv - g.yBottom()) / (g.yTop() - g.yBottom()) * L.height(); };
  const double xScale = cappi ? 1.0 : 0.001;  // axis units: degrees or km
  const double yScale = cappi ? 1.0 : 0.001;
  const int xTarget = std::max(3, L.width() / 90), yTarget = std::max(3, L.height() / 45);
  const std::vector<double> xTicks = niceTicks(g.xFirst() * xScale, g.xLast() * xScale, xTarget);
  const std::vector<double> yTicks = niceTicks(g.yBottom() * yScale, g.yTop() * yScale, yTarget);
  const int xDecimals = xTicks.size() > 1 ? decimalsFor(xTicks[1] - xTicks[0]) : 0;
  const int yDecimals = yTicks.size() > 1 ? decimalsFor(yTicks[1] - yTicks[0]) : 0;

  // --- map lines and contours over the raster (CAPPI), clipped to the plot area ---
  if (cappi) {
    const double midLon = mid(g.xFirst(), g.xLast());
    // A line's points on the plot: longitudes continuous along it, and near the box's middle.
    auto plotPoints = [&](const map::GeoPolyline& line) {
      std::vector<glm::dvec2> points;
      double previous = midLon;
      for (const glm::dvec2& p : line.lonLatDeg) {
        double lon = p.x;
        lon += 360.0 * std::round((previous - lon) / 360.0);
        previous = lon;
        points.emplace_back(xPixel(lon), yPixel(p.y));
      }
      return points;
    };
    auto drawLine = [&](const std::vector<glm::dvec2>& points, glm::u8vec4 color, double widthPx) {
      for (std::size_t k = 1; k < points.size(); ++k)
        drawClippedSegment(img, points[k - 1], points[k], color, widthPx, L);
    };
    for (const SlicePlotLines& set : o.mapLines)
      for (const map::GeoPolyline& line : set.lines) drawLine(plotPoints(line), set.color, set.widthPx);
    // Contours: the lines, then one label per long line at its middle, where no label is yet.
    std::vector<glm::dvec4> placed;  // label boxes: x0, y0, x1, y1
    for (const SlicePlotContours& set : o.contours) {
      for (const map::ContourLine& c : set.lines) drawLine(plotPoints(c.line), set.color, set.widthPx);
      if (!set.labelled) continue;
      const TextStyle style{kTickPx, set.color, kWhite, 2.5};
      for (const map::ContourLine& c : set.lines) {
        const std::vector<glm::dvec2> points = plotPoints(c.line);
        double length = 0.0;
        for (std::size_t k = 1; k < points.size(); ++k) length += glm::distance(points[k - 1], points[k]);
        if (length < 100.0) continue;
        double walked = 0.0;
        glm::dvec2 at = points.front();
        for (std::size_t k = 1; k < points.size(); ++k) {
          const double step = glm::distance(points[k - 1], points[k]);
          if (walked + step >= 0.5 * length) {
            at = points[k - 1] + (points[k] - points[k - 1]) * ((0.5 * length - walked) / std::max(step, 1e-9));
            break;
          }
          walked += step;
        }
        const std::string text = map::contourLabel(c.value);
        const double halfWidth = 0.32 * kTickPx * static_cast<double>(text.size()) + 3.0, halfHeight = 0.6 * kTickPx;
        const glm::dvec4 box{at.x - halfWidth, at.y - halfHeight, at.x + halfWidth, at.y + halfHeight};
        if (box.x < L.left || box.z > L.right || box.y < L.top || box.w > L.bottom) continue;
        const bool overlaps = std::any_of(placed.begin(), placed.end(), [&](const glm::dvec4& b) {
          return box.x < b.z + 20.0 && b.x < box.z + 20.0 && box.y < b.w + 20.0 && b.y < box.w + 20.0;
        });
        if (overlaps) continue;
        placed.push_back(box);
        drawText(img, font, text, at.x, at.y, style, HAlign::Center, VAlign::Middle);
      }
    }
  }

  // --- grid lines, then the frame and ticks ---
  for (double t : xTicks) vLine(img, static_cast<int>(std::floor(xPixel(t / xScale))), L.top, L.bottom, kGridLine);
  for (double t : yTicks) hLine(img, L.left, L.right, static_cast<int>(std::floor(yPixel(t / yScale))), kGridLine);
  if (!cappi) {
    // The path's interior points: dashed verticals.
    const auto& d = g.path().pointDistancesMeters();
    for (std::size_t k = 1; k + 1 < d.size(); ++k) {
      const int x = static_cast<int>(std::floor(xPixel(d[k])));
      for (int y = L.top; y < L.bottom; ++y)
        if ((y - L.top) % 10 < 6) blendPixel(img, x, y, {0, 0, 0, 160}, 255);
    }
  }
  frame(img, L.left, L.top, L.right, L.bottom, kBlack);
  const TextStyle tick{kTickPx, kBlack, kWhite, 0.0};
  for (double t : xTicks) {
    const int x = static_cast<int>(std::floor(xPixel(t / xScale)));
    vLine(img, x, L.bottom, L.bottom + 5, kBlack);
    const std::string label = cappi ? longitudeLabel(t, xDecimals) : fixed(t, xDecimals);
    drawText(img, font, label, x + 0.5, L.bottom + 8, tick, HAlign::Center, VAlign::Top);
  }
  for (double t : yTicks) {
    const int y = static_cast<int>(std::floor(yPixel(t / yScale)));
    hLine(img, L.left - 5, L.left, y, kBlack);
    const std::string label = cappi ? latitudeLabel(t, yDecimals) : fixed(t, yDecimals);
    drawText(img, font, label, L.left - 8, y + 0.5, tick, HAlign::Right, VAlign::Middle);
  }
  const TextStyle axis{kAxisPx, kBlack, kWhite, 0.0};
  const std::string datum = volume::toString(g.datum());
  const std::string xLabel = cappi ? "longitude" : "distance along the path (km)";
  const std::string yLabel = cappi ? std::string("latitude") : std::string("height ").append(datum).append(" (km)");
  drawText(img, font, xLabel, mid(L.left, L.right), L.bottom + 30, axis, HAlign::Center, VAlign::Top);
  drawText(img, font, yLabel, 16, mid(L.top, L.bottom), axis, HAlign::Center, VAlign::Top, TextDirection::Up);

  // --- marks on the plot ---
  const TextStyle markLabel{kTickPx + 1, kBlack, kWhite, 2.0};
  if (cappi) {
    for (const SlicePlotMarker& m : o.markers) {
      double lon = m.lonDeg;
      while (lon < g.xFirst()) lon += 360.0;
      while (lon > g.xLast()) lon -= 360.0;
      const double x = xPixel(lon), y = yPixel(m.latDeg);
      if (x < L.left || x >= L.right || y < L.top || y >= L.bottom) continue;
      const int ix = static_cast<int>(std::floor(x)), iy = static_cast<int>(std::floor(y));
      for (int pass = 0; pass < 2; ++pass) {
        const glm::u8vec4 c = pass == 0 ? kWhite : kBlack;
        const int w = pass == 0 ? 2 : 1;
        for (int k = -6; k <= 6; ++k)
          for (int s = -w + 1; s < w; ++s) {
            blendPixel(img, ix + k, iy + s, c, 255);
            blendPixel(img, ix + s, iy + k, c, 255);
          }
      }
      drawText(img, font, m.label, x + 9, y - 4, markLabel, HAlign::Left, VAlign::Bottom);
    }
  } else {
    const auto& d = g.path().pointDistancesMeters();
    for (std::size_t k = 0; k < d.size(); ++k) {
      const double x = xPixel(d[k]);
      const HAlign align = k == 0 ? HAlign::Left : k + 1 == d.size() ? HAlign::Right : HAlign::Center;
      // A small down-pointing triangle above the frame, the letter above it.
      for (int r = 0; r < 6; ++r)
        hLine(img, static_cast<int>(x) - (5 - r), static_cast<int>(x) + (5 - r) + 1, L.top - 9 + r, kBlack);
      drawText(img, font, pointLetter(k),
               k == 0              ? x - 5
               : k + 1 == d.size() ? x + 5
                                   : x,
               L.top - 12, TextStyle{kAxisPx, kBlack, kWhite, 0.0}, align, VAlign::Bottom);
    }
  }

  // --- colour key ---
  const auto& stops = o.colors.stops();
  if (!stops.empty()) {
    const int kx0 = L.right + 22, kx1 = kx0 + 18;
    const int ky0 = L.top + 22, ky1 = std::max(ky0 + 40, L.bottom - 64);
    drawColorKey(img, font, o.colors, o.units, kx0, ky0, kx1, ky1, tick, TextStyle{kAxisPx, kBlack, kWhite, 0.0});
    // Swatches: no echo (and values below the key), no data.
    const int sy = ky1 + 14;
    fillRect(img, kx0, sy, kx1, sy + 12, o.noEchoColor);
    frame(img, kx0, sy, kx1, sy + 12, kBlack);
    drawText(img, font, "no echo", kx1 + 7, sy + 6, tick, HAlign::Left, VAlign::Middle);
    for (int y = sy + 24; y < sy + 36; ++y)
      for (int x = kx0; x < kx1; ++x) img.set(x, y, (x + y) % 8 < 2 ? o.noDataHatchColor : o.noDataColor);
    frame(img, kx0, sy + 24, kx1, sy + 36, kBlack);
    drawText(img, font, "no data", kx1 + 7, sy + 30, tick, HAlign::Left, VAlign::Middle);
  }

  // --- title, subtitle, SYNTHETIC ---
  drawText(img, font, o.title, 12, 10, TextStyle{kTitlePx, kBlack, kWhite, 0.0}, HAlign::Left, VAlign::Top);
  drawText(img, font, o.subtitle, 12, 34, TextStyle{kSubtitlePx, {40, 40, 40, 255}, kWhite, 0.0}, HAlign::Left,
           VAlign::Top);
  if (o.synthetic) {
    // Top right, on the first line (title, subtitle, the free line below) it does not overlap.
    const TextStyle red{kTitlePx, {200, 0, 0, 255}, kWhite, 2.0};
    const double markWidth = font.textWidthPx("SYNTHETIC DATA", kTitlePx);
    double markY = 58;
    if (12 + font.textWidthPx(o.title, kTitlePx) + 16 + markWidth <= o.widthPx - 12) {
      markY = 10;
    } else if (12 + font.textWidthPx(o.subtitle, kSubtitlePx) + 16 + markWidth <= o.widthPx - 12) {
      markY = 32;
    }
    drawText(img, font, "SYNTHETIC DATA", o.widthPx - 12, markY, red, HAlign::Right, VAlign::Top);
    // Also on the data, where a cropped picture keeps it.
    drawText(img, font, "SYNTHETIC", L.left + 6, L.bottom - 6, TextStyle{kTickPx + 1, {200, 0, 0, 255}, kWhite, 2.0},
             HAlign::Left, VAlign::Bottom);
  }
  return img;
}

Status addSliceCoastlines(SlicePlotOptions& options, const volume::SliceGeometry& g, const SlicePlotLayout& L,
                          const std::string& gshhgDir, char* resolutionOut) {
  if (g.kind() != volume::SliceGeometry::Kind::Cappi || L.width() <= 0) return Ok{};
  const double midLatRad = mid(g.yBottom(), g.yTop()) * std::numbers::pi / 180.0;
  // Metres per pixel across the box (a degree of longitude: 111.32 km x cos(latitude) on the sphere).
  const double metresPerPixel =
      std::abs(g.xLast() - g.xFirst()) * 111320.0 * std::max(0.05, std::cos(midLatRad)) / L.width();
  const map::GshhgResolution res = map::gshhgResolutionForScale(metresPerPixel);
  auto lines = map::readBoxMapLines(gshhgDir, g.yBottom(), g.yTop(), g.xFirst(), g.xLast(), res);
  if (!lines) return lines.forwardError();
  if (resolutionOut) *resolutionOut = map::gshhgResolutionLetter(res);
  options.mapLines.push_back({std::move(lines->internal), {120, 120, 120, 220}, 1.0});
  options.mapLines.push_back({std::move(lines->coasts), {25, 25, 25, 235}, 1.3});
  options.mapLines.push_back({std::move(lines->borders), {130, 20, 20, 235}, 1.3});
  return Ok{};
}

Status addSliceOverlays(SlicePlotOptions& options, const std::vector<std::string>& overlayPaths) {
  for (const std::string& path : overlayPaths) {
    auto file = map::readVectorFile(path);
    if (!file) return file.forwardError();
    options.mapLines.push_back({std::move(file->lines), {0, 70, 170, 235}, 1.4});
  }
  return Ok{};
}

std::string utcLabel(const std::string& iso) {
  if (iso.empty()) return "time unknown";
  if (iso.size() == 20 && iso[10] == 'T' && iso[19] == 'Z') return iso.substr(0, 10) + " " + iso.substr(11, 8) + " UTC";
  return iso;
}

SlicePlotOptions slicePlotOptionsFor(const volume::SliceSource& source, const volume::SliceGeometry& g,
                                     const volume::TransferFunction& transfer, int widthPx, int heightPx) {
  SlicePlotOptions o;
  o.widthPx = widthPx;
  o.heightPx = heightPx;
  o.units = source.field().units;
  o.synthetic = source.synthetic();
  o.colors = transfer.colors;
  std::string field = source.field().name;
  if (!source.field().units.empty()) field += " (" + source.field().units + ")";
  std::string time = source.isRadar() ? "volume start " : "valid ";
  time += utcLabel(source.validTime());
  if (const volume::GridVolume* grid = source.grid(); grid && !volume::memberText(*grid).empty())
    time += ", ensemble " + volume::memberText(*grid);
  if (const volume::GridVolume* grid = source.grid(); grid && !volume::extraIndexText(*grid).empty())
    time += ", " + volume::extraIndexText(*grid);
  if (g.kind() == volume::SliceGeometry::Kind::Cappi) {
    char h[64];
    std::snprintf(h, sizeof h, "%.2f", g.cappiHeightMeters() / 1000.0);
    std::string height = h;
    while (height.back() == '0') height.pop_back();
    if (height.back() == '.') height += '0';
    o.title = source.name() + "   " + field + "   " +
              (g.pressurePa() ? numberText(*g.pressurePa() / 100.0) + " hPa"
                              : "CAPPI at " + height + " km " + volume::toString(g.datum()));
    o.subtitle = time;
    if (const volume::PolarVolume* p = source.polar()) {
      o.markers.push_back({p->site.latDeg, p->site.lonDeg, source.name()});
    }
  } else {
    const auto& points = g.path().points();
    char len[64];
    std::snprintf(len, sizeof len, "%.0f km", g.path().lengthMeters() / 1000.0);
    o.title = source.name() + "   " + field + "   cross-section " + pointLetter(0) + "–" +
              pointLetter(points.size() - 1) + ", " + len;
    o.subtitle = time + "    ";
    for (std::size_t k = 0; k < points.size(); ++k) {
      if (k) o.subtitle += "  ";
      o.subtitle += pointLetter(k);
      o.subtitle += ' ';
      o.subtitle += latitudeLabel(points[k].latDeg, 2);
      o.subtitle += ' ';
      o.subtitle += longitudeLabel(points[k].lonDeg, 2);
    }
  }
  if (const volume::GridVolume* grid = source.grid(); grid && grid->approximateHeights) {
    o.subtitle += "    heights APPROXIMATE";
  }
  return o;
}

}  // namespace atmoglobe::engine
