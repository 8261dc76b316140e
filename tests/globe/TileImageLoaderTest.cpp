// TileImageLoader: background production, compositing, priorities, frames, shutdown, errors.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include "atmoglobe/globe/ImageryPyramid.h"
#include "atmoglobe/globe/TileImageLoader.h"

namespace atmoglobe::globe {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// A scripted layer: solid colour, records the order of calls; optionally blocks the first call
/// until open() (to build up a queue behind it) or sleeps per tile.
class FakeLayer : public ImageryLayer {
 public:
  explicit FakeLayer(glm::u8vec4 colour, int maxLevel = 3) : colour_(colour), maxLevel_(maxLevel) {}

  Result<std::optional<ImageRGBA8>> tileImage(const TileId& t) const override {
    {
      std::unique_lock lock(mutex_);
      calls_.push_back(t);
      changed_.notify_all();
      if (gated_ && calls_.size() == 1) changed_.wait(lock, [&] { return open_; });  // only the first call waits
    }
    if (sleep_.count() > 0) std::this_thread::sleep_for(sleep_);
    if (noData_) return std::optional<ImageRGBA8>{};
    return std::optional<ImageRGBA8>{ImageRGBA8::filled(256, 256, colour_)};
  }
  int maxLevel() const override { return maxLevel_; }
  std::string description() const override { return "fake"; }

  void gate() { gated_ = true; }
  void open() {
    std::lock_guard lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }
  void waitForCalls(std::size_t n) const {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return calls_.size() >= n; });
  }
  std::vector<TileId> calls() const {
    std::lock_guard lock(mutex_);
    return calls_;
  }
  std::chrono::milliseconds sleep_{0};
  bool noData_ = false;

 private:
  glm::u8vec4 colour_;
  int maxLevel_;
  bool gated_ = false;
  bool open_ = false;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  mutable std::vector<TileId> calls_;
};

/// Layer whose pixels vary: left half transparent, right half (200, 0, 0) with alpha = row.
class HalfLayer : public ImageryLayer {
 public:
  Result<std::optional<ImageRGBA8>> tileImage(const TileId&) const override {
    ImageRGBA8 image = ImageRGBA8::filled(256, 256, {9, 9, 9, 0});
    for (int j = 0; j < 256; ++j)
      for (int i = 128; i < 256; ++i) image.set(i, j, {200, 0, 0, static_cast<std::uint8_t>(j)});
    return std::optional<ImageRGBA8>{std::move(image)};
  }
  int maxLevel() const override { return 7; }
  std::string description() const override { return "half"; }
};

TEST(TileImageLoaderTest, ReturnsNullptrThenTheImageAfterWaitIdle) {
  auto layer = std::make_shared<FakeLayer>(glm::u8vec4{10, 20, 30, 0});
  layer->gate();  // holds the worker inside the first tileImage call until open()
  TileImageLoader loader({layer}, {});
  const TileId t{2, 5, 1};
  EXPECT_EQ(loader.request(t, 1.0), nullptr);
  layer->waitForCalls(1);
  EXPECT_EQ(loader.request(t, 1.0), nullptr);  // in flight: not queued a second time
  EXPECT_FALSE(loader.idle());
  layer->open();
  loader.waitIdle();
  EXPECT_TRUE(loader.idle());
  std::shared_ptr<const ImageRGBA8> image = loader.request(t, 1.0);
  ASSERT_NE(image, nullptr);
  EXPECT_EQ(image->width, 256);
  EXPECT_EQ(image->at(17, 200), glm::u8vec4(10, 20, 30, 255));  // bottom layer's alpha ignored
  EXPECT_EQ(layer->calls().size(), 1u);
  const TileImageLoaderStats s = loader.stats();
  EXPECT_EQ(s.tilesDecoded, 1u);
  EXPECT_EQ(s.cacheBytes, 256u * 256u * 4u);
  EXPECT_GE(s.decodeSeconds, 0.0);
  EXPECT_EQ(s.errors, 0u);
  EXPECT_EQ(loader.maxLevel(), 3);
}

TEST(TileImageLoaderTest, CompositesLayersBottomToTop) {
  auto bottom = std::make_shared<FakeLayer>(glm::u8vec4{10, 20, 30, 0});
  auto empty = std::make_shared<FakeLayer>(glm::u8vec4{99, 99, 99, 255});
  empty->noData_ = true;  // std::nullopt: contributes nothing
  auto half = std::make_shared<HalfLayer>();
  TileImageLoader loader({bottom, empty, half}, {});
  EXPECT_EQ(loader.maxLevel(), 7);
  loader.request({0, 0, 0}, 0);
  loader.waitIdle();
  std::shared_ptr<const ImageRGBA8> image = loader.request({0, 0, 0}, 0);
  ASSERT_NE(image, nullptr);
  EXPECT_EQ(image->at(5, 100), glm::u8vec4(10, 20, 30, 255));   // top transparent there
  EXPECT_EQ(image->at(200, 0), glm::u8vec4(10, 20, 30, 255));   // alpha 0 row
  EXPECT_EQ(image->at(200, 255), glm::u8vec4(200, 0, 0, 255));  // alpha 255 row: top only
  // Row 128: alpha 128/255 -> c = 200 * 128/255 + 10 * 127/255 = 105.37 (red), 20 * 127/255 = 9.96
  // (green), 30 * 127/255 = 14.94 (blue); rounding to 8 bits is the only error.
  const glm::u8vec4 mid = image->at(200, 128);
  EXPECT_NEAR(mid.r, 200.0 * 128 / 255 + 10.0 * 127 / 255, 0.5);
  EXPECT_NEAR(mid.g, 20.0 * 127 / 255, 0.5);
  EXPECT_NEAR(mid.b, 30.0 * 127 / 255, 0.5);
  EXPECT_EQ(mid.a, 255);
}

TEST(TileImageLoaderTest, HigherPriorityFirstAndReRequestUpdatesPriority) {
  auto layer = std::make_shared<FakeLayer>(glm::u8vec4{1, 2, 3, 255});
  layer->gate();
  TileImageLoader loader({layer}, {.cacheBudgetBytes = 256u << 20, .workerThreads = 1});
  const TileId a{1, 0, 0}, b{1, 1, 0}, c{1, 2, 0}, d{1, 3, 0}, e{1, 0, 1};
  loader.request(a, 0.0);
  layer->waitForCalls(1);  // the only worker is now busy with a
  loader.request(b, 1.0);
  loader.request(c, 5.0);
  loader.request(d, 3.0);
  loader.request(e, 3.0);   // same priority as d, requested later: after d
  loader.request(b, 10.0);  // re-request raises b above everything
  EXPECT_FALSE(loader.idle());
  layer->open();
  loader.waitIdle();
  EXPECT_EQ(layer->calls(), (std::vector<TileId>{a, b, c, d, e}));
}

TEST(TileImageLoaderTest, EndFrameDropsRequestsNotRepeated) {
  auto layer = std::make_shared<FakeLayer>(glm::u8vec4{1, 2, 3, 255});
  layer->gate();
  TileImageLoader loader({layer}, {.cacheBudgetBytes = 256u << 20, .workerThreads = 1});
  const TileId a{1, 0, 0}, b{1, 1, 0}, c{1, 2, 0};
  loader.request(a, 0.0);
  layer->waitForCalls(1);
  loader.request(b, 1.0);
  loader.request(c, 2.0);
  loader.endFrame();       // frame 1: a (in flight), b, c all wanted
  loader.request(c, 2.0);  // frame 2 wants only c
  loader.endFrame();       // b dropped
  layer->open();
  loader.waitIdle();
  EXPECT_EQ(layer->calls(), (std::vector<TileId>{a, c}));
  EXPECT_NE(loader.request(a, 0.0), nullptr);  // the in-flight tile completed and was kept
  EXPECT_EQ(loader.request(b, 1.0), nullptr);  // wanted again: queued afresh
  loader.waitIdle();
  EXPECT_NE(loader.request(b, 1.0), nullptr);
}

TEST(TileImageLoaderTest, DestructorWithQueuedWorkReturnsPromptly) {
  auto layer = std::make_shared<FakeLayer>(glm::u8vec4{1, 2, 3, 255});
  layer->sleep_ = std::chrono::milliseconds(20);
  const auto start = Clock::now();
  {
    TileImageLoader loader({layer}, {.cacheBudgetBytes = 256u << 20, .workerThreads = 2});
    for (std::uint32_t x = 0; x < 32; ++x)
      for (std::uint32_t y = 0; y < 16; ++y) loader.request({4, x, y}, 0.0);
    layer->waitForCalls(1);
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  // All 512 tiles would take 512 * 20 ms / 2 workers = 5.1 s; a prompt stop waits for the at most
  // 2 tiles in flight (~20-40 ms). 1 s leaves room for a loaded 2-core machine.
  EXPECT_LT(seconds, 1.0);
  EXPECT_LT(layer->calls().size(), 50u);
}

TEST(TileImageLoaderTest, ManyWorkersProduceEveryTileAndCacheRespectsBudget) {
  auto layer = std::make_shared<FakeLayer>(glm::u8vec4{4, 5, 6, 255});
  const std::size_t tileBytes = 256u * 256u * 4u;
  TileImageLoader loader({layer}, {.cacheBudgetBytes = 10 * tileBytes, .workerThreads = 3});
  for (std::uint32_t x = 0; x < 8; ++x)
    for (std::uint32_t y = 0; y < 4; ++y) EXPECT_EQ(loader.request({2, x, y}, x + y * 0.1), nullptr);
  loader.waitIdle();
  const TileImageLoaderStats s = loader.stats();
  EXPECT_EQ(s.tilesDecoded, 32u);
  EXPECT_EQ(layer->calls().size(), 32u);
  EXPECT_EQ(s.cacheBytes, 10 * tileBytes);
  EXPECT_EQ(s.cacheEvictions, 22u);
}

fs::path freshDir() { return atmoglobe_test::freshTestDir("imagery"); }

TEST(TileImageLoaderTest, CorruptTileFileGivesAnErrorMessageNotACrash) {
  const fs::path dir = freshDir();
  const std::string source = (dir / "w.png").string();
  ASSERT_TRUE(writePng(source, ImageRGBA8::filled(512, 256, {50, 60, 70, 255})).ok());
  const fs::path out = dir / "p";
  ASSERT_TRUE(buildPyramid(source, out.string(), {}).ok());
  const std::string corrupt = (out / "0" / "1" / "0.png").string();
  std::ofstream(corrupt, std::ios::trunc) << "definitely not a png";
  Result<std::shared_ptr<GeographicPyramidLayer>> pyramid = GeographicPyramidLayer::open(out.string());
  ASSERT_TRUE(pyramid.ok());
  auto top = std::make_shared<HalfLayer>();
  TileImageLoader loader({*pyramid, top}, {});
  loader.request({0, 0, 0}, 0);
  loader.request({0, 1, 0}, 0);
  loader.waitIdle();
  std::vector<std::string> errors = loader.takeErrors();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find(corrupt), std::string::npos) << errors[0];
  EXPECT_TRUE(loader.takeErrors().empty());
  EXPECT_EQ(loader.stats().errors, 1u);
  std::shared_ptr<const ImageRGBA8> good = loader.request({0, 0, 0}, 0);
  std::shared_ptr<const ImageRGBA8> bad = loader.request({0, 1, 0}, 0);
  ASSERT_NE(good, nullptr);
  ASSERT_NE(bad, nullptr);  // remembered: not re-queued every frame
  EXPECT_EQ(good->at(10, 10), glm::u8vec4(50, 60, 70, 255));
  EXPECT_EQ(bad->at(10, 10), glm::u8vec4(0, 0, 0, 255));      // failed bottom layer: black
  EXPECT_EQ(bad->at(200, 255), glm::u8vec4(200, 0, 0, 255));  // the other layer still drawn
  loader.waitIdle();
  EXPECT_TRUE(loader.takeErrors().empty());
  EXPECT_EQ(loader.stats().tilesDecoded, 2u);
}

}  // namespace
}  // namespace atmoglobe::globe
