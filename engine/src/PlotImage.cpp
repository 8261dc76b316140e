#include <atmoglobe/engine/PlotImage.h>

#include <stb/stb_easy_font.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>

namespace atmoglobe::engine {

namespace {

constexpr int kMarginLeft = 78, kMarginRight = 24, kMarginTop = 40, kMarginBottom = 56;
constexpr int kTextScale = 2;

struct Canvas {
  globe::ImageRGBA8& img;
  void put(int x, int y, glm::u8vec4 c) const {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    img.set(x, y, c);
  }
  void rect(int x0, int y0, int x1, int y1, glm::u8vec4 c) const {  // inclusive
    for (int y = std::max(0, y0); y <= std::min(img.height - 1, y1); ++y)
      for (int x = std::max(0, x0); x <= std::min(img.width - 1, x1); ++x) img.set(x, y, c);
  }
  void line(double x0, double y0, double x1, double y1, glm::u8vec4 c, int thickness = 1) const {
    const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
    const int n = std::max(1, static_cast<int>(std::ceil(len)));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      const int x = static_cast<int>(std::floor(x0 + t * (x1 - x0)));
      const int y = static_cast<int>(std::floor(y0 + t * (y1 - y0)));
      rect(x - (thickness - 1) / 2, y - (thickness - 1) / 2, x + thickness / 2, y + thickness / 2, c);
    }
  }
  void disc(int cx, int cy, int r, glm::u8vec4 c) const {
    for (int y = -r; y <= r; ++y)
      for (int x = -r; x <= r; ++x)
        if (x * x + y * y <= r * r) put(cx + x, cy + y, c);
  }
  void ring(int cx, int cy, int r, glm::u8vec4 c) const {
    for (int y = -r - 1; y <= r + 1; ++y)
      for (int x = -r - 1; x <= r + 1; ++x) {
        const double d = std::sqrt(static_cast<double>(x * x + y * y));
        if (std::abs(d - r) <= 0.8) put(cx + x, cy + y, c);
      }
  }
  /// Text with its top-left corner at (x, y); vertical: rotated 90 deg counter-clockwise
  /// (reads bottom to top), (x, y) is then its bottom-left corner.
  void text(int x, int y, const std::string& s, glm::u8vec4 c, int scale = kTextScale, bool vertical = false) const {
    if (s.empty()) return;
    std::vector<char> buf(s.begin(), s.end());
    buf.push_back('\0');
    std::vector<char> quads(s.size() * 270 + 1024);  // stb: ~270 bytes per character at worst
    const int n = stb_easy_font_print(0.0f, 0.0f, buf.data(), nullptr, quads.data(), static_cast<int>(quads.size()));
    for (int q = 0; q < n; ++q) {
      const float* v0 = reinterpret_cast<const float*>(quads.data() + static_cast<std::size_t>(q) * 64);
      const float* v2 = reinterpret_cast<const float*>(quads.data() + static_cast<std::size_t>(q) * 64 + 32);
      const int qx0 = static_cast<int>(v0[0]) * scale, qy0 = static_cast<int>(v0[1]) * scale;
      const int qx1 = static_cast<int>(v2[0]) * scale - 1, qy1 = static_cast<int>(v2[1]) * scale - 1;
      if (!vertical) {
        rect(x + qx0, y + qy0, x + qx1, y + qy1, c);
      } else {
        rect(x + qy0, y - qx1, x + qy1, y - qx0, c);
      }
    }
  }
};

double niceStep(double raw) {
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10.0 * p;
}

/// 1-2-5 values: the largest <= v (down) or the smallest >= v (up). v > 0.
double nice125(double v, bool up) {
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  const double ms[] = {1.0, 2.0, 5.0, 10.0};
  if (up) {
    for (double m : ms)
      if (m * p >= v * (1 - 1e-12)) return m * p;
    return 10.0 * p;
  }
  for (int i = 3; i >= 0; --i)
    if (ms[i] * p <= v * (1 + 1e-12)) return ms[i] * p;
  return p;
}

std::vector<double> logTicks(double lo, double hi) {
  std::vector<double> out;
  for (double p = std::pow(10.0, std::floor(std::log10(lo))); p <= hi * 1.0001; p *= 10.0)
    for (double m : {1.0, 2.0, 5.0})
      if (m * p >= lo * 0.9999 && m * p <= hi * 1.0001) out.push_back(m * p);
  return out;
}

std::string formatTick(double v) {
  char buf[32];
  const double a = std::abs(v);
  if (a == 0.0) return "0";
  if (a >= 1e5 || a < 1e-3) {
    std::snprintf(buf, sizeof buf, "%.0e", v);
  } else if (std::abs(v - std::round(v)) < 1e-9 * std::max(1.0, a)) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
  } else {
    std::snprintf(buf, sizeof buf, "%g", v);
  }
  return buf;
}

}  // namespace

int plotTextWidthPx(const std::string& text, int scale) {
  std::vector<char> buf(text.begin(), text.end());
  buf.push_back('\0');
  return stb_easy_font_width(buf.data()) * scale;
}

glm::dvec2 PlotFrame::toPixel(double x, double y) const {
  const double fx = logX ? (std::log10(x) - std::log10(xMin)) / (std::log10(xMax) - std::log10(xMin))
                         : (x - xMin) / (xMax - xMin);
  const double fy = (y - yMin) / (yMax - yMin);
  return {left + fx * (right - left), bottom - fy * (bottom - top)};
}

PlotFrame layoutPlot(const ScatterPlot& plot, int widthPx, int heightPx) {
  assert(widthPx >= 200 && heightPx >= 150);
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  auto add = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y) || (plot.logX && x <= 0.0)) return;
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  };
  for (const PlotPoint& p : plot.points) add(p.x, p.y);
  for (const PlotLine& l : plot.lines)
    for (const glm::dvec2& p : l.points) add(p.x, p.y);
  if (!std::isfinite(x0)) x0 = 1.0, x1 = 10.0, y0 = 0.0, y1 = 1.0;
  PlotFrame f;
  f.logX = plot.logX;
  if (plot.logX) {
    f.xMin = nice125(x0, false);
    f.xMax = nice125(x1, true);
    if (f.xMax <= f.xMin) f.xMax = nice125(f.xMin * 1.5, true);
  } else {
    if (x1 <= x0) x0 -= 1.0, x1 += 1.0;
    const double s = niceStep((x1 - x0) / 6.0);
    f.xMin = std::floor(x0 / s) * s, f.xMax = std::ceil(x1 / s) * s;
  }
  if (y1 <= y0) y0 -= 1.0, y1 += 1.0;
  const double sy = niceStep((y1 - y0) / 6.0);
  f.yMin = std::floor(y0 / sy) * sy, f.yMax = std::ceil(y1 / sy) * sy;
  if (f.yMax <= f.yMin) f.yMax = f.yMin + sy;
  f.left = kMarginLeft, f.top = kMarginTop, f.right = widthPx - 1 - kMarginRight,
  f.bottom = heightPx - 1 - kMarginBottom;
  return f;
}

globe::ImageRGBA8 drawScatterPlot(const ScatterPlot& plot, int widthPx, int heightPx) {
  globe::ImageRGBA8 img = globe::ImageRGBA8::filled(widthPx, heightPx, {255, 255, 255, 255});
  const Canvas cv{img};
  const PlotFrame f = layoutPlot(plot, widthPx, heightPx);
  const glm::u8vec4 black{0, 0, 0, 255}, grid{225, 225, 225, 255};

  // Grid and ticks.
  std::vector<double> xt;
  if (plot.logX) {
    xt = logTicks(f.xMin, f.xMax);
  } else {
    const double s = niceStep((f.xMax - f.xMin) / 6.0);
    for (double v = f.xMin; v <= f.xMax + 1e-9 * s; v += s) xt.push_back(v);
  }
  std::vector<double> yt;
  const double sy = niceStep((f.yMax - f.yMin) / 6.0);
  for (double v = f.yMin; v <= f.yMax + 1e-9 * sy; v += sy) yt.push_back(v);
  for (double v : xt) {
    const int px = static_cast<int>(std::floor(f.toPixel(v, f.yMin).x));
    cv.line(px, f.top, px, f.bottom, grid);
    cv.line(px, f.bottom, px, f.bottom + 5, black);
    const std::string s = formatTick(v);
    cv.text(px - plotTextWidthPx(s, kTextScale) / 2, f.bottom + 9, s, black);
  }
  for (double v : yt) {
    const int py = static_cast<int>(std::floor(f.toPixel(f.xMin, v).y));
    cv.line(f.left, py, f.right, py, grid);
    cv.line(f.left - 5, py, f.left, py, black);
    const std::string s = formatTick(v);
    cv.text(f.left - 9 - plotTextWidthPx(s, kTextScale), py - 6, s, black);
  }
  cv.line(f.left, f.top, f.left, f.bottom, black);
  cv.line(f.left, f.bottom, f.right, f.bottom, black);
  cv.line(f.right, f.top, f.right, f.bottom, black);
  cv.line(f.left, f.top, f.right, f.top, black);

  // Labels.
  cv.text((widthPx - plotTextWidthPx(plot.title, kTextScale)) / 2, 12, plot.title, black);
  cv.text((f.left + f.right - plotTextWidthPx(plot.xLabel, kTextScale)) / 2, heightPx - 24, plot.xLabel, black);
  cv.text(8, (f.top + f.bottom + plotTextWidthPx(plot.yLabel, kTextScale)) / 2, plot.yLabel, black, kTextScale, true);

  // Lines, then points on top.
  for (const PlotLine& l : plot.lines) {
    for (std::size_t i = 1; i < l.points.size(); ++i) {
      const glm::dvec2 a = f.toPixel(l.points[i - 1].x, l.points[i - 1].y);
      const glm::dvec2 b = f.toPixel(l.points[i].x, l.points[i].y);
      cv.line(a.x, a.y, b.x, b.y, l.color, 2);
    }
  }
  for (const PlotPoint& p : plot.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || (plot.logX && p.x <= 0.0)) continue;
    const glm::dvec2 q = f.toPixel(p.x, p.y);
    const int cx = static_cast<int>(std::floor(q.x)), cy = static_cast<int>(std::floor(q.y));
    cv.disc(cx, cy, p.radiusPx, p.color);
    if (p.ring) {
      cv.ring(cx, cy, p.radiusPx + 3, p.color);
      cv.ring(cx, cy, p.radiusPx + 4, p.color);
    }
    if (!p.label.empty()) cv.text(cx + p.radiusPx + 7, cy - 6, p.label, p.color);
  }

  // Legend.
  if (!plot.legend.empty()) {
    int w = 0;
    for (const PlotLegendEntry& e : plot.legend) w = std::max(w, plotTextWidthPx(e.text, kTextScale));
    const int x0 = f.right - w - 34, y0 = f.top + 8;
    const int h = static_cast<int>(plot.legend.size()) * 20 + 8;
    cv.rect(x0, y0, f.right - 8, y0 + h, {255, 255, 255, 255});
    cv.line(x0, y0, f.right - 8, y0, black), cv.line(x0, y0 + h, f.right - 8, y0 + h, black);
    cv.line(x0, y0, x0, y0 + h, black), cv.line(f.right - 8, y0, f.right - 8, y0 + h, black);
    for (std::size_t i = 0; i < plot.legend.size(); ++i) {
      const int y = y0 + 8 + static_cast<int>(i) * 20;
      cv.disc(x0 + 10, y + 6, 4, plot.legend[i].color);
      cv.text(x0 + 20, y, plot.legend[i].text, black);
    }
  }
  return img;
}

}  // namespace atmoglobe::engine
