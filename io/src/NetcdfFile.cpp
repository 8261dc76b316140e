#include <atmoglobe/io/NetcdfFile.h>

#include <atmoglobe/io/Compression.h>
#include <atmoglobe/io/Hdf5Guard.h>

#include <netcdf_filter.h>
#include <netcdf_mem.h>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <system_error>

namespace atmoglobe::io {

namespace {
constexpr std::size_t kMaxAttributeChars = std::size_t{1} << 20;

std::string ncError(int status) { return nc_strerror(status); }

// --- Work-around for an HDF5 identifier leak under netCDF-C ---
// Measured with netCDF-C 4.9.0 over HDF5 1.10.8: every nc_open of an ODIM_H5 file leaves one
// HDF5 attribute identifier (and one datatype identifier) open per dataset whose CLASS
// attribute is not DIMENSION_SCALE (ODIM's CLASS="IMAGE"): 112 per open of a 112-dataset
// volume, still open after nc_close. HDF5 scans every open attribute identifier of the process
// on each attribute open (twice), so each leaked identifier makes every later attribute read
// of every file slower (after 23 opens of that volume, one MLL CfRadial read took ~4x as long).
// NetcdfFile therefore notes the HDF5 file identifier that nc_open created and, just before
// nc_close, closes the attribute identifiers still open through it (netCDF-C holds none open
// between calls: a fresh open of a CfRadial file shows 0). Not for a file the HDF5 guard found
// damaged (Hdf5Guard.h): after failed attribute reads, closing the ids left open crashed libhdf5
// later in the same process (fuzz_odim: SEGV in H5A__close after a few hundred corrupt files; with
// no clean-up, none in 5,830). The HDF5 functions are looked up
// at run time in the HDF5 library that netCDF-C already loaded, so the build does not change
// and a netCDF-C built without HDF5 just skips this. hid_t is 64-bit from HDF5 1.10 on: older
// versions are skipped.
namespace h5 {
using hid_t = std::int64_t;
constexpr unsigned kObjFile = 0x0001u, kObjAttr = 0x0010u, kObjLocal = 0x0020u;
constexpr hid_t kObjAll = 0x001F;  // H5F_OBJ_ALL as a file id: every open file
struct Api {
  long (*getObjCount)(hid_t, unsigned) = nullptr;                     // H5Fget_obj_count (ssize_t)
  long (*getObjIds)(hid_t, unsigned, std::size_t, hid_t*) = nullptr;  // H5Fget_obj_ids (ssize_t)
  int (*attrClose)(hid_t) = nullptr;                                  // H5Aclose
  bool ok() const { return getObjCount && getObjIds && attrClose; }
};
const Api& api() {
  static const Api a = [] {
    Api r;
    using Version = int (*)(unsigned*, unsigned*, unsigned*);
    auto version = reinterpret_cast<Version>(dlsym(RTLD_DEFAULT, "H5get_libversion"));
    unsigned major = 0, minor = 0, release = 0;
    if (!version || version(&major, &minor, &release) < 0 || major < 1 || (major == 1 && minor < 10)) return r;
    r.getObjCount = reinterpret_cast<decltype(r.getObjCount)>(dlsym(RTLD_DEFAULT, "H5Fget_obj_count"));
    r.getObjIds = reinterpret_cast<decltype(r.getObjIds)>(dlsym(RTLD_DEFAULT, "H5Fget_obj_ids"));
    r.attrClose = reinterpret_cast<decltype(r.attrClose)>(dlsym(RTLD_DEFAULT, "H5Aclose"));
    return r;
  }();
  return a;
}
/// Ids of the open objects of `types` in `file` (kObjAll: all files).
std::vector<hid_t> openIds(hid_t file, unsigned types) {
  const Api& a = api();
  if (!a.ok()) return {};
  const long n = a.getObjCount(file, types);
  if (n <= 0) return {};
  std::vector<hid_t> ids(static_cast<std::size_t>(n));
  const long got = a.getObjIds(file, types, ids.size(), ids.data());
  ids.resize(got > 0 ? std::min(ids.size(), static_cast<std::size_t>(got)) : 0);
  return ids;
}
}  // namespace h5

void trimRight(std::string& s) {
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ' || s.back() == '\n' || s.back() == '\t')) s.pop_back();
  // Fixed-length HDF5 strings may hold a NUL before the declared end.
  const auto nul = s.find('\0');
  if (nul != std::string::npos) s.resize(nul);
}
}  // namespace

std::size_t NcVar::elementCount() const {
  std::size_t n = 1;
  for (std::size_t d : shape) n *= d;  // overflow guarded by checkReadable()
  return n;
}

std::size_t ncTypeSize(nc_type type) {
  switch (type) {
    case NC_BYTE:
    case NC_UBYTE:
    case NC_CHAR: return 1;
    case NC_SHORT:
    case NC_USHORT: return 2;
    case NC_INT:
    case NC_UINT:
    case NC_FLOAT: return 4;
    case NC_INT64:
    case NC_UINT64:
    case NC_DOUBLE: return 8;
    default: return 0;
  }
}

bool ncTypeIsNumeric(nc_type type) { return type != NC_CHAR && ncTypeSize(type) != 0; }

namespace {
/// nc_open / nc_open_mem with the HDF5 file id that the open added (see closeLeakedAttributes()).
struct Opened {
  int status = NC_NOERR;
  int ncid = -1;
  bool hdf5 = false;
  std::int64_t hdf5FileId = -1;
};
template <class OpenFn>
Opened openTracked(OpenFn&& openFn) {
  Opened o;
  std::vector<h5::hid_t> filesBefore = h5::openIds(h5::kObjAll, h5::kObjFile);
  std::sort(filesBefore.begin(), filesBefore.end());
  o.status = openFn(&o.ncid);
  if (o.status != NC_NOERR) return o;
  int mode = 0;
  int formatx = 0;
  if (nc_inq_format_extended(o.ncid, &formatx, &mode) == NC_NOERR) o.hdf5 = (formatx == NC_FORMATX_NC_HDF5);
  if (o.hdf5) {
    // The one HDF5 file id that the open added is this file's.
    std::vector<h5::hid_t> added;
    for (h5::hid_t id : h5::openIds(h5::kObjAll, h5::kObjFile))
      if (!std::binary_search(filesBefore.begin(), filesBefore.end(), id)) added.push_back(id);
    if (added.size() == 1) o.hdf5FileId = added.front();
  }
  return o;
}

/// Classic-format headers (CDF-1/2/5) carry names of any length, and netCDF-C 4.9.0 copies them
/// whole into the caller's buffer (nc_inq_dimname and the like), where every caller, here and in
/// the grid reader, has NC_MAX_NAME + 1 bytes: a corrupt header overflowed them (fuzz_grid; a
/// 538-byte file naming a dimension with 4099 characters). So the header is walked here, before
/// netCDF-C opens the file, and a name over NC_MAX_NAME is refused. Returns what is wrong, or ""
/// (also for headers this walk cannot follow: netCDF-C then judges them). netCDF-4/HDF5 names
/// are bounded by the netCDF-4 layer.
/// `totalBytes`: the whole file's size (`size` may be only its head). A count of dimensions,
/// attributes or variables that the rest of the file cannot hold (each entry takes 8 bytes at
/// least) is refused too: netCDF-C allocated such counts before reading them (fuzz_grid: a 9 GB
/// calloc from a 20 kB file).
std::string classicHeaderProblem(const unsigned char* p, std::size_t size, std::size_t totalBytes) {
  if (size < 8 || p[0] != 'C' || p[1] != 'D' || p[2] != 'F') return {};
  const int version = p[3];
  if (version != 1 && version != 2 && version != 5) return {};
  const std::size_t countBytes = version == 5 ? 8 : 4;  // nelems, name lengths, dim lengths
  std::size_t at = 4 + countBytes;                      // magic, numrecs
  bool ran = false;                                     // ran past the bytes we have (or gave up)
  bool pastEnd = false;                                 // ran past them reading the header
  auto get = [&](std::size_t n) -> std::uint64_t {
    if (ran || at + n > size) {
      pastEnd = pastEnd || !ran;
      ran = true;
      return 0;
    }
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) v = (v << 8) | p[at + i];
    at += n;
    return v;
  };
  auto skip = [&](std::uint64_t n) {
    if (ran || n > size - at) {
      pastEnd = pastEnd || !ran;
      ran = true;
      return;
    }
    at += static_cast<std::size_t>(n);
  };
  auto pad4 = [](std::uint64_t n) { return (n + 3) / 4 * 4; };
  std::string problem;
  auto count = [&](const char* what) -> std::uint64_t {
    const std::uint64_t n = get(countBytes);
    if (!ran && n > (totalBytes - std::min(at, totalBytes)) / 8) {
      if (problem.empty())
        problem = std::to_string(n) + " " + what + " claimed in a file of " + std::to_string(totalBytes) + " bytes";
      ran = true;
      return 0;
    }
    return n;
  };
  auto name = [&](const char* what) {
    const std::uint64_t n = get(countBytes);
    if (!ran && n > NC_MAX_NAME && problem.empty())
      problem = std::string("a ") + what + " name of " + std::to_string(n) + " characters (at most " +
                std::to_string(NC_MAX_NAME) + ")";
    skip(pad4(n));
  };
  auto typeBytes = [](std::uint64_t t) -> std::uint64_t {
    switch (t) {
      case NC_BYTE:
      case NC_CHAR:
      case NC_UBYTE: return 1;
      case NC_SHORT:
      case NC_USHORT: return 2;
      case NC_INT:
      case NC_FLOAT:
      case NC_UINT: return 4;
      case NC_DOUBLE:
      case NC_INT64:
      case NC_UINT64: return 8;
      default: return 0;
    }
  };
  auto attributes = [&]() {
    get(4);  // NC_ATTRIBUTE or ZERO
    const std::uint64_t n = count("attributes");
    for (std::uint64_t a = 0; a < n && !ran && problem.empty(); ++a) {
      name("attribute");
      const std::uint64_t type = get(4);
      const std::uint64_t bytes = typeBytes(type);
      const std::uint64_t values = get(countBytes);
      // Classic files know NC_BYTE..NC_DOUBLE (1-6), CDF-5 also 7-11. netCDF-C 4.9.0 crashed
      // (SEGV in NC_hashmapfree) freeing a header whose attribute had type 12 (fuzz_grid).
      if (!ran && (bytes == 0 || (version != 5 && type > NC_DOUBLE))) {
        if (problem.empty()) problem = "an attribute of unknown type " + std::to_string(type);
        ran = true;
        return;
      }
      if (!ran && values > (totalBytes - std::min(at, totalBytes)) / bytes) {
        if (problem.empty())
          problem = "an attribute of " + std::to_string(values) + " values claimed in a file of " +
                    std::to_string(totalBytes) + " bytes";
        return;
      }
      skip(pad4(values * bytes));
    }
  };
  get(4);  // NC_DIMENSION or ZERO
  const std::uint64_t ndims = count("dimensions");
  std::vector<std::uint64_t> dimLengths;  // 0: the record dimension
  for (std::uint64_t d = 0; d < ndims && !ran && problem.empty(); ++d) {
    name("dimension");
    dimLengths.push_back(get(countBytes));
  }
  attributes();
  get(4);  // NC_VARIABLE or ZERO
  const std::uint64_t nvars = count("variables");
  for (std::uint64_t v = 0; v < nvars && !ran && problem.empty(); ++v) {
    name("variable");
    const std::uint64_t rank = get(countBytes);
    if (!ran && rank > (totalBytes - std::min(at, totalBytes)) / 4) {
      problem = "a variable of " + std::to_string(rank) + " dimensions claimed in a file of " +
                std::to_string(totalBytes) + " bytes";
      break;
    }
    // Dimension ids must name dimensions, and the record dimension (length 0) may only come
    // first: netCDF-C 4.9.0 divided by the product of the lengths checking a variable's size
    // (SIGFPE in NC_check_vlen, fuzz_grid).
    for (std::uint64_t k = 0; k < rank && !ran && problem.empty(); ++k) {
      const std::uint64_t id = get(countBytes);
      if (ran) break;
      if (id >= dimLengths.size())
        problem = "a variable uses dimension id " + std::to_string(id) + " of " + std::to_string(dimLengths.size());
      else if (k > 0 && dimLengths[static_cast<std::size_t>(id)] == 0)
        problem = "a variable has the record dimension other than first";
    }
    if (!problem.empty()) break;
    attributes();
    const std::uint64_t type = get(4);  // nc_type
    if (!ran && problem.empty() && (typeBytes(type) == 0 || (version != 5 && type > NC_DOUBLE))) {
      problem = "a variable of unknown type " + std::to_string(type);
      break;
    }
    get(countBytes);            // vsize
    get(version == 1 ? 4 : 8);  // begin
  }
  // A header that needs more bytes than the whole file holds (netCDF-C would find it truncated).
  if (problem.empty() && pastEnd && size == totalBytes)
    problem = "the header runs past the end of the file (" + std::to_string(totalBytes) + " bytes; truncated?)";
  return problem;
}

/// The HDF5 guard (Hdf5Guard.h) for an HDF5 file: "" when it may be opened in this process,
/// else the error. `damaged`: set when the guard's walk met failing library calls.
std::string hdf5GuardProblem(const std::string& label, const unsigned char* head, std::size_t headBytes,
                             const unsigned char* memory, std::size_t memoryBytes, bool* damaged) {
  if (!looksLikeHdf5(head, headBytes)) return {};
  auto settings = hdf5GuardSettingsFromEnvironment();
  if (!settings) return label + ": " + settings.error();
  const Hdf5GuardOutcome o = checkHdf5InChild(label, memory, memoryBytes, *settings);
  *damaged = o.damaged;
  if (o.kind == Hdf5GuardOutcome::Kind::Crashed || o.kind == Hdf5GuardOutcome::Kind::TimedOut)
    return label + ": cannot open as netCDF/HDF5: " + o.message;
  return {};  // passed, refused cleanly (the open below says why), or not run (fork failed)
}

std::string openFailure(const std::string& label, int st) {
  const bool corrupt = st == NC_EHDFERR || st == NC_ENOTNC || st == NC_EINVAL || st == NC_ETRUNC;
  return label + ": cannot open as netCDF/HDF5: " + ncError(st) +
         (corrupt ? " (the file may be truncated or corrupt)" : "");
}
}  // namespace

Result<NetcdfFile> NetcdfFile::open(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return makeError(path + ": cannot read file: " + ec.message());
  auto wrapper = fileCompression(path);
  if (!wrapper) return wrapper.forwardError();
  if (*wrapper != Compression::None) {
    auto content = readFileBytes(path);
    if (!content) return content.forwardError();
    return openMemory(content->label, std::make_shared<std::vector<unsigned char>>(std::move(content->bytes)));
  }
  bool damaged = false;
  {
    // The classic header's names, before netCDF-C reads them (classicHeaderProblem): the first
    // 16 MiB at most (a header that needs more is left to netCDF-C).
    std::vector<unsigned char> head = peekFileContent(path, std::min<std::size_t>(size, std::size_t{16} << 20));
    if (auto bad = classicHeaderProblem(head.data(), head.size(), size); !bad.empty())
      return makeError(path + ": not a valid netCDF file: " + bad + " (the header is corrupt)");
    if (auto bad = hdf5GuardProblem(path, head.data(), head.size(), nullptr, 0, &damaged); !bad.empty())
      return makeError(bad);
  }
  // The checks above read bytes only; the guard holds the lock around its fork (Hdf5Guard.cpp), so
  // other threads read on while its child walks the file.
  const NetcdfLock lock;
  const Opened o = openTracked([&](int* ncid) { return nc_open(path.c_str(), NC_NOWRITE, ncid); });
  if (o.status != NC_NOERR) return makeError(openFailure(path, o.status));
  NetcdfFile file(path, o.ncid, size, o.hdf5);
  file.hdf5FileId_ = damaged ? -1 : o.hdf5FileId;  // a damaged file's ids are left alone
  return file;
}

Result<NetcdfFile> NetcdfFile::openMemory(const std::string& label, std::shared_ptr<std::vector<unsigned char>> bytes) {
  if (!bytes || bytes->empty()) return makeError(label + ": cannot open as netCDF/HDF5: the content is empty");
  if (auto bad = classicHeaderProblem(bytes->data(), bytes->size(), bytes->size()); !bad.empty())
    return makeError(label + ": not a valid netCDF file: " + bad + " (the header is corrupt)");
  bool damaged = false;
  if (auto bad = hdf5GuardProblem(label, bytes->data(), bytes->size(), bytes->data(), bytes->size(), &damaged);
      !bad.empty())
    return makeError(bad);
  const NetcdfLock lock;
  const Opened o = openTracked(
      [&](int* ncid) { return nc_open_mem(label.c_str(), NC_NOWRITE, bytes->size(), bytes->data(), ncid); });
  if (o.status != NC_NOERR) return makeError(openFailure(label, o.status));
  NetcdfFile file(label, o.ncid, bytes->size(), o.hdf5);
  file.hdf5FileId_ = damaged ? -1 : o.hdf5FileId;  // a damaged file's ids are left alone
  file.memory_ = std::move(bytes);
  return file;
}

void NetcdfFile::closeLeakedAttributes() {
  if (hdf5FileId_ < 0) return;
  const h5::Api& a = h5::api();
  for (h5::hid_t id : h5::openIds(hdf5FileId_, h5::kObjAttr | h5::kObjLocal)) a.attrClose(id);
  hdf5FileId_ = -1;
}

void NetcdfFile::close() {
  if (ncid_ < 0) return;
  const NetcdfLock lock;
  closeLeakedAttributes();
  nc_close(ncid_);
  ncid_ = -1;
}

NetcdfFile::NetcdfFile(NetcdfFile&& other) noexcept
    : path_(std::move(other.path_)), ncid_(other.ncid_), fileSize_(other.fileSize_), hdf5_(other.hdf5_),
      hdf5FileId_(other.hdf5FileId_), memory_(std::move(other.memory_)), dataBytesRead_(other.dataBytesRead_) {
  other.ncid_ = -1;
  other.hdf5FileId_ = -1;
}

NetcdfFile& NetcdfFile::operator=(NetcdfFile&& other) noexcept {
  if (this != &other) {
    close();
    path_ = std::move(other.path_);
    ncid_ = other.ncid_;
    fileSize_ = other.fileSize_;
    hdf5_ = other.hdf5_;
    hdf5FileId_ = other.hdf5FileId_;
    memory_ = std::move(other.memory_);
    dataBytesRead_ = other.dataBytesRead_;
    other.ncid_ = -1;
    other.hdf5FileId_ = -1;
  }
  return *this;
}

NetcdfFile::~NetcdfFile() { close(); }

std::optional<int> NetcdfFile::findGroup(int parent, const std::string& name) const {
  const NetcdfLock lock;
  int id = -1;
  if (nc_inq_grp_ncid(parent, name.c_str(), &id) != NC_NOERR) return std::nullopt;
  return id;
}

std::vector<std::string> NetcdfFile::childGroupNames(int parent) const {
  const NetcdfLock lock;
  int n = 0;
  if (nc_inq_grps(parent, &n, nullptr) != NC_NOERR || n <= 0) return {};
  std::vector<int> ids(static_cast<std::size_t>(n));
  if (nc_inq_grps(parent, &n, ids.data()) != NC_NOERR) return {};
  std::vector<std::string> names;
  names.reserve(ids.size());
  for (int id : ids) {
    char buf[NC_MAX_NAME + 1] = {};
    if (nc_inq_grpname(id, buf) == NC_NOERR) names.emplace_back(buf);
  }
  return names;
}

std::string NetcdfFile::groupPath(int groupId) const {
  const NetcdfLock lock;
  std::size_t len = 0;
  if (nc_inq_grpname_full(groupId, &len, nullptr) != NC_NOERR) return "?";
  std::string s(len, '\0');
  if (nc_inq_grpname_full(groupId, &len, s.data()) != NC_NOERR) return "?";
  trimRight(s);
  return s;
}

std::optional<std::size_t> NetcdfFile::dimensionLength(int group, const std::string& name, int* dimId) const {
  const NetcdfLock lock;
  int id = -1;
  if (nc_inq_dimid(group, name.c_str(), &id) != NC_NOERR) return std::nullopt;
  std::size_t len = 0;
  if (nc_inq_dimlen(group, id, &len) != NC_NOERR) return std::nullopt;
  if (dimId) *dimId = id;
  return len;
}

namespace {
/// The NcVar of variable `varId` (named `name`) in `group`, whose path is `groupPath`.
/// One nc_inq_var for type, rank and dimension ids, one nc_inq_dimlen per dimension.
std::optional<NcVar> describeVariable(int group, int varId, const char* name, const std::string& groupPath) {
  NcVar v;
  v.groupId = group;
  v.varId = varId;
  v.name = (groupPath == "/" ? "/" : groupPath + "/") + name;
  int ndims = 0;
  int dimIds[NC_MAX_VAR_DIMS];
  if (nc_inq_var(group, varId, nullptr, &v.type, &ndims, dimIds, nullptr) != NC_NOERR || ndims < 0 ||
      ndims > NC_MAX_VAR_DIMS)
    return std::nullopt;
  v.dimIds.assign(dimIds, dimIds + ndims);
  v.shape.reserve(v.dimIds.size());
  for (int d : v.dimIds) {
    std::size_t len = 0;
    if (nc_inq_dimlen(group, d, &len) != NC_NOERR) return std::nullopt;
    v.shape.push_back(len);
  }
  return v;
}
}  // namespace

std::optional<NcVar> NetcdfFile::findVariable(int group, const std::string& name) const {
  const NetcdfLock lock;
  int varId = -1;
  if (nc_inq_varid(group, name.c_str(), &varId) != NC_NOERR) return std::nullopt;
  return describeVariable(group, varId, name.c_str(), groupPath(group));
}

Result<NcVar> NetcdfFile::variable(int group, const std::string& name) const {
  auto v = findVariable(group, name);
  if (!v) {
    const std::string gp = groupPath(group);
    return makeError(message("required variable '" + (gp == "/" ? "" : gp) + "/" + name + "' not found"));
  }
  return *v;
}

std::vector<NcVar> NetcdfFile::variables(int group) const {
  const NetcdfLock lock;
  int n = 0;
  if (nc_inq_varids(group, &n, nullptr) != NC_NOERR || n <= 0) return {};
  std::vector<int> ids(static_cast<std::size_t>(n));
  if (nc_inq_varids(group, &n, ids.data()) != NC_NOERR) return {};
  const std::string gp = groupPath(group);
  std::vector<NcVar> out;
  out.reserve(ids.size());
  for (int id : ids) {
    char buf[NC_MAX_NAME + 1] = {};
    if (nc_inq_varname(group, id, buf) != NC_NOERR) continue;
    if (auto v = describeVariable(group, id, buf, gp)) out.push_back(std::move(*v));
  }
  return out;
}

std::string NetcdfFile::attrLabel(int group, int varId, const std::string& name) const {
  const NetcdfLock lock;
  const std::string gp = groupPath(group);
  std::string owner = gp;
  if (varId != NC_GLOBAL) {
    char buf[NC_MAX_NAME + 1] = {};
    nc_inq_varname(group, varId, buf);
    owner = (gp == "/" ? "/" : gp + "/") + buf;
  }
  return "attribute '" + owner + (owner.back() == '/' ? "" : ":") + name + "'";
}

bool NetcdfFile::hasAttribute(int group, int varId, const std::string& name) const {
  const NetcdfLock lock;
  int id = -1;
  return nc_inq_attid(group, varId, name.c_str(), &id) == NC_NOERR;
}

Result<std::vector<double>> NetcdfFile::attributeDoubles(int group, int varId, const std::string& name,
                                                         std::size_t maxCount) const {
  const NetcdfLock lock;
  nc_type type = NC_NAT;
  std::size_t len = 0;
  int st = nc_inq_att(group, varId, name.c_str(), &type, &len);
  if (st != NC_NOERR) return makeError(message(attrLabel(group, varId, name) + " not found"));
  if (!ncTypeIsNumeric(type)) return makeError(message(attrLabel(group, varId, name) + " is not numeric"));
  if (len == 0 || len > maxCount)
    return makeError(message(attrLabel(group, varId, name) + " has " + std::to_string(len) + " values, expected 1 to " +
                             std::to_string(maxCount)));
  std::vector<double> values(len);
  st = nc_get_att_double(group, varId, name.c_str(), values.data());
  if (st != NC_NOERR && st != NC_ERANGE) return makeError(message(attrLabel(group, varId, name) + ": " + ncError(st)));
  return values;
}

Result<double> NetcdfFile::attributeDouble(int group, int varId, const std::string& name) const {
  auto v = attributeDoubles(group, varId, name, 1);
  if (!v) return v.forwardError();
  return v->front();
}

Result<std::string> NetcdfFile::attributeString(int group, int varId, const std::string& name) const {
  const NetcdfLock lock;
  nc_type type = NC_NAT;
  std::size_t len = 0;
  int st = nc_inq_att(group, varId, name.c_str(), &type, &len);
  if (st != NC_NOERR) return makeError(message(attrLabel(group, varId, name) + " not found"));
  if (type == NC_CHAR) {
    if (len > kMaxAttributeChars) return makeError(message(attrLabel(group, varId, name) + " is too long"));
    std::string s(len, '\0');
    if (len > 0 && (st = nc_get_att_text(group, varId, name.c_str(), s.data())) != NC_NOERR)
      return makeError(message(attrLabel(group, varId, name) + ": " + ncError(st)));
    trimRight(s);
    return s;
  }
  if (type == NC_STRING) {
    if (len != 1)
      return makeError(
          message(attrLabel(group, varId, name) + " holds " + std::to_string(len) + " strings, expected 1"));
    char* p = nullptr;
    if ((st = nc_get_att_string(group, varId, name.c_str(), &p)) != NC_NOERR)
      return makeError(message(attrLabel(group, varId, name) + ": " + ncError(st)));
    std::string s = p ? std::string(p) : std::string();
    nc_free_string(1, &p);
    trimRight(s);
    return s;
  }
  return makeError(message(attrLabel(group, varId, name) + " is not text"));
}

Status NetcdfFile::checkReadable(const NcVar& var, std::size_t elementCount, std::size_t elementBytes) const {
  const NetcdfLock lock;
  // Overflow-safe product of the requested element count with the element size.
  if (elementCount > kMaxElementsPerRead)
    return makeError(message("variable '" + var.name + "' claims " + std::to_string(elementCount) +
                             " values, more than the " + std::to_string(kMaxElementsPerRead) + " a read may hold"));
  const double bytes = static_cast<double>(elementCount) * static_cast<double>(elementBytes);
  double factor = 1.0;
  if (hdf5_) {
    int storage = NC_CONTIGUOUS;
    nc_inq_var_chunking(var.groupId, var.varId, &storage, nullptr);
    std::size_t nfilters = 0;
    nc_inq_var_filter_ids(var.groupId, var.varId, &nfilters, nullptr);
    if (storage != NC_CONTIGUOUS || nfilters > 0) factor = kMaxCompressionRatio;
  }
  if (bytes > static_cast<double>(fileSize_) * factor)
    return makeError(message("variable '" + var.name + "' claims " + std::to_string(elementCount) + " values (" +
                             std::to_string(static_cast<unsigned long long>(bytes)) + " bytes), more than the " +
                             std::to_string(fileSize_) + "-byte file can hold"));
  return Ok{};
}

namespace {
template <class T>
int getVara(int g, int v, const std::size_t* s, const std::size_t* c, T* out) {
  if constexpr (std::is_same_v<T, signed char> || std::is_same_v<T, std::int8_t>)
    return nc_get_vara_schar(g, v, s, c, reinterpret_cast<signed char*>(out));
  else if constexpr (std::is_same_v<T, unsigned char> || std::is_same_v<T, std::uint8_t>)
    return nc_get_vara_uchar(g, v, s, c, reinterpret_cast<unsigned char*>(out));
  else if constexpr (std::is_same_v<T, short>) return nc_get_vara_short(g, v, s, c, out);
  else if constexpr (std::is_same_v<T, unsigned short>) return nc_get_vara_ushort(g, v, s, c, out);
  else if constexpr (std::is_same_v<T, int>) return nc_get_vara_int(g, v, s, c, out);
  else if constexpr (std::is_same_v<T, unsigned int>) return nc_get_vara_uint(g, v, s, c, out);
  else if constexpr (std::is_same_v<T, long long>) return nc_get_vara_longlong(g, v, s, c, out);
  else if constexpr (std::is_same_v<T, unsigned long long>) return nc_get_vara_ulonglong(g, v, s, c, out);
  else if constexpr (std::is_same_v<T, float>) return nc_get_vara_float(g, v, s, c, out);
  else if constexpr (std::is_same_v<T, double>) return nc_get_vara_double(g, v, s, c, out);
  else static_assert(sizeof(T) == 0, "unsupported element type");
}
template <class T>
int getVars(int g, int v, const std::size_t* s, const std::size_t* c, const std::ptrdiff_t* d, T* out) {
  if constexpr (std::is_same_v<T, signed char> || std::is_same_v<T, std::int8_t>)
    return nc_get_vars_schar(g, v, s, c, d, reinterpret_cast<signed char*>(out));
  else if constexpr (std::is_same_v<T, unsigned char> || std::is_same_v<T, std::uint8_t>)
    return nc_get_vars_uchar(g, v, s, c, d, reinterpret_cast<unsigned char*>(out));
  else if constexpr (std::is_same_v<T, short>) return nc_get_vars_short(g, v, s, c, d, out);
  else if constexpr (std::is_same_v<T, unsigned short>) return nc_get_vars_ushort(g, v, s, c, d, out);
  else if constexpr (std::is_same_v<T, int>) return nc_get_vars_int(g, v, s, c, d, out);
  else if constexpr (std::is_same_v<T, unsigned int>) return nc_get_vars_uint(g, v, s, c, d, out);
  else if constexpr (std::is_same_v<T, long long>) return nc_get_vars_longlong(g, v, s, c, d, out);
  else if constexpr (std::is_same_v<T, unsigned long long>) return nc_get_vars_ulonglong(g, v, s, c, d, out);
  else if constexpr (std::is_same_v<T, float>) return nc_get_vars_float(g, v, s, c, d, out);
  else if constexpr (std::is_same_v<T, double>) return nc_get_vars_double(g, v, s, c, d, out);
  else static_assert(sizeof(T) == 0, "unsupported element type");
}

std::uint64_t slabBytes(const NcVar& var, const std::vector<std::size_t>& count) {
  std::uint64_t n = std::max<std::size_t>(ncTypeSize(var.type), 1);
  for (std::size_t c : count) n *= c;
  return n;
}
}  // namespace

namespace {
std::mutex& tallyMutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, std::uint64_t>& tally() {
  static std::map<std::string, std::uint64_t> t;
  return t;
}
void tallyRead(const std::string& variable, std::uint64_t bytes) {
  const std::lock_guard<std::mutex> lock(tallyMutex());
  tally()[variable] += bytes;
}
}  // namespace

std::map<std::string, std::uint64_t> netcdfReadTally() {
  const std::lock_guard<std::mutex> lock(tallyMutex());
  return tally();
}

void resetNetcdfReadTally() {
  const std::lock_guard<std::mutex> lock(tallyMutex());
  tally().clear();
}

template <class T>
Status NetcdfFile::readSlab(const NcVar& var, const std::vector<std::size_t>& start,
                            const std::vector<std::size_t>& count, T* out) const {
  assert(start.size() == var.shape.size() && count.size() == var.shape.size());
  for (std::size_t d = 0; d < var.shape.size(); ++d) {
    if (start[d] > var.shape[d] || count[d] > var.shape[d] - start[d])
      return makeError(
          message("variable '" + var.name + "': read outside its shape (dimension " + std::to_string(d) + ")"));
  }
  const int st = [&] {
    const NetcdfLock lock;
    return getVara(var.groupId, var.varId, start.data(), count.data(), out);
  }();
  dataBytesRead_ += slabBytes(var, count);
  tallyRead(var.name, slabBytes(var, count));
  if (st != NC_NOERR && st != NC_ERANGE)
    return makeError(message("reading variable '" + var.name + "': " + ncError(st)));
  if (st == NC_ERANGE)
    return makeError(message("reading variable '" + var.name + "': values out of range for the reader's type"));
  return Ok{};
}

template <class T>
Status NetcdfFile::readSlab(const NcVar& var, const std::vector<std::size_t>& start,
                            const std::vector<std::size_t>& count, const std::vector<std::ptrdiff_t>& stride,
                            T* out) const {
  assert(start.size() == var.shape.size() && count.size() == var.shape.size() && stride.size() == var.shape.size());
  for (std::size_t d = 0; d < var.shape.size(); ++d) {
    if (stride[d] < 1)
      return makeError(message("variable '" + var.name + "': stride below 1 (dimension " + std::to_string(d) + ")"));
    if (count[d] == 0) continue;
    const std::size_t step = static_cast<std::size_t>(stride[d]);
    if (start[d] >= var.shape[d] || (count[d] - 1) > (var.shape[d] - 1 - start[d]) / step)
      return makeError(
          message("variable '" + var.name + "': read outside its shape (dimension " + std::to_string(d) + ")"));
  }
  const int st = [&] {
    const NetcdfLock lock;
    return getVars(var.groupId, var.varId, start.data(), count.data(), stride.data(), out);
  }();
  dataBytesRead_ += slabBytes(var, count);
  tallyRead(var.name, slabBytes(var, count));
  if (st != NC_NOERR && st != NC_ERANGE)
    return makeError(message("reading variable '" + var.name + "': " + ncError(st)));
  if (st == NC_ERANGE)
    return makeError(message("reading variable '" + var.name + "': values out of range for the reader's type"));
  return Ok{};
}

template <class T>
Result<std::vector<T>> NetcdfFile::readAll(const NcVar& var) const {
  std::size_t n = 1;
  for (std::size_t d : var.shape) {
    if (d != 0 && n > kMaxElementsPerRead / d) {
      return makeError(
          message("variable '" + var.name + "' claims more than " + std::to_string(kMaxElementsPerRead) + " values"));
    }
    n *= d;
  }
  if (auto ok = checkReadable(var, n, std::max<std::size_t>(ncTypeSize(var.type), 1)); !ok) return ok.forwardError();
  std::vector<T> out(n);
  if (n == 0) return out;
  std::vector<std::size_t> start(var.shape.size(), 0);
  if (auto st = readSlab(var, start, var.shape, out.data()); !st) return st.forwardError();
  return out;
}

Result<std::string> NetcdfFile::readText(const NcVar& var, std::size_t row) const {
  const NetcdfLock lock;
  if (var.type == NC_CHAR) {
    if (var.shape.empty() || var.shape.size() > 2)
      return makeError(message("variable '" + var.name + "' is not a text array"));
    std::vector<std::size_t> start(var.shape.size(), 0), count = var.shape;
    if (var.shape.size() == 2) {
      if (row >= var.shape[0]) return makeError(message("variable '" + var.name + "': row out of range"));
      start[0] = row;
      count[0] = 1;
    }
    const std::size_t len = count.back();
    if (len > kMaxAttributeChars) return makeError(message("variable '" + var.name + "' is too long"));
    std::string s(len, '\0');
    const int st = nc_get_vara_text(var.groupId, var.varId, start.data(), count.data(), s.data());
    dataBytesRead_ += len;
    tallyRead(var.name, len);
    if (st != NC_NOERR) return makeError(message("reading variable '" + var.name + "': " + ncError(st)));
    trimRight(s);
    return s;
  }
  if (var.type == NC_STRING) {
    if (var.shape.size() > 1) return makeError(message("variable '" + var.name + "' is not a string array"));
    std::vector<std::size_t> start(var.shape.size(), 0), count(var.shape.size(), 1);
    if (var.shape.size() == 1) {
      if (row >= var.shape[0]) return makeError(message("variable '" + var.name + "': row out of range"));
      start[0] = row;
    }
    char* p = nullptr;
    const int st = nc_get_vara_string(var.groupId, var.varId, start.data(), count.data(), &p);
    if (st == NC_NOERR && p) dataBytesRead_ += std::strlen(p), tallyRead(var.name, std::strlen(p));
    if (st != NC_NOERR) return makeError(message("reading variable '" + var.name + "': " + ncError(st)));
    std::string s = p ? std::string(p) : std::string();
    nc_free_string(1, &p);
    trimRight(s);
    return s;
  }
  return makeError(message("variable '" + var.name + "' is not text"));
}

bool hasNetcdfSignature(const unsigned char* bytes, std::size_t size) {
  if (size >= 4 && bytes[0] == 'C' && bytes[1] == 'D' && bytes[2] == 'F' &&
      (bytes[3] == 1 || bytes[3] == 2 || bytes[3] == 5))
    return true;
  // HDF5 puts its superblock at 0, 512, 1024, 2048 ... (a user block before it).
  constexpr std::array<unsigned char, 8> kHdf5 = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  for (std::size_t off = 0; off + 8 <= size; off = (off == 0 ? 512 : off * 2)) {
    if (std::memcmp(bytes + off, kHdf5.data(), 8) == 0) return true;
  }
  return false;
}

bool hasNetcdfSignature(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::array<unsigned char, 8> head{};
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  if (compressionOf(head.data(), static_cast<std::size_t>(in.gcount())) != Compression::None) {
    const std::vector<unsigned char> content = peekFileContent(path, std::size_t{1} << 16);
    return hasNetcdfSignature(content.data(), content.size());
  }
  if (in.gcount() >= 4 && head[0] == 'C' && head[1] == 'D' && head[2] == 'F' &&
      (head[3] == 1 || head[3] == 2 || head[3] == 5))
    return true;
  // HDF5 puts its superblock at 0, 512, 1024, 2048 ... (a user block before it).
  constexpr std::array<unsigned char, 8> kHdf5 = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return false;
  for (std::uintmax_t off = 0; off + 8 <= size; off = (off == 0 ? 512 : off * 2)) {
    in.clear();
    in.seekg(static_cast<std::streamoff>(off));
    if (!in.read(reinterpret_cast<char*>(head.data()), 8)) return false;
    if (head == kHdf5) return true;
  }
  return false;
}

#define ATMOGLOBE_NC_INSTANTIATE(T)                                                                                \
  template Status NetcdfFile::readSlab<T>(const NcVar&, const std::vector<std::size_t>&,                           \
                                          const std::vector<std::size_t>&, T*) const;                              \
  template Status NetcdfFile::readSlab<T>(const NcVar&, const std::vector<std::size_t>&,                           \
                                          const std::vector<std::size_t>&, const std::vector<std::ptrdiff_t>&, T*) \
      const;                                                                                                       \
  template Result<std::vector<T>> NetcdfFile::readAll<T>(const NcVar&) const;
ATMOGLOBE_NC_INSTANTIATE(signed char)
ATMOGLOBE_NC_INSTANTIATE(unsigned char)
ATMOGLOBE_NC_INSTANTIATE(short)
ATMOGLOBE_NC_INSTANTIATE(unsigned short)
ATMOGLOBE_NC_INSTANTIATE(int)
ATMOGLOBE_NC_INSTANTIATE(unsigned int)
ATMOGLOBE_NC_INSTANTIATE(long long)
ATMOGLOBE_NC_INSTANTIATE(unsigned long long)
ATMOGLOBE_NC_INSTANTIATE(float)
ATMOGLOBE_NC_INSTANTIATE(double)
#undef ATMOGLOBE_NC_INSTANTIATE

}  // namespace atmoglobe::io
