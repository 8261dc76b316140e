#include "atmoglobe/globe/ImageryPyramid.h"

#include "atmoglobe/globe/AtomicFile.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace atmoglobe::globe {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPyramidKind = "atmoglobe-geographic-pyramid";
constexpr int kPyramidVersion = 1;

/// `dir` without a trailing separator, lexically normalised ("out/" -> "out").
fs::path normalizedDir(const std::string& dir) {
  fs::path p = fs::path(dir).lexically_normal();
  if (p.has_parent_path() && p.filename().empty()) p = p.parent_path();
  return p;
}

std::string tileRelativePath(const TileId& t, const std::string& extension) {
  return std::to_string(t.level) + "/" + std::to_string(t.x) + "/" + std::to_string(t.y) + "." + extension;
}

class PyramidWriter {
 public:
  PyramidWriter(const ImageRGBA8& source, fs::path root, int maxLevel, const PyramidBuildOptions& options)
      : source_(source), root_(std::move(root)), maxLevel_(maxLevel), options_(options),
        total_(pyramidTileCount(maxLevel)) {}

  /// Produces tile t (and, depth first, all its descendants down to maxLevel) into `out`.
  Status build(const TileId& t, ImageRGBA8& out) {
    if (t.level == maxLevel_) {
      resampleSource(t, out);
    } else {
      out = ImageRGBA8::filled(kTileSizePx, kTileSizePx, {0, 0, 0, 255});
      ImageRGBA8 child;
      for (int i = 0; i < 4; ++i) {
        Status s = build(childTile(t, i), child);
        if (!s) return s;
        boxFilterInto(child, (i & 1) * (kTileSizePx / 2), (i >> 1) * (kTileSizePx / 2), out);
      }
    }
    const fs::path dir = root_ / std::to_string(t.level) / std::to_string(t.x);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return makeError(dir.string() + ": cannot create directory (" + ec.message() + ")");
    const fs::path file = dir / (std::to_string(t.y) + ".png");
    Result<std::vector<std::uint8_t>> png = encodePng(out, file.string());
    if (!png) return png.forwardError();
    Status written = writeFileInStagedDirectory(
        file.string(), std::string_view(reinterpret_cast<const char*>(png->data()), png->size()));
    if (!written) return written;
    ++written_;
    if (options_.progress && !options_.progress(written_, total_)) {
      return makeError(root_.string() + ": build cancelled after " + std::to_string(written_) + " of " +
                       std::to_string(total_) + " tiles");
    }
    return Ok{};
  }

 private:
  /// Bilinear resampling of the equirectangular source at each output pixel centre.
  void resampleSource(const TileId& t, ImageRGBA8& out) const {
    out = ImageRGBA8::filled(kTileSizePx, kTileSizePx, {0, 0, 0, 255});
    const GeoRectangle r = tileRectangle(t);
    const double sizeDeg = r.eastDeg - r.westDeg;
    for (int j = 0; j < kTileSizePx; ++j) {
      const double latDeg = r.northDeg - (j + 0.5) * sizeDeg / kTileSizePx;
      const double v = (90.0 - latDeg) / 180.0;
      for (int i = 0; i < kTileSizePx; ++i) {
        const double lonDeg = r.westDeg + (i + 0.5) * sizeDeg / kTileSizePx;
        const double u = (lonDeg + 180.0) / 360.0;
        out.set(i, j, sampleBilinear(source_, u, v));
      }
    }
  }

  /// 2x2 box filter of `child` (256 px) into the 128 px quadrant of `out` at (x0, y0).
  static void boxFilterInto(const ImageRGBA8& child, int x0, int y0, ImageRGBA8& out) {
    const ImageRGBA8 half = halfSize(child);
    for (int j = 0; j < half.height; ++j)
      for (int i = 0; i < half.width; ++i) {
        const std::uint8_t* p = &half.pixels[(static_cast<std::size_t>(j) * half.width + i) * 4];
        out.set(x0 + i, y0 + j, glm::u8vec4(p[0], p[1], p[2], p[3]));
      }
  }

  const ImageRGBA8& source_;
  fs::path root_;
  int maxLevel_;
  const PyramidBuildOptions& options_;
  std::uint64_t total_;
  std::uint64_t written_ = 0;
};

Status writeInfo(const fs::path& dir, const PyramidInfo& info, int sourceWidth, int sourceHeight) {
  nlohmann::json j;
  j["kind"] = kPyramidKind;
  j["version"] = kPyramidVersion;
  j["tiling"] = "EPSG:4326, level 0 = 2 x 1 tiles of 180 deg, row 0 at the north";
  j["maxLevel"] = info.maxLevel;
  j["tileSizePx"] = info.tileSizePx;
  j["format"] = info.format;
  j["source"] = info.source;
  j["sourceWidthPx"] = sourceWidth;
  j["sourceHeightPx"] = sourceHeight;
  return writeFileInStagedDirectory((dir / "pyramid.json").string(), j.dump(2) + "\n");
}

}  // namespace

std::uint64_t pyramidTileCount(int maxLevel) {
  std::uint64_t n = 0;
  for (int z = 0; z <= maxLevel; ++z) n += 2ull << (2 * z);
  return n;
}

int naturalPyramidLevel(int widthPx) {
  int level = 0;
  while (level < kMaxPyramidLevel && (std::int64_t{2} << level) * kTileSizePx < widthPx) ++level;
  return level;
}

Status buildPyramid(const std::string& imagePath, const std::string& outDir, const PyramidBuildOptions& options,
                    PyramidInfo* infoOut) {
  if (options.maxLevel < -1 || options.maxLevel > kMaxPyramidLevel) {
    return makeError(outDir + ": max level " + std::to_string(options.maxLevel) + " is outside 0.." +
                     std::to_string(kMaxPyramidLevel));
  }
  Result<ImageRGBA8> source = decodeImageFile(imagePath);
  if (!source) return source.forwardError();
  const int w = source->width, h = source->height;
  if (std::abs(w - 2 * h) > 1) {
    return makeError(imagePath + ": not an equirectangular world image: " + std::to_string(w) + " x " +
                     std::to_string(h) + " px, expected width = 2 x height (within 1 px)");
  }
  const fs::path out = normalizedDir(outDir);
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) return makeError(out.string() + ": exists and is not a directory");
    // Never replace a directory that is not a pyramid (it could be anything of the user's).
    if (!fs::is_empty(out, ec) && !fs::exists(out / "pyramid.json", ec)) {
      return makeError(out.string() + ": exists, is not empty and holds no pyramid.json; refusing to replace it");
    }
  } else if (out.has_parent_path()) {
    fs::create_directories(out.parent_path(), ec);
    if (ec) return makeError(out.parent_path().string() + ": cannot create directory (" + ec.message() + ")");
  }

  PyramidInfo info;
  info.maxLevel = options.maxLevel >= 0 ? options.maxLevel : naturalPyramidLevel(w);
  info.source = fs::path(imagePath).filename().string();

  // Built whole under a hidden name beside `out`, then swapped in (globe/AtomicFile.h): a build
  // that fails, is cancelled or is killed leaves the previous pyramid as it was.
  Result<AtomicDirectory> staged = AtomicDirectory::create(out.string());
  if (!staged) return staged.forwardError();
  const fs::path tmp = staged->dir();
  PyramidWriter writer(*source, tmp, info.maxLevel, options);
  ImageRGBA8 root;
  for (std::uint32_t x = 0; x < tileColumns(0); ++x) {
    Status s = writer.build(TileId{0, x, 0}, root);
    if (!s) return s;  // the AtomicDirectory destructor removes the staged tree
  }
  // pyramid.json last: a tree without it is never a pyramid (readPyramidInfo refuses it).
  if (Status s = writeInfo(tmp, info, w, h); !s) return s;
  if (Status s = staged->publish(); !s) return s;
  if (infoOut) *infoOut = info;
  return Ok{};
}

Result<PyramidInfo> readPyramidInfo(const std::string& dir) {
  const fs::path path = normalizedDir(dir) / "pyramid.json";
  std::ifstream in(path);
  if (!in) return makeError(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return makeError(path.string() + ": not valid JSON");
  auto field = [&](const char* name) -> const nlohmann::json* {
    auto it = j.find(name);
    return it == j.end() ? nullptr : &*it;
  };
  const nlohmann::json* kind = field("kind");
  if (!kind || !kind->is_string() || kind->get<std::string>() != kPyramidKind) {
    return makeError(path.string() + ": \"kind\" is not \"" + kPyramidKind + "\"");
  }
  PyramidInfo info;
  const nlohmann::json* maxLevel = field("maxLevel");
  if (!maxLevel || !maxLevel->is_number_integer() || maxLevel->get<int>() < 0 || maxLevel->get<int>() > kMaxTileLevel) {
    return makeError(path.string() + ": \"maxLevel\" missing or outside 0.." + std::to_string(kMaxTileLevel));
  }
  info.maxLevel = maxLevel->get<int>();
  const nlohmann::json* tileSize = field("tileSizePx");
  if (!tileSize || !tileSize->is_number_integer() || tileSize->get<int>() != kTileSizePx) {
    return makeError(path.string() + ": \"tileSizePx\" must be " + std::to_string(kTileSizePx));
  }
  info.tileSizePx = kTileSizePx;
  const nlohmann::json* format = field("format");
  if (!format || !format->is_string() || format->get<std::string>() != "png") {
    return makeError(path.string() + ": \"format\" must be \"png\"");
  }
  info.format = "png";
  if (const nlohmann::json* source = field("source"); source && source->is_string())
    info.source = source->get<std::string>();
  return info;
}

// --- GeographicPyramidLayer ---

Result<std::shared_ptr<GeographicPyramidLayer>> GeographicPyramidLayer::open(const std::string& dir) {
  Result<PyramidInfo> info = readPyramidInfo(dir);
  if (!info) return info.forwardError();
  return std::shared_ptr<GeographicPyramidLayer>(new GeographicPyramidLayer(normalizedDir(dir).string(), *info));
}

std::string GeographicPyramidLayer::tilePath(const TileId& t) const {
  return (fs::path(dir_) / tileRelativePath(t, info_.format)).string();
}

std::string GeographicPyramidLayer::description() const {
  return "geographic pyramid " + dir_ + " (levels 0.." + std::to_string(info_.maxLevel) + ", from " + info_.source +
         ")";
}

Result<std::shared_ptr<const ImageRGBA8>> GeographicPyramidLayer::loadStoredTile(const TileId& t) const {
  const std::string path = tilePath(t);
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::shared_ptr<const ImageRGBA8>{};
  Result<ImageRGBA8> image = decodeImageFile(path);
  if (!image) return image.forwardError();
  if (image->width != kTileSizePx || image->height != kTileSizePx) {
    return makeError(path + ": tile is " + std::to_string(image->width) + " x " + std::to_string(image->height) +
                     " px, expected " + std::to_string(kTileSizePx) + " x " + std::to_string(kTileSizePx));
  }
  return std::make_shared<const ImageRGBA8>(std::move(*image));
}

Result<std::optional<ImageRGBA8>> GeographicPyramidLayer::tileImage(const TileId& t) const {
  assert(isValid(t));
  if (t.level <= info_.maxLevel) {
    Result<std::shared_ptr<const ImageRGBA8>> stored = loadStoredTile(t);
    if (!stored) return stored.forwardError();
    if (!*stored) return std::optional<ImageRGBA8>{};
    return std::optional<ImageRGBA8>{**stored};
  }
  const TileId a = ancestorTile(t, info_.maxLevel);
  std::shared_ptr<const ImageRGBA8> ancestor;
  {
    std::lock_guard lock(mutex_);
    if (auto* cached = ancestors_.find(a)) ancestor = *cached;
  }
  if (!ancestor) {
    // Decoded outside the lock; two threads may decode the same ancestor at once (harmless).
    Result<std::shared_ptr<const ImageRGBA8>> stored = loadStoredTile(a);
    if (!stored) return stored.forwardError();
    if (!*stored) return std::optional<ImageRGBA8>{};
    ancestor = *stored;
    std::lock_guard lock(mutex_);
    ancestors_.insert(a, ancestor, ancestor->byteSize());
  }
  const glm::dvec4 uv = uvTransformInAncestor(t, a);
  ImageRGBA8 out = ImageRGBA8::filled(kTileSizePx, kTileSizePx, {0, 0, 0, 0});
  for (int j = 0; j < kTileSizePx; ++j) {
    const double v = (j + 0.5) / kTileSizePx * uv.y + uv.w;
    for (int i = 0; i < kTileSizePx; ++i) {
      const double u = (i + 0.5) / kTileSizePx * uv.x + uv.z;
      out.set(i, j, sampleBilinear(*ancestor, u, v));
    }
  }
  return std::optional<ImageRGBA8>{std::move(out)};
}

}  // namespace atmoglobe::globe
