// Map lines over the globe (MapRendererGL): visible where expected from 1e7 m and from 1 m, and
// not hidden by the globe (the pixels they cover with the globe drawn first, counted against the
// same lines drawn alone).
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/map/Gshhg.h>
#include <atmoglobe/map/MapLod.h>

#include "GLTestUtil.h"

#include <chrono>
#include <filesystem>
#include <thread>

using namespace atmoglobe;

namespace {

// Pixels whose colour is close to the line colour (1, 0, 1): magenta appears nowhere else.
int countLinePixels(const globe::ImageRGBA8& image) {
  int n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const glm::u8vec4 p = image.at(x, y);
      n += p.r > 160 && p.b > 160 && p.g < 100;
    }
  return n;
}

bool lineNear(const globe::ImageRGBA8& image, glm::dvec2 px, int radius) {
  for (int y = static_cast<int>(px.y) - radius; y <= static_cast<int>(px.y) + radius; ++y)
    for (int x = static_cast<int>(px.x) - radius; x <= static_cast<int>(px.x) + radius; ++x) {
      if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
      const glm::u8vec4 p = image.at(x, y);
      if (p.r > 160 && p.b > 160 && p.g < 100) return true;
    }
  return false;
}

struct MapRender : ::testing::Test {
  void SetUp() override {
    testutil::glContext();
    auto loader = engine::openImagery({}, {});  // no imagery: the globe's base colour
    ASSERT_TRUE(loader) << loader.error();
    auto r = engine::SceneRendererGL::create(*loader);
    ASSERT_TRUE(r) << r.error();
    renderer_ = std::move(*r);
  }
  // The frame with the globe (withGlobe) or the lines alone on black.
  globe::ImageRGBA8 render(const engine::Camera& camera, bool withGlobe) {
    auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    EXPECT_TRUE(fb);
    testutil::beginReverseZ(**fb);
    if (withGlobe) {
      // The globe as it is once every tile of the view is loaded (they load on a worker): the
      // frame drawn before that depends on the worker's timing (a coarser tile's mesh and colour).
      for (int i = 0; i < 500; ++i) {
        testutil::beginReverseZ(**fb);
        renderer_->globe().draw(camera);
        if (renderer_->globe().lastFrameComplete()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      EXPECT_TRUE(renderer_->globe().lastFrameComplete());
    }
    renderer_->map().draw(camera);
    glFinish();
    return (*fb)->readColor();
  }
  std::unique_ptr<engine::SceneRendererGL> renderer_;
  static std::string crudeCoast() {
    return map::gshhgPath(map::defaultGshhgDirectory(), map::GshhgKind::Shoreline, map::GshhgResolution::Crude);
  }
  static bool gshhgInstalled() { return std::filesystem::exists(crudeCoast()); }
  // The built-in coastlines and borders on, every layer magenta (what countLinePixels counts).
  bool useMagentaCoastlines() {
    if (!renderer_->setMapContext(true)) return false;
    const engine::MapLineStyle magenta{glm::vec3(1.0f, 0.0f, 1.0f), 2.0f, 1.0f};
    for (int layer = 0; layer < 3; ++layer) renderer_->map().setBuiltinStyle(layer, magenta);
    return true;
  }
};

}  // namespace

TEST_F(MapRender, CoastlineFromTenThousandKilometres) {
  if (!gshhgInstalled()) GTEST_SKIP() << crudeCoast() << " missing (apt-get install gmt-gshhg)";
  ASSERT_TRUE(useMagentaCoastlines());
  const engine::Camera camera({38.0, -9.0, 1e7, 0.0, -90.0, 0.0}, 60.0, 480, 360);
  const globe::ImageRGBA8 with = render(camera, true), alone = render(camera, false);
  // Cabo da Roca (crude coast within 25 km: ~2 px here at ~12 km/px) has a line within 3 px.
  const auto cape = camera.projectToPixel(globe::geodeticToEcef({38.7804, -9.4989, 0.0}));
  ASSERT_TRUE(cape);
  EXPECT_TRUE(lineNear(with, *cape, 3));
  // The middle of the Atlantic (35 N, 40 W) has none within 10 px.
  const auto ocean = camera.projectToPixel(globe::geodeticToEcef({35.0, -40.0, 0.0}));
  ASSERT_TRUE(ocean);
  EXPECT_FALSE(lineNear(with, *ocean, 10));
  // Not hidden by the globe: the same pixels with the globe as alone (lines alone have no depth
  // to test against; the far side is cut analytically in both). 0.5 %: antialiased edge pixels
  // blended over the base colour instead of black can cross the magenta threshold differently.
  const int nWith = countLinePixels(with), nAlone = countLinePixels(alone);
  EXPECT_GT(nAlone, 2000);
  EXPECT_NEAR(nWith, nAlone, 0.005 * nAlone) << "with globe " << nWith << ", alone " << nAlone;
  std::cout << "1e7 m: line pixels with the globe " << nWith << ", alone " << nAlone << "\n";
}

TEST_F(MapRender, LineFromOneMetre) {
  // A 2 km geodesic line through (38.78 N, 9.49 W); the camera 1 m above its middle, looking down
  // at 60 deg: the line crosses the picture's centre (its ground footprint is ~1.2 m across).
  const double lat = 38.78, lon = -9.49;
  const auto a = globe::geodesicDirect(lat, lon, 60.0, 1000.0), b = globe::geodesicDirect(lat, lon, 240.0, 1000.0);
  renderer_->map().addLines({{{{a.lonDeg, a.latDeg}, {b.lonDeg, b.latDeg}}}}, {glm::vec3(1, 0, 1), 3.0f, 1.0f});
  const engine::Camera camera({lat, lon, 1.0, 0.0, -90.0, 0.0}, 60.0, 320, 240);
  const globe::ImageRGBA8 with = render(camera, true), alone = render(camera, false);
  // The line through the nadir: at the centre, and at the projected point 0.3 m along it.
  const auto mid = camera.projectToPixel(globe::geodeticToEcef({lat, lon, 0.0}));
  const auto q = globe::geodesicDirect(lat, lon, 60.0, 0.3);
  const auto along = camera.projectToPixel(globe::geodeticToEcef({q.latDeg, q.lonDeg, 0.0}));
  ASSERT_TRUE(mid && along);
  EXPECT_TRUE(lineNear(with, *mid, 1));
  EXPECT_TRUE(lineNear(with, *along, 1));
  // 0.3 m to the side (azimuth 150): ~60 px away at 1 m, no line.
  const auto s = globe::geodesicDirect(lat, lon, 150.0, 0.3);
  const auto side = camera.projectToPixel(globe::geodeticToEcef({s.latDeg, s.lonDeg, 0.0}));
  ASSERT_TRUE(side);
  EXPECT_FALSE(lineNear(with, *side, 3));
  const int nWith = countLinePixels(with), nAlone = countLinePixels(alone);
  EXPECT_GT(nAlone, 500);
  EXPECT_NEAR(nWith, nAlone, 0.005 * nAlone) << "with globe " << nWith << ", alone " << nAlone;
  std::cout << "1 m: line pixels with the globe " << nWith << ", alone " << nAlone << "\n";
}

TEST_F(MapRender, LinesBehindTheEarthAreHidden) {
  // A line on the far side of the Earth (antipode of the view centre) draws nothing.
  renderer_->map().addLines({{{{170.0, -38.0}, {172.0, -36.0}}}}, {glm::vec3(1, 0, 1), 3.0f, 1.0f});
  const engine::Camera camera({38.0, -9.0, 1e7, 0.0, -90.0, 0.0}, 60.0, 320, 240);
  EXPECT_EQ(countLinePixels(render(camera, true)), 0);
  EXPECT_EQ(countLinePixels(render(camera, false)), 0);  // the analytic horizon cut, not the depth
}

// Each part of the view at the level its distance asks for: from 45 km east of Lisbon looking
// out to sea, the bins near the eye at the level of the eye's height and those toward the
// horizon (760 km away) coarser; the coast at Cabo da Roca, 70 km away, still drawn where it is.
TEST_F(MapRender, FarBinsAreDrawnAtCoarserLevels) {
  if (!gshhgInstalled()) GTEST_SKIP() << crudeCoast() << " missing (apt-get install gmt-gshhg)";
  ASSERT_TRUE(useMagentaCoastlines());
  const engine::Camera camera({38.75, -8.90, 45e3, 280.0, -20.0, 0.0}, 60.0, 320, 240);
  const globe::ImageRGBA8 image = render(camera, false);
  const engine::MapFrameStats stats = renderer_->map().draw(camera);
  const auto near = map::gshhgResolutionForScale(45e3 / camera.focalLengthPx());
  std::cout << "bins at each level (crude .. full):";
  int levels = 0;
  for (int n : stats.binsAtLevel) {
    std::cout << " " << n;
    levels += n > 0;
  }
  std::cout << "\n";
  EXPECT_EQ(stats.resolution, near) << "the finest level: the eye's height's";
  EXPECT_GT(stats.binsAtLevel[static_cast<std::size_t>(near)], 0);
  int coarser = 0;
  for (int r = 0; r < static_cast<int>(near); ++r) coarser += stats.binsAtLevel[static_cast<std::size_t>(r)];
  EXPECT_GT(coarser, 0) << "bins toward the horizon at a coarser level";
  EXPECT_GE(levels, 2);
  const auto cape = camera.projectToPixel(globe::geodeticToEcef({38.7804, -9.4989, 0.0}));
  ASSERT_TRUE(cape);
  EXPECT_TRUE(lineNear(image, *cape, 3));
}

// With a build budget (the viewer's) a view of a new level draws the level before until every
// chunk of the new one is made, a few each frame, and then draws what an unbounded frame does.
TEST_F(MapRender, ABuildBudgetKeepsTheLevelBeforeUntilTheNewOneIsMade) {
  if (!gshhgInstalled()) GTEST_SKIP() << crudeCoast() << " missing (apt-get install gmt-gshhg)";
  ASSERT_TRUE(useMagentaCoastlines());
  engine::MapRendererGL& map = renderer_->map();
  // 1 microsecond: one chunk a frame (at least one is made whatever the budget).
  map.setBuildBudgetMs(0.001);
  const engine::Camera far({38.0, -9.0, 1e7, 0.0, -90.0, 0.0}, 60.0, 240, 180);
  const engine::Camera near({38.7, -9.3, 3.0e5, 0.0, -90.0, 0.0}, 60.0, 240, 180);
  ASSERT_NE(map::gshhgResolutionForScale(1e7 / far.focalLengthPx()),
            map::gshhgResolutionForScale(3.0e5 / near.focalLengthPx()));
  // The first frame has no level to keep: made whole.
  const globe::ImageRGBA8 farImage = render(far, false);
  EXPECT_TRUE(map.lastFrameComplete());
  EXPECT_GT(countLinePixels(farImage), 500);
  // The near view's first frame: the far level's lines (cached), not complete.
  const globe::ImageRGBA8 first = render(near, false);
  EXPECT_FALSE(map.lastFrameComplete());
  EXPECT_GT(countLinePixels(first), 100) << "the level before is drawn meanwhile";
  int frames = 1;
  globe::ImageRGBA8 last = first;
  while (!map.lastFrameComplete() && frames < 2000) {
    last = render(near, false);
    ++frames;
  }
  ASSERT_TRUE(map.lastFrameComplete()) << "not complete after " << frames << " frames";
  EXPECT_GT(frames, 2) << "a budget of 1 us builds one chunk a frame";
  // Complete: the same pixels as a frame without a budget.
  map.setBuildBudgetMs(0.0);
  const globe::ImageRGBA8 unbounded = render(near, false);
  EXPECT_TRUE(map.lastFrameComplete());
  int differ = 0;
  for (int y = 0; y < last.height; ++y)
    for (int x = 0; x < last.width; ++x) differ += last.at(x, y) != unbounded.at(x, y);
  EXPECT_EQ(differ, 0);
  std::cout << "the near level made over " << frames << " frames\n";
}
