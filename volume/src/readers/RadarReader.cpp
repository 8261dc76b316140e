#include <atmoglobe/volume/RadarReader.h>

#include <atmoglobe/globe/Text.h>
#include <atmoglobe/io/Compression.h>
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/CfRadialReader.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/NexradReader.h>
#include <atmoglobe/volume/OdimReader.h>
#include <atmoglobe/volume/RainbowReader.h>
#include <atmoglobe/volume/SigmetReader.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <system_error>

namespace atmoglobe::volume {

const char* toString(RadarFormat f) {
  switch (f) {
    case RadarFormat::Unknown: return "unknown";
    case RadarFormat::CfRadial: return "CfRadial";
    case RadarFormat::OdimH5: return "ODIM_H5";
    case RadarFormat::NexradLevel2: return "NEXRAD Level II";
    case RadarFormat::SigmetIris: return "Sigmet/IRIS RAW";
    case RadarFormat::Rainbow5: return "Rainbow 5";
  }
  return "unknown";
}

namespace {

constexpr std::array<unsigned char, 8> kHdf5Signature = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// HDF5 puts its superblock at 0, 512, 1024, 2048 ... (a user block before it).
bool hasHdf5Signature(std::ifstream& in, std::uintmax_t size) {
  for (std::uintmax_t off = 0; off + 8 <= size; off = (off == 0 ? 512 : off * 2)) {
    std::array<unsigned char, 8> buf{};
    in.clear();
    in.seekg(static_cast<std::streamoff>(off));
    if (!in.read(reinterpret_cast<char*>(buf.data()), 8)) return false;
    if (buf == kHdf5Signature) return true;
  }
  return false;
}

bool contains(const std::string& s, const char* what) { return s.find(what) != std::string::npos; }

/// An open HDF5/netCDF-4 file: ODIM or CfRadial from its attributes and variables.
RadarFormat classifyHdf5(const io::NetcdfFile& f) {
  std::string conventions, version;
  if (f.hasAttribute(f.root(), NC_GLOBAL, "Conventions")) {
    if (auto c = f.attributeString(f.root(), NC_GLOBAL, "Conventions")) conventions = *c;
  }
  if (f.hasAttribute(f.root(), NC_GLOBAL, "version")) {
    if (auto v = f.attributeString(f.root(), NC_GLOBAL, "version")) version = *v;
  }
  if (conventions.rfind("ODIM_H5", 0) == 0) return RadarFormat::OdimH5;
  for (const std::string* s : {&conventions, &version}) {
    if (contains(*s, "CF/Radial") || contains(*s, "CF-Radial") || contains(*s, "Cf/Radial"))
      return RadarFormat::CfRadial;
  }
  if (f.findVariable(f.root(), "sweep_start_ray_index")) return RadarFormat::CfRadial;
  if (auto what = f.findGroup(f.root(), "what"); what && f.hasAttribute(*what, NC_GLOBAL, "object"))
    return RadarFormat::OdimH5;
  return RadarFormat::Unknown;
}

/// What the first bytes say. HDF5 files need classifyHdf5() to tell ODIM from CfRadial;
/// they come back as Unknown with *hdf5 = true.
Result<RadarFormat> detectByMagic(const std::string& path, bool* hdf5) {
  *hdf5 = false;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return makeError(path + ": no such file (or not a regular file)");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return makeError(path + ": cannot read file: " + ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open file for reading");
  std::array<unsigned char, 64> head{};
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  const auto n = static_cast<std::size_t>(in.gcount());
  if (n >= 4 && head[0] == 'C' && head[1] == 'D' && head[2] == 'F' && (head[3] == 1 || head[3] == 2 || head[3] == 5))
    return RadarFormat::CfRadial;
  if (n >= 4 && head[0] == 'A' && head[1] == 'R' && head[2] == '2' && head[3] == 'V') return RadarFormat::NexradLevel2;
  if (looksLikeSigmetRaw(head.data(), n)) return RadarFormat::SigmetIris;
  if (looksLikeRainbow5(head.data(), n)) return RadarFormat::Rainbow5;
  if (n >= 8 && std::memcmp(head.data(), "ARCHIVE2", 8) == 0) return RadarFormat::NexradLevel2;  // legacy header
  *hdf5 = hasHdf5Signature(in, size);
  return RadarFormat::Unknown;
}

std::string firstBytesText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 8> buf{};
  in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
  const auto n = static_cast<std::size_t>(in.gcount());
  if (n == 0) return "the file is empty";
  std::ostringstream os;
  os << "it starts with bytes";
  for (std::size_t i = 0; i < n; ++i)
    os << ' ' << std::hex << std::setw(2) << std::setfill('0') << static_cast<int>(static_cast<unsigned char>(buf[i]));
  return os.str();
}

std::string firstBytesText(const std::vector<unsigned char>& bytes) {
  if (bytes.empty()) return "the content is empty";
  std::ostringstream os;
  os << "it starts with bytes";
  for (std::size_t i = 0; i < std::min<std::size_t>(8, bytes.size()); ++i)
    os << ' ' << std::hex << std::setw(2) << std::setfill('0') << static_cast<int>(bytes[i]);
  return os.str();
}

/// The format of a decompressed content (the rules of detectRadarFormat on bytes); HDF5 content
/// comes back as Unknown with *hdf5 = true.
RadarFormat detectInMemory(const std::vector<unsigned char>& b, bool* hdf5) {
  *hdf5 = false;
  const std::size_t n = b.size();
  if (n >= 4 && b[0] == 'C' && b[1] == 'D' && b[2] == 'F' && (b[3] == 1 || b[3] == 2 || b[3] == 5))
    return RadarFormat::CfRadial;
  if (looksLikeNexradLevel2(b.data(), n)) return RadarFormat::NexradLevel2;
  if (looksLikeSigmetRaw(b.data(), n)) return RadarFormat::SigmetIris;
  if (looksLikeRainbow5(b.data(), n)) return RadarFormat::Rainbow5;
  *hdf5 = io::hasNetcdfSignature(b.data(), n);
  return RadarFormat::Unknown;
}

const char* kFormatList = "a CfRadial, ODIM_H5 or NEXRAD Level II file, nor Sigmet/IRIS RAW or Rainbow 5";

/// A gzip/bzip2-wrapped file: decompressed into memory, detected and read from there.
Result<RadarVolume> readWrapped(const std::string& path, const ReadOptions& options, RadarFormat* detectedOnly) {
  auto content = io::readFileBytes(path);
  if (!content) return content.forwardError();
  const std::string& label = content->label;
  bool hdf5 = false;
  RadarFormat format = detectInMemory(content->bytes, &hdf5);
  Result<RadarVolume> vol =
      makeError(label + ": not " + std::string(kFormatList) + " inside the " + toString(content->compression) +
                " wrapper (" + firstBytesText(content->bytes) + ")");
  if (hdf5) {
    auto opened =
        io::NetcdfFile::openMemory(label, std::make_shared<std::vector<unsigned char>>(std::move(content->bytes)));
    if (!opened) return opened.forwardError();
    format = classifyHdf5(*opened);
    if (detectedOnly) {
      *detectedOnly = format;
      return RadarVolume{};
    }
    if (format == RadarFormat::CfRadial) vol = readCfRadial(*opened, options);
    else if (format == RadarFormat::OdimH5) vol = readOdimH5(*opened, options);
    else vol = makeError(label + ": an HDF5/netCDF-4 file that is neither ODIM_H5 nor CfRadial");
  } else {
    if (detectedOnly) {
      *detectedOnly = format;
      return RadarVolume{};
    }
    switch (format) {
      case RadarFormat::CfRadial: {
        auto opened =
            io::NetcdfFile::openMemory(label, std::make_shared<std::vector<unsigned char>>(std::move(content->bytes)));
        if (!opened) return opened.forwardError();
        vol = readCfRadial(*opened, options);
        break;
      }
      case RadarFormat::NexradLevel2: vol = readNexradLevel2(label, content->bytes, options); break;
      case RadarFormat::SigmetIris: vol = readSigmetIris(label, content->bytes, options); break;
      case RadarFormat::Rainbow5: vol = readRainbow5(label, content->bytes, options); break;
      default: break;
    }
  }
  if (!vol) return vol;
  vol->sourcePath = path;
  vol->compression = toString(content->compression);
  return vol;
}

}  // namespace

Result<RadarFormat> detectRadarFormat(const std::string& path) {
  auto wrapper = io::fileCompression(path);
  if (wrapper && *wrapper != io::Compression::None) {
    RadarFormat format = RadarFormat::Unknown;
    auto st = readWrapped(path, {}, &format);
    if (!st) return st.forwardError();
    return format;
  }
  bool hdf5 = false;
  auto magic = detectByMagic(path, &hdf5);
  if (!magic || !hdf5) return magic;
  auto opened = io::NetcdfFile::open(path);
  if (!opened) return opened.forwardError();
  return classifyHdf5(*opened);
}

Result<RadarVolume> readRadarVolume(const std::string& path, const ReadOptions& options) {
  if (auto wrapper = io::fileCompression(path); wrapper && *wrapper != io::Compression::None)
    return readWrapped(path, options, nullptr);
  bool hdf5 = false;
  auto format = detectByMagic(path, &hdf5);
  if (!format) return format.forwardError();
  if (hdf5) {
    // Opened once: classified and read through the same handle.
    auto opened = io::NetcdfFile::open(path);
    if (!opened) return opened.forwardError();
    switch (classifyHdf5(*opened)) {
      case RadarFormat::CfRadial: return readCfRadial(*opened, options);
      case RadarFormat::OdimH5: return readOdimH5(*opened, options);
      default:
        return makeError(path +
                         ": an HDF5/netCDF-4 file that is neither ODIM_H5 (no Conventions \"ODIM_H5/...\" "
                         "or /what:object) nor CfRadial (no CF/Radial Conventions or sweep_start_ray_index)");
    }
  }
  switch (*format) {
    case RadarFormat::CfRadial: return readCfRadial(path, options);
    case RadarFormat::OdimH5: return readOdimH5(path, options);
    case RadarFormat::NexradLevel2: return readNexradLevel2(path, options);
    case RadarFormat::SigmetIris: return readSigmetIris(path, options);
    case RadarFormat::Rainbow5: return readRainbow5(path, options);
    case RadarFormat::Unknown: break;
  }
  return makeError(path + ": not " + std::string(kFormatList) + " (" + firstBytesText(path) + ")");
}

Result<std::size_t> selectField(const std::vector<FieldInfo>& fields, const std::string& requested,
                                const std::string& noun) {
  const std::string wanted = requested.empty() ? chooseDefaultField(fields) : requested;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (fields[i].name == wanted) return i;
  }
  std::string names;
  for (const auto& fi : fields) names += (names.empty() ? "" : ", ") + fi.name;
  return makeError("no " + noun + " '" + wanted + "' (the file has: " + names + ")");
}

std::string chooseDefaultField(const std::vector<FieldInfo>& fields) {
  return chooseDefaultFieldWithReason(fields).name;
}

std::string normalizeIso8601(const std::string& text) {
  // YYYY-MM-DD[T ]HH:MM:SS, anything after the seconds (fraction, zone "Z") ignored.
  const std::string t(trimAscii(text));
  if (t.size() < 19) return {};
  auto digits = [&](std::size_t pos, std::size_t len) {
    for (std::size_t i = pos; i < pos + len; ++i)
      if (!std::isdigit(static_cast<unsigned char>(t[i]))) return false;
    return true;
  };
  if (!digits(0, 4) || t[4] != '-' || !digits(5, 2) || t[7] != '-' || !digits(8, 2) || (t[10] != 'T' && t[10] != ' ') ||
      !digits(11, 2) || t[13] != ':' || !digits(14, 2) || t[16] != ':' || !digits(17, 2))
    return {};
  return t.substr(0, 10) + "T" + t.substr(11, 8) + "Z";
}

double iso8601ToEpochSeconds(const std::string& text) {
  const std::string t = normalizeIso8601(text);
  if (t.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::tm tm{};
  tm.tm_year = std::stoi(t.substr(0, 4)) - 1900;
  tm.tm_mon = std::stoi(t.substr(5, 2)) - 1;
  tm.tm_mday = std::stoi(t.substr(8, 2));
  tm.tm_hour = std::stoi(t.substr(11, 2));
  tm.tm_min = std::stoi(t.substr(14, 2));
  tm.tm_sec = std::stoi(t.substr(17, 2));
  return static_cast<double>(timegm(&tm));
}

namespace {
const char* angleKind(SweepMode m) { return m == SweepMode::Rhi ? "azimuth" : "elevation"; }
}  // namespace

std::string describeVolumeJson(const RadarVolume& v) {
  nlohmann::ordered_json j;
  j["format"] = v.format;
  j["file"] = v.sourcePath;
  if (!v.compression.empty()) j["compression"] = v.compression;
  j["site"] = {{"name", v.site.name},
               {"place", v.site.placeName},
               {"lat_deg", v.site.latDeg},
               {"lon_deg", v.site.lonDeg},
               {"height_m", v.site.antennaHeightMeters},
               {"height_datum", toString(v.site.heightDatum)}};
  if (!v.siteLocationSource.empty()) j["site"]["location_source"] = v.siteLocationSource;
  if (!v.sourceFiles.empty()) j["files"] = v.sourceFiles;
  j["time"] = v.timeIso8601;
  j["beam_width_deg"] = v.beamWidthDeg > 0 ? nlohmann::ordered_json(v.beamWidthDeg) : nlohmann::ordered_json(nullptr);
  nlohmann::ordered_json sweeps = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < v.sweeps.size(); ++i) {
    const Sweep& s = v.sweeps[i];
    sweeps.push_back({{"index", i},
                      {"index_in_file", s.indexInFile},
                      {"fixed_angle_deg", s.fixedAngleDeg},
                      {"fixed_angle_kind", angleKind(s.mode)},
                      {"mode", toString(s.mode)},
                      {"rays", s.rayCount()},
                      {"gates", s.gateCount},
                      {"first_gate_m", s.firstGateRangeMeters},
                      {"gate_spacing_m", s.gateSpacingMeters},
                      {"complete", s.complete}});
    if (!s.startTimeIso8601.empty()) sweeps.back()["start_time"] = s.startTimeIso8601;
    if (!s.endTimeIso8601.empty()) sweeps.back()["end_time"] = s.endTimeIso8601;
  }
  j["sweeps"] = std::move(sweeps);
  nlohmann::ordered_json fields = nlohmann::ordered_json::array();
  for (const FieldInfo& f : v.fields) {
    const FieldKindEvidence k = classifyField(f);
    fields.push_back({{"name", f.name},
                      {"units", f.units},
                      {"standard_name", f.standardName},
                      {"kind", toString(k.kind)},
                      {"kind_reason", k.reason}});
  }
  j["fields"] = std::move(fields);
  const DefaultField d = chooseDefaultFieldWithReason(v.fields);
  j["default_field"] = {{"name", d.name}, {"reason", d.reason}};
  if (std::isfinite(v.nyquistVelocityMps)) j["nyquist_velocity_mps"] = v.nyquistVelocityMps;
  j["loaded_field"] = v.loadedField.name;
  j["warnings"] = v.warnings;
  // NaN cannot be written to JSON; the readers reject NaN metadata, so dump() never fails.
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string describeVolumeText(const RadarVolume& v) {
  std::ostringstream os;
  os << std::fixed;
  os << "file:    " << v.sourcePath << "\n";
  if (!v.sourceFiles.empty()) {
    os << "files:   " << v.sourceFiles.size() << " assembled into this volume\n";
    for (const std::string& f : v.sourceFiles) os << "  " << f << "\n";
  }
  os << "format:  " << v.format << (v.compression.empty() ? "" : " (" + v.compression + "-compressed file)") << "\n";
  os << "site:    " << (v.site.name.empty() && v.site.placeName.empty() ? "(unnamed)" : siteTitle(v.site))
     << std::setprecision(5) << "  lat " << v.site.latDeg << " deg  lon " << v.site.lonDeg << " deg  antenna height "
     << std::setprecision(1) << v.site.antennaHeightMeters << " m (" << toString(v.site.heightDatum) << ")\n";
  if (!v.siteLocationSource.empty()) os << "         position from " << v.siteLocationSource << "\n";
  os << "time:    " << (v.timeIso8601.empty() ? "(unknown)" : v.timeIso8601) << "\n";
  if (v.beamWidthDeg > 0) os << "beam:    " << std::setprecision(2) << v.beamWidthDeg << " deg\n";
  os << "sweeps:  " << v.sweeps.size() << "\n";
  os << "  index  fixed_angle_deg  mode   rays  gates  first_gate_m  gate_spacing_m\n";
  for (std::size_t i = 0; i < v.sweeps.size(); ++i) {
    const Sweep& s = v.sweeps[i];
    os << "  " << std::setw(5) << i << "  " << std::setw(15) << std::setprecision(2) << s.fixedAngleDeg
       << (s.mode == SweepMode::Rhi ? "a" : " ") << " " << std::setw(5) << std::left << toString(s.mode) << std::right
       << " " << std::setw(5) << s.rayCount() << "  " << std::setw(5) << s.gateCount << "  " << std::setw(12)
       << std::setprecision(1) << s.firstGateRangeMeters << "  " << std::setw(14) << std::setprecision(2)
       << s.gateSpacingMeters << (s.complete ? "" : "  partial") << "\n";
  }
  if (std::any_of(v.sweeps.begin(), v.sweeps.end(), [](const Sweep& s) { return s.mode == SweepMode::Rhi; }))
    os << "  (a: the fixed angle of an RHI sweep is its azimuth)\n";
  if (std::isfinite(v.nyquistVelocityMps))
    os << "nyquist: " << std::setprecision(2) << v.nyquistVelocityMps << " m/s (largest of the sweeps)\n";
  os << "fields:  " << v.fields.size() << "\n";
  for (const FieldInfo& f : v.fields) {
    const FieldKindEvidence k = classifyField(f);
    os << "  " << f.name << (f.units.empty() ? "" : " [" + f.units + "]") << "  " << toString(k.kind) << " ("
       << k.reason << ")\n";
  }
  const DefaultField d = chooseDefaultFieldWithReason(v.fields);
  if (!d.name.empty()) os << "default field: " << d.name << " (" << d.reason << ")\n";
  for (const std::string& w : v.warnings) os << "warning: " << w << "\n";
  return os.str();
}

}  // namespace atmoglobe::volume
