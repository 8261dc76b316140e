// Golden images: whole frames compared with reviewed PNGs in tests/golden/.
//
// Tolerance: the frames are deterministic on one Mesa/llvmpipe build; across Mesa
// versions texture filtering (LOD selection of mip levels, rounding of 8-bit blends) and
// edge rasterisation may differ by a few 8-bit steps on some pixels. We allow a mean
// absolute difference of 1.0 (per channel, 0..255) and at most 0.5 % of pixels differing
// by more than 24 in any channel. A misplaced tile, a flipped axis, a missing pole cap or
// a seam changes thousands of pixels by far more than that.
// On failure the actual and a difference image are written to the test output directory;
// tests/promote-golden.sh copies the actual images over the golden ones after review.
#include "GLTestUtil.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>

#include <gtest/gtest.h>

#include <cstdlib>

namespace {

using namespace atmoglobe;

struct GoldenCase {
  const char* name;
  engine::CameraPose pose;
  double fovDeg;
};

const GoldenCase kCases[] = {
    {"globe_europe_africa", {30.0, 15.0, 1.4e7, 0.0, -90.0, 0.0}, 45.0},
    {"oblique_alps_horizon", {45.0, 8.0, 3e5, 20.0, -15.0, 0.0}, 60.0},
    {"north_pole_antimeridian", {80.0, 180.0, 4e6, 180.0, -60.0, 0.0}, 60.0},
};

}  // namespace

TEST(GoldenImage, GlobeViewsMatchReviewedImages) {
  testutil::glContext();
  auto loader = engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()}}, {});
  ASSERT_TRUE(loader) << loader.error();
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer) << renderer.error();
  const int w = 320, h = 180;
  auto fb = engine::FramebufferGL::create(w, h);
  ASSERT_TRUE(fb);
  for (const GoldenCase& c : kCases) {
    const engine::Camera camera(c.pose, c.fovDeg, w, h);
    auto actual = (*renderer)->renderToImage(camera, {}, **fb);
    ASSERT_TRUE(actual) << actual.error();
    const std::string goldenPath = std::string(ATMOGLOBE_SOURCE_DIR) + "/tests/golden/" + c.name + ".png";
    const std::string actualPath = testutil::testOutputDir() + "/" + c.name + ".actual.png";
    ASSERT_TRUE(globe::writePng(actualPath, *actual));
    auto golden = globe::decodeImageFile(goldenPath);
    if (!golden || golden->width != w || golden->height != h) {
      ADD_FAILURE() << (golden ? goldenPath + ": wrong size" : golden.error()) << " (review " << actualPath
                    << ", then tests/promote-golden.sh)";
      continue;
    }
    globe::ImageRGBA8 diff = globe::ImageRGBA8::filled(w, h, {0, 0, 0, 255});
    double sumAbs = 0.0;
    int bad = 0;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const glm::ivec4 a(actual->at(x, y)), g(golden->at(x, y));
        const glm::ivec3 d = glm::abs(glm::ivec3(a) - glm::ivec3(g));
        sumAbs += d.r + d.g + d.b;
        const int m = std::max({d.r, d.g, d.b});
        if (m > 24) ++bad;
        const auto v = static_cast<std::uint8_t>(std::min(255, m * 8));
        diff.set(x, y, {v, v, v, 255});
      }
    }
    const double meanAbs = sumAbs / (3.0 * w * h);
    const double badFraction = static_cast<double>(bad) / (w * h);
    const bool pass = meanAbs <= 1.0 && badFraction <= 0.005;
    if (!pass) {
      const std::string diffPath = testutil::testOutputDir() + "/" + c.name + ".diff.png";
      EXPECT_TRUE(globe::writePng(diffPath, diff));
      ADD_FAILURE() << c.name << ": mean |diff| " << meanAbs << ", pixels off by >24: " << 100.0 * badFraction
                    << " %; actual " << actualPath << ", diff " << diffPath;
    }
  }
}

TEST(GoldenImage, RealRadarVolumesMatchReviewedImages) {
  // Real volumes (../shared/data) ray-marched over the globe, DVR and MIP: same tolerance
  // rule as above (mean |diff| <= 1, <= 0.5 % of pixels off by more than 24).
  testutil::glContext();
  auto loader = engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()}}, {});
  ASSERT_TRUE(loader) << loader.error();
  struct RadarCase {
    const char* name;
    const char* file;
    const char* mode;
    engine::CameraPose pose;
  };
  const std::string data = ATMOGLOBE_SHARED_DATA_DIR;
  const RadarCase cases[] = {
      {"radar_klbb_dvr", "/radar_nexrad/KLBB20160601_150025_V06", "dvr", {31.9, -101.81, 1.5e5, 0.0, -35.0, 0.0}},
      {"radar_au40_mip", "/radar_odim/40_20181220_060630.pvol.h5", "mip", {-37.2, 149.0, 1.2e5, 20.0, -40.0, 0.0}},
  };
  const int w = 200, h = 112;
  auto fb = engine::FramebufferGL::create(w, h);
  ASSERT_TRUE(fb);
  for (const RadarCase& c : cases) {
    auto renderer = engine::SceneRendererGL::create(*loader);
    ASSERT_TRUE(renderer) << renderer.error();
    engine::RadarLayerDescription d;
    d.path = data + c.file;
    d.mode = c.mode;
    auto layer = (*renderer)->addRadar(d);
    ASSERT_TRUE(layer) << layer.error();
    const engine::Camera camera(c.pose, 50.0, w, h);
    auto actual = (*renderer)->renderToImage(camera, {}, **fb);
    ASSERT_TRUE(actual) << actual.error();
    const std::string goldenPath = std::string(ATMOGLOBE_SOURCE_DIR) + "/tests/golden/" + c.name + ".png";
    const std::string actualPath = testutil::testOutputDir() + "/" + c.name + ".actual.png";
    ASSERT_TRUE(globe::writePng(actualPath, *actual));
    auto golden = globe::decodeImageFile(goldenPath);
    if (!golden || golden->width != w || golden->height != h) {
      ADD_FAILURE() << (golden ? goldenPath + ": wrong size" : golden.error()) << " (review " << actualPath
                    << ", then tests/promote-golden.sh)";
      continue;
    }
    double sumAbs = 0.0;
    int bad = 0;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const glm::ivec3 d3 = glm::abs(glm::ivec3(glm::ivec4(actual->at(x, y))) - glm::ivec3(glm::ivec4(golden->at(x, y))));
        sumAbs += d3.r + d3.g + d3.b;
        if (std::max({d3.r, d3.g, d3.b}) > 24) ++bad;
      }
    }
    const double meanAbs = sumAbs / (3.0 * w * h);
    const double badFraction = static_cast<double>(bad) / (w * h);
    EXPECT_LE(meanAbs, 1.0) << c.name << " (actual " << actualPath << ")";
    EXPECT_LE(badFraction, 0.005) << c.name << " (actual " << actualPath << ")";
  }
}
