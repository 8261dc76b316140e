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
  auto loader =
      engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()}}, {});
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
    testutil::expectMatchesGolden(c.name, *actual);
  }
}

TEST(GoldenImage, RealRadarVolumesMatchReviewedImages) {
  // Real volumes (../shared/data) ray-marched over the globe, DVR and MIP: same tolerance
  // rule as above (mean |diff| <= 1, <= 0.5 % of pixels off by more than 24).
  testutil::glContext();
  auto loader =
      engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()}}, {});
  ASSERT_TRUE(loader) << loader.error();
  struct RadarCase {
    const char* name;
    const char* file;
    const char* mode;
    engine::CameraPose pose;
  };
  const std::string data = atmoglobe_test::testDataDir();
  const RadarCase cases[] = {
      {"radar_klbb_dvr", "/radar_nexrad/KLBB20160601_150025_V06", "dvr", {31.9, -101.81, 1.5e5, 0.0, -35.0, 0.0}},
      {"radar_au40_mip", "/radar_odim/40_20181220_060630.pvol.h5", "mip", {-37.2, 149.0, 1.2e5, 20.0, -40.0, 0.0}},
  };
  const int w = 200, h = 112;
  auto fb = engine::FramebufferGL::create(w, h);
  ASSERT_TRUE(fb);
  for (const RadarCase& c : cases) {
    SKIP_WITHOUT_TEST_DATA(data + c.file);
    auto renderer = engine::SceneRendererGL::create(*loader);
    ASSERT_TRUE(renderer) << renderer.error();
    engine::VolumeLayerDescription d;
    d.path = data + c.file;
    d.mode = *engine::parseName<volume::VolumeRenderMode>(c.mode);
    auto layer = (*renderer)->addVolume(d);
    ASSERT_TRUE(layer) << layer.error();
    const engine::Camera camera(c.pose, 50.0, w, h);
    auto actual = (*renderer)->renderToImage(camera, {}, **fb);
    ASSERT_TRUE(actual) << actual.error();
    testutil::expectMatchesGolden(c.name, *actual);
  }
}
