#pragma once
// A small RAII wrapper over netCDF-C for the radar readers (CfRadial, ODIM_H5 through
// netCDF-C's HDF5 layer).
//
// Every failure comes back as a Result whose message names the file and, where there is
// one, the group/variable/attribute ("FILE: variable '/dataset1/data1/data': ...").
// Reads into memory go through checkReadable(), which refuses element counts that the
// file cannot hold (see there), so a header that claims gigabytes never turns into a
// gigabyte allocation.
#include <atmoglobe/globe/Result.h>

#include <netcdf.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// A variable found in a group: ids, type and shape (dimension lengths as the file gives them).
struct NcVar {
  int groupId = -1;
  int varId = -1;
  std::string name;            ///< full path for messages, e.g. "/dataset1/data1/data"
  nc_type type = NC_NAT;
  std::vector<std::size_t> shape;
  std::vector<int> dimIds;
  std::size_t elementCount() const;
};

/// Upper bound on the elements one read may allocate, whatever the file says: 2^28
/// (1 GiB of floats). The largest real volumes hold ~10^7-10^8 gates per field.
inline constexpr std::size_t kMaxElementsPerRead = std::size_t{1} << 28;

/// Largest compression ratio that checkReadable() accepts for chunked/filtered variables.
/// zlib deflate cannot exceed 1032:1; 1100 leaves room for chunk padding.
inline constexpr double kMaxCompressionRatio = 1100.0;

class NetcdfFile {
 public:
  /// Opens read-only. Fails with "PATH: cannot open as netCDF/HDF5: <netCDF-C message>".
  static Result<NetcdfFile> open(const std::string& path);

  NetcdfFile(NetcdfFile&& other) noexcept;
  NetcdfFile& operator=(NetcdfFile&& other) noexcept;
  NetcdfFile(const NetcdfFile&) = delete;
  NetcdfFile& operator=(const NetcdfFile&) = delete;
  ~NetcdfFile();

  const std::string& path() const { return path_; }
  int root() const { return ncid_; }
  /// Size of the file on disk (bytes).
  std::uintmax_t fileSizeBytes() const { return fileSize_; }
  /// True for netCDF-4/HDF5 files, false for classic/64-bit-offset/CDF5.
  bool isHdf5() const { return hdf5_; }

  // --- groups (netCDF-4 only; a classic file has just the root) ---
  /// Child group of `parent` by name, or nullopt.
  std::optional<int> findGroup(int parent, const std::string& name) const;
  /// Names of the direct child groups of `parent`, in the file's order.
  std::vector<std::string> childGroupNames(int parent) const;
  /// Full path of a group ("/" for the root, "/dataset1/what" ...).
  std::string groupPath(int groupId) const;

  // --- dimensions ---
  /// Length of the named dimension visible from `group`, or nullopt if it has none.
  std::optional<std::size_t> dimensionLength(int group, const std::string& name, int* dimId = nullptr) const;

  // --- variables ---
  std::optional<NcVar> findVariable(int group, const std::string& name) const;
  Result<NcVar> variable(int group, const std::string& name) const;
  std::vector<NcVar> variables(int group) const;

  // --- attributes (pass varId = NC_GLOBAL for a group's own attributes) ---
  bool hasAttribute(int group, int varId, const std::string& name) const;
  /// A numeric attribute holding exactly one value (a scalar or a 1-element array).
  Result<double> attributeDouble(int group, int varId, const std::string& name) const;
  /// A numeric attribute of at most maxCount values.
  Result<std::vector<double>> attributeDoubles(int group, int varId, const std::string& name,
                                               std::size_t maxCount) const;
  /// A text attribute (NC_CHAR or NC_STRING, a 1-element string array accepted); trailing
  /// NULs and blanks removed.
  Result<std::string> attributeString(int group, int varId, const std::string& name) const;

  // --- data ---
  /// Refuses reads the file cannot back: more than kMaxElementsPerRead elements, or more
  /// bytes than the file size (contiguous, unfiltered storage; classic files) or than
  /// the file size times kMaxCompressionRatio (chunked or filtered netCDF-4/HDF5 storage).
  Status checkReadable(const NcVar& var, std::size_t elementCount, std::size_t elementBytes) const;

  /// Reads a hyperslab converted to T (netCDF-C conversion rules; a value out of T's
  /// range is an error). `out` must hold the product of `count`.
  template <class T>
  Status readSlab(const NcVar& var, const std::vector<std::size_t>& start,
                  const std::vector<std::size_t>& count, T* out) const;

  /// Reads the whole variable converted to T, after checkReadable().
  template <class T>
  Result<std::vector<T>> readAll(const NcVar& var) const;

  /// Reads a character variable (or a row of a 2-D char variable: row index `row`), as text.
  Result<std::string> readText(const NcVar& var, std::size_t row) const;

  /// "PATH: " + what: the start of every message about this file.
  std::string message(const std::string& what) const { return path_ + ": " + what; }

 private:
  NetcdfFile(std::string path, int ncid, std::uintmax_t size, bool hdf5)
      : path_(std::move(path)), ncid_(ncid), fileSize_(size), hdf5_(hdf5) {}
  std::string attrLabel(int group, int varId, const std::string& name) const;

  std::string path_;
  int ncid_ = -1;
  std::uintmax_t fileSize_ = 0;
  bool hdf5_ = false;
};

/// Calls f(T{}) with T the C++ type matching a numeric netCDF type (the readers read a
/// field in its stored type and decode it themselves). Error for text/compound types.
template <class F>
Status visitNumericType(nc_type type, F&& f) {
  switch (type) {
    case NC_BYTE: return f((signed char)0);
    case NC_UBYTE: return f((unsigned char)0);
    case NC_SHORT: return f((short)0);
    case NC_USHORT: return f((unsigned short)0);
    case NC_INT: return f(0);
    case NC_UINT: return f(0u);
    case NC_INT64: return f(0LL);
    case NC_UINT64: return f(0ULL);
    case NC_FLOAT: return f(0.0f);
    case NC_DOUBLE: return f(0.0);
    default: return makeError("not a numeric netCDF type");
  }
}

/// Size in bytes of one value of a netCDF numeric type (0 for non-numeric types).
std::size_t ncTypeSize(nc_type type);
/// True for the integer and floating-point netCDF types.
bool ncTypeIsNumeric(nc_type type);

}  // namespace atmoglobe::volume
