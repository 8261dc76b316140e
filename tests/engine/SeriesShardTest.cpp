// Shards of a series (engine::seriesShard, docs/scale-out.md): disjoint, contiguous, and together
// every frame once, for every number of frames and shards; bad shard numbers are errors.
#include <atmoglobe/engine/SceneTime.h>

#include <gtest/gtest.h>

#include <vector>

namespace {
using namespace atmoglobe::engine;

TEST(SeriesShard, ShardsHoldEveryFrameOnceInOrder) {
  for (std::size_t frames = 0; frames <= 40; ++frames)
    for (std::size_t count = 1; count <= 12; ++count) {
      std::vector<int> seen(frames, 0);
      std::size_t next = 0;
      for (std::size_t k = 0; k < count; ++k) {
        auto r = seriesShard(frames, k, count);
        ASSERT_TRUE(r) << r.error();
        EXPECT_EQ(r->begin, next) << "contiguous, in order";
        EXPECT_LE(r->begin, r->end);
        // Balanced: sizes differ by at most one frame.
        EXPECT_LE(r->size(), frames / count + 1);
        EXPECT_GE(r->size(), frames / count);
        for (std::size_t f = r->begin; f < r->end; ++f) ++seen[f];
        next = r->end;
      }
      EXPECT_EQ(next, frames);
      for (std::size_t f = 0; f < frames; ++f) EXPECT_EQ(seen[f], 1) << frames << " frames, " << count << " shards";
    }
  // Large series: no overflow of frames * index.
  const std::size_t big = std::size_t{1} << 40;
  auto last = seriesShard(big, 999, 1000);
  ASSERT_TRUE(last);
  EXPECT_EQ(last->end, big);
  EXPECT_EQ(seriesFrameCount(4, 2), 7u);
  EXPECT_EQ(seriesFrameCount(1, 5), 1u);
  EXPECT_EQ(seriesFrameCount(0, 5), 0u);
}

TEST(SeriesShard, BadShardNumbersAreErrors) {
  auto zero = seriesShard(10, 0, 0);
  ASSERT_FALSE(zero);
  EXPECT_NE(zero.error().find("at least 1"), std::string::npos) << zero.error();
  auto beyond = seriesShard(10, 3, 3);
  ASSERT_FALSE(beyond);
  EXPECT_NE(beyond.error().find("numbered 0 to 2"), std::string::npos) << beyond.error();
}

}  // namespace
