// LruCache: byte budget, least-recently-used order, eviction count.
#include <gtest/gtest.h>

#include <string>

#include "atmoglobe/globe/LruCache.h"

namespace atmoglobe::globe {
namespace {

TEST(LruCacheTest, KeepsWithinBudgetEvictingLeastRecentlyUsed) {
  LruCache<int, std::string> cache(100);
  EXPECT_EQ(cache.budgetBytes(), 100u);
  cache.insert(1, "one", 40);
  cache.insert(2, "two", 40);
  EXPECT_EQ(cache.bytes(), 80u);
  EXPECT_EQ(cache.size(), 2u);
  ASSERT_NE(cache.find(1), nullptr);  // 1 becomes the most recent; 2 is now the oldest
  EXPECT_EQ(*cache.find(1), "one");
  cache.insert(3, "three", 40);  // 120 > 100: evicts 2
  EXPECT_EQ(cache.find(2), nullptr);
  EXPECT_NE(cache.find(1), nullptr);
  EXPECT_NE(cache.find(3), nullptr);
  EXPECT_EQ(cache.bytes(), 80u);
  EXPECT_EQ(cache.evictions(), 1u);
  // Order now (newest first): 3, 1. Two more entries of 30 evict 1, then 3.
  cache.insert(4, "four", 30);  // 110: evicts 1
  EXPECT_FALSE(cache.contains(1));
  cache.insert(5, "five", 30);  // 100: fits
  EXPECT_TRUE(cache.contains(3));
  EXPECT_EQ(cache.bytes(), 100u);
  cache.insert(6, "six", 1);  // 101: evicts 3
  EXPECT_FALSE(cache.contains(3));
  EXPECT_EQ(cache.evictions(), 3u);
  EXPECT_EQ(cache.size(), 3u);
  EXPECT_LE(cache.bytes(), cache.budgetBytes());
}

TEST(LruCacheTest, ReplacingAKeyUpdatesBytesAndOrder) {
  LruCache<int, int> cache(100);
  cache.insert(1, 10, 50);
  cache.insert(2, 20, 40);
  cache.insert(1, 11, 10);  // replace: 1 is now newest and counts 10 bytes
  EXPECT_EQ(cache.bytes(), 50u);
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_EQ(*cache.find(1), 11);
  cache.insert(3, 30, 55);  // 105: evicts the oldest, 2
  EXPECT_FALSE(cache.contains(2));
  EXPECT_TRUE(cache.contains(1));
  EXPECT_EQ(cache.evictions(), 1u);
  EXPECT_TRUE(cache.erase(1));
  EXPECT_FALSE(cache.erase(1));
  EXPECT_EQ(cache.bytes(), 55u);
  EXPECT_EQ(cache.evictions(), 1u);  // erase is not an eviction
}

TEST(LruCacheTest, OversizedEntryIsKeptAlone) {
  LruCache<int, int> cache(100);
  cache.insert(1, 1, 30);
  cache.insert(2, 2, 30);
  cache.insert(3, 3, 500);
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_TRUE(cache.contains(3));
  EXPECT_EQ(cache.bytes(), 500u);
  EXPECT_EQ(cache.evictions(), 2u);
  cache.insert(4, 4, 10);  // the oversized one is now the oldest and goes
  EXPECT_FALSE(cache.contains(3));
  EXPECT_EQ(cache.bytes(), 10u);
}

TEST(LruCacheTest, EvictWhileStopsAtFirstEntryToKeep) {
  LruCache<int, int> cache(1000);
  for (int i = 0; i < 5; ++i) cache.insert(i, i * 10, 1);
  cache.find(0);                                                          // order newest first: 0, 4, 3, 2, 1
  cache.evictWhile([](const int& key, const int&) { return key != 3; });  // drops 1, 2; stops at 3
  EXPECT_EQ(cache.size(), 3u);
  EXPECT_FALSE(cache.contains(1));
  EXPECT_FALSE(cache.contains(2));
  EXPECT_TRUE(cache.contains(3));
  EXPECT_EQ(cache.evictions(), 2u);
  cache.evictWhile([](const int&, const int&) { return true; });
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_EQ(cache.bytes(), 0u);
}

}  // namespace
}  // namespace atmoglobe::globe
