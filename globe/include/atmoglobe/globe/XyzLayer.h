#pragma once
// XyzMercatorLayer: a standard "slippy map" tile directory DIR/{z}/{x}/{y}.png|.jpg|.jpeg in
// web mercator (EPSG:3857; zoom z has 2^z x 2^z tiles, x from -180 deg eastwards, y from the
// north at +85.0511287798 deg), reprojected on the fly into geographic tiles.
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "atmoglobe/globe/ImageryLayer.h"
#include "atmoglobe/globe/LruCache.h"

namespace atmoglobe::globe {

/// Latitude (deg) of the web-mercator square's north edge: atan(sinh(pi)).
inline constexpr double kWebMercatorMaxLatDeg = 85.0511287798066;

/// Deepest zoom directory XyzMercatorLayer looks for.
inline constexpr int kMaxMercatorZoom = 24;

/// Mercator tile address (zoom, column, row from the north).
struct MercatorTileId {
  int zoom = 0;
  std::uint32_t x = 0;
  std::uint32_t y = 0;
  friend bool operator==(const MercatorTileId&, const MercatorTileId&) = default;
};

struct MercatorTileIdHash {
  std::size_t operator()(const MercatorTileId& t) const { return TileIdHash{}(TileId{t.zoom, t.x, t.y}); }
};

/// Web-mercator normalised coordinates of (lonDeg, latDeg): x in [0,1] from -180 eastwards,
/// y in [0,1] from the north edge (85.05 deg) southwards (spherical mercator formulas,
/// EPSG:3857); y is outside [0,1] beyond +-85.05 deg.
glm::dvec2 webMercatorNormalized(double lonDeg, double latDeg);
/// Inverse of webMercatorNormalized: (lonDeg, latDeg).
glm::dvec2 webMercatorNormalizedToLonLat(double x, double y);

class XyzMercatorLayer : public ImageryLayer {
 public:
  /// Opens DIR: finds the zoom levels present (numeric subdirectories 0..kMaxMercatorZoom that
  /// contain at least one numeric column directory). Error if there are none.
  /// `cacheBudgetBytes`: decoded mercator tiles kept in memory.
  static Result<std::shared_ptr<XyzMercatorLayer>> open(const std::string& dir,
                                                        std::size_t cacheBudgetBytes = 64u << 20);

  /// Reprojects into geographic tile t. For each output pixel centre (lon, lat): alpha 0 if
  /// |lat| > kWebMercatorMaxLatDeg; otherwise sampled from mercator zoom zm, where zm = the
  /// smallest available zoom >= t.level + 1 (or the deepest available one if none is that deep).
  /// t.level + 1 matches the geographic tile's east-west pixel size at every latitude (both
  /// shrink with cos(lat)); north-south the mercator pixels are then finer still. If the tile at
  /// zm is missing, ancestors (zm-1, zm-2, ...) are used; if none exists, alpha 0. Sampling is
  /// bilinear within one mercator tile, clamped at its edges. If zm would be more than 3 zooms
  /// deeper than t.level + 1 (no overview tiles for this coarse level: >64x too many tiles to
  /// read) the result is std::nullopt. std::nullopt also when no pixel got data.
  Result<std::optional<ImageRGBA8>> tileImage(const TileId& t) const override;
  /// Geographic level matching the deepest zoom: deepest zoom - 1 (at least 0).
  int maxLevel() const override;
  std::string description() const override;

  const std::vector<int>& zoomLevels() const { return zooms_; }
  /// Path of an existing file for mercator tile m (png, jpg or jpeg), or "" if none.
  std::string findTileFile(const MercatorTileId& m) const;

 private:
  XyzMercatorLayer(std::string dir, std::vector<int> zooms, std::size_t cacheBudgetBytes)
      : dir_(std::move(dir)), zooms_(std::move(zooms)), cache_(cacheBudgetBytes) {}
  /// Decoded tile (nullptr if the file does not exist), through the cache.
  Result<std::shared_ptr<const ImageRGBA8>> loadTile(const MercatorTileId& m) const;

  std::string dir_;
  std::vector<int> zooms_;  // ascending
  mutable std::mutex mutex_;
  mutable LruCache<MercatorTileId, std::shared_ptr<const ImageRGBA8>, MercatorTileIdHash> cache_;
};

}  // namespace atmoglobe::globe
