#include "atmoglobe/globe/TileImageLoader.h"

#include <algorithm>
#include <chrono>

#include "atmoglobe/globe/ImageryPyramid.h"

namespace atmoglobe::globe {

TileImageLoader::TileImageLoader(std::vector<std::shared_ptr<const ImageryLayer>> layers,
                                 TileImageLoaderOptions options)
    : layers_(std::move(layers)), cache_(options.cacheBudgetBytes) {
  assert(options.workerThreads >= 1);
  for (const auto& layer : layers_) {
    assert(layer);
    (void)layer;
  }
  for (int i = 0; i < std::max(options.workerThreads, 1); ++i) workers_.emplace_back([this] { workerLoop(); });
}

TileImageLoader::~TileImageLoader() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    queue_.clear();
    pending_.clear();
  }
  workAvailable_.notify_all();
  for (std::thread& w : workers_) w.join();
}

std::shared_ptr<const ImageRGBA8> TileImageLoader::request(const TileId& t, double priority) {
  assert(isValid(t));
  std::lock_guard lock(mutex_);
  if (auto* cached = cache_.find(t)) return *cached;
  if (inFlight_.count(t)) return nullptr;
  auto it = pending_.find(t);
  if (it != pending_.end()) {
    it->second.frame = frame_;
    if (it->second.position->priority != priority) {
      QueueKey key = *it->second.position;
      key.priority = priority;
      queue_.erase(it->second.position);
      it->second.position = queue_.insert(key).first;
    }
    return nullptr;
  }
  auto position = queue_.insert(QueueKey{priority, nextSequence_++, t}).first;
  pending_.emplace(t, Pending{position, frame_});
  workAvailable_.notify_one();
  return nullptr;
}

void TileImageLoader::endFrame() {
  std::lock_guard lock(mutex_);
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (it->second.frame != frame_) {
      queue_.erase(it->second.position);
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  ++frame_;
  if (queue_.empty() && inFlight_.empty()) becameIdle_.notify_all();
}

bool TileImageLoader::idle() const {
  std::lock_guard lock(mutex_);
  return queue_.empty() && inFlight_.empty();
}

void TileImageLoader::waitIdle() {
  std::unique_lock lock(mutex_);
  becameIdle_.wait(lock, [this] { return queue_.empty() && inFlight_.empty(); });
}

int TileImageLoader::maxLevel() const {
  int level = 0;
  for (const auto& layer : layers_) level = std::max(level, layer->maxLevel());
  return level;
}

std::vector<std::string> TileImageLoader::takeErrors() {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  out.swap(errors_);
  return out;
}

TileImageLoaderStats TileImageLoader::stats() const {
  std::lock_guard lock(mutex_);
  TileImageLoaderStats s = stats_;
  s.cacheEvictions = cache_.evictions();
  s.cacheBytes = cache_.bytes();
  return s;
}

void TileImageLoader::workerLoop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    workAvailable_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_) return;
    const TileId t = queue_.begin()->tile;
    queue_.erase(queue_.begin());
    pending_.erase(t);
    inFlight_.insert(t);
    lock.unlock();

    const auto start = std::chrono::steady_clock::now();
    std::vector<std::string> errors;
    std::shared_ptr<const ImageRGBA8> image = produce(t, errors);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    lock.lock();
    cache_.insert(t, image, image->byteSize());
    inFlight_.erase(t);
    ++stats_.tilesDecoded;
    stats_.decodeSeconds += seconds;
    stats_.errors += errors.size();
    for (std::string& e : errors) errors_.push_back(std::move(e));
    if (queue_.empty() && inFlight_.empty()) becameIdle_.notify_all();
  }
}

std::shared_ptr<const ImageRGBA8> TileImageLoader::produce(const TileId& t, std::vector<std::string>& errors) const {
  ImageRGBA8 out = ImageRGBA8::filled(kTileSizePx, kTileSizePx, {0, 0, 0, 255});
  bool bottom = true;
  for (const auto& layer : layers_) {
    Result<std::optional<ImageRGBA8>> image = layer->tileImage(t);
    const bool isBottom = bottom;
    bottom = false;
    if (!image) {
      errors.push_back(image.error());
      continue;
    }
    if (!image->has_value()) continue;
    const ImageRGBA8& src = **image;
    if (src.width != kTileSizePx || src.height != kTileSizePx) {
      errors.push_back(layer->description() + ": tile " + std::to_string(t.level) + "/" + std::to_string(t.x) + "/" +
                       std::to_string(t.y) + " is " + std::to_string(src.width) + " x " + std::to_string(src.height) +
                       " px, expected 256 x 256");
      continue;
    }
    std::uint8_t* d = out.pixels.data();
    const std::uint8_t* s = src.pixels.data();
    const std::size_t n = out.pixels.size();
    if (isBottom) {
      // The bottom layer's RGB as is; its alpha is ignored (the globe surface is opaque).
      for (std::size_t i = 0; i < n; i += 4) {
        d[i] = s[i];
        d[i + 1] = s[i + 1];
        d[i + 2] = s[i + 2];
      }
      continue;
    }
    // Straight-alpha "over" onto an opaque destination, rounded to nearest.
    for (std::size_t i = 0; i < n; i += 4) {
      const unsigned a = s[i + 3];
      if (a == 0) continue;
      for (std::size_t c = 0; c < 3; ++c) {
        d[i + c] = static_cast<std::uint8_t>((s[i + c] * a + d[i + c] * (255u - a) + 127u) / 255u);
      }
    }
  }
  return std::make_shared<const ImageRGBA8>(std::move(out));
}

}  // namespace atmoglobe::globe
