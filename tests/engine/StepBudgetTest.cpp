// Time steps within a memory budget (docs/memory.md): steps dropped and read again draw as
// before, the background loader's steps are used, and a volume the GPU cannot hold is drawn at a
// lower resolution with a warning instead of failing.
#include "GLTestUtil.h"
#include "SyntheticGridVolume.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GridVolumeGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/volume/SyntheticGrid.h>

#include <gtest/gtest.h>

#include <cstdlib>

namespace {
using namespace atmoglobe;

struct Series {
  engine::SceneDescription scene;
  std::unique_ptr<engine::SceneRendererGL> renderer;
  engine::SceneTimeAxis axis;
};

Series loadSeries(const std::string& name, int steps) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  volume::SyntheticGridOptions go;
  go.nx = go.ny = 40;
  go.levels = 12;
  go.times = steps;
  go.spacingKm = 6.0;
  EXPECT_TRUE(volume::writeSyntheticGrid(dir + "/" + name, go));
  auto scene = engine::parseSceneJson(std::string(R"({"camera": {"lat_deg": 34.3, "lon_deg": -97.9, "height_m": 150000,
      "heading_deg": 30, "pitch_deg": -45, "roll_deg": 0}, "fov_deg": 50, "size": [64, 36],
      "grids": [{"path": "@data/)") + name +
                                          R"(", "step_m": 800}]})",
                                      "s.json", dir, dir);
  EXPECT_TRUE(scene) << scene.error();
  auto loader = engine::openImagery({}, {});
  auto renderer = engine::SceneRendererGL::create(*loader);
  EXPECT_TRUE(renderer);
  EXPECT_TRUE((*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0]));
  auto axis = engine::sceneTimeAxis(**renderer);
  EXPECT_TRUE(axis);
  return {*scene, std::move(*renderer), std::move(*axis)};
}

globe::ImageRGBA8 draw(Series& s) {
  const engine::Camera camera(s.scene.camera, s.scene.fovYDeg, s.scene.widthPx, s.scene.heightPx);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  auto image = s.renderer->renderToImage(camera, {}, **fb);
  EXPECT_TRUE(image);
  return *image;
}

TEST(StepBudget, DroppedStepsAreReadAgainAndDrawTheSame) {
  Series s = loadSeries("budget_series.nc", 6);
  s.renderer->setMemoryBudget(1);  // nothing but the step shown stays
  std::vector<globe::ImageRGBA8> first;
  for (std::size_t step = 0; step < 6; ++step) {
    ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, step));
    first.push_back(draw(s));
    EXPECT_EQ(s.renderer->stepCache().stats().entries, 1u) << "only the step shown is held";
  }
  const auto before = s.renderer->stepCache().stats();
  EXPECT_GE(before.drops, 5u);
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 2));  // dropped: read again
  EXPECT_EQ(draw(s).pixels, first[2].pixels);
  EXPECT_NE(first[2].pixels, first[5].pixels) << "the storm moves between steps";

  // With room for the series, a step shown before is found, not read again.
  s.renderer->setMemoryBudget(std::uint64_t{1} << 30);
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 3));
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 2));
  const auto hitsBefore = s.renderer->stepCache().stats().hits;
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 3));
  EXPECT_EQ(s.renderer->stepCache().stats().hits, hitsBefore + 1);
  EXPECT_EQ(draw(s).pixels, first[3].pixels);
}

TEST(StepBudget, PrefetchedStepsAreUsedAndDrawTheSame) {
  Series s = loadSeries("prefetch_series.nc", 5);
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 0));
  engine::ScenePrefetcher prefetch(*s.renderer, s.axis, 2);
  prefetch.request(0);
  prefetch.waitIdle();
  EXPECT_EQ(prefetch.stepsPrepared(), 2u);  // steps 1 and 2
  EXPECT_TRUE(s.renderer->stepCache().contains(engine::stepKey(0, 1, false)));
  EXPECT_TRUE(s.renderer->stepCache().contains(engine::stepKey(0, 2, false)));
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 1));
  // The prepared step became the GPU volume (its CPU entry gone: the volume holds the twin).
  EXPECT_FALSE(s.renderer->stepCache().contains(engine::stepKey(0, 1, false)));
  EXPECT_TRUE(s.renderer->stepCache().contains(engine::stepKey(0, 1, true)));
  const globe::ImageRGBA8 prefetched = draw(s);
  // The same step with nothing prepared ahead.
  Series fresh = loadSeries("prefetch_series_2.nc", 5);
  ASSERT_TRUE(engine::showSceneTime(*fresh.renderer, fresh.axis, 1));
  EXPECT_EQ(draw(fresh).pixels, prefetched.pixels);
}

// Sets $ATMOGLOBE_MAX_TEXTURE_BYTES for one scope.
struct TextureLimit {
  explicit TextureLimit(std::size_t bytes) { setenv("ATMOGLOBE_MAX_TEXTURE_BYTES", std::to_string(bytes).c_str(), 1); }
  ~TextureLimit() { unsetenv("ATMOGLOBE_MAX_TEXTURE_BYTES"); }
};

TEST(GpuMemory, GridOverTheLimitIsDrawnAtLowerResolutionWithAWarning) {
  Series s = loadSeries("gpu_limit_series.nc", 2);
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 1));
  const globe::ImageRGBA8 full = draw(s);
  const volume::GridVolume grid = testutil::gridVolumeOf(&s.renderer->layer(0));
  ASSERT_EQ(grid.nx, 40u);
  const std::size_t fullBytes = (grid.nx * grid.ny * grid.nz) * 8;  // RG32F
  s.renderer->setMemoryBudget(1);  // step 1 is dropped once step 0 shows: uploaded again below
  ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 0));
  {
    // Below the full texture, above a quarter of it: one halving fits.
    TextureLimit limit(fullBytes / 2);
    testing::internal::CaptureStderr();
    ASSERT_TRUE(engine::showSceneTime(*s.renderer, s.axis, 1));
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("warning:"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("over the GPU memory limit"), std::string::npos) << warnings;
    // Columns 0, 2, ..., 38 and the last, 39, so the region stays the same.
    EXPECT_NE(warnings.find("drawn at lower resolution, 21 x 21 x 12"), std::string::npos) << warnings;
  }
  const volume::GridVolume& reduced = testutil::gridVolumeOf(&s.renderer->layer(0));
  EXPECT_EQ(reduced.nx, 21u);
  EXPECT_EQ(reduced.ny, 21u);
  const globe::ImageRGBA8 low = draw(s);
  // The frame still renders the storm: the same pixels are coloured by the volume as at full
  // resolution, give or take its edges (half the columns: edges move by up to a 12 km cell).
  int coloured = 0, colouredFull = 0;
  const globe::ImageRGBA8 background = [&] {
    engine::SceneDescription none = s.scene;
    auto loader = engine::openImagery({}, {});
    auto r = engine::SceneRendererGL::create(*loader);
    const engine::Camera camera(none.camera, none.fovYDeg, none.widthPx, none.heightPx);
    auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    return *(*r)->renderToImage(camera, {}, **fb);
  }();
  for (std::size_t i = 0; i < low.pixels.size(); i += 4) {
    const bool differs = low.pixels[i] != background.pixels[i] || low.pixels[i + 1] != background.pixels[i + 1];
    const bool differsFull = full.pixels[i] != background.pixels[i] || full.pixels[i + 1] != background.pixels[i + 1];
    coloured += differs ? 1 : 0;
    colouredFull += differsFull ? 1 : 0;
  }
  // The storm covers ~40 of the 2304 pixels at this camera (measured). At half the columns its
  // edges move by up to a cell (12 km here), so the count may change, but not by a factor of 2.
  EXPECT_GT(colouredFull, 20);
  EXPECT_GT(coloured, colouredFull / 2) << "the lower-resolution frame must still show the storm";
  EXPECT_LT(coloured, colouredFull * 2) << "nor more than the storm";

  // Below what any halving reaches: a clear error, not a crash.
  TextureLimit tiny(16);
  auto none = engine::GridVolumeGL::create(grid);
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().find("even at 1/"), std::string::npos) << none.error();
}

TEST(GpuMemory, RadarOverTheLimitIsDrawnWithFewerGates) {
  testutil::glContext();
  testutil::SyntheticPolarGeometry geometry;
  const volume::PolarVolume polar = testutil::polarOf(testutil::syntheticRadarVolume(
      geometry, [](double r, double, double) { return static_cast<float>(r / 5000.0); }));
  const std::size_t fullBytes =
      static_cast<std::size_t>(polar.maxGates + 1) * (polar.maxRays + 1) * polar.sweeps.size() * 4;
  TextureLimit limit(fullBytes * 6 / 10);
  testing::internal::CaptureStderr();
  auto gl = engine::RadarVolumeGL::create(polar);
  const std::string warnings = testing::internal::GetCapturedStderr();
  ASSERT_TRUE(gl) << gl.error();
  EXPECT_EQ((*gl)->polar().maxGates, polar.maxGates / 2);
  EXPECT_EQ((*gl)->polar().sweeps[0].gateSpacingMeters, 2 * polar.sweeps[0].gateSpacingMeters);
  EXPECT_NE(warnings.find("drawn at lower resolution, 200 gates"), std::string::npos) << warnings;
}

}  // namespace

namespace {
using namespace atmoglobe;

TEST(StepBudget, SceneKeyIsParsedAndChecked) {
  auto scene = engine::parseSceneJson(R"({"memory_budget_mb": 64})", "s.json", "", "");
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_EQ(scene->memoryBudgetMb, 64.0);
  EXPECT_EQ(engine::parseSceneJson("{}", "s.json", "", "")->memoryBudgetMb, 0.0);  // 0: the default
  for (const char* bad : {R"({"memory_budget_mb": -1})", R"({"memory_budget_mb": "lots"})"}) {
    auto wrong = engine::parseSceneJson(bad, "s.json", "", "");
    ASSERT_FALSE(wrong) << bad;
    EXPECT_NE(wrong.error().find("memory_budget_mb"), std::string::npos) << wrong.error();
  }
}

}  // namespace
