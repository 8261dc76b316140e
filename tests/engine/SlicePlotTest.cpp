// TrueType text (engine/TextRaster.h) and slice plots (engine/SlicePlot.h), GL-free: glyphs land
// where they are anchored with their halo, the plot's raster pixels carry the colour table's
// colours (no echo and no data apart), and a slice of the synthetic radar is written as a PNG of
// the size asked for.
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/engine/TextRaster.h>
#include <atmoglobe/map/MapLod.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/SliceSource.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace {
using namespace atmoglobe;

const engine::Font& font() {
  const auto& f = engine::Font::dejaVuSans();
  EXPECT_TRUE(f) << f.error();
  return **f;
}

// The bounding box of pixels that differ from `background`.
struct Box {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
Box inkBox(const globe::ImageRGBA8& img, glm::u8vec4 background) {
  Box b;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (img.at(x, y) != background) {
        b.x0 = std::min(b.x0, x);
        b.y0 = std::min(b.y0, y);
        b.x1 = std::max(b.x1, x);
        b.y1 = std::max(b.y1, y);
      }
  return b;
}
}  // namespace

TEST(TextRaster, MissingFontFileIsAClearError) {
  auto f = engine::Font::load("/no/such/dir/DejaVuSans.ttf");
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().find("/no/such/dir/DejaVuSans.ttf: no such font file"), std::string::npos) << f.error();
  const std::string notFont = ATMOGLOBE_TEST_OUTPUT_DIR + "/not_a_font.ttf";
  {
    std::FILE* out = std::fopen(notFont.c_str(), "wb");
    std::fputs("hello, not a font at all", out);
    std::fclose(out);
  }
  auto g = engine::Font::load(notFont);
  ASSERT_FALSE(g);
  EXPECT_NE(g.error().find("not a TrueType font"), std::string::npos) << g.error();
}

TEST(TextRaster, Utf8DecodesMultiByteCharactersAndReplacesBadBytes) {
  const std::vector<char32_t> cps = engine::decodeUtf8("35°N \xe2\x80\x93 \xff");
  ASSERT_EQ(cps.size(), 8u);
  EXPECT_EQ(cps[2], U'\u00b0');
  EXPECT_EQ(cps[5], U'\u2013');
  EXPECT_EQ(cps[7], U'\ufffd');
}

// Text anchored at (x, y): left/top anchoring puts the ink's top-left near the anchor; the ink
// is as wide as the advance says and as tall as the capitals; the halo
// widens it by its radius on every side; Up turns it (tall and narrow).
TEST(TextRaster, TextLandsWhereAnchoredWithItsHalo) {
  const engine::Font& f = font();
  const glm::u8vec4 bg{0, 0, 0, 255};
  const std::string text = "HEIGHT 10 KM";  // capitals and digits: no ascender above the caps, no descender
  const double px = 20.0;
  const double width = f.textWidthPx(text, px);
  const engine::Font::Metrics m = f.metrics(px);
  EXPECT_GT(width, 5.0 * px);  // 12 characters of ~0.5-0.7 em
  EXPECT_LT(width, 12.0 * px);
  EXPECT_NEAR(m.ascentPx - m.descentPx, px, 1e-3);  // stb's pixel height convention

  globe::ImageRGBA8 plain = globe::ImageRGBA8::filled(400, 100, bg);
  engine::drawText(plain, f, text, 50, 30, {px, {255, 255, 255, 255}, {0, 0, 0, 255}, 0.0}, engine::HAlign::Left,
                   engine::VAlign::Top);
  const Box b = inkBox(plain, bg);
  // The first glyph (H) starts at its left side bearing (~1.5 px at 20 px) right of the anchor;
  // capitals start below the ascent line by ascent - cap height (~0.25 ascent ~ 4 px).
  EXPECT_GE(b.x0, 50);
  EXPECT_LE(b.x0, 53);
  EXPECT_GE(b.y0, 31);
  EXPECT_LE(b.y0, 36);
  EXPECT_NEAR(b.x1 - b.x0 + 1, width, 4.0);  // bearings of the first and last glyph
  // The cap height: below the ascent (room for accents), above 0.7 of it in any Latin font.
  EXPECT_GE(b.y1 - b.y0 + 1, 0.7 * m.ascentPx);
  EXPECT_LE(b.y1 - b.y0 + 1, m.ascentPx);

  globe::ImageRGBA8 haloed = globe::ImageRGBA8::filled(400, 100, bg);
  engine::drawText(haloed, f, text, 50, 30, {px, {0, 0, 0, 255}, {255, 255, 255, 255}, 3.0}, engine::HAlign::Left,
                   engine::VAlign::Top);
  const Box h = inkBox(haloed, bg);
  EXPECT_NEAR(h.x0, b.x0 - 3, 1);
  EXPECT_NEAR(h.x1, b.x1 + 3, 1);
  EXPECT_NEAR(h.y0, b.y0 - 3, 1);
  // Black text on its white halo: the middle of the H's left stem is black, right beside it white.
  bool black = false, white = false;
  for (int x = h.x0; x < h.x0 + 12; ++x) {
    const glm::u8vec4 c = haloed.at(x, (b.y0 + b.y1) / 2);
    black = black || c.r < 40;
    white = white || c.r > 215;
  }
  EXPECT_TRUE(black && white);

  globe::ImageRGBA8 up = globe::ImageRGBA8::filled(100, 400, bg);
  engine::drawText(up, f, text, 30, 350, {px, {255, 255, 255, 255}, {0, 0, 0, 255}, 0.0}, engine::HAlign::Left,
                   engine::VAlign::Top, engine::TextDirection::Up);
  const Box u = inkBox(up, bg);
  EXPECT_NEAR(u.y1 - u.y0 + 1, width, 4.0);
  EXPECT_EQ(u.x1 - u.x0, b.y1 - b.y0);  // the same glyphs, turned
  EXPECT_LE(u.y1, 350);                 // reads upwards from the anchor
  EXPECT_GE(u.x0, 30);                  // the tops of the letters face left, towards the anchor
}

TEST(SlicePlot, NiceTicksAndCoordinateLabels) {
  EXPECT_EQ(engine::niceTicks(0.0, 113.0, 5), (std::vector<double>{0, 25, 50, 75, 100}));
  EXPECT_EQ(engine::niceTicks(-1.3, 1.3, 6), (std::vector<double>{-1, -0.5, 0, 0.5, 1}));
  EXPECT_EQ(engine::latitudeLabel(35.5, 1), "35.5°N");
  EXPECT_EQ(engine::latitudeLabel(-12.0, 0), "12°S");
  EXPECT_EQ(engine::longitudeLabel(-97.25, 2), "97.25°W");
  EXPECT_EQ(engine::longitudeLabel(190.0, 0), "170°W");  // continuous longitudes past 180
  EXPECT_EQ(engine::utcLabel("2020-05-01T21:00:00Z"), "2020-05-01 21:00:00 UTC");
}

// The raster in the plot: each plot pixel has the colour of the raster pixel under its centre
// (table RGB for echoes, white for no echo and for values below the table, grey or its hatching
// for no data); the image has the size asked for; the area keeps the CAPPI box's shape.
TEST(SlicePlot, RasterPixelsCarryTheTableColours) {
  volume::CappiSpec spec;
  spec.box = {34.0, 36.0, -98.0, -96.0};
  spec.datum = volume::SliceHeightDatum::Ellipsoid;
  auto probe = volume::SliceGeometry::cappi(spec, nullptr);
  ASSERT_TRUE(probe);
  const int width = 700, height = engine::cappiImageHeightFor(spec.box, width);
  auto layout = engine::layoutSlicePlot(*probe, width, height);
  ASSERT_TRUE(layout) << layout.error();
  // The shape at 35 deg: 2 deg of longitude are cos(35 deg) of 2 deg of latitude.
  EXPECT_NEAR(double(layout->width()) / layout->height(), std::cos(35.0 * M_PI / 180.0), 0.01);
  spec.columns = 4;
  spec.rows = 2;
  auto geometry = volume::SliceGeometry::cappi(spec, nullptr);
  ASSERT_TRUE(geometry);
  volume::SliceRaster r;
  r.columns = 4;
  r.rows = 2;
  const float nan = std::numeric_limits<float>::quiet_NaN(), noEcho = -std::numeric_limits<float>::infinity();
  r.values = {12.0f, 37.0f, 63.0f, noEcho, -40.0f, nan, 50.0f, 5.0f};
  engine::SlicePlotOptions o;
  o.widthPx = width;
  o.heightPx = height;
  o.colors = volume::nwsReflectivityTable();
  o.units = "dBZ";
  o.title = "TEST";
  auto img = engine::drawSlicePlot(r, *geometry, o);
  ASSERT_TRUE(img) << img.error();
  EXPECT_EQ(img->width, width);
  EXPECT_EQ(img->height, height);
  const engine::SlicePlotLayout L = *layout;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) {
      // The middle of raster pixel (i, j) in the plot, away from grid lines and text.
      const int x = L.left + static_cast<int>((i + 0.5) * L.width() / 4) + 3;
      const int y = L.top + static_cast<int>((j + 0.5) * L.height() / 2) + 3;
      const float v = r.at(i, j);
      const glm::u8vec4 got = img->at(x, y);
      if (std::isnan(v)) {
        EXPECT_TRUE(got == o.noDataColor || got == o.noDataHatchColor) << i << "," << j;
      } else if (std::isinf(v) || v < -20.0f) {
        EXPECT_EQ(got, o.noEchoColor) << i << "," << j;  // below the NWS table's -20 dBZ: as no echo
      } else {
        const volume::Rgba8 c = o.colors.map(v);
        EXPECT_EQ(got, glm::u8vec4(c.r, c.g, c.b, 255)) << i << "," << j << " value " << v;
      }
    }
  // Without SYNTHETIC, no red mark; with it, the top-right corner has the red text.
  auto countRed = [](const globe::ImageRGBA8& image) {
    int n = 0;
    for (int y = 0; y < 40; ++y)
      for (int x = image.width - 200; x < image.width; ++x) {
        const glm::u8vec4 c = image.at(x, y);
        n += c.r > 150 && c.g < 80 && c.b < 80;
      }
    return n;
  };
  EXPECT_EQ(countRed(*img), 0);
  o.synthetic = true;
  auto marked = engine::drawSlicePlot(r, *geometry, o);
  ASSERT_TRUE(marked);
  EXPECT_GT(countRed(*marked), 100);
  // Too small an image is refused.
  o.widthPx = 100;
  EXPECT_FALSE(engine::drawSlicePlot(r, *geometry, o));
}

// Map lines on a CAPPI: a meridian and a parallel given as a polyline land on the pixels their
// longitude and latitude map to (within the line's half-width plus antialiasing), in their colour,
// and nothing of them outside the plot area (the lines run from far outside the box). Longitudes
// given 360 deg away land at the same place.
TEST(SlicePlot, MapLinesLandOnTheirCoordinatesInsideThePlotOnly) {
  volume::CappiSpec spec;
  spec.box = {34.0, 36.0, -98.0, -96.0};
  spec.datum = volume::SliceHeightDatum::Ellipsoid;
  spec.columns = 4;
  spec.rows = 2;
  auto geometry = volume::SliceGeometry::cappi(spec, nullptr);
  ASSERT_TRUE(geometry);
  const int width = 700, height = engine::cappiImageHeightFor(spec.box, width);
  auto layout = engine::layoutSlicePlot(*geometry, width, height);
  ASSERT_TRUE(layout);
  const engine::SlicePlotLayout L = *layout;
  volume::SliceRaster r;
  r.columns = 4;
  r.rows = 2;
  r.values.assign(8, -std::numeric_limits<float>::infinity());  // no echo: white
  engine::SlicePlotOptions o;
  o.widthPx = width;
  o.heightPx = height;
  o.colors = volume::nwsReflectivityTable();
  const glm::u8vec4 blue{0, 0, 255, 255};
  map::GeoPolyline meridian, parallel;
  meridian.lonLatDeg = {{-96.7 + 360.0, 20.0}, {-96.7 + 360.0, 50.0}};  // 263.3 E: the same meridian
  parallel.lonLatDeg = {{-120.0, 35.3}, {-80.0, 35.3}};
  auto plain = engine::drawSlicePlot(r, *geometry, o);
  ASSERT_TRUE(plain) << plain.error();
  o.mapLines.push_back({{meridian, parallel}, blue, 1.0});
  auto img = engine::drawSlicePlot(r, *geometry, o);
  ASSERT_TRUE(img) << img.error();
  const double x = L.left + (-96.7 - -98.0) / 2.0 * L.width();
  const double y = L.bottom - (35.3 - 34.0) / 2.0 * L.height();
  // Every pixel the lines changed, by where it is.
  int onMeridian = 0, onParallel = 0, outside = 0, elsewhere = 0;
  for (int py = 0; py < img->height; ++py)
    for (int px = 0; px < img->width; ++px) {
      if (img->at(px, py) == plain->at(px, py)) continue;
      const bool inPlot = px >= L.left && px < L.right && py >= L.top && py < L.bottom;
      if (!inPlot) ++outside;
      else if (std::abs(px + 0.5 - x) <= 1.0) ++onMeridian;
      else if (std::abs(py + 0.5 - y) <= 1.0) ++onParallel;
      else ++elsewhere;
    }
  EXPECT_EQ(outside, 0);
  EXPECT_EQ(elsewhere, 0);
  // The whole height and width, at most two pixels across (antialiasing); full blue on the centre
  // pixel where no grid line passes.
  EXPECT_GE(onMeridian, L.height());
  EXPECT_LE(onMeridian, 2 * L.height() + 4);
  EXPECT_GE(onParallel, L.width() - 4);
  const glm::u8vec4 centre = img->at(static_cast<int>(std::floor(x)), L.top + L.height() / 3 + 1);
  EXPECT_GT(centre.b, 200);
  EXPECT_LT(centre.r, 100);
}

// The GSHHG lines of a box come at the resolution the scale asks for, and hold the coast the box
// holds (the Texas Gulf coast in 26..30 N, 98..94 W); without GSHHG installed: skipped.
TEST(SlicePlot, CoastlinesOfABoxAtTheScaleAsked) {
  EXPECT_EQ(map::gshhgResolutionForScale(20000.0), map::GshhgResolution::Crude);
  EXPECT_EQ(map::gshhgResolutionForScale(3000.0), map::GshhgResolution::Low);
  EXPECT_EQ(map::gshhgResolutionForScale(600.0), map::GshhgResolution::Intermediate);
  EXPECT_EQ(map::gshhgResolutionForScale(150.0), map::GshhgResolution::High);
  EXPECT_EQ(map::gshhgResolutionForScale(50.0), map::GshhgResolution::Full);
  const std::string dir = map::defaultGshhgDirectory();
  if (!std::filesystem::exists(map::gshhgPath(dir, map::GshhgKind::Shoreline, map::GshhgResolution::Intermediate)))
    GTEST_SKIP() << "GSHHG not installed (Debian package gmt-gshhg)";
  auto lines = map::readBoxMapLines(dir, 26.0, 30.0, -98.0, -94.0, map::GshhgResolution::Intermediate);
  ASSERT_TRUE(lines) << lines.error();
  std::size_t inBox = 0;
  for (const map::GeoPolyline& l : lines->coasts)
    for (const glm::dvec2& p : l.lonLatDeg) inBox += p.x > -98.0 && p.x < -94.0 && p.y > 26.0 && p.y < 30.0;
  EXPECT_GT(inBox, 100u);
  EXPECT_FALSE(lines->internal.empty());  // the Texas-Louisiana line
  EXPECT_FALSE(map::readBoxMapLines("/nonexistent", 26.0, 30.0, -98.0, -94.0, map::GshhgResolution::Crude));
}

// End to end: the synthetic radar volume, a cross-section, the plot, a PNG written and read back
// at the size asked for.
TEST(SlicePlot, SyntheticRadarCrossSectionPngHasTheSizeAskedFor) {
  const std::string dir = ATMOGLOBE_TEST_OUTPUT_DIR;
  const std::string radar = dir + "/plot_synthetic.nc", png = dir + "/cross.png";
  ASSERT_TRUE(volume::writeSyntheticCfRadial(radar, volume::SyntheticRadarOptions{}).ok());
  volume::SliceSourceOptions load;
  load.path = radar;
  auto source = volume::SliceSource::load(load);
  ASSERT_TRUE(source) << source.error();
  auto transfer = (*source)->transfer("auto");
  ASSERT_TRUE(transfer);
  EXPECT_EQ(transfer->colors.name(), "NWS reflectivity");  // the 3-D view's table for reflectivity
  volume::SliceRequest request;
  request.cappi = false;
  request.path = {{34.7, -98.2}, {35.0, -97.8}, {35.4, -97.3}};
  request.columns = request.rows = 16;
  auto probe = volume::sliceGeometryFor(**source, request);
  ASSERT_TRUE(probe) << probe.error();
  auto layout = engine::layoutSlicePlot(*probe, 640, 360);
  ASSERT_TRUE(layout);
  request.columns = layout->width();
  request.rows = layout->height();
  auto geometry = volume::sliceGeometryFor(**source, request);
  ASSERT_TRUE(geometry);
  auto raster = volume::sampleSource(**source, *geometry);
  ASSERT_TRUE(raster) << raster.error();
  EXPECT_GT(raster->echoCount, 1000u);
  const engine::SlicePlotOptions o = engine::slicePlotOptionsFor(**source, *geometry, *transfer, 640, 360);
  EXPECT_TRUE(o.synthetic);
  EXPECT_NE(o.title.find("KTLX"), std::string::npos);
  EXPECT_NE(o.subtitle.find("2020-05-01 21:00:00 UTC"), std::string::npos);
  EXPECT_NE(o.subtitle.find("C 35.40°N 97.30°W"), std::string::npos) << o.subtitle;
  auto img = engine::drawSlicePlot(*raster, *geometry, o);
  ASSERT_TRUE(img) << img.error();
  ASSERT_TRUE(globe::writePng(png, *img).ok());
  auto back = globe::decodeImageFile(png);
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(back->width, 640);
  EXPECT_EQ(back->height, 360);
  EXPECT_FALSE(std::filesystem::exists(png + ".tmp"));
}

// The frame legend: its colour key shows the table's colours top (high) to bottom (low), and the
// scale bar is a round length drawn at the image's scale.
TEST(FrameLegend, KeyColoursAndScaleBarLength) {
  if (!engine::Font::dejaVuSans()) GTEST_SKIP() << "DejaVu Sans not installed (fonts-dejavu-core)";
  globe::ImageRGBA8 img = globe::ImageRGBA8::filled(640, 360, {0, 0, 0, 255});
  engine::FrameLegend legend;
  legend.title = "KTLX  DBZ";
  legend.keys.push_back(engine::LegendKey{"KTLX DBZ", "dBZ", volume::nwsReflectivityTable()});
  legend.metersPerPixel = 250.0;  // a fifth of the width is 32 km: the bar is 20 km = 80 px
  legend.synthetic = true;
  ASSERT_TRUE(engine::drawFrameLegend(img, legend));
  // The key is the rightmost coloured column band: find a column whose pixels match the table.
  const double scale = 360.0 / 720.0 < 0.6 ? 0.6 : 360.0 / 720.0;
  const int x = 640 - static_cast<int>(46 * scale) - static_cast<int>(14 * scale) / 2;
  const int y0 = static_cast<int>(60 * scale) + static_cast<int>(36 * scale), y1 = 360 - static_cast<int>(40 * scale);
  // NWS: a stepped table from -20 to 80 dBZ (75 + one band); a row's value is linear in y.
  int matched = 0, rows = 0;
  for (int y = y0 + 2; y < y1 - 2; y += 7) {
    const double v = 80.0 - (y - y0 + 0.5) / (y1 - y0) * 100.0;
    const volume::Rgba8 want = volume::nwsReflectivityTable().map(static_cast<float>(v));
    const std::size_t i = (static_cast<std::size_t>(y) * 640 + static_cast<std::size_t>(x)) * 4;
    ++rows;
    matched += img.pixels[i] == want.r && img.pixels[i + 1] == want.g && img.pixels[i + 2] == want.b ? 1 : 0;
  }
  // Rows on a band edge may take the neighbouring band: all but a few match.
  EXPECT_GE(matched, rows - 3) << matched << " of " << rows;
  // The scale bar: a white run along its row, 80 px long.
  const int yb = 360 - static_cast<int>(14 * scale);
  int run = 0;
  for (int xx = 0; xx < 640; ++xx) {
    const std::size_t i = (static_cast<std::size_t>(yb) * 640 + static_cast<std::size_t>(xx)) * 4;
    run += img.pixels[i] == 255 && img.pixels[i + 1] == 255 && img.pixels[i + 2] == 255 ? 1 : 0;
  }
  EXPECT_EQ(run, 80);
}
