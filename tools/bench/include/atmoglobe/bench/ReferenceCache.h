#pragma once
// Reference images (volume::renderReference: double precision, exact inverse), cached on disk
// because they cost 10-90 s each: one file per settings key under OUT/reference-cache/, named by
// a hash of the key, holding the full key (checked on reading: a hash collision is a miss) and
// the image. A missing, foreign, truncated or corrupted file is a miss, never an error: the
// reference is rendered again and the file rewritten.
//
// File layout (native byte order; the cache is a local speed-up, not an exchange format):
//   uint32 key length (<= 4096) | key bytes | int32 width, int32 height (1..8192) |
//   width x height x dvec4 premultiplied RGBA (double), row-major from the top row.
#include <atmoglobe/bench/Views.h>
#include <atmoglobe/volume/VolumeImage.h>
#include <atmoglobe/volume/VolumeRenderSettings.h>

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

namespace atmoglobe::bench {

/// The key of a reference image: volume identity (radars: the path) and field (grids: @time
/// step), camera pose, fovY, size, mode, interpolation, step, iso value, early termination,
/// transfer function and occlusion (radars "no-occlusion", grids "ellipsoid") ("ref-v1|...").
/// Every number through formatG (10 digits).
std::string referenceKey(const BenchView& view, int widthPx, int heightPx, const volume::VolumeRenderSettings& s);

/// 64-bit FNV-1a of `s`, with the offset basis 1469598103934665603: NOT the standard
/// 14695981039346656037 (a digit was lost when this was first written). Kept as it is on
/// purpose: the cache file names are this hash, and changing it would orphan every cached
/// reference (each costs 10-90 s to render again).
std::uint64_t fnv1a(const std::string& s);

/// "%016llx.ref" of fnv1a(key).
std::string referenceFileName(const std::string& key);

/// The image stored in `file` under `key`; nullopt when the file is missing, holds another key,
/// or is truncated or malformed.
std::optional<volume::VolumeImage> readCachedReference(const std::filesystem::path& file, const std::string& key);

/// Writes `img` under `key` to a temporary beside `file`, then renames it into place. Returns
/// false when that failed (a cache that cannot be written only costs time on the next run).
bool writeCachedReference(const std::filesystem::path& file, const std::string& key, const volume::VolumeImage& img);

/// The settings every reference is rendered with: linear interpolation, the default
/// reflectivity transfer function, `mode`, `stepMeters` (defaults for the rest).
volume::VolumeRenderSettings referenceSettings(volume::VolumeRenderMode mode, double stepMeters);
/// The same with the volume's own transfer function (grids: by the variable).
volume::VolumeRenderSettings referenceSettings(volume::VolumeRenderMode mode, double stepMeters,
                                               const volume::TransferFunction& transfer);

/// Reference images on demand: from the cache in `dir`, else rendered (occlusion off, on
/// `threads` threads, progress on `log`) and stored.
struct ReferenceStore {
  std::filesystem::path dir;
  int threads = 2;
  std::ostream* log = nullptr;  ///< progress lines; null: none
  double secondsRendering = 0.0;
  int rendered = 0, cached = 0;

  volume::VolumeImage get(const BenchView& view, int widthPx, int heightPx, const volume::VolumeRenderSettings& s);
};

}  // namespace atmoglobe::bench
