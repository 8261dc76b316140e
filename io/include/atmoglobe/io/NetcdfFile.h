#pragma once
// A small RAII wrapper over netCDF-C for the radar readers (CfRadial, ODIM_H5 through
// netCDF-C's HDF5 layer) and the forecast-grid reader (volume/GridReader.h).
//
// Threads: every member that calls netCDF-C (open, openMemory, the queries, the reads, the
// destructor) holds netcdfLibraryMutex() (NetcdfLock.h) while it does, so handles may be used on
// any thread. Code that calls netCDF-C itself on root() or an NcVar's ids holds it too.
//
// Every failure comes back as a Result whose message names the file and, where there is
// one, the group/variable/attribute ("FILE: variable '/dataset1/data1/data': ...").
// Reads into memory go through checkReadable(), which refuses element counts that the
// file cannot hold (see there), so a header that claims gigabytes never turns into a
// gigabyte allocation.
//
// Every data read (readSlab, readAll, readText) adds the bytes it asked for, in the variable's
// stored type (elements x element size, before any decompression), to dataBytesRead(): the
// grid reader reports it so that a test can show a crop costs what the crop holds.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/io/NetcdfLock.h>

#include <netcdf.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace atmoglobe::io {

/// A variable found in a group: ids, type and shape (dimension lengths as the file gives them).
struct NcVar {
  int groupId = -1;
  int varId = -1;
  std::string name;  ///< full path for messages, e.g. "/dataset1/data1/data"
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
  /// A gzip- or bzip2-wrapped file (Compression.h) is decompressed into memory and opened there
  /// (openMemory); its messages then start "PATH (gzip): ".
  static Result<NetcdfFile> open(const std::string& path);

  /// Opens a netCDF/HDF5 file image held in memory (netCDF-C's nc_open_mem), read-only. `label`
  /// names it in messages ("FILE (gzip)"); the handle keeps `bytes` alive until it closes.
  /// fileSizeBytes() is the image's size (the bound checkReadable() applies).
  static Result<NetcdfFile> openMemory(const std::string& label, std::shared_ptr<std::vector<unsigned char>> bytes);

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
  Status readSlab(const NcVar& var, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                  T* out) const;

  /// The same with a stride per dimension (nc_get_vars): element m of dimension d is index
  /// start[d] + m * stride[d]. Strides must be >= 1; the last element read must lie inside the
  /// shape. `out` must hold the product of `count`.
  template <class T>
  Status readSlab(const NcVar& var, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                  const std::vector<std::ptrdiff_t>& stride, T* out) const;

  /// Reads the whole variable converted to T, after checkReadable().
  template <class T>
  Result<std::vector<T>> readAll(const NcVar& var) const;

  /// Reads a character variable (or a row of a 2-D char variable: row index `row`), as text.
  Result<std::string> readText(const NcVar& var, std::size_t row) const;

  /// "PATH: " + what: the start of every message about this file.
  std::string message(const std::string& what) const { return path_ + ": " + what; }

  /// Bytes of variable data read through this handle so far: elements requested times the
  /// size of the stored type (uncompressed), summed over readSlab/readAll/readText. Metadata
  /// (attributes, dimensions) is not counted. HDF5 reads whole chunks from the disk, so the
  /// bytes that cross the disk can be larger for chunked variables (docs/grids.md).
  std::uint64_t dataBytesRead() const { return dataBytesRead_; }

 private:
  NetcdfFile(std::string path, int ncid, std::uintmax_t size, bool hdf5)
      : path_(std::move(path)), ncid_(ncid), fileSize_(size), hdf5_(hdf5) {}
  std::string attrLabel(int group, int varId, const std::string& name) const;
  /// Closes the HDF5 attribute identifiers that netCDF-C left open through this file (a leak
  /// of netCDF-C 4.9 / HDF5 1.10 on datasets with a non-dimension-scale CLASS attribute, e.g.
  /// every ODIM data array; see NetcdfFile.cpp), then nc_close.
  void closeLeakedAttributes();
  void close();

  std::string path_;
  int ncid_ = -1;
  std::uintmax_t fileSize_ = 0;
  bool hdf5_ = false;
  std::int64_t hdf5FileId_ = -1;                        ///< HDF5 file id that nc_open created (-1: unknown / not HDF5)
  std::shared_ptr<std::vector<unsigned char>> memory_;  ///< the image of an in-memory open (openMemory)
  mutable std::uint64_t dataBytesRead_ = 0;
};

/// Process-wide (every NetcdfFile, every thread): bytes of variable data read per variable name
/// (NcVar::name), counted as dataBytesRead() counts them, since the last resetNetcdfReadTally().
/// For tests that check a reader read only what it was asked for (a scene naming one field of
/// a many-field file reads that field's data and no other field's).
std::map<std::string, std::uint64_t> netcdfReadTally();
void resetNetcdfReadTally();

/// True when the file starts like a netCDF file: classic "CDF\x01", "CDF\x02", "CDF\x05", or the
/// HDF5 signature at offset 0, 512, 1024, 2048 ... (netCDF-4). False for anything else,
/// including a file that cannot be read. A gzip/bzip2-wrapped file is judged by its content (the
/// first 64 KiB, so an HDF5 user block of up to 32 KiB).
bool hasNetcdfSignature(const std::string& path);
/// The same test on bytes in memory (the signature offsets that lie inside them).
bool hasNetcdfSignature(const unsigned char* bytes, std::size_t size);

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

/// Decodes raw values of type T to floats: out[i] = one(static_cast<double>(raw[i])), where
/// `one` maps a raw value (as double) to its decoded float (scale/offset, fill -> kNoData ...).
/// For 8-bit types, and for 16-bit integer types when at least 65536 values are to be
/// decoded so that the table pays for itself, `one` is evaluated once per possible raw value
/// into a lookup table that apply() then indexes: bit-identical to calling `one` per element,
/// without the per-element double arithmetic. Other types call `one` per element (inlined).
template <class T, class F>
class RawDecoder {
 public:
  RawDecoder(const F& one, std::size_t valueCount) : one_(one) {
    if constexpr (kTableable) {
      if (sizeof(T) == 1 || valueCount >= kValues) {
        table_.resize(kValues);
        for (std::size_t u = 0; u < kValues; ++u)
          table_[u] = one_(static_cast<double>(static_cast<T>(static_cast<U>(u))));
      }
    }
  }
  void apply(const T* raw, std::size_t n, float* out) const {
    if constexpr (kTableable) {
      if (!table_.empty()) {
        const float* table = table_.data();
        for (std::size_t i = 0; i < n; ++i) out[i] = table[static_cast<U>(raw[i])];
        return;
      }
    }
    for (std::size_t i = 0; i < n; ++i) out[i] = one_(static_cast<double>(raw[i]));
  }

 private:
  static constexpr bool kTableable = std::is_integral_v<T> && (sizeof(T) == 1 || sizeof(T) == 2);
  using U = std::make_unsigned_t<std::conditional_t<kTableable, T, unsigned char>>;
  static constexpr std::size_t kValues = std::size_t{1} << (8 * sizeof(U));
  F one_;
  std::vector<float> table_;
};

/// Reads the hyperslab (start, count) of `var` in its stored type T and decodes its n values
/// (n = product of count) into out[0, n) with `decoder`. When T is no wider than a float, no
/// raw buffer is allocated: the raw values are read into the upper part of `out` and decoded
/// front to back through a small stack block (out[i] ends at byte 4(i+1), at or below where
/// raw value i+1 starts, so no raw value is overwritten before it is decoded); only 8-byte
/// types need a separate raw buffer. Same errors as readSlab().
template <class T, class F>
Status readSlabDecoded(const NetcdfFile& f, const NcVar& var, const std::vector<std::size_t>& start,
                       const std::vector<std::size_t>& count, const RawDecoder<T, F>& decoder, float* out,
                       std::size_t n) {
  if constexpr (sizeof(T) <= sizeof(float)) {
    auto* bytes = reinterpret_cast<unsigned char*>(out);
    const std::size_t rawOffset = (sizeof(float) - sizeof(T)) * n;  // a multiple of sizeof(T)
    if (auto st = f.readSlab<T>(var, start, count, reinterpret_cast<T*>(bytes + rawOffset)); !st) return st;
    constexpr std::size_t kBlock = 2048;
    T block[kBlock];
    for (std::size_t i = 0; i < n; i += kBlock) {
      const std::size_t m = std::min(kBlock, n - i);
      std::memcpy(block, bytes + rawOffset + i * sizeof(T), m * sizeof(T));
      decoder.apply(block, m, out + i);
    }
    return Ok{};
  } else {
    std::unique_ptr<T[]> raw(new T[n]);  // uninitialised: the read fills it
    if (auto st = f.readSlab<T>(var, start, count, raw.get()); !st) return st;
    decoder.apply(raw.get(), n, out);
    return Ok{};
  }
}

/// Size in bytes of one value of a netCDF numeric type (0 for non-numeric types).
std::size_t ncTypeSize(nc_type type);
/// True for the integer and floating-point netCDF types.
bool ncTypeIsNumeric(nc_type type);

}  // namespace atmoglobe::io
