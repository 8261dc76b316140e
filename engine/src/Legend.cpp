// Frame legends and the shared plot drawing (Legend.h).
#include <atmoglobe/engine/Legend.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace atmoglobe::engine {

void fillRect(globe::ImageRGBA8& img, int x0, int y0, int x1, int y1, glm::u8vec4 c) {
  for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) blendPixel(img, x, y, c, 255);
}
void hLine(globe::ImageRGBA8& img, int x0, int x1, int y, glm::u8vec4 c) { fillRect(img, x0, y, x1, y + 1, c); }
void vLine(globe::ImageRGBA8& img, int x, int y0, int y1, glm::u8vec4 c) { fillRect(img, x, y0, x + 1, y1, c); }
void frame(globe::ImageRGBA8& img, int x0, int y0, int x1, int y1, glm::u8vec4 c) {
  hLine(img, x0 - 1, x1 + 1, y0 - 1, c);
  hLine(img, x0 - 1, x1 + 1, y1, c);
  vLine(img, x0 - 1, y0 - 1, y1 + 1, c);
  vLine(img, x1, y0 - 1, y1 + 1, c);
}

int decimalsFor(double step) {
  int d = 0;
  while (d < 4 && std::abs(step * std::pow(10.0, d) - std::round(step * std::pow(10.0, d))) > 1e-6) ++d;
  return d;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::abs(v) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : v);
  return buf;
}

std::vector<double> niceTicks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || target < 1) return ticks;
  const double raw = (hi - lo) / target;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  double step = p;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    step = m * p;
    if (step >= raw) break;
  }
  const double eps = 1e-9 * (hi - lo);
  for (double v = std::ceil((lo - eps) / step) * step; v <= hi + eps; v += step) {
    ticks.push_back(std::abs(v) < eps ? 0.0 : v);
  }
  return ticks;
}

std::vector<LegendKey> mergeLegendKeys(const std::vector<LegendKey>& in) {
  // Layers with the same table and units share one key (its title names them all).
  std::vector<LegendKey> keys;
  for (const LegendKey& k : in) {
    auto same = std::find_if(keys.begin(), keys.end(), [&](const LegendKey& o) {
      return o.units == k.units && o.colors.stops() == k.colors.stops() && o.colors.scale() == k.colors.scale() &&
             o.colors.offset() == k.colors.offset();
    });
    if (same == keys.end()) keys.push_back(k);
    else same->title += ", " + k.title;
  }
  return keys;
}

glm::dvec2 colorKeyRange(const volume::ColorTable& colors) {
  const auto& stops = colors.stops();
  if (stops.empty()) return {0.0, 1.0};
  const bool stepped =
      std::all_of(stops.begin(), stops.end(), [](const volume::ColorStop& s) { return s.start == s.end; });
  auto field = [&](double tableValue) { return (tableValue - colors.offset()) / colors.scale(); };
  double lo = field(stops.front().value), hi = field(stops.back().value);
  if (stepped && stops.size() >= 2) hi = field(2 * stops.back().value - stops[stops.size() - 2].value);
  if (lo > hi) std::swap(lo, hi);
  if (!(hi > lo)) hi = lo + 1.0;
  return {lo, hi};
}

void drawColorKey(globe::ImageRGBA8& img, const Font& font, const volume::ColorTable& colors, const std::string& units,
                  int kx0, int ky0, int kx1, int ky1, const TextStyle& tick, const TextStyle& unitsStyle) {
  const auto& stops = colors.stops();
  if (stops.empty()) return;
  const glm::u8vec4 kBlack{0, 0, 0, 255};
  const bool stepped =
      std::all_of(stops.begin(), stops.end(), [](const volume::ColorStop& s) { return s.start == s.end; });
  auto field = [&](double tableValue) { return (tableValue - colors.offset()) / colors.scale(); };
  const glm::dvec2 range = colorKeyRange(colors);
  const double lo = range.x, hi = range.y;
  for (int y = ky0; y < ky1; ++y) {
    const double v = hi - (y - ky0 + 0.5) / (ky1 - ky0) * (hi - lo);
    const volume::Rgba8 c = colors.map(static_cast<float>(v));
    fillRect(img, kx0, y, kx1, y + 1, glm::u8vec4{c.r, c.g, c.b, 255});
  }
  frame(img, kx0, ky0, kx1, ky1, kBlack);
  std::vector<double> ticks;
  if (stepped && stops.size() <= 40) {
    const int every = std::max(
        1, static_cast<int>(std::ceil(16.0 * static_cast<double>(stops.size() + 1) / static_cast<double>(ky1 - ky0))));
    for (std::size_t k = 0; k < stops.size(); k += static_cast<std::size_t>(every))
      ticks.push_back(field(stops[k].value));
  } else {
    ticks = niceTicks(lo, hi, std::max(2, (ky1 - ky0) / 40));
  }
  const int keyDecimals = ticks.size() > 1 ? decimalsFor(std::abs(ticks[1] - ticks[0])) : 0;
  for (double t : ticks) {
    const int y = static_cast<int>(std::floor(ky0 + (hi - t) / (hi - lo) * (ky1 - ky0)));
    hLine(img, kx1, kx1 + 4, y, tick.color);
    drawText(img, font, fixed(t, keyDecimals), kx1 + 7, y + 0.5, tick, HAlign::Left, VAlign::Middle);
  }
  drawText(img, font, units.empty() ? std::string("(no units)") : units, 0.5 * (kx0 + kx1), ky0 - 8, unitsStyle,
           HAlign::Center, VAlign::Bottom);
}

namespace {
// A round length (1, 2, 5 x 10^k m) of at most `maxMeters`.
double roundLength(double maxMeters) {
  const double p = std::pow(10.0, std::floor(std::log10(maxMeters)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= maxMeters) return m * p;
  return p;
}
}  // namespace

ScaleBar scaleBarFor(double metersPerPixel, int widthPx) {
  ScaleBar bar;
  if (!(metersPerPixel > 0.0 && std::isfinite(metersPerPixel)) || widthPx < 1) return bar;
  bar.meters = roundLength(metersPerPixel * widthPx / 5.0);
  bar.lengthPx = static_cast<int>(std::lround(bar.meters / metersPerPixel));
  bar.label = bar.meters >= 1000.0 ? fixed(bar.meters / 1000.0, bar.meters >= 10000.0 ? 0 : 1) + " km"
                                   : fixed(bar.meters, 0) + " m";
  return bar;
}

Status drawFrameLegend(globe::ImageRGBA8& img, const FrameLegend& legend) {
  const auto& fontResult = Font::dejaVuSans();
  if (!fontResult) return makeError(fontResult.error());
  const Font& font = **fontResult;
  const glm::u8vec4 white{255, 255, 255, 255}, black{0, 0, 0, 255};
  // White text with a dark halo: reads over imagery, clouds and echoes alike.
  const double scale = std::clamp(img.height / 720.0, 0.6, 2.0);
  const TextStyle title{17.0 * scale, white, black, 2.0};
  const TextStyle line{13.0 * scale, white, black, 2.0};
  const TextStyle tick{11.0 * scale, white, black, 1.5};
  double y = 8.0 * scale;
  if (!legend.title.empty()) {
    drawText(img, font, legend.title, 10 * scale, y, title, HAlign::Left, VAlign::Top);
    y += 24.0 * scale;
  }
  for (const std::string& s : legend.subtitles) {
    drawText(img, font, s, 10 * scale, y, line, HAlign::Left, VAlign::Top);
    y += 18.0 * scale;
  }
  if (legend.synthetic) {
    drawText(img, font, "SYNTHETIC DATA", img.width - 10 * scale, 8 * scale,
             TextStyle{17.0 * scale, {230, 30, 30, 255}, white, 2.0}, HAlign::Right, VAlign::Top);
  }
  // Keys: right edge, side by side from the right, below the SYNTHETIC line.
  const int keyWidth = static_cast<int>(14 * scale), column = static_cast<int>(70 * scale);
  const int top = static_cast<int>(60 * scale), bottom = img.height - static_cast<int>(40 * scale);
  int x1 = img.width - static_cast<int>(46 * scale);
  for (const LegendKey& k : mergeLegendKeys(legend.keys)) {
    if (bottom - top < 60 || x1 - keyWidth < img.width / 2) break;  // no room: fewer keys rather than overlap
    drawColorKey(img, font, k.colors, k.units, x1 - keyWidth, top + static_cast<int>(36 * scale), x1, bottom, tick,
                 line);
    drawText(img, font, k.title, x1 + 2 * scale, top + 4 * scale, tick, HAlign::Right, VAlign::Bottom);
    x1 -= column;
  }
  // Scale bar: a round length of at most a fifth of the width, at the image centre's scale.
  if (const ScaleBar bar = scaleBarFor(legend.metersPerPixel, img.width); bar.meters > 0.0) {
    const int px = bar.lengthPx;
    const int x0 = static_cast<int>(12 * scale), yb = img.height - static_cast<int>(14 * scale);
    fillRect(img, x0 - 1, yb - 1, x0 + px + 1, yb + 3, black);
    fillRect(img, x0, yb, x0 + px, yb + 2, white);
    drawText(img, font, bar.label + " (at the centre)", x0, yb - 4 * scale, tick, HAlign::Left, VAlign::Bottom);
  }
  return Ok{};
}

}  // namespace atmoglobe::engine
