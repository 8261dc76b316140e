#pragma once
// Geographic imagery pyramids: building one from an equirectangular world image, and reading it.
//
// On disk: DIR/pyramid.json (metadata) and DIR/{z}/{x}/{y}.png for every tile of levels
// 0..maxLevel of the geographic tiling in TileId.h (256 x 256 px tiles, row 0 = north edge).
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "atmoglobe/globe/Image.h"
#include "atmoglobe/globe/ImageryLayer.h"
#include "atmoglobe/globe/LruCache.h"
#include "atmoglobe/globe/Result.h"
#include "atmoglobe/globe/TileId.h"

namespace atmoglobe::globe {

inline constexpr int kTileSizePx = 256;

/// Deepest level buildPyramid accepts: level 10 is 2048 x 1024 tiles (2.8 M files in all), at
/// ~0.0007 deg/px far finer than any source image the decoder accepts (kMaxImagePixels gives a
/// natural level of at most 6); the cap keeps a typo from starting a build that never ends.
inline constexpr int kMaxPyramidLevel = 10;

struct PyramidBuildOptions {
  /// -1: the smallest level whose resolution (2^(level+1) * 256 px around the equator) is at
  /// least the source image's width; otherwise 0..kMaxPyramidLevel.
  int maxLevel = -1;
  /// Optional: called after each tile is written with (tilesWritten, tilesTotal); returning false
  /// cancels the build (an error is returned and nothing is left behind).
  std::function<bool(std::uint64_t, std::uint64_t)> progress;
};

struct PyramidInfo {
  int maxLevel = 0;
  int tileSizePx = kTileSizePx;
  std::string format = "png";  ///< tile file format (extension)
  std::string source;          ///< file name of the image the pyramid was built from
};

/// Number of tiles in levels 0..maxLevel: sum of 2 * 4^z.
std::uint64_t pyramidTileCount(int maxLevel);

/// The level buildPyramid chooses for a source `widthPx` wide when options.maxLevel is -1.
int naturalPyramidLevel(int widthPx);

/// From an equirectangular whole-world image (-180..180 x 90..-90; any size, checked:
/// width == 2*height within 1 px, else error) writes DIR/pyramid.json and DIR/{z}/{x}/{y}.png
/// for every tile of levels 0..maxLevel. Level maxLevel resamples the source (bilinear, pixel
/// centres, clamped at the poles and at +-180 deg); coarser levels are 2x2 box-filtered from
/// the level below (rounded to nearest). Atomic: builds into DIR.tmp-XXXXXX then renames to DIR
/// (replacing an old pyramid only after success); on failure nothing new is left behind.
/// Errors begin with the offending file or directory: "<path>: <reason>".
Status buildPyramid(const std::string& imagePath, const std::string& outDir, const PyramidBuildOptions& options,
                    PyramidInfo* infoOut = nullptr);

/// Reads and checks DIR/pyramid.json.
Result<PyramidInfo> readPyramidInfo(const std::string& dir);

/// A pyramid written by buildPyramid, as an imagery layer.
class GeographicPyramidLayer : public ImageryLayer {
 public:
  /// Opens DIR (reads pyramid.json; tiles are read lazily).
  static Result<std::shared_ptr<GeographicPyramidLayer>> open(const std::string& dir);

  /// Levels 0..maxLevel: the stored tile (std::nullopt if its file is missing; error if it is
  /// unreadable, corrupt or not 256x256). Deeper tiles: the crop of the ancestor at maxLevel,
  /// upsampled bilinearly (sampleBilinear, clamped at the ancestor's edges: within half a source
  /// pixel of an ancestor edge, pixels repeat the edge instead of blending with the neighbour
  /// tile). Decoded ancestors are kept in a small internal cache (32 MiB).
  Result<std::optional<ImageRGBA8>> tileImage(const TileId& t) const override;
  int maxLevel() const override { return info_.maxLevel; }
  std::string description() const override;

  const PyramidInfo& info() const { return info_; }
  /// Path of tile t's file (whether it exists or not).
  std::string tilePath(const TileId& t) const;

 private:
  GeographicPyramidLayer(std::string dir, PyramidInfo info) : dir_(std::move(dir)), info_(std::move(info)) {}
  /// The decoded stored tile; nullptr if its file does not exist.
  Result<std::shared_ptr<const ImageRGBA8>> loadStoredTile(const TileId& t) const;

  std::string dir_;
  PyramidInfo info_;
  mutable std::mutex mutex_;
  mutable LruCache<TileId, std::shared_ptr<const ImageRGBA8>, TileIdHash> ancestors_{32u << 20};
};

}  // namespace atmoglobe::globe
