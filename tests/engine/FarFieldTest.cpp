// The far field of a radar network (engine/FarFieldGL.h, shaders/far_field.frag): seen from far
// away, the network drawn from slabs integrated down the vertical against the same network
// marched (and against the CPU reference), and used only where every pixel over it is wide.
#include "GLTestUtil.h"
#include "SyntheticPolarVolume.h"
#include "TestOutputDir.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FarFieldGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarNetworkGL.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/engine/VolumeSourceGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <vector>

namespace {

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;

constexpr double kCentreLatDeg = 36.0, kCentreLonDeg = -98.0;

// Reflectivity of a broad storm system around (centreLatDeg, centreLonDeg): a band 100 km wide
// through the centre, at 2-8 km, modulated by cells 40 km apart (up to 60 dBZ).
float stormAround(double centreLatDeg, double centreLonDeg, double latDeg, double lonDeg, double heightMeters) {
  const globe::GeodesicLine g = globe::geodesicInverse(centreLatDeg, centreLonDeg, latDeg, lonDeg);
  const double az = glm::radians(g.azimuth1Deg);
  const double x = g.distanceMeters * std::sin(az), y = g.distanceMeters * std::cos(az);
  const double band = std::exp(-std::pow((x - 0.5 * y) / 100e3, 2) - std::pow((heightMeters - 5000.0) / 3000.0, 2));
  const double cells = 0.6 + 0.4 * std::sin(x / 40e3 * 6.283) * std::cos(y / 40e3 * 6.283);
  const double dbz = 60.0 * band * cells;
  return dbz < 5.0 ? volume::kNoEcho : static_cast<float>(dbz);
}

float stormAt(double latDeg, double lonDeg, double heightMeters) {
  return stormAround(kCentreLatDeg, kCentreLonDeg, latDeg, lonDeg, heightMeters);
}

// A radar at (lat, lon) seeing the storm (testutil::radarSeeingField).
std::shared_ptr<const volume::PolarVolume> radarAt(double latDeg, double lonDeg) {
  return testutil::radarSeeingField(latDeg, lonDeg, stormAt);
}

// A volume image over black, 8-bit (to look at).
globe::ImageRGBA8 overBlack(const volume::VolumeImage& v) {
  globe::ImageRGBA8 out;
  out.width = v.widthPx;
  out.height = v.heightPx;
  for (int y = 0; y < v.heightPx; ++y)
    for (int x = 0; x < v.widthPx; ++x) {
      const glm::dvec4 c = glm::clamp(v.at(x, y), 0.0, 1.0) * 255.0;
      out.pixels.insert(out.pixels.end(),
                        {static_cast<std::uint8_t>(std::lround(c.r)), static_cast<std::uint8_t>(std::lround(c.g)),
                         static_cast<std::uint8_t>(std::lround(c.b)), 255});
    }
  return out;
}

// The network drawn with the far field on (auto) and off, the far field's slab sets made, and
// the far field again with every pixel visiting the slabs (no skipping by the mask).
struct Frames {
  volume::VolumeImage farField, marched, unmasked;
  volume::VolumeImage levelZero;  ///< the far field from the plan's slabs only (no merged levels)
  std::size_t slabSets = 0;
  int drawn = 0;  ///< pixels of the marched frame with alpha above 0.05
};
Frames drawBoth(engine::VolumeRendererGL& renderer, engine::RadarNetworkGL* network,
                const engine::VolumeRenderOptions& options, const Camera& camera) {
  Frames f;
  engine::VolumeRenderOptions on = options;
  on.farField = engine::FarField::Auto;
  const std::size_t before = renderer.farField().slabSetsMade();
  f.farField = testutil::renderVolumesGpu(renderer, camera, {{network, on}});
  f.slabSets = renderer.farField().slabSetsMade() - before;
  renderer.farField().setMaskSkipping(false);
  f.unmasked = testutil::renderVolumesGpu(renderer, camera, {{network, on}});
  renderer.farField().setMaskSkipping(true);
  renderer.farField().setMergedLevels(false);
  f.levelZero = testutil::renderVolumesGpu(renderer, camera, {{network, on}});
  renderer.farField().setMergedLevels(true);
  f.marched = testutil::renderVolumesGpu(renderer, camera, {{network, options}});
  for (int y = 0; y < camera.heightPx(); ++y)
    for (int x = 0; x < camera.widthPx(); ++x) f.drawn += f.marched.at(x, y).a > 0.05;
  return f;
}

// The far field's frame against the march's: the mask changes nothing, the far field was used, and
// its error and opacity are within the bounds docs/networks.md states. Returns the error.
volume::ImageError expectLikeTheMarch(const Frames& f, const std::string& what) {
  const volume::ImageError e = volume::compareImages(f.farField, f.marched);
  // The opacity drawn in all: the slabs' optical depth scaled by each piece's slant length.
  double alphaFar = 0.0, alphaMarched = 0.0;
  for (int y = 0; y < f.marched.heightPx; ++y)
    for (int x = 0; x < f.marched.widthPx; ++x) {
      alphaFar += f.farField.at(x, y).a;
      alphaMarched += f.marched.at(x, y).a;
    }
  const double opacityChange = alphaFar / alphaMarched - 1.0;
  std::cout << "far field, " << what << ": opacity in all " << opacityChange * 100.0 << " % from the march's; "
            << f.drawn << " pixels drawn, " << f.slabSets << " slab sets; against the march mean " << e.meanAbs
            << " max " << e.maxAbs << " PSNR " << e.psnrDb << " dB\n";
  EXPECT_GT(f.drawn, 1500) << what << ": the storm must fill part of the view";
  // Pixels whose ray the mask finds over empty columns only draw nothing: exactly what visiting
  // the slabs draws there (mask pyramid: MaskPyramidCoversEveryTexel).
  const volume::ImageError masked = volume::compareImages(f.farField, f.unmasked);
  EXPECT_EQ(masked.maxAbs, 0.0) << what << ": skipping by the mask changed " << masked.meanAbs << " of 255 on average";
  EXPECT_GT(e.maxAbs, 0.0) << what << ": the far field drew the marched picture exactly: was it used?";
  // Merged slabs where a pixel allows them: as close to the march as the plan's slabs alone.
  const volume::ImageError levelZero = volume::compareImages(f.levelZero, f.marched);
  const volume::ImageError merged = volume::compareImages(f.farField, f.levelZero);
  std::cout << "  from the plan's slabs only: against the march mean " << levelZero.meanAbs << " max "
            << levelZero.maxAbs << " PSNR " << levelZero.psnrDb << " dB; the merged levels changed it by mean "
            << merged.meanAbs << " max " << merged.maxAbs << "\n";
  // They add at most 0.015 of 255 to the mean error: measured +0.004 straight down, 0 at 55 deg
  // (only the plan's slabs qualify there), +0.003 at 72 deg; with slabs up to half a pixel across
  // the ray instead of a quarter, +0.044 at 55 deg.
  EXPECT_LT(e.meanAbs, levelZero.meanAbs + 0.015) << what;
  // The far field's error against the march: measured 0.17-0.18 of 255 mean, 43.5-43.8 dB over
  // Oklahoma (the march against the reference 0.002-0.02). Under 0.3 on average, and 40 dB, the
  // level docs/networks.md states for it; pixels where a ray's slant piece crosses a storm's edge
  // within a slab differ most (max 68-126).
  EXPECT_LT(e.meanAbs, 0.3) << what;
  EXPECT_GT(e.psnrDb, 40.0) << what;
  // The opacity in all within 2 % of the march's (measured +0.54 and +0.57 %): without the
  // slant scaling of each piece's optical depth the oblique view loses 7.8 %.
  EXPECT_LT(std::abs(opacityChange), 0.02) << what;
  return e;
}

class FarField : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    testutil::glContext();
    // Five overlapping radars over the storm, 100-150 km apart.
    const std::vector<std::shared_ptr<const volume::PolarVolume>> radars{
        radarAt(36.0, -98.0), radarAt(36.9, -97.2), radarAt(35.1, -98.8), radarAt(36.8, -99.2), radarAt(35.2, -96.9)};
    auto gl =
        engine::RadarNetworkGL::create(radars, volume::OverlapRule::WeightedMean, volume::FieldKind::Reflectivity);
    ASSERT_TRUE(gl) << gl.error();
    network_ = std::move(*gl).release();
    radars_ = new std::vector<std::shared_ptr<const volume::PolarVolume>>(radars);
  }
  static void TearDownTestSuite() {
    delete network_;
    delete radars_;
  }
  void SetUp() override {
    testutil::glContext();
    auto r = engine::VolumeRendererGL::create();
    ASSERT_TRUE(r) << r.error();
    renderer_ = std::move(*r);
    options_.render.transfer = volume::defaultReflectivityTransfer();
    options_.render.stepMeters = 250.0;
  }
  Frames draw(const Camera& camera) { return drawBoth(*renderer_, network_, options_, camera); }
  static inline engine::RadarNetworkGL* network_ = nullptr;
  static inline std::vector<std::shared_ptr<const volume::PolarVolume>>* radars_ = nullptr;
  std::unique_ptr<engine::VolumeRendererGL> renderer_;
  engine::VolumeRenderOptions options_;
};

TEST_F(FarField, FromFarAwayTheSlabsDrawWhatTheMarchDraws) {
  // Straight down from 1,500 km, oblique from 1,200 km up, 700 km south (55 deg down) and from
  // 1,500 km up, 450 km south (72 deg down): 320 x 180 pixels 5-8 km wide over the network.
  const globe::GeodesicPoint south = globe::geodesicDirect(kCentreLatDeg, kCentreLonDeg, 180.0, 700e3);
  const globe::GeodesicPoint nearSouth = globe::geodesicDirect(kCentreLatDeg, kCentreLonDeg, 180.0, 450e3);
  const Camera views[] = {
      Camera(CameraPose{kCentreLatDeg, kCentreLonDeg, 1.5e6, 0.0, -90.0, 0.0}, 40.0, 320, 180),
      Camera(CameraPose{south.latDeg, south.lonDeg, 1.2e6, 0.0, -55.0, 0.0}, 40.0, 320, 180),
      Camera(CameraPose{nearSouth.latDeg, nearSouth.lonDeg, 1.5e6, 0.0, -72.0, 0.0}, 40.0, 320, 180)};
  const std::string dir = atmoglobe_test::freshTestDir("far_field");
  for (const Camera& camera : views) {
    const Frames f = draw(camera);
    const std::string name = dir + "/pitch" + std::to_string(static_cast<int>(-camera.pose().pitchDeg));
    EXPECT_TRUE(globe::writePng(name + "_far_field.png", overBlack(f.farField)));
    EXPECT_TRUE(globe::writePng(name + "_marched.png", overBlack(f.marched)));
    const volume::VolumeImage ref = volume::renderReference({{&network_->referenceSampler(), options_.render}},
                                                            engine::referenceCameraFor(camera), false, 2);
    const volume::ImageError eRef = volume::compareImages(f.farField, ref);
    const volume::ImageError marchRef = volume::compareImages(f.marched, ref);
    expectLikeTheMarch(f, "pitch " + std::to_string(camera.pose().pitchDeg));
    std::cout << "  against the reference mean " << eRef.meanAbs << " (the march: " << marchRef.meanAbs << ")\n";
    // The first view makes the slabs; the others, as wide a footprint, take the same ones.
    EXPECT_EQ(f.slabSets, camera.pose().pitchDeg == -90.0 ? 1u : 0u);
    // Near the vertical the pixels draw from merged slabs.
    if (camera.pose().pitchDeg < -60.0) {
      EXPECT_GT(volume::compareImages(f.farField, f.levelZero).maxAbs, 0.0) << "merged slabs unused";
    }
  }
}

// Where the far field's coordinates wrap or bend: the test's network and storm moved onto the
// antimeridian (radars on both sides of 180 deg: texel x from the box's west edge must wrap; with
// neither the wrap in texelAt nor the one in piece(), the east half is lost: 1.0 of 255 mean,
// opacity -45 to -50 %), to 80 deg N and over the North Pole (a radar's range holds it: the box
// spans every longitude; above 75 deg each piece's texel is converted exactly, not interpolated,
// though at these views interpolating draws the same to 0.001 of 255), drawn as above.
TEST(FarFieldAtTheEdges, AcrossTheAntimeridianAndNearThePoleTheSlabsDrawWhatTheMarchDraws) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 250.0;
  struct Place {
    const char* name;
    double latDeg, lonDeg;
  };
  const std::string dir = atmoglobe_test::freshTestDir("far_field_edges");
  for (const Place& place :
       {Place{"antimeridian", -17.0, 180.0}, Place{"north80", 80.0, 15.0}, Place{"pole", 88.5, 15.0}}) {
    const auto field = [&place](double latDeg, double lonDeg, double heightMeters) {
      return stormAround(place.latDeg, place.lonDeg, latDeg, lonDeg, heightMeters);
    };
    // The fixture's layout: one radar at the centre and four 115-135 km away.
    std::vector<std::shared_ptr<const volume::PolarVolume>> radars{
        testutil::radarSeeingField(place.latDeg, place.lonDeg, field)};
    double westMostLon = 180.0, eastMostLon = -180.0, nearestToPoleMeters = 1e30;
    for (const auto& [azimuthDeg, distanceMeters] :
         {std::pair{35.0, 120e3}, std::pair{215.0, 120e3}, std::pair{300.0, 125e3}, std::pair{130.0, 135e3}}) {
      const globe::GeodesicPoint p = globe::geodesicDirect(place.latDeg, place.lonDeg, azimuthDeg, distanceMeters);
      radars.push_back(testutil::radarSeeingField(p.latDeg, p.lonDeg, field));
      nearestToPoleMeters =
          std::min(nearestToPoleMeters, globe::geodesicInverse(p.latDeg, p.lonDeg, 90.0, 0.0).distanceMeters);
      westMostLon = std::min(westMostLon, p.lonDeg);
      eastMostLon = std::max(eastMostLon, p.lonDeg);
    }
    if (std::string(place.name) == "antimeridian") {
      ASSERT_TRUE(westMostLon < -179.0 && eastMostLon > 179.0) << "the radars must lie on both sides of 180 deg";
    }
    if (std::string(place.name) == "pole") {
      // radarSeeingField's gates end at 120 km.
      ASSERT_LT(nearestToPoleMeters, 100e3) << "a radar's range must hold the pole";
    }
    auto network =
        engine::RadarNetworkGL::create(radars, volume::OverlapRule::WeightedMean, volume::FieldKind::Reflectivity);
    ASSERT_TRUE(network) << network.error();
    // Straight down, from the south looking north, and from the west looking east (across the
    // antimeridian in the first place, across every meridian near the pole in the last).
    const globe::GeodesicPoint south = globe::geodesicDirect(place.latDeg, place.lonDeg, 180.0, 700e3);
    const globe::GeodesicPoint west = globe::geodesicDirect(place.latDeg, place.lonDeg, 270.0, 700e3);
    const Camera views[] = {
        Camera(CameraPose{place.latDeg, place.lonDeg, 1.5e6, 0.0, -90.0, 0.0}, 40.0, 320, 180),
        Camera(CameraPose{south.latDeg, south.lonDeg, 1.2e6, 0.0, -55.0, 0.0}, 40.0, 320, 180),
        Camera(CameraPose{west.latDeg, west.lonDeg, 1.2e6, west.azimuthDeg + 180.0, -55.0, 0.0}, 40.0, 320, 180)};
    for (const Camera& camera : views) {
      const Frames f = drawBoth(**renderer, network->get(), options, camera);
      engine::VolumeRenderOptions on = options;
      on.farField = engine::FarField::Auto;
      const std::optional<engine::FarFieldPlan> plan = engine::FarFieldGL::planFor(camera, {network->get(), on});
      ASSERT_TRUE(plan) << place.name;
      std::cout << place.name << ": texels from " << plan->westDeg << " E " << plan->southDeg << " N, " << plan->columns
                << " x " << plan->rows << " of " << plan->lonStepDeg << " x " << plan->latStepDeg << " deg\n";
      if (std::string(place.name) == "pole") {
        EXPECT_GE(plan->columns * plan->lonStepDeg, 360.0) << "over the pole the texels span every longitude";
      }
      const std::string name = dir + "/" + place.name + "_heading" +
                               std::to_string(std::lround(camera.pose().headingDeg)) + "_pitch" +
                               std::to_string(std::lround(-camera.pose().pitchDeg));
      EXPECT_TRUE(globe::writePng(name + "_far_field.png", overBlack(f.farField)));
      EXPECT_TRUE(globe::writePng(name + "_marched.png", overBlack(f.marched)));
      expectLikeTheMarch(f, std::string(place.name) + ", heading " + std::to_string(camera.pose().headingDeg) +
                                ", pitch " + std::to_string(camera.pose().pitchDeg));
    }
  }
}

TEST(FarFieldMask, MaskPyramidCoversEveryTexel) {
  // Odd, even, one-texel and lopsided sizes; a few set texels each (a sparse storm field).
  const int sizes[][2] = {{1, 1}, {2, 1}, {5, 3}, {7, 7}, {64, 32}, {65, 33}, {129, 2}, {1, 77}, {2078, 17}};
  std::uint32_t seed = 12345u;
  auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    for (int trial = 0; trial < 4; ++trial) {
      std::vector<std::uint8_t> level0(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
      for (int n = 0; n < 1 + trial * 3; ++n) level0[next() % level0.size()] = 255;
      if (trial == 3) level0.back() = 255;  // the last texel: the one an odd size's edge covers
      const auto levels = engine::FarFieldGL::maskPyramid(level0, w, h);
      int expected = 1;
      while ((std::max(w, h) >> expected) > 0) ++expected;
      ASSERT_EQ(levels.size(), static_cast<std::size_t>(expected)) << w << "x" << h;
      ASSERT_EQ(levels.back().size(), 1u);
      for (std::size_t l = 0; l < levels.size(); ++l) {
        const int lw = std::max(1, w >> l), lh = std::max(1, h >> l);
        ASSERT_EQ(levels[l].size(), static_cast<std::size_t>(lw) * static_cast<std::size_t>(lh));
        // Each texel of level l is set exactly when a level-0 texel mapping to it is.
        std::vector<std::uint8_t> want(levels[l].size(), 0);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const int cx = std::min(x >> l, lw - 1), cy = std::min(y >> l, lh - 1);
            auto& m = want[static_cast<std::size_t>(cy) * static_cast<std::size_t>(lw) + static_cast<std::size_t>(cx)];
            m = std::max(
                m, level0[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)]);
          }
        EXPECT_EQ(levels[l], want) << w << "x" << h << " level " << l;
      }
    }
  }
}

TEST(FarFieldMask, TheMaskLevelsLieApartInOneTexture) {
  // Each level where maskPyramid sizes it, inside the texture, overlapping no other.
  const int sizes[][2] = {{1, 1},   {2, 1},   {5, 3},  {3, 5},     {64, 32},
                          {65, 33}, {129, 2}, {1, 77}, {2078, 17}, {2078, 1008}};
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    const engine::FarFieldGL::MaskAtlas atlas = engine::FarFieldGL::maskAtlas(w, h);
    const std::vector<std::uint8_t> level0(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 1);
    const auto pyramid = engine::FarFieldGL::maskPyramid(level0, w, h);
    ASSERT_EQ(atlas.levels.size(), pyramid.size()) << w << "x" << h;
    std::vector<int> owner(static_cast<std::size_t>(atlas.width) * static_cast<std::size_t>(atlas.height), -1);
    for (std::size_t l = 0; l < atlas.levels.size(); ++l) {
      const auto& r = atlas.levels[l];
      EXPECT_EQ(static_cast<std::size_t>(r[2]) * static_cast<std::size_t>(r[3]), pyramid[l].size()) << l;
      EXPECT_EQ(r[2], std::max(1, w >> l));
      ASSERT_GE(r[0], 0);
      ASSERT_GE(r[1], 0);
      ASSERT_LE(r[0] + r[2], atlas.width) << w << "x" << h << " level " << l;
      ASSERT_LE(r[1] + r[3], atlas.height) << w << "x" << h << " level " << l;
      for (int y = r[1]; y < r[1] + r[3]; ++y)
        for (int x = r[0]; x < r[0] + r[2]; ++x) {
          int& o =
              owner[static_cast<std::size_t>(y) * static_cast<std::size_t>(atlas.width) + static_cast<std::size_t>(x)];
          EXPECT_EQ(o, -1) << w << "x" << h << ": levels " << o << " and " << l << " overlap at " << x << "," << y;
          o = static_cast<int>(l);
        }
    }
    // At most half as much again as level 0 along its shorter side.
    EXPECT_LE(static_cast<double>(atlas.width) * atlas.height, 1.5 * w * h + std::max(w, h)) << w << "x" << h;
  }
}

// Pixels side by side ask the mask about chords of different lengths, so at different levels.
// This machine's llvmpipe answers textureSize(sampler, level) wrongly where the level varies from
// pixel to pixel (fetches at the levels' sizes it gave missed their texels in 26-42 % of the
// pixels of a 128 x 128 texture; with each level's size computed instead, none), so with the mask's
// levels as GL mip levels pixels over storms were skipped: 407 of the 159-radar continental view
// at 1280x720, speckling its storms, and 2 of the third view here. Small cells far apart leave
// most columns empty, where the mask matters: it must change no pixel.
TEST(FarFieldMask, PixelsAskingForDifferentLevelsSkipNothing) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  // Cells 10 km across at 2-9 km, 0.4 deg apart.
  const auto cells = [](double latDeg, double lonDeg, double heightMeters) {
    const double dy = (latDeg / 0.4 - std::round(latDeg / 0.4)) * 0.4 * 111e3;
    const double dx = (lonDeg / 0.4 - std::round(lonDeg / 0.4)) * 0.4 * 90e3;
    const double dbz =
        55.0 * std::exp(-(dx * dx + dy * dy) / (5e3 * 5e3) - std::pow((heightMeters - 5500.0) / 3500.0, 2));
    return dbz < 5.0 ? volume::kNoEcho : static_cast<float>(dbz);
  };
  const std::vector<std::shared_ptr<const volume::PolarVolume>> radars{testutil::radarSeeingField(36.0, -98.0, cells),
                                                                       testutil::radarSeeingField(36.9, -97.2, cells),
                                                                       testutil::radarSeeingField(35.2, -96.9, cells)};
  auto network =
      engine::RadarNetworkGL::create(radars, volume::OverlapRule::WeightedMean, volume::FieldKind::Reflectivity);
  ASSERT_TRUE(network) << network.error();
  engine::VolumeRenderOptions on;
  on.render.transfer = volume::defaultReflectivityTransfer();
  on.render.stepMeters = 250.0;
  on.farField = engine::FarField::Auto;
  const globe::GeodesicPoint south = globe::geodesicDirect(36.0, -98.0, 180.0, 900e3);
  const globe::GeodesicPoint west = globe::geodesicDirect(36.0, -98.0, 270.0, 1500e3);
  const Camera views[] = {Camera(CameraPose{36.0, -98.0, 1.6e6, 0.0, -90.0, 0.0}, 40.0, 320, 180),
                          Camera(CameraPose{south.latDeg, south.lonDeg, 1.6e6, 0.0, -55.0, 0.0}, 40.0, 640, 360),
                          Camera(CameraPose{south.latDeg, south.lonDeg, 3.0e6, 0.0, -60.0, 0.0}, 40.0, 1280, 720),
                          Camera(CameraPose{west.latDeg, west.lonDeg, 3.0e6, 90.0, -60.0, 0.0}, 40.0, 1280, 720)};
  for (const Camera& camera : views) {
    const std::size_t before = (*renderer)->farField().slabSetsMade();
    const volume::VolumeImage masked = testutil::renderVolumesGpu(**renderer, camera, {{network->get(), on}});
    (*renderer)->farField().setMaskSkipping(false);
    const volume::VolumeImage unmasked = testutil::renderVolumesGpu(**renderer, camera, {{network->get(), on}});
    (*renderer)->farField().setMaskSkipping(true);
    int drawn = 0, changed = 0;
    for (int y = 0; y < camera.heightPx(); ++y)
      for (int x = 0; x < camera.widthPx(); ++x) {
        drawn += unmasked.at(x, y).a > 0.05;
        changed += masked.at(x, y) != unmasked.at(x, y);
      }
    const std::string what = std::to_string(camera.widthPx()) + " px, pitch " + std::to_string(camera.pose().pitchDeg);
    std::cout << what << ": " << drawn << " pixels drawn, " << changed << " changed by the mask\n";
    EXPECT_GT(drawn, 200) << what << ": the cells must be seen";
    EXPECT_EQ(changed, 0) << what;
    if (camera.pose().heightMeters == 1.6e6 && camera.pose().pitchDeg == -90.0) {
      EXPECT_EQ((*renderer)->farField().slabSetsMade() - before, 1u) << "the far field was not used";
    }
  }
}

TEST_F(FarField, TheSlabsEndAtTheHighestEcho) {
  // stormAt echoes (5 dBZ or more) up to 9.73 km: 60 exp(-((h - 5 km) / 3 km)^2) = 5 there. A
  // radar's occupied cells (volume::buildOccupancyGrid) reach from a sweep with echo up to the next
  // sweep's centre, 1 deg higher (the rule interpolates between beam centres): 2.1 km at the last
  // gate (120 km); plus the support's margin there (0.44 km: the arcs' sagitta, the beam's
  // curvature, 50 m) and a cell (32 over the box's ~19 km: 0.6 km): 12.87 km at most. The highest
  // beam (7.5 deg, 0.5 deg wide above its centre, at 120 km) is 17.9 km up, where the slabs ended
  // before.
  const std::optional<engine::FarFieldExtent> e = network_->farFieldExtent();
  ASSERT_TRUE(e);
  std::cout << "far field top " << e->topMeters << " m\n";
  EXPECT_GT(e->topMeters, 9730.0);
  EXPECT_LT(e->topMeters, 12870.0);
}

TEST_F(FarField, ACloseViewIsMarchedAndASecondFrameMakesNoSlabs) {
  // 300 km up: pixels of 1.6 km at 320 x 180 (under FarFieldGL::kMinFootprintMeters).
  const Camera close(CameraPose{kCentreLatDeg, kCentreLonDeg, 3e5, 0.0, -90.0, 0.0}, 40.0, 320, 180);
  const Frames f = draw(close);
  EXPECT_EQ(f.slabSets, 0u);
  EXPECT_EQ(volume::compareImages(f.farField, f.marched).maxAbs, 0.0);
  const Camera far(CameraPose{kCentreLatDeg, kCentreLonDeg, 2e6, 0.0, -90.0, 0.0}, 40.0, 320, 180);
  EXPECT_EQ(draw(far).slabSets, 1u);
  EXPECT_EQ(draw(far).slabSets, 0u) << "the same view again must reuse the slabs";
  // Farther away the slabs made are fine enough: none made.
  const Camera farther(CameraPose{kCentreLatDeg, kCentreLonDeg, 4e6, 0.0, -90.0, 0.0}, 40.0, 320, 180);
  EXPECT_EQ(draw(farther).slabSets, 0u);
  // Another transfer function makes them again.
  options_.render.transfer.maxOpacity *= 0.5;
  EXPECT_EQ(draw(far).slabSets, 1u);
  // Near the limb (an eye 800 km up, 3,000 km south, looking at the network's ground nearly
  // edge-on) the thickest slab (2.2 km: 10 km to the 12.2 km top) lies across the rays: with the
  // narrowest pixel 2.3 km wide it spans under a pixel and the far field draws; with 2.1 km
  // (still over FarFieldGL::kMinFootprintMeters) over a pixel (FarFieldGL::kMaxSlabAcrossPixels)
  // and it is marched, pixel for pixel.
  {
    const std::optional<engine::FarFieldExtent> extent = network_->farFieldExtent();
    ASSERT_TRUE(extent);
    const volume::BoundingSphere sphere = network_->referenceSampler().boundingSphere();
    const globe::GeodesicPoint south = globe::geodesicDirect(kCentreLatDeg, kCentreLonDeg, 180.0, 3000e3);
    const CameraPose pose{south.latDeg, south.lonDeg, 8e5, 0.0, -13.5, 0.0};
    const double nearest = glm::length(sphere.centreEcef - Camera(pose, 8.0, 320, 180).eyeEcef()) - sphere.radiusMeters;
    engine::VolumeRenderOptions on = options_;
    on.farField = engine::FarField::Auto;
    for (const double pixelMeters : {2300.0, 2100.0}) {
      // 180 pixels tall: focal length = 90 / tan(fov / 2).
      const double fovDeg = 2.0 * glm::degrees(std::atan(90.0 / (nearest / pixelMeters)));
      const Camera limb(pose, fovDeg, 320, 180);
      const std::optional<engine::FarFieldPlan> plan = engine::FarFieldGL::planFor(limb, {network_, on});
      if (pixelMeters > 2200.0) {
        ASSERT_TRUE(plan) << "pixels of 2.3 km";
        EXPECT_GT(plan->view.maxIncidenceDeg, 85.0);
        EXPECT_NEAR(plan->boundariesMeters[0] - plan->boundariesMeters[1], 2200.0, 100.0) << "the thickest slab";
        continue;
      }
      EXPECT_FALSE(plan) << "pixels of 2.1 km";
      const Frames atLimb = draw(limb);
      std::cout << "near the limb, pixels of 2.1 km: " << atLimb.drawn << " pixels drawn, marched\n";
      EXPECT_GT(atLimb.drawn, 100);
      EXPECT_EQ(atLimb.slabSets, 0u);
      EXPECT_EQ(volume::compareImages(atLimb.farField, atLimb.marched).maxAbs, 0.0);
    }
  }
  // MIP is marched whatever the setting.
  options_.render.mode = volume::VolumeRenderMode::Mip;
  const Frames mip = draw(far);
  EXPECT_EQ(mip.slabSets, 0u);
  EXPECT_EQ(volume::compareImages(mip.farField, mip.marched).maxAbs, 0.0);
}

// An image of n x n times fewer pixels, each the mean of the n x n pixels it covers.
volume::VolumeImage averageDown(const volume::VolumeImage& fine, int n) {
  volume::VolumeImage out;
  out.widthPx = fine.widthPx / n;
  out.heightPx = fine.heightPx / n;
  out.rgbaPremultiplied.assign(static_cast<std::size_t>(out.widthPx) * static_cast<std::size_t>(out.heightPx),
                               glm::dvec4(0.0));
  for (int y = 0; y < out.heightPx * n; ++y)
    for (int x = 0; x < out.widthPx * n; ++x)
      out.rgbaPremultiplied[static_cast<std::size_t>(y / n) * static_cast<std::size_t>(out.widthPx) +
                            static_cast<std::size_t>(x / n)] += fine.at(x, y) / static_cast<double>(n * n);
  return out;
}

// Near the limb a ray's piece of a 2 km slab runs tens of km sideways: it is cut into sub-pieces
// that each run at most a pixel's width (shaders/far_field.frag). Seen so slantwise, the march
// itself is far from the pixel's whole footprint (one ray where the pixel spans tens of km of
// ground along the view), so both are measured against the mean of 4 x 4 rays per pixel as well
// as against each other.
TEST_F(FarField, NearTheLimbTheSlabsDrawWhatTheMarchDraws) {
  struct View {
    const char* name;
    double distanceMeters, heightMeters, fovDeg;
  };
  const std::string dir = atmoglobe_test::freshTestDir("far_field_limb");
  // Pixels of 4.4-5.8 km at the network's nearest point: its 2 km slabs span at most half a pixel
  // across the rays (FarFieldGL::kMaxSlabAcrossPixels allows a pixel: with pixels of 2.3 km the
  // far field was measured at 1.35x the march's error against 4 x 4 rays, opacity +7.2 %).
  for (const View& v : {View{"limb800", 3000e3, 8e5, 16.0}, View{"limb2000", 3500e3, 2e6, 16.0},
                        View{"slant1500", 2000e3, 1.5e6, 20.0}}) {
    // From v.distanceMeters south of the storm's centre, looking at it (5 km up).
    const globe::GeodesicPoint south = globe::geodesicDirect(kCentreLatDeg, kCentreLonDeg, 180.0, v.distanceMeters);
    const glm::dvec3 eye = globe::geodeticToEcef({south.latDeg, south.lonDeg, v.heightMeters});
    const glm::dvec3 d = glm::normalize(globe::geodeticToEcef({kCentreLatDeg, kCentreLonDeg, 5000.0}) - eye);
    const glm::dmat3 enu = globe::enuAxes(south.latDeg, south.lonDeg);
    const double pitchDeg = glm::degrees(std::asin(glm::dot(d, enu[2])));
    const double headingDeg = glm::degrees(std::atan2(glm::dot(d, enu[0]), glm::dot(d, enu[1])));
    const Camera camera(CameraPose{south.latDeg, south.lonDeg, v.heightMeters, headingDeg, pitchDeg, 0.0}, v.fovDeg,
                        320, 180);
    const Camera fine(camera.pose(), v.fovDeg, 1280, 720);
    engine::VolumeRenderOptions on = options_;
    on.farField = engine::FarField::Auto;
    const std::optional<engine::FarFieldPlan> plan = engine::FarFieldGL::planFor(camera, {network_, on});
    ASSERT_TRUE(plan) << v.name << ": every pixel over the network is 4 km wide or more";
    EXPECT_TRUE(plan->view.subPieces) << v.name << ": a 2 km slab seen 70 deg or more from the vertical";
    const Frames f = draw(camera);
    const volume::VolumeImage rays4x4 =
        averageDown(testutil::renderVolumesGpu(*renderer_, fine, {{network_, options_}}), 4);
    const volume::ImageError farMarch = volume::compareImages(f.farField, f.marched);
    const volume::ImageError far4x4 = volume::compareImages(f.farField, rays4x4);
    const volume::ImageError march4x4 = volume::compareImages(f.marched, rays4x4);
    double alphaFar = 0.0, alphaMarched = 0.0, alpha4x4 = 0.0;
    for (int y = 0; y < camera.heightPx(); ++y)
      for (int x = 0; x < camera.widthPx(); ++x) {
        alphaFar += f.farField.at(x, y).a;
        alphaMarched += f.marched.at(x, y).a;
        alpha4x4 += rays4x4.at(x, y).a;
      }
    std::cout << v.name << ": its ground seen up to " << plan->view.maxIncidenceDeg << " deg from the vertical, "
              << f.drawn << " pixels drawn; far field against the march mean " << farMarch.meanAbs << " max "
              << farMarch.maxAbs << " (" << farMarch.psnrDb << " dB), opacity in all "
              << (alphaFar / alphaMarched - 1.0) * 100.0
              << " % (4 x 4 rays: " << (alpha4x4 / alphaMarched - 1.0) * 100.0 << " %); against 4 x 4 rays: far field "
              << far4x4.meanAbs << " (" << far4x4.psnrDb << " dB), march " << march4x4.meanAbs << " ("
              << march4x4.psnrDb << " dB)\n";
    EXPECT_TRUE(globe::writePng(dir + "/" + v.name + "_far_field.png", overBlack(f.farField)));
    EXPECT_TRUE(globe::writePng(dir + "/" + v.name + "_marched.png", overBlack(f.marched)));
    EXPECT_TRUE(globe::writePng(dir + "/" + v.name + "_4x4.png", overBlack(rays4x4)));
    EXPECT_GT(f.drawn, 100) << v.name << ": the storm must fill part of the view";
    EXPECT_GT(farMarch.maxAbs, 0.0) << v.name << ": the far field drew the marched picture exactly: was it used?";
    EXPECT_EQ(volume::compareImages(f.farField, f.unmasked).maxAbs, 0.0) << v.name << ": the mask changed pixels";
    // Against 4 x 4 rays the far field was measured at 0.88x, 0.83x and 0.97x the march's mean
    // error (0.083 against 0.094, 0.14 against 0.17, 0.30 against 0.31 of 255); with each piece one
    // texel at its middle (no sub-pieces) 1.52x, 1.03x and 0.97x. At most 1.25x.
    EXPECT_LT(far4x4.meanAbs, 1.25 * march4x4.meanAbs) << v.name;
    // The opacity in all within 6 % of the march's: measured +4.8, +2.2 and +1.3 % (-9.1, +1.3
    // and +1.3 % without sub-pieces). Near the limb the storm is a band a few pixels tall, and
    // each slab spreads its echo over its thickness (up to half a pixel across the ray), which
    // adds to the band's edges; away from the limb it is within 2 % (expectLikeTheMarch).
    EXPECT_LT(std::abs(alphaFar / alphaMarched - 1.0), 0.06) << v.name;
  }
}

TEST_F(FarField, MadeOverFramesTheSlabsEndAsThoseMadeAtOnce) {
  // 160 x 90 pixels 2,000 km up: slabs of more than a band's block (FarFieldGL::kBandBlock) each
  // way, so that bands meet along rows and along columns.
  const Camera far(CameraPose{kCentreLatDeg, kCentreLonDeg, 2e6, 0.0, -90.0, 0.0}, 40.0, 160, 90);
  engine::VolumeRenderOptions on = options_;
  on.farField = engine::FarField::Auto;
  const Frames atOnce = draw(far);  // no budget: made whole in the frame
  ASSERT_EQ(atOnce.slabSets, 1u);
  ASSERT_FALSE(renderer_->farFieldPending());
  ASSERT_GT(volume::compareImages(atOnce.farField, atOnce.marched).maxAbs, 0.0);

  // A budget of a microsecond a frame: one band a frame, each a block of kBandBlock x kBandBlock
  // texels (or what is left of a row of blocks).
  auto made = engine::VolumeRendererGL::create();
  ASSERT_TRUE(made) << made.error();
  engine::VolumeRendererGL& r = **made;
  r.setFarFieldBuildBudgetMs(1e-3);
  const volume::VolumeImage first = testutil::renderVolumesGpu(r, far, {{network_, on}});
  EXPECT_TRUE(r.farFieldPending());
  EXPECT_EQ(r.farField().slabSetsMade(), 0u);
  EXPECT_EQ(volume::compareImages(first, atOnce.marched).maxAbs, 0.0) << "until its slabs are made it is marched";
  int frames = 1;
  volume::VolumeImage last = first;
  while (r.farFieldPending() && frames < 5000) {
    last = testutil::renderVolumesGpu(r, far, {{network_, on}});
    ++frames;
  }
  const std::optional<engine::FarFieldPlan> plan = engine::FarFieldGL::planFor(far, {network_, on});
  ASSERT_TRUE(plan);
  std::cout << "far field made over " << frames << " frames, " << r.farField().bandsMarched() << " bands; "
            << plan->columns << " x " << plan->rows << " texels, " << plan->slabCount() << " slabs\n";
  ASSERT_FALSE(r.farFieldPending());
  EXPECT_EQ(r.farField().slabSetsMade(), 1u);
  EXPECT_EQ(r.farField().bandsMarched(), static_cast<std::size_t>(frames)) << "one band a frame";
  ASSERT_GT(plan->columns, engine::FarFieldGL::kBandBlock);
  ASSERT_GT(plan->rows, engine::FarFieldGL::kBandBlock);
  // At least 2 x 2 blocks a slab, then the mask's level 0 in bands of kBandBlock rows.
  const int maskBands = (plan->rows + engine::FarFieldGL::kBandBlock - 1) / engine::FarFieldGL::kBandBlock;
  EXPECT_GE(frames, 4 * plan->slabCount() + maskBands) << "the slabs and the mask must have been made in bands";
  // The same texels whether marched in bands or whole: the same picture, pixel for pixel.
  EXPECT_EQ(volume::compareImages(last, atOnce.farField).maxAbs, 0.0);

  // Nearer (texels twice as fine needed): drawn from the coarser slabs while the finer are made.
  const Camera nearer(CameraPose{kCentreLatDeg, kCentreLonDeg, 1e6, 0.0, -90.0, 0.0}, 40.0, 160, 90);
  const Frames fine = draw(nearer);
  ASSERT_EQ(fine.slabSets, 1u) << "nearer, finer slabs are needed";
  const std::size_t bands = r.farField().bandsMarched();
  const volume::VolumeImage meanwhile = testutil::renderVolumesGpu(r, nearer, {{network_, on}});
  EXPECT_TRUE(r.farFieldPending());
  EXPECT_GT(r.farField().bandsMarched(), bands);
  EXPECT_GT(volume::compareImages(meanwhile, fine.marched).maxAbs, 0.0) << "the coarser slabs, not the march";
  EXPECT_GT(volume::compareImages(meanwhile, fine.farField).maxAbs, 0.0) << "not the finer slabs yet";
  const volume::ImageError coarse = volume::compareImages(meanwhile, fine.marched);
  const volume::ImageError fineError = volume::compareImages(fine.farField, fine.marched);
  std::cout << "nearer, against the march: the coarser slabs mean " << coarse.meanAbs << " (" << coarse.psnrDb
            << " dB), the finer " << fineError.meanAbs << " (" << fineError.psnrDb << " dB)\n";
  // Texels twice as wide as the view needs: measured 0.74 of 255 mean (35.6 dB) against the
  // finer slabs' 0.40 (39.9 dB; 160 x 90 pixels 9 km wide). Within 3x the finer slabs' error: a
  // stand-in for a few frames, not a wrong picture.
  EXPECT_LT(coarse.meanAbs, 3.0 * fineError.meanAbs);
}

TEST_F(FarField, AtRestTheTilesWaitForTheSlabsAndTheRefinedFrameIsDrawnFromThem) {
  const Camera far(CameraPose{kCentreLatDeg, kCentreLonDeg, 2e6, 0.0, -90.0, 0.0}, 40.0, 160, 90);
  engine::VolumeRenderOptions on = options_;
  on.farField = engine::FarField::Auto;
  auto fb = engine::FramebufferGL::create(far.widthPx(), far.heightPx());
  ASSERT_TRUE(fb);
  const auto clear = [&] {
    (*fb)->bind();
    glClearDepth(0.0);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  };
  clear();
  renderer_->draw(far, {{network_, on}}, **fb);  // slabs made at once
  const globe::ImageRGBA8 oneShot = (*fb)->readColor();

  auto made = engine::VolumeRendererGL::create();
  ASSERT_TRUE(made) << made.error();
  engine::VolumeRendererGL& r = **made;
  r.setFarFieldBuildBudgetMs(1e-3);  // one band a call
  int calls = 0, callsWithSlabsPending = 0;
  bool done = false;
  while (!done && calls < 5000) {
    clear();
    done = r.drawProgressive(far, {{network_, on}}, **fb, 0.0);  // one tile a call
    ++calls;
    if (r.farFieldPending()) {
      ++callsWithSlabsPending;
      EXPECT_FALSE(done);
      EXPECT_EQ(r.progressiveTiles().first, 0u) << "a tile marched while the slabs are being made";
    }
  }
  std::cout << "at rest: " << calls << " calls, " << callsWithSlabsPending << " of them making slabs, "
            << r.progressiveTiles().second << " tiles\n";
  ASSERT_TRUE(done);
  EXPECT_EQ(r.farField().slabSetsMade(), 1u);
  // One band a call, at least 2 x 2 blocks a slab (MadeOverFramesTheSlabsEndAsThoseMadeAtOnce);
  // the call that completes the set is not pending.
  const std::optional<engine::FarFieldPlan> plan = engine::FarFieldGL::planFor(far, {network_, on});
  ASSERT_TRUE(plan);
  EXPECT_GE(callsWithSlabsPending, 4 * plan->slabCount() - 1);
  // The set completed before any tile was marched: the first call's preview stays (marched again,
  // a network's preview took 0.4-0.6 s in the viewer).
  EXPECT_EQ(r.previewsMarched(), 1u);
  // After the slabs: the tiles, one a call, from the far field.
  EXPECT_EQ(calls - callsWithSlabsPending, static_cast<int>(r.progressiveTiles().second));
  const globe::ImageRGBA8 refined = (*fb)->readColor();
  int differing = 0;
  for (int y = 0; y < refined.height; ++y)
    for (int x = 0; x < refined.width; ++x) differing += refined.at(x, y) != oneShot.at(x, y);
  EXPECT_EQ(differing, 0) << "the refined frame must be draw()'s with the slabs made at once";
}

TEST(FarFieldScene, TheSceneKeyRoundTrips) {
  const std::string dir = atmoglobe_test::freshTestDir("far_field_scene");
  auto scene = engine::parseSceneJson(R"({"radars": [{"path": "n/*.nc", "far_field": "auto"}]})", "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_EQ(engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0].farField, engine::FarField::Auto);
  EXPECT_NE(engine::sceneToJson(*scene).find("\"far_field\": \"auto\""), std::string::npos);
  const auto bad = engine::parseSceneJson(R"({"radars": [{"path": "n/*.nc", "far_field": "on"}]})", "s.json", dir, dir);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("far_field"), std::string::npos) << bad.error();
}

// Without "far_field" (or --far-field) a network takes the command's default: the viewer sets it
// to auto (it makes the slabs over frames), render leaves it unset, which draws it marched; an
// explicit "off" stays off in the viewer, and an unset one is not written back.
TEST(FarFieldScene, UnsetTheViewerDrawsTheFarFieldAndRenderMarches) {
  const std::string dir = atmoglobe_test::freshTestDir("far_field_default");
  auto scene = engine::parseSceneJson(
      R"({"radars": [{"path": "a/*.nc"}, {"path": "b/*.nc", "far_field": "off"}, {"path": "c/*.nc", "far_field": "auto"}],
          "grids": [{"path": "g.nc", "variable": "T"}]})",
      "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  std::vector<engine::VolumeLayerDescription> radars = engine::volumesOfKind(*scene, engine::VolumeKind::Radar);
  ASSERT_EQ(radars.size(), 3u);
  EXPECT_FALSE(radars[0].farField.has_value());
  EXPECT_EQ(engine::sceneToJson(*scene).find("\"far_field\": \"auto\""),
            engine::sceneToJson(*scene).rfind("\"far_field\": \"auto\""))
      << "only the third radar's is written";
  engine::SceneDescription viewed = *scene;
  engine::setUnsetFarField(viewed, engine::FarField::Auto);
  radars = engine::volumesOfKind(viewed, engine::VolumeKind::Radar);
  EXPECT_EQ(radars[0].farField, engine::FarField::Auto);
  EXPECT_EQ(radars[1].farField, engine::FarField::Off);
  EXPECT_EQ(radars[2].farField, engine::FarField::Auto);
  EXPECT_FALSE(engine::volumesOfKind(viewed, engine::VolumeKind::Grid)[0].farField.has_value()) << "grids have none";
  // Unset, the layer's options draw it marched (render).
  auto unset = engine::layerRenderOptions(engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0],
                                          volume::FieldInfo{"DBZH", "dBZ", ""}, 0.0, volume::ValueRange{0.0, 60.0});
  ASSERT_TRUE(unset) << unset.error();
  EXPECT_EQ(unset->farField, engine::FarField::Off);
}

}  // namespace
