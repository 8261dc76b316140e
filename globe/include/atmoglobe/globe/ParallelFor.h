#pragma once
// fn(0) .. fn(n - 1) on up to one thread per core (the calling thread one of them), each index
// once, in no particular order; returns when all are done. `maxThreads` > 0 caps the threads. The
// one thread pool of the libraries' CPU work that splits into independent pieces (a network's
// radars read, prepared and packed; a crop's sweeps; a slice's rows; a regular grid's levels).
// `fn` must not throw. A call made from within `fn` (a nested loop: a network's radars each
// building their own empty-space grid) runs on its own thread, in order, instead of starting
// threads of its own (cores x cores threads otherwise).
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace atmoglobe::globe {

namespace detail {
inline thread_local bool insideParallelFor = false;
}

template <class Fn>
void parallelFor(std::size_t n, Fn fn, unsigned maxThreads = 0) {
  if (detail::insideParallelFor) {
    for (std::size_t k = 0; k < n; ++k) fn(k);
    return;
  }
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  if (maxThreads > 0) threads = std::min(threads, maxThreads);
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(n, 1)));
  std::atomic<std::size_t> next{0};
  // On one thread a nested loop may still use the cores.
  auto work = [&] {
    detail::insideParallelFor = threads > 1;
    for (std::size_t k = next++; k < n; k = next++) fn(k);
    detail::insideParallelFor = false;
  };
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < threads; ++w) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
}

}  // namespace atmoglobe::globe
