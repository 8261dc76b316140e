// The memory budget's cache (volume/StepCache.h) and the lower-resolution copies of the GPU
// fallback (volume/Decimate.h).
#include "SyntheticGridVolume.h"

#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/StepCache.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

namespace {
using namespace atmoglobe;

std::shared_ptr<const int> value(int v) { return std::make_shared<const int>(v); }

TEST(StepCache, DropsLeastRecentlyUsedToHoldTheBudget) {
  volume::StepCache cache(100);
  cache.put("a", value(1), 40);
  cache.put("b", value(2), 40);
  ASSERT_TRUE(cache.get<int>("a"));  // a is now more recent than b
  cache.put("c", value(3), 40);      // 120 > 100: b, the least recently used, goes
  EXPECT_TRUE(cache.contains("a"));
  EXPECT_FALSE(cache.contains("b"));
  EXPECT_TRUE(cache.contains("c"));
  const auto s = cache.stats();
  EXPECT_EQ(s.heldBytes, 80u);
  EXPECT_LE(s.peakHeldBytes, 100u);
  EXPECT_EQ(s.drops, 1u);
  EXPECT_EQ(s.pendingBytes, 40u);  // dropped, not yet released
  cache.releaseDropped();
  EXPECT_EQ(cache.stats().pendingBytes, 0u);
  EXPECT_EQ(*cache.get<int>("c"), 3);
  EXPECT_FALSE(cache.get<int>("b"));
}

TEST(StepCache, ErasePrefixDropsOneLayersEntriesOnly) {
  volume::StepCache cache(1000);
  cache.put("grid:1:0:gpu", value(1), 10);
  cache.put("grid:1:2:cpu", value(2), 20);
  cache.put("grid:10:0:gpu", value(3), 40);  // another layer whose number starts with 1
  cache.put("radar:1:0:gpu", value(4), 80);
  cache.erasePrefix("grid:1:");
  EXPECT_FALSE(cache.contains("grid:1:0:gpu"));
  EXPECT_FALSE(cache.contains("grid:1:2:cpu"));
  EXPECT_TRUE(cache.contains("grid:10:0:gpu"));
  EXPECT_TRUE(cache.contains("radar:1:0:gpu"));
  EXPECT_EQ(cache.stats().heldBytes, 120u);
  EXPECT_EQ(cache.stats().pendingBytes, 30u);
  cache.releaseDropped();
  EXPECT_EQ(cache.stats().pendingBytes, 0u);
}

TEST(StepCache, EntriesInUseStayAndCount) {
  volume::StepCache cache(100);
  auto shown = value(7);
  cache.put("shown", shown, 90);  // held outside too: in use
  cache.put("next", value(8), 30);
  // 120 > 100 and "shown" cannot go: "next" does, though it is the more recent.
  EXPECT_TRUE(cache.contains("shown"));
  EXPECT_FALSE(cache.contains("next"));
  EXPECT_EQ(cache.stats().inUseBytes, 90u);
  EXPECT_FALSE(cache.fitsBesidesInUse(20));
  EXPECT_TRUE(cache.fitsBesidesInUse(10));
  shown.reset();  // no longer shown: the next put may drop it
  cache.put("other", value(9), 30);
  EXPECT_FALSE(cache.contains("shown"));
  EXPECT_LE(cache.stats().heldBytes, 100u);
}

TEST(StepCache, BudgetChangeAndReplacement) {
  volume::StepCache cache(1000);
  for (int k = 0; k < 10; ++k) cache.put(std::string("k").append(std::to_string(k)), value(k), 100);
  EXPECT_EQ(cache.stats().heldBytes, 1000u);
  cache.setBudget(250);  // the two most recent stay
  EXPECT_EQ(cache.stats().entries, 2u);
  EXPECT_TRUE(cache.contains("k9"));
  EXPECT_TRUE(cache.contains("k8"));
  cache.put("k9", value(99), 50);  // replaced, not added
  EXPECT_EQ(cache.stats().heldBytes, 150u);
  EXPECT_EQ(*cache.get<int>("k9"), 99);
  cache.erase("k8");
  EXPECT_EQ(cache.stats().heldBytes, 50u);
}

// Parts several entries share (a network's clusters a later step keeps) count once: three steps
// of 10 bytes each sharing a 60-byte part fit a budget of 100 (counted per entry they would take
// 210); the part leaves the count with the last entry holding it, in use or not; what is in use
// counts it once too.
TEST(StepCache, SharedPartsCountOnce) {
  volume::StepCache cache(100);
  const int part = 0, other = 0;
  const volume::StepCache::SharedPart big{&part, 60};
  cache.put("s0", value(0), 10, {big});
  cache.put("s1", value(1), 10, {big});
  cache.put("s2", value(2), 10, {big});
  EXPECT_EQ(cache.stats().heldBytes, 90u);
  EXPECT_EQ(cache.stats().entries, 3u);
  EXPECT_EQ(cache.stats().drops, 0u);
  // A fourth step with a part of its own: 90 + 10 + 10 > 100, so s0 goes (the shared part stays).
  cache.put("s3", value(3), 10, {big, {&other, 10}});
  EXPECT_FALSE(cache.contains("s0"));
  EXPECT_TRUE(cache.contains("s1"));
  EXPECT_EQ(cache.stats().heldBytes, 100u);
  EXPECT_EQ(cache.stats().pendingBytes, 10u);  // s0's own bytes only
  // In use: s1 and s3 held outside; the shared part counts once.
  const auto held1 = cache.get<int>("s1"), held3 = cache.get<int>("s3");
  EXPECT_EQ(cache.stats().inUseBytes, 10u + 10u + 60u + 10u);
  EXPECT_FALSE(cache.fitsBesidesInUse(11));
  EXPECT_TRUE(cache.fitsBesidesInUse(10));
  // Replacing s1 by an entry without the part, then erasing the others: the part goes with the last.
  cache.put("s1", value(11), 10);
  cache.erase("s2");
  EXPECT_EQ(cache.stats().heldBytes, 10u + 10u + 60u + 10u);
  cache.erase("s3");
  EXPECT_EQ(cache.stats().heldBytes, 10u);
  cache.releaseDropped();
  EXPECT_EQ(cache.stats().pendingBytes, 0u);
}

TEST(StepCache, DefaultBudgetIsAQuarterOfMemory) {
  const std::uint64_t ram = volume::physicalMemoryBytes();
  ASSERT_GT(ram, 0u);
  EXPECT_EQ(volume::defaultMemoryBudgetBytes(), ram / 4);
  EXPECT_GT(volume::peakResidentBytes(), 0u);
  EXPECT_GT(volume::currentResidentBytes(), 0u);
}

// The background loader's use of the cache (engine::ScenePrefetcher): a worker marks steps as
// loading and puts them while the thread that shows them waits for, gets, holds and releases
// them. The budget holds whenever the showing thread looks, and the step it holds stays. Run
// under ThreadSanitizer too (ctest label threads).
TEST(StepCache, WorkerPutsWhileTheShowingThreadGetsAndReleases) {
  constexpr int kSteps = 300;
  constexpr std::uint64_t kBytes = 100, kBudget = 8 * kBytes;
  volume::StepCache cache(kBudget);
  auto key = [](int s) { return "grid:0:" + std::to_string(s) + ":cpu"; };
  std::thread worker([&] {
    for (int s = 0; s < kSteps; ++s) {
      cache.markLoading(key(s));
      cache.put(key(s), value(s), kBytes);
    }
  });
  std::shared_ptr<const int> shown;  // the step on screen: in use, never dropped
  int shownStep = -1, found = 0;
  for (int s = 0; s < kSteps; ++s) {
    cache.waitWhileLoading(key(s));
    if (auto v = cache.get<int>(key(s))) {  // null: not put yet, or already dropped (read again)
      EXPECT_EQ(*v, s);
      shown = v;
      shownStep = s;
      ++found;
    }
    if (shownStep >= 0) {
      EXPECT_TRUE(cache.contains(key(shownStep)));
    }
    EXPECT_LE(cache.stats().heldBytes, kBudget);
    cache.releaseDropped();  // on this thread, as the GL thread does
  }
  worker.join();
  cache.releaseDropped();
  const auto st = cache.stats();
  EXPECT_LE(st.heldBytes, kBudget);
  EXPECT_EQ(st.pendingBytes, 0u);
  EXPECT_EQ(st.heldBytes + st.drops * kBytes, kSteps * kBytes);  // every step put was kept or dropped
  EXPECT_TRUE(cache.get<int>(key(kSteps - 1)));                  // the newest stays
  if (shownStep >= 0) {
    EXPECT_TRUE(cache.contains(key(shownStep)));
  }
  std::printf("steps found by the showing thread while the worker put them: %d of %d\n", found, kSteps);
}

TEST(Decimate, GridKeepsEveryOtherColumnAndRowAndTheEdges) {
  auto g = testutil::rectilinearGrid(
      testutil::evenlySpaced(-100.0, 0.5, 11), testutil::evenlySpaced(30.0, 0.5, 8), {0.0, 1000.0, 2000.0},
      [](double, double) { return 100.0; }, [](double lat, double lon, double h) { return lat * 1000 + lon + h; });
  const volume::GridVolume d = volume::decimateGrid(g, 2);
  EXPECT_EQ(d.nx, 6u);  // 0, 2, 4, 6, 8, 10
  EXPECT_EQ(d.ny, 5u);  // 0, 2, 4, 6 and the last row, 7
  EXPECT_EQ(d.nz, 3u);
  EXPECT_EQ(d.lonDeg.back(), g.lonDeg.back());
  EXPECT_EQ(d.latDeg.back(), g.latDeg.back());
  EXPECT_EQ(d.value(1, 1, 1), g.value(1, 2, 2));
  EXPECT_EQ(d.value(2, 4, 5), g.value(2, 7, 10));
  EXPECT_EQ(d.heightMeters(2, 4, 5), g.heightMeters(2, 7, 10));
  EXPECT_EQ(d.valueMax, g.valueMax);  // the largest value sits at a kept corner
  // A global grid whose column count halves evenly keeps wrapping.
  auto global = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 30.0, 12), testutil::evenlySpaced(-60.0, 30.0, 5), {0.0, 1000.0},
      [](double, double) { return 0.0; }, [](double, double lon, double) { return lon; });
  global.wrapsLongitude = true;
  const volume::GridVolume gd = volume::decimateGrid(global, 2);
  EXPECT_EQ(gd.nx, 6u);
  EXPECT_TRUE(gd.wrapsLongitude);
  EXPECT_EQ(gd.lonDeg[1], 60.0);
}

}  // namespace
