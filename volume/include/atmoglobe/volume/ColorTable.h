#pragma once
// Colour tables: a field value (physical units, e.g. dBZ) -> 8-bit RGBA.
//
// GL-free; shared by the cone export and the volume renderer. A table is an increasing list of
// stops; the band [stop i, stop i+1) is painted from stop i's start colour to its end colour,
// linearly in RGBA with the position inside the band (start == end: a solid, stepped band).
// Values at or above the last stop take the last stop's start colour; values below the first stop,
// "no echo" (-inf) and "no data" (NaN) are fully transparent (0,0,0,0).
//
// Tables given:
//   - nwsReflectivityTable(): the NWS reflectivity colours, -20..75 dBZ in 5 dBZ bands (5-75 dBZ:
//     the NWS/AWIPS table, which MetPy also ships as its NWSReflectivity colortable; -20..0 dBZ:
//     muted clear-air cyans). STEPPED, not interpolated, as NWS products draw them: 37 dBZ -> the
//     35 dBZ colour.
//   - cividisTable(): a colour-vision-deficiency-friendly, perceptually uniform map, "cividis"
//     (Nunez, Anderton & Renslow 2018, PLoS ONE 13(7): e0199239), sampled at 17 of the 256
//     published control points (every 16th and the last), interpolated linearly between them.
//   - readPalFile(): GRLevelX / Weather and Climate Toolkit `.pal` colour tables.
#include <atmoglobe/globe/Result.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::volume {

struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0, a = 0;
  friend bool operator==(const Rgba8&, const Rgba8&) = default;
};
inline constexpr Rgba8 kTransparent{0, 0, 0, 0};

/// Start of one band: the band runs from `value` to the next stop's value.
struct ColorStop {
  double value = 0.0;  ///< band start, in table units (see ColorTable::scale/offset)
  Rgba8 start;         ///< colour at `value`
  Rgba8 end;           ///< colour approached at the next stop's value (== start: solid band)
  friend bool operator==(const ColorStop&, const ColorStop&) = default;
};

class ColorTable {
 public:
  ColorTable() = default;
  /// Precondition (asserted): stops strictly increasing in value, scale finite and non-zero.
  ColorTable(std::string name, std::string units, std::vector<ColorStop> stops, double scale = 1.0,
             double offset = 0.0);

  /// Colour of a field value in the field's units. Table units: value * scale + offset (the .pal
  /// convention, e.g. Scale 1.9438 turns m/s into knots). NaN / -inf / below the first stop:
  /// transparent. Exact (integer rounding of the interpolated channels: <= 0.5 of an 8-bit step).
  Rgba8 map(float value) const;

  const std::string& name() const { return name_; }
  const std::string& units() const { return units_; }
  const std::vector<ColorStop>& stops() const { return stops_; }
  double scale() const { return scale_; }
  double offset() const { return offset_; }
  bool empty() const { return stops_.empty(); }

 private:
  std::string name_;
  std::string units_;
  std::vector<ColorStop> stops_;
  double scale_ = 1.0;
  double offset_ = 0.0;
};

/// NWS reflectivity colours (dBZ; sources in the file comment): 20 stepped bands from -20 to 75
/// dBZ, opaque.
ColorTable nwsReflectivityTable();

/// Cividis over [minValue, maxValue] (field units; e.g. -10..70 dBZ), opaque. Below minValue:
/// transparent; above maxValue: the last colour. Control point k (published entry i_k of 256) sits
/// at minValue + (i_k / 255) * (maxValue - minValue); linear in between. Measured against all 256
/// published entries on the red channel (the one with a kink): at most 0.042 (11/255) off, at
/// entry 23 where red leaves 0. Precondition: min < max, both finite.
ColorTable cividisTable(double minValue, double maxValue);

/// Sequential and rainbow tables over [minValue, maxValue] (opaque; below: transparent; above:
/// the last colour; linear between equally spaced colours). Precondition: min < max, finite.
///  - viridis: perceptually uniform, colour-blind safe (matplotlib's default; 9 colours);
///  - turbo: a rainbow with monotonic lightness in each half, readable by the colour-blind far
///    better than jet (Google's published polynomial, 17 colours);
///  - grayscale: black to white;
///  - greens: a single-hue sequential green (ColorBrewer Greens, 9 classes).
ColorTable viridisTable(double minValue, double maxValue);
ColorTable turboTable(double minValue, double maxValue);
ColorTable grayscaleTable(double minValue, double maxValue);
ColorTable greensTable(double minValue, double maxValue);

/// Parses the text of a GR/WCT colour table. Recognised lines (keys case-insensitive, ';' starts
/// a comment, blank lines ignored):
///   Product: TEXT   Units: TEXT   Scale: X   Offset: X   Step: X   Decimals: N   RF: r g b
///   Color:  value r g b [r2 g2 b2]        (no second colour: blends to the next stop's colour)
///   Color4: value r g b a [r2 g2 b2 a2]
///   SolidColor:  value r g b              (a solid band up to the next stop)
///   SolidColor4: value r g b a
/// Channels are integers 0..255; values must increase from line to line. Errors name
/// `nameForErrors`, the line number and the reason ("f.pal:7: Color needs 4 or 7 numbers, got 3").
Result<ColorTable> parsePalText(std::string_view text, const std::string& nameForErrors);

/// Reads and parses a .pal file (at most 1 MiB). Errors name the file (and the line).
Result<ColorTable> readPalFile(const std::string& path);

}  // namespace atmoglobe::volume
