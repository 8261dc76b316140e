// NEXRAD Level II in its other forms: legacy message-1 archives (built here from the published
// layout, ICD for the RDA/RPG 2620002 before build 10: no real legacy file is at hand) and
// real-time chunk sets (the real KLBB archive split the way the feed splits a volume).
//
// Legacy layout written below (facts from the ICD, our own code): 24-byte volume header
// ("ARCHIVE2." or "AR2V0001." + 3-byte extension, Julian date, ms of day, ICAO), then
// uncompressed 2432-byte frames: 12-byte CTM, 16-byte message header (halfword size, channel,
// type 1, ...), 100-byte radial header (byte offsets: 0 ms, 4 date, 8 azimuth binary angle,
// 10 azimuth number, 12 radial status, 14 elevation binary angle, 16 elevation number, 18/20
// first surveillance/Doppler gate range m, 22/24 their gate intervals, 26/28 their gate counts,
// 36/38/40 REF/VEL/SW pointers from the body start, 42 velocity resolution, 44 VCP, 60 Nyquist
// 0.01 m/s), then the 8-bit gates. Scalings: REF (raw - 66) / 2 dBZ; VEL (raw - 129) / 2 m/s at
// 0.5 m/s resolution (code 2), raw - 129 at 1 m/s (code 4); SW (raw - 129) / 2.
#include <atmoglobe/volume/NexradReader.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace atmoglobe::volume {
namespace {

namespace fs = std::filesystem;

const std::string kKlbb = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
const std::string kOuRadar = atmoglobe_test::testDataPath("stations/OURadar_nexrad-locations.json");

using Bytes = std::vector<unsigned char>;

Bytes readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path outDir(const std::string& name) {
  const fs::path dir = fs::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "nexrad_forms" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string writeFile(const fs::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

void put16(Bytes& b, std::size_t at, unsigned v) {
  b[at] = static_cast<unsigned char>(v >> 8);
  b[at + 1] = static_cast<unsigned char>(v);
}
void put32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<unsigned char>(v >> (24 - 8 * i));
}
unsigned binaryAngle(double deg) { return static_cast<unsigned>(std::lround(deg * 65536.0 / 360.0)) & 0xFFFFu; }

// ------------------------------------------------------------------ legacy message 1

struct LegacyRadial {
  double azimuthDeg = 0, elevationDeg = 0.5;
  unsigned azimuthNumber = 1, status = 1, elevationNumber = 1;
  int surFirst = 500, surStep = 1000, dopFirst = 250, dopStep = 250;
  Bytes ref, vel, sw;
  unsigned velResolution = 2;
};

constexpr std::uint32_t kDay = 13390;    // 2006-08-29 (day 1 = 1970-01-01; Python datetime)
constexpr std::uint32_t kMs = 36000000;  // 10:00:00 UTC
constexpr int kNyquistCounts = 2650;     // 26.50 m/s

Bytes legacyFrame(const LegacyRadial& r, std::uint32_t ms) {
  Bytes f(2432, 0);
  const std::size_t h = 12, b = 28;
  put16(f, h, (2432 - 12) / 2);  // message size in halfwords (header included, CTM not)
  f[h + 3] = 1;                  // message type 1
  put16(f, b + 0, ms >> 16), put16(f, b + 2, ms & 0xFFFF);
  put16(f, b + 4, kDay);
  put16(f, b + 8, binaryAngle(r.azimuthDeg));
  put16(f, b + 10, r.azimuthNumber);
  put16(f, b + 12, r.status);
  put16(f, b + 14, binaryAngle(r.elevationDeg));
  put16(f, b + 16, r.elevationNumber);
  put16(f, b + 18, static_cast<unsigned>(r.surFirst) & 0xFFFFu);
  put16(f, b + 20, static_cast<unsigned>(r.dopFirst) & 0xFFFFu);
  put16(f, b + 22, static_cast<unsigned>(r.surStep));
  put16(f, b + 24, static_cast<unsigned>(r.dopStep));
  put16(f, b + 26, static_cast<unsigned>(r.ref.size()));
  put16(f, b + 28, static_cast<unsigned>(std::max(r.vel.size(), r.sw.size())));
  std::size_t at = 100;
  auto place = [&](const Bytes& gates, std::size_t pointerAt) {
    if (gates.empty()) return;
    put16(f, b + pointerAt, static_cast<unsigned>(at));
    std::copy(gates.begin(), gates.end(), f.begin() + static_cast<std::ptrdiff_t>(b + at));
    at += gates.size();
  };
  place(r.ref, 36);
  place(r.vel, 38);
  place(r.sw, 40);
  put16(f, b + 42, r.velResolution);
  put16(f, b + 44, 21);
  put16(f, b + 60, kNyquistCounts);
  return f;
}

const Bytes kRefRaw = {0, 1, 2, 66, 130, 255};   // no echo, no data, -32, 0, 32, 94.5 dBZ
const Bytes kVelRaw = {0, 1, 2, 129, 131, 255};  // no echo, no data, -63.5, 0, 1, 63 m/s (0.5 m/s)

// Two cuts: cut 1 at 0.5 deg, surveillance only (REF, 1 km gates from 500 m), four radials 90
// deg apart, the first starting the volume; cut 2 at 1.45 deg, Doppler (REF 1 km gates and
// VEL/SW 250 m gates from 250 m), four radials, the last ending the volume.
std::vector<LegacyRadial> legacyRadials(unsigned velResolution = 2) {
  std::vector<LegacyRadial> out;
  for (unsigned cut = 1; cut <= 2; ++cut) {
    for (unsigned i = 0; i < 4; ++i) {
      LegacyRadial r;
      r.azimuthDeg = 90.0 * i + 0.5;
      r.azimuthNumber = i + 1;
      r.elevationNumber = cut;
      r.elevationDeg = cut == 1 ? 0.5 : 1.45;
      r.status = i == 0 ? (cut == 1 ? 3u : 0u) : i == 3 ? (cut == 2 ? 4u : 2u) : 1u;
      r.ref = kRefRaw;
      if (cut == 2) {
        r.vel = kVelRaw;
        r.sw = kVelRaw;
        r.velResolution = velResolution;
      }
      out.push_back(r);
    }
  }
  return out;
}

Bytes legacyFile(const char* magic, const std::vector<LegacyRadial>& radials, std::size_t dropLast = 0) {
  Bytes file(24, 0);
  std::memcpy(file.data(), magic, 9);
  std::memcpy(&file[9], "001", 3);
  put32(file, 12, kDay);
  put32(file, 16, kMs);
  std::memcpy(&file[20], "KTLX", 4);
  for (std::size_t i = 0; i + dropLast < radials.size(); ++i) {
    const Bytes f = legacyFrame(radials[i], kMs + static_cast<std::uint32_t>(i) * 1000);
    file.insert(file.end(), f.begin(), f.end());
  }
  return file;
}

// A site list of our own (positions made up for the test: not a real site's), CSV.
std::string siteList() {
  const fs::path dir = outDir("sites");
  std::ofstream(dir / "sites.csv") << "icao,lat,lon,elevation,tower\nKABC,10,20,30,5\nKTLX,35.25,-97.5,370,20\n";
  return (dir / "sites.csv").string();
}

ReadOptions withSites(const std::string& field = "") {
  ReadOptions o;
  o.fieldName = field;
  o.nexradSiteList = siteList();
  return o;
}

TEST(NexradLegacy, ReadsMessageOneWithTheSiteFromTheList) {
  const fs::path dir = outDir("legacy");
  const std::string path = writeFile(dir / "KTLX20060829_100000", legacyFile("ARCHIVE2.", legacyRadials()));
  // Detected from content (the ARCHIVE2 header), read through the dispatcher.
  auto fmt = detectRadarFormat(path);
  ASSERT_TRUE(fmt.ok()) << fmt.error();
  EXPECT_EQ(*fmt, RadarFormat::NexradLevel2);
  Result<RadarVolume> v = readRadarVolume(path, withSites());
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->site.name, "KTLX");
  EXPECT_EQ(v->site.latDeg, 35.25);
  EXPECT_EQ(v->site.lonDeg, -97.5);
  EXPECT_EQ(v->site.antennaHeightMeters, 390.0);  // ground 370 + tower 20
  EXPECT_NE(v->siteLocationSource.find("NEXRAD site list"), std::string::npos) << v->siteLocationSource;
  EXPECT_NE(v->siteLocationSource.find("sites.csv"), std::string::npos) << v->siteLocationSource;
  EXPECT_EQ(v->timeIso8601, "2006-08-29T10:00:00Z");
  EXPECT_DOUBLE_EQ(v->nyquistVelocityMps, 26.5);
  std::vector<std::string> names;
  for (const FieldInfo& f : v->fields) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"REF", "VEL", "SW"}));
  EXPECT_EQ(v->loadedField.name, "REF");
  EXPECT_TRUE(v->warnings.empty()) << v->warnings.front();  // complete: both cuts end, the volume ends

  ASSERT_EQ(v->sweeps.size(), 2u);
  for (const Sweep& s : v->sweeps) {
    EXPECT_TRUE(s.complete);
    ASSERT_EQ(s.rayCount(), 4u);
    EXPECT_EQ(s.gateCount, 6u);
    EXPECT_EQ(s.firstGateRangeMeters, 500.0);  // surveillance geometry
    EXPECT_EQ(s.gateSpacingMeters, 1000.0);
    // Binary angles: 0.5 deg = 91 counts = 0.4998779 deg; 1 count = 0.0055 deg.
    EXPECT_NEAR(s.azimuthDeg[1], 90.5, 360.0 / 65536.0);
    EXPECT_TRUE(isNoEcho(s.value(2, 0)));
    EXPECT_TRUE(isNoData(s.value(2, 1)));
    EXPECT_EQ(s.value(2, 2), -32.0f);
    EXPECT_EQ(s.value(2, 3), 0.0f);
    EXPECT_EQ(s.value(2, 4), 32.0f);
    EXPECT_EQ(s.value(2, 5), 94.5f);
  }
  EXPECT_NEAR(v->sweeps[0].elevationDeg[0], 0.5, 360.0 / 65536.0);
  EXPECT_NEAR(v->sweeps[1].elevationDeg[0], 1.45, 360.0 / 65536.0);
  EXPECT_EQ(v->sweeps[0].startTimeIso8601, "2006-08-29T10:00:00Z");
  EXPECT_EQ(v->sweeps[1].endTimeIso8601, "2006-08-29T10:00:07Z");
}

TEST(NexradLegacy, DopplerMomentsHaveTheirOwnGatesAndScaling) {
  const fs::path dir = outDir("legacy_vel");
  const std::string path = writeFile(dir / "KTLX_vel", legacyFile("AR2V0001.", legacyRadials()));
  Result<RadarVolume> v = readNexradLevel2(path, withSites("VEL"));
  ASSERT_TRUE(v.ok()) << v.error();
  ASSERT_EQ(v->sweeps.size(), 1u);  // cut 1 holds no VEL
  const Sweep& s = v->sweeps[0];
  EXPECT_EQ(s.firstGateRangeMeters, 250.0);  // Doppler geometry, not the surveillance one
  EXPECT_EQ(s.gateSpacingMeters, 250.0);
  EXPECT_EQ(s.gateCount, 6u);
  EXPECT_TRUE(isNoEcho(s.value(0, 0)));
  EXPECT_TRUE(isNoData(s.value(0, 1)));
  EXPECT_EQ(s.value(0, 2), -63.5f);
  EXPECT_EQ(s.value(0, 3), 0.0f);
  EXPECT_EQ(s.value(0, 4), 1.0f);
  EXPECT_EQ(s.value(0, 5), 63.0f);
  ASSERT_EQ(v->warnings.size(), 1u);
  EXPECT_NE(v->warnings[0].find("cuts 1 (0.50 deg) hold no VEL"), std::string::npos) << v->warnings[0];

  // Velocity resolution code 4 (1 m/s): raw 131 -> 2 m/s.
  const std::string fine = writeFile(dir / "KTLX_vel_1mps", legacyFile("AR2V0001.", legacyRadials(4)));
  Result<RadarVolume> w = readNexradLevel2(fine, withSites("VEL"));
  ASSERT_TRUE(w.ok()) << w.error();
  EXPECT_EQ(w->sweeps[0].value(0, 4), 2.0f);
  EXPECT_EQ(w->sweeps[0].value(0, 2), -127.0f);

  ReadOptions sw = withSites("SW");
  Result<RadarVolume> x = readNexradLevel2(path, sw);
  ASSERT_TRUE(x.ok()) << x.error();
  EXPECT_EQ(x->sweeps[0].value(1, 4), 1.0f);
}

TEST(NexradLegacy, IncompleteVolumeIsReadAndSaysWhichCutsAreComplete) {
  const fs::path dir = outDir("legacy_partial");
  // The last radial of cut 2 (azimuth 270.5, end of volume) is missing.
  const std::string path = writeFile(dir / "KTLX_partial", legacyFile("ARCHIVE2.", legacyRadials(), 1));
  Result<RadarVolume> v = readNexradLevel2(path, withSites());
  ASSERT_TRUE(v.ok()) << v.error();
  ASSERT_EQ(v->sweeps.size(), 2u);
  EXPECT_TRUE(v->sweeps[0].complete);
  const Sweep& s = v->sweeps[1];
  EXPECT_FALSE(s.complete);
  // Three measured rays at 0.5, 90.5, 180.5; the gaps filled with no-data rays 1 deg apart
  // (message 1's azimuth spacing): 89 + 89 + 179 = 357 of them.
  ASSERT_EQ(s.rayCount(), 360u);
  std::size_t measured = 0;
  for (std::size_t r = 0; r < s.rayCount(); ++r) {
    bool any = false;
    for (std::uint32_t g = 0; g < s.gateCount; ++g) any = any || !isNoData(s.value(r, g));
    measured += any;
  }
  EXPECT_EQ(measured, 3u);
  ASSERT_EQ(v->warnings.size(), 1u);
  const std::string& w = v->warnings[0];
  EXPECT_NE(w.find("complete cuts 1 (0.50 deg)"), std::string::npos) << w;
  EXPECT_NE(w.find("partial: cut 2"), std::string::npos) << w;
  EXPECT_NE(w.find("no end-of-volume radial"), std::string::npos) << w;
}

TEST(NexradLegacy, WithoutASiteListTheBuiltInTableGivesThePosition) {
  const fs::path dir = outDir("legacy_nolist");
  const std::string path = writeFile(dir / "KTLX_nolist", legacyFile("ARCHIVE2.", legacyRadials()));
  unsetenv("ATMOGLOBE_NEXRAD_SITES");
  Result<RadarVolume> v = readNexradLevel2(path, ReadOptions{});
  ASSERT_TRUE(v.ok()) << v.error();
  // KTLX in assets/nexrad_sites.csv: 35.333056 N, 97.277778 W, ground 369.7 m, tower 15 m (NOAA).
  EXPECT_NEAR(v->site.latDeg, 35.333056, 1e-6);
  EXPECT_NEAR(v->site.lonDeg, -97.277778, 1e-6);
  EXPECT_NEAR(v->site.antennaHeightMeters, 369.7 + 15.0, 1e-9);
  EXPECT_NE(v->siteLocationSource.find("built-in NEXRAD site table"), std::string::npos) << v->siteLocationSource;
  // A user's list wins over the table (here it puts KTLX elsewhere).
  setenv("ATMOGLOBE_NEXRAD_SITES", siteList().c_str(), 1);
  Result<RadarVolume> w = readNexradLevel2(path, ReadOptions{});
  unsetenv("ATMOGLOBE_NEXRAD_SITES");
  ASSERT_TRUE(w.ok()) << w.error();
  EXPECT_EQ(w->site.latDeg, 35.25);

  // An ICAO id neither has: the error says how to give a list.
  Bytes other = legacyFile("ARCHIVE2.", legacyRadials());
  std::memcpy(&other[20], "KXYZ", 4);
  const std::string unknown = writeFile(dir / "KXYZ", other);
  Result<RadarVolume> u = readNexradLevel2(unknown, withSites());
  ASSERT_FALSE(u.ok());
  EXPECT_NE(u.error().find("'KXYZ' is not in NEXRAD site list"), std::string::npos) << u.error();
  Result<RadarVolume> x = readNexradLevel2(unknown, ReadOptions{});
  ASSERT_FALSE(x.ok());
  EXPECT_NE(x.error().find(unknown), std::string::npos) << x.error();
  EXPECT_NE(x.error().find("'KXYZ' is not in the built-in NEXRAD site table"), std::string::npos) << x.error();
  EXPECT_NE(x.error().find("ATMOGLOBE_NEXRAD_SITES"), std::string::npos) << x.error();
}

TEST(NexradLegacy, TruncatedFrameIsAnError) {
  const fs::path dir = outDir("legacy_truncated");
  Bytes file = legacyFile("ARCHIVE2.", legacyRadials());
  file.resize(24 + 2432 * 3 + 28 + 60);  // the fourth frame stops inside its radial header
  Result<RadarVolume> v = readNexradLevel2(writeFile(dir / "cut", file), withSites());
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.error().find("shorter than its 100-byte radial header"), std::string::npos) << v.error();
  file.resize(24 + 2432 * 3 + 28 + 103);  // header complete, REF gates cut off
  Result<RadarVolume> w = readNexradLevel2(writeFile(dir / "cut2", file), withSites());
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error().find("does not fit"), std::string::npos) << w.error();
}

TEST(NexradLegacy, KlbbPositionFromTheRealSiteList) {
  SKIP_WITHOUT_TEST_DATA(kOuRadar);
  const fs::path dir = outDir("legacy_klbb");
  Bytes file = legacyFile("ARCHIVE2.", legacyRadials());
  std::memcpy(&file[20], "KLBB", 4);
  ReadOptions o;
  o.nexradSiteList = kOuRadar;
  Result<RadarVolume> v = readNexradLevel2(writeFile(dir / "KLBB_legacy", file), o);
  ASSERT_TRUE(v.ok()) << v.error();
  // The OURadar list: KLBB 33.654167, -101.814167 (StationListTest reads the same entry); the
  // message-31 KLBB file's own VOL block says 33.654140, -101.814163: within 3e-5 deg (3 m).
  EXPECT_NEAR(v->site.latDeg, 33.65414, 1e-4);
  EXPECT_NEAR(v->site.lonDeg, -101.81416, 1e-4);
}

// ------------------------------------------------------------------ real-time chunks

struct Record {
  std::size_t offset, size;  ///< control word included
};

std::vector<Record> ldmRecords(const Bytes& file) {
  std::vector<Record> out;
  std::size_t pos = 24;
  while (pos + 4 <= file.size()) {
    const auto n = static_cast<std::int32_t>((std::uint32_t{file[pos]} << 24) | (std::uint32_t{file[pos + 1]} << 16) |
                                             (std::uint32_t{file[pos + 2]} << 8) | file[pos + 3]);
    const std::size_t len = static_cast<std::size_t>(n < 0 ? -n : n);
    out.push_back({pos, 4 + len});
    pos += 4 + len;
  }
  return out;
}

Bytes slice(const Bytes& file, const Record& r) {
  return Bytes(file.begin() + static_cast<std::ptrdiff_t>(r.offset),
               file.begin() + static_cast<std::ptrdiff_t>(r.offset + r.size));
}

/// The KLBB archive split as the real-time feed splits a volume: the start chunk is the volume
/// header, the metadata record and the first radial record; each later record is a chunk; the
/// last one is the end chunk. Written under names NNN-S / NNN-I / NNN-E. Returns paths in order.
std::vector<std::string> writeChunks(const fs::path& dir, const Bytes& file, std::size_t upTo = 0) {
  const std::vector<Record> recs = ldmRecords(file);
  std::vector<std::string> paths;
  Bytes start(file.begin(), file.begin() + 24);
  for (std::size_t i = 0; i < 2; ++i) {
    const Bytes r = slice(file, recs[i]);
    start.insert(start.end(), r.begin(), r.end());
  }
  paths.push_back(writeFile(dir / "KLBB_20160601-150025-001-S", start));
  const std::size_t last = upTo ? upTo : recs.size() - 1;
  for (std::size_t i = 2; i <= last; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "KLBB_20160601-150025-%03zu-%c", i, i + 1 == recs.size() ? 'E' : 'I');
    paths.push_back(writeFile(dir / name, slice(file, recs[i])));
  }
  return paths;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void expectSameVolume(const RadarVolume& a, const RadarVolume& b) {
  EXPECT_EQ(a.site.name, b.site.name);
  EXPECT_EQ(a.site.latDeg, b.site.latDeg);
  EXPECT_EQ(a.site.lonDeg, b.site.lonDeg);
  EXPECT_EQ(a.site.antennaHeightMeters, b.site.antennaHeightMeters);
  EXPECT_EQ(a.timeIso8601, b.timeIso8601);
  EXPECT_EQ(a.loadedField.name, b.loadedField.name);
  EXPECT_EQ(a.fields.size(), b.fields.size());
  EXPECT_EQ(a.nyquistVelocityMps, b.nyquistVelocityMps);
  ASSERT_EQ(a.sweeps.size(), b.sweeps.size());
  for (std::size_t k = 0; k < a.sweeps.size(); ++k) {
    SCOPED_TRACE("sweep " + std::to_string(k));
    const Sweep &x = a.sweeps[k], &y = b.sweeps[k];
    EXPECT_EQ(x.indexInFile, y.indexInFile);
    EXPECT_EQ(x.fixedAngleDeg, y.fixedAngleDeg);
    EXPECT_EQ(x.azimuthDeg, y.azimuthDeg);
    EXPECT_EQ(x.elevationDeg, y.elevationDeg);
    EXPECT_EQ(x.gateCount, y.gateCount);
    EXPECT_EQ(x.firstGateRangeMeters, y.firstGateRangeMeters);
    EXPECT_TRUE(sameBits(x.values, y.values));
    EXPECT_EQ(x.complete, y.complete);
  }
}

TEST(NexradChunks, KlbbChunksAssembleToTheArchive) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  const Bytes file = readAll(kKlbb);
  const fs::path dir = outDir("chunks_full");
  std::vector<std::string> paths = writeChunks(dir, file);
  ASSERT_EQ(paths.size(), 45u);  // 46 records: start (header + 2 records), 43 intermediate, end
  // Given in reverse name order: the reader orders the chunks by their first radial's time.
  std::reverse(paths.begin(), paths.end());
  for (const char* field : {"REF", "VEL"}) {
    SCOPED_TRACE(field);
    ReadOptions o;
    o.fieldName = field;
    Result<RadarVolume> archive = readNexradLevel2(kKlbb, o);
    ASSERT_TRUE(archive.ok()) << archive.error();
    Result<RadarVolume> chunks = readNexradChunks(paths, dir.string(), o);
    ASSERT_TRUE(chunks.ok()) << chunks.error();
    expectSameVolume(*chunks, *archive);
    EXPECT_EQ(chunks->sourcePath, dir.string());
    ASSERT_EQ(chunks->sourceFiles.size(), 45u);
    EXPECT_NE(chunks->sourceFiles.front().find("001-S"), std::string::npos);
    EXPECT_NE(chunks->sourceFiles.back().find("045-E"), std::string::npos);
    // Only the assembly note beyond the archive's own warnings (VEL: split cuts left out).
    ASSERT_EQ(chunks->warnings.size(), archive->warnings.size() + 1);
    EXPECT_NE(chunks->warnings[0].find("assembled from 45 real-time chunks"), std::string::npos);
  }
  // The directory through the set reader and loadRadar: the same volume.
  RadarSetOptions set;
  set.label = dir.string();
  auto files = expandRadarPaths(dir.string());
  ASSERT_TRUE(files.ok()) << files.error();
  Result<RadarVolume> viaSet = readRadarVolumeSet(*files, set);
  ASSERT_TRUE(viaSet.ok()) << viaSet.error();
  Result<RadarVolume> archive = readNexradLevel2(kKlbb, ReadOptions{});
  ASSERT_TRUE(archive.ok());
  expectSameVolume(*viaSet, *archive);
  RadarLoadOptions lo;
  lo.buildRenderLayout = true;
  Result<LoadedRadar> loaded = loadRadar(dir.string(), lo);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(loaded->layout->sweeps.size(), 9u);  // as the archive: split cuts merged by the layout
}

TEST(NexradChunks, KlbbVolumeInProgress) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  const Bytes file = readAll(kKlbb);
  Result<RadarVolume> archive = readNexradLevel2(kKlbb, ReadOptions{});
  ASSERT_TRUE(archive.ok()) << archive.error();
  const fs::path dir = outDir("chunks_partial");
  const std::vector<std::string> paths = writeChunks(dir, file, 20);  // records 0..20 of 46
  Result<RadarVolume> v = readNexradChunks(paths, dir.string(), ReadOptions{});
  ASSERT_TRUE(v.ok()) << v.error();
  ASSERT_GT(v->sweeps.size(), 0u);
  ASSERT_LT(v->sweeps.size(), archive->sweeps.size());
  // The cuts before the last one read are complete and equal to the archive's; the last is
  // partial: its measured rays are the archive's first rays, the others no data.
  std::size_t partial = 0;
  for (std::size_t k = 0; k < v->sweeps.size(); ++k) {
    const Sweep& s = v->sweeps[k];
    const Sweep& a = archive->sweeps[k];
    ASSERT_EQ(s.indexInFile, a.indexInFile);
    if (s.complete) {
      EXPECT_TRUE(sameBits(s.values, a.values)) << k;
      continue;
    }
    ++partial;
    EXPECT_EQ(s.rayCount(), a.rayCount());  // 0.5 deg super-resolution cut: padded to 720 rays
    std::size_t measured = 0;
    for (std::size_t r = 0; r < s.rayCount(); ++r) {
      bool any = false;
      for (std::uint32_t g = 0; g < s.gateCount; ++g) any = any || !isNoData(s.value(r, g));
      if (!any) continue;
      ++measured;
      // A measured ray is the archive's ray of the same index (the chunks are its first radials).
      ASSERT_LT(r, a.rayCount());
      EXPECT_EQ(s.azimuthDeg[r], a.azimuthDeg[r]);
      EXPECT_EQ(0, std::memcmp(&s.values[r * s.gateCount], &a.values[r * a.gateCount], s.gateCount * sizeof(float)));
    }
    EXPECT_GT(measured, 0u);
    EXPECT_LT(measured, a.rayCount());
  }
  EXPECT_EQ(partial, 1u);
  const std::string all = [&] {
    std::string s;
    for (const std::string& w : v->warnings) s += w + "\n";
    return s;
  }();
  EXPECT_NE(all.find("incomplete volume"), std::string::npos) << all;
  EXPECT_NE(all.find("complete cuts 1 (0.48 deg)"), std::string::npos) << all;
  EXPECT_NE(all.find("not in the data yet: cuts"), std::string::npos) << all;
  EXPECT_NE(all.find("of VCP 21"), std::string::npos) << all;
  EXPECT_NE(all.find("no end-of-volume radial"), std::string::npos) << all;
}

TEST(NexradChunks, KlbbMissingAndRepeatedChunks) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  const Bytes file = readAll(kKlbb);
  Result<RadarVolume> archive = readNexradLevel2(kKlbb, ReadOptions{});
  ASSERT_TRUE(archive.ok()) << archive.error();
  const fs::path dir = outDir("chunks_gap");
  std::vector<std::string> paths = writeChunks(dir, file);
  // A chunk given twice: its radials are dropped the second time, the volume is the archive's.
  std::vector<std::string> twice = paths;
  fs::copy_file(paths[10], dir / "copy_of_chunk_11");
  twice.push_back((dir / "copy_of_chunk_11").string());
  Result<RadarVolume> d = readNexradChunks(twice, dir.string(), ReadOptions{});
  ASSERT_TRUE(d.ok()) << d.error();
  expectSameVolume(*d, *archive);
  ASSERT_EQ(d->warnings.size(), 2u);
  EXPECT_NE(d->warnings[1].find("120 duplicate radials"), std::string::npos) << d->warnings[1];

  // An intermediate chunk lost: the volume ends, but one cut has a hole of no-data rays.
  paths.erase(paths.begin() + 10);
  Result<RadarVolume> g = readNexradChunks(paths, dir.string(), ReadOptions{});
  ASSERT_TRUE(g.ok()) << g.error();
  ASSERT_EQ(g->sweeps.size(), archive->sweeps.size());
  std::size_t partial = 0;
  for (const Sweep& s : g->sweeps) partial += !s.complete;
  EXPECT_EQ(partial, 1u);
  const std::string& w = g->warnings.back();
  EXPECT_NE(w.find("incomplete volume"), std::string::npos) << w;
  EXPECT_NE(w.find(" rays of 720"), std::string::npos) << w;
  EXPECT_EQ(w.find("no end-of-volume radial"), std::string::npos) << w;
}

TEST(NexradChunks, KlbbBadChunkSets) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  const Bytes file = readAll(kKlbb);
  const fs::path dir = outDir("chunks_bad");
  std::vector<std::string> paths = writeChunks(dir, file, 5);
  // No start chunk.
  std::vector<std::string> noStart(paths.begin() + 1, paths.end());
  Result<RadarVolume> a = readNexradChunks(noStart, "SET", ReadOptions{});
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("SET: no start chunk"), std::string::npos) << a.error();
  // Two start chunks (two volumes' chunks mixed).
  fs::copy_file(paths[0], dir / "other-001-S");
  std::vector<std::string> two = paths;
  two.push_back((dir / "other-001-S").string());
  Result<RadarVolume> b = readNexradChunks(two, "SET", ReadOptions{});
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().find("2 start chunks"), std::string::npos) << b.error();
  EXPECT_NE(b.error().find("other-001-S"), std::string::npos) << b.error();
  // A file that is neither.
  std::vector<std::string> junk = paths;
  junk.push_back(writeFile(dir / "junk", Bytes{'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'}));
  Result<RadarVolume> c = readNexradChunks(junk, "SET", ReadOptions{});
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().find("junk: not a NEXRAD Level II chunk"), std::string::npos) << c.error();
}

}  // namespace
}  // namespace atmoglobe::volume
