#include <atmoglobe/io/PageAllocator.h>

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace atmoglobe::io {

namespace {
#if defined(__linux__)
#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23  // Linux 5.14 uapi value; older kernels answer EINVAL
#endif
std::size_t pageBytes() {
  static const std::size_t page = [] {
    const long p = sysconf(_SC_PAGESIZE);
    return p > 0 ? static_cast<std::size_t>(p) : std::size_t{4096};
  }();
  return page;
}
#endif
}  // namespace

void populatePages(void* data, std::size_t bytes, std::size_t minBytes) {
#if defined(__linux__)
  if (data == nullptr || bytes < minBytes) return;
  const std::size_t page = pageBytes();
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + page - 1) & ~(page - 1);  // whole pages only: the
  const std::uintptr_t last = (begin + bytes) & ~(page - 1);      // partial ones are shared
  if (last <= first) return;
  (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_POPULATE_WRITE);
#else
  (void)data;
  (void)bytes;
  (void)minBytes;
#endif
}

void assignPopulated(std::vector<float>& values, std::size_t n, float fill) {
  if (n > values.capacity()) {
    std::vector<float> fresh;
    fresh.reserve(n);
    populatePages(fresh.data(), n * sizeof(float));
    values = std::move(fresh);
  }
  values.assign(n, fill);
}

}  // namespace atmoglobe::io
