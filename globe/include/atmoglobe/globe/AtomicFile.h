#pragma once
// Atomic outputs: the one helper every writer of a user-visible file or directory goes through
// (exports, PNGs, CSVs, NRRD, tile pyramids, bench reports). Nothing half-written is ever left
// where a good output was, even when the process is killed (SIGKILL) at any moment.
//
// Files: written to a hidden temporary name in the SAME directory (".NAME.tmp<pid>-<n>", so the
// final rename(2) stays on one file system and is atomic), fsynced, then renamed over the
// destination. Directories (tile pyramids): built under such a hidden name beside the
// destination, then swapped in with one renameat2(RENAME_EXCHANGE) and the old tree removed.
// On any error the temporary is removed and the destination is untouched. A process killed
// mid-write leaves its hidden temporary behind; the next write of the same output removes every
// such temporary whose process (the <pid> in its name) no longer runs.
#include <atmoglobe/globe/Result.h>

#include <ctime>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::globe {

/// A hidden temporary name beside `path` (same directory, unique per process and call), for
/// writers that create the file themselves (e.g. through netCDF-C). Error if path has no name.
/// Also removes stale temporaries of `path` left by killed processes (removeStaleTemporaries).
Result<std::string> temporaryPathBeside(const std::string& path);

/// Removes the temporaries of `path` (files or directories named ".NAME.tmp<pid>-<n>" beside it,
/// or that name followed by ".SUFFIX", which libzip uses for the archive it writes)
/// whose process <pid> no longer runs. Returns how many were removed. Temporaries of a running
/// process (this one or another writing the same output) are left alone.
int removeStaleTemporaries(const std::string& path);

/// Completes such a write: fsyncs `tempPath`, renames it over `path`, fsyncs the directory.
/// On failure the temporary is removed and `path` is untouched; errors name `path`.
Status commitTemporary(const std::string& tempPath, const std::string& path);

/// Writes `bytes` to `path` atomically (temp + fsync + rename + fsync of the directory).
/// Errors name the path and the OS reason (strerror).
Status writeFileAtomic(const std::string& path, std::string_view bytes);

/// A file written in pieces (e.g. a CSV streamed row block by row block) and published whole by
/// commit(). Destroying it without a successful commit() removes the temporary.
class AtomicFileWriter {
 public:
  static Result<AtomicFileWriter> create(const std::string& path);
  AtomicFileWriter(AtomicFileWriter&& other) noexcept;
  AtomicFileWriter& operator=(AtomicFileWriter&&) = delete;
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  ~AtomicFileWriter();

  Status write(std::string_view bytes);
  /// fsync, rename over the destination, fsync the directory. At most once.
  Status commit();

 private:
  AtomicFileWriter(std::string path, std::string tempPath, int fd);
  void discard();
  std::string path_, tempPath_;
  int fd_ = -1;
};

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

/// A directory output (a tile pyramid) built whole before anyone sees it. create() makes an empty
/// hidden directory beside `path`; the caller fills dir() (writeFileInStagedDirectory, no
/// per-file fsync); publish() syncs the file system once and swaps the staged tree with `path` in
/// one renameat2(RENAME_EXCHANGE) (a plain rename when `path` does not exist yet), then removes
/// the previous tree. Readers see the whole old tree or the whole new one, never a mixture and
/// never nothing. Destroying it without publish() removes the staged tree.
class AtomicDirectory {
 public:
  static Result<AtomicDirectory> create(const std::string& path);
  AtomicDirectory(AtomicDirectory&& other) noexcept;
  AtomicDirectory& operator=(AtomicDirectory&&) = delete;
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;
  ~AtomicDirectory();

  /// The staged directory to fill.
  const std::string& dir() const { return stagePath_; }
  Status publish();

 private:
  AtomicDirectory(std::string path, std::string stagePath);
  std::string path_, stagePath_;
  bool published_ = false;
};

/// The time to embed in outputs that record one (COLLADA <created>, zip entry times): now, or
/// $SOURCE_DATE_EPOCH (seconds since 1970, the reproducible-builds convention) when it is set to
/// a valid non-negative integer, so that the same input gives the same bytes.
std::time_t outputTime();

/// Writes a file inside an AtomicDirectory's staged tree: plain write, no fsync and no rename
/// (publish() makes the whole tree visible and durable at once).
Status writeFileInStagedDirectory(const std::string& path, std::string_view bytes);

}  // namespace atmoglobe::globe
