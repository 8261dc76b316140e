// The control panel's logic: which edits read the data again (LayerEdit.h), the draw order,
// byte counts, the scale bar shared with the PNG legend; an edited transfer function drawn by the
// GPU marcher against the CPU reference; and SceneRendererGL's live edits (options, crop reload,
// vertical exaggeration, order, visibility, memory).
#include "GLTestUtil.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/LayerEdit.h>
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/ReferenceRenderer.h>
#include <atmoglobe/volume/SyntheticRadar.h>
#include <atmoglobe/volume/TransferFunction.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

namespace {

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;
using engine::LayerChange;

TEST(LayerEdit, OptionsOrReload) {
  engine::VolumeLayerDescription a;
  a.path = "x.nc";
  engine::VolumeLayerDescription b = a;
  EXPECT_EQ(engine::layerChange(a, b), LayerChange::None);
  b.mode = volume::VolumeRenderMode::Mip;
  EXPECT_EQ(engine::layerChange(a, b), LayerChange::Options);
  b = a;
  b.settings.opacityPoints = {{0.0, 0.0}, {40.0, 0.5}};
  EXPECT_EQ(engine::layerChange(a, b), LayerChange::Options);
  b = a;
  b.beam = engine::BeamApproximation::StraightLine;
  EXPECT_EQ(engine::layerChange(a, b), LayerChange::Options);
  b = a;
  b.field = "VEL";
  EXPECT_EQ(engine::layerChange(a, b), LayerChange::Reload);
  b = a;
  b.settings.crop.topMeters = 8000.0;
  EXPECT_EQ(engine::layerChange(a, b), LayerChange::Reload);

  engine::VolumeLayerDescription g;  // no iso value ("the kind's default") equals itself
  g.kind = engine::VolumeKind::Grid;
  EXPECT_EQ(engine::layerChange(g, g), LayerChange::None);
  engine::VolumeLayerDescription h = g;
  h.isoValue = 30.0;
  EXPECT_EQ(engine::layerChange(g, h), LayerChange::Options);
  h = g;
  h.field = "qr";
  EXPECT_EQ(engine::layerChange(g, h), LayerChange::Reload);
  h = g;
  h.time = "3";
  EXPECT_EQ(engine::layerChange(g, h), LayerChange::Reload);
  h = g;  // another member or a statistic over the members: read again
  h.member = 2;
  EXPECT_EQ(engine::layerChange(g, h), LayerChange::Reload);
  h = g;
  h.ensemble = *volume::parseEnsembleStatistic("spread");
  EXPECT_EQ(engine::layerChange(g, h), LayerChange::Reload);
  engine::VolumeLayerDescription k = h;
  k.ensemble = *volume::parseEnsembleStatistic("prob:>=5");
  EXPECT_EQ(engine::layerChange(h, k), LayerChange::Reload);
  EXPECT_EQ(engine::layerChange(k, k), LayerChange::None);
}

// The one validation: the same limits for both kinds, each kind's own keys refused on the other.
TEST(LayerEdit, OneValidationForBothKinds) {
  for (engine::VolumeKind kind : {engine::VolumeKind::Radar, engine::VolumeKind::Grid}) {
    engine::VolumeLayerDescription d;
    d.kind = kind;
    d.path = "x.nc";
    EXPECT_TRUE(engine::validateVolumeLayer(d, "here"));
    d.stepMeters = 5e5;  // a grid seen from space: allowed for both
    EXPECT_TRUE(engine::validateVolumeLayer(d, "here"));
    d.stepMeters = 2e6;
    EXPECT_EQ(engine::validateVolumeLayer(d, "here").error(), "here: step must be in 1..1000000 m");
    d.stepMeters = 250.0;
    d.isoValue = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(engine::validateVolumeLayer(d, "here"));
  }
  engine::VolumeLayerDescription radar;
  radar.path = "x.nc";
  radar.time = "3";
  EXPECT_FALSE(engine::validateVolumeLayer(radar, "here"));
  engine::VolumeLayerDescription grid;
  grid.kind = engine::VolumeKind::Grid;
  grid.path = "g.nc";
  grid.label = "KTLX";
  EXPECT_FALSE(engine::validateVolumeLayer(grid, "here"));
  EXPECT_EQ(engine::parseName<engine::BeamApproximation>("4/3"), engine::BeamApproximation::EffectiveEarthLocalSphere);
  EXPECT_FALSE(engine::parseName<volume::VolumeRenderMode>("volume"));
  EXPECT_EQ(engine::quotedNames<volume::VolumeRenderMode>(), "\"dvr\", \"mip\", \"iso\"");
}

TEST(LayerEdit, OrderBytesAndTables) {
  const std::vector<std::size_t> order{0, 1, 2, 3};
  EXPECT_EQ(engine::moveInOrder(order, 2, -1), (std::vector<std::size_t>{0, 2, 1, 3}));
  EXPECT_EQ(engine::moveInOrder(order, 0, +1), (std::vector<std::size_t>{1, 0, 2, 3}));
  EXPECT_EQ(engine::moveInOrder(order, 3, +1), order);  // already last
  EXPECT_EQ(engine::moveInOrder(order, 0, -5), order);
  EXPECT_EQ(engine::moveInOrder(order, 9, 1), order);
  EXPECT_EQ(engine::formatBytes(512), "512 B");
  EXPECT_EQ(engine::formatBytes(1536), "1.5 KiB");
  EXPECT_EQ(engine::formatBytes(4u << 20), "4.0 MiB");
  EXPECT_EQ(engine::formatBytes(std::uint64_t{5} << 29), "2.50 GiB");
  // Every table the panel offers is one transferForField takes.
  for (const std::string& name : engine::colorTableChoices()) {
    auto tf = volume::transferForField(name, volume::FieldInfo{"DBZH", "dBZ", ""}, 27.0, {-10.0, 60.0});
    EXPECT_TRUE(tf) << name << ": " << tf.error();
  }
}

TEST(LayerEdit, ScaleBarIsARoundLengthOfAtMostAFifth) {
  // 1280 px at 150 m/px: a fifth is 38.4 km -> 20 km, 133 px.
  const engine::ScaleBar bar = engine::scaleBarFor(150.0, 1280);
  EXPECT_DOUBLE_EQ(bar.meters, 20000.0);
  EXPECT_EQ(bar.lengthPx, 133);
  EXPECT_EQ(bar.label, "20 km");
  EXPECT_EQ(engine::scaleBarFor(1.0, 1000).label, "200 m");
  EXPECT_EQ(engine::scaleBarFor(8.0, 1000).label, "1.0 km");
  EXPECT_DOUBLE_EQ(engine::scaleBarFor(0.0, 1000).meters, 0.0);
  EXPECT_DOUBLE_EQ(engine::scaleBarFor(std::nan(""), 1000).meters, 0.0);
}

float storm(double r, double az, double el) {
  const double v = 62.0 * std::exp(-std::pow((r - 55e3) / 18e3, 2) - std::pow((az - 20.0) / 18.0, 2) -
                                   std::pow((el - 3.0) / 4.0, 2));
  return v < 5.0 ? volume::kNoEcho : static_cast<float>(v);
}

// 120 km south of the radar, 60 km up, looking north and down at the storm (RadarMarchTest's view).
const CameraPose kObliquePose{32.6, -101.814, 6e4, 10.0, -25.0, 0.0};

TEST(TransferEdit, EditedControlPointsRenderOnTheGpuAsOnTheReference) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const volume::PolarVolume pv =
      testutil::polarOf(testutil::syntheticRadarVolume(testutil::SyntheticPolarGeometry{}, storm));
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  const Camera camera(kObliquePose, 40.0, 80, 60);
  // A curve no ramp gives: weak echoes (5..15 dBZ) faint, a hole at 30 dBZ, the core opaque,
  // and the first point above zero (everything below it visible too).
  const std::vector<glm::dvec2> points{{5.0, 0.05}, {15.0, 0.3}, {30.0, 0.0}, {45.0, 0.9}, {62.0, 1.0}};
  for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip}) {
    for (bool preintegrated : {false, true}) {
      if (preintegrated && mode != volume::VolumeRenderMode::Dvr) continue;
      engine::VolumeRenderOptions options;
      options.render.mode = mode;
      options.render.stepMeters = 500.0;
      options.render.transfer = volume::withOpacityPoints(volume::defaultReflectivityTransfer(), points);
      options.classification = preintegrated ? engine::Classification::Preintegrated : engine::Classification::Point;
      const volume::VolumeImage gpu = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), options}});
      const volume::VolumeImage ref =
          volume::renderReference(pv, options.render, engine::referenceCameraFor(camera), false, 2);
      const volume::ImageError e = volume::compareImages(gpu, ref);
      // The edit must change the picture, or the comparison below says nothing about it.
      engine::VolumeRenderOptions ramp = options;
      ramp.render.transfer = volume::defaultReflectivityTransfer();
      const volume::ImageError changed =
          volume::compareImages(testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), ramp}}), gpu);
      std::cout << "mode " << static_cast<int>(mode) << (preintegrated ? " preintegrated" : "")
                << ": edited curve GPU vs reference mean " << e.meanAbs << " PSNR " << e.psnrDb
                << " dB; edited vs default ramp mean " << changed.meanAbs << "\n";
      // DVR: the whole storm's look changes (measured 2.7); MIP shows the colour of each ray's
      // maximum with that value's opacity, so only rays whose maximum sits in the edited
      // bands change (measured 0.76).
      EXPECT_GT(changed.meanAbs, mode == volume::VolumeRenderMode::Dvr ? 2.0 : 0.3)
          << "the edited curve must differ visibly from the default ramp";
      if (preintegrated) continue;  // pre-integration approximates colour: its error is measured elsewhere
      // RadarMarchTest's tolerances (GpuMatchesTheReferenceInEveryMode): a mean of 1 step of 255
      // and 30 dB PSNR, for the same reasons (float positions, half-float values, a table of
      // 4096 entries that now tabulates the control points' curve).
      EXPECT_LT(e.meanAbs, 1.0);
      EXPECT_GT(e.psnrDb, 30.0);
    }
  }
}

class SceneEdits : public ::testing::Test {
 protected:
  void SetUp() override {
    testutil::glContext();
    const std::string dir = testutil::testOutputDir();
    path_ = dir + "/panel_radar.nc";
    volume::SyntheticRadarOptions ro;
    ro.elevationsDeg = {0.5, 1.5, 2.5, 3.5, 5.0, 7.0, 10.0};
    ro.maxRangeMeters = 120e3;
    ASSERT_TRUE(volume::writeSyntheticCfRadial(path_, ro));
    auto loader = engine::openImagery({}, {});
    ASSERT_TRUE(loader);
    auto r = engine::SceneRendererGL::create(*loader);
    ASSERT_TRUE(r) << r.error();
    renderer_ = std::move(*r);
    engine::VolumeLayerDescription d;
    d.path = path_;
    d.stepMeters = 500.0;
    ASSERT_TRUE(renderer_->addVolume(d));
  }
  std::string path_;
  std::unique_ptr<engine::SceneRendererGL> renderer_;
};

TEST_F(SceneEdits, OptionsApplyWithoutReadingAgainAndCropReads) {
  const engine::RadarSourceGL& layer = testutil::radarOf(&renderer_->layer(0));
  const engine::VolumeGL* before = &layer.volume();
  engine::VolumeLayerDescription d = layer.description();
  d.mode = volume::VolumeRenderMode::Mip;
  d.colors = "cividis";
  d.beam = engine::BeamApproximation::StraightLine;
  d.settings.opacityPoints = {{10.0, 0.0}, {50.0, 0.7}};
  ASSERT_TRUE(renderer_->setVolumeDescription(0, d));
  EXPECT_EQ(&layer.volume(), before) << "render options must not re-upload the volume";
  EXPECT_EQ(layer.options().render.mode, volume::VolumeRenderMode::Mip);
  EXPECT_EQ(layer.options().render.transfer.opacityPoints.size(), 2u);
  EXPECT_EQ(layer.radarVolume().beamApproximation(), engine::BeamApproximation::StraightLine);
  EXPECT_EQ(layer.description().colors, "cividis");
  // A bad edit is refused and changes nothing.
  engine::VolumeLayerDescription bad = d;
  bad.stepMeters = -1.0;
  EXPECT_FALSE(renderer_->setVolumeDescription(0, bad));
  EXPECT_DOUBLE_EQ(layer.options().render.stepMeters, 500.0);
  // A crop box: the volume is read again, cut to the box (fewer measured values).
  const std::uint64_t fullCpu = renderer_->layerMemory()[0].cpuBytes;
  const float fullMax = layer.radarVolume().polar().maxValue;
  d.settings.crop.southDeg = 35.2;  // the storm's core is ~40 km south of the site (35.33 N)
  ASSERT_TRUE(renderer_->setVolumeDescription(0, d));
  EXPECT_NE(&layer.volume(), before);
  EXPECT_LT(layer.radarVolume().polar().maxValue, fullMax) << "the crop must cut the storm's core away";
  EXPECT_EQ(layer.options().render.mode, volume::VolumeRenderMode::Mip) << "the options survive a reload";
  EXPECT_EQ(renderer_->layerMemory()[0].cpuBytes, fullCpu) << "a crop marks gates, it keeps the layout";
}

TEST_F(SceneEdits, ExaggerationOrderVisibilityAndMemory) {
  const std::vector<engine::LayerMemory> memory = renderer_->layerMemory();
  ASSERT_EQ(memory.size(), 1u);
  const engine::RadarSourceGL& layer = testutil::radarOf(&renderer_->layer(0));
  EXPECT_EQ(memory[0].cpuBytes, layer.radarVolume().polar().byteSize());
  EXPECT_EQ(memory[0].gpuBytes, layer.volume().gpuBytes());
  EXPECT_GT(memory[0].gpuBytes, 0u);
  ASSERT_TRUE(renderer_->changeVerticalExaggeration(3.0));
  EXPECT_DOUBLE_EQ(renderer_->verticalExaggeration(), 3.0);
  EXPECT_DOUBLE_EQ(testutil::radarOf(&renderer_->layer(0)).radarVolume().exaggeration(), 3.0);
  EXPECT_FALSE(renderer_->changeVerticalExaggeration(1000.0));
  EXPECT_DOUBLE_EQ(renderer_->verticalExaggeration(), 3.0);
  EXPECT_FALSE(renderer_->setVolumeOrder({0, 0}));
  EXPECT_FALSE(renderer_->setVolumeOrder({1}));
  EXPECT_TRUE(renderer_->setVolumeOrder({0}));
  EXPECT_TRUE(renderer_->addVolume(renderer_->layer(0).description()));  // as the viewer adds a radar coming into view
  ASSERT_TRUE(renderer_->setVolumeOrder({1, 0}));
  ASSERT_TRUE(renderer_->addVolume(renderer_->layer(0).description()));
  EXPECT_EQ(renderer_->volumeOrder(), (std::vector<std::size_t>{1, 0, 2})) << "a layer added after an order goes last";
  // Switched off: the frame is the frame without the volume.
  const Camera camera(CameraPose{34.6, -97.8, 3e5, 0.0, -90.0, 0.0}, 50.0, 96, 64);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto shown = renderer_->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(shown);
  renderer_->layer(0).visible = false;
  renderer_->layer(1).visible = false;
  renderer_->layer(2).visible = false;
  auto hidden = renderer_->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(hidden);
  auto loader = engine::openImagery({}, {});
  auto empty = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(empty);
  auto none = (*empty)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(none);
  EXPECT_EQ(hidden->pixels, none->pixels);
  EXPECT_NE(shown->pixels, none->pixels) << "the storm must show from this view";
  EXPECT_TRUE(renderer_->legendFor(camera).keys.empty()) << "no colour key for a layer switched off";
}

// The edit as the panel makes it (setVolumeDescription with control points) in a whole frame:
// GPU frame against the reference frame (drawReference), as GridMarchTest's scene comparison.
TEST_F(SceneEdits, EditedCurveFrameMatchesTheReferenceFrame) {
  const Camera camera(CameraPose{34.3, -97.8, 9e4, 0.0, -35.0, 0.0}, 50.0, 160, 100);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto before = renderer_->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(before) << before.error();
  engine::VolumeLayerDescription d = renderer_->layer(0).description();
  d.settings.opacityPoints = {{5.0, 0.02}, {25.0, 0.02}, {35.0, 0.8}, {45.0, 0.1}, {65.0, 1.0}};
  ASSERT_TRUE(renderer_->setVolumeDescription(0, d));
  auto gpu = renderer_->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(gpu) << gpu.error();
  renderer_->setReferenceVolumes(2);
  auto ref = renderer_->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(ref) << ref.error();
  const std::string dir = testutil::testOutputDir();
  EXPECT_TRUE(globe::writePng(dir + "/panel_curve_default.png", *before));
  EXPECT_TRUE(globe::writePng(dir + "/panel_curve_edited_gpu.png", *gpu));
  EXPECT_TRUE(globe::writePng(dir + "/panel_curve_edited_reference.png", *ref));
  auto meanAbs = [](const globe::ImageRGBA8& a, const globe::ImageRGBA8& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
      if (i % 4 != 3) sum += std::abs(int(a.pixels[i]) - int(b.pixels[i]));
    return sum / (0.75 * static_cast<double>(a.pixels.size()));
  };
  const double edit = meanAbs(*before, *gpu), error = meanAbs(*gpu, *ref);
  std::cout << "scene frame: edited vs default mean " << edit << ", edited GPU vs reference mean " << error
            << " (8-bit)\n";
  EXPECT_GT(edit, 1.0) << "the edit must show in the frame";
  // GridMarchTest's scene tolerance (radar + grid frame against the reference): below one 8-bit step.
  EXPECT_LT(error, 1.0);
}

// Switching the field of a many-field file reads that field (the panel's field list), and the
// colours follow its kind.
TEST(SceneFieldSwitch, RealNexradFieldSwitchReadsThatField) {
  const std::string klbb = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
  SKIP_WITHOUT_TEST_DATA(klbb);
  testutil::glContext();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto r = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(r) << r.error();
  engine::VolumeLayerDescription d;
  d.path = klbb;
  ASSERT_TRUE((*r)->addVolume(d));
  const engine::RadarSourceGL& layer = testutil::radarOf(&(*r)->layer(0));
  EXPECT_EQ(layer.radarVolume().polar().fieldName, "REF");
  const std::vector<std::string> fields = layer.fieldChoices();
  ASSERT_GT(fields.size(), 1u);
  ASSERT_NE(std::find(fields.begin(), fields.end(), "VEL"), fields.end());
  const volume::ColorTable refColors = layer.options().render.transfer.colors;
  d.field = "VEL";
  ASSERT_TRUE((*r)->setVolumeDescription(0, d));
  EXPECT_EQ(layer.radarVolume().polar().fieldName, "VEL");
  EXPECT_EQ(layer.loadedField().name, "VEL");
  EXPECT_LT(layer.radarVolume().polar().minValue, 0.0f) << "velocities towards the radar are negative";
  EXPECT_NE(layer.options().render.transfer.colors.stops(), refColors.stops()) << "velocity colours, not NWS";
  d.field = "NOPE";
  EXPECT_FALSE((*r)->setVolumeDescription(0, d));
  EXPECT_EQ(layer.radarVolume().polar().fieldName, "VEL") << "a failed switch leaves the layer as it was";
}

}  // namespace
