// Colour tables: NWS reflectivity colours, cividis samples, GR/WCT .pal parsing and its errors.
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace atmoglobe;
using namespace atmoglobe::volume;

namespace {

::testing::AssertionResult sameColor(Rgba8 got, int r, int g, int b, int a) {
  if (got.r == r && got.g == g && got.b == b && got.a == a) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got (" << int(got.r) << "," << int(got.g) << "," << int(got.b) << ","
                                       << int(got.a) << "), want (" << r << "," << g << "," << b << "," << a << ")";
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::filesystem::path dir = std::filesystem::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "colortable";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace

// Reference: the NWS reflectivity colours (5-75 dBZ as in the NWS/AWIPS table that MetPy ships as
// its NWSReflectivity colortable; -20..0 dBZ muted clear-air cyans), dBZ: R G B. NWS products
// step: a value takes the colour of the 5 dBZ band it falls in.
TEST(ColorTable, NwsReflectivityStepsAt5Dbz) {
  const ColorTable t = nwsReflectivityTable();
  EXPECT_TRUE(sameColor(t.map(-20.0f), 50, 79, 79, 255));
  EXPECT_TRUE(sameColor(t.map(0.0f), 187, 255, 255, 255));
  EXPECT_TRUE(sameColor(t.map(20.0f), 0, 255, 0, 255));
  EXPECT_TRUE(sameColor(t.map(34.99f), 0, 144, 0, 255));  // still the 30 dBZ band
  EXPECT_TRUE(sameColor(t.map(35.0f), 255, 255, 0, 255));
  EXPECT_TRUE(sameColor(t.map(37.0f), 255, 255, 0, 255));  // stepped, not blended toward 40
  EXPECT_TRUE(sameColor(t.map(47.5f), 255, 144, 0, 255));
  EXPECT_TRUE(sameColor(t.map(65.0f), 255, 0, 255, 255));
  EXPECT_TRUE(sameColor(t.map(75.0f), 235, 235, 235, 255));
  EXPECT_TRUE(sameColor(t.map(90.0f), 235, 235, 235, 255));  // above the top: the last colour
}

TEST(ColorTable, BelowTableNoEchoAndNoDataAreTransparent) {
  const ColorTable t = nwsReflectivityTable();
  EXPECT_TRUE(sameColor(t.map(-20.01f), 0, 0, 0, 0));
  EXPECT_TRUE(sameColor(t.map(-32.0f), 0, 0, 0, 0));
  EXPECT_TRUE(sameColor(t.map(kNoEcho), 0, 0, 0, 0));
  EXPECT_TRUE(sameColor(t.map(kNoData), 0, 0, 0, 0));
}

// Reference: the published cividis table (Nunez et al. 2018) entry 0 = (0.000000, 0.135112,
// 0.304751), entry 128 = (0.488697, 0.485318, 0.471008), entry 255 = (0.995737, 0.909344,
// 0.217772), times 255 and rounded by hand: (0, 34, 78), (125, 124, 120), (254, 232, 56). The
// 8-bit end points also match an independent 8-bit listing of cividis: (0,34,78) ... (254,232,56).
TEST(ColorTable, CividisEndsAndMiddle) {
  const ColorTable t = cividisTable(-10.0, 70.0);
  EXPECT_TRUE(sameColor(t.map(-10.0f), 0, 34, 78, 255));
  EXPECT_TRUE(sameColor(t.map(70.0f), 254, 232, 56, 255));
  const double mid = -10.0 + 128.0 / 255.0 * 80.0;  // where entry 128 sits
  EXPECT_TRUE(sameColor(t.map(static_cast<float>(mid)), 125, 124, 120, 255));
  EXPECT_TRUE(sameColor(t.map(-10.5f), 0, 0, 0, 0));
  // Monotone lightness proxy: the green channel rises from end to end for this map.
  int lastG = -1;
  for (int i = 0; i <= 80; ++i) {
    const Rgba8 c = t.map(static_cast<float>(-10 + i));
    EXPECT_GE(c.g, lastG) << "at " << -10 + i;
    lastG = c.g;
  }
}

TEST(ColorTable, PalFileColorsGradientsAndSolids) {
  const std::string path = writeTemp("good.pal",
                                     "; a test table written by hand\n"
                                     "Product: BR\n"
                                     "Units: DBZ\n"
                                     "Step: 5\n"
                                     "\n"
                                     "Color: 10  0 0 0   100 100 100   ; explicit gradient\n"
                                     "color: 20  200 0 0                ; blends to the next entry\n"
                                     "SolidColor: 30 0 0 200\n"
                                     "Color4: 40 10 20 30 128\n"
                                     "RF: 119 0 125\n");
  Result<ColorTable> t = readPalFile(path);
  ASSERT_TRUE(t.ok()) << t.error();
  EXPECT_EQ(t->name(), "BR");
  EXPECT_EQ(t->units(), "DBZ");
  EXPECT_TRUE(sameColor(t->map(9.9f), 0, 0, 0, 0));
  EXPECT_TRUE(sameColor(t->map(10.0f), 0, 0, 0, 255));
  EXPECT_TRUE(sameColor(t->map(15.0f), 50, 50, 50, 255));   // half way 0 -> 100
  EXPECT_TRUE(sameColor(t->map(25.0f), 100, 0, 100, 255));  // half way (200,0,0) -> (0,0,200)
  EXPECT_TRUE(sameColor(t->map(35.0f), 0, 0, 200, 255));    // solid band
  EXPECT_TRUE(sameColor(t->map(39.9f), 0, 0, 200, 255));
  EXPECT_TRUE(sameColor(t->map(55.0f), 10, 20, 30, 128));  // last entry, with alpha
}

TEST(ColorTable, PalScaleAndOffsetConvertDataUnits) {
  // Table in knots, data in m/s: table value = data * 1.94384 + 0.
  Result<ColorTable> t =
      parsePalText("Units: KTS\nScale: 1.94384\nSolidColor: -10 0 0 255\nSolidColor: 10 255 0 0\n", "v.pal");
  ASSERT_TRUE(t.ok()) << t.error();
  EXPECT_TRUE(sameColor(t->map(4.0f), 0, 0, 255, 255));  // 7.8 kt
  EXPECT_TRUE(sameColor(t->map(6.0f), 255, 0, 0, 255));  // 11.7 kt
  Result<ColorTable> o = parsePalText("Offset: 20\nSolidColor: 0 1 2 3\nSolidColor: 30 4 5 6\n", "o.pal");
  ASSERT_TRUE(o.ok()) << o.error();
  EXPECT_TRUE(sameColor(o->map(5.0f), 1, 2, 3, 255));   // 25
  EXPECT_TRUE(sameColor(o->map(10.0f), 4, 5, 6, 255));  // 30
}

TEST(ColorTable, PalErrorsNameFileAndLine) {
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"Units: DBZ\n\nColor: 10 0 0\n", "bad.pal:3: Color needs 4 or 7 numbers, got 3"},
      {"Color: 10 0 0 0\nColor: 10 1 1 1\n", "bad.pal:2: value 10 is not above the previous entry's 10"},
      {"Color: 10 0 300 0\n", "bad.pal:1: colour channels must be integers 0..255"},
      {"Color: 10 0 0 0\nColour: 20 1 1 1\n", "bad.pal:2: unknown key 'Colour'"},
      {"; only a comment\nColor: x 0 0 0\n", "bad.pal:2: color: 'x' is not a number"},
      {"Color4: 10 0 0 0\n", "bad.pal:1: Color4 needs 5 or 9 numbers, got 4"},
      {"just words\n", "bad.pal:1: expected 'Key: value'"},
      {"Scale: 0\nColor: 1 0 0 0\n", "bad.pal:1: Scale must not be 0"},
      {"Product: BR\n", "bad.pal: no Color/Color4/SolidColor lines"},
  };
  for (const Case& c : cases) {
    Result<ColorTable> t = parsePalText(c.text, "bad.pal");
    ASSERT_FALSE(t.ok()) << c.text;
    EXPECT_NE(t.error().find(c.expect), std::string::npos) << "got: " << t.error() << "\nwant: " << c.expect;
  }
  Result<ColorTable> missing = readPalFile("/nonexistent/table.pal");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("/nonexistent/table.pal"), std::string::npos);
  // The file path and the line number reach the message from disk too.
  const std::string path = writeTemp("bad-line.pal", "Color: 0 0 0 0\nColor: 5 1 2\n");
  Result<ColorTable> fromDisk = readPalFile(path);
  ASSERT_FALSE(fromDisk.ok());
  EXPECT_NE(fromDisk.error().find(path + ":2:"), std::string::npos) << fromDisk.error();
}

// The sequential and rainbow tables: published end colours, lightness running the right way
// (viridis, grayscale up; greens down), turbo from blue through green to red, and model variables
// given them by meaning.
TEST(ColorTable, SequentialAndRainbowTables) {
  using atmoglobe::volume::Rgba8;
  auto lightness = [](Rgba8 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  const auto viridis = atmoglobe::volume::viridisTable(0.0, 1.0);
  EXPECT_EQ(viridis.map(0.0f), (Rgba8{0x44, 0x01, 0x54, 255}));
  EXPECT_EQ(viridis.map(1.0f), (Rgba8{0xfd, 0xe7, 0x25, 255}));
  const auto gray = atmoglobe::volume::grayscaleTable(-5.0, 5.0);
  const auto greens = atmoglobe::volume::greensTable(0.0, 10.0);
  double prevV = -1.0, prevG = -1.0, prevGreens = 1e9;
  for (int k = 0; k <= 20; ++k) {
    const float x = static_cast<float>(k) / 20.0f;
    const double v = lightness(viridis.map(x)), g = lightness(gray.map(-5.0f + 10.0f * x)),
                 gr = lightness(greens.map(10.0f * x));
    EXPECT_GT(v, prevV) << x;
    EXPECT_GE(g, prevG) << x;
    EXPECT_LT(gr, prevGreens) << x;
    prevV = v;
    prevG = g;
    prevGreens = gr;
  }
  EXPECT_EQ(gray.map(-5.0f), (Rgba8{0, 0, 0, 255}));
  EXPECT_EQ(gray.map(5.0f), (Rgba8{255, 255, 255, 255}));
  const auto turbo = atmoglobe::volume::turboTable(0.0, 1.0);
  const Rgba8 low = turbo.map(0.15f), mid = turbo.map(0.5f), high = turbo.map(0.9f);
  EXPECT_GT(low.b, low.r);
  EXPECT_GT(mid.g, mid.r);
  EXPECT_GT(mid.g, mid.b);
  EXPECT_GT(high.r, high.g);
  EXPECT_GT(high.r, high.b);
  // Below the range: transparent, as every table.
  EXPECT_EQ(turbo.map(-0.1f).a, 0);
}

TEST(ColorTable, ModelVariablesGetColoursByMeaning) {
  using atmoglobe::volume::defaultColorsFor;
  using atmoglobe::volume::FieldInfo;
  EXPECT_EQ(defaultColorsFor(FieldInfo{"t", "K", "air_temperature"}), "turbo");
  EXPECT_EQ(defaultColorsFor(FieldInfo{"T2", "K", ""}), "turbo");
  EXPECT_EQ(defaultColorsFor(FieldInfo{"rhumidity", "%", "relative_humidity"}), "greens");
  EXPECT_EQ(defaultColorsFor(FieldInfo{"QVAPOR", "kg kg-1", ""}), "greens");
  EXPECT_EQ(defaultColorsFor(FieldInfo{"QCLOUD", "kg kg-1", ""}), "grayscale");
  EXPECT_EQ(defaultColorsFor(FieldInfo{"dbz", "dBZ", ""}), "NWS");
  // A model's W is not a radar's spectrum width: its standard_name says so.
  EXPECT_EQ(defaultColorsFor(FieldInfo{"W", "m s-1", "upward_air_velocity"}), "viridis");
  EXPECT_EQ(defaultColorsFor(FieldInfo{"VRADH", "m/s", ""}), "auto") << "a radar velocity: by its kind";
  EXPECT_EQ(defaultColorsFor(FieldInfo{"foo", "1", ""}), "viridis");
  // "auto" on a model variable uses that table over the variable's values.
  auto t = atmoglobe::volume::transferForField("auto", FieldInfo{"t", "K", "air_temperature"}, NAN, {210.0, 300.0});
  ASSERT_TRUE(t);
  EXPECT_EQ(t->colors.name(), "turbo");
  EXPECT_DOUBLE_EQ(t->colors.stops().front().value, 210.0);
  EXPECT_DOUBLE_EQ(t->colors.stops().back().value, 300.0);
}
