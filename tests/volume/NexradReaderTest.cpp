// NEXRAD Level II reader: the KLBB sample's facts, decoded values, and bad input.
//
// Reference values: decoded independently with Python 3 (bz2 module + struct, no radar library):
// each LDM record bz2.decompress'ed, messages walked (message 31: 12 + 2 * size bytes, others
// 2432), message 31 radial header / VOL / moment blocks unpacked with struct at the ICD offsets.
// The script is summarised in the comments next to the values it produced.
#include <atmoglobe/volume/NexradReader.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <string>
#include <vector>

namespace atmoglobe::volume {
namespace {

const std::string kKlbb = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");

std::vector<unsigned char> readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string writeTemp(const std::string& name, const std::vector<unsigned char>& bytes) {
  const std::filesystem::path dir = std::filesystem::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "nexrad";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path;
}

TEST(NexradReader, KlbbSiteTimeAndFields) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  Result<RadarVolume> vol = readNexradLevel2(kKlbb, ReadOptions{});
  ASSERT_TRUE(vol.ok()) << vol.error();
  EXPECT_EQ(vol->format, "NEXRAD Level II");
  EXPECT_EQ(vol->site.name, "KLBB");
  // VOL block (Python struct '>ffhH' at +8): 33.65414047241211, -101.81416320800781, site 1005 m,
  // feedhorn 24 m. The floats are exact in float32, so compare to float precision.
  EXPECT_NEAR(vol->site.latDeg, 33.65414047241211, 1e-12);
  EXPECT_NEAR(vol->site.lonDeg, -101.81416320800781, 1e-12);
  EXPECT_EQ(vol->site.antennaHeightMeters, 1005.0 + 24.0);
  EXPECT_EQ(vol->site.heightDatum, HeightDatum::MeanSeaLevel);
  // Volume header: Julian day 16954, 54026000 ms -> 2016-06-01 15:00:26 UTC.
  EXPECT_EQ(vol->timeIso8601, "2016-06-01T15:00:26Z");
  std::vector<std::string> names;
  for (const FieldInfo& f : vol->fields) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"REF", "ZDR", "PHI", "RHO", "VEL", "SW"}));
  EXPECT_EQ(vol->loadedField.name, "REF");
  EXPECT_EQ(vol->loadedField.units, "dBZ");
}

TEST(NexradReader, KlbbReflectivitySweeps) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  Result<RadarVolume> vol = readNexradLevel2(kKlbb, ReadOptions{});
  ASSERT_TRUE(vol.ok()) << vol.error();
  // VCP 21 (message 5): 11 cuts. Target angles = binary angle * 360/65536 of the codes
  // 88, 88, 264, 264, 440, 616, 784, 1096, 1800, 2656, 3552.
  const int codes[] = {88, 88, 264, 264, 440, 616, 784, 1096, 1800, 2656, 3552};
  // Rays per cut and REF gate counts per cut (first radial of each cut).
  const std::size_t rays[] = {720, 720, 720, 720, 360, 360, 360, 360, 360, 360, 360};
  const std::uint32_t gates[] = {1832, 1192, 1632, 1192, 1312, 1076, 908, 696, 448, 308, 232};
  // Mean ray elevation per cut (Python: sum / count of the message-31 elevation floats). The data
  // README lists 0.53, 0.53, 1.45, 1.45, 2.42, 3.38, 4.31, 6.02, 9.89, 14.59, 19.51: its first two
  // are these means, the rest the VCP targets; both are checked.
  const double meanElevationDeg[] = {0.530426025390625,  0.52734375,         1.4514694213867188, 1.4501953125,
                                     2.4192581176757812, 3.3828353881835938, 4.3095550537109375, 6.0139923095703125,
                                     9.885757446289062,  14.591484069824219, 19.50371551513672};
  ASSERT_EQ(vol->sweeps.size(), 11u);
  std::size_t totalRays = 0, splitRays = 0;
  for (std::size_t i = 0; i < 11; ++i) {
    const Sweep& s = vol->sweeps[i];
    SCOPED_TRACE("sweep " + std::to_string(i));
    EXPECT_EQ(s.indexInFile, static_cast<int>(i));  // file order survives the stable sort
    EXPECT_NEAR(s.fixedAngleDeg, codes[i] * 360.0 / 65536.0, 1e-12);
    EXPECT_EQ(s.mode, SweepMode::Ppi);
    EXPECT_EQ(s.rayCount(), rays[i]);
    EXPECT_EQ(s.elevationDeg.size(), rays[i]);
    EXPECT_EQ(s.gateCount, gates[i]);
    EXPECT_EQ(s.firstGateRangeMeters, 2125.0);
    EXPECT_EQ(s.gateSpacingMeters, 250.0);
    EXPECT_EQ(s.values.size(), rays[i] * gates[i]);
    const double mean =
        std::accumulate(s.elevationDeg.begin(), s.elevationDeg.end(), 0.0) / static_cast<double>(s.rayCount());
    EXPECT_NEAR(mean, meanElevationDeg[i], 1e-9);  // float sums in a different order
    totalRays += s.rayCount();
    if (i < 4) splitRays += s.rayCount();
  }
  EXPECT_EQ(totalRays, 5400u);
  EXPECT_EQ(splitRays, 4 * 720u);  // 720 radials in each of the four split cuts
}

TEST(NexradReader, KlbbDecodedValues) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  // Python: cut 1 (elevation number 1) radial 0, az 287.292480, el 0.703125, REF 8-bit, scale 2,
  // offset 66: raw 50, 53, 57 at gates 0-2 -> -8.0, -6.5, -4.5 dBZ; first raw 0 at gate 74.
  Result<RadarVolume> ref = readNexradLevel2(kKlbb, ReadOptions{});
  ASSERT_TRUE(ref.ok()) << ref.error();
  const Sweep& s0 = ref->sweeps[0];
  EXPECT_NEAR(s0.azimuthDeg[0], 287.292480, 1e-5);
  EXPECT_NEAR(s0.elevationDeg[0], 0.703125, 1e-6);
  EXPECT_EQ(s0.value(0, 0), -8.0f);
  EXPECT_EQ(s0.value(0, 1), -6.5f);
  EXPECT_EQ(s0.value(0, 2), -4.5f);
  EXPECT_TRUE(isNoEcho(s0.value(0, 74)));
  // Radial 100: az 337.263794, raw 37, 61, 46 -> -14.5, -2.5, -10.0; raw 0 at gate 4.
  EXPECT_NEAR(s0.azimuthDeg[100], 337.263794, 1e-5);
  EXPECT_EQ(s0.value(100, 0), -14.5f);
  EXPECT_EQ(s0.value(100, 1), -2.5f);
  EXPECT_EQ(s0.value(100, 2), -10.0f);
  EXPECT_TRUE(isNoEcho(s0.value(100, 4)));
  // Cut 11 radial 359: az 56.541138, raw 54, 40, 37 -> -6.0, -13.0, -14.5; raw 0 at gate 7.
  const Sweep& s10 = ref->sweeps[10];
  EXPECT_NEAR(s10.azimuthDeg[359], 56.541138, 1e-5);
  EXPECT_EQ(s10.value(359, 0), -6.0f);
  EXPECT_EQ(s10.value(359, 1), -13.0f);
  EXPECT_EQ(s10.value(359, 2), -14.5f);
  EXPECT_TRUE(isNoEcho(s10.value(359, 7)));
  // Cut 2 (Doppler half of the first split cut) carries REF over 1192 gates; gates past a ray's
  // own count do not exist here, but cut 1 rays all have 1832.

  // VEL: cut 2 radial 5, az 295.257568, scale 2, offset 129: raw 133 -> 2.0 m/s at gates 0-2;
  // raw 1 (range folded) at gate 9 -> no data; raw 0 at gate 16 -> no echo.
  ReadOptions vel;
  vel.fieldName = "VEL";
  Result<RadarVolume> v = readNexradLevel2(kKlbb, vel);
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->loadedField.units, "m/s");
  // Split cuts: the surveillance cuts 1 and 3 lack VEL and are dropped: 9 sweeps.
  ASSERT_EQ(v->sweeps.size(), 9u);
  EXPECT_EQ(v->sweeps[0].indexInFile, 1);
  EXPECT_EQ(v->sweeps[1].indexInFile, 3);
  EXPECT_EQ(v->sweeps[0].gateCount, 1192u);
  EXPECT_NEAR(v->sweeps[0].azimuthDeg[5], 295.257568, 1e-5);
  EXPECT_EQ(v->sweeps[0].value(5, 0), 2.0f);
  EXPECT_TRUE(isNoData(v->sweeps[0].value(5, 9)));
  EXPECT_TRUE(isNoEcho(v->sweeps[0].value(5, 16)));

  // PHI is 16-bit: cut 5 radial 200, az 160.526733, scale 2.8361001014709473, offset 2:
  // raw 428, 196, 542 -> 150.2062638, 68.4037915, 190.4023062 deg (Python double); raw 0 at gate 4.
  ReadOptions phi;
  phi.fieldName = "phi";  // case-insensitive
  Result<RadarVolume> p = readNexradLevel2(kKlbb, phi);
  ASSERT_TRUE(p.ok()) << p.error();
  ASSERT_EQ(p->sweeps.size(), 9u);  // the Doppler cuts 2 and 4 lack PHI
  const Sweep& p2 = p->sweeps[2];
  EXPECT_EQ(p2.indexInFile, 4);
  EXPECT_NEAR(p2.azimuthDeg[200], 160.526733, 1e-5);
  // float32 arithmetic (raw - offset) / scale: relative 1e-7 of ~190 -> 2e-5.
  EXPECT_NEAR(p2.value(200, 0), 150.2062638, 2e-5);
  EXPECT_NEAR(p2.value(200, 1), 68.4037915, 2e-5);
  EXPECT_NEAR(p2.value(200, 2), 190.4023062, 2e-5);
  EXPECT_TRUE(isNoEcho(p2.value(200, 4)));
}

TEST(NexradReader, MetadataOnlyRead) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  ReadOptions o;
  o.loadValues = false;
  Result<RadarVolume> vol = readNexradLevel2(kKlbb, o);
  ASSERT_TRUE(vol.ok()) << vol.error();
  ASSERT_EQ(vol->sweeps.size(), 11u);
  EXPECT_EQ(vol->sweeps[0].gateCount, 1832u);
  for (const Sweep& s : vol->sweeps) EXPECT_TRUE(s.values.empty());
}

// --- Bad input: each must give an error naming the file, never crash or over-allocate.
void expectError(const std::string& path, const ReadOptions& o, const std::string& fragment) {
  Result<RadarVolume> r = readNexradLevel2(path, o);
  ASSERT_FALSE(r.ok()) << path << " read without error";
  EXPECT_NE(r.error().find(path), std::string::npos) << r.error();
  EXPECT_NE(r.error().find(fragment), std::string::npos) << r.error();
}

TEST(NexradReader, BadInputFromTheRealFile) {
  SKIP_WITHOUT_TEST_DATA(kKlbb);
  const std::vector<unsigned char> good = readAll(kKlbb);
  ASSERT_EQ(good.size(), 3982637u);

  std::vector<unsigned char> truncated(good.begin(), good.begin() + 100000);
  expectError(writeTemp("truncated", truncated), {}, "claims 267119 bytes");

  std::vector<unsigned char> huge = good;  // first record's size -> 0x7FFFFFFF (2 GiB)
  huge[24] = 0x7F, huge[25] = 0xFF, huge[26] = 0xFF, huge[27] = 0xFF;
  expectError(writeTemp("huge_record", huge), {}, "claims 2147483647 bytes");

  std::vector<unsigned char> corrupt = good;  // scramble the middle of record 1's bzip2 stream
  for (std::size_t i = 7404 + 4 + 100000; i < 7404 + 4 + 100400; ++i) corrupt[i] ^= 0x5A;
  expectError(writeTemp("corrupt_bzip2", corrupt), {}, "corrupt bzip2");

  std::vector<unsigned char> cut = good;  // cut a bzip2 stream short but keep a consistent size
  // Record 1 becomes 1000 bytes long: a stream that ends early.
  cut[7404] = 0, cut[7405] = 0, cut[7406] = 0x03, cut[7407] = 0xE8;
  cut.resize(7404 + 4 + 1000);
  expectError(writeTemp("short_bzip2", cut), {}, "bzip2");

  std::vector<unsigned char> magic = good;
  std::memcpy(magic.data(), "XXXX", 4);
  expectError(writeTemp("wrong_magic", magic), {}, "not a NEXRAD Level II file");

  expectError(writeTemp("empty", {}), {}, "not a NEXRAD Level II file");
  expectError("/nonexistent/KLBB_missing", {}, "cannot open");

  ReadOptions unknown;
  unknown.fieldName = "DBZH";
  expectError(kKlbb, unknown, "field 'DBZH' is not in the file");
}

// --- Hand-built files (uncompressed record) to reach the checks inside a message.
void put16(std::vector<unsigned char>& b, std::size_t at, unsigned v) {
  b[at] = static_cast<unsigned char>(v >> 8);
  b[at + 1] = static_cast<unsigned char>(v);
}
void put32(std::vector<unsigned char>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<unsigned char>(v >> (24 - 8 * i));
}
void putFloat(std::vector<unsigned char>& b, std::size_t at, float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  put32(b, at, u);
}

struct RadialSpec {
  float azimuthDeg = 10.0f, elevationDeg = 0.5f;
  std::string raw = std::string("\x00\x01\x02\x42\x82", 5);  // raw 0, 1, 2, 66, 130
  std::uint32_t refPointer = 0;                              // 0: the real position
  unsigned gateCountField = 0;                               // 0: raw.size()
};

std::vector<unsigned char> buildFile(const RadialSpec& spec) {
  constexpr std::size_t kVol = 32 + 2 * 4, kRef = kVol + 44;
  std::vector<unsigned char> body(kRef + 28 + spec.raw.size(), 0);
  std::memcpy(body.data(), "TEST", 4);
  putFloat(body, 12, spec.azimuthDeg);
  body[22] = 1;  // elevation number
  putFloat(body, 24, spec.elevationDeg);
  put16(body, 30, 2);
  put32(body, 32, kVol);
  put32(body, 36, spec.refPointer ? spec.refPointer : static_cast<std::uint32_t>(kRef));
  body[kVol] = 'R';
  std::memcpy(&body[kVol + 1], "VOL", 3);
  putFloat(body, kVol + 8, 40.0f);
  putFloat(body, kVol + 12, -100.0f);
  put16(body, kVol + 16, 500);
  put16(body, kVol + 18, 20);
  body[kRef] = 'D';
  std::memcpy(&body[kRef + 1], "REF", 3);
  put16(body, kRef + 8, spec.gateCountField ? spec.gateCountField : static_cast<unsigned>(spec.raw.size()));
  put16(body, kRef + 10, 2125);
  put16(body, kRef + 12, 250);
  body[kRef + 19] = 8;
  putFloat(body, kRef + 20, 2.0f);
  putFloat(body, kRef + 24, 66.0f);
  std::memcpy(&body[kRef + 28], spec.raw.data(), spec.raw.size());
  if (body.size() % 2) body.push_back(0);

  std::vector<unsigned char> message(12 + 16, 0);
  put16(message, 12, static_cast<unsigned>((16 + body.size()) / 2));
  message[15] = 31;
  message.insert(message.end(), body.begin(), body.end());

  std::vector<unsigned char> file(24, 0);
  std::memcpy(file.data(), "AR2V0006.001", 12);
  std::memcpy(&file[20], "TEST", 4);
  std::vector<unsigned char> size(4);
  put32(size, 0, static_cast<std::uint32_t>(-static_cast<std::int32_t>(message.size())));  // last record
  file.insert(file.end(), size.begin(), size.end());
  file.insert(file.end(), message.begin(), message.end());
  return file;
}

TEST(NexradReader, HandBuiltRadialDecodesBySpec) {
  Result<RadarVolume> vol = readNexradLevel2(writeTemp("handmade_ok", buildFile({})), ReadOptions{});
  ASSERT_TRUE(vol.ok()) << vol.error();
  ASSERT_EQ(vol->sweeps.size(), 1u);
  const Sweep& s = vol->sweeps[0];
  ASSERT_EQ(s.gateCount, 5u);
  // value = (raw - 66) / 2; raw 0 below threshold, raw 1 range folded.
  EXPECT_TRUE(isNoEcho(s.value(0, 0)));
  EXPECT_TRUE(isNoData(s.value(0, 1)));
  EXPECT_EQ(s.value(0, 2), -32.0f);
  EXPECT_EQ(s.value(0, 3), 0.0f);
  EXPECT_EQ(s.value(0, 4), 32.0f);
  EXPECT_EQ(vol->site.antennaHeightMeters, 520.0);
  // No VCP message: the fixed angle is the mean elevation.
  EXPECT_EQ(s.fixedAngleDeg, 0.5);
}

TEST(NexradReader, HandBuiltBadRadials) {
  RadialSpec nanAz;
  nanAz.azimuthDeg = std::nanf("");
  expectError(writeTemp("nan_azimuth", buildFile(nanAz)), {}, "azimuth");

  RadialSpec nanEl;
  nanEl.elevationDeg = std::nanf("");
  expectError(writeTemp("nan_elevation", buildFile(nanEl)), {}, "elevation");

  RadialSpec badPointer;
  badPointer.refPointer = 60000;
  expectError(writeTemp("bad_pointer", buildFile(badPointer)), {}, "outside the message");

  RadialSpec tooManyGates;
  tooManyGates.gateCountField = 65535;  // claims far more gate bytes than the message has
  expectError(writeTemp("too_many_gates", buildFile(tooManyGates)), {}, "claims 65535 gates");
}

}  // namespace
}  // namespace atmoglobe::volume
