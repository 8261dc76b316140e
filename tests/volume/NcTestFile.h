#pragma once
// A small netCDF-C writer for tests that build their own files (grids, bad input). Every call
// checks its status and records a GoogleTest failure naming the call, so a broken test file
// shows up as such and not as a reader bug.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <map>
#include <string>
#include <vector>

namespace atmoglobe_test {

class NcTestFile {
 public:
  /// mode: NC_NETCDF4 (default) or 0 for classic.
  explicit NcTestFile(const std::string& path, int mode = NC_NETCDF4) : path_(path) {
    ok(nc_create(path.c_str(), NC_CLOBBER | mode, &root_), "create " + path);
  }
  ~NcTestFile() { close(); }
  NcTestFile(const NcTestFile&) = delete;
  NcTestFile& operator=(const NcTestFile&) = delete;

  int root() const { return root_; }
  int group(const std::string& name, int parent = -1) {
    int g = -1;
    ok(nc_def_grp(parent < 0 ? root_ : parent, name.c_str(), &g), "group " + name);
    return g;
  }
  /// Dimensions live in the root group here (visible from every group); NC_UNLIMITED allowed.
  void dim(const std::string& name, std::size_t length) {
    int id = -1;
    ok(nc_def_dim(root_, name.c_str(), length, &id), "dim " + name);
    dims_[name] = id;
  }
  /// A variable on named dimensions, in group `g` (-1: root). Returns {group, id}.
  struct Var {
    int group = -1, id = -1;
  };
  Var var(const std::string& name, nc_type type, const std::vector<std::string>& dims, int g = -1) {
    std::vector<int> ids;
    for (const auto& d : dims) ids.push_back(dims_.at(d));
    Var v{g < 0 ? root_ : g, -1};
    ok(nc_def_var(v.group, name.c_str(), type, static_cast<int>(ids.size()), ids.empty() ? nullptr : ids.data(), &v.id),
       "var " + name);
    return v;
  }
  void text(Var v, const std::string& name, const std::string& value) {
    ok(nc_put_att_text(v.group, v.id, name.c_str(), value.size(), value.c_str()), "att " + name);
  }
  void globalText(const std::string& name, const std::string& value) {
    ok(nc_put_att_text(root_, NC_GLOBAL, name.c_str(), value.size(), value.c_str()), "att " + name);
  }
  /// A numeric attribute stored in `type`.
  void number(Var v, const std::string& name, nc_type type, const std::vector<double>& values) {
    ok(nc_put_att_double(v.group, v.id, name.c_str(), type, values.size(), values.data()), "att " + name);
  }
  /// Writes a whole variable from doubles (netCDF-C converts to the stored type).
  void put(Var v, const std::vector<double>& values) {
    endDef();
    ok(nc_put_var_double(v.group, v.id, values.data()), "put");
  }
  /// Writes a hyperslab (for record variables).
  void put(Var v, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
           const std::vector<double>& values) {
    endDef();
    ok(nc_put_vara_double(v.group, v.id, start.data(), count.data(), values.data()), "put slab");
  }
  void putText(Var v, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
               const std::string& s) {
    endDef();
    ok(nc_put_vara_text(v.group, v.id, start.data(), count.data(), s.data()), "put text");
  }
  void endDef() {
    if (defining_) {
      const int st = nc_enddef(root_);
      if (st != NC_NOERR && st != NC_ENOTINDEFINE) ok(st, "enddef");
      defining_ = false;
    }
  }
  void close() {
    if (root_ >= 0) {
      ok(nc_close(root_), "close " + path_);
      root_ = -1;
    }
  }

 private:
  void ok(int status, const std::string& what) {
    if (status != NC_NOERR)
      ADD_FAILURE() << "netCDF test file " << path_ << ": " << what << ": " << nc_strerror(status);
  }
  std::string path_;
  int root_ = -1;
  bool defining_ = true;
  std::map<std::string, int> dims_;
};

}  // namespace atmoglobe_test
