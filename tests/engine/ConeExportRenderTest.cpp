// The cone export read back by the engine itself: a .glb written by exportCones is loaded
// with tinygltf, turned back into ECEF by its node matrix and drawn; each cone's rim must
// land on the pixel where the exact geolocation puts the last gate.
#include "GLTestUtil.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GltfModelRendererGL.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/ConeExport.h>
#include <atmoglobe/volume/Geolocation.h>

#include <gtest/gtest.h>

using namespace atmoglobe;

TEST(ConeExportRender, ExportedGlbDrawsAtTheGeolocatedPlace) {
  testutil::glContext();
  // One PPI sweep at 10 deg, 360 rays, 200 gates of 250 m: echo only in the last 8 gates of
  // the rays around azimuth 90, so the lit part of the cone is a small patch of its rim.
  volume::RadarVolume v;
  v.format = "synthetic";
  v.sourcePath = "synthetic";
  v.site = {"TEST", 45.0, 7.0, 500.0, volume::HeightDatum::Ellipsoid, {}};
  v.loadedField = {"DBZ", "dBZ", {}};
  v.fields = {v.loadedField};
  volume::Sweep s;
  s.fixedAngleDeg = 10.0;
  s.firstGateRangeMeters = 1125.0;
  s.gateSpacingMeters = 250.0;
  s.gateCount = 200;
  for (int ray = 0; ray < 360; ++ray) {
    s.azimuthDeg.push_back(static_cast<float>(ray + 0.5));
    s.elevationDeg.push_back(10.0f);
    for (std::uint32_t g = 0; g < s.gateCount; ++g) {
      s.values.push_back(ray >= 85 && ray < 95 && g >= 192 ? 50.0f : volume::kNoEcho);
    }
  }
  v.sweeps.push_back(s);
  volume::ConeExportOptions options;
  options.useGeoid = false;
  auto scene = volume::buildConeScene(v, volume::nwsReflectivityTable(), options);
  ASSERT_TRUE(scene) << scene.error();
  const std::string path = testutil::testOutputDir() + "/cones.glb";
  auto written = volume::exportCones(*scene, path);
  ASSERT_TRUE(written) << written.error();

  auto model = engine::GltfModelRendererGL::load(path);
  ASSERT_TRUE(model) << model.error();
  EXPECT_EQ((*model)->triangleCount(), scene->cones[0].mesh.triangleCount());

  // Straight down from 120 km over the site: the lit patch sits east of the site.
  const volume::GeolocationSite site{45.0, 7.0, 500.0};
  const volume::GatePosition rim =
      volume::geolocateGateExact(site, volume::BeamModel{}, 90.0, 10.0, 1125.0 + 196 * 250.0);
  const engine::Camera camera({45.0, 7.0, 1.2e5, 0.0, -90.0, 0.0}, 60.0, 160, 160);
  const auto predicted = camera.projectToPixel(rim.ecef);
  ASSERT_TRUE(predicted);
  auto fb = engine::FramebufferGL::create(160, 160);
  ASSERT_TRUE(fb);
  testutil::beginReverseZ(**fb);
  (*model)->draw(camera);
  const globe::ImageRGBA8 image = (*fb)->readColor();
  double sx = 0, sy = 0, n = 0;
  for (int y = 0; y < 160; ++y) {
    for (int x = 0; x < 160; ++x) {
      const glm::u8vec4 p = image.at(x, y);
      if (p.r + p.g + p.b > 60) {
        sx += x + 0.5;
        sy += y + 0.5;
        n += 1;
      }
    }
  }
  ASSERT_GT(n, 3.0) << "nothing drawn";
  // The patch spans 2 km in range and 10 deg in azimuth (~8.6 km across at 49 km) = ~2 x 8 px
  // here; its centroid is the geolocated centre of the patch within 1.5 px (texel edges).
  EXPECT_NEAR(sx / n, predicted->x, 1.5);
  EXPECT_NEAR(sy / n, predicted->y, 1.5);
}

TEST(ConeExportRender, BrokenGlbIsAClearError) {
  testutil::glContext();
  const std::string path = testutil::testOutputDir() + "/broken.glb";
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("glTF this is not a real binary", f);
    std::fclose(f);
  }
  auto model = engine::GltfModelRendererGL::load(path);
  ASSERT_FALSE(model);
  EXPECT_NE(model.error().find("broken.glb"), std::string::npos) << model.error();
}
