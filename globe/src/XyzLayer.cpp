#include "atmoglobe/globe/XyzLayer.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <unordered_map>

#include "atmoglobe/globe/Angles.h"
#include "atmoglobe/globe/ImageryPyramid.h"

namespace atmoglobe::globe {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMissingTileBytes = 64;  // what a "no such file" cache entry is charged

/// Parses a directory name made only of decimal digits; -1 otherwise.
long parseIndex(const std::string& name) {
  if (name.empty() || name.size() > 9) return -1;
  long value = -1;
  auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), value);
  if (ec != std::errc() || end != name.data() + name.size()) return -1;
  return value;
}

bool hasNumericSubdirectory(const fs::path& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (parseIndex(it->path().filename().string()) >= 0 && it->is_directory(ec)) return true;
  }
  return false;
}

}  // namespace

glm::dvec2 webMercatorNormalized(double lonDeg, double latDeg) {
  const double phi = degreesToRadians(latDeg);
  return {(lonDeg + 180.0) / 360.0, 0.5 - std::log(std::tan(kPi / 4.0 + phi / 2.0)) / (2.0 * kPi)};
}

glm::dvec2 webMercatorNormalizedToLonLat(double x, double y) {
  return {x * 360.0 - 180.0, radiansToDegrees(std::atan(std::sinh(kPi * (1.0 - 2.0 * y))))};
}

Result<std::shared_ptr<XyzMercatorLayer>> XyzMercatorLayer::open(const std::string& dir, std::size_t cacheBudgetBytes) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return makeError(dir + ": not a directory");
  std::vector<int> zooms;
  fs::directory_iterator it(dir, ec);
  if (ec) return makeError(dir + ": cannot list (" + ec.message() + ")");
  for (fs::directory_iterator end; it != end; it.increment(ec)) {
    if (ec) return makeError(dir + ": cannot list (" + ec.message() + ")");
    const long z = parseIndex(it->path().filename().string());
    if (z < 0 || z > kMaxMercatorZoom) continue;
    if (hasNumericSubdirectory(it->path())) zooms.push_back(static_cast<int>(z));
  }
  if (zooms.empty()) {
    return makeError(dir + ": no zoom directories 0.." + std::to_string(kMaxMercatorZoom) +
                     " holding tile columns (expected DIR/{z}/{x}/{y}.png or .jpg)");
  }
  std::sort(zooms.begin(), zooms.end());
  return std::shared_ptr<XyzMercatorLayer>(new XyzMercatorLayer(dir, std::move(zooms), cacheBudgetBytes));
}

int XyzMercatorLayer::maxLevel() const { return std::max(zooms_.back() - 1, 0); }

std::string XyzMercatorLayer::description() const {
  return "web-mercator XYZ tiles " + dir_ + " (zooms " + std::to_string(zooms_.front()) + ".." +
         std::to_string(zooms_.back()) + ")";
}

std::string XyzMercatorLayer::findTileFile(const MercatorTileId& m) const {
  const fs::path base = fs::path(dir_) / std::to_string(m.zoom) / std::to_string(m.x);
  for (const char* ext : {".png", ".jpg", ".jpeg"}) {
    const fs::path p = base / (std::to_string(m.y) + ext);
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  return {};
}

Result<std::shared_ptr<const ImageRGBA8>> XyzMercatorLayer::loadTile(const MercatorTileId& m) const {
  {
    std::lock_guard lock(mutex_);
    if (auto* cached = cache_.find(m)) return *cached;
  }
  // Decoded outside the lock so workers decode in parallel; a duplicate decode is harmless.
  std::shared_ptr<const ImageRGBA8> image;
  const std::string path = findTileFile(m);
  if (!path.empty()) {
    Result<ImageRGBA8> decoded = decodeImageFile(path);
    if (!decoded) return decoded.forwardError();
    image = std::make_shared<const ImageRGBA8>(std::move(*decoded));
  }
  std::lock_guard lock(mutex_);
  cache_.insert(m, image, image ? image->byteSize() : kMissingTileBytes);
  return image;
}

Result<std::optional<ImageRGBA8>> XyzMercatorLayer::tileImage(const TileId& t) const {
  assert(isValid(t));
  const int wantedZoom = t.level + 1;
  auto atLeast = std::lower_bound(zooms_.begin(), zooms_.end(), wantedZoom);
  const int zm = atLeast != zooms_.end() ? *atLeast : zooms_.back();
  if (zm > wantedZoom + 3) return std::optional<ImageRGBA8>{};
  // Zooms to try for each pixel: zm, then the available coarser ones (ancestor fallback).
  std::vector<int> tryZooms;
  for (auto it = zooms_.rbegin(); it != zooms_.rend(); ++it) {
    if (*it <= zm) tryZooms.push_back(*it);
  }

  std::unordered_map<MercatorTileId, std::shared_ptr<const ImageRGBA8>, MercatorTileIdHash> local;
  ImageRGBA8 out = ImageRGBA8::filled(kTileSizePx, kTileSizePx, {0, 0, 0, 0});
  const GeoRectangle r = tileRectangle(t);
  const double sizeDeg = r.eastDeg - r.westDeg;
  bool anyData = false;
  MercatorTileId lastKey{-1, 0, 0};
  const ImageRGBA8* lastImage = nullptr;
  for (int j = 0; j < kTileSizePx; ++j) {
    const double latDeg = r.northDeg - (j + 0.5) * sizeDeg / kTileSizePx;
    if (std::abs(latDeg) > kWebMercatorMaxLatDeg) continue;
    const double my = webMercatorNormalized(0.0, latDeg).y;
    for (int i = 0; i < kTileSizePx; ++i) {
      const double lonDeg = r.westDeg + (i + 0.5) * sizeDeg / kTileSizePx;
      const double mx = (lonDeg + 180.0) / 360.0;
      for (int z : tryZooms) {
        const double n = std::ldexp(1.0, z);
        const double maxIndex = n - 1.0;
        const double fx = std::clamp(std::floor(mx * n), 0.0, maxIndex);
        const double fy = std::clamp(std::floor(my * n), 0.0, maxIndex);
        const MercatorTileId m{z, static_cast<std::uint32_t>(fx), static_cast<std::uint32_t>(fy)};
        if (!(m == lastKey)) {  // neighbouring pixels mostly share a tile: skip the hash lookup
          auto found = local.find(m);
          if (found == local.end()) {
            Result<std::shared_ptr<const ImageRGBA8>> loaded = loadTile(m);
            if (!loaded) return loaded.forwardError();
            found = local.emplace(m, *loaded).first;
          }
          lastKey = m;
          lastImage = found->second.get();
        }
        if (!lastImage) continue;  // missing at this zoom: try the ancestor
        out.set(i, j, sampleBilinear(*lastImage, mx * n - fx, my * n - fy));
        anyData = true;
        break;
      }
    }
  }
  if (!anyData) return std::optional<ImageRGBA8>{};
  return std::optional<ImageRGBA8>{std::move(out)};
}

}  // namespace atmoglobe::globe
