#include <atmoglobe/volume/NexradReader.h>

#include <atmoglobe/volume/StationList.h>

#include <bzlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
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

std::string formatAngle(double deg) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", deg);
  return buf;
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

// Radial status (message 31 byte 21, message 1 halfword 7; ICD 2620002): 0 start of an
// elevation, 1 intermediate, 2 end of an elevation, 3 start of the volume, 4 end of the volume,
// 5 start of the last elevation.
bool statusStartsCut(unsigned s) { return s == 0 || s == 3 || s == 5; }
bool statusEndsCut(unsigned s) { return s == 2 || s == 4; }

// One cut (elevation number) being collected. Values are stored directly in the sweep layout
// (ray-major, `stride` gates a ray, kNoData padding) so the finished array is moved, not copied.
struct Cut {
  int elevationNumber = 0;
  std::vector<float> azimuthDeg, elevationDeg;
  std::vector<float> values;  // rows of `stride` gates, one per ray seen so far
  std::uint32_t stride = 0;   // largest gate count of the field in this cut
  double firstGateMeters = 0, gateSpacingMeters = 0;
  bool hasField = false;
  // Bookkeeping for completeness and duplicates.
  std::set<unsigned> azimuthNumbers;
  unsigned maxAzimuthNumber = 0;
  bool sawStart = false, sawEnd = false;
  double azimuthSpacingDeg = 0;  // nominal (message 31 azimuth resolution; 1 deg for message 1)
  std::uint32_t firstDay = 0, firstMs = 0, lastDay = 0, lastMs = 0;

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

  // Complete: the end-of-elevation radial was seen and every azimuth number up to the last.
  bool complete() const { return sawStart && sawEnd && azimuthNumbers.size() == maxAzimuthNumber; }
};

/// One moment of one radial, as both message types describe it.
struct Moment {
  std::string name;
  std::uint32_t gates = 0;
  int firstGateMeters = 0, intervalMeters = 0;
  unsigned wordBits = 8;
  float scale = 1, offset = 0;
  const unsigned char* raw = nullptr;
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
  std::size_t radials = 0;        // message 31
  std::size_t legacyRadials = 0;  // message 1
  std::size_t duplicateRadials = 0;
  bool sawEndOfVolume = false;
  std::uint32_t firstRadialDay = 0, firstRadialMs = 0;

 private:
  Error fail(std::size_t record, const std::string& what) const {
    return makeError(path_ + ": NEXRAD record " + std::to_string(record) + ": " + what);
  }
  Status parseVcp(const unsigned char* body, std::size_t size, std::size_t record);
  Status parseRadial(const unsigned char* body, std::size_t size, std::size_t record);
  Status parseLegacyRadial(const unsigned char* body, std::size_t size, std::size_t record);
  // Registers a radial of `cut` (nullptr when it repeats one already seen: dropped).
  Cut* beginRadial(int elevationNumber, unsigned azimuthNumber, unsigned status, float azimuth, float elevation,
                   std::uint32_t day, std::uint32_t ms);
  Status storeMoment(Cut& cut, std::size_t rayIndex, const Moment& m, std::size_t record, const std::string& where);
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
        if (Status s = parseLegacyRadial(header + kMessageHeaderBytes, bodyBytes, record); !s) return s;
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

Cut* Parser::beginRadial(int elevationNumber, unsigned azimuthNumber, unsigned status, float azimuth, float elevation,
                         std::uint32_t day, std::uint32_t ms) {
  Cut& cut = cuts[elevationNumber];
  if (cut.azimuthDeg.empty() && cut.azimuthNumbers.empty()) {
    cut.elevationNumber = elevationNumber;
    cutOrder.push_back(elevationNumber);
  }
  if (azimuthNumber > 0 && !cut.azimuthNumbers.insert(azimuthNumber).second) {
    ++duplicateRadials;  // the same radial twice (a chunk given twice): the first is kept
    return nullptr;
  }
  cut.maxAzimuthNumber = std::max(cut.maxAzimuthNumber, azimuthNumber);
  if (statusStartsCut(status)) cut.sawStart = true;
  if (statusEndsCut(status)) cut.sawEnd = true;
  if (status == 4) sawEndOfVolume = true;
  if (cut.azimuthDeg.empty()) cut.firstDay = day, cut.firstMs = ms;
  cut.lastDay = day, cut.lastMs = ms;
  float az = std::fmod(azimuth, 360.0f);
  if (az < 0) az += 360.0f;
  cut.azimuthDeg.push_back(az);
  cut.elevationDeg.push_back(elevation);
  return &cut;
}

Status Parser::storeMoment(Cut& cut, std::size_t rayIndex, const Moment& m, std::size_t record,
                           const std::string& where) {
  if (std::find(fieldNames.begin(), fieldNames.end(), m.name) == fieldNames.end()) fieldNames.push_back(m.name);
  if (upper(m.name) != field_) return Ok{};
  if (m.intervalMeters <= 0)
    return fail(record, where + ": moment " + m.name + " gate interval " + std::to_string(m.intervalMeters) + " m");
  if (!std::isfinite(m.scale) || m.scale == 0.0f || !std::isfinite(m.offset)) {
    return fail(record, where + ": moment " + m.name + " has an unusable scale/offset");
  }
  if (!cut.hasField) {
    cut.hasField = true;
    cut.firstGateMeters = m.firstGateMeters;
    cut.gateSpacingMeters = m.intervalMeters;
  } else if (cut.firstGateMeters != m.firstGateMeters || cut.gateSpacingMeters != m.intervalMeters) {
    return fail(record, where + ": moment " + m.name + " gate geometry changes within elevation cut " +
                            std::to_string(cut.elevationNumber));
  }
  if (!loadValues_) {
    cut.stride = std::max(cut.stride, m.gates);
    return Ok{};
  }
  float* out = cut.row(rayIndex, m.gates);
  if (m.wordBits == 8) {
    std::array<float, 256> lut;
    lut[0] = kNoEcho;
    lut[1] = kNoData;
    for (int v = 2; v < 256; ++v) lut[v] = (static_cast<float>(v) - m.offset) / m.scale;
    for (std::uint32_t g = 0; g < m.gates; ++g) out[g] = lut[m.raw[g]];
  } else {
    for (std::uint32_t g = 0; g < m.gates; ++g) {
      const std::uint16_t v = be16(m.raw + 2 * g);
      out[g] = v == 0 ? kNoEcho : v == 1 ? kNoData : (static_cast<float>(v) - m.offset) / m.scale;
    }
  }
  return Ok{};
}

Status Parser::parseRadial(const unsigned char* body, std::size_t size, std::size_t record) {
  constexpr std::size_t kRadialHeaderBytes = 32;
  if (size < kRadialHeaderBytes) return fail(record, "message 31 shorter than its radial header");
  const std::size_t radialIndex = radials++;
  const std::string where = "radial " + std::to_string(radialIndex);
  const std::uint32_t ms = be32(body + 4);
  const std::uint32_t day = be16(body + 8);
  if (radialIndex == 0 && legacyRadials == 0) {
    firstRadialMs = ms;
    firstRadialDay = day;
  }
  const unsigned azimuthNumber = be16(body + 10);
  const float azimuth = beFloat(body + 12);
  const unsigned resolution = body[20];  // 1: 0.5 deg, 2: 1 deg
  const unsigned status = body[21];
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
  Cut* cutPtr = beginRadial(elevationNumber, azimuthNumber, status, azimuth, elevation, day, ms);
  if (cutPtr == nullptr) return Ok{};
  Cut& cut = *cutPtr;
  if (cut.azimuthSpacingDeg == 0) cut.azimuthSpacingDeg = resolution == 1 ? 0.5 : 1.0;
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
      Moment m;
      m.name = name;
      m.gates = be16(block + 8);
      m.firstGateMeters = static_cast<std::int16_t>(be16(block + 10));
      m.intervalMeters = static_cast<std::int16_t>(be16(block + 12));
      m.wordBits = block[19];
      m.scale = beFloat(block + 20);
      m.offset = beFloat(block + 24);
      m.raw = block + kMomentHeaderBytes;
      if (upper(name) == field_) {
        if (m.wordBits != 8 && m.wordBits != 16) {
          return fail(record, where + ": moment " + name + " has word size " + std::to_string(m.wordBits) +
                                  " (8 or 16 expected)");
        }
        const std::size_t dataBytes = std::size_t{m.gates} * (m.wordBits / 8);
        if (ptr + kMomentHeaderBytes + dataBytes > size) {
          return fail(record,
                      where + ": moment " + name + " claims " + std::to_string(m.gates) + " gates, beyond the message");
        }
      }
      if (Status s = storeMoment(cut, rayIndex, m, record, where); !s) return s;
    }
  }
  if (loadValues_ && cut.stride > 0) cut.row(rayIndex, 0);  // pads a ray without the field
  return Ok{};
}

// Message 1 (digital radar data, the layout before message 31; ICD 2620002 before build 10):
// a 100-byte header then 8-bit moments. Byte offsets in the message body (after the 16-byte
// message header): 0 collection time (ms, uint32), 4 modified Julian date, 8 azimuth (binary
// angle, 360 deg = 65536), 10 azimuth number, 12 radial status, 14 elevation (binary angle),
// 16 elevation number, 18 / 20 range to the first surveillance / Doppler gate (m, int16),
// 22 / 24 surveillance / Doppler gate interval (m), 26 / 28 surveillance / Doppler gate counts,
// 36 / 38 / 40 pointers to reflectivity / velocity / spectrum width (bytes from the body's
// start; 0 = absent), 42 velocity resolution (2: 0.5 m/s, 4: 1 m/s), 44 VCP number,
// 60 Nyquist velocity (int16, 0.01 m/s). Values: REF = (raw - 66) / 2 dBZ; VEL = (raw - 129) / 2
// m/s (0.5 m/s resolution) or raw - 129 (1 m/s); SW = (raw - 129) / 2 m/s; raw 0 below
// threshold, raw 1 range folded, as in message 31.
Status Parser::parseLegacyRadial(const unsigned char* body, std::size_t size, std::size_t record) {
  constexpr std::size_t kHeaderBytes = 100;
  if (size < kHeaderBytes) return fail(record, "message 1 shorter than its 100-byte radial header");
  const std::size_t radialIndex = legacyRadials++;
  const std::string where = "message 1 radial " + std::to_string(radialIndex);
  const std::uint32_t ms = be32(body + 0);
  const std::uint32_t day = be16(body + 4);
  if (radialIndex == 0 && radials == 0) {
    firstRadialMs = ms;
    firstRadialDay = day;
  }
  constexpr double kBinaryAngle = 360.0 / 65536.0;
  const auto azimuth = static_cast<float>(be16(body + 8) * kBinaryAngle);
  double elevationDeg = be16(body + 14) * kBinaryAngle;
  if (elevationDeg > 180.0) elevationDeg -= 360.0;  // a negative elevation
  if (elevationDeg < -90.0 || elevationDeg > 90.0) {
    return fail(record, where + ": elevation " + formatAngle(elevationDeg) + " deg is outside [-90, 90]");
  }
  const unsigned azimuthNumber = be16(body + 10);
  const unsigned status = be16(body + 12);
  const int elevationNumber = be16(body + 16);
  if (elevationNumber > 255) return fail(record, where + ": elevation number " + std::to_string(elevationNumber));
  Cut* cutPtr = beginRadial(elevationNumber, azimuthNumber, status, azimuth, static_cast<float>(elevationDeg), day, ms);
  if (cutPtr == nullptr) return Ok{};
  Cut& cut = *cutPtr;
  if (cut.azimuthSpacingDeg == 0) cut.azimuthSpacingDeg = 1.0;
  const std::size_t rayIndex = cut.azimuthDeg.size() - 1;
  if (vcp == 0) vcp = be16(body + 44);
  const double nyquist = static_cast<std::int16_t>(be16(body + 60)) * 0.01;
  if (nyquist > 0.0 && nyquist < 200.0 && !(nyquist <= nyquistMps)) nyquistMps = nyquist;

  const int surFirst = static_cast<std::int16_t>(be16(body + 18));
  const int dopFirst = static_cast<std::int16_t>(be16(body + 20));
  const int surStep = be16(body + 22), dopStep = be16(body + 24);
  const std::uint32_t surBins = be16(body + 26), dopBins = be16(body + 28);
  const unsigned velResolution = be16(body + 42);
  struct Spec {
    const char* name;
    std::size_t pointer;
    std::uint32_t gates;
    int first, step;
    float scale, offset;
  };
  const Spec specs[] = {
      {"REF", be16(body + 36), surBins, surFirst, surStep, 2.0f, 66.0f},
      {"VEL", be16(body + 38), dopBins, dopFirst, dopStep, velResolution == 4 ? 1.0f : 2.0f, 129.0f},
      {"SW", be16(body + 40), dopBins, dopFirst, dopStep, 2.0f, 129.0f},
  };
  for (const Spec& sp : specs) {
    if (sp.pointer == 0 || sp.gates == 0) continue;
    if (sp.pointer < kHeaderBytes || sp.pointer + sp.gates > size) {
      return fail(record, where + ": moment " + sp.name + " (pointer " + std::to_string(sp.pointer) + ", " +
                              std::to_string(sp.gates) + " gates) does not fit the " + std::to_string(size) +
                              "-byte message");
    }
    Moment m;
    m.name = sp.name;
    m.gates = sp.gates;
    m.firstGateMeters = sp.first;
    m.intervalMeters = sp.step;
    m.wordBits = 8;
    m.scale = sp.scale;
    m.offset = sp.offset;
    m.raw = body + sp.pointer;
    if (Status s = storeMoment(cut, rayIndex, m, record, where); !s) return s;
  }
  if (loadValues_ && cut.stride > 0) cut.row(rayIndex, 0);
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

/// A piece of a volume: a whole file after its volume header, or one real-time chunk.
struct Segment {
  std::string path;
  const std::vector<unsigned char>* bytes = nullptr;
  std::size_t offset = 0;  ///< where the records start (24 after a volume header)
  bool rawFrames = false;  ///< legacy: uncompressed 2432-byte frames, no LDM records
};

/// The legacy layout (message 1 in uncompressed frames right after the header): the header says
/// ARCHIVE2 or AR2V0001 and no bzip2 LDM record follows it.
bool isRawFrameLayout(const std::vector<unsigned char>& file) {
  const bool legacyHeader = std::memcmp(file.data(), "ARCHIVE2", 8) == 0 ||
                            std::memcmp(file.data(), "AR2V0001", 8) == 0;
  const bool ldm = file.size() >= kVolumeHeaderBytes + 7 && std::memcmp(&file[kVolumeHeaderBytes + 4], "BZh", 3) == 0;
  return legacyHeader && !ldm;
}

Status parseSegment(Parser& parser, const Segment& seg, std::vector<unsigned char>& buffer, std::size_t* record) {
  const std::vector<unsigned char>& file = *seg.bytes;
  const std::string& path = seg.path;
  if (seg.rawFrames) {
    if (Status s = parser.parseRecord(file.data() + seg.offset, file.size() - seg.offset, (*record)++); !s)
      return s.forwardError();
    return Ok{};
  }
  std::size_t pos = seg.offset;
  while (pos < file.size()) {
    if (file.size() - pos < 4) return makeError(path + ": truncated NEXRAD record size at byte " + std::to_string(pos));
    const auto control = static_cast<std::int32_t>(be32(&file[pos]));
    const std::size_t length = control < 0
                                   ? std::size_t{0} - static_cast<std::size_t>(static_cast<std::int64_t>(control))
                                   : static_cast<std::size_t>(control);
    pos += 4;
    if (length == 0)
      return makeError(path + ": NEXRAD record " + std::to_string(*record) + " at byte " + std::to_string(pos - 4) +
                       " has size 0");
    if (length > file.size() - pos) {
      return makeError(path + ": NEXRAD record " + std::to_string(*record) + " at byte " + std::to_string(pos - 4) +
                       " claims " + std::to_string(length) + " bytes but only " + std::to_string(file.size() - pos) +
                       " remain (truncated or corrupt file)");
    }
    const unsigned char* data = &file[pos];
    if (length >= 3 && std::memcmp(data, "BZh", 3) == 0) {
      std::size_t produced = 0;
      if (Status s = decompressRecord(path, *record, data, length, &buffer, &produced); !s) return s.forwardError();
      if (Status s = parser.parseRecord(buffer.data(), produced, *record); !s) return s.forwardError();
    } else {
      if (Status s = parser.parseRecord(data, length, *record); !s) return s.forwardError();
    }
    pos += length;
    ++*record;
    if (control < 0) break;
  }
  return Ok{};
}

/// "1 (0.53 deg), 3 (1.45 deg)" for a list of cut numbers.
std::string describeCuts(const std::vector<int>& numbers, const std::map<int, double>& angleByCut) {
  std::string out;
  for (int n : numbers) {
    out += (out.empty() ? "" : ", ") + std::to_string(n);
    if (auto it = angleByCut.find(n); it != angleByCut.end()) out += " (" + formatAngle(it->second) + " deg)";
  }
  return out;
}

/// Fills the azimuths a partial cut has not reached yet with no-data rays at its nominal spacing,
/// so no renderer interpolates across the gap. Returns the covered azimuth span as text.
void padPartialSweep(Sweep& sw, double spacingDeg, bool loadValues) {
  if (sw.azimuthDeg.empty() || spacingDeg <= 0) return;
  std::vector<float> sorted = sw.azimuthDeg;
  std::sort(sorted.begin(), sorted.end());
  double meanEl = 0;
  for (float e : sw.elevationDeg) meanEl += e;
  meanEl /= static_cast<double>(sw.elevationDeg.size());
  std::vector<float> added;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const double a = sorted[i];
    const double b = i + 1 < sorted.size() ? sorted[i + 1] : sorted[0] + 360.0;
    if (b - a <= 1.5 * spacingDeg) continue;
    for (double x = a + spacingDeg; x < b - 0.5 * spacingDeg; x += spacingDeg)
      added.push_back(static_cast<float>(std::fmod(x, 360.0)));
  }
  for (float a : added) {
    sw.azimuthDeg.push_back(a);
    sw.elevationDeg.push_back(static_cast<float>(meanEl));
  }
  if (loadValues) sw.values.resize(sw.rayCount() * sw.gateCount, kNoData);
}

Result<RadarVolume> readWithField(const std::string& label, const std::vector<Segment>& segments,
                                  const std::string& fieldUpper, const ReadOptions& options, bool fieldChosen) {
  Parser parser(label, fieldUpper, options.loadValues);
  std::vector<unsigned char> buffer;
  std::size_t record = 0;
  for (const Segment& seg : segments) {
    parser.path_ = seg.path;
    if (Status s = parseSegment(parser, seg, buffer, &record); !s) return s.forwardError();
  }
  const std::string& path = label;
  const std::vector<unsigned char>& header = *segments.front().bytes;

  if (parser.radials == 0 && parser.legacyRadials == 0)
    return makeError(path +
                     ": no radials found (neither message 31 nor message 1: not a NEXRAD Level II volume, or "
                     "empty)");

  RadarVolume vol;
  vol.format = "NEXRAD Level II";
  vol.sourcePath = path;
  vol.site.name = trimName(header.data() + 20, 4);
  std::string locationSource;
  std::string list = options.nexradSiteList;
  if (list.empty()) {
    if (const char* env = std::getenv("ATMOGLOBE_NEXRAD_SITES"); env && *env) list = env;
  }
  std::string placeName;
  // The user's list ($ATMOGLOBE_NEXRAD_SITES, --nexrad-sites) wins over the built-in table.
  Result<std::vector<Station>> userStations = std::vector<Station>{};
  if (!list.empty()) userStations = readStationList(list);
  const std::vector<Station>& builtin = builtinNexradSites();
  const std::string listName = list.empty() ? std::string(kBuiltinNexradSiteTable) : "NEXRAD site list " + list;
  if (!parser.haveSite) {
    if (parser.legacyRadials == 0) return makeError(path + ": no VOL block: the file does not give the radar site");
    // Legacy files carry no position: the NEXRAD site list gives it from the ICAO id.
    const std::string icao = vol.site.name;
    if (!userStations) return makeError(path + ": NEXRAD site list: " + userStations.error());
    const Station* it = findStation(list.empty() ? builtin : *userStations, icao);
    if (icao.empty() || !it) {
      return makeError(path + ": a legacy NEXRAD Level II file (message 1) gives no site position, and its ICAO id '" +
                       icao + "' is not in " + listName +
                       (list.empty() ? "; give a list that has it: set ATMOGLOBE_NEXRAD_SITES=FILE (a CSV or JSON "
                                       "station list) or pass one (info --nexrad-sites FILE)"
                                     : ""));
    }
    parser.site.latDeg = it->latDeg;
    parser.site.lonDeg = it->lonDeg;
    placeName = it->name;
    // Antenna height: ground elevation + tower height (the OURadar list's "height").
    parser.site.antennaHeightMeters = it->elevationMeters + it->towerHeightMeters.value_or(0.0);
    parser.site.heightDatum = HeightDatum::MeanSeaLevel;
    locationSource = listName + " (" + it->id + ": ground " +
                     std::to_string(static_cast<long long>(std::lround(it->elevationMeters))) + " m + tower " +
                     std::to_string(static_cast<long long>(std::lround(it->towerHeightMeters.value_or(0)))) +
                     " m), not the file (legacy message-1 files give no position)";
    parser.haveSite = true;
  } else if (!vol.site.name.empty()) {
    // The place of the ICAO id, for titles only: a list that cannot be read, or that lacks the
    // id, leaves the name alone (the position comes from the file).
    const Station* it = findStation(list.empty() || !userStations ? builtin : *userStations, vol.site.name);
    if (it) placeName = it->name;
  }
  if (!std::isfinite(parser.site.latDeg) || std::abs(parser.site.latDeg) > 90.0 || !std::isfinite(parser.site.lonDeg) ||
      std::abs(parser.site.lonDeg) > 360.0) {
    return makeError(path + ": VOL block site latitude/longitude out of range");
  }

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
      auto again = readWithField(label, segments, upper(parser.fieldNames.front()), options, true);
      if (again)
        again->warnings.insert(again->warnings.begin(), "no REF moment in the volume: loaded " +
                                                            parser.fieldNames.front() + ", its first moment");
      return again;
    }
    std::string names;
    for (const std::string& n : parser.fieldNames) names += (names.empty() ? "" : ", ") + n;
    return makeError(path + ": field '" + options.fieldName + "' is not in the file (fields: " + names + ")");
  }
  const std::string siteName = vol.site.name;
  vol.loadedField = {loadedName, momentUnits(loadedName), {}};
  vol.nyquistVelocityMps = parser.nyquistMps;
  vol.site = parser.site;
  vol.site.name = siteName;
  vol.site.placeName = placeName == siteName ? std::string() : placeName;
  vol.siteLocationSource = locationSource;
  vol.timeIso8601 = isoTime(be32(header.data() + 12), be32(header.data() + 16));
  if (vol.timeIso8601.empty()) vol.timeIso8601 = isoTime(parser.firstRadialDay, parser.firstRadialMs);

  std::map<int, double> angleByCut;
  std::vector<int> withoutField, partial, missingEnd;
  std::string partialText;
  for (int number : parser.cutOrder) {
    Cut& cut = parser.cuts[number];
    double fixed = 0;
    if (number >= 1 && static_cast<std::size_t>(number) <= parser.vcpAnglesDeg.size() &&
        parser.vcpAnglesDeg[number - 1] > 0) {
      fixed = parser.vcpAnglesDeg[number - 1];
    } else {
      double sum = 0;
      for (float e : cut.elevationDeg) sum += e;
      fixed = cut.elevationDeg.empty() ? 0.0 : sum / static_cast<double>(cut.elevationDeg.size());
    }
    angleByCut[number] = fixed;
    if (!cut.hasField) {
      withoutField.push_back(number);  // split cut without this moment
      continue;
    }
    Sweep sw;
    sw.indexInFile = number - 1;
    sw.mode = SweepMode::Ppi;
    sw.firstGateRangeMeters = cut.firstGateMeters;
    sw.gateSpacingMeters = cut.gateSpacingMeters;
    sw.gateCount = cut.stride;
    sw.azimuthDeg = std::move(cut.azimuthDeg);
    sw.elevationDeg = std::move(cut.elevationDeg);
    sw.fixedAngleDeg = fixed;
    sw.startTimeIso8601 = isoTime(cut.firstDay, cut.firstMs);
    sw.endTimeIso8601 = isoTime(cut.lastDay, cut.lastMs);
    if (options.loadValues) {
      sw.values = std::move(cut.values);
      sw.values.resize(sw.rayCount() * sw.gateCount, kNoData);  // trailing rays without the field
    }
    if (!cut.complete()) {
      sw.complete = false;
      partial.push_back(number);
      partialText += (partialText.empty() ? "" : "; ") + std::string("cut ") + std::to_string(number) + " (" +
                     formatAngle(fixed) + " deg): " + std::to_string(sw.rayCount()) + " rays" +
                     (cut.maxAzimuthNumber > 0 && cut.sawEnd ? " of " + std::to_string(cut.maxAzimuthNumber)
                                                             : (cut.sawEnd ? "" : ", its end not reached"));
      padPartialSweep(sw, cut.azimuthSpacingDeg, options.loadValues);
    }
    vol.sweeps.push_back(std::move(sw));
  }
  for (std::size_t i = 0; i < parser.vcpAnglesDeg.size(); ++i) {
    const int number = static_cast<int>(i) + 1;
    if (parser.cuts.count(number) == 0) {
      missingEnd.push_back(number);
      angleByCut[number] = parser.vcpAnglesDeg[i];
    }
  }
  if (!withoutField.empty()) {
    vol.warnings.push_back("elevation cuts " + describeCuts(withoutField, angleByCut) + " hold no " + loadedName +
                           " and are left out (split cuts scan one angle twice, each time with part of the moments)");
  }
  if (parser.duplicateRadials > 0) {
    vol.warnings.push_back(std::to_string(parser.duplicateRadials) +
                           " duplicate radials (an elevation and azimuth number seen before) were dropped, the first "
                           "kept");
  }
  const bool inProgress = !partial.empty() || !missingEnd.empty() || (!parser.sawEndOfVolume && !parser.cuts.empty());
  if (inProgress) {
    std::vector<int> complete;
    for (int number : parser.cutOrder)
      if (parser.cuts[number].complete()) complete.push_back(number);
    std::string text = "incomplete volume (in progress, or its end is missing): ";
    text += complete.empty() ? std::string("no cut is complete")
                             : "complete cuts " + describeCuts(complete, angleByCut);
    if (!partialText.empty()) text += "; partial: " + partialText + " (the azimuths not reached are no data)";
    if (!missingEnd.empty()) {
      text += "; not in the data yet: cuts " + describeCuts(missingEnd, angleByCut) + " of VCP " +
              std::to_string(parser.vcp);
    }
    if (!parser.sawEndOfVolume) text += "; no end-of-volume radial";
    vol.warnings.push_back(text);
  }
  sortSweepsByAngle(vol);
  return vol;
}

Result<std::vector<unsigned char>> readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return makeError(path + ": cannot determine file size");
  in.seekg(0);
  std::vector<unsigned char> file(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(file.data()), size)) return makeError(path + ": read error");
  return file;
}

Result<RadarVolume> readSegments(const std::string& label, const std::vector<Segment>& segments,
                                 const ReadOptions& options) {
  const bool chosen = !options.fieldName.empty();
  return readWithField(label, segments, chosen ? upper(options.fieldName) : std::string("REF"), options, chosen);
}

/// (Julian day, ms) of the first radial (message 31 or 1) of a chunk's first record, for ordering.
std::optional<std::uint64_t> firstRadialTime(const std::string& path, const std::vector<unsigned char>& bytes,
                                             std::size_t offset) {
  if (bytes.size() < offset + 8) return std::nullopt;
  const auto control = static_cast<std::int32_t>(be32(&bytes[offset]));
  const std::size_t length = control < 0 ? std::size_t{0} - static_cast<std::size_t>(static_cast<std::int64_t>(control))
                                         : std::size_t(control);
  if (length == 0 || length > bytes.size() - offset - 4) return std::nullopt;
  std::vector<unsigned char> buffer;
  std::size_t produced = 0;
  if (!decompressRecord(path, 0, &bytes[offset + 4], length, &buffer, &produced)) return std::nullopt;
  std::size_t pos = 0;
  while (pos + kCtmBytes + kMessageHeaderBytes + 10 <= produced) {
    const unsigned char* header = buffer.data() + pos + kCtmBytes;
    const unsigned type = header[3];
    const unsigned char* body = header + kMessageHeaderBytes;
    if (type == 31) return (std::uint64_t{be16(body + 8)} << 32) | be32(body + 4);
    if (type == 1) return (std::uint64_t{be16(body + 4)} << 32) | be32(body + 0);
    pos += type == 31 ? kCtmBytes + std::size_t{be16(header)} * 2 : kFrameBytes;
  }
  return std::nullopt;
}

}  // namespace

bool looksLikeNexradLevel2(const unsigned char* bytes, std::size_t size) {
  return size >= 8 && (std::memcmp(bytes, "AR2V00", 6) == 0 || std::memcmp(bytes, "ARCHIVE2", 8) == 0);
}

bool looksLikeNexradChunk(const unsigned char* bytes, std::size_t size) {
  return size >= 7 && std::memcmp(bytes + 4, "BZh", 3) == 0 && be32(bytes) != 0;
}

Result<RadarVolume> readNexradLevel2(const std::string& path, const ReadOptions& options) {
  auto file = readFileBytes(path);
  if (!file) return file.forwardError();
  return readNexradLevel2(path, *file, options);
}

Result<RadarVolume> readNexradLevel2(const std::string& path, const std::vector<unsigned char>& file,
                                     const ReadOptions& options) {
  if (file.size() < kVolumeHeaderBytes || !looksLikeNexradLevel2(file.data(), file.size())) {
    return makeError(path + ": not a NEXRAD Level II file (no 24-byte 'AR2V00' or 'ARCHIVE2' volume header)");
  }
  Segment seg{path, &file, kVolumeHeaderBytes, isRawFrameLayout(file)};
  return readSegments(path, {seg}, options);
}

Result<RadarVolume> readNexradChunks(const std::vector<std::string>& paths, const std::string& label,
                                     const ReadOptions& options) {
  if (paths.empty()) return makeError(label + ": no NEXRAD chunks given");
  std::vector<std::vector<unsigned char>> files;
  files.reserve(paths.size());
  std::vector<std::size_t> starts, others;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    auto bytes = readFileBytes(paths[i]);
    if (!bytes) return bytes.forwardError();
    files.push_back(std::move(*bytes));
    const auto& f = files.back();
    if (f.size() >= kVolumeHeaderBytes && looksLikeNexradLevel2(f.data(), f.size())) {
      starts.push_back(i);
    } else if (looksLikeNexradChunk(f.data(), f.size())) {
      others.push_back(i);
    } else {
      return makeError(paths[i] +
                       ": not a NEXRAD Level II chunk (neither the 24-byte volume header of a start chunk nor an "
                       "LDM record: a 4-byte size and a bzip2 stream)");
    }
  }
  if (starts.empty()) {
    return makeError(label + ": no start chunk among the " + std::to_string(paths.size()) +
                     " NEXRAD chunks (the one beginning with the 24-byte AR2V volume header, '-S' in the feed's "
                     "names): the volume's site, time and scan strategy are in it");
  }
  if (starts.size() > 1) {
    std::string names;
    for (std::size_t i : starts) names += (names.empty() ? "" : ", ") + paths[i];
    return makeError(label + ": " + std::to_string(starts.size()) +
                     " start chunks (files with a volume header) in one set: " + names +
                     "; the chunks of one volume have one start chunk (give one volume's chunks)");
  }
  // The chunks after the start chunk in the order they were scanned: by the time of their first
  // radial (content, not names), names breaking ties.
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed;
  for (std::size_t i : others) {
    const auto t = firstRadialTime(paths[i], files[i], 0);
    keyed.emplace_back(t.value_or(0), i);
  }
  std::stable_sort(keyed.begin(), keyed.end(), [&](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Segment> segments;
  const std::size_t s = starts.front();
  segments.push_back({paths[s], &files[s], kVolumeHeaderBytes, isRawFrameLayout(files[s])});
  for (const auto& [key, i] : keyed) segments.push_back({paths[i], &files[i], 0, false});
  auto vol = readSegments(label, segments, options);
  if (!vol) return vol;
  vol->sourcePath = label;
  for (const Segment& seg : segments) vol->sourceFiles.push_back(seg.path);
  vol->warnings.insert(vol->warnings.begin(), "assembled from " + std::to_string(paths.size()) +
                                                  " real-time chunks (start chunk " + paths[s] + ")");
  return vol;
}

}  // namespace atmoglobe::volume
