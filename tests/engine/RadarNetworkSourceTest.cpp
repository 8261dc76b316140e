// A radar network layer from files (engine::RadarNetworkSourceGL, docs/networks.md): the integrate
// rule draws each radar as separate radar layers do, velocity is drawn per radar, and the
// network's steps stay within the memory budget (docs/memory.md).
#include "GLTestUtil.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarNetworkSourceGL.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

namespace {
using namespace atmoglobe;

// Two overlapping SYNTHETIC radars (KTLX, KVNX: 175 km apart, 150 km range) of one storm field at
// two times 5 minutes apart: DIR/KTLX_0.nc, DIR/KVNX_0.nc, DIR/KTLX_1.nc, DIR/KVNX_1.nc. `apart`:
// also KLBB (DIR/KLBB_0.nc, DIR/KLBB_1.nc), 420 km from KVNX: a cluster of its own. `rescan`: the
// second time's volumes scan other elevations (as many), so their tables and records differ.
std::string writePair(const std::string& name, bool velocity = false, bool apart = false, bool rescan = false) {
  const std::string dir = testutil::testOutputDir() + "/" + name;
  std::filesystem::create_directories(dir);
  struct Site {
    const char* id;
    double latDeg, lonDeg, altitudeMeters;
  };
  std::vector<Site> sites = {{"KTLX", 35.3331, -97.2778, 384.7}, {"KVNX", 36.7408, -98.1278, 378.6}};
  if (apart) sites.push_back({"KLBB", 33.6541, -101.8142, 993.0});
  volume::SyntheticRadarOptions o;
  o.elevationsDeg = {0.5, 1.5, 3.0, 6.0};
  o.raysPerSweep = 180;
  o.gateSpacingMeters = 1000.0;
  o.maxRangeMeters = 150000.0;
  o.radialVelocity = velocity;
  std::vector<std::pair<double, double>> at;
  for (const Site& s : sites) at.emplace_back(s.latDeg, s.lonDeg);
  o.networkStorms = volume::syntheticNetworkStorms(at, 400.0, 1);
  for (int t = 0; t < 2; ++t)
    for (const Site& s : sites) {
      volume::SyntheticRadarOptions r = o;
      r.siteId = s.id;
      r.siteLatDeg = s.latDeg;
      r.siteLonDeg = s.lonDeg;
      r.antennaAltitudeMslMeters = s.altitudeMeters;
      r.startTimeIso8601 = t == 0 ? "2020-05-01T21:00:00Z" : "2020-05-01T21:05:00Z";
      if (rescan && t == 1) r.elevationsDeg = {0.5, 1.0, 2.0, 7.0};
      EXPECT_TRUE(volume::writeSyntheticCfRadial(dir + "/" + s.id + "_" + std::to_string(t) + ".nc", r));
    }
  return dir;
}

// A network whose step changes one radar of two: KVNX has one volume (21:00), KTLX two (21:00,
// 21:05), so at 21:05 the network shows KTLX's second volume beside KVNX's first. Opened at its
// latest step (both radars uploaded) and drawn.
struct ChangingPair {
  std::unique_ptr<engine::SceneRendererGL> renderer;
  const engine::RadarNetworkSourceGL* source = nullptr;
  engine::SceneTimeAxis axis;
  globe::ImageRGBA8 latest;
};
std::optional<ChangingPair> openChangingPair(const std::string& name);

// The pair's first volumes alone (21:00): a network of one step, uploaded whole.
std::string firstStepOnly(const std::string& name) {
  const std::string dir = writePair(name);
  std::filesystem::remove(dir + "/KTLX_1.nc");
  std::filesystem::remove(dir + "/KVNX_1.nc");
  return dir;
}

const engine::Camera& camera() {
  // Above the middle of the pair, 600 km up, looking down at both.
  static const engine::Camera c(engine::CameraPose{36.0, -97.7, 6e5, 0.0, -90.0, 0.0}, 60.0, 160, 90);
  return c;
}

globe::ImageRGBA8 draw(engine::SceneRendererGL& renderer) {
  auto fb = engine::FramebufferGL::create(camera().widthPx(), camera().heightPx());
  EXPECT_TRUE(fb) << fb.error();
  auto image = renderer.renderToImage(camera(), {}, **fb);
  EXPECT_TRUE(image) << image.error();
  return *image;
}

std::unique_ptr<engine::SceneRendererGL> emptyRenderer() {
  testutil::glContext();
  auto loader = engine::openImagery({}, {});
  auto renderer = engine::SceneRendererGL::create(*loader);
  EXPECT_TRUE(renderer) << renderer.error();
  return std::move(*renderer);
}

engine::VolumeLayerDescription radarLayer(const std::string& path) {
  engine::VolumeLayerDescription d;
  d.kind = engine::VolumeKind::Radar;
  d.path = path;
  d.stepMeters = 1000.0;
  return d;
}

TEST(RadarNetworkSource, IntegrateDrawsEachRadarAsSeparateRadarLayersDo) {
  const std::string dir = writePair("network_integrate");
  auto network = emptyRenderer();
  engine::VolumeLayerDescription d = radarLayer(dir);
  d.overlap = volume::OverlapRule::Integrate;
  auto added = network->addVolume(d);
  ASSERT_TRUE(added) << added.error();
  const auto* source = network->layerAs<engine::RadarNetworkSourceGL>(0);
  ASSERT_NE(source, nullptr);
  EXPECT_EQ(source->rule(), volume::OverlapRule::Integrate);
  EXPECT_TRUE(source->clusters().empty());
  ASSERT_EQ(source->radarsApart().size(), 2u);

  auto separate = emptyRenderer();
  for (const char* file : {"/KTLX_1.nc", "/KVNX_1.nc"}) {
    auto layer = separate->addVolume(radarLayer(dir + file));
    ASSERT_TRUE(layer) << layer.error();
  }
  // The volumes alone (the scenes' site markers differ: the network labels each site its own
  // way), through the same marcher.
  std::vector<engine::VolumeLayerGL> apart, layers;
  for (const engine::VolumeGL* v : source->volumes()) apart.push_back({v, source->options()});
  for (std::size_t i = 0; i < separate->volumeLayerCount(); ++i)
    for (const engine::VolumeGL* v : separate->layer(i).volumes()) layers.push_back({v, separate->layer(i).options()});
  const volume::VolumeImage a = testutil::renderVolumesGpu(network->volumeRenderer(), camera(), apart);
  const volume::VolumeImage b = testutil::renderVolumesGpu(separate->volumeRenderer(), camera(), layers);
  int drawn = 0;
  for (int y = 0; y < camera().heightPx(); ++y)
    for (int x = 0; x < camera().widthPx(); ++x) drawn += b.at(x, y).a > 0.05;
  ASSERT_GT(drawn, 30) << "the storm is in view";
  // The same volumes integrated by the same march; only the order in which the two radars'
  // extinctions are summed may differ (float addition): at most 1 of 255.
  const volume::ImageError e = volume::compareImages(a, b);
  std::cout << "network under integrate vs two radar layers: " << drawn << " pixels drawn, max " << e.maxAbs
            << ", mean " << e.meanAbs << " of 255\n";
  EXPECT_LE(e.maxAbs, 1.0);
}

TEST(RadarNetworkSource, TheLegendSaysWhenTheFarFieldMayDrawIt) {
  // A forecaster must be able to tell a frame drawn from the far field's slabs (FarFieldGL.h).
  const std::string dir = writePair("network_far_field_legend", false);
  for (engine::FarField f : {engine::FarField::Off, engine::FarField::Auto}) {
    auto renderer = emptyRenderer();
    engine::VolumeLayerDescription d = radarLayer(dir);
    d.farField = f;
    auto added = renderer->addVolume(d);
    ASSERT_TRUE(added) << added.error();
    const auto* source = renderer->layerAs<engine::RadarNetworkSourceGL>(0);
    ASSERT_NE(source, nullptr);
    EXPECT_EQ(source->options().farField, f);
    EXPECT_EQ(source->legendPart().subtitle.find("vertical slabs") != std::string::npos, f == engine::FarField::Auto)
        << source->legendPart().subtitle;
  }
}

TEST(RadarNetworkSource, VelocityIsDrawnPerRadarAndACombiningRuleIsRefused) {
  // The mean of radial velocities from two sites is meaningless: without a rule the network draws
  // each radar apart; a combining rule asked for is refused, saying why and what to do.
  const std::string dir = writePair("network_velocity", true);
  auto renderer = emptyRenderer();
  engine::VolumeLayerDescription d = radarLayer(dir);
  d.field = "VEL";
  auto added = renderer->addVolume(d);
  ASSERT_TRUE(added) << added.error();
  const auto* source = renderer->layerAs<engine::RadarNetworkSourceGL>(0);
  ASSERT_NE(source, nullptr);
  EXPECT_EQ(source->rule(), volume::OverlapRule::Integrate);
  EXPECT_FALSE(source->valuesCombine());
  EXPECT_NE(source->legendPart().subtitle.find("not combined"), std::string::npos) << source->legendPart().subtitle;

  auto refused = emptyRenderer();
  d.overlap = volume::OverlapRule::WeightedMean;
  auto mean = refused->addVolume(d);
  ASSERT_FALSE(mean);
  EXPECT_NE(mean.error().find("cannot be combined"), std::string::npos) << mean.error();
  EXPECT_NE(mean.error().find("draw each radar apart"), std::string::npos) << mean.error();
}

TEST(RadarNetworkSource, AStepLargerThanTheBudgetIsRefusedBeforeAnyRead) {
  const std::string dir = writePair("network_budget_refused");
  auto renderer = emptyRenderer();
  renderer->setMemoryBudget(1 << 20);  // 1 MiB; one volume holds 4 x 180 x 148 gates (1.2 MiB at 12 bytes)
  auto added = renderer->addVolume(radarLayer(dir));
  ASSERT_FALSE(added);
  EXPECT_NE(added.error().find("more than the memory budget of 1.0 MiB"), std::string::npos) << added.error();
  EXPECT_EQ(renderer->stepCache().stats().entries, 0u) << "nothing was read";
}

TEST(RadarNetworkSource, StepsStayWithinTheBudgetAndDrawTheSameWhenReadAgain) {
  const std::string dir = writePair("network_budget_steps");
  auto renderer = emptyRenderer();
  auto added = renderer->addVolume(radarLayer(dir));  // mean rule, latest step (1)
  ASSERT_TRUE(added) << added.error();
  auto axis = engine::sceneTimeAxis(*renderer);
  ASSERT_TRUE(axis) << axis.error();
  ASSERT_EQ(axis->times.size(), 2u);
  const globe::ImageRGBA8 latest = draw(*renderer);
  // Two volumes, their upload parts (RadarNetworkGL::prepareRadar) and the step's GPU network are
  // held, each once.
  const auto oneStep = renderer->stepCache().stats();
  EXPECT_EQ(oneStep.entries, 5u);
  EXPECT_TRUE(renderer->stepCache().contains(engine::stepKey(0, 1, true)));

  // Room for one step only: showing the other drops the first one's GPU network (the largest
  // part: textures), and coming back uploads it again and draws the same picture.
  renderer->setMemoryBudget(oneStep.heldBytes + oneStep.heldBytes / 4);
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 0));
  const globe::ImageRGBA8 earlier = draw(*renderer);
  EXPECT_NE(earlier.pixels, latest.pixels) << "the storms move in 5 minutes";
  auto stats = renderer->stepCache().stats();
  EXPECT_LE(stats.heldBytes, stats.budgetBytes);
  EXPECT_GE(stats.drops, 1u);
  EXPECT_FALSE(renderer->stepCache().contains(engine::stepKey(0, 1, true)));
  EXPECT_TRUE(renderer->stepCache().contains(engine::stepKey(0, 0, true)));
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 1));
  EXPECT_EQ(draw(*renderer).pixels, latest.pixels);
  stats = renderer->stepCache().stats();
  EXPECT_LE(stats.heldBytes, stats.budgetBytes);

  // With room for both, a step shown before is found in the cache: no read, no upload.
  renderer->setMemoryBudget(oneStep.heldBytes * 4);
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 0));
  const auto hits = renderer->stepCache().stats().hits;
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 1));
  EXPECT_EQ(renderer->stepCache().stats().hits, hits + 1);
  EXPECT_EQ(draw(*renderer).pixels, latest.pixels);
}

TEST(RadarNetworkSource, TheStepAheadIsReadInTheBackgroundAndDrawsTheSame) {
  // The scene prefetcher reads the next step's volumes on its thread (docs/networks.md); showing
  // that step then finds them in the cache and only builds and uploads the network.
  const std::string dir = writePair("network_prefetch");
  auto renderer = emptyRenderer();
  ASSERT_TRUE(renderer->addVolume(radarLayer(dir)));  // shows the latest step (1)
  auto axis = engine::sceneTimeAxis(*renderer);
  ASSERT_TRUE(axis) << axis.error();
  ASSERT_EQ(axis->times.size(), 2u);
  {
    engine::ScenePrefetcher prefetch(*renderer, *axis, 1);
    prefetch.request(1);  // step 1 shown: step 0 is next (play wraps)
    prefetch.waitIdle();
    EXPECT_EQ(prefetch.stepsPrepared(), 1u);
  }
  // Step 0's two volumes (KTLX_0, KVNX_0) and their upload parts come from the cache: four hits;
  // its network is new: one miss. Without the prefetcher all five would be misses.
  const auto before = renderer->stepCache().stats();
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 0));
  const auto after = renderer->stepCache().stats();
  EXPECT_EQ(after.hits - before.hits, 4u);
  EXPECT_EQ(after.misses - before.misses, 1u);
  EXPECT_LE(after.heldBytes, after.budgetBytes);

  // The same picture as a renderer that read step 0 itself.
  auto alone = emptyRenderer();
  ASSERT_TRUE(alone->addVolume(radarLayer(dir)));
  ASSERT_TRUE(engine::showSceneTime(*alone, *axis, 0));
  const auto aloneStats = alone->stepCache().stats();
  EXPECT_EQ(draw(*renderer).pixels, draw(*alone).pixels);
  EXPECT_GE(aloneStats.misses, 5u) << "read on the GL thread: volumes, parts and the network missed";
}

std::optional<ChangingPair> openChangingPair(const std::string& name) {
  const std::string dir = writePair(name);
  std::filesystem::remove(dir + "/KVNX_1.nc");
  ChangingPair p;
  p.renderer = emptyRenderer();
  if (auto added = p.renderer->addVolume(radarLayer(dir)); !added) {
    ADD_FAILURE() << added.error();
    return std::nullopt;
  }
  p.source = p.renderer->layerAs<engine::RadarNetworkSourceGL>(0);
  auto axis = engine::sceneTimeAxis(*p.renderer);
  if (!p.source || !axis || axis->times.size() != 2) {
    ADD_FAILURE() << "a network layer of two steps expected" << (axis ? "" : ": " + axis.error());
    return std::nullopt;
  }
  EXPECT_EQ(p.source->radarsUploaded(), 2u);
  p.axis = std::move(*axis);
  p.latest = draw(*p.renderer);
  return p;
}

TEST(RadarNetworkSource, AStepOfALoopOverTheBudgetUploadsOnlyTheRadarsThatChanged) {
  auto pair = openChangingPair("network_take_over");
  ASSERT_TRUE(pair);
  auto& renderer = pair->renderer;
  const auto* source = pair->source;
  const engine::SceneTimeAxis* axis = &pair->axis;
  const globe::ImageRGBA8& latest = pair->latest;

  // Within a budget that cannot hold both steps' GPU parts, step 0 takes over step 1's textures and
  // uploads KTLX's tiles only; step 1's GPU part leaves the cache (it no longer draws).
  const auto oneStep = renderer->stepCache().stats();
  renderer->setMemoryBudget(oneStep.heldBytes + oneStep.heldBytes / 10);
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 0));
  EXPECT_EQ(source->radarsUploaded(), 3u);
  EXPECT_FALSE(renderer->stepCache().contains(engine::stepKey(0, 1, true)));
  const globe::ImageRGBA8 earlier = draw(*renderer);
  EXPECT_NE(earlier.pixels, latest.pixels) << "KTLX's storms move in 5 minutes";

  // Pixel for pixel the network uploaded whole: a renderer that opens step 0's volumes alone.
  auto whole = emptyRenderer();
  ASSERT_TRUE(whole->addVolume(radarLayer(firstStepOnly("network_take_over_whole"))));
  EXPECT_EQ(whole->layerAs<engine::RadarNetworkSourceGL>(0)->radarsUploaded(), 2u);
  EXPECT_EQ(earlier.pixels, draw(*whole).pixels);

  // And back: the first picture again, one radar uploaded.
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 1));
  EXPECT_EQ(source->radarsUploaded(), 4u);
  EXPECT_EQ(draw(*renderer).pixels, latest.pixels);
  const auto stats = renderer->stepCache().stats();
  EXPECT_LE(stats.heldBytes, stats.budgetBytes);
}

// Within a budget that holds the loop a step keeps the step shown before (for the replay) and
// copies its textures on the GPU, uploading only the radars that changed; the copy draws what a
// network uploaded whole draws, and the step before still draws its own picture from the cache.
TEST(RadarNetworkSource, AStepOfALoopWithinTheBudgetCopiesTheRadarsThatDidNotChange) {
  auto pair = openChangingPair("network_copy");
  ASSERT_TRUE(pair);
  auto& renderer = pair->renderer;
  const auto* source = pair->source;
  const engine::SceneTimeAxis* axis = &pair->axis;
  const globe::ImageRGBA8& latest = pair->latest;
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 0));
  EXPECT_EQ(source->radarsUploaded(), 3u) << "KTLX's tiles alone";
  EXPECT_TRUE(renderer->stepCache().contains(engine::stepKey(0, 1, true))) << "step 1 kept for the replay";
  const globe::ImageRGBA8 earlier = draw(*renderer);
  EXPECT_NE(earlier.pixels, latest.pixels) << "KTLX's storms move in 5 minutes";
  auto whole = emptyRenderer();
  ASSERT_TRUE(whole->addVolume(radarLayer(firstStepOnly("network_copy_whole"))));
  EXPECT_EQ(earlier.pixels, draw(*whole).pixels);
  // The replay: step 1 from the cache, nothing uploaded, its picture as first drawn.
  ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 1));
  EXPECT_EQ(source->radarsUploaded(), 3u);
  EXPECT_EQ(draw(*renderer).pixels, latest.pixels);
}

// A step rebuilds only the clusters whose radars changed: a cluster of radars apart from the
// others whose volumes are those of the step before is that step's network itself (nothing of it
// built or uploaded again), within the budget (the step before kept) and over it (its textures
// taken over), and the picture is the one of a network built whole. KTLX's two volumes scan
// other elevations, so its rows of the tables taken over or copied must be replaced.
TEST(RadarNetworkSource, AStepKeepsTheClustersWhoseRadarsDidNotChange) {
  for (const bool overBudget : {false, true}) {
    SCOPED_TRACE(overBudget ? "over the budget" : "within the budget");
    const std::string name = overBudget ? "network_keep_over" : "network_keep_within";
    const std::string dir = writePair(name, false, true, true);
    std::filesystem::remove(dir + "/KVNX_1.nc");
    std::filesystem::remove(dir + "/KLBB_1.nc");  // KLBB shows its 21:00 volume at both steps
    auto renderer = emptyRenderer();
    ASSERT_TRUE(renderer->addVolume(radarLayer(dir)));
    const auto* source = renderer->layerAs<engine::RadarNetworkSourceGL>(0);
    ASSERT_NE(source, nullptr);
    auto axis = engine::sceneTimeAxis(*renderer);
    ASSERT_TRUE(axis) << axis.error();
    ASSERT_EQ(axis->times.size(), 2u);
    ASSERT_EQ(source->clusters().size(), 2u) << "the pair, and KLBB apart";
    ASSERT_EQ(source->clusters()[1]->network().radarCount(), 1u);
    const engine::RadarNetworkGL* lone = source->clusters()[1].get();
    const engine::RadarNetworkGL* pair = source->clusters()[0].get();
    EXPECT_EQ(source->radarsUploaded(), 3u);
    const globe::ImageRGBA8 latest = draw(*renderer);
    if (overBudget) {
      const auto oneStep = renderer->stepCache().stats();
      renderer->setMemoryBudget(oneStep.heldBytes + oneStep.heldBytes / 10);
    }

    ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 0));
    ASSERT_EQ(source->clusters().size(), 2u);
    EXPECT_EQ(source->clusters()[1].get(), lone) << "KLBB's network kept";
    EXPECT_NE(source->clusters()[0].get(), pair) << "the pair's network built again (KTLX changed)";
    EXPECT_EQ(source->radarsUploaded(), 4u) << "KTLX's tiles alone";
    EXPECT_EQ(renderer->stepCache().contains(engine::stepKey(0, 1, true)), !overBudget);
    const globe::ImageRGBA8 earlier = draw(*renderer);
    EXPECT_NE(earlier.pixels, latest.pixels) << "KTLX's storms move in 5 minutes";

    // Pixel for pixel the network built whole from the 21:00 volumes.
    const std::string wholeDir = writePair(name + "_whole", false, true, true);
    for (const char* file : {"KTLX_1.nc", "KVNX_1.nc", "KLBB_1.nc"}) std::filesystem::remove(wholeDir + "/" + file);
    auto whole = emptyRenderer();
    ASSERT_TRUE(whole->addVolume(radarLayer(wholeDir)));
    EXPECT_EQ(earlier.pixels, draw(*whole).pixels);

    // Within the budget both steps are cached and hold KLBB's network, which counts once: taking
    // the later step out frees its pair's network alone.
    if (!overBudget) {
      const std::uint64_t before = renderer->stepCache().stats().heldBytes, pairBytes = pair->gpuBytes();
      renderer->stepCache().erase(engine::stepKey(0, 1, true));
      EXPECT_EQ(before - renderer->stepCache().stats().heldBytes, pairBytes)
          << "KLBB's network (" << lone->gpuBytes() << " bytes) is still held by the step shown";
      renderer->stepCache().releaseDropped();
    }

    // And back: KLBB's network still the same one, the first picture again.
    ASSERT_TRUE(engine::showSceneTime(*renderer, *axis, 1));
    EXPECT_EQ(source->clusters()[1].get(), lone);
    EXPECT_EQ(draw(*renderer).pixels, latest.pixels);
    const auto stats = renderer->stepCache().stats();
    EXPECT_LE(stats.heldBytes, stats.budgetBytes);
  }
}

}  // namespace
