#pragma once
// TileImageLoader: produces composited tile images on worker threads, off the render thread.
//
// The render thread calls request() for every tile it would like to draw, each frame, then
// endFrame(). Tiles not yet decoded are queued by priority; workers ask every layer for the tile
// (ImageryLayer::tileImage), composite the answers and keep the result in a byte-budgeted LRU
// cache. All public member functions are thread-safe.
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "atmoglobe/globe/Image.h"
#include "atmoglobe/globe/ImageryLayer.h"
#include "atmoglobe/globe/LruCache.h"
#include "atmoglobe/globe/TileId.h"

namespace atmoglobe::globe {

struct TileImageLoaderOptions {
  std::size_t cacheBudgetBytes = 256u << 20;  ///< decoded composites kept (a 256x256 tile is 256 KiB)
  int workerThreads = 1;                      ///< >= 1
};

struct TileImageLoaderStats {
  std::uint64_t tilesDecoded = 0;  ///< composites produced
  double decodeSeconds = 0;        ///< worker wall time spent producing them (summed over workers)
  std::uint64_t cacheEvictions = 0;
  std::size_t cacheBytes = 0;
  std::uint64_t errors = 0;  ///< layer failures (one per layer and tile)
};

class TileImageLoader {
 public:
  /// `layers`: bottom first; each must be non-null.
  TileImageLoader(std::vector<std::shared_ptr<const ImageryLayer>> layers, TileImageLoaderOptions options);
  /// Drops the queue and joins the workers; waits only for the tiles being produced right now
  /// (at most one per worker).
  ~TileImageLoader();
  TileImageLoader(const TileImageLoader&) = delete;
  TileImageLoader& operator=(const TileImageLoader&) = delete;

  /// The composited 256x256 image for t, if already produced (marked recently used); else
  /// nullptr and t is queued (once) with `priority` (higher first; ties in request order;
  /// re-requesting updates the priority). The composite is always opaque: the bottom layer's
  /// RGB is taken as is (its alpha ignored), each layer above is alpha-blended over it
  /// (straight alpha). Pixels with no data in the bottom layer, or where the bottom layer had
  /// no image for t, are black. A layer that FAILED for t (corrupt/unreadable file) counts as
  /// having no data for t: the message is reported once through takeErrors() and the composite
  /// of the other layers is cached like any other, so the failure is not retried every frame
  /// (it is retried only after the tile has been evicted from the cache).
  std::shared_ptr<const ImageRGBA8> request(const TileId& t, double priority);

  /// Drops queued requests not re-requested since the last call (tiles the view no longer
  /// needs). Call once per frame after the requests. Tiles already being produced complete.
  void endFrame();

  bool idle() const;                      ///< nothing queued or in flight
  void waitIdle();                        ///< blocks until idle (headless rendering uses this)
  int maxLevel() const;                   ///< max over layers
  std::vector<std::string> takeErrors();  ///< messages of failed tiles since the last call
  TileImageLoaderStats stats() const;

 private:
  struct QueueKey {
    double priority;
    std::uint64_t sequence;
    TileId tile;
    bool operator<(const QueueKey& o) const {
      if (priority != o.priority) return priority > o.priority;  // higher first
      return sequence < o.sequence;
    }
  };
  struct Pending {
    std::set<QueueKey>::iterator position;
    std::uint64_t frame;
  };

  void workerLoop();
  std::shared_ptr<const ImageRGBA8> produce(const TileId& t, std::vector<std::string>& errors) const;

  std::vector<std::shared_ptr<const ImageryLayer>> layers_;
  mutable std::mutex mutex_;
  std::condition_variable workAvailable_;
  std::condition_variable becameIdle_;
  bool stopping_ = false;
  std::uint64_t frame_ = 0;
  std::uint64_t nextSequence_ = 0;
  std::set<QueueKey> queue_;
  std::unordered_map<TileId, Pending, TileIdHash> pending_;
  std::unordered_set<TileId, TileIdHash> inFlight_;
  LruCache<TileId, std::shared_ptr<const ImageRGBA8>, TileIdHash> cache_;
  std::vector<std::string> errors_;
  TileImageLoaderStats stats_;
  std::vector<std::thread> workers_;
};

}  // namespace atmoglobe::globe
