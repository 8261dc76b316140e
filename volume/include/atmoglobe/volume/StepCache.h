#pragma once
// A memory budget for the data of time steps and volumes: one least-recently-used cache, GL-free,
// shared by a scene's grid time steps and radar loops (engine::SceneRendererGL) and its
// background loader (engine::ScenePrefetcher). Entries are type-erased shared pointers with the
// bytes they hold (CPU arrays and, for GPU volumes, their textures: the caller says).
//
// Budget rule: after every put, the bytes held are at most the budget, unless the entries in
// use (their data held outside the cache too: the volumes shown) alone exceed it. Entries not
// in use are dropped least recently used first, and their owner reloads them when asked again.
// Dropped data are not destroyed inside put() (a worker thread may put, and a GPU volume must
// die on the GL thread): they wait in a list that releaseDropped() empties on the caller's
// thread; their bytes are no longer counted as held, but pendingBytes() says what waits.
//
// Shared parts: an entry may name parts it shares with other entries (a radar network's clusters
// that a later time step keeps as they were), each counted once however many entries hold it, and
// freed (no longer counted) when the last entry holding it leaves the cache.
//
// Thread-safe: every member locks one mutex.
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <condition_variable>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace atmoglobe::volume {

/// Physical memory of this machine (bytes; sysconf), 0 when unknown.
std::uint64_t physicalMemoryBytes();
/// The default budget: a quarter of physical memory (1 GiB when unknown). A quarter leaves room
/// for the rest of the process (imagery tiles, the frame, the driver) and for other programs.
std::uint64_t defaultMemoryBudgetBytes();
/// Peak resident set size of this process so far (getrusage ru_maxrss; bytes).
std::uint64_t peakResidentBytes();
/// Resident set size now (/proc/self/statm; bytes), 0 where unavailable.
std::uint64_t currentResidentBytes();

/// Bytes held by the arrays of a grid (values, heights, coordinates, level values).
std::uint64_t gridVolumeBytes(const GridVolume& grid);
/// Bytes held by the arrays of a polar render layout (values, azimuths).
std::uint64_t polarVolumeBytes(const PolarVolume& volume);

class StepCache {
 public:
  explicit StepCache(std::uint64_t budgetBytes = defaultMemoryBudgetBytes()) : budget_(budgetBytes) {}
  StepCache(const StepCache&) = delete;
  StepCache& operator=(const StepCache&) = delete;

  /// Changes the budget (bytes, > 0) and drops what no longer fits.
  void setBudget(std::uint64_t bytes);
  std::uint64_t budget() const;

  /// Something an entry holds that other entries may hold too: its identity (the object's
  /// address, alive while any entry holds it) and its bytes.
  struct SharedPart {
    const void* id = nullptr;
    std::uint64_t bytes = 0;
  };
  /// Adds `data` under `key` (replacing an entry of that key) as the most recently used, then
  /// drops least recently used entries not in use until the budget holds. `bytes`: what the entry
  /// holds besides `parts`, which count once over all the entries that hold them.
  void put(const std::string& key, std::shared_ptr<const void> data, std::uint64_t bytes,
           std::vector<SharedPart> parts = {});
  /// The entry's data (marked most recently used), or null (counted as a miss).
  template <class T>
  std::shared_ptr<const T> get(const std::string& key) {
    return std::static_pointer_cast<const T>(getErased(key));
  }
  bool contains(const std::string& key) const;
  /// Removes the entry (its data released by releaseDropped()).
  void erase(const std::string& key);
  /// Removes every entry whose key starts with `prefix` (a layer whose data changed).
  void erasePrefix(const std::string& prefix);
  /// Whether `bytes` more would fit after dropping every entry not in use: a background loader
  /// asks before loading ahead, so what it loads does not push out what is shown.
  bool fitsBesidesInUse(std::uint64_t bytes) const;
  /// Drops entries not in use until the budget holds: for an owner that has just let go of data
  /// it put (the step it showed before), whose entries put() could not drop while held.
  void enforceBudget();
  /// Destroys the dropped data on the calling thread (the GL thread, for GPU volumes).
  void releaseDropped();
  /// A background loader says it is loading `key` (so the thread that shows it waits for it
  /// instead of reading it twice); put() or abandonLoading() ends that.
  void markLoading(const std::string& key);
  void abandonLoading(const std::string& key);
  /// Blocks while `key` is being loaded by a background loader.
  void waitWhileLoading(const std::string& key);

  struct Stats {
    std::uint64_t budgetBytes = 0;
    std::uint64_t heldBytes = 0;      ///< bytes of the entries now
    std::uint64_t peakHeldBytes = 0;  ///< largest heldBytes after any put
    std::uint64_t inUseBytes = 0;     ///< of heldBytes, entries whose data are also held outside
    std::uint64_t pendingBytes = 0;   ///< dropped, waiting for releaseDropped()
    std::size_t entries = 0;
    std::uint64_t hits = 0, misses = 0, drops = 0;
  };
  Stats stats() const;

 private:
  std::shared_ptr<const void> getErased(const std::string& key);
  void enforceLocked();
  struct Entry {
    std::string key;
    std::shared_ptr<const void> data;
    std::uint64_t bytes = 0;
    std::vector<SharedPart> parts;
  };
  /// Takes `e` out of the count (its bytes and the parts no other entry holds) into dropped_.
  void dropLocked(Entry&& e);
  /// What the entries for which `counted` holds take: their bytes and their parts, each once.
  template <class Counted>
  std::uint64_t bytesOfLocked(Counted counted) const;
  struct PartCount {
    std::size_t entries = 0;
    std::uint64_t bytes = 0;
  };
  std::unordered_map<const void*, PartCount> parts_;
  mutable std::mutex mutex_;
  std::condition_variable loaded_;
  std::vector<std::string> loading_;
  std::uint64_t budget_;
  std::list<Entry> lru_;  ///< most recently used first
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
  std::vector<Entry> dropped_;
  std::uint64_t held_ = 0, peak_ = 0, pending_ = 0, hits_ = 0, misses_ = 0, drops_ = 0;
};

}  // namespace atmoglobe::volume
