#pragma once
// Writing zip archives (KMZ) through libzip, atomically.
//
// The archive is built by libzip at a temporary name beside the target, then fsynced and
// renamed over it as every atomic write here is (AtomicFile.h): a failure leaves any earlier
// file at `path` untouched and no temporary behind. libzip writes zip64 records where an entry
// or the archive needs them (over 4 GiB or 65535 entries), so there is no size limit here.
#include <atmoglobe/globe/Result.h>

#include <string>
#include <vector>

namespace atmoglobe::volume {

struct ZipEntry {
  std::string name;     ///< path inside the archive, '/'-separated, UTF-8; unique in the archive
  std::string bytes;    ///< the file's content
  bool deflate = true;  ///< false: stored as is (for data that is already compressed, e.g. PNG)
};

/// Writes `entries`, in order, as a zip archive at `path` (entries rw-r--r--, time of writing).
/// Errors name `path` and the reason libzip or the OS gives. Needs at least one entry (libzip
/// writes no file for an empty archive).
Status writeZipArchiveAtomic(const std::string& path, const std::vector<ZipEntry>& entries);

}  // namespace atmoglobe::volume
