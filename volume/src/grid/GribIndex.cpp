// The index of a GRIB file's messages: one pass with ecCodes at the first open records each
// message's byte offset and length and the keys that place it in a variable (shortName,
// typeOfLevel, level, times, step, member, grid); the index is kept in the cache directory
// (never beside the data), keyed by the file's absolute path, size and modification time, so
// that a later open reads the index and then only the messages it needs.
#include "GribInternal.h"

#include <atmoglobe/volume/RadarVolumeSet.h>

#include <atmoglobe/globe/AtomicFile.h>
#include <atmoglobe/io/Compression.h>

#include <eccodes.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>

namespace atmoglobe::volume::grib {

namespace {

/// The largest forecast step (in the message's step units) the index takes (see scan).
constexpr long kMaxStepUnits = 10'000'000;

/// Bumped when the index's content changes meaning: an index of another version is rebuilt.
constexpr int kIndexVersion = 2;  // 2: numberOfPoints

/// ecCodes' handler of a failed internal check: throws (GribInternal.h, EcCodesCheckFailed).
void throwEcCodesCheck(const char* message) {
  throw EcCodesCheckFailed(message ? message : "ecCodes assertion failed");
}

/// ecCodes' default context is shared: one caller at a time (reads may run on loader threads).
/// The first use installs the handler of failed checks, before any call into ecCodes.
std::mutex& ecCodesMutex() {
  static std::mutex m;
  static const bool handlerSet = [] {
    codes_set_codes_assertion_failed_proc(&throwEcCodesCheck);
    return true;
  }();
  (void)handlerSet;
  return m;
}

std::string getString(codes_handle* h, const char* key) {
  char buf[256];
  std::size_t len = sizeof buf;
  if (codes_get_string(h, key, buf, &len) != CODES_SUCCESS) return {};
  return std::string(buf);
}

long getLong(codes_handle* h, const char* key, long fallback) {
  long v = 0;
  if (codes_get_long(h, key, &v) != CODES_SUCCESS || v == CODES_MISSING_LONG) return fallback;
  return v;
}

/// FNV-1a 64: a stable name for the cache file of a path (std::hash is not stable across builds).
std::string pathHash(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

/// What identifies the file's version: absolute path, size and modification time.
struct FileStamp {
  std::string absolutePath;
  std::uint64_t size = 0;
  std::int64_t mtimeNs = 0;
};

Result<FileStamp> stampOf(const std::string& path) {
  std::error_code ec;
  FileStamp s;
  s.absolutePath = std::filesystem::absolute(path, ec).lexically_normal().string();
  if (ec) return makeError(path + ": " + ec.message());
  s.size = std::filesystem::file_size(path, ec);
  if (ec) return makeError(path + ": cannot read: " + ec.message());
  const auto t = std::filesystem::last_write_time(path, ec);
  if (ec) return makeError(path + ": cannot read: " + ec.message());
  s.mtimeNs = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  return s;
}

nlohmann::json toJson(const GribMessage& m) {
  return {{"offset", m.offset},
          {"length", m.length},
          {"shortName", m.shortName},
          {"typeOfLevel", m.typeOfLevel},
          {"gridType", m.gridType},
          {"name", m.name},
          {"units", m.units},
          {"level", m.level},
          {"dataDate", m.dataDate},
          {"dataTime", m.dataTime},
          {"validityDate", m.validityDate},
          {"validityTime", m.validityTime},
          {"stepRange", m.stepRange},
          {"endStep", m.endStep},
          {"number", m.number},
          {"Ni", m.ni},
          {"Nj", m.nj},
          {"numberOfPoints", m.points},
          {"edition", m.edition}};
}

GribMessage fromJson(const nlohmann::json& j) {
  GribMessage m;
  m.offset = j.at("offset").get<std::uint64_t>();
  m.length = j.at("length").get<std::uint64_t>();
  m.shortName = j.at("shortName").get<std::string>();
  m.typeOfLevel = j.at("typeOfLevel").get<std::string>();
  m.gridType = j.at("gridType").get<std::string>();
  m.name = j.at("name").get<std::string>();
  m.units = j.at("units").get<std::string>();
  m.level = j.at("level").get<double>();
  m.dataDate = j.at("dataDate").get<long>();
  m.dataTime = j.at("dataTime").get<long>();
  m.validityDate = j.at("validityDate").get<long>();
  m.validityTime = j.at("validityTime").get<long>();
  m.stepRange = j.at("stepRange").get<std::string>();
  m.endStep = j.at("endStep").get<long>();
  m.number = j.at("number").get<long>();
  m.ni = j.at("Ni").get<long>();
  m.nj = j.at("Nj").get<long>();
  m.points = j.at("numberOfPoints").get<long>();
  m.edition = j.at("edition").get<long>();
  return m;
}

/// The cached index when it is there, readable and of this very file; nullopt otherwise (the
/// caller rebuilds it).
std::optional<GribIndex> loadCached(const std::string& cacheFile, const FileStamp& stamp) {
  std::ifstream in(cacheFile, std::ios::binary);
  if (!in) return std::nullopt;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.at("version").get<int>() != kIndexVersion || j.at("path").get<std::string>() != stamp.absolutePath ||
        j.at("size").get<std::uint64_t>() != stamp.size || j.at("mtime_ns").get<std::int64_t>() != stamp.mtimeNs)
      return std::nullopt;
    GribIndex idx;
    idx.compression = j.at("compression").get<std::string>();
    for (const auto& m : j.at("messages")) idx.messages.push_back(fromJson(m));
    for (const auto& w : j.at("warnings")) idx.warnings.push_back(w.get<std::string>());
    if (idx.messages.empty()) return std::nullopt;
    for (const GribMessage& m : idx.messages)  // an index claiming bytes past the file is stale or damaged
      if (m.offset + m.length < m.offset || (idx.compression == "none" && m.offset + m.length > stamp.size))
        return std::nullopt;
    return idx;
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

/// Section 0 of the next message at or after the position of `f` (searched for "GRIB"), checked
/// before ecCodes reads it: ecCodes allocates the length a message declares before reading it, and
/// a damaged GRIB2 (or edition 3) length (64 bits) asks for exabytes, which aborts the process. A message that
/// declares more bytes than the content has left is cut: returns its offset and declared length
/// (the caller skips it); nullopt otherwise, `f` back where it was.
std::optional<std::pair<std::uint64_t, std::uint64_t>> cutMessageAhead(FILE* f, std::uint64_t contentBytes) {
  const long start = std::ftell(f);
  if (start < 0) return std::nullopt;
  std::optional<std::pair<std::uint64_t, std::uint64_t>> cut;
  // Section 0 is usually right here (16 bytes read); after junk, the marker is searched within
  // the next 64 KiB (ecCodes skips junk between messages the same way).
  std::vector<unsigned char> buf(16);
  std::size_t got = std::fread(buf.data(), 1, buf.size(), f);
  if (got == 16 && !(buf[0] == 'G' && buf[1] == 'R' && buf[2] == 'I' && buf[3] == 'B')) {
    buf.resize(std::size_t{1} << 16);
    got += std::fread(buf.data() + 16, 1, buf.size() - 16, f);
  }
  for (std::size_t p = 0; p + 16 <= got; ++p) {
    if (buf[p] != 'G' || buf[p + 1] != 'R' || buf[p + 2] != 'I' || buf[p + 3] != 'B') continue;
    const std::uint64_t at = static_cast<std::uint64_t>(start) + p;
    std::uint64_t declared = 0;
    if (buf[p + 7] == 2 || buf[p + 7] == 3) {
      // GRIB2, and edition 3 (experimental; ecCodes reads its section 0 as GRIB2's: a fuzz_grib
      // input declaring 8.3 GB of edition 3 made it allocate that): 64 bits.
      for (int k = 0; k < 8; ++k) declared = (declared << 8) | buf[p + 8 + static_cast<std::size_t>(k)];
    } else if (buf[p + 7] == 1 && !(buf[p + 4] & 0x80)) {
      // GRIB1: 24 bits (with the top bit set, ECMWF's large-message coding: left to ecCodes).
      declared = (std::uint64_t{buf[p + 4]} << 16) | (std::uint64_t{buf[p + 5]} << 8) | buf[p + 6];
    }
    if (declared > 0 && (declared < 16 || declared > contentBytes - at)) cut = std::pair{at, declared};
    break;
  }
  std::fseek(f, start, SEEK_SET);
  return cut;
}

/// One pass over the content with ecCodes: every message's keys; damaged stretches skipped
/// with a warning naming the byte offset (ecCodes resynchronises on the next "GRIB").
Status scan(FILE* f, const std::string& label, GribIndex& idx) {
  const std::lock_guard<std::mutex> lock(ecCodesMutex());
  std::fseek(f, 0, SEEK_END);
  const long endPos = std::ftell(f);
  std::fseek(f, 0, SEEK_SET);
  const std::uint64_t contentBytes = endPos > 0 ? static_cast<std::uint64_t>(endPos) : 0;
  for (std::size_t count = 0;; ++count) {
    const long before = std::ftell(f);
    if (auto cut = cutMessageAhead(f, contentBytes)) {
      idx.warnings.push_back(label + ": damaged GRIB message " + std::to_string(count + 1) + " (at byte " +
                             std::to_string(cut->first) + "): it declares " + std::to_string(cut->second) +
                             " bytes, the content has " + std::to_string(contentBytes - cut->first) +
                             " from there; skipped");
      std::fseek(f, static_cast<long>(cut->first + 4), SEEK_SET);  // on to the next "GRIB"
      continue;
    }
    // A failed check inside ecCodes (EcCodesCheckFailed, GribInternal.h) skips the message: its
    // bytes were read before the handle was built, so the scan goes on after it.
    try {
      int err = 0;
      std::unique_ptr<codes_handle, decltype(&codes_handle_delete)> h(
          codes_handle_new_from_file(nullptr, f, PRODUCT_GRIB, &err), &codes_handle_delete);
      if (!h) {
        if (err == CODES_SUCCESS) break;  // end of the content
        idx.warnings.push_back(label + ": damaged GRIB message " + std::to_string(count + 1) + " (from byte " +
                               std::to_string(before) + "): " + codes_get_error_message(err) + "; skipped");
        if (std::ftell(f) <= before) break;  // no progress: stop rather than loop
        continue;
      }
      GribMessage m;
      long offset = 0, length = 0;
      codes_get_long(h.get(), "offset", &offset);
      codes_get_long(h.get(), "totalLength", &length);
      m.offset = static_cast<std::uint64_t>(offset);
      m.length = static_cast<std::uint64_t>(length);
      m.shortName = getString(h.get(), "shortName");
      m.typeOfLevel = getString(h.get(), "typeOfLevel");
      m.gridType = getString(h.get(), "gridType");
      m.name = getString(h.get(), "name");
      m.units = getString(h.get(), "units");
      double level = 0;
      if (codes_get_double(h.get(), "level", &level) == CODES_SUCCESS) m.level = level;
      m.dataDate = getLong(h.get(), "dataDate", 0);
      m.dataTime = getLong(h.get(), "dataTime", 0);
      // Before the validity time: ecCodes computes it in steps of a day, so a damaged step of 1.9e9
      // hours (fuzz_grib) takes minutes. 1e7 step units: 1141 years in hours, 116 days in seconds.
      // A step ecCodes cannot represent in its units ("unable to represent the step") reads as
      // nothing, and the validity time computed from it then never ends (fuzz_grib): skipped too.
      long step = 0;
      const int stepError = codes_get_long(h.get(), "endStep", &step);
      if (stepError != CODES_SUCCESS && codes_is_defined(h.get(), "endStep")) {
        idx.warnings.push_back(label + ": damaged GRIB message " + std::to_string(count + 1) + " (at byte " +
                               std::to_string(offset) + "): its forecast step cannot be read (" +
                               codes_get_error_message(stepError) + "); skipped");
        continue;
      }
      m.endStep = stepError == CODES_SUCCESS && step != CODES_MISSING_LONG ? step : 0;
      if (m.endStep > kMaxStepUnits || m.endStep < -kMaxStepUnits) {
        idx.warnings.push_back(label + ": damaged GRIB message " + std::to_string(count + 1) + " (at byte " +
                               std::to_string(offset) + "): a forecast step of " + std::to_string(m.endStep) +
                               " units; skipped");
        continue;
      }
      m.validityDate = getLong(h.get(), "validityDate", m.dataDate);
      m.validityTime = getLong(h.get(), "validityTime", m.dataTime);
      m.stepRange = getString(h.get(), "stepRange");
      m.number = codes_is_defined(h.get(), "number") ? getLong(h.get(), "number", -1) : -1;
      // A reduced Gaussian grid with a row of no points: ecCodes asserts (and aborts the process) when
      // it works out the grid's points (fuzz_grib: "bottom != 0" in grib_gaussian_reduced.c). Its pl
      // is read as stored, so the row is seen before any key computed from it is asked for.
      if (m.gridType.find("_gg") != std::string::npos) {
        std::size_t rows = 0;
        if (codes_get_size(h.get(), "pl", &rows) == CODES_SUCCESS && rows > 0 && rows < (1u << 20)) {
          std::vector<long> pl(rows);
          if (codes_get_long_array(h.get(), "pl", pl.data(), &rows) == CODES_SUCCESS &&
              std::any_of(pl.begin(), pl.begin() + static_cast<std::ptrdiff_t>(rows), [](long n) { return n <= 0; })) {
            idx.warnings.push_back(label + ": damaged GRIB message " + std::to_string(count + 1) + " (at byte " +
                                   std::to_string(offset) +
                                   "): a reduced Gaussian grid with a row of no points; skipped");
            continue;
          }
        }
      }
      m.ni = getLong(h.get(), "Ni", 0);
      m.nj = getLong(h.get(), "Nj", 0);
      m.points = getLong(h.get(), "numberOfPoints", 0);
      m.edition = getLong(h.get(), "edition", 0);
      idx.messages.push_back(std::move(m));
    } catch (const EcCodesCheckFailed& e) {
      idx.warnings.push_back(label + ": damaged GRIB message " + std::to_string(count + 1) + " (from byte " +
                             std::to_string(before) + "): ecCodes failed an internal check on it (" + e.what() +
                             "); skipped");
      if (std::ftell(f) <= before) break;  // no progress: stop rather than loop
    }
  }
  return Ok{};
}

}  // namespace

bool hasGribSignature(const std::string& path) {
  const std::vector<unsigned char> head = io::peekFileContent(path, 4);
  return head.size() == 4 && head[0] == 'G' && head[1] == 'R' && head[2] == 'I' && head[3] == 'B';
}

std::string cacheDirectory() {
  if (const char* d = std::getenv("ATMOGLOBE_CACHE_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/atmoglobe";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/atmoglobe";
  return {};
}

Result<GribIndex> gribIndex(const std::string& path) {
  auto stamp = stampOf(path);
  if (!stamp) return stamp.forwardError();
  const std::string dir = cacheDirectory();
  const std::string cacheFile = dir.empty() ? std::string()
                                            : dir + "/grib-index/" + pathHash(stamp->absolutePath) + ".json";
  if (!cacheFile.empty())
    if (auto cached = loadCached(cacheFile, *stamp)) {
      cached->path = path;
      cached->files = {path};
      cached->fileCompressed = {cached->compression != "none"};
      cached->cacheFile = cacheFile;
      cached->fromCache = true;
      return std::move(*cached);
    }

  auto compression = io::fileCompression(path);
  if (!compression) return compression.forwardError();
  GribIndex idx;
  idx.path = path;
  idx.compression = io::toString(*compression);
  idx.files = {path};
  idx.fileCompressed = {*compression != io::Compression::None};
  if (*compression == io::Compression::None) {
    std::unique_ptr<FILE, decltype(&std::fclose)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) return makeError(path + ": cannot open");
    if (auto st = scan(f.get(), path, idx); !st) return st.forwardError();
  } else {
    auto content = io::readFileBytes(path);
    if (!content) return content.forwardError();
    std::unique_ptr<FILE, decltype(&std::fclose)> f(fmemopen(content->bytes.data(), content->bytes.size(), "rb"),
                                                    &std::fclose);
    if (!f) return makeError(content->label + ": cannot read the unwrapped content");
    if (auto st = scan(f.get(), content->label, idx); !st) return st.forwardError();
  }
  if (idx.messages.empty()) {
    std::string why = idx.warnings.empty() ? std::string() : " (" + idx.warnings.front() + ")";
    return makeError(path + ": no readable GRIB message" + why);
  }

  if (!cacheFile.empty()) {
    nlohmann::json j;
    j["version"] = kIndexVersion;
    j["path"] = stamp->absolutePath;
    j["size"] = stamp->size;
    j["mtime_ns"] = stamp->mtimeNs;
    j["compression"] = idx.compression;
    j["messages"] = nlohmann::json::array();
    for (const GribMessage& m : idx.messages) j["messages"].push_back(toJson(m));
    j["warnings"] = idx.warnings;
    std::error_code ec;
    std::filesystem::create_directories(dir + "/grib-index", ec);
    // Not kept (read-only cache, full disk): the index is still used, only made again next time.
    if (!ec && globe::writeFileAtomic(cacheFile, j.dump(0, ' ', false, nlohmann::json::error_handler_t::replace)))
      idx.cacheFile = cacheFile;
  }
  return idx;
}

Result<GribContent> GribContent::open(const GribIndex& index) {
  GribContent c;
  for (std::size_t i = 0; i < index.files.size(); ++i) {
    File f;
    f.path = f.label = index.files[i];
    if (i < index.fileCompressed.size() && index.fileCompressed[i]) {
      auto content = io::readFileBytes(f.path);
      if (!content) return content.forwardError();
      f.compressed = true;
      f.label = content->label;
      f.unwrapped = std::move(content->bytes);
    }
    c.files_.push_back(std::move(f));
  }
  return c;
}

Result<const std::vector<unsigned char>*> GribContent::read(const GribMessage& m) {
  if (auto it = read_.find({m.file, m.offset}); it != read_.end() && it->second.size() == m.length) return &it->second;
  if (m.file >= files_.size()) return makeError("GRIB message of file " + std::to_string(m.file) + ": no such file");
  const File& f = files_[m.file];
  std::vector<unsigned char> out;
  if (f.compressed) {
    if (m.offset + m.length > f.unwrapped.size())
      return makeError(f.label + ": GRIB message at byte " + std::to_string(m.offset) +
                       " is past the end of the content (the file changed since it was indexed)");
    out.assign(f.unwrapped.begin() + static_cast<std::ptrdiff_t>(m.offset),
               f.unwrapped.begin() + static_cast<std::ptrdiff_t>(m.offset + m.length));
  } else {
    std::ifstream in(f.path, std::ios::binary);
    if (!in) return makeError(f.path + ": cannot open");
    out.resize(m.length);
    in.seekg(static_cast<std::streamoff>(m.offset));
    in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(m.length));
    if (static_cast<std::uint64_t>(in.gcount()) != m.length)
      return makeError(f.path + ": GRIB message at byte " + std::to_string(m.offset) + " (" + std::to_string(m.length) +
                       " bytes) is cut short (the file changed since it was indexed)");
  }
  bytesRead_ += m.length;
  reads_.push_back({f.path, m.offset, m.length, f.compressed});
  return &(read_[{m.file, m.offset}] = std::move(out));
}

bool isGribSet(const std::string& spec) {
  if (!isRadarFileSet(spec)) return false;
  auto paths = expandRadarPaths(spec);
  if (!paths) return false;
  for (const std::string& p : *paths)
    if (hasGribSignature(p)) return true;
  return false;
}

Result<GribIndex> gribIndexOf(const std::string& spec) {
  if (!isRadarFileSet(spec)) return gribIndex(spec);
  auto paths = expandRadarPaths(spec);
  if (!paths) return paths.forwardError();
  GribIndex set;
  set.path = spec;
  set.fromCache = true;
  std::set<std::string> compressions;
  for (const std::string& p : *paths) {
    if (!hasGribSignature(p))
      return makeError(spec + ": " + p + " is not a GRIB file (a set of GRIB files holds GRIB files only)");
    auto one = gribIndex(p);
    if (!one) return one.forwardError();
    const auto file = static_cast<std::uint32_t>(set.files.size());
    set.files.push_back(p);
    set.fileCompressed.push_back(one->compression != "none");
    compressions.insert(one->compression);
    for (GribMessage& m : one->messages) {
      m.file = file;
      set.messages.push_back(std::move(m));
    }
    for (std::string& w : one->warnings) set.warnings.push_back(std::move(w));
    if (set.cacheFile.empty() && !one->cacheFile.empty())
      set.cacheFile = one->cacheFile.substr(0, one->cacheFile.rfind('/') + 1);  // the directory
    set.fromCache = set.fromCache && one->fromCache;
  }
  set.compression = compressions.size() == 1 ? *compressions.begin() : "mixed";
  return set;
}

std::mutex& ecCodesLock() { return ecCodesMutex(); }

}  // namespace atmoglobe::volume::grib
