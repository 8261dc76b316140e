// A radar network as one GPU volume (engine/RadarNetworkGL.h, shaders/sample_network.glsl) against
// the CPU reference of the same network (volume::RadarNetworkSampler: the same coverage index and
// overlap rule in double), in every mode and rule; and a network of one radar against that radar
// drawn alone.
#include "GLTestUtil.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/RadarNetworkGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>

namespace {

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;

constexpr double kStormLatDeg = 35.4, kStormLonDeg = -97.3;

// A radar at (lat, lon) seeing one storm (a 3-D Gaussian around (kStormLatDeg, kStormLonDeg,
// 3 km), 55 dBZ at its centre, 30 km wide) with a calibration bias of `biasDb`
// (testutil::radarSeeingField: 8 sweeps 0.5..7.5 deg, 180 rays, 240 gates of 500 m, to 122 km).
std::shared_ptr<const volume::PolarVolume> radarSeeingTheStorm(double latDeg, double lonDeg, double biasDb) {
  return testutil::radarSeeingField(latDeg, lonDeg, [biasDb](double lat, double lon, double heightMeters) {
    const double d = globe::geodesicInverse(kStormLatDeg, kStormLonDeg, lat, lon).distanceMeters;
    const double x = 55.0 * std::exp(-std::pow(d / 30e3, 2) - std::pow((heightMeters - 3000.0) / 3000.0, 2));
    return x < 5.0 ? volume::kNoEcho : static_cast<float>(x + biasDb);
  });
}

// Three radars around the storm (60-90 km from it, overlapping) with different biases.
std::vector<std::shared_ptr<const volume::PolarVolume>> threeRadarsAroundTheStorm() {
  return {radarSeeingTheStorm(35.33, -97.95, 0.0), radarSeeingTheStorm(35.95, -96.9, 6.0),
          radarSeeingTheStorm(34.8, -96.9, -4.0)};
}

// Looking north-east at the storm from 90 km south-west, 25 km up, 96 x 54 pixels.
Camera cameraOnTheStorm() {
  const globe::GeodesicPoint eye = globe::geodesicDirect(kStormLatDeg, kStormLonDeg, 225.0, 90e3);
  return Camera(CameraPose{eye.latDeg, eye.lonDeg, 2.5e4, 45.0, -12.0, 0.0}, 50.0, 96, 54);
}

TEST(RadarNetworkGL, GpuMatchesTheReferenceForEveryRuleAndMode) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  // The three radars around the storm and a fourth 700 km away that no coverage cell over the
  // storm lists.
  std::vector<std::shared_ptr<const volume::PolarVolume>> radars = threeRadarsAroundTheStorm();
  radars.push_back(radarSeeingTheStorm(35.0, -89.5, 0.0));
  const Camera camera = cameraOnTheStorm();
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  options.render.isoValue = 25.0;
  options.skipEmptySpace = false;
  for (auto rule : {volume::OverlapRule::WeightedMean, volume::OverlapRule::LowestBeam, volume::OverlapRule::Maximum}) {
    auto gl = engine::RadarNetworkGL::create(radars, rule, volume::FieldKind::Reflectivity);
    ASSERT_TRUE(gl) << gl.error();
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
      options.render.mode = mode;
      options.skipEmptySpace = false;
      const volume::VolumeImage ref =
          volume::renderReference({{&(*gl)->referenceSampler(), options.render}}, rc, false, 2);
      const volume::VolumeImage gpu = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), options}});
      const volume::ImageError e = volume::compareImages(gpu, ref);
      int drawn = 0;
      for (int y = 0; y < camera.heightPx(); ++y)
        for (int x = 0; x < camera.widthPx(); ++x) drawn += ref.at(x, y).a > 0.05;
      std::cout << "network rule " << volume::toString(rule) << ", mode " << static_cast<int>(mode)
                << ": GPU vs reference mean " << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb << " dB, "
                << drawn << " pixels drawn\n";
      ASSERT_GT(drawn, 200) << "the storm must fill part of the view";
      // As for one radar (RadarMarch.GpuMatchesTheReferenceInEveryMode): mean below one 8-bit
      // step, 30 dB.
      EXPECT_LT(e.meanAbs, 1.0);
      EXPECT_GT(e.psnrDb, 30.0);
      // Skipping (the network's empty-space grid, built from each radar's) does not change the picture.
      options.skipEmptySpace = true;
      const volume::VolumeImage skipped = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), options}});
      EXPECT_LE(volume::compareImages(skipped, gpu).maxAbs, 1.0) << "skipping changed the picture";
    }
  }
}

// A variant of the storm's view (a rule, an exaggeration): the GPU against the reference of the
// same settings, and that reference against the one of a baseline (so that a test sees the
// variant change the picture).
// The three radars around the storm, a renderer and the reflectivity transfer, for each rule.
class RadarNetworkGLVariants : public ::testing::Test {
 protected:
  struct Check {
    volume::ImageError gpu, changed;
  };
  void SetUp() override {
    testutil::glContext();
    auto r = engine::VolumeRendererGL::create();
    ASSERT_TRUE(r) << r.error();
    renderer_ = std::move(*r);
    options_.render.transfer = volume::defaultReflectivityTransfer();
  }
  Check check(const engine::RadarNetworkGL& gl, const volume::VolumeSampler& baseline,
              const volume::VolumeRenderSettings& baselineSettings) const {
    const Camera camera = cameraOnTheStorm();
    const volume::RenderCamera rc = engine::referenceCameraFor(camera);
    const volume::VolumeImage base = volume::renderReference({{&baseline, baselineSettings}}, rc, false, 2);
    const volume::VolumeImage ref = volume::renderReference({{&gl.referenceSampler(), options_.render}}, rc, false, 2);
    const volume::VolumeImage gpu = testutil::renderVolumesGpu(*renderer_, camera, {{&gl, options_}});
    return {volume::compareImages(gpu, ref), volume::compareImages(ref, base)};
  }
  static constexpr volume::OverlapRule kRules[] = {volume::OverlapRule::WeightedMean, volume::OverlapRule::LowestBeam,
                                                   volume::OverlapRule::Maximum};
  std::unique_ptr<engine::VolumeRendererGL> renderer_;
  const std::vector<std::shared_ptr<const volume::PolarVolume>> radars_ = threeRadarsAroundTheStorm();
  engine::VolumeRenderOptions options_;
};

// The step rule (volume/StepRule.h) on a network: the cell crossing is the smallest of the
// radars' over the sample (RadarNetworkSampler::cellCrossingMeters, VOL_cellCrossing in
// sample_network.glsl), and the GPU takes the samples the reference takes, for every rule.
TEST_F(RadarNetworkGLVariants, TheStepRuleTakesTheReferencesSamples) {
  // 250 m: the cells here (gates of 500 m, 1 deg between sweeps: 1-2 km at 60-120 km) and the
  // pixels (1.5 km at 90 km) leave room for levels 1 and 2.
  options_.render.stepMeters = 250.0;
  volume::VolumeRenderSettings fixedStep = options_.render;
  fixedStep.samplesPerCell = 0.0;
  options_.render.samplesPerCell = 1.0;
  for (auto rule : kRules) {
    auto gl = engine::RadarNetworkGL::create(radars_, rule, volume::FieldKind::Reflectivity);
    ASSERT_TRUE(gl) << gl.error();
    const auto [e, moved] = check(**gl, (*gl)->referenceSampler(), fixedStep);
    std::cout << "network rule " << volume::toString(rule) << ", 1 sample per cell: GPU vs reference mean " << e.meanAbs
              << " max " << e.maxAbs << "; the rule's reference against the fixed step's: mean " << moved.meanAbs
              << " max " << moved.maxAbs << "\n";
    // The rule took other samples than the fixed step (else this test would not test it) ...
    EXPECT_GT(moved.maxAbs, 1.0);
    // ... and the GPU took the same ones: mean under half an 8-bit step (the network's target).
    EXPECT_LT(e.meanAbs, 0.5);
    EXPECT_GT(e.psnrDb, 30.0);
  }
}

// Vertical exaggeration (volume/VerticalExaggeration.h) under every combining rule: each radar
// maps the drawn point back on its local sphere (sample_network.glsl), the reference through the
// exact geodetic mapping (volume::ExaggeratedSampler around the network); the picture changes
// (the storm is three times as tall) and the GPU follows the reference.
TEST_F(RadarNetworkGLVariants, AnExaggeratedNetworkMatchesTheReference) {
  options_.render.stepMeters = 500.0;
  for (auto rule : kRules) {
    auto flat = engine::RadarNetworkGL::create(radars_, rule, volume::FieldKind::Reflectivity);
    auto tall = engine::RadarNetworkGL::create(radars_, rule, volume::FieldKind::Reflectivity, 3.0);
    ASSERT_TRUE(flat && tall) << (flat ? tall.error() : flat.error());
    EXPECT_EQ((*tall)->exaggeration(), 3.0);
    const auto [e, changed] = check(**tall, (*flat)->referenceSampler(), options_.render);
    std::cout << "network rule " << volume::toString(rule) << ", exaggerated 3x: GPU vs reference mean " << e.meanAbs
              << " max " << e.maxAbs << " PSNR " << e.psnrDb << " dB; against true scale: mean " << changed.meanAbs
              << "\n";
    EXPECT_GT(changed.meanAbs, 1.0);  // the storm is drawn three times as tall
    // Mean under half an 8-bit step (the network's target); the local sphere's height error,
    // times 1 - 1/3, is metres at these 60-120 km ranges.
    EXPECT_LT(e.meanAbs, 0.5);
    EXPECT_GT(e.psnrDb, 30.0);
  }
  EXPECT_FALSE(
      engine::RadarNetworkGL::create(radars_, volume::OverlapRule::WeightedMean, volume::FieldKind::Reflectivity, 0.0));
}

TEST(RadarNetworkGL, TheOrderOfTheRadarsChangesNoPixel) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const std::vector<std::shared_ptr<const volume::PolarVolume>> radars = threeRadarsAroundTheStorm();
  const std::vector<std::shared_ptr<const volume::PolarVolume>> reversed(radars.rbegin(), radars.rend());
  const Camera camera = cameraOnTheStorm();
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  for (auto rule : {volume::OverlapRule::WeightedMean, volume::OverlapRule::LowestBeam, volume::OverlapRule::Maximum}) {
    auto a = engine::RadarNetworkGL::create(radars, rule, volume::FieldKind::Reflectivity);
    auto b = engine::RadarNetworkGL::create(reversed, rule, volume::FieldKind::Reflectivity);
    ASSERT_TRUE(a && b);
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip}) {
      options.render.mode = mode;
      const volume::ImageError e =
          volume::compareImages(testutil::renderVolumesGpu(**renderer, camera, {{a->get(), options}}),
                                testutil::renderVolumesGpu(**renderer, camera, {{b->get(), options}}));
      std::cout << "radars reversed, rule " << volume::toString(rule) << ", mode " << static_cast<int>(mode) << ": max "
                << e.maxAbs << "\n";
      // The rules do not depend on the order (the mean's float sums may round apart; a tie of
      // the lowest beam, which would go to the first listed, needs two beams within a float's
      // rounding): at most 1 of 255.
      EXPECT_LE(e.maxAbs, 1.0) << volume::toString(rule);
    }
  }
}

// The overlapping Belgian pair (Wideumont and Helchteren, 128 km apart; real ODIM_H5 volumes of
// different days, drawn together for the rules' sake) through the GPU and the reference.
TEST(RadarNetworkGL, TheBelgianPairMatchesTheReferenceForEveryRule) {
  const std::string wid = atmoglobe_test::testDataPath("radar_odim/bewid.pvol.hdf");
  const std::string hel =
      atmoglobe_test::testDataPath("radar_odim/behel_loop/20200207130000.rad.behel.pvol.dbzh.scanz.hdf");
  SKIP_WITHOUT_TEST_DATA(wid, hel);
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  std::vector<std::shared_ptr<const volume::PolarVolume>> radars;
  for (const std::string& path : {wid, hel}) {
    volume::RadarLoadOptions load;
    load.buildRenderLayout = true;
    auto r = volume::loadRadar(path, load);
    ASSERT_TRUE(r) << r.error();
    radars.push_back(std::make_shared<const volume::PolarVolume>(std::move(*r->layout)));
  }
  // Above the middle of the pair, 400 km up, looking down.
  const Camera camera(CameraPose{50.5, 5.45, 4e5, 0.0, -90.0, 0.0}, 60.0, 96, 64);
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  options.render.mode = volume::VolumeRenderMode::Mip;
  for (auto rule : {volume::OverlapRule::WeightedMean, volume::OverlapRule::LowestBeam, volume::OverlapRule::Maximum}) {
    auto gl = engine::RadarNetworkGL::create(radars, rule, volume::FieldKind::Reflectivity);
    ASSERT_TRUE(gl) << gl.error();
    ASSERT_EQ((*gl)->network().coverage().maxPerCell(), 2u) << "the pair overlaps";
    const volume::VolumeImage ref =
        volume::renderReference({{&(*gl)->referenceSampler(), options.render}}, rc, false, 2);
    const volume::VolumeImage gpu = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), options}});
    const volume::ImageError e = volume::compareImages(gpu, ref);
    int drawn = 0;
    for (int y = 0; y < camera.heightPx(); ++y)
      for (int x = 0; x < camera.widthPx(); ++x) drawn += ref.at(x, y).a > 0.05;
    std::cout << "Belgian pair, rule " << volume::toString(rule) << ": GPU vs reference mean " << e.meanAbs << " max "
              << e.maxAbs << " PSNR " << e.psnrDb << " dB, " << drawn << " pixels drawn\n";
    ASSERT_GT(drawn, 300);
    EXPECT_LT(e.meanAbs, 0.5);  // the bound: half an 8-bit step on average
  }
}

TEST(RadarNetworkGL, ANetworkOfOneRadarIsThatRadar) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const auto radar = radarSeeingTheStorm(35.33, -97.95, 0.0);
  auto network =
      engine::RadarNetworkGL::create({radar}, volume::OverlapRule::WeightedMean, volume::FieldKind::Reflectivity);
  ASSERT_TRUE(network) << network.error();
  auto alone = engine::RadarVolumeGL::create(*radar);
  ASSERT_TRUE(alone) << alone.error();
  const globe::GeodesicPoint eye = globe::geodesicDirect(kStormLatDeg, kStormLonDeg, 225.0, 90e3);
  const Camera camera(CameraPose{eye.latDeg, eye.lonDeg, 2.5e4, 45.0, -12.0, 0.0}, 50.0, 96, 54);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip}) {
    options.render.mode = mode;
    const volume::VolumeImage a = testutil::renderVolumesGpu(**renderer, camera, {{network->get(), options}});
    const volume::VolumeImage b = testutil::renderVolumesGpu(**renderer, camera, {{alone->get(), options}});
    const volume::ImageError e = volume::compareImages(a, b);
    std::cout << "network of one vs the radar alone, mode " << static_cast<int>(mode) << ": mean " << e.meanAbs
              << " max " << e.maxAbs << "\n";
    // The same samples of the same half-float texels through the same beam model; the two
    // samplers' float arithmetic differs (positions relative to the network's origin, the mean
    // rule's weight), so a pixel may differ by rounding: at most 2 of 255.
    EXPECT_LE(e.maxAbs, 2.0);
    EXPECT_LT(e.meanAbs, 0.05);
  }
}

// The empty-space grid's texels as the GPU holds them (cells, then blocks).
std::vector<std::uint16_t> occupancyTexels(const engine::OccupancyGridGL& o) {
  const volume::OccupancyGrid& g = o.grid();
  std::vector<std::uint16_t> texels(static_cast<std::size_t>(g.cells.x) * g.cells.y * (g.cells.z + g.blocks.z));
  glGetTextureImage(o.texture(), 0, GL_RED, GL_HALF_FLOAT, static_cast<GLsizei>(texels.size() * 2), texels.data());
  return texels;
}

// The same radars with the second 3 dB stronger wherever it has echoes (another volume): the
// same empty-space runs, other maxima.
std::vector<std::shared_ptr<const volume::PolarVolume>> withTheSecondStronger(
    const std::vector<std::shared_ptr<const volume::PolarVolume>>& radars) {
  volume::PolarVolume stronger = *radars[1];
  for (float& v : stronger.values)
    if (volume::isMeasuredValue(v)) v += 3.0f;
  stronger.maxValue += 3.0f;
  std::vector<std::shared_ptr<const volume::PolarVolume>> next = radars;
  next[1] = std::make_shared<const volume::PolarVolume>(std::move(stronger));
  return next;
}

// A step that changes one radar's values but not where it has echoes keeps the layout of the
// empty-space grid, so only the cells of that radar's boxes are computed again and uploaded
// (taking the step before's grid over, or copying it): cells, blocks and texels equal those of the
// network built whole, and so do the pictures; a copied step before draws on as before.
TEST(RadarNetworkGL, AStepRebuildsOnlyTheChangedRadarsCellsOfTheEmptySpaceGrid) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const std::vector<std::shared_ptr<const volume::PolarVolume>> radars = threeRadarsAroundTheStorm();
  const std::vector<std::shared_ptr<const volume::PolarVolume>> next = withTheSecondStronger(radars);
  const Camera camera = cameraOnTheStorm();
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  options.render.mode = volume::VolumeRenderMode::Mip;  // every echo shows, through the grid's skipping
  auto whole = engine::RadarNetworkGL::create(next, volume::OverlapRule::Maximum, volume::FieldKind::Reflectivity);
  ASSERT_TRUE(whole) << whole.error();
  EXPECT_EQ((*whole)->occupancyCellsBuilt(), (*whole)->occupancyCells());
  const volume::VolumeImage wholeImage = testutil::renderVolumesGpu(**renderer, camera, {{whole->get(), options}});
  for (auto use : {engine::RadarNetworkGL::PreviousTexture::TakeOver, engine::RadarNetworkGL::PreviousTexture::Copy}) {
    SCOPED_TRACE(use == engine::RadarNetworkGL::PreviousTexture::Copy ? "copied" : "taken over");
    auto first = engine::RadarNetworkGL::create(radars, volume::OverlapRule::Maximum, volume::FieldKind::Reflectivity);
    ASSERT_TRUE(first) << first.error();
    const volume::VolumeImage firstImage = testutil::renderVolumesGpu(**renderer, camera, {{first->get(), options}});
    const std::vector<float> firstCells = (*first)->occupancy().grid().maxValues;
    ASSERT_NE(firstCells, (*whole)->occupancy().grid().maxValues) << "the stronger echoes raise cells";
    auto step = engine::RadarNetworkGL::create(next, volume::OverlapRule::Maximum, volume::FieldKind::Reflectivity, 1.0,
                                               {}, first->get(), use);
    ASSERT_TRUE(step) << step.error();
    const engine::RadarNetworkGL& s = **step;
    std::cout << "empty-space grid: " << s.occupancyCellsBuilt() << " of " << s.occupancyCells()
              << " cells built again\n";
    EXPECT_GT(s.occupancyCellsBuilt(), 0u);
    // The three radars see one storm, so the changed one's boxes reach most of the grid (87 %):
    // a part of it all the same (a continental network's step redoes a small part).
    EXPECT_LT(s.occupancyCellsBuilt(), s.occupancyCells()) << "a part, not the grid";
    EXPECT_EQ(s.occupancy().grid().maxValues, (*whole)->occupancy().grid().maxValues);
    EXPECT_EQ(s.occupancy().grid().blockMaxValues, (*whole)->occupancy().grid().blockMaxValues);
    EXPECT_EQ(occupancyTexels(s.occupancy()), occupancyTexels((*whole)->occupancy()));
    EXPECT_EQ(volume::compareImages(testutil::renderVolumesGpu(**renderer, camera, {{&s, options}}), wholeImage).maxAbs,
              0.0);
    if (use == engine::RadarNetworkGL::PreviousTexture::Copy) {
      EXPECT_EQ((*first)->occupancy().grid().maxValues, firstCells);
      EXPECT_EQ(
          volume::compareImages(testutil::renderVolumesGpu(**renderer, camera, {{first->get(), options}}), firstImage)
              .maxAbs,
          0.0);
    } else {
      EXPECT_FALSE((*first)->drawable());
    }
  }
}

// A network kept whole by a later step is held by both steps: a third step that changes one of
// its radars copies its textures even when asked to take them over, so the first step (still
// cached in a viewer) draws on as before.
TEST(RadarNetworkGL, ANetworkKeptByALaterStepIsNeverTakenOver) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const std::vector<std::shared_ptr<const volume::PolarVolume>> radars = threeRadarsAroundTheStorm();
  const std::vector<std::shared_ptr<const volume::PolarVolume>> next = withTheSecondStronger(radars);
  const auto rule = volume::OverlapRule::Maximum;
  const auto kind = volume::FieldKind::Reflectivity;
  const auto takeOver = engine::RadarNetworkGL::PreviousTexture::TakeOver;
  auto first = engine::RadarNetworkGL::createByCluster(radars, rule, kind);
  ASSERT_TRUE(first) << first.error();
  ASSERT_EQ(first->size(), 1u);
  auto second = engine::RadarNetworkGL::createByCluster(radars, rule, kind, 1.0, {}, *first, takeOver);
  ASSERT_TRUE(second) << second.error();
  ASSERT_EQ(second->front(), first->front()) << "nothing changed: kept whole";
  const Camera camera = cameraOnTheStorm();
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  options.render.mode = volume::VolumeRenderMode::Mip;
  const volume::VolumeImage before = testutil::renderVolumesGpu(**renderer, camera, {{first->front().get(), options}});
  auto third = engine::RadarNetworkGL::createByCluster(next, rule, kind, 1.0, {}, *second, takeOver);
  ASSERT_TRUE(third) << third.error();
  EXPECT_NE(third->front(), first->front());
  EXPECT_EQ(third->front()->radarsUploaded(), 1) << "the changed radar's tiles, the others' copied";
  EXPECT_TRUE(first->front()->drawable());
  EXPECT_EQ(
      volume::compareImages(testutil::renderVolumesGpu(**renderer, camera, {{first->front().get(), options}}), before)
          .maxAbs,
      0.0);
  auto whole = engine::RadarNetworkGL::create(next, rule, kind);
  ASSERT_TRUE(whole) << whole.error();
  EXPECT_EQ(volume::compareImages(testutil::renderVolumesGpu(**renderer, camera, {{third->front().get(), options}}),
                                  testutil::renderVolumesGpu(**renderer, camera, {{whole->get(), options}}))
                .maxAbs,
            0.0);
}

}  // namespace
