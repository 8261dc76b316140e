#pragma once
// Atomic file writes: nothing half-written is ever left where a good file was.
//
// Each file is written to a temporary name in the SAME directory (so the final rename(2) stays
// on one file system and is atomic), flushed with fsync, then renamed over the destination. On
// any failure the temporary is removed and the destination is untouched.
#include <atmoglobe/globe/Result.h>

#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::volume {

/// A hidden temporary name beside `path` (same directory, unique per process and call), for
/// writers that create the file themselves (e.g. through netCDF-C). Error if path has no name.
Result<std::string> temporaryPathBeside(const std::string& path);

/// Completes such a write: fsyncs `tempPath`, renames it over `path`, fsyncs the directory.
/// On failure the temporary is removed and `path` is untouched; errors name `path`.
Status commitTemporary(const std::string& tempPath, const std::string& path);

/// Writes `bytes` to `path` atomically (temp + fsync + rename + fsync of the directory).
/// Errors name the path and the OS reason (strerror).
Status writeFileAtomic(const std::string& path, std::string_view bytes);

/// Several files committed together: add() writes each to its temporary name; commit() renames
/// them all into place (after every write succeeded). Destroying the set without commit() (or
/// after a failed add) removes every temporary. A failure in the middle of commit() (rename of
/// file k fails) leaves files 0..k-1 replaced: rename is atomic per file, not across files;
/// commit() stops at the first failure and removes the temporaries not yet renamed.
class AtomicFileSet {
 public:
  AtomicFileSet() = default;
  AtomicFileSet(const AtomicFileSet&) = delete;
  AtomicFileSet& operator=(const AtomicFileSet&) = delete;
  ~AtomicFileSet();

  /// Writes `bytes` to a temporary beside `path` (fsynced).
  Status add(const std::string& path, std::string_view bytes);
  /// Renames every temporary into place, in the order added.
  Status commit();

 private:
  struct Entry {
    std::string path, tempPath;
    bool renamed = false;
  };
  std::vector<Entry> entries_;
};

}  // namespace atmoglobe::volume
