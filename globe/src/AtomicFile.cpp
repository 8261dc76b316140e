#include <atmoglobe/globe/AtomicFile.h>

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>  // renameat2 (glibc >= 2.28, _GNU_SOURCE: on by default with g++)
#include <sys/stat.h>
#include <unistd.h>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace atmoglobe::globe {

namespace fs = std::filesystem;

namespace {

std::string osError(const std::string& path, const char* what, int err) {
  return path + ": " + what + ": " + std::strerror(err);
}

std::string parentDir(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// The hidden prefix of every temporary of `path`: ".NAME.tmp" (then <pid>-<n>).
std::string temporaryPrefix(const fs::path& p) {
  // GCC 12 misreports -Wrestrict on "." + std::string: append.
  std::string name = ".";
  name.append(p.filename().string());
  name.append(".tmp");
  return name;
}

bool processRuns(long pid) {
  if (pid <= 0 || pid > 0x3fffffff) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

// Writes all of `bytes` to `fd`; 0 or errno.
int writeAll(int fd, std::string_view bytes) {
  const char* data = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  return 0;
}

// Creates a temporary beside `path` open for writing; returns its name and fd.
Result<std::pair<std::string, int>> createTemp(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return makeError(path + ": is a directory");
  auto tempName = temporaryPathBeside(path);
  if (!tempName) return tempName.forwardError();
  const int fd = ::open(tempName->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return makeError(osError(path, "cannot create file in its directory", errno));
  return std::pair<std::string, int>(*tempName, fd);
}

// Writes a temporary beside `path`; returns its name or an error (nothing left behind).
Result<std::string> writeTemp(const std::string& path, std::string_view bytes) {
  auto created = createTemp(path);
  if (!created) return created.forwardError();
  const auto [temp, fd] = *created;
  if (const int err = writeAll(fd, bytes); err != 0) {
    ::close(fd);
    ::unlink(temp.c_str());
    return makeError(osError(path, "write failed", err));
  }
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    ::unlink(temp.c_str());
    return makeError(osError(path, "fsync failed", err));
  }
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(temp.c_str());
    return makeError(osError(path, "close failed", err));
  }
  return temp;
}

void syncDir(const std::string& path) {
  // Makes the rename durable; failure here does not undo a completed rename, so it is not an error.
  const int dfd = ::open(parentDir(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

}  // namespace

int removeStaleTemporaries(const std::string& path) {
  const fs::path p(path);
  if (p.filename().empty()) return 0;
  const std::string prefix = temporaryPrefix(p);
  std::error_code ec;
  int removed = 0;
  for (fs::directory_iterator it(parentDir(path), ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    // ".NAME.tmp<pid>-<n>", or that followed by '.' and a suffix: libzip writes the archive to
    // "<our temporary>.XXXXXX" before renaming it onto our temporary.
    const std::string rest = name.substr(prefix.size());
    const std::size_t dash = rest.find('-');
    if (dash == 0 || dash == std::string::npos || dash > 10 || dash + 1 == rest.size()) continue;
    if (rest.find_first_not_of("0123456789") != dash) continue;
    const std::size_t afterN = rest.find_first_not_of("0123456789", dash + 1);
    if (afterN == dash + 1 || (afterN != std::string::npos && rest[afterN] != '.')) continue;
    if (processRuns(std::stol(rest.substr(0, dash)))) continue;
    std::error_code ignored;
    if (fs::remove_all(it->path(), ignored) > 0) ++removed;
  }
  return removed;
}

Result<std::string> temporaryPathBeside(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(path);
  if (p.filename().empty()) return makeError(path + ": not a file name");
  removeStaleTemporaries(path);
  std::string name = temporaryPrefix(p);
  name.append(std::to_string(::getpid()));
  name.push_back('-');
  name.append(std::to_string(counter.fetch_add(1)));
  return (p.parent_path() / name).string();
}

Status commitTemporary(const std::string& tempPath, const std::string& path) {
  const int fd = ::open(tempPath.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    ::unlink(tempPath.c_str());
    return makeError(osError(path, "fsync failed", err));
  }
  ::close(fd);
  if (::rename(tempPath.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tempPath.c_str());
    return makeError(osError(path, "rename into place failed", err));
  }
  syncDir(path);
  return Ok{};
}

Status writeFileAtomic(const std::string& path, std::string_view bytes) {
  AtomicFileSet set;
  if (Status s = set.add(path, bytes); !s) return s;
  return set.commit();
}

// --- AtomicFileWriter ---

AtomicFileWriter::AtomicFileWriter(std::string path, std::string tempPath, int fd)
    : path_(std::move(path)), tempPath_(std::move(tempPath)), fd_(fd) {}

AtomicFileWriter::AtomicFileWriter(AtomicFileWriter&& other) noexcept
    : path_(std::move(other.path_)), tempPath_(std::move(other.tempPath_)), fd_(other.fd_) {
  other.fd_ = -1;
  other.tempPath_.clear();
}

AtomicFileWriter::~AtomicFileWriter() { discard(); }

void AtomicFileWriter::discard() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!tempPath_.empty()) ::unlink(tempPath_.c_str());
  tempPath_.clear();
}

Result<AtomicFileWriter> AtomicFileWriter::create(const std::string& path) {
  auto created = createTemp(path);
  if (!created) return created.forwardError();
  return AtomicFileWriter(path, created->first, created->second);
}

Status AtomicFileWriter::write(std::string_view bytes) {
  if (fd_ < 0) return makeError(path_ + ": write after commit or failure");
  if (const int err = writeAll(fd_, bytes); err != 0) {
    discard();
    return makeError(osError(path_, "write failed", err));
  }
  return Ok{};
}

Status AtomicFileWriter::commit() {
  if (fd_ < 0) return makeError(path_ + ": commit after commit or failure");
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const int err = errno;
    discard();
    return makeError(osError(path_, "close failed", err));
  }
  const std::string temp = tempPath_;
  tempPath_.clear();
  return commitTemporary(temp, path_);  // removes the temporary on failure
}

// --- AtomicFileSet ---

AtomicFileSet::~AtomicFileSet() {
  for (const Entry& e : entries_) {
    if (!e.renamed) ::unlink(e.tempPath.c_str());
  }
}

Status AtomicFileSet::add(const std::string& path, std::string_view bytes) {
  Result<std::string> temp = writeTemp(path, bytes);
  if (!temp) return temp.forwardError();
  entries_.push_back(Entry{path, std::move(temp.value()), false});
  return Ok{};
}

Status AtomicFileSet::commit() {
  for (Entry& e : entries_) {
    if (e.renamed) continue;
    if (::rename(e.tempPath.c_str(), e.path.c_str()) != 0) {
      return makeError(osError(e.path, "cannot rename into place", errno));  // destructor removes the rest
    }
    e.renamed = true;
    syncDir(e.path);
  }
  return Ok{};
}

// --- AtomicDirectory ---

AtomicDirectory::AtomicDirectory(std::string path, std::string stagePath)
    : path_(std::move(path)), stagePath_(std::move(stagePath)) {}

AtomicDirectory::AtomicDirectory(AtomicDirectory&& other) noexcept
    : path_(std::move(other.path_)), stagePath_(std::move(other.stagePath_)), published_(other.published_) {
  other.published_ = true;  // the moved-from object owns nothing
}

AtomicDirectory::~AtomicDirectory() {
  if (published_ || stagePath_.empty()) return;
  std::error_code ignored;
  fs::remove_all(stagePath_, ignored);
}

Result<AtomicDirectory> AtomicDirectory::create(const std::string& path) {
  auto stage = temporaryPathBeside(path);
  if (!stage) return stage.forwardError();
  if (::mkdir(stage->c_str(), 0777) != 0) return makeError(osError(path, "cannot create a directory beside it", errno));
  return AtomicDirectory(path, *stage);
}

Status AtomicDirectory::publish() {
  if (published_) return makeError(path_ + ": published twice");
  // One syncfs makes every staged file durable before the swap (cheaper than fsync per tile).
  if (const int fd = ::open(stagePath_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); fd >= 0) {
    ::syncfs(fd);
    ::close(fd);
  }
  struct stat st {};
  if (::lstat(path_.c_str(), &st) != 0) {
    if (::rename(stagePath_.c_str(), path_.c_str()) != 0) {
      return makeError(osError(path_, "cannot rename the finished directory into place", errno));
    }
  } else {
    if (!S_ISDIR(st.st_mode)) return makeError(path_ + ": exists and is not a directory");
    // Swap: the new tree appears at path_ in one step; the old one is now at stagePath_.
    if (::renameat2(AT_FDCWD, stagePath_.c_str(), AT_FDCWD, path_.c_str(), RENAME_EXCHANGE) != 0) {
      const int err = errno;
      if (err != EINVAL && err != ENOSYS) {
        return makeError(osError(path_, "cannot swap the finished directory into place", err));
      }
      // A file system without RENAME_EXCHANGE: move the old tree aside, then the new one in.
      // Between the two renames `path_` does not exist (a kill there leaves the old tree under a
      // hidden name beside it, which the next build removes): not atomic, said here and in docs.
      auto aside = temporaryPathBeside(path_);
      if (!aside) return aside.forwardError();
      if (::rename(path_.c_str(), aside->c_str()) != 0) {
        return makeError(osError(path_, "cannot move the old directory aside", errno));
      }
      if (::rename(stagePath_.c_str(), path_.c_str()) != 0) {
        const int err2 = errno;
        ::rename(aside->c_str(), path_.c_str());  // put the old one back
        return makeError(osError(path_, "cannot rename the finished directory into place", err2));
      }
      std::error_code ignored;
      fs::remove_all(*aside, ignored);
      published_ = true;
      syncDir(path_);
      return Ok{};
    }
    published_ = true;
    syncDir(path_);
    std::error_code ignored;
    fs::remove_all(stagePath_, ignored);  // the old tree; if killed here, the next build removes it
    return Ok{};
  }
  published_ = true;
  syncDir(path_);
  return Ok{};
}

std::time_t outputTime() {
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH"); epoch && *epoch) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(epoch, &end, 10);
    if (errno == 0 && *end == '\0' && v >= 0) return static_cast<std::time_t>(v);
  }
  return std::time(nullptr);
}

Status writeFileInStagedDirectory(const std::string& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) return makeError(osError(path, "cannot create", errno));
  const int err = writeAll(fd, bytes);
  if (::close(fd) != 0 && err == 0) return makeError(osError(path, "close failed", errno));
  if (err != 0) return makeError(osError(path, "write failed", err));
  return Ok{};
}

}  // namespace atmoglobe::globe
