// XyzMercatorLayer: reprojection of web-mercator XYZ tiles into geographic tiles.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "atmoglobe/globe/XyzLayer.h"

namespace atmoglobe::globe {
namespace {

namespace fs = std::filesystem;

// References from PROJ: `cs2cs -d 6 EPSG:4326 EPSG:3857` (input "lat lon"):
//   66.51326044311186 0   -> 0.000000 10018754.171395   (north edge of mercator row 1 at zoom 2)
//   40.25390625 -59.94140625 -> -6672646.821183 4902908.135781
//   85.0511287798066 0    -> 0.000000 20037508.342789   (top of the mercator square)
// and `echo "0 10018754.171394622" | cs2cs -d 10 EPSG:3857 EPSG:4326` -> 66.5132604431.
constexpr double kHalfWorldM = 20037508.342789;
constexpr double kRow1NorthLatDeg = 66.5132604431;
const glm::u8vec4 kBlue{0, 0, 255, 255}, kGreen{0, 255, 0, 255}, kRed{255, 0, 0, 255};

fs::path freshDir() { return atmoglobe_test::freshTestDir("imagery"); }

void writeTile(const fs::path& root, int z, int x, int y, const ImageRGBA8& image) {
  const fs::path d = root / std::to_string(z) / std::to_string(x);
  fs::create_directories(d);
  ASSERT_TRUE(writePng((d / (std::to_string(y) + ".png")).string(), image).ok());
}

/// Zoom 0: blue everywhere. Zoom 1: only (1,1,0) (lon 0..180, lat 0..85.05), green.
/// Zoom 2: (2,2,1) red (lon 0..90, lat 0..66.51) and (2,1,1) a ramp: red = column, green = row.
fs::path makeXyz(bool withCoarse) {
  const fs::path root = freshDir() / "xyz";
  if (withCoarse) {
    writeTile(root, 0, 0, 0, ImageRGBA8::filled(256, 256, kBlue));
    writeTile(root, 1, 1, 0, ImageRGBA8::filled(256, 256, kGreen));
  }
  writeTile(root, 2, 2, 1, ImageRGBA8::filled(256, 256, kRed));
  ImageRGBA8 ramp = ImageRGBA8::filled(256, 256, {0, 0, 0, 255});
  for (int j = 0; j < 256; ++j)
    for (int i = 0; i < 256; ++i) ramp.set(i, j, {static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j), 7, 255});
  writeTile(root, 2, 1, 1, ramp);
  return root;
}

glm::dvec2 pixelLonLat(const TileId& t, int i, int j) {
  const GeoRectangle r = tileRectangle(t);
  const double px = (r.eastDeg - r.westDeg) / 256.0;
  return {r.westDeg + (i + 0.5) * px, r.northDeg - (j + 0.5) * px};
}

TEST(XyzLayerTest, MercatorFormulasMatchProj) {
  const glm::dvec2 a = webMercatorNormalized(0.0, kRow1NorthLatDeg);
  EXPECT_NEAR(a.y, (kHalfWorldM - 10018754.171395) / (2 * kHalfWorldM),
              1e-9);  // cs2cs prints mm: 1e-9 of 40000 km = 0.04 mm
  EXPECT_NEAR(a.y, 0.25, 1e-9);
  const glm::dvec2 b = webMercatorNormalized(-59.94140625, 40.25390625);
  EXPECT_NEAR(b.x, (-6672646.821183 + kHalfWorldM) / (2 * kHalfWorldM), 1e-9);
  EXPECT_NEAR(b.y, (kHalfWorldM - 4902908.135781) / (2 * kHalfWorldM), 1e-9);
  EXPECT_NEAR(webMercatorNormalized(0.0, kWebMercatorMaxLatDeg).y, 0.0, 1e-12);
  const glm::dvec2 back = webMercatorNormalizedToLonLat(b.x, b.y);
  EXPECT_NEAR(back.x, -59.94140625, 1e-9);
  EXPECT_NEAR(back.y, 40.25390625, 1e-9);
}

TEST(XyzLayerTest, OpenFindsZoomsAndRejectsDirectoriesWithoutTiles) {
  const fs::path root = makeXyz(true);
  Result<std::shared_ptr<XyzMercatorLayer>> layer = XyzMercatorLayer::open(root.string());
  ASSERT_TRUE(layer.ok()) << layer.error();
  EXPECT_EQ((*layer)->zoomLevels(), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ((*layer)->maxLevel(), 1);  // zoom 2 (1024 px around) = geographic level 1 (1024 px)
  const fs::path empty = root.parent_path() / "empty";
  fs::create_directories(empty / "notazoom");
  Result<std::shared_ptr<XyzMercatorLayer>> none = XyzMercatorLayer::open(empty.string());
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().find(empty.string()), std::string::npos);
  Result<std::shared_ptr<XyzMercatorLayer>> missing = XyzMercatorLayer::open((root / "nope").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("nope"), std::string::npos);
}

TEST(XyzLayerTest, RedTileLandsOnItsLonLatBoxWithAncestorFallbackAroundIt) {
  Result<std::shared_ptr<XyzMercatorLayer>> layer = XyzMercatorLayer::open(makeXyz(true).string());
  ASSERT_TRUE(layer.ok());
  // Geographic tile (1, 2, 0): lon 0..90, lat 90..0 -> mercator zoom 2 (level + 1).
  const TileId t{1, 2, 0};
  Result<std::optional<ImageRGBA8>> image = (*layer)->tileImage(t);
  ASSERT_TRUE(image.ok()) << image.error();
  ASSERT_TRUE(image->has_value());
  int red = 0, green = 0, clear = 0;
  for (int j = 0; j < 256; ++j) {
    const double lat = pixelLonLat(t, 0, j).y;
    for (int i = 0; i < 256; ++i) {
      const glm::u8vec4 p = (**image).at(i, j);
      if (lat > kWebMercatorMaxLatDeg) {
        ASSERT_EQ(p.a, 0) << j;  // above the mercator square: no data
        ++clear;
      } else if (lat > kRow1NorthLatDeg) {
        ASSERT_EQ(p, kGreen) << j;  // (2,2,0) missing -> its parent (1,1,0)
        ++green;
      } else {
        ASSERT_EQ(p, kRed) << j;  // (2,2,1): lon 0..90, lat 0..66.51
        ++red;
      }
    }
  }
  // Row counts follow from the latitudes: 90/256 deg per row.
  EXPECT_EQ(clear, 256 * static_cast<int>(std::round((90 - kWebMercatorMaxLatDeg) / (90.0 / 256))));
  EXPECT_EQ(red, 256 * static_cast<int>(std::ceil(kRow1NorthLatDeg / (90.0 / 256) - 0.5)));
  EXPECT_GT(green, 0);

  // Geographic (1, 0, 1): lon -180..-90, lat 0..-90: nothing at zooms 2 and 1, so zoom 0 (blue)
  // two levels up; below -85.05 no data.
  Result<std::optional<ImageRGBA8>> sw = (*layer)->tileImage({1, 0, 1});
  ASSERT_TRUE(sw.ok());
  ASSERT_TRUE(sw->has_value());
  EXPECT_EQ((**sw).at(100, 100), kBlue);
  EXPECT_EQ((**sw).at(100, 255).a, 0);
}

TEST(XyzLayerTest, PixelsComeFromTheRightPlaceInsideAMercatorTile) {
  Result<std::shared_ptr<XyzMercatorLayer>> layer = XyzMercatorLayer::open(makeXyz(true).string());
  ASSERT_TRUE(layer.ok());
  // Geographic (1, 1, 0) covers lon -90..0, lat 90..0; pixel (85, 141) is centred at
  // lon -59.94140625, lat 40.25390625, inside mercator tile (2, 1, 1) whose red = column and
  // green = row. Expected texel coordinates from the cs2cs metres above: x_tile = 4x - 1, etc.
  Result<std::optional<ImageRGBA8>> image = (*layer)->tileImage({1, 1, 0});
  ASSERT_TRUE(image.ok());
  const glm::dvec2 lonLat = pixelLonLat({1, 1, 0}, 85, 141);
  ASSERT_DOUBLE_EQ(lonLat.x, -59.94140625);
  ASSERT_DOUBLE_EQ(lonLat.y, 40.25390625);
  const double x = (-6672646.821183 + kHalfWorldM) / (2 * kHalfWorldM);
  const double y = (kHalfWorldM - 4902908.135781) / (2 * kHalfWorldM);
  const double column = (4 * x - 1) * 256 - 0.5, row = (4 * y - 1) * 256 - 0.5;  // pixel centres
  const glm::u8vec4 p = (**image).at(85, 141);
  // A bilinear sample of a linear ramp is the ramp itself; the only error is rounding to 8 bits.
  EXPECT_NEAR(p.r, column, 0.5 + 1e-6);
  EXPECT_NEAR(p.g, row, 0.5 + 1e-6);
  EXPECT_EQ(p.b, 7);
}

TEST(XyzLayerTest, NoDataIsTransparentAndNoDataAtAllIsNullopt) {
  Result<std::shared_ptr<XyzMercatorLayer>> layer = XyzMercatorLayer::open(makeXyz(false).string());
  ASSERT_TRUE(layer.ok());
  // Geographic level 0 tile (0, 1, 0): lon 0..180, lat 90..-90; only zoom 2 exists, red tile at
  // lon 0..90, lat 0..66.51. Everything else: alpha 0.
  const TileId t{0, 1, 0};
  Result<std::optional<ImageRGBA8>> image = (*layer)->tileImage(t);
  ASSERT_TRUE(image.ok());
  ASSERT_TRUE(image->has_value());
  int red = 0;
  for (int j = 0; j < 256; ++j) {
    for (int i = 0; i < 256; ++i) {
      const glm::dvec2 ll = pixelLonLat(t, i, j);
      const glm::u8vec4 p = (**image).at(i, j);
      if (ll.x > 0 && ll.x < 90 && ll.y > 0 && ll.y < kRow1NorthLatDeg) {
        ASSERT_EQ(p, kRed) << i << "," << j;
        ++red;
      } else {
        ASSERT_EQ(p, glm::u8vec4(0, 0, 0, 0)) << i << "," << j;
      }
    }
  }
  EXPECT_GT(red, 100 * 80);
  // lon -180..-90, lat 0..-90 has nothing at any zoom.
  Result<std::optional<ImageRGBA8>> empty = (*layer)->tileImage({1, 0, 1});
  ASSERT_TRUE(empty.ok());
  EXPECT_FALSE(empty->has_value());
  // Geographic (3, 8, 0) covers lon 0..22.5, lat 90..67.5: zoom 2 is the deepest (used for
  // level 3), and its tile there, (2, 2, 0), is missing: no data at all. (3, 8, 1), lat 67.5..45,
  // reaches down into the red tile below 66.51 deg.
  Result<std::optional<ImageRGBA8>> polar = (*layer)->tileImage({3, 8, 0});
  ASSERT_TRUE(polar.ok());
  Result<std::optional<ImageRGBA8>> below = (*layer)->tileImage({3, 8, 1});
  ASSERT_TRUE(below.ok());
  ASSERT_TRUE(below->has_value());
  EXPECT_EQ((**below).at(128, 0).a, 0);     // lat 67.46
  EXPECT_EQ((**below).at(128, 255), kRed);  // lat 45.04
  EXPECT_FALSE(polar->has_value());
}

TEST(XyzLayerTest, CorruptTileIsAnErrorNamingTheFile) {
  const fs::path root = makeXyz(false);
  const fs::path bad = root / "2" / "2" / "1.png";
  std::ofstream(bad, std::ios::trunc) << "not a png";
  Result<std::shared_ptr<XyzMercatorLayer>> layer = XyzMercatorLayer::open(root.string());
  ASSERT_TRUE(layer.ok());
  Result<std::optional<ImageRGBA8>> image = (*layer)->tileImage({1, 2, 0});
  ASSERT_FALSE(image.ok());
  EXPECT_NE(image.error().find(bad.string()), std::string::npos) << image.error();
}

}  // namespace
}  // namespace atmoglobe::globe
