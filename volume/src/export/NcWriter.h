#pragma once
// Private to the volume library: a netCDF-C call wrapper for the netCDF writers (SyntheticRadar.cpp,
// SyntheticGrid.cpp, Mosaic.cpp). The first failure is kept, naming the file and what was
// being written. Its users hold io::NetcdfLock from nc_create to nc_close (io/NetcdfLock.h).
#include <atmoglobe/globe/Result.h>

#include <netcdf.h>

#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::volume {

class NcWriter {
 public:
  NcWriter(std::string path, int ncid) : path_(std::move(path)), ncid_(ncid) {}
  bool ok() const { return err_.empty(); }
  const std::string& error() const { return err_; }
  void check(int status, const std::string& what) {
    if (status != NC_NOERR && err_.empty())
      err_ = path_ + ": netCDF write failed (" + what + "): " + nc_strerror(status);
  }
  void text(int varid, const char* name, const std::string& value) {
    check(nc_put_att_text(ncid_, varid, name, value.size(), value.c_str()), name);
  }
  int var(const char* name, nc_type type, std::vector<int> dims) {
    int id = -1;
    check(nc_def_var(ncid_, name, type, static_cast<int>(dims.size()), dims.empty() ? nullptr : dims.data(), &id),
          name);
    return id;
  }
  int ncid() const { return ncid_; }

 private:
  std::string path_;
  int ncid_;
  std::string err_;
};

/// Creates an empty file beside `path` (so the rename stays on one file system) and opens it as
/// a netCDF-4 file for writing.
Status createTemporaryNetcdf(const std::string& path, std::string* temp, int* ncid);

/// Closes the file and renames it into place; on any failure (the writer's first or the close)
/// removes the temporary and returns the error.
Status closeAndCommitNetcdf(const std::string& path, const std::string& temp, const NcWriter& w);

}  // namespace atmoglobe::volume
