// buildPyramid / readPyramidInfo / GeographicPyramidLayer on synthetic equirectangular images.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "atmoglobe/globe/ImageryPyramid.h"

namespace atmoglobe::globe {
namespace {

namespace fs = std::filesystem;

fs::path freshDir() { return atmoglobe_test::freshTestDir("imagery"); }

/// Colour of the 45 x 45 deg region holding (lonDeg, latDeg): 8 columns from -180, 4 rows from +90.
glm::u8vec4 regionColour(double lonDeg, double latDeg, std::uint8_t blue = 200) {
  const int ix = static_cast<int>(std::floor((lonDeg + 180.0) / 45.0));
  const int iy = static_cast<int>(std::floor((90.0 - latDeg) / 45.0));
  return {static_cast<std::uint8_t>(30 * ix + 10), static_cast<std::uint8_t>(50 * iy + 20), blue, 255};
}

/// A w x h equirectangular image whose pixels take the colour of their region (pixel centres).
ImageRGBA8 regionImage(int w, int h, std::uint8_t blue = 200) {
  ImageRGBA8 image = ImageRGBA8::filled(w, h, {0, 0, 0, 0});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      image.set(x, y, regionColour(-180.0 + (x + 0.5) * 360.0 / w, 90.0 - (y + 0.5) * 180.0 / h, blue));
  return image;
}

ImageRGBA8 noiseImage(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  ImageRGBA8 image = ImageRGBA8::filled(w, h, {0, 0, 0, 255});
  for (std::size_t i = 0; i < image.pixels.size(); i += 4)
    for (int c = 0; c < 3; ++c) image.pixels[i + c] = static_cast<std::uint8_t>(rng() & 0xff);
  return image;
}

std::string tileFile(const fs::path& dir, int z, int x, int y) {
  return (dir / std::to_string(z) / std::to_string(x) / (std::to_string(y) + ".png")).string();
}

/// True if `parent` holds an entry whose name starts with `prefix` (e.g. a leftover staged ".out.tmp<pid>-<n>").
bool hasEntryStartingWith(const fs::path& parent, const std::string& prefix) {
  for (const auto& e : fs::directory_iterator(parent))
    if (e.path().filename().string().rfind(prefix, 0) == 0) return true;
  return false;
}

TEST(ImageryPyramidTest, NaturalLevelIsSmallestLevelAtLeastAsFineAsTheSource) {
  // Level z is 2^(z+1) * 256 px around the equator: 512, 1024, 2048, 4096...
  EXPECT_EQ(naturalPyramidLevel(100), 0);
  EXPECT_EQ(naturalPyramidLevel(512), 0);
  EXPECT_EQ(naturalPyramidLevel(513), 1);
  EXPECT_EQ(naturalPyramidLevel(1024), 1);
  EXPECT_EQ(naturalPyramidLevel(2048), 2);
  EXPECT_EQ(naturalPyramidLevel(2049), 3);
  EXPECT_EQ(naturalPyramidLevel(21600), 6);  // Blue Marble 21600 px: 32768 >= 21600 > 16384
  EXPECT_EQ(pyramidTileCount(0), 2u);
  EXPECT_EQ(pyramidTileCount(2), 2u + 8u + 32u);
}

TEST(ImageryPyramidTest, RegionColoursLandInTheRightTiles) {
  const fs::path dir = freshDir();
  const std::string source = (dir / "world.png").string();
  ASSERT_TRUE(writePng(source, regionImage(1024, 512)).ok());
  PyramidInfo info;
  const fs::path out = dir / "pyramid";
  Status s = buildPyramid(source, out.string(), {}, &info);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(info.maxLevel, 1);  // 1024 px wide -> level 1 (1024 px)
  EXPECT_EQ(info.source, "world.png");
  Result<PyramidInfo> read = readPyramidInfo(out.string());
  ASSERT_TRUE(read.ok()) << read.error();
  EXPECT_EQ(read->maxLevel, 1);
  EXPECT_EQ(read->tileSizePx, 256);
  EXPECT_EQ(read->format, "png");
  EXPECT_FALSE(fs::exists(tileFile(out, 2, 0, 0)));
  EXPECT_FALSE(hasEntryStartingWith(dir, ".pyramid.tmp"));

  Result<std::shared_ptr<GeographicPyramidLayer>> layer = GeographicPyramidLayer::open(out.string());
  ASSERT_TRUE(layer.ok()) << layer.error();
  EXPECT_EQ((*layer)->maxLevel(), 1);
  // Every pixel centre of every tile at levels 0 and 1 away from region borders has its
  // region's colour. Near a border (within one source pixel, 360/1024 deg, at level 1; within one
  // level-0 pixel at level 0, where the box filter mixes) the colour is a blend: skipped.
  for (int z = 0; z <= 1; ++z) {
    for (std::uint32_t x = 0; x < tileColumns(z); ++x) {
      for (std::uint32_t y = 0; y < tileRows(z); ++y) {
        const TileId t{z, x, y};
        Result<std::optional<ImageRGBA8>> image = (*layer)->tileImage(t);
        ASSERT_TRUE(image.ok()) << image.error();
        ASSERT_TRUE(image->has_value());
        const ImageRGBA8& im = **image;
        ASSERT_EQ(im.width, 256);
        const GeoRectangle r = tileRectangle(t);
        const double px = (r.eastDeg - r.westDeg) / 256.0;
        const double margin = std::max(px, 360.0 / 1024.0);
        int checked = 0;
        for (int j = 0; j < 256; j += 5) {
          for (int i = 0; i < 256; i += 5) {
            const double lon = r.westDeg + (i + 0.5) * px, lat = r.northDeg - (j + 0.5) * px;
            const double dLon = std::remainder(lon + 180.0, 45.0), dLat = std::remainder(90.0 - lat, 45.0);
            if (std::abs(dLon) < margin || std::abs(dLat) < margin) continue;
            ASSERT_EQ(im.at(i, j), regionColour(lon, lat))
                << "tile " << z << "/" << x << "/" << y << " px " << i << "," << j;
            ++checked;
          }
        }
        EXPECT_GT(checked, 1000);
      }
    }
  }
  // One explicit spot: level 1 tile x=2, y=0 covers lon 0..90, lat 90..0; its pixel (64, 64)
  // is at lon 22.68, lat 67.32 -> region column 4, row 0 -> (130, 20, 200).
  Result<std::optional<ImageRGBA8>> spot = (*layer)->tileImage({1, 2, 0});
  ASSERT_TRUE(spot.ok());
  EXPECT_EQ((**spot).at(64, 64), glm::u8vec4(130, 20, 200, 255));
}

TEST(ImageryPyramidTest, SourceAtNaturalResolutionIsCopiedExactlyAndCoarserLevelsAreBoxFiltered) {
  const fs::path dir = freshDir();
  const std::string source = (dir / "noise.png").string();
  const ImageRGBA8 noise = noiseImage(1024, 512, 7);
  ASSERT_TRUE(writePng(source, noise).ok());
  const fs::path out = dir / "p";
  ASSERT_TRUE(buildPyramid(source, out.string(), {}).ok());
  // Level 1 is exactly 1024 x 512 px: tile (1, x, y) pixel (i, j) is source pixel (256x+i, 256y+j).
  for (std::uint32_t x = 0; x < 4; ++x) {
    for (std::uint32_t y = 0; y < 2; ++y) {
      Result<ImageRGBA8> tile = decodeImageFile(tileFile(out, 1, static_cast<int>(x), static_cast<int>(y)));
      ASSERT_TRUE(tile.ok()) << tile.error();
      for (int j = 0; j < 256; ++j)
        for (int i = 0; i < 256; ++i)
          ASSERT_EQ(tile->at(i, j), noise.at(static_cast<int>(256 * x) + i, static_cast<int>(256 * y) + j));
    }
  }
  // Level 0 pixel = rounded mean of the 2 x 2 source pixels under it.
  for (int x = 0; x < 2; ++x) {
    Result<ImageRGBA8> tile = decodeImageFile(tileFile(out, 0, x, 0));
    ASSERT_TRUE(tile.ok());
    for (int j = 0; j < 256; ++j) {
      for (int i = 0; i < 256; ++i) {
        const int sx = 512 * x + 2 * i, sy = 2 * j;
        for (int c = 0; c < 4; ++c) {
          const int sum =
              noise.at(sx, sy)[c] + noise.at(sx + 1, sy)[c] + noise.at(sx, sy + 1)[c] + noise.at(sx + 1, sy + 1)[c];
          ASSERT_NEAR(tile->at(i, j)[c], sum / 4.0, 0.5) << i << "," << j;  // rounding to 8 bits only
        }
      }
    }
  }
}

TEST(ImageryPyramidTest, LevelCountFor2048x1024IsThree) {
  const fs::path dir = freshDir();
  const std::string source = (dir / "world2048.png").string();
  ASSERT_TRUE(writePng(source, regionImage(2048, 1024)).ok());
  PyramidInfo info;
  const fs::path out = dir / "p";
  ASSERT_TRUE(buildPyramid(source, out.string(), {}, &info).ok());
  EXPECT_EQ(info.maxLevel, 2);
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(out))
    if (e.path().extension() == ".png") ++files;
  EXPECT_EQ(files, 2 + 8 + 32);
  EXPECT_TRUE(fs::exists(tileFile(out, 2, 7, 3)));
  EXPECT_FALSE(fs::exists(out / "3"));
}

TEST(ImageryPyramidTest, ExplicitMaxLevelAndTilesDeeperThanMaxLevelAreUpsampledCrops) {
  const fs::path dir = freshDir();
  const std::string source = (dir / "noise.png").string();
  ASSERT_TRUE(writePng(source, noiseImage(512, 256, 11)).ok());
  PyramidBuildOptions options;
  options.maxLevel = 1;  // finer than the source's natural level 0: upsampled, still fine
  const fs::path out = dir / "p";
  ASSERT_TRUE(buildPyramid(source, out.string(), options).ok());
  Result<std::shared_ptr<GeographicPyramidLayer>> layer = GeographicPyramidLayer::open(out.string());
  ASSERT_TRUE(layer.ok());
  EXPECT_FALSE(fs::exists(tileFile(out, 2, 0, 0)));

  Result<ImageRGBA8> ancestorFile = decodeImageFile(tileFile(out, 1, 1, 1));
  ASSERT_TRUE(ancestorFile.ok());
  const ImageRGBA8& a = *ancestorFile;
  // Level 2 tile (2, 3, 3): the south-east child of (1, 1, 1): its pixel i covers ancestor
  // x = 128 + i/2 - 0.25 (pixel centres), i.e. weights 0.75/0.25 between neighbouring ancestor
  // pixels, clamped at the ancestor's edge. Written out here independently of sampleBilinear.
  Result<std::optional<ImageRGBA8>> child = (*layer)->tileImage({2, 3, 3});
  ASSERT_TRUE(child.ok()) << child.error();
  ASSERT_TRUE(child->has_value());
  auto axis = [](int i, int offset, int* lo, int* hi, double* wHi) {
    const double x = std::clamp(offset + i / 2.0 - 0.25, 0.0, 255.0);
    *lo = static_cast<int>(std::floor(x));
    *hi = std::min(*lo + 1, 255);
    *wHi = x - *lo;
  };
  for (int j = 0; j < 256; ++j) {
    for (int i = 0; i < 256; ++i) {
      int x0, x1, y0, y1;
      double wx, wy;
      axis(i, 128, &x0, &x1, &wx);
      axis(j, 128, &y0, &y1, &wy);
      for (int c = 0; c < 4; ++c) {
        const double expected = (1 - wy) * ((1 - wx) * a.at(x0, y0)[c] + wx * a.at(x1, y0)[c]) +
                                wy * ((1 - wx) * a.at(x0, y1)[c] + wx * a.at(x1, y1)[c]);
        // Weights are multiples of 1/4, so the exact value is a multiple of 1/16; the only error is
        // rounding to 8 bits (<= 0.5).
        ASSERT_NEAR((**child).at(i, j)[c], expected, 0.5) << i << "," << j << " c" << c;
      }
    }
  }
  // Three levels deeper: (4, 8, 8) is the north-west 1/8 x 1/8 of (1, 1, 1); its pixel (0,0)
  // is at ancestor x = y = (0.5/256) * 32 - 0.5 < 0 -> clamped to ancestor pixel (0, 0).
  Result<std::optional<ImageRGBA8>> deep = (*layer)->tileImage({4, 8, 8});
  ASSERT_TRUE(deep.ok());
  EXPECT_EQ((**deep).at(0, 0), a.at(0, 0));
  // (4, 8, 8) pixel (255, 255): ancestor x = y = (255.5/256) * 32 - 0.5 = 31.4375.
  const double f = 31.4375 - 31;
  for (int c = 0; c < 4; ++c) {
    const double expected = (1 - f) * ((1 - f) * a.at(31, 31)[c] + f * a.at(32, 31)[c]) +
                            f * ((1 - f) * a.at(31, 32)[c] + f * a.at(32, 32)[c]);
    EXPECT_NEAR((**deep).at(255, 255)[c], expected, 0.5);
  }
}

TEST(ImageryPyramidTest, BadInputsAreErrorsNamingTheFileAndLeaveNoDirectory) {
  const fs::path dir = freshDir();
  const fs::path out = dir / "out";
  const std::string missing = (dir / "missing.jpg").string();
  const std::string text = (dir / "text.png").string();
  std::ofstream(text) << "hello, not a picture\n";
  const std::string square = (dir / "square.png").string();
  ASSERT_TRUE(writePng(square, ImageRGBA8::filled(100, 100, {1, 2, 3, 255})).ok());
  for (const std::string& bad : {missing, text, square}) {
    Status s = buildPyramid(bad, out.string(), {});
    ASSERT_FALSE(s.ok()) << bad;
    EXPECT_EQ(s.error().rfind(bad + ": ", 0), 0u) << s.error();  // "<file>: <reason>"
    EXPECT_FALSE(fs::exists(out)) << bad;
    EXPECT_FALSE(hasEntryStartingWith(dir, "out.")) << bad;
  }
  Status sq = buildPyramid(square, out.string(), {});
  EXPECT_NE(sq.error().find("100 x 100"), std::string::npos) << sq.error();
  // width = 2 * height within 1 px is accepted (201 x 100), 202 x 100 is not.
  const std::string odd = (dir / "odd.png").string();
  ASSERT_TRUE(writePng(odd, ImageRGBA8::filled(201, 100, {1, 2, 3, 255})).ok());
  EXPECT_TRUE(buildPyramid(odd, out.string(), {}).ok());
  const std::string wide = (dir / "wide.png").string();
  ASSERT_TRUE(writePng(wide, ImageRGBA8::filled(203, 100, {1, 2, 3, 255})).ok());
  EXPECT_FALSE(buildPyramid(wide, (dir / "out2").string(), {}).ok());
  PyramidBuildOptions tooDeep;
  tooDeep.maxLevel = kMaxPyramidLevel + 1;
  EXPECT_FALSE(buildPyramid(odd, (dir / "out3").string(), tooDeep).ok());
  EXPECT_FALSE(fs::exists(dir / "out3"));
}

TEST(ImageryPyramidTest, InterruptedBuildLeavesNoDirectoryAndKeepsTheOldPyramid) {
  const fs::path dir = freshDir();
  const fs::path out = dir / "out";
  const std::string source = (dir / "w.png").string();
  ASSERT_TRUE(writePng(source, regionImage(1024, 512, 10)).ok());
  PyramidBuildOptions cancelling;
  std::uint64_t calls = 0;
  cancelling.progress = [&](std::uint64_t done, std::uint64_t total) {
    ++calls;
    EXPECT_EQ(total, 10u);
    return done < 4;  // stop after the 4th tile
  };
  Status s = buildPyramid(source, out.string(), cancelling);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(calls, 4u);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(hasEntryStartingWith(dir, ".out."));

  // A finished build, then a cancelled rebuild with other colours: the old pyramid is untouched.
  ASSERT_TRUE(buildPyramid(source, out.string(), {}).ok());
  const std::string other = (dir / "other.png").string();
  ASSERT_TRUE(writePng(other, regionImage(1024, 512, 90)).ok());
  ASSERT_FALSE(buildPyramid(other, out.string(), cancelling).ok());
  Result<ImageRGBA8> kept = decodeImageFile(tileFile(out, 1, 2, 0));
  ASSERT_TRUE(kept.ok());
  EXPECT_EQ(kept->at(64, 64).b, 10);
  EXPECT_FALSE(hasEntryStartingWith(dir, ".out."));
  // A finished rebuild replaces it.
  ASSERT_TRUE(buildPyramid(other, (dir / "out/").string(), {}).ok());
  Result<ImageRGBA8> replaced = decodeImageFile(tileFile(out, 1, 2, 0));
  ASSERT_TRUE(replaced.ok());
  EXPECT_EQ(replaced->at(64, 64).b, 90);
  EXPECT_FALSE(hasEntryStartingWith(dir, ".out."));
}

TEST(ImageryPyramidTest, RefusesToReplaceADirectoryThatIsNotAPyramid) {
  const fs::path dir = freshDir();
  const fs::path out = dir / "precious";
  fs::create_directories(out);
  std::ofstream(out / "thesis.tex") << "\\begin{document}";
  const std::string source = (dir / "w.png").string();
  ASSERT_TRUE(writePng(source, regionImage(512, 256)).ok());
  Status s = buildPyramid(source, out.string(), {});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find(out.string()), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "thesis.tex"));
}

TEST(ImageryPyramidTest, CorruptMetadataAndTilesAreErrorsNamingTheFile) {
  const fs::path dir = freshDir();
  const std::string source = (dir / "w.png").string();
  ASSERT_TRUE(writePng(source, regionImage(512, 256)).ok());
  const fs::path out = dir / "p";
  ASSERT_TRUE(buildPyramid(source, out.string(), {}).ok());
  Result<std::shared_ptr<GeographicPyramidLayer>> layer = GeographicPyramidLayer::open(out.string());
  ASSERT_TRUE(layer.ok());
  const std::string tile = tileFile(out, 0, 1, 0);
  std::ofstream(tile, std::ios::trunc) << "garbage";
  Result<std::optional<ImageRGBA8>> bad = (*layer)->tileImage({0, 1, 0});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find(tile), std::string::npos) << bad.error();
  // Deeper tiles read the same (corrupt) ancestor: also an error, not a crash.
  EXPECT_FALSE((*layer)->tileImage({3, 9, 2}).ok());
  // A missing tile file: no data.
  fs::remove(tileFile(out, 0, 0, 0));
  Result<std::optional<ImageRGBA8>> none = (*layer)->tileImage({0, 0, 0});
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->has_value());

  const std::string json = (out / "pyramid.json").string();
  std::ofstream(json, std::ios::trunc) << "{ \"kind\": ";
  Result<PyramidInfo> info = readPyramidInfo(out.string());
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.error().find(json), std::string::npos) << info.error();
  std::ofstream(json, std::ios::trunc)
      << R"({"kind":"atmoglobe-geographic-pyramid","maxLevel":-3,"tileSizePx":256,"format":"png"})";
  EXPECT_FALSE(readPyramidInfo(out.string()).ok());
  EXPECT_FALSE(GeographicPyramidLayer::open((dir / "nowhere").string()).ok());
}

}  // namespace
}  // namespace atmoglobe::globe
