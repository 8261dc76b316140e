// The netCDF writers' shared steps (NcWriter.h).
#include "NcWriter.h"

#include <atmoglobe/volume/AtomicFile.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace atmoglobe::volume {

Status createTemporaryNetcdf(const std::string& path, std::string* temp, int* ncid) {
  auto tempName = temporaryPathBeside(path);
  if (!tempName) return tempName.forwardError();
  *temp = *tempName;
  const int fd = ::open(temp->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return makeError(path + ": cannot create file in its directory: " + std::strerror(errno));
  ::close(fd);
  if (const int st = nc_create(temp->c_str(), NC_NETCDF4 | NC_CLOBBER, ncid); st != NC_NOERR) {
    ::unlink(temp->c_str());
    return makeError(path + ": cannot create netCDF-4 file: " + nc_strerror(st));
  }
  return Ok{};
}

Status closeAndCommitNetcdf(const std::string& path, const std::string& temp, const NcWriter& w) {
  std::string err = w.ok() ? std::string() : w.error();
  if (const int st = nc_close(w.ncid()); st != NC_NOERR && err.empty())
    err = path + ": netCDF close failed: " + nc_strerror(st);
  if (!err.empty()) {
    ::unlink(temp.c_str());
    return makeError(err);
  }
  return commitTemporary(temp, path);
}

}  // namespace atmoglobe::volume
