#include <atmoglobe/volume/ColorTable.h>

#include <atmoglobe/globe/Text.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

namespace atmoglobe::volume {

ColorTable::ColorTable(std::string name, std::string units, std::vector<ColorStop> stops, double scale, double offset)
    : name_(std::move(name)), units_(std::move(units)), stops_(std::move(stops)), scale_(scale), offset_(offset) {
  assert(std::isfinite(scale_) && scale_ != 0.0 && std::isfinite(offset_));
  for (std::size_t i = 1; i < stops_.size(); ++i) assert(stops_[i].value > stops_[i - 1].value);
}

namespace {
std::uint8_t lerpChannel(std::uint8_t a, std::uint8_t b, double t) {
  const double v = a + (static_cast<double>(b) - a) * t;
  return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}
}  // namespace

Rgba8 ColorTable::map(float value) const {
  if (!std::isfinite(value) || stops_.empty()) return kTransparent;  // no data (NaN), no echo (-inf)
  const double v = static_cast<double>(value) * scale_ + offset_;
  if (v < stops_.front().value) return kTransparent;
  if (v >= stops_.back().value) return stops_.back().start;
  // First stop whose value is > v, minus one: the band holding v.
  const auto it =
      std::upper_bound(stops_.begin(), stops_.end(), v, [](double x, const ColorStop& s) { return x < s.value; });
  const ColorStop& s = *(it - 1);
  if (s.start == s.end) return s.start;
  const double t = (v - s.value) / (it->value - s.value);
  return Rgba8{lerpChannel(s.start.r, s.end.r, t), lerpChannel(s.start.g, s.end.g, t),
               lerpChannel(s.start.b, s.end.b, t), lerpChannel(s.start.a, s.end.a, t)};
}

ColorTable nwsReflectivityTable() {
  // NWS reflectivity colours, dBZ: R G B (5-75 dBZ: the NWS/AWIPS table, also MetPy's
  // NWSReflectivity colortable; below: clear-air cyans). Stepped: each colour holds for 5 dBZ.
  struct Row {
    int dbz;
    std::uint8_t r, g, b;
  };
  static constexpr std::array<Row, 20> kRows{{
      {-20, 50, 79, 79}, {-15, 102, 139, 139}, {-10, 150, 205, 205}, {-5, 174, 238, 238}, {0, 187, 255, 255},
      {5, 0, 236, 236},  {10, 1, 160, 246},    {15, 0, 0, 246},      {20, 0, 255, 0},     {25, 0, 200, 0},
      {30, 0, 144, 0},   {35, 255, 255, 0},    {40, 231, 192, 0},    {45, 255, 144, 0},   {50, 255, 0, 0},
      {55, 214, 0, 0},   {60, 192, 0, 0},      {65, 255, 0, 255},    {70, 153, 85, 201},  {75, 235, 235, 235},
  }};
  std::vector<ColorStop> stops;
  for (const Row& row : kRows) {
    const Rgba8 c{row.r, row.g, row.b, 255};
    stops.push_back(ColorStop{static_cast<double>(row.dbz), c, c});
  }
  return ColorTable("NWS reflectivity", "dBZ", std::move(stops));
}

ColorTable cividisTable(double minValue, double maxValue) {
  assert(std::isfinite(minValue) && std::isfinite(maxValue) && minValue < maxValue);
  // Cividis (Nunez, Anderton & Renslow 2018, PLoS ONE 13(7): e0199239), the published 256-entry
  // RGB table in [0, 1] as distributed with matplotlib: entries 0, 16, ..., 240 and 255.
  struct Point {
    int entry;
    double r, g, b;
  };
  static constexpr std::array<Point, 17> kPoints{{
      {0, 0.000000, 0.135112, 0.304751},
      {16, 0.000000, 0.178802, 0.414764},
      {32, 0.103401, 0.220406, 0.435790},
      {48, 0.195057, 0.264372, 0.425924},
      {64, 0.263738, 0.307831, 0.422789},
      {80, 0.324250, 0.351289, 0.426250},
      {96, 0.380830, 0.395164, 0.435653},
      {112, 0.435168, 0.439763, 0.451134},
      {128, 0.488697, 0.485318, 0.471008},
      {144, 0.547840, 0.531895, 0.471704},
      {160, 0.609105, 0.579816, 0.463638},
      {176, 0.671991, 0.629316, 0.448018},
      {192, 0.736488, 0.680629, 0.424028},
      {208, 0.802667, 0.733978, 0.390153},
      {224, 0.870717, 0.789572, 0.343333},
      {240, 0.941147, 0.847530, 0.275815},
      {255, 0.995737, 0.909344, 0.217772},
  }};
  auto to8 = [](double c) { return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
  std::vector<ColorStop> stops;
  for (std::size_t k = 0; k < kPoints.size(); ++k) {
    const Point& p = kPoints[k];
    const Point& q = kPoints[std::min(k + 1, kPoints.size() - 1)];
    const double value = minValue + (p.entry / 255.0) * (maxValue - minValue);
    stops.push_back(
        ColorStop{value, Rgba8{to8(p.r), to8(p.g), to8(p.b), 255}, Rgba8{to8(q.r), to8(q.g), to8(q.b), 255}});
  }
  return ColorTable("cividis", "", std::move(stops));
}

namespace {

// An opaque table over [minValue, maxValue] from colours at equally spaced positions, linear
// between them.
ColorTable evenlySpacedTable(const char* name, const std::vector<Rgba8>& colors, double minValue, double maxValue) {
  assert(std::isfinite(minValue) && std::isfinite(maxValue) && minValue < maxValue && colors.size() >= 2);
  std::vector<ColorStop> stops;
  const std::size_t n = colors.size();
  for (std::size_t k = 0; k < n; ++k) {
    const double value = minValue + static_cast<double>(k) / static_cast<double>(n - 1) * (maxValue - minValue);
    stops.push_back(ColorStop{value, colors[k], colors[std::min(k + 1, n - 1)]});
  }
  return ColorTable(name, "", std::move(stops));
}

}  // namespace

ColorTable viridisTable(double minValue, double maxValue) {
  // Viridis (van der Walt & Smith, matplotlib 2.0; CC0), the 9 equally spaced colours of the
  // published 256-entry table.
  return evenlySpacedTable("viridis",
                           {{0x44, 0x01, 0x54, 255},
                            {0x47, 0x2d, 0x7b, 255},
                            {0x3b, 0x52, 0x8b, 255},
                            {0x2c, 0x72, 0x8e, 255},
                            {0x21, 0x91, 0x8c, 255},
                            {0x28, 0xae, 0x80, 255},
                            {0x5e, 0xc9, 0x62, 255},
                            {0xad, 0xdc, 0x30, 255},
                            {0xfd, 0xe7, 0x25, 255}},
                           minValue, maxValue);
}

ColorTable turboTable(double minValue, double maxValue) {
  // Turbo (Mikhailov 2019, Google AI blog "Turbo, an improved rainbow colormap"), from its
  // published degree-5 polynomial approximation (R, G, B of x in [0, 1]), sampled at 17 points.
  std::vector<Rgba8> colors;
  auto poly = [](double x, const std::array<double, 6>& c) {
    return c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))));
  };
  constexpr std::array<double, 6> kR{0.13572138, 4.61539260, -42.66032258, 132.13108234, -152.94239396, 59.28637943};
  constexpr std::array<double, 6> kG{0.09140261, 2.19418839, 4.84296658, -14.18503333, 4.27729857, 2.82956604};
  constexpr std::array<double, 6> kB{0.10667330, 12.64194608, -60.58204836, 110.36276771, -89.90310912, 27.34824973};
  auto to8 = [](double c) { return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
  for (int k = 0; k <= 16; ++k) {
    const double x = k / 16.0;
    colors.push_back(Rgba8{to8(poly(x, kR)), to8(poly(x, kG)), to8(poly(x, kB)), 255});
  }
  return evenlySpacedTable("turbo", colors, minValue, maxValue);
}

ColorTable grayscaleTable(double minValue, double maxValue) {
  return evenlySpacedTable("grayscale", {{0, 0, 0, 255}, {255, 255, 255, 255}}, minValue, maxValue);
}

ColorTable greensTable(double minValue, double maxValue) {
  // A single-hue sequential green (ColorBrewer "Greens", 9 classes: Brewer, colorbrewer2.org).
  return evenlySpacedTable("greens",
                           {{0xf7, 0xfc, 0xf5, 255},
                            {0xe5, 0xf5, 0xe0, 255},
                            {0xc7, 0xe9, 0xc0, 255},
                            {0xa1, 0xd9, 0x9b, 255},
                            {0x74, 0xc4, 0x76, 255},
                            {0x41, 0xab, 0x5d, 255},
                            {0x23, 0x8b, 0x45, 255},
                            {0x00, 0x6d, 0x2c, 255},
                            {0x00, 0x44, 0x1b, 255}},
                           minValue, maxValue);
}

// ---------------------------------------------------------------------------------------------
// .pal parsing

namespace {

// Whitespace- (or comma-) separated numbers; false on anything that is not a finite number.
bool parseNumbers(std::string_view s, std::vector<double>* out, std::string* bad) {
  out->clear();
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (std::isspace(static_cast<unsigned char>(s[i])) || s[i] == ',')) ++i;
    if (i >= s.size()) break;
    std::size_t j = i;
    while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j])) && s[j] != ',') ++j;
    std::string_view tok = s.substr(i, j - i);
    if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
    double v = 0.0;
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (r.ec != std::errc() || r.ptr != tok.data() + tok.size() || !std::isfinite(v)) {
      *bad = std::string(s.substr(i, j - i));
      return false;
    }
    out->push_back(v);
    i = j;
  }
  return true;
}

}  // namespace

Result<ColorTable> parsePalText(std::string_view text, const std::string& nameForErrors) {
  std::string product, units;
  double scale = 1.0, offset = 0.0;
  struct Pending {
    double value;
    Rgba8 start;
    std::optional<Rgba8> end;
    bool solid;
    int line;
  };
  std::vector<Pending> entries;

  int lineNo = 0;
  std::size_t pos = 0;
  std::vector<double> nums;
  while (pos <= text.size()) {
    const std::size_t eol = text.find('\n', pos);
    std::string_view line = text.substr(pos, eol == std::string_view::npos ? std::string_view::npos : eol - pos);
    pos = eol == std::string_view::npos ? text.size() + 1 : eol + 1;
    ++lineNo;
    const auto where = [&](const std::string& why) {
      return makeError(nameForErrors + ":" + std::to_string(lineNo) + ": " + why);
    };
    if (const std::size_t c = line.find(';'); c != std::string_view::npos) line = line.substr(0, c);
    line = trimAscii(line);
    if (line.empty()) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) return where("expected 'Key: value', got '" + std::string(line) + "'");
    const std::string key = toLowerAscii(trimAscii(line.substr(0, colon)));
    const std::string_view rest = trimAscii(line.substr(colon + 1));

    if (key == "product") {
      product = std::string(rest);
      continue;
    }
    if (key == "units") {
      units = std::string(rest);
      continue;
    }
    std::string bad;
    if (!parseNumbers(rest, &nums, &bad)) return where(key + ": '" + bad + "' is not a number");
    if (key == "scale" || key == "offset" || key == "step" || key == "decimals") {
      if (nums.size() != 1) return where(key + " needs 1 number, got " + std::to_string(nums.size()));
      if (key == "scale") {
        if (nums[0] == 0.0) return where("Scale must not be 0");
        scale = nums[0];
      } else if (key == "offset") {
        offset = nums[0];
      }
      continue;  // Step and Decimals only affect a legend
    }
    if (key == "rf" || key == "nd") {  // range-folded / no-data colours: not drawn on the cone
      if (nums.size() != 3 && nums.size() != 4)
        return where(key + " needs 3 or 4 numbers, got " + std::to_string(nums.size()));
      continue;
    }
    const bool hasAlpha = key == "color4" || key == "solidcolor4";
    const bool solid = key == "solidcolor" || key == "solidcolor4";
    if (key != "color" && key != "color4" && key != "solidcolor" && key != "solidcolor4") {
      return where("unknown key '" + std::string(trimAscii(line.substr(0, colon))) + "'");
    }
    const std::size_t n = hasAlpha ? 4 : 3;
    const std::size_t allowedA = 1 + n, allowedB = solid ? 1 + n : 1 + 2 * n;
    if (nums.size() != allowedA && nums.size() != allowedB) {
      const std::string counts = allowedA == allowedB ? std::to_string(allowedA)
                                                      : std::to_string(allowedA) + " or " + std::to_string(allowedB);
      return where(std::string(trimAscii(line.substr(0, colon))) + " needs " + counts + " numbers, got " +
                   std::to_string(nums.size()));
    }
    auto channel = [&](std::size_t i, std::uint8_t* outC) -> bool {
      const double c = nums[i];
      if (c < 0.0 || c > 255.0 || c != std::floor(c)) return false;
      *outC = static_cast<std::uint8_t>(c);
      return true;
    };
    auto colour = [&](std::size_t first, Rgba8* c) -> bool {
      c->a = 255;
      return channel(first, &c->r) && channel(first + 1, &c->g) && channel(first + 2, &c->b) &&
             (!hasAlpha || channel(first + 3, &c->a));
    };
    Pending p{nums[0], {}, std::nullopt, solid, lineNo};
    if (!colour(1, &p.start)) return where("colour channels must be integers 0..255");
    if (nums.size() == allowedB && !solid) {
      Rgba8 e;
      if (!colour(1 + n, &e)) return where("colour channels must be integers 0..255");
      p.end = e;
    }
    if (!entries.empty() && !(p.value > entries.back().value)) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "value %g is not above the previous entry's %g (line %d): values must increase",
                    p.value, entries.back().value, entries.back().line);
      return where(buf);
    }
    entries.push_back(p);
  }
  if (entries.empty()) return makeError(nameForErrors + ": no Color/Color4/SolidColor lines: not a colour table");

  std::vector<ColorStop> stops;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const Pending& e = entries[i];
    Rgba8 end = e.start;
    if (!e.solid) {
      if (e.end) end = *e.end;
      else if (i + 1 < entries.size()) end = entries[i + 1].start;
    }
    stops.push_back(ColorStop{e.value, e.start, end});
  }
  return ColorTable(product.empty() ? nameForErrors : product, units, std::move(stops), scale, offset);
}

Result<ColorTable> readPalFile(const std::string& path) {
  constexpr std::streamoff kMaxBytes = 1 << 20;
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open colour table");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return makeError(path + ": cannot read colour table");
  if (size > kMaxBytes) return makeError(path + ": colour table larger than 1 MiB: not a .pal file");
  in.seekg(0);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), size)) return makeError(path + ": cannot read colour table");
  return parsePalText(text, path);
}

}  // namespace atmoglobe::volume
