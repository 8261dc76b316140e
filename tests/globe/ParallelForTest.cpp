// The libraries' one thread pool (globe/ParallelFor.h): every index once, and a loop nested in
// another runs on the thread of its outer index instead of starting threads of its own.
#include <atmoglobe/globe/ParallelFor.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace {
using namespace atmoglobe;

TEST(ParallelFor, EveryIndexOnce) {
  for (std::size_t n : {0u, 1u, 7u, 1000u}) {
    std::vector<std::atomic<int>> hits(n);
    globe::parallelFor(n, [&](std::size_t k) { ++hits[k]; });
    for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(hits[k].load(), 1) << "index " << k << " of " << n;
  }
}

TEST(ParallelFor, ANestedLoopRunsOnTheThreadOfItsOuterIndex) {
  constexpr std::size_t kOuter = 6, kInner = 50;
  std::vector<std::atomic<int>> hits(kOuter * kInner);
  std::atomic<int> elsewhere{0};
  std::vector<std::thread::id> outerThread(kOuter);
  globe::parallelFor(kOuter, [&](std::size_t o) {
    outerThread[o] = std::this_thread::get_id();
    globe::parallelFor(kInner, [&](std::size_t i) {
      ++hits[o * kInner + i];
      if (std::this_thread::get_id() != outerThread[o]) ++elsewhere;
    });
  });
  for (std::size_t k = 0; k < hits.size(); ++k) EXPECT_EQ(hits[k].load(), 1) << "index " << k;
  EXPECT_EQ(elsewhere.load(), 0);
  // And after the outer loop a loop uses the pool again: more than one thread where the machine
  // has more than one core.
  std::vector<std::thread::id> ids(64);
  globe::parallelFor(ids.size(), [&](std::size_t k) {
    ids[k] = std::this_thread::get_id();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  });
  bool several = false;
  for (const auto& id : ids) several = several || id != ids.front();
  if (std::thread::hardware_concurrency() > 1) {
    EXPECT_TRUE(several);
  }
}

}  // namespace
