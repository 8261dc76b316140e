#pragma once
// fn(0) .. fn(n - 1) on up to one thread per core (the calling thread one of them), each index
// once, in no particular order; returns when all are done. For the engine's CPU work that splits
// into independent pieces (a network's radars read, prepared and packed). Internal to engine/.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace atmoglobe::engine {

template <class Fn>
void parallelFor(std::size_t n, Fn fn) {
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t k = next++; k < n; k = next++) fn(k);
  };
  const unsigned threads =
      std::max(1u, std::min<unsigned>(std::thread::hardware_concurrency(), static_cast<unsigned>(n)));
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < threads; ++w) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
}

}  // namespace atmoglobe::engine
