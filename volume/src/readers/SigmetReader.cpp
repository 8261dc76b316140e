#include <atmoglobe/volume/SigmetReader.h>
#include "ReadUnwrapped.h"

#include <atmoglobe/io/Compression.h>
#include <atmoglobe/volume/RadarReader.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <limits>

namespace atmoglobe::volume {

namespace {

constexpr std::size_t kRecord = kSigmetRecordBytes;
constexpr std::size_t kBhdrBytes = 12;              // raw_prod_bhdr
constexpr std::size_t kIngestDataHeaderBytes = 76;  // ingest_data_header
constexpr std::size_t kRayHeaderWords = 6;
constexpr int kProductHdrId = 27, kIngestHeaderId = 23, kIngestDataHeaderId = 24, kRawProductType = 15;

std::uint16_t u16(const unsigned char* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::int16_t s16(const unsigned char* p) { return static_cast<std::int16_t>(u16(p)); }
std::uint32_t u32(const unsigned char* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) | (std::uint32_t{p[3]} << 24);
}
std::int32_t s32(const unsigned char* p) { return static_cast<std::int32_t>(u32(p)); }
/// IRIS binary angles: BIN2 = 360 / 2^16 deg, BIN4 = 360 / 2^32 deg per unit.
double bin2(std::uint16_t v) { return v * (360.0 / 65536.0); }
double bin4(std::uint32_t v) { return v * (360.0 / 4294967296.0); }
/// An angle in [0, 360) as (-180, 180] (latitudes, longitudes, elevations).
double signedDeg(double a) { return a > 180.0 ? a - 360.0 : a; }

std::string trimText(const unsigned char* p, std::size_t n) {
  std::string s(reinterpret_cast<const char*>(p), n);
  const auto nul = s.find('\0');
  if (nul != std::string::npos) s.resize(nul);
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

/// ymds_time (12 bytes): seconds of the day (SINT4), milliseconds + flags (UINT2: ms in the low 10
/// bits, 0x800 = UTC), year, month, day (SINT2). `westMinutes`: added when the UTC flag is clear.
std::string ymdsIso(const unsigned char* p, int westMinutes) {
  const std::int32_t seconds = s32(p);
  const std::uint16_t msFlags = u16(p + 4);
  const int year = s16(p + 6), month = s16(p + 8), day = s16(p + 10);
  if (year < 1900 || month < 1 || month > 12 || day < 1 || day > 31 || seconds < 0 || seconds > 86400 * 2) return {};
  std::tm tm{};
  tm.tm_year = year - 1900;
  tm.tm_mon = month - 1;
  tm.tm_mday = day;
  std::int64_t t = static_cast<std::int64_t>(timegm(&tm)) + seconds;
  if ((msFlags & 0x800) == 0) t += static_cast<std::int64_t>(westMinutes) * 60;
  const std::time_t tt = static_cast<std::time_t>(t);
  std::tm out{};
  if (gmtime_r(&tt, &out) == nullptr) return {};
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &out);
  return buf;
}

enum class Decode { Dbz1, Vel1, Width1, Zdr1, Phidp1, Rho1, Ldr1, Centred2, Width2, Rho2, Phidp2 };

struct TypeInfo {
  int code;
  const char* name;
  const char* units;
  const char* standardName;
  int bytes;
  Decode decode;
};

// IRIS data types with a published conversion (IRIS Programmer's Manual, data type table and the
// 1-/2-byte format sections).
constexpr TypeInfo kTypes[] = {
    {1, "DBT", "dBZ", "", 1, Decode::Dbz1},
    {2, "DBZ", "dBZ", "equivalent_reflectivity_factor", 1, Decode::Dbz1},
    {3, "VEL", "m/s", "radial_velocity_of_scatterers_away_from_instrument", 1, Decode::Vel1},
    {4, "WIDTH", "m/s", "doppler_spectrum_width", 1, Decode::Width1},
    {5, "ZDR", "dB", "log_differential_reflectivity_hv", 1, Decode::Zdr1},
    {7, "DBZC", "dBZ", "", 1, Decode::Dbz1},
    {8, "DBT2", "dBZ", "", 2, Decode::Centred2},
    {9, "DBZ2", "dBZ", "equivalent_reflectivity_factor", 2, Decode::Centred2},
    {10, "VEL2", "m/s", "radial_velocity_of_scatterers_away_from_instrument", 2, Decode::Centred2},
    {11, "WIDTH2", "m/s", "doppler_spectrum_width", 2, Decode::Width2},
    {12, "ZDR2", "dB", "log_differential_reflectivity_hv", 2, Decode::Centred2},
    {15, "KDP2", "deg/km", "specific_differential_phase_hv", 2, Decode::Centred2},
    {16, "PHIDP", "degrees", "differential_phase_hv", 1, Decode::Phidp1},
    {18, "SQI", "unitless", "", 1, Decode::Rho1},
    {19, "RHOHV", "unitless", "cross_correlation_ratio_hv", 1, Decode::Rho1},
    {20, "RHOHV2", "unitless", "cross_correlation_ratio_hv", 2, Decode::Rho2},
    {21, "DBZC2", "dBZ", "", 2, Decode::Centred2},
    {22, "VELC2", "m/s", "", 2, Decode::Centred2},
    {23, "SQI2", "unitless", "", 2, Decode::Rho2},
    {24, "PHIDP2", "degrees", "differential_phase_hv", 2, Decode::Phidp2},
    {25, "LDRH", "dB", "", 1, Decode::Ldr1},
    {26, "LDRH2", "dB", "", 2, Decode::Centred2},
    {27, "LDRV", "dB", "", 1, Decode::Ldr1},
    {28, "LDRV2", "dB", "", 2, Decode::Centred2},
    {57, "ZDRC", "dB", "", 1, Decode::Zdr1},
    {58, "ZDRC2", "dB", "", 2, Decode::Centred2},
    {61, "DBTV8", "dBZ", "", 1, Decode::Dbz1},
    {62, "DBTV16", "dBZ", "", 2, Decode::Centred2},
    {63, "DBZV8", "dBZ", "", 1, Decode::Dbz1},
    {64, "DBZV16", "dBZ", "", 2, Decode::Centred2},
};

const TypeInfo* typeInfo(int code) {
  for (const TypeInfo& t : kTypes)
    if (t.code == code) return &t;
  return nullptr;
}

/// Raw bin -> physical value (raw 0: no echo; the top raw value: area not scanned = no data).
float decodeValue(const TypeInfo& t, unsigned raw, double nyquist, double nyquistVel) {
  if (raw == 0) return kNoEcho;
  if ((t.bytes == 1 && raw == 255) || (t.bytes == 2 && raw == 65535)) return kNoData;
  const double n = raw;
  switch (t.decode) {
    case Decode::Dbz1: return static_cast<float>((n - 64.0) / 2.0);
    case Decode::Vel1:
      return std::isfinite(nyquistVel) ? static_cast<float>((n - 128.0) / 127.0 * nyquistVel) : kNoData;
    case Decode::Width1: return std::isfinite(nyquist) ? static_cast<float>(n / 256.0 * nyquist) : kNoData;
    case Decode::Zdr1: return static_cast<float>((n - 128.0) / 16.0);
    case Decode::Phidp1: return static_cast<float>(180.0 * (n - 1.0) / 254.0);
    case Decode::Rho1: return static_cast<float>(std::sqrt((n - 1.0) / 253.0));
    case Decode::Ldr1: return static_cast<float>((n - 1.0) / 5.0 - 45.0);
    case Decode::Centred2: return static_cast<float>((n - 32768.0) / 100.0);
    case Decode::Width2: return static_cast<float>(n / 100.0);
    case Decode::Rho2: return static_cast<float>((n - 1.0) / 65533.0);
    case Decode::Phidp2: return static_cast<float>(360.0 * (n - 1.0) / 65534.0);
  }
  return kNoData;
}

/// The 16-bit words of one sweep's records after their raw_prod_bhdr, read in order.
class WordStream {
 public:
  struct Segment {
    const unsigned char* data;
    std::size_t bytes;
  };
  explicit WordStream(std::vector<Segment> segments) : segs_(std::move(segments)) {}
  bool next(std::uint16_t* w) {
    while (seg_ < segs_.size() && pos_ + 2 > segs_[seg_].bytes) {
      ++seg_;
      pos_ = 0;
    }
    if (seg_ >= segs_.size()) return false;
    *w = u16(segs_[seg_].data + pos_);
    pos_ += 2;
    return true;
  }

 private:
  std::vector<Segment> segs_;
  std::size_t seg_ = 0, pos_ = 0;
};

struct SweepType {
  const TypeInfo* info = nullptr;  // null: not decoded (extended headers, unknown types)
  int code = 0;
  int bits = 0;
};

class Reader {
 public:
  Reader(const std::string& label, const std::vector<unsigned char>& bytes, const ReadOptions& options)
      : label_(label), b_(bytes), options_(options) {}
  Result<RadarVolume> read();

 private:
  Error fail(const std::string& what) const { return makeError(label_ + ": Sigmet/IRIS " + what); }
  Status readSweep(const std::vector<std::size_t>& records, RadarVolume& vol, int loadedCode);

  std::string label_;
  const std::vector<unsigned char>& b_;
  ReadOptions options_;
  std::vector<int> typeCodes_;
  std::uint32_t bins_ = 0;
  double firstBinMeters_ = 0, binStepMeters_ = 0;
  SweepMode mode_ = SweepMode::Ppi;
  double nyquist_ = std::numeric_limits<double>::quiet_NaN();
  double nyquistVel_ = std::numeric_limits<double>::quiet_NaN();
  int westMinutes_ = 0;
};

Result<RadarVolume> Reader::read() {
  const std::size_t n = b_.size();
  if (n < 2 * kRecord || !looksLikeSigmetRaw(b_.data(), n)) {
    if (!looksLikeSigmetRaw(b_.data(), n))
      return fail("RAW: no product_hdr of a RAW product (structure id 27, product type 15) at byte 0");
    return fail("RAW: truncated: " + std::to_string(n) + " bytes, the product and ingest headers alone take " +
                std::to_string(2 * kRecord));
  }
  const unsigned char* ih = b_.data() + kRecord;  // ingest_header
  if (s16(ih) != kIngestHeaderId)
    return fail("record 1 is not an ingest_header (structure id " + std::to_string(s16(ih)) + ", expected 23)");

  RadarVolume vol;
  vol.format = "Sigmet/IRIS RAW";
  vol.sourcePath = label_;
  // ingest_configuration (ingest_header + 12)
  vol.site.name = trimText(ih + 162, 16);
  vol.site.latDeg = signedDeg(bin4(u32(ih + 180)));
  vol.site.lonDeg = signedDeg(bin4(u32(ih + 184)));
  const std::int32_t altitudeCm = s32(ih + 200);
  vol.site.antennaHeightMeters = altitudeCm != 0 ? altitudeCm / 100.0 : double(s16(ih + 188)) + double(s16(ih + 190));
  vol.site.heightDatum = HeightDatum::MeanSeaLevel;
  if (std::abs(vol.site.latDeg) > 90.0)
    return fail(
        std::string("site latitude ").append(std::to_string(vol.site.latDeg)).append(" deg is outside [-90, 90]"));
  westMinutes_ = s16(ih + 178);
  vol.timeIso8601 = ymdsIso(ih + 100, westMinutes_);

  // task_configuration (ingest_header + 492): DSP data mask (task_dsp_info at +624).
  const std::uint32_t words[5] = {u32(ih + 628), u32(ih + 636), u32(ih + 640), u32(ih + 644), u32(ih + 648)};
  for (int w = 0; w < 5; ++w)
    for (int bit = 0; bit < 32; ++bit)
      if ((words[w] >> bit) & 1u) typeCodes_.push_back(32 * w + bit);
  if (typeCodes_.empty()) return fail("ingest header: the DSP data mask lists no data type");
  const std::int32_t prf = s32(ih + 760);
  const std::uint16_t multiPrf = u16(ih + 768);
  // task_range_info (+1264)
  const std::int32_t firstBinCm = s32(ih + 1264);
  const std::int16_t outBins = s16(ih + 1274);
  const std::int32_t stepCm = s32(ih + 1280);
  if (u16(ih + 1284) != 0) return fail("task uses variable range-bin spacing, which is not supported");
  if (outBins <= 0 || stepCm <= 0 || firstBinCm < 0)
    return fail("task_range_info: " + std::to_string(outBins) + " output bins of " + std::to_string(stepCm) +
                " cm from " + std::to_string(firstBinCm) + " cm (need > 0 bins and step)");
  bins_ = static_cast<std::uint32_t>(outBins);
  firstBinMeters_ = firstBinCm / 100.0;
  binStepMeters_ = stepCm / 100.0;
  // task_scan_info (+1424)
  const std::uint16_t scanMode = u16(ih + 1424);
  mode_ = (scanMode == 1 || scanMode == 4) ? SweepMode::Ppi : scanMode == 2 ? SweepMode::Rhi : SweepMode::Other;
  // task_misc_info (+1744): wavelength (1/100 cm), horizontal beam width (BIN4)
  const std::int32_t wavelength = s32(ih + 1744);
  vol.beamWidthDeg = bin4(u32(ih + 1808));
  if (!(vol.beamWidthDeg > 0 && vol.beamWidthDeg < 20)) vol.beamWidthDeg = 0;
  if (wavelength > 0 && prf > 0) {
    nyquist_ = wavelength / 1.0e4 * prf / 4.0;
    nyquistVel_ = nyquist_ * (multiPrf <= 3 ? multiPrf + 1 : 1);
  }

  for (int code : typeCodes_) {
    if (const TypeInfo* t = typeInfo(code)) {
      vol.fields.push_back({t->name, t->units, t->standardName});
      if (t->decode == Decode::Vel1 || t->decode == Decode::Width1 ||
          std::string(t->standardName) == "radial_velocity_of_scatterers_away_from_instrument")
        vol.nyquistVelocityMps = nyquistVel_;
    }
  }
  if (vol.fields.empty()) return fail("none of the file's data types has a known conversion");
  int loadedCode = -1;
  if (options_.loadValues || !options_.fieldName.empty()) {
    auto idx = selectField(vol.fields, options_.fieldName);
    if (!idx) return makeError(label_ + ": " + idx.error());
    vol.loadedField = vol.fields[*idx];
    for (int code : typeCodes_)
      if (const TypeInfo* t = typeInfo(code); t && vol.loadedField.name == t->name) loadedCode = code;
    if (!options_.loadValues) vol.loadedField = {};
  }

  // Records 2...: group by the sweep number of their raw_prod_bhdr, in file order.
  std::vector<std::vector<std::size_t>> sweeps;
  int current = std::numeric_limits<int>::min();
  for (std::size_t k = 2; k * kRecord < n; ++k) {
    const unsigned char* rec = b_.data() + k * kRecord;
    if (n - k * kRecord < kBhdrBytes) return fail("record " + std::to_string(k) + ": truncated block header");
    const int sweepNo = s16(rec + 2);
    if (sweepNo <= 0) break;  // no sweep: the end of the data (padding records)
    if (sweepNo != current) {
      sweeps.emplace_back();
      current = sweepNo;
    }
    sweeps.back().push_back(k);
  }
  if (sweeps.empty()) return fail("no data records (the file ends after its headers)");
  for (const auto& records : sweeps)
    if (Status st = readSweep(records, vol, options_.loadValues ? loadedCode : -1); !st) return st.forwardError();
  if (vol.sweeps.empty()) return fail("no sweep holds a ray");
  std::stable_sort(vol.sweeps.begin(), vol.sweeps.end(),
                   [](const Sweep& a, const Sweep& c) { return a.fixedAngleDeg < c.fixedAngleDeg; });
  return vol;
}

Status Reader::readSweep(const std::vector<std::size_t>& records, RadarVolume& vol, int loadedCode) {
  const std::size_t n = b_.size();
  const std::size_t first = records.front();
  const unsigned char* rec = b_.data() + first * kRecord;
  const std::size_t recBytes = std::min(kRecord, n - first * kRecord);
  const int sweepNo = s16(rec + 2);
  const std::string where = "sweep " + std::to_string(sweepNo) + " (record " + std::to_string(first) + ")";
  const std::size_t headersEnd = kBhdrBytes + typeCodes_.size() * kIngestDataHeaderBytes;
  if (headersEnd > recBytes) return fail(where + ": truncated ingest_data_headers");
  std::vector<SweepType> types(typeCodes_.size());
  const unsigned char* idh0 = rec + kBhdrBytes;
  int raysExpected = 0;
  for (std::size_t t = 0; t < typeCodes_.size(); ++t) {
    const unsigned char* idh = rec + kBhdrBytes + t * kIngestDataHeaderBytes;
    if (s16(idh) != kIngestDataHeaderId)
      return fail(where + ": ingest_data_header " + std::to_string(t) + " has structure id " +
                  std::to_string(s16(idh)) + " (expected 24)");
    types[t].code = u16(idh + 38);
    types[t].bits = s16(idh + 36);
    if (types[t].code != typeCodes_[t])
      return fail(where + ": ingest_data_header " + std::to_string(t) + " is for data type " +
                  std::to_string(types[t].code) + ", the DSP mask says " + std::to_string(typeCodes_[t]));
    if (types[t].bits <= 0 || types[t].bits % 8 != 0 || types[t].bits > 1024)
      return fail(where + ": data type " + std::to_string(types[t].code) + " has " + std::to_string(types[t].bits) +
                  " bits per bin");
    types[t].info = typeInfo(types[t].code);
    if (types[t].info && types[t].info->bytes * 8 != types[t].bits)
      return fail(where + ": data type " + std::string(types[t].info->name) + " stored with " +
                  std::to_string(types[t].bits) + " bits per bin (expected " +
                  std::to_string(types[t].info->bytes * 8) + ")");
    const int expected = s16(idh + 30);
    if (t == 0) raysExpected = expected;
    else if (expected != raysExpected)
      return fail(where + ": data types expect different ray counts (" + std::to_string(raysExpected) + ", " +
                  std::to_string(expected) + ")");
  }
  if (raysExpected <= 0 || raysExpected > 65535)
    return fail(where + ": " + std::to_string(raysExpected) + " rays expected");

  std::vector<WordStream::Segment> segs;
  segs.push_back({rec + headersEnd, recBytes - headersEnd});
  for (std::size_t i = 1; i < records.size(); ++i) {
    const std::size_t k = records[i];
    const std::size_t bytes = std::min(kRecord, n - k * kRecord);
    segs.push_back({b_.data() + k * kRecord + kBhdrBytes, bytes - kBhdrBytes});
  }
  WordStream ws(std::move(segs));

  Sweep sw;
  sw.indexInFile = sweepNo - 1;
  sw.mode = mode_;
  const double fixed = bin2(u16(idh0 + 34));
  sw.fixedAngleDeg = mode_ == SweepMode::Rhi ? fixed : signedDeg(fixed);
  sw.firstGateRangeMeters = firstBinMeters_;
  sw.gateSpacingMeters = binStepMeters_;
  sw.gateCount = bins_;
  const bool load = loadedCode >= 0;

  std::vector<std::uint16_t> ray;
  for (int r = 0; r < raysExpected; ++r) {
    bool haveAngles = false;
    std::uint16_t header[kRayHeaderWords] = {};
    bool loadedPresent = false;
    std::vector<std::uint16_t> loadedWords;
    const TypeInfo* loadedInfo = nullptr;
    for (const SweepType& t : types) {
      const std::size_t maxWords = kRayHeaderWords + (std::size_t{bins_} * static_cast<std::size_t>(t.bits) + 15) / 16;
      ray.assign(maxWords, 0);
      std::size_t filled = 0;
      bool present = true, atStart = true;
      while (true) {
        std::uint16_t code = 0;
        if (!ws.next(&code))
          return fail(where + ", ray " + std::to_string(r) + ": the data ends inside the ray (truncated file?)");
        if (code == 1) {
          if (atStart) present = false;
          break;
        }
        atStart = false;
        if (code & 0x8000u) {
          const std::size_t count = code & 0x7FFFu;
          if (filled + count > maxWords)
            return fail(where + ", ray " + std::to_string(r) + ": run-length data of " +
                        std::to_string(filled + count) + " words, more than the " + std::to_string(maxWords) +
                        " a ray of " + std::to_string(bins_) + " bins holds");
          for (std::size_t i = 0; i < count; ++i) {
            if (!ws.next(&ray[filled + i]))
              return fail(where + ", ray " + std::to_string(r) + ": the data ends inside the ray (truncated file?)");
          }
          filled += count;
        } else {
          filled = std::min(maxWords, filled + code);  // a zero run past the ray's end adds nothing
        }
      }
      if (!present) continue;
      if (filled < kRayHeaderWords)
        return fail(where + ", ray " + std::to_string(r) + ": shorter than its 6-word ray header");
      if (!haveAngles || t.code == loadedCode) {
        std::copy_n(ray.begin(), kRayHeaderWords, header);
        haveAngles = true;
      }
      if (t.code == loadedCode) {
        loadedPresent = true;
        loadedInfo = t.info;
        loadedWords.assign(ray.begin(), ray.end());
      }
    }
    if (!haveAngles) continue;  // ray absent in every type
    const double az0 = bin2(header[0]), az1 = bin2(header[2]);
    double daz = az1 - az0;
    if (daz > 180) daz -= 360;
    if (daz < -180) daz += 360;
    double az = az0 + daz / 2;
    if (az < 0) az += 360;
    if (az >= 360) az -= 360;
    const double el = (signedDeg(bin2(header[1])) + signedDeg(bin2(header[3]))) / 2;
    sw.azimuthDeg.push_back(static_cast<float>(az));
    sw.elevationDeg.push_back(static_cast<float>(el));
    if (!load) continue;
    const std::size_t base = sw.values.size();
    sw.values.resize(base + bins_, kNoData);
    if (!loadedPresent || loadedInfo == nullptr) continue;
    const int rayBins = static_cast<std::int16_t>(loadedWords[4]);
    if (rayBins < 0 || static_cast<std::uint32_t>(rayBins) > bins_)
      return fail(where + ", ray " + std::to_string(r) + ": claims " + std::to_string(rayBins) +
                  " bins, the task has " + std::to_string(bins_));
    const std::uint16_t* data = loadedWords.data() + kRayHeaderWords;
    for (int g = 0; g < rayBins; ++g) {
      const unsigned raw = loadedInfo->bytes == 2 ? data[g] : (data[g / 2] >> (8 * (g % 2))) & 0xFFu;
      sw.values[base + static_cast<std::size_t>(g)] = decodeValue(*loadedInfo, raw, nyquist_, nyquistVel_);
    }
  }
  if (sw.rayCount() == 0) return Ok{};
  vol.sweeps.push_back(std::move(sw));
  return Ok{};
}

}  // namespace

bool looksLikeSigmetRaw(const unsigned char* bytes, std::size_t size) {
  return size >= 26 && s16(bytes) == kProductHdrId && u16(bytes + 24) == kRawProductType;
}

Result<RadarVolume> readSigmetIris(const std::string& label, const std::vector<unsigned char>& bytes,
                                   const ReadOptions& options) {
  return Reader(label, bytes, options).read();
}

Result<RadarVolume> readSigmetIris(const std::string& path, const ReadOptions& options) {
  return readUnwrapped(path, options,
                       [](const std::string& label, const std::vector<unsigned char>& bytes, const ReadOptions& o) {
                         return readSigmetIris(label, bytes, o);
                       });
}

}  // namespace atmoglobe::volume
