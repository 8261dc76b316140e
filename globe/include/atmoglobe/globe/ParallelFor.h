#pragma once
// fn(0) .. fn(n - 1) on up to one thread per core (the calling thread one of them), each index
// once, in no particular order; returns when all are done. `maxThreads` > 0 caps the threads. The
// one thread pool of the libraries' CPU work that splits into independent pieces (a network's
// radars read, prepared and packed; a crop's sweeps; a slice's rows; a regular grid's levels).
// `fn` must not throw.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace atmoglobe::globe {

template <class Fn>
void parallelFor(std::size_t n, Fn fn, unsigned maxThreads = 0) {
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t k = next++; k < n; k = next++) fn(k);
  };
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  if (maxThreads > 0) threads = std::min(threads, maxThreads);
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(n, 1)));
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < threads; ++w) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
}

}  // namespace atmoglobe::globe
