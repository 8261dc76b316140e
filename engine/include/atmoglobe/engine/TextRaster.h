#pragma once
// Text drawn into images with a real TrueType font: GL-free, for every picture that carries
// words: slice plots, the colour keys and titles of rendered pictures (Legend.h), and marker
// labels, which MarkerRendererGL.h uploads as GL textures from the same coverage masks.
//
// The font: DejaVu Sans from Debian `fonts-dejavu-core` (kDejaVuSansPath), rasterised by
// stb_truetype (Debian libstb, the implementation compiled into libstb). Text is UTF-8 (the
// degree sign, the micro sign and the like are in DejaVu); glyphs are placed at sub-pixel pen
// positions with the font's kerning, anti-aliased (8-bit coverage).
//
// The halo: the text's coverage dilated by a disc of haloRadiusPx (the largest coverage within
// that distance), drawn under the text in the halo colour, so labels read over imagery and data.
//
// Pixels: origin at the top-left, y down (the README's convention); (x, y) of drawText is the
// anchor point, continuous (the pixel (i, j) covers [i, i + 1) x [j, j + 1)).
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/Result.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::engine {

/// DejaVu Sans as Debian installs it (package fonts-dejavu-core).
inline constexpr const char* kDejaVuSansPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// 8-bit coverage of a piece of text (0 = none, 255 = full), with where its pen started.
struct TextMask {
  int width = 0, height = 0;
  std::vector<std::uint8_t> coverage;  ///< width x height, row 0 at the top
  double penX = 0.0;                   ///< pen start (left end of the baseline) in mask pixels
  double baselineY = 0.0;              ///< baseline in mask pixels (y down)
  double advancePx = 0.0;              ///< pen advance of the whole text (its width)
  std::uint8_t at(int x, int y) const {
    return coverage[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
  }
};

class Font {
 public:
  /// Reads a TrueType file (at most 64 MiB). Errors name the file: missing ("...: no such file;
  /// install Debian fonts-dejavu-core" for the default font), unreadable, not a TrueType font.
  static Result<std::shared_ptr<const Font>> load(const std::string& path);
  /// DejaVu Sans (kDejaVuSansPath), loaded once per process (thread-safe).
  static const Result<std::shared_ptr<const Font>>& dejaVuSans();

  const std::string& path() const { return path_; }

  /// Vertical metrics at a pixel height (ascent - descent = pixelHeight, stb's convention):
  /// ascent above the baseline (> 0), descent below it (< 0), the font's line gap.
  struct Metrics {
    double ascentPx = 0.0, descentPx = 0.0, lineGapPx = 0.0;
    double lineHeightPx() const { return ascentPx - descentPx + lineGapPx; }
  };
  Metrics metrics(double pixelHeight) const;
  /// Advance width of `utf8` (px), kerning included.
  double textWidthPx(std::string_view utf8, double pixelHeight) const;
  /// The text's coverage, with `marginPx` empty pixels on every side (room for a halo).
  TextMask rasterize(std::string_view utf8, double pixelHeight, int marginPx = 0) const;

  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

 private:
  Font() = default;
  struct Impl;
  std::string path_;
  std::vector<unsigned char> bytes_;
  std::unique_ptr<Impl> impl_;
};

/// Decodes UTF-8 into code points; invalid bytes become U+FFFD.
std::vector<char32_t> decodeUtf8(std::string_view utf8);

/// The coverage dilated by a disc of radius `radiusPx` (each pixel: the largest coverage of any
/// pixel whose centre lies within radiusPx of its centre). Same size as the mask.
std::vector<std::uint8_t> dilateCoverage(const TextMask& mask, double radiusPx);

struct TextStyle {
  double pixelHeight = 14.0;  ///< ascent - descent (px)
  glm::u8vec4 color{0, 0, 0, 255};
  glm::u8vec4 haloColor{255, 255, 255, 255};
  double haloRadiusPx = 0.0;  ///< 0: no halo
};

enum class HAlign { Left, Center, Right };
/// Baseline: y is the baseline; Top: the ascent line; Middle: halfway between ascent and
/// baseline (the middle of capitals and digits, near enough); Bottom: the descent line.
enum class VAlign { Baseline, Top, Middle, Bottom };
/// Horizontal text, or turned 90 degrees counter-clockwise (read bottom to top: a y-axis label).
enum class TextDirection { Horizontal, Up };

/// Draws `utf8` into `image` (straight-alpha "over" compositing: halo first, then the text),
/// anchored at (x, y) as halign/valign say, in the text's own frame (for TextDirection::Up the
/// anchor's "left" is the bottom end of the turned text). Pixels outside the image are clipped.
void drawText(globe::ImageRGBA8& image, const Font& font, std::string_view utf8, double x, double y,
              const TextStyle& style, HAlign halign = HAlign::Left, VAlign valign = VAlign::Baseline,
              TextDirection direction = TextDirection::Horizontal);

/// Composites `color` with coverage-scaled alpha over pixel (x, y) (straight alpha; clipped).
void blendPixel(globe::ImageRGBA8& image, int x, int y, glm::u8vec4 color, std::uint8_t coverage);

}  // namespace atmoglobe::engine
