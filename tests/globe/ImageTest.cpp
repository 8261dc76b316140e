// Image decoding/encoding (stb) and bilinear sampling.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "atmoglobe/globe/Image.h"

namespace atmoglobe::globe {
namespace {

namespace fs = std::filesystem;

fs::path freshDir() { return atmoglobe_test::freshTestDir("imagery"); }

ImageRGBA8 distinctPixels(int w, int h) {
  ImageRGBA8 image = ImageRGBA8::filled(w, h, {0, 0, 0, 0});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      image.set(x, y,
                {static_cast<std::uint8_t>(x * 31 + 1), static_cast<std::uint8_t>(y * 47 + 2),
                 static_cast<std::uint8_t>(x * y + 3), static_cast<std::uint8_t>(255 - x - y)});
  return image;
}

TEST(ImageTest, PngRoundTripIsLosslessAndLeavesNoTmpFile) {
  const fs::path dir = freshDir();
  const ImageRGBA8 image = distinctPixels(7, 5);
  EXPECT_EQ(image.byteSize(), 7u * 5u * 4u);
  const std::string path = (dir / "a.png").string();
  ASSERT_TRUE(writePng(path, image).ok());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);  // a.png alone
  Result<ImageRGBA8> back = decodeImageFile(path);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->width, 7);
  EXPECT_EQ(back->height, 5);
  EXPECT_EQ(back->pixels, image.pixels);  // PNG is lossless, alpha included
  // Row 0 is the top: pixel (0, 4) holds the last row's values.
  EXPECT_EQ(back->at(0, 4), image.at(0, 4));
}

TEST(ImageTest, DecodesTheInstalledEarthJpeg) {
  // Size from `file /usr/share/xplanet/images/earth.jpg`: "baseline, precision 8, 2048x1024, components 3".
  Result<ImageRGBA8> earth = decodeImageFile("/usr/share/xplanet/images/earth.jpg");
  ASSERT_TRUE(earth.ok()) << earth.error();
  EXPECT_EQ(earth->width, 2048);
  EXPECT_EQ(earth->height, 1024);
  EXPECT_EQ(earth->at(1000, 500).a, 255);  // RGB input gets opaque alpha
}

TEST(ImageTest, MissingFileErrorNamesTheFile) {
  const std::string path = (freshDir() / "nope.png").string();
  Result<ImageRGBA8> r = decodeImageFile(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(path), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("No such file"), std::string::npos) << r.error();
}

TEST(ImageTest, TextFileAndTruncatedPngAreErrorsNamingTheFile) {
  const fs::path dir = freshDir();
  const std::string text = (dir / "notes.png").string();
  std::ofstream(text) << "this is not an image\n";
  Result<ImageRGBA8> r = decodeImageFile(text);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(text), std::string::npos) << r.error();

  const std::string good = (dir / "good.png").string();
  ASSERT_TRUE(writePng(good, distinctPixels(64, 64)).ok());
  const auto size = fs::file_size(good);
  const std::string cut = (dir / "cut.png").string();
  fs::copy_file(good, cut);
  fs::resize_file(cut, size / 2);
  Result<ImageRGBA8> truncated = decodeImageFile(cut);
  ASSERT_FALSE(truncated.ok());
  EXPECT_NE(truncated.error().find(cut), std::string::npos) << truncated.error();

  Result<ImageRGBA8> empty = decodeImageMemory(nullptr, 0, "empty-buffer");
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("empty-buffer"), std::string::npos);

  Result<ImageRGBA8> directory = decodeImageFile(dir.string());
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.error().find(dir.string()), std::string::npos);
}

TEST(ImageTest, AHeaderClaimingMorePixelsThanTheFileCanHoldIsRefused) {
  // fuzz_image finding (fuzz/corpus/image/timeout-*): a 21-byte RLE TGA claiming 65535 x 1279 px
  // (335 MB decoded) is refused from its header; a highly compressible real PNG still decodes.
  const std::string path = std::string(ATMOGLOBE_SOURCE_DIR) + "/fuzz/corpus/image/timeout-tga-claims-65535x1279.tga";
  Result<ImageRGBA8> r = decodeImageFile(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(path), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("65535 x 1279 px, more than a file of 21 bytes can hold"), std::string::npos) << r.error();
  // 4096 x 4096 of one colour (16.8 M px): PNG packs it into a few kB, over 16384 px per byte
  // only beyond the always-allowed 2^24 px, so it must decode.
  ImageRGBA8 flat;
  flat.width = flat.height = 4096;
  flat.pixels.assign(std::size_t{4096} * 4096 * 4, 200);
  const fs::path dir = freshDir();
  const std::string file = (dir / "flat.png").string();
  ASSERT_TRUE(writePng(file, flat).ok());
  Result<ImageRGBA8> decoded = decodeImageFile(file);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(decoded->width, 4096);
}

TEST(ImageTest, WritePngIntoMissingDirectoryIsAnError) {
  const std::string path = (freshDir() / "no" / "such" / "dir" / "a.png").string();
  Status s = writePng(path, distinctPixels(2, 2));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find(path), std::string::npos) << s.error();
}

TEST(ImageTest, SampleBilinearUsesPixelCentresAndClampsAtEdges) {
  // 2 x 1 image: red channel 0 and 200. Pixel centres at u = 0.25 and 0.75 (= (i + 0.5) / 2).
  ImageRGBA8 image = ImageRGBA8::filled(2, 1, {0, 0, 0, 255});
  image.set(1, 0, {200, 0, 0, 255});
  EXPECT_EQ(sampleBilinear(image, 0.25, 0.5).r, 0);
  EXPECT_EQ(sampleBilinear(image, 0.75, 0.5).r, 200);
  EXPECT_EQ(sampleBilinear(image, 0.5, 0.5).r, 100);   // halfway between the centres
  EXPECT_EQ(sampleBilinear(image, 0.375, 0.5).r, 50);  // a quarter of the way
  EXPECT_EQ(sampleBilinear(image, 0.0, 0.5).r, 0);     // left of the first centre: clamped
  EXPECT_EQ(sampleBilinear(image, 1.0, 0.5).r, 200);   // right of the last centre: clamped
  EXPECT_EQ(sampleBilinear(image, 0.5, 0.0).r, 100);   // v outside the single row: clamped

  // 2 x 2 corners 0, 40, 80, 120 (green): the centre of the image is their mean, 60.
  ImageRGBA8 square = ImageRGBA8::filled(2, 2, {0, 0, 0, 0});
  square.set(1, 0, {0, 40, 0, 0});
  square.set(0, 1, {0, 80, 0, 0});
  square.set(1, 1, {0, 120, 0, 0});
  EXPECT_EQ(sampleBilinear(square, 0.5, 0.5).g, 60);
  // At (u, v) = (0.625, 0.25): x = 0.75, y = 0 -> 0.25 * 0 + 0.75 * 40 = 30.
  EXPECT_EQ(sampleBilinear(square, 0.625, 0.25).g, 30);
  // Rounds to nearest: 1-px ramp 0 -> 1 sampled at 0.75 of the way gives 0.75 -> 1.
  ImageRGBA8 ramp = ImageRGBA8::filled(2, 1, {0, 0, 0, 0});
  ramp.set(1, 0, {0, 0, 1, 0});
  EXPECT_EQ(sampleBilinear(ramp, 0.625, 0.5).b, 1);
  EXPECT_EQ(sampleBilinear(ramp, 0.375, 0.5).b, 0);
}

// The next mip level: GL's sizes (floor, at least 1) and the rounded mean of each 2 x 2.
TEST(ImageTest, HalfSizeIsTheRoundedMeanOfEach2x2) {
  ImageRGBA8 image = ImageRGBA8::filled(5, 3, glm::u8vec4(0));
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) image.set(x, y, glm::u8vec4(10 * x + y, 255 - x, 7 * y, 255));
  const ImageRGBA8 half = halfSize(image);
  ASSERT_EQ(half.width, 2);  // the odd column and row are left out
  ASSERT_EQ(half.height, 1);
  // (0,0) (1,0) (0,1) (1,1): red 0, 10, 1, 11 -> 22/4 = 5.5 -> 6; green 255, 254 twice -> 254.5 -> 255.
  EXPECT_EQ(half.at(0, 0), glm::u8vec4(6, 255, 4, 255));  // blue 0, 0, 7, 7 -> 3.5 -> 4
  EXPECT_EQ(half.at(1, 0),
            glm::u8vec4(26, 253, 4, 255));  // red 20, 30, 21, 31 -> 25.5 -> 26; green 253, 252 -> 252.5 -> 253

  // A side of one pixel: the mean along the other side.
  ImageRGBA8 column = ImageRGBA8::filled(1, 4, glm::u8vec4(0));
  for (int y = 0; y < 4; ++y) column.set(0, y, glm::u8vec4(static_cast<std::uint8_t>(100 * (y % 2)), 0, 0, 255));
  const ImageRGBA8 c = halfSize(column);
  ASSERT_EQ(c.width, 1);
  ASSERT_EQ(c.height, 2);
  EXPECT_EQ(c.at(0, 0), glm::u8vec4(50, 0, 0, 255));
  EXPECT_EQ(c.at(0, 1), glm::u8vec4(50, 0, 0, 255));
  const ImageRGBA8 row = halfSize(ImageRGBA8::filled(2, 1, glm::u8vec4(9, 8, 7, 6)));
  EXPECT_EQ(row.width, 1);
  EXPECT_EQ(row.height, 1);
  EXPECT_EQ(row.at(0, 0), glm::u8vec4(9, 8, 7, 6));
}

}  // namespace
}  // namespace atmoglobe::globe
