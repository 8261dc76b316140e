#pragma once
// ImageryLayer: one source of surface imagery, delivered per geographic (EPSG:4326) tile.
#include <optional>
#include <string>

#include "atmoglobe/globe/Image.h"
#include "atmoglobe/globe/Result.h"
#include "atmoglobe/globe/TileId.h"

namespace atmoglobe::globe {

/// One source of imagery. Thread-safe: tileImage may be called from several worker threads.
class ImageryLayer {
 public:
  virtual ~ImageryLayer() = default;

  /// 256x256 RGBA image covering geographic tile t's rectangle exactly (row 0 = north edge,
  /// column 0 = west edge), resampled from this layer's best data at or above t's resolution;
  /// alpha 0 (and RGB 0) where the layer has no data. std::nullopt if the layer has no data at
  /// all for t. Error for corrupt/unreadable files (the message names the file).
  virtual Result<std::optional<ImageRGBA8>> tileImage(const TileId& t) const = 0;

  /// The geographic level at which this layer's data is fully resolved (refining deeper gives
  /// no new detail).
  virtual int maxLevel() const = 0;

  /// One line for humans: kind of layer and where it reads from.
  virtual std::string description() const = 0;
};

}  // namespace atmoglobe::globe
