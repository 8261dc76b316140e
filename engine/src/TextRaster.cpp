// TrueType text into images (TextRaster.h). stb_truetype's implementation is compiled into
// Debian's libstb (linked as PkgConfig::STB): only the declarations are included here.
#include <atmoglobe/engine/TextRaster.h>

#include <stb/stb_truetype.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>

namespace atmoglobe::engine {

struct Font::Impl {
  stbtt_fontinfo info{};
};

Font::~Font() = default;

std::vector<char32_t> decodeUtf8(std::string_view s) {
  std::vector<char32_t> out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra = 0;
    char32_t cp = 0;
    if (c < 0x80) {
      cp = c;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1;
      cp = c & 0x1Fu;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2;
      cp = c & 0x0Fu;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3;
      cp = c & 0x07u;
    } else {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    bool valid = i + static_cast<std::size_t>(extra) < s.size();
    for (int k = 1; valid && k <= extra; ++k) {
      const auto cc = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
      if ((cc & 0xC0) != 0x80) {
        valid = false;
        break;
      }
      cp = (cp << 6) | (cc & 0x3Fu);
    }
    if (!valid) {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    out.push_back(cp);
    i += static_cast<std::size_t>(extra) + 1;
  }
  return out;
}

Result<std::shared_ptr<const Font>> Font::load(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    std::string hint = path == kDejaVuSansPath ? " (install the Debian package fonts-dejavu-core)" : "";
    return makeError(path + ": no such font file" + hint);
  }
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return makeError(path + ": cannot read the font file: " + ec.message());
  if (size > (std::uintmax_t{64} << 20)) return makeError(path + ": font file larger than 64 MiB");
  std::ifstream in(path, std::ios::binary);
  std::shared_ptr<Font> font(new Font());
  font->path_ = path;
  font->bytes_.resize(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(font->bytes_.data()), static_cast<std::streamsize>(size))) {
    return makeError(path + ": cannot read the font file");
  }
  font->impl_ = std::make_unique<Impl>();
  const int offset = stbtt_GetFontOffsetForIndex(font->bytes_.data(), 0);
  if (size < 12 || offset < 0 || !stbtt_InitFont(&font->impl_->info, font->bytes_.data(), offset)) {
    return makeError(path + ": not a TrueType font stb_truetype can read");
  }
  return std::shared_ptr<const Font>(std::move(font));
}

const Result<std::shared_ptr<const Font>>& Font::dejaVuSans() {
  static const Result<std::shared_ptr<const Font>> font = load(kDejaVuSansPath);
  return font;
}

Font::Metrics Font::metrics(double pixelHeight) const {
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&impl_->info, &ascent, &descent, &gap);
  const double scale = stbtt_ScaleForPixelHeight(&impl_->info, static_cast<float>(pixelHeight));
  return {ascent * scale, descent * scale, gap * scale};
}

namespace {
struct PlacedGlyph {
  int glyph = 0;
  double penX = 0.0;
};
// Glyphs and their pen positions (px) along a baseline from 0; the total advance in *advance.
std::vector<PlacedGlyph> layoutGlyphs(const stbtt_fontinfo& info, std::string_view utf8, float scale, double* advance) {
  std::vector<PlacedGlyph> glyphs;
  double pen = 0.0;
  int previous = 0;
  for (char32_t cp : decodeUtf8(utf8)) {
    const int g = stbtt_FindGlyphIndex(&info, static_cast<int>(cp));
    if (previous) pen += double(scale) * stbtt_GetGlyphKernAdvance(&info, previous, g);
    glyphs.push_back({g, pen});
    int adv = 0, lsb = 0;
    stbtt_GetGlyphHMetrics(&info, g, &adv, &lsb);
    pen += double(scale) * adv;
    previous = g;
  }
  *advance = pen;
  return glyphs;
}
}  // namespace

double Font::textWidthPx(std::string_view utf8, double pixelHeight) const {
  double advance = 0.0;
  layoutGlyphs(impl_->info, utf8, stbtt_ScaleForPixelHeight(&impl_->info, static_cast<float>(pixelHeight)), &advance);
  return advance;
}

TextMask Font::rasterize(std::string_view utf8, double pixelHeight, int marginPx) const {
  const stbtt_fontinfo& info = impl_->info;
  const float scale = stbtt_ScaleForPixelHeight(&info, static_cast<float>(pixelHeight));
  double advance = 0.0;
  const std::vector<PlacedGlyph> glyphs = layoutGlyphs(info, utf8, scale, &advance);
  const Metrics m = metrics(pixelHeight);
  // The box relative to the pen start on the baseline (y down): the line's ascent..descent and
  // 0..advance, grown to every glyph's bitmap box.
  int minX = 0, maxX = static_cast<int>(std::ceil(advance));
  int minY = -static_cast<int>(std::ceil(m.ascentPx)), maxY = static_cast<int>(std::ceil(-m.descentPx));
  struct Box {
    int x0, y0, x1, y1, ix;
    float shift;
  };
  std::vector<Box> boxes;
  for (const PlacedGlyph& g : glyphs) {
    const int ix = static_cast<int>(std::floor(g.penX));
    const auto shift = static_cast<float>(g.penX - ix);
    Box b{0, 0, 0, 0, ix, shift};
    stbtt_GetGlyphBitmapBoxSubpixel(&info, g.glyph, scale, scale, shift, 0.0f, &b.x0, &b.y0, &b.x1, &b.y1);
    minX = std::min(minX, ix + b.x0);
    maxX = std::max(maxX, ix + b.x1);
    minY = std::min(minY, b.y0);
    maxY = std::max(maxY, b.y1);
    boxes.push_back(b);
  }
  TextMask mask;
  mask.width = maxX - minX + 2 * marginPx;
  mask.height = maxY - minY + 2 * marginPx;
  mask.coverage.assign(static_cast<std::size_t>(mask.width) * static_cast<std::size_t>(mask.height), 0);
  mask.penX = marginPx - minX;
  mask.baselineY = marginPx - minY;
  mask.advancePx = advance;
  std::vector<unsigned char> bitmap;
  for (std::size_t k = 0; k < glyphs.size(); ++k) {
    const Box& b = boxes[k];
    const int w = b.x1 - b.x0, h = b.y1 - b.y0;
    if (w <= 0 || h <= 0) continue;
    bitmap.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    stbtt_MakeGlyphBitmapSubpixel(&info, bitmap.data(), w, h, w, scale, scale, b.shift, 0.0f, glyphs[k].glyph);
    const int ox = marginPx - minX + b.ix + b.x0, oy = marginPx - minY + b.y0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        auto& dst = mask.coverage[static_cast<std::size_t>(oy + y) * static_cast<std::size_t>(mask.width) +
                                  static_cast<std::size_t>(ox + x)];
        dst = std::max(dst,
                       bitmap[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)]);
      }
  }
  return mask;
}

std::vector<std::uint8_t> dilateCoverage(const TextMask& mask, double radiusPx) {
  std::vector<std::uint8_t> out(mask.coverage.size(), 0);
  const int r = static_cast<int>(std::floor(radiusPx));
  std::vector<std::pair<int, int>> disc;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (dx * dx + dy * dy <= radiusPx * radiusPx) disc.emplace_back(dx, dy);
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x) {
      const std::uint8_t c = mask.at(x, y);
      if (c == 0) continue;
      for (auto [dx, dy] : disc) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= mask.width || yy >= mask.height) continue;
        auto& o =
            out[static_cast<std::size_t>(yy) * static_cast<std::size_t>(mask.width) + static_cast<std::size_t>(xx)];
        o = std::max(o, c);
      }
    }
  return out;
}

void blendPixel(globe::ImageRGBA8& image, int x, int y, glm::u8vec4 color, std::uint8_t coverage) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height || coverage == 0) return;
  const double a = (color.a / 255.0) * (coverage / 255.0);
  if (a <= 0.0) return;
  std::uint8_t* p =
      &image
           .pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) *
                   4];
  const double da = p[3] / 255.0;
  const double oa = a + da * (1.0 - a);
  for (int c = 0; c < 3; ++c) {
    const double v = (color[c] * a + p[c] * da * (1.0 - a)) / std::max(oa, 1e-12);
    p[c] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
  }
  p[3] = static_cast<std::uint8_t>(std::lround(oa * 255.0));
}

void drawText(globe::ImageRGBA8& image, const Font& font, std::string_view utf8, double x, double y,
              const TextStyle& style, HAlign halign, VAlign valign, TextDirection direction) {
  if (utf8.empty()) return;
  const int margin = static_cast<int>(std::ceil(style.haloRadiusPx)) + 1;
  const TextMask mask = font.rasterize(utf8, style.pixelHeight, margin);
  const Font::Metrics m = font.metrics(style.pixelHeight);
  // The anchor in mask coordinates (continuous, y down).
  const double ax = mask.penX + (halign == HAlign::Left     ? 0.0
                                 : halign == HAlign::Center ? 0.5 * mask.advancePx
                                                            : mask.advancePx);
  const double ay = mask.baselineY - (valign == VAlign::Baseline ? 0.0
                                      : valign == VAlign::Top    ? m.ascentPx
                                      : valign == VAlign::Middle ? 0.5 * 0.75 * m.ascentPx  // cap height ~0.75 ascent
                                                                 : m.descentPx);
  const std::vector<std::uint8_t> halo = style.haloRadiusPx > 0.0 ? dilateCoverage(mask, style.haloRadiusPx)
                                                                  : std::vector<std::uint8_t>{};
  // Mask pixel (mx, my) -> image pixel. Horizontal: a shift by the anchor (rounded so glyphs keep
  // their rasterised sub-pixel placement). Up (90 deg counter-clockwise): (u, v) = (my, W - mx).
  const bool up = direction == TextDirection::Up;
  const double anchorU = up ? ay : ax, anchorV = up ? mask.width - ax : ay;
  const int ox = static_cast<int>(std::lround(x - anchorU)), oy = static_cast<int>(std::lround(y - anchorV));
  auto target = [&](int mx, int my, int* ix, int* iy) {
    if (up) {
      *ix = ox + my;
      *iy = oy + (mask.width - 1 - mx);
    } else {
      *ix = ox + mx;
      *iy = oy + my;
    }
  };
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 0 && halo.empty()) continue;
    for (int my = 0; my < mask.height; ++my)
      for (int mx = 0; mx < mask.width; ++mx) {
        const std::size_t k =
            static_cast<std::size_t>(my) * static_cast<std::size_t>(mask.width) + static_cast<std::size_t>(mx);
        const std::uint8_t c = pass == 0 ? halo[k] : mask.coverage[k];
        if (!c) continue;
        int ix = 0, iy = 0;
        target(mx, my, &ix, &iy);
        blendPixel(image, ix, iy, pass == 0 ? style.haloColor : style.color, c);
      }
  }
}

}  // namespace atmoglobe::engine
