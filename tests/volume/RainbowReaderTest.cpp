// Rainbow 5 reader on ../shared/data/radar_rainbow: facts from the file's XML
// (checked by reading the text here, not through the reader: slice count, posangles, rangestep,
// bins, sensorinfo) and decoded values against an independent decoding: the BLOBs are found by
// their text header here, inflated with zlib's uncompress after the 4-byte big-endian qCompress
// size, and converted with min + (raw - 1) (max - min) / (2^depth - 2) (raw 0: no echo). The
// conversion is checked on the file's value range: raw 1 must give min and 255 max, which with
// min -31.5 and max 95.5 is the 0.5 dB step of 8-bit Rainbow reflectivity.
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RainbowReader.h>

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

namespace atmoglobe::volume {
namespace {

const std::string kVol = atmoglobe_test::testDataPath("radar_rainbow/2013051000000600dBZ.vol");

std::vector<unsigned char> readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The inflated data of BLOB `id`, found by its text header.
std::vector<unsigned char> handBlob(const std::vector<unsigned char>& f, int id) {
  const std::string s(f.begin(), f.end());
  const std::string head = "<BLOB blobid=\"" + std::to_string(id) + "\"";
  const std::size_t at = s.find(head);
  EXPECT_NE(at, std::string::npos);
  const std::size_t sizeAt = s.find("size=\"", at) + 6;
  const std::size_t size = std::stoul(s.substr(sizeAt, s.find('"', sizeAt) - sizeAt));
  const std::size_t data = s.find('>', at) + 2;  // '>' then '\n'
  const unsigned char* p = f.data() + data;
  uLongf n = (uLongf{p[0]} << 24) | (uLongf{p[1]} << 16) | (uLongf{p[2]} << 8) | p[3];
  std::vector<unsigned char> out(n);
  EXPECT_EQ(uncompress(out.data(), &n, p + 4, static_cast<uLong>(size - 4)), Z_OK);
  return out;
}

TEST(RainbowReader, FactsFromTheXml) {
  SKIP_WITHOUT_TEST_DATA(kVol);
  EXPECT_EQ(*detectRadarFormat(kVol), RadarFormat::Rainbow5);
  const std::vector<unsigned char> f = readAll(kVol);
  const std::string xml(f.begin(),
                        f.begin() + static_cast<long>(std::string(f.begin(), f.end()).find("<!-- END XML -->")));
  // posangle of each slice, in file order, read from the text.
  std::vector<double> posangles;
  const std::regex pos("<posangle>([-0-9.]+)</posangle>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), pos); it != std::sregex_iterator(); ++it)
    posangles.push_back(std::stod((*it)[1]));
  ASSERT_EQ(posangles.size(), 14u);  // README: 14 slices, 0.6 to 30.0 deg

  ReadOptions meta;
  meta.loadValues = false;
  auto v = readRadarVolume(kVol, meta);
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->format, "Rainbow 5");
  EXPECT_NEAR(v->site.latDeg, 50.856633, 1e-9);  // <sensorinfo><lat>
  EXPECT_NEAR(v->site.lonDeg, 6.379967, 1e-9);
  EXPECT_NEAR(v->site.antennaHeightMeters, 116.7, 1e-9);
  EXPECT_EQ(v->site.name, "143DEX");
  EXPECT_NEAR(v->beamWidthDeg, 1.326, 1e-9);
  EXPECT_EQ(v->timeIso8601, "2013-05-10T00:00:06Z");  // <scan date time>; the file name says 00:00:06
  ASSERT_EQ(v->sweeps.size(), 14u);
  EXPECT_NEAR(v->sweeps.front().fixedAngleDeg, 0.6, 1e-9);
  EXPECT_NEAR(v->sweeps.back().fixedAngleDeg, 30.0, 1e-9);
  std::vector<double> sorted = posangles;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const Sweep& s = v->sweeps[i];
    EXPECT_DOUBLE_EQ(s.fixedAngleDeg, sorted[i]);
    EXPECT_EQ(s.mode, SweepMode::Ppi);
    EXPECT_EQ(s.rayCount(), 361u);                    // rays="361"
    EXPECT_EQ(s.gateCount, 400u);                     // bins="400"
    EXPECT_DOUBLE_EQ(s.gateSpacingMeters, 250.0);     // rangestep 0.25 km
    EXPECT_DOUBLE_EQ(s.firstGateRangeMeters, 125.0);  // start_range 0 + half a step
    for (float e : s.elevationDeg) EXPECT_FLOAT_EQ(e, static_cast<float>(sorted[i]));
  }
  ASSERT_EQ(v->fields.size(), 1u);
  EXPECT_EQ(v->fields[0].name, "dBZ");
  EXPECT_EQ(v->fields[0].units, "dBZ");
  EXPECT_EQ(chooseDefaultField(v->fields), "dBZ");
}

TEST(RainbowReader, ValuesAndAnglesMatchAnIndependentDecoding) {
  SKIP_WITHOUT_TEST_DATA(kVol);
  const std::vector<unsigned char> f = readAll(kVol);
  auto v = readRadarVolume(kVol, {});
  ASSERT_TRUE(v.ok()) << v.error();
  // Slice 0 (0.6 deg, first after sorting too): angles BLOB 0 (16 bit), data BLOB 1 (8 bit).
  const Sweep& s = v->sweeps[0];
  ASSERT_NEAR(s.fixedAngleDeg, 0.6, 1e-9);
  const std::vector<unsigned char> angles = handBlob(f, 0);
  const std::vector<unsigned char> raw = handBlob(f, 1);
  ASSERT_EQ(angles.size(), 361u * 2);
  ASSERT_EQ(raw.size(), 361u * 400);
  std::size_t mismatches = 0, echo = 0, noEcho = 0;
  unsigned rawMin = 255, rawMax = 0;
  for (std::size_t r = 0; r < 361; ++r) {
    // start angle (big-endian, 360/65536 deg) + anglestep 1 / 2
    const double start = ((angles[2 * r] << 8) | angles[2 * r + 1]) * 360.0 / 65536.0;
    EXPECT_NEAR(s.azimuthDeg[r], std::fmod(start + 0.5, 360.0), 1e-4) << r;
    for (std::size_t g = 0; g < 400; ++g) {
      const unsigned n = raw[r * 400 + g];
      const float want = n == 0 ? -INFINITY : static_cast<float>(-31.5 + (n - 1.0) * (95.5 + 31.5) / 254.0);
      mismatches += s.value(r, static_cast<std::uint32_t>(g)) == want ? 0 : 1;
      if (n) {
        ++echo;
        rawMin = std::min(rawMin, n);
        rawMax = std::max(rawMax, n);
      } else {
        ++noEcho;
      }
    }
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_GT(echo, 1000u);
  // The range of the file's values lies inside the stated min..max (raw 1..255).
  EXPECT_GE(rawMin, 1u);
  EXPECT_LE(rawMax, 255u);
  std::printf("[ rainbow ] slice 0: %zu gates compared (%zu echo, raw %u..%u = %.1f..%.1f dBZ, %zu no echo)\n",
              std::size_t{361} * 400, echo, rawMin, rawMax, -31.5 + (rawMin - 1) * 0.5, -31.5 + (rawMax - 1) * 0.5,
              noEcho);
  // Every slice decodes, every value within [min, max] or no echo.
  std::size_t outside = 0;
  for (const Sweep& sw : v->sweeps)
    for (float x : sw.values) outside += (isNoEcho(x) || (x >= -31.5F && x <= 95.5F)) ? 0 : 1;
  EXPECT_EQ(outside, 0u);
}

TEST(RainbowReader, BadInputGivesErrorsNoCrash) {
  SKIP_WITHOUT_TEST_DATA(kVol);
  const std::vector<unsigned char> f = readAll(kVol);
  std::size_t errors = 0;
  for (std::size_t cut : {std::size_t{8}, std::size_t{100}, std::size_t{5000}, std::size_t{22211}, std::size_t{22300},
                          f.size() / 2, f.size() - 100, f.size() - 1}) {
    const std::vector<unsigned char> part(f.begin(), f.begin() + static_cast<long>(cut));
    auto v = readRainbow5("cut", part, {});
    if (v.ok()) continue;
    ++errors;
    EXPECT_EQ(v.error().rfind("cut: ", 0), 0u) << v.error();
  }
  EXPECT_GE(errors, 7u);
  // A BLOB whose zlib data is damaged.
  std::vector<unsigned char> g = f;
  const std::string s(f.begin(), f.end());
  const std::size_t blob1 = s.find("<BLOB blobid=\"1\"");
  for (std::size_t i = s.find('>', blob1) + 10; i < s.find('>', blob1) + 40; ++i) g[i] ^= 0x33;
  auto v = readRainbow5("damaged", g, {});
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.error().find("BLOB 1"), std::string::npos) << v.error();
}

}  // namespace
}  // namespace atmoglobe::volume
