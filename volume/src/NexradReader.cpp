#include <atmoglobe/volume/NexradReader.h>

#include <bzlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <limits>
#include <map>
#include <vector>

namespace atmoglobe::volume {

namespace {

constexpr std::size_t kVolumeHeaderBytes = 24;
constexpr std::size_t kCtmBytes = 12;
constexpr std::size_t kMessageHeaderBytes = 16;
constexpr std::size_t kFrameBytes = 2432;  // fixed frame of every message type but 31

std::uint16_t be16(const unsigned char* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }
std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
float beFloat(const unsigned char* p) { return std::bit_cast<float>(be32(p)); }

std::string trimName(const unsigned char* p, std::size_t n) {
  std::string s(reinterpret_cast<const char*>(p), n);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  return s;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

const char* momentUnits(const std::string& name) {
  if (name == "REF") return "dBZ";
  if (name == "VEL" || name == "SW") return "m/s";
  if (name == "ZDR" || name == "CFP") return "dB";
  if (name == "PHI") return "degrees";
  if (name == "RHO") return "unitless";
  return "";
}

// Days since 1970-01-01 (day 1 = 1970-01-01, the ICD's "modified Julian date") + ms -> ISO 8601.
std::string isoTime(std::uint32_t julianDay, std::uint32_t msOfDay) {
  if (julianDay == 0) return {};
  const std::int64_t seconds = (static_cast<std::int64_t>(julianDay) - 1) * 86400 + msOfDay / 1000;
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  if (gmtime_r(&t, &tm) == nullptr) return {};
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// One cut (elevation number) being collected. Values are stored directly in the sweep layout
// (ray-major, `stride` gates a ray, kNoData padding) so the finished array is moved, not copied.
struct Cut {
  int elevationNumber = 0;
  std::vector<float> azimuthDeg, elevationDeg;
  std::vector<float> values;  // rows of `stride` gates, one per ray seen so far
  std::uint32_t stride = 0;   // largest gate count of the field in this cut
  double firstGateMeters = 0, gateSpacingMeters = 0;
  bool hasField = false;

  // Makes room for a row of `gates` values for ray `ray` (rows before it already exist or are
  // created as no data) and returns it, filled with kNoData.
  float* row(std::size_t ray, std::uint32_t gates) {
    if (gates > stride) {
      std::vector<float> wider;
      wider.reserve(std::max<std::size_t>(360, ray + 1) * gates);
      wider.assign(ray * gates, kNoData);
      for (std::size_t r = 0; stride > 0 && r < values.size() / stride; ++r) {
        std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(r * stride), stride,
                    wider.begin() + static_cast<std::ptrdiff_t>(r * gates));
      }
      values = std::move(wider);
      stride = gates;
    }
    values.resize((ray + 1) * stride, kNoData);
    return values.data() + ray * stride;
  }
};

class Parser {
 public:
  Parser(std::string path, std::string field, bool loadValues)
      : path_(std::move(path)), field_(std::move(field)), loadValues_(loadValues) {}

  Status parseRecord(const unsigned char* data, std::size_t size, std::size_t recordIndex);

  std::string path_;
  std::string field_;
  bool loadValues_;
  std::vector<std::string> fieldNames;
  double nyquistMps = std::numeric_limits<double>::quiet_NaN();  ///< largest of the RAD blocks
  bool haveSite = false;
  RadarSite site;
  int vcp = 0;
  std::vector<double> vcpAnglesDeg;  // target elevation per cut (message 5), cut 1 first
  std::map<int, Cut> cuts;
  std::vector<int> cutOrder;
  std::size_t radials = 0;
  std::size_t legacyRadials = 0;
  std::uint32_t firstRadialDay = 0, firstRadialMs = 0;

 private:
  Error fail(std::size_t record, const std::string& what) const {
    return makeError(path_ + ": NEXRAD record " + std::to_string(record) + ": " + what);
  }
  Status parseVcp(const unsigned char* body, std::size_t size, std::size_t record);
  Status parseRadial(const unsigned char* body, std::size_t size, std::size_t record);
};

Status Parser::parseRecord(const unsigned char* data, std::size_t size, std::size_t record) {
  std::size_t pos = 0;
  while (pos + kCtmBytes + kMessageHeaderBytes <= size) {
    const unsigned char* header = data + pos + kCtmBytes;
    const std::uint16_t halfwords = be16(header);
    const unsigned type = header[3];
    if (type == 31) {
      const std::size_t messageBytes = std::size_t{halfwords} * 2;
      if (messageBytes < kMessageHeaderBytes || pos + kCtmBytes + messageBytes > size) {
        return fail(record, "message 31 at byte " + std::to_string(pos) + " claims " + std::to_string(messageBytes) +
                                " bytes, beyond the record (" + std::to_string(size) + " bytes)");
      }
      if (Status s = parseRadial(header + kMessageHeaderBytes, messageBytes - kMessageHeaderBytes, record); !s)
        return s;
      pos += kCtmBytes + messageBytes;
    } else {
      const std::size_t bodyBytes = std::min(kFrameBytes, size - pos) - kCtmBytes - kMessageHeaderBytes;
      if (type == 5) {
        if (Status s = parseVcp(header + kMessageHeaderBytes, bodyBytes, record); !s) return s;
      } else if (type == 1) {
        ++legacyRadials;
      }
      pos += kFrameBytes;
    }
  }
  return Ok{};
}

Status Parser::parseVcp(const unsigned char* body, std::size_t size, std::size_t record) {
  // Message 5: pattern size, type, number, number of cuts, ...; cuts of 23 halfwords from byte 22.
  if (size < 22 || !vcpAnglesDeg.empty()) return Ok{};
  const std::size_t cutCount = be16(body + 6);
  if (cutCount > 32 || 22 + cutCount * 46 > size) {
    return fail(record, "VCP message claims " + std::to_string(cutCount) + " elevation cuts");
  }
  vcp = be16(body + 4);
  for (std::size_t i = 0; i < cutCount; ++i) {
    // Binary angle: 360 deg = 65536 counts (ICD table "angle data format").
    vcpAnglesDeg.push_back(be16(body + 22 + i * 46) * (360.0 / 65536.0));
  }
  return Ok{};
}

Status Parser::parseRadial(const unsigned char* body, std::size_t size, std::size_t record) {
  constexpr std::size_t kRadialHeaderBytes = 32;
  if (size < kRadialHeaderBytes) return fail(record, "message 31 shorter than its radial header");
  const std::size_t radialIndex = radials++;
  const std::string where = "radial " + std::to_string(radialIndex);
  if (radialIndex == 0) {
    firstRadialMs = be32(body + 4);
    firstRadialDay = be16(body + 8);
  }
  const float azimuth = beFloat(body + 12);
  const int elevationNumber = body[22];
  const float elevation = beFloat(body + 24);
  const std::size_t blockCount = be16(body + 30);
  if (!std::isfinite(azimuth) || azimuth < -360.0f || azimuth > 720.0f) {
    return fail(record, where + ": azimuth is not a finite angle");
  }
  if (!std::isfinite(elevation) || elevation < -90.0f || elevation > 90.0f) {
    return fail(record, where + ": elevation is not a finite angle in [-90, 90]");
  }
  if (blockCount > 16 || kRadialHeaderBytes + blockCount * 4 > size) {
    return fail(record, where + ": " + std::to_string(blockCount) + " data blocks do not fit the message");
  }
  Cut& cut = cuts[elevationNumber];
  if (cut.azimuthDeg.empty()) {
    cut.elevationNumber = elevationNumber;
    cutOrder.push_back(elevationNumber);
  }
  float az = std::fmod(azimuth, 360.0f);
  if (az < 0) az += 360.0f;
  cut.azimuthDeg.push_back(az);
  cut.elevationDeg.push_back(elevation);
  const std::size_t rayIndex = cut.azimuthDeg.size() - 1;

  for (std::size_t b = 0; b < blockCount; ++b) {
    const std::size_t ptr = be32(body + kRadialHeaderBytes + b * 4);
    if (ptr == 0) continue;
    if (ptr + 4 > size)
      return fail(record, where + ": data block pointer " + std::to_string(ptr) + " outside the message");
    const unsigned char* block = body + ptr;
    const std::string name = trimName(block + 1, 3);
    if (block[0] == 'R' && name == "VOL") {
      if (ptr + 44 > size) return fail(record, where + ": VOL block truncated");
      if (!haveSite) {
        site.latDeg = beFloat(block + 8);
        site.lonDeg = beFloat(block + 12);
        const auto siteHeight = static_cast<std::int16_t>(be16(block + 16));
        const std::uint16_t feedhorn = be16(block + 18);
        site.antennaHeightMeters = static_cast<double>(siteHeight) + feedhorn;
        site.heightDatum = HeightDatum::MeanSeaLevel;
        if (vcp == 0) vcp = be16(block + 40);
        haveSite = true;
      }
    } else if (block[0] == 'R' && name == "RAD") {
      // Radial data constant block (ICD for RDA/RPG, message 31): Nyquist velocity at byte 16,
      // a signed 16-bit count of 0.01 m/s.
      if (ptr + 18 <= size) {
        const double nyquist = static_cast<std::int16_t>(be16(block + 16)) * 0.01;
        if (nyquist > 0.0 && nyquist < 200.0 && !(nyquist <= nyquistMps)) nyquistMps = nyquist;
      }
    } else if (block[0] == 'D') {
      constexpr std::size_t kMomentHeaderBytes = 28;
      if (ptr + kMomentHeaderBytes > size) return fail(record, where + ": moment " + name + " header truncated");
      if (std::find(fieldNames.begin(), fieldNames.end(), name) == fieldNames.end()) fieldNames.push_back(name);
      if (upper(name) != field_) continue;
      const std::uint32_t gates = be16(block + 8);
      const auto firstGate = static_cast<std::int16_t>(be16(block + 10));
      const auto interval = static_cast<std::int16_t>(be16(block + 12));
      const unsigned wordBits = block[19];
      const float scale = beFloat(block + 20);
      const float offset = beFloat(block + 24);
      if (wordBits != 8 && wordBits != 16) {
        return fail(record,
                    where + ": moment " + name + " has word size " + std::to_string(wordBits) + " (8 or 16 expected)");
      }
      const std::size_t dataBytes = std::size_t{gates} * (wordBits / 8);
      if (ptr + kMomentHeaderBytes + dataBytes > size) {
        return fail(record,
                    where + ": moment " + name + " claims " + std::to_string(gates) + " gates, beyond the message");
      }
      if (interval <= 0)
        return fail(record, where + ": moment " + name + " gate interval " + std::to_string(interval) + " m");
      if (!std::isfinite(scale) || scale == 0.0f || !std::isfinite(offset)) {
        return fail(record, where + ": moment " + name + " has an unusable scale/offset");
      }
      if (!cut.hasField) {
        cut.hasField = true;
        cut.firstGateMeters = firstGate;
        cut.gateSpacingMeters = interval;
      } else if (cut.firstGateMeters != firstGate || cut.gateSpacingMeters != interval) {
        return fail(record, where + ": moment " + name + " gate geometry changes within elevation cut " +
                                std::to_string(elevationNumber));
      }
      if (!loadValues_) {
        cut.stride = std::max(cut.stride, gates);
      } else {
        const unsigned char* raw = block + kMomentHeaderBytes;
        float* out = cut.row(rayIndex, gates);
        if (wordBits == 8) {
          std::array<float, 256> lut;
          lut[0] = kNoEcho;
          lut[1] = kNoData;
          for (int v = 2; v < 256; ++v) lut[v] = (static_cast<float>(v) - offset) / scale;
          for (std::uint32_t g = 0; g < gates; ++g) out[g] = lut[raw[g]];
        } else {
          for (std::uint32_t g = 0; g < gates; ++g) {
            const std::uint16_t v = be16(raw + 2 * g);
            out[g] = v == 0 ? kNoEcho : v == 1 ? kNoData : (static_cast<float>(v) - offset) / scale;
          }
        }
      }
    }
  }
  if (loadValues_ && cut.stride > 0) cut.row(rayIndex, 0);  // pads a ray without the field
  return Ok{};
}

// Decompresses one bzip2 stream into `out` (reused between records), growing it up to the cap.
Status decompressRecord(const std::string& path, std::size_t record, const unsigned char* in, std::size_t inSize,
                        std::vector<unsigned char>* out, std::size_t* outSize) {
  bz_stream strm{};
  if (BZ2_bzDecompressInit(&strm, 0, 0) != BZ_OK) return makeError(path + ": cannot initialise bzip2");
  strm.next_in = const_cast<char*>(reinterpret_cast<const char*>(in));
  strm.avail_in = static_cast<unsigned>(inSize);
  if (out->size() < std::size_t{1} << 20) out->resize(std::size_t{1} << 20);
  std::size_t produced = 0;
  int rc = BZ_OK;
  for (;;) {
    if (produced == out->size()) {
      if (out->size() >= kNexradMaxRecordBytes) {
        BZ2_bzDecompressEnd(&strm);
        return makeError(path + ": NEXRAD record " + std::to_string(record) + " decompresses to more than " +
                         std::to_string(kNexradMaxRecordBytes >> 20) + " MiB (corrupt file?)");
      }
      out->resize(std::min(out->size() * 2, kNexradMaxRecordBytes));
    }
    strm.next_out = reinterpret_cast<char*>(out->data() + produced);
    strm.avail_out = static_cast<unsigned>(out->size() - produced);
    rc = BZ2_bzDecompress(&strm);
    produced = out->size() - strm.avail_out;
    if (rc == BZ_STREAM_END) break;
    if (rc != BZ_OK) {
      BZ2_bzDecompressEnd(&strm);
      return makeError(path + ": NEXRAD record " + std::to_string(record) + ": corrupt bzip2 data (libbz2 error " +
                       std::to_string(rc) + ")");
    }
    if (strm.avail_in == 0 && strm.avail_out != 0) {
      BZ2_bzDecompressEnd(&strm);
      return makeError(path + ": NEXRAD record " + std::to_string(record) +
                       ": bzip2 stream ends early (truncated file?)");
    }
  }
  BZ2_bzDecompressEnd(&strm);
  *outSize = produced;
  return Ok{};
}

Result<RadarVolume> readWithField(const std::string& path, const std::vector<unsigned char>& file,
                                  const std::string& fieldUpper, const ReadOptions& options, bool fieldChosen) {
  Parser parser(path, fieldUpper, options.loadValues);
  std::vector<unsigned char> buffer;
  std::size_t pos = kVolumeHeaderBytes;
  std::size_t record = 0;
  while (pos < file.size()) {
    if (file.size() - pos < 4) return makeError(path + ": truncated NEXRAD record size at byte " + std::to_string(pos));
    const auto control = static_cast<std::int32_t>(be32(&file[pos]));
    const std::size_t length = control < 0
                                   ? std::size_t{0} - static_cast<std::size_t>(static_cast<std::int64_t>(control))
                                   : static_cast<std::size_t>(control);
    pos += 4;
    if (length == 0)
      return makeError(path + ": NEXRAD record " + std::to_string(record) + " at byte " + std::to_string(pos - 4) +
                       " has size 0");
    if (length > file.size() - pos) {
      return makeError(path + ": NEXRAD record " + std::to_string(record) + " at byte " + std::to_string(pos - 4) +
                       " claims " + std::to_string(length) + " bytes but only " + std::to_string(file.size() - pos) +
                       " remain (truncated or corrupt file)");
    }
    const unsigned char* data = &file[pos];
    if (length >= 3 && std::memcmp(data, "BZh", 3) == 0) {
      std::size_t produced = 0;
      if (Status s = decompressRecord(path, record, data, length, &buffer, &produced); !s) return s.forwardError();
      if (Status s = parser.parseRecord(buffer.data(), produced, record); !s) return s.forwardError();
    } else {
      if (Status s = parser.parseRecord(data, length, record); !s) return s.forwardError();
    }
    pos += length;
    ++record;
    if (control < 0) break;
  }

  if (parser.radials == 0) {
    if (parser.legacyRadials > 0) {
      return makeError(path +
                       ": holds only legacy message-1 radials (Archive II before 2008), which are not supported");
    }
    return makeError(path + ": no message 31 radials found (not a NEXRAD Level II volume, or empty)");
  }
  if (!parser.haveSite) return makeError(path + ": no VOL block: the file does not give the radar site");
  if (!std::isfinite(parser.site.latDeg) || std::abs(parser.site.latDeg) > 90.0 || !std::isfinite(parser.site.lonDeg) ||
      std::abs(parser.site.lonDeg) > 360.0) {
    return makeError(path + ": VOL block site latitude/longitude out of range");
  }

  RadarVolume vol;
  vol.format = "NEXRAD Level II";
  vol.sourcePath = path;
  for (const std::string& n : parser.fieldNames) vol.fields.push_back({n, momentUnits(n), {}});
  bool found = false;
  std::string loadedName;
  for (const std::string& n : parser.fieldNames) {
    if (upper(n) == fieldUpper) {
      found = true;
      loadedName = n;
    }
  }
  if (!found) {
    if (!fieldChosen && !parser.fieldNames.empty()) {
      return readWithField(path, file, upper(parser.fieldNames.front()), options, true);
    }
    std::string names;
    for (const std::string& n : parser.fieldNames) names += (names.empty() ? "" : ", ") + n;
    return makeError(path + ": field '" + options.fieldName + "' is not in the file (fields: " + names + ")");
  }
  vol.loadedField = {loadedName, momentUnits(loadedName), {}};
  vol.nyquistVelocityMps = parser.nyquistMps;
  vol.site = parser.site;
  const unsigned char* h = file.data();
  vol.site.name = trimName(h + 20, 4);
  vol.timeIso8601 = isoTime(be32(h + 12), be32(h + 16));
  if (vol.timeIso8601.empty()) vol.timeIso8601 = isoTime(parser.firstRadialDay, parser.firstRadialMs);

  for (int number : parser.cutOrder) {
    Cut& cut = parser.cuts[number];
    if (!cut.hasField) continue;  // split cut without this moment
    Sweep sw;
    sw.indexInFile = number - 1;
    sw.mode = SweepMode::Ppi;
    sw.firstGateRangeMeters = cut.firstGateMeters;
    sw.gateSpacingMeters = cut.gateSpacingMeters;
    sw.gateCount = cut.stride;
    sw.azimuthDeg = std::move(cut.azimuthDeg);
    sw.elevationDeg = std::move(cut.elevationDeg);
    if (number >= 1 && static_cast<std::size_t>(number) <= parser.vcpAnglesDeg.size() &&
        parser.vcpAnglesDeg[number - 1] > 0) {
      sw.fixedAngleDeg = parser.vcpAnglesDeg[number - 1];
    } else {
      double sum = 0;
      for (float e : sw.elevationDeg) sum += e;
      sw.fixedAngleDeg = sum / static_cast<double>(sw.elevationDeg.size());
    }
    if (options.loadValues) {
      sw.values = std::move(cut.values);
      sw.values.resize(sw.rayCount() * sw.gateCount, kNoData);  // trailing rays without the field
    }
    vol.sweeps.push_back(std::move(sw));
  }
  std::stable_sort(vol.sweeps.begin(), vol.sweeps.end(),
                   [](const Sweep& a, const Sweep& b) { return a.fixedAngleDeg < b.fixedAngleDeg; });
  return vol;
}

}  // namespace

bool looksLikeNexradLevel2(const unsigned char* bytes, std::size_t size) {
  return size >= 8 && std::memcmp(bytes, "AR2V00", 6) == 0;
}

Result<RadarVolume> readNexradLevel2(const std::string& path, const ReadOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return makeError(path + ": cannot determine file size");
  in.seekg(0);
  std::vector<unsigned char> file(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(file.data()), size)) return makeError(path + ": read error");
  return readNexradLevel2(path, file, options);
}

Result<RadarVolume> readNexradLevel2(const std::string& path, const std::vector<unsigned char>& file,
                                     const ReadOptions& options) {
  if (file.size() < kVolumeHeaderBytes || !looksLikeNexradLevel2(file.data(), file.size())) {
    return makeError(path + ": not a NEXRAD Level II file (no 24-byte 'AR2V00' volume header)");
  }
  const bool chosen = !options.fieldName.empty();
  return readWithField(path, file, chosen ? upper(options.fieldName) : std::string("REF"), options, chosen);
}

}  // namespace atmoglobe::volume
