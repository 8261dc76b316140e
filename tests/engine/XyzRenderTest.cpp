// End to end: an XYZ (web-mercator) directory drawn over the base pyramid where it has
// data, with the base showing through elsewhere and above 85.05 deg.
#include "GLTestUtil.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>

#include <gtest/gtest.h>

#include <filesystem>

using namespace atmoglobe;

TEST(XyzRender, OverlayShowsWhereItHasDataAndBaseElsewhere) {
  testutil::glContext();
  // Zoom 0..1 where only tile z1/x1/y0 (lon 0..180, lat 0..85.05) exists: solid red.
  // Zoom 0 must exist for the layer to be openable at coarse levels; make it fully
  // transparent so it adds no data.
  const std::string dir = testutil::testOutputDir() + "/xyz-overlay";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/0/0");
  std::filesystem::create_directories(dir + "/1/1");
  ASSERT_TRUE(globe::writePng(dir + "/0/0/0.png", globe::ImageRGBA8::filled(256, 256, {0, 0, 0, 0})));
  ASSERT_TRUE(globe::writePng(dir + "/1/1/0.png", globe::ImageRGBA8::filled(256, 256, {255, 0, 0, 255})));

  auto loader = engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()},
                                     {engine::ImageryLayerDescription::Type::Xyz, dir}},
                                    {});
  ASSERT_TRUE(loader) << loader.error();
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer) << renderer.error();
  auto fb = engine::FramebufferGL::create(64, 64);
  ASSERT_TRUE(fb);
  auto centre = [&](double lat, double lon) {
    const engine::Camera camera({lat, lon, 2e6, 0.0, -90.0, 0.0}, 20.0, 64, 64);
    auto image = (*renderer)->renderToImage(camera, {}, **fb);
    EXPECT_TRUE(image) << (image ? "" : image.error());
    return image ? testutil::blockMean(*image, 32, 32, 3) : glm::dvec3(-1.0);
  };
  const glm::dvec3 inside = centre(45.0, 90.0);  // inside the red tile
  EXPECT_GT(inside.r, 240.0);
  EXPECT_LT(inside.g, 15.0);
  EXPECT_LT(inside.b, 15.0);
  const glm::dvec3 outside = centre(-45.0, 90.0);  // south: no XYZ data -> base (Indian Ocean)
  EXPECT_GT(outside.b, outside.r + 20.0);
  const glm::dvec3 westOfTile = centre(45.0, -90.0);  // North America: base
  EXPECT_LT(westOfTile.r, 200.0);
  EXPECT_GT(westOfTile.g, 20.0);
  const glm::dvec3 pole = centre(89.0, 90.0);  // above 85.05: mercator has no data
  EXPECT_GT(pole.g, 150.0);                    // base shows (Arctic ice: bright, not red)
}
