// The memory budget of time steps and volumes (StepCache.h).
#include <atmoglobe/volume/StepCache.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace atmoglobe::volume {

std::uint64_t physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || pageSize <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize);
}

std::uint64_t defaultMemoryBudgetBytes() {
  const std::uint64_t ram = physicalMemoryBytes();
  return ram > 0 ? ram / 4 : std::uint64_t{1} << 30;
}

std::uint64_t peakResidentBytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // Linux: kilobytes
}

std::uint64_t currentResidentBytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long sizePages = 0, residentPages = 0;
  const int n = std::fscanf(f, "%lu %lu", &sizePages, &residentPages);
  std::fclose(f);
  const long pageSize = sysconf(_SC_PAGESIZE);
  return n == 2 && pageSize > 0 ? static_cast<std::uint64_t>(residentPages) * static_cast<std::uint64_t>(pageSize) : 0;
}

std::uint64_t gridVolumeBytes(const GridVolume& g) {
  return (g.values.capacity() + g.heightAboveEllipsoidMeters.capacity()) * sizeof(float) +
         (g.lonDeg.capacity() + g.latDeg.capacity() + g.levelValues.capacity() + g.rowFirstLonDeg.capacity() +
          g.rowSpacingDeg.capacity()) *
             sizeof(double) +
         g.rowLengthPoints.capacity() * sizeof(std::size_t);
}

std::uint64_t polarVolumeBytes(const PolarVolume& v) {
  std::uint64_t bytes = v.values.capacity() * sizeof(float);
  for (const PolarSweepLayout& s : v.sweeps) bytes += s.azimuthDeg.capacity() * sizeof(float) + sizeof s;
  return bytes;
}

void StepCache::setBudget(std::uint64_t bytes) {
  std::lock_guard lock(mutex_);
  budget_ = std::max<std::uint64_t>(bytes, 1);
  enforceLocked();
}

void StepCache::enforceBudget() {
  std::lock_guard lock(mutex_);
  enforceLocked();
}

std::uint64_t StepCache::budget() const {
  std::lock_guard lock(mutex_);
  return budget_;
}

void StepCache::dropLocked(Entry&& e) {
  std::uint64_t freed = e.bytes;
  for (const SharedPart& p : e.parts) {
    const auto it = parts_.find(p.id);
    if (it == parts_.end() || --it->second.entries > 0) continue;
    freed += it->second.bytes;
    parts_.erase(it);
  }
  held_ -= freed;
  pending_ += freed;
  dropped_.push_back(std::move(e));
}

template <class Counted>
std::uint64_t StepCache::bytesOfLocked(Counted counted) const {
  std::uint64_t bytes = 0;
  std::vector<const void*> seen;
  for (const Entry& e : lru_) {
    if (!counted(e)) continue;
    bytes += e.bytes;
    for (const SharedPart& p : e.parts)
      if (std::find(seen.begin(), seen.end(), p.id) == seen.end()) {
        seen.push_back(p.id);
        bytes += p.bytes;
      }
  }
  return bytes;
}

void StepCache::put(const std::string& key, std::shared_ptr<const void> data, std::uint64_t bytes,
                    std::vector<SharedPart> parts) {
  std::lock_guard lock(mutex_);
  // The new entry's parts first, so that one the replaced entry shares is not freed meanwhile.
  for (const SharedPart& p : parts) {
    PartCount& count = parts_[p.id];
    if (count.entries++ == 0) {
      count.bytes = p.bytes;
      held_ += p.bytes;
    }
  }
  if (auto it = index_.find(key); it != index_.end()) {
    dropLocked(std::move(*it->second));
    lru_.erase(it->second);
    index_.erase(it);
  }
  lru_.push_front(Entry{key, std::move(data), bytes, std::move(parts)});
  index_[key] = lru_.begin();
  held_ += bytes;
  enforceLocked();
  peak_ = std::max(peak_, held_);
  if (const auto it = std::find(loading_.begin(), loading_.end(), key); it != loading_.end()) {
    loading_.erase(it);
    loaded_.notify_all();
  }
}

void StepCache::markLoading(const std::string& key) {
  std::lock_guard lock(mutex_);
  loading_.push_back(key);
}

void StepCache::abandonLoading(const std::string& key) {
  std::lock_guard lock(mutex_);
  if (const auto it = std::find(loading_.begin(), loading_.end(), key); it != loading_.end()) loading_.erase(it);
  loaded_.notify_all();
}

void StepCache::waitWhileLoading(const std::string& key) {
  std::unique_lock lock(mutex_);
  loaded_.wait(lock, [&] { return std::find(loading_.begin(), loading_.end(), key) == loading_.end(); });
}

void StepCache::enforceLocked() {
  // Oldest first; an entry in use (its data held outside the cache too) stays.
  for (auto it = lru_.end(); held_ > budget_ && it != lru_.begin();) {
    --it;
    if (it->data.use_count() > 1) continue;
    ++drops_;
    index_.erase(it->key);
    dropLocked(std::move(*it));
    it = lru_.erase(it);
  }
}

std::shared_ptr<const void> StepCache::getErased(const std::string& key) {
  std::lock_guard lock(mutex_);
  const auto it = index_.find(key);
  if (it == index_.end()) {
    ++misses_;
    return nullptr;
  }
  ++hits_;
  lru_.splice(lru_.begin(), lru_, it->second);
  return it->second->data;
}

bool StepCache::contains(const std::string& key) const {
  std::lock_guard lock(mutex_);
  return index_.count(key) > 0;
}

void StepCache::erase(const std::string& key) {
  std::lock_guard lock(mutex_);
  const auto it = index_.find(key);
  if (it == index_.end()) return;
  dropLocked(std::move(*it->second));
  lru_.erase(it->second);
  index_.erase(it);
}

void StepCache::erasePrefix(const std::string& prefix) {
  std::lock_guard lock(mutex_);
  for (auto it = lru_.begin(); it != lru_.end();) {
    if (it->key.compare(0, prefix.size(), prefix) != 0) {
      ++it;
      continue;
    }
    index_.erase(it->key);
    dropLocked(std::move(*it));
    it = lru_.erase(it);
  }
}

bool StepCache::fitsBesidesInUse(std::uint64_t bytes) const {
  std::lock_guard lock(mutex_);
  const std::uint64_t inUse = bytesOfLocked([](const Entry& e) { return e.data.use_count() > 1; });
  return inUse + bytes <= budget_;
}

void StepCache::releaseDropped() {
  std::vector<Entry> dying;
  {
    std::lock_guard lock(mutex_);
    dying.swap(dropped_);
    pending_ = 0;
  }
  if (dying.empty()) return;
  dying.clear();  // destroyed here, outside the lock, on the caller's thread
#ifdef __GLIBC__
  // glibc raises its mmap threshold after freeing a large block, so later steps come from the
  // heap, and freed steps stay in the process (RSS grew ~2.4 MB a step over 300 steps of a
  // 120 x 120 x 20 grid without this): give free heap pages back to the system.
  malloc_trim(0);
#endif
}

StepCache::Stats StepCache::stats() const {
  std::lock_guard lock(mutex_);
  Stats s;
  s.budgetBytes = budget_;
  s.heldBytes = held_;
  s.peakHeldBytes = peak_;
  s.inUseBytes = bytesOfLocked([](const Entry& e) { return e.data.use_count() > 1; });
  s.pendingBytes = pending_;
  s.entries = lru_.size();
  s.hits = hits_;
  s.misses = misses_;
  s.drops = drops_;
  return s;
}

}  // namespace atmoglobe::volume
