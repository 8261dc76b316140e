#include <atmoglobe/volume/AtomicFile.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace atmoglobe::volume {

namespace {

std::string osError(const std::string& path, const char* what, int err) {
  return path + ": " + what + ": " + std::strerror(err);
}

std::string parentDir(const std::string& path) {
  const std::filesystem::path p(path);
  const std::filesystem::path parent = p.parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Writes a temporary beside `path`; returns its name or an error (nothing left behind).
Result<std::string> writeTemp(const std::string& path, std::string_view bytes) {
  auto tempName = temporaryPathBeside(path);
  if (!tempName) return tempName;
  const std::string temp = *tempName;
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return makeError(osError(path, "cannot create file in its directory", errno));
  const char* data = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      ::unlink(temp.c_str());
      return makeError(osError(path, "write failed", err));
    }
    data += n;
    left -= static_cast<std::size_t>(n);
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

Result<std::string> temporaryPathBeside(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path p(path);
  if (p.filename().empty()) return makeError(path + ": not a file name");
  // Hidden name in the same directory (GCC 12 misreports -Wrestrict on "." + std::string: append).
  std::string name = ".";
  name.append(p.filename().string());
  name.append(".tmp");
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

AtomicFileSet::~AtomicFileSet() {
  for (const Entry& e : entries_) {
    if (!e.renamed) ::unlink(e.tempPath.c_str());
  }
}

Status AtomicFileSet::add(const std::string& path, std::string_view bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return makeError(path + ": is a directory");
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

}  // namespace atmoglobe::volume
