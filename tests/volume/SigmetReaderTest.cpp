// Sigmet/IRIS RAW reader on the two Sürgavere files of ../shared/data: facts
// (site, time, task, sweeps, angles, gates, fields) and decoded values checked against an
// independent decoding written here from the IRIS Programmer's Manual: the records are walked
// word by word by this file's own code (raw_prod_bhdr skipped, ingest_data_headers counted, the
// run-length codes expanded), not through the reader, and the raw bins converted with the
// manual's formulas. Facts not taken from the file itself: the Sürgavere radar stands at about
// 58.48 N 25.52 E (Estonian Environment Agency, ../shared/data/README.md names the radar), the
// times are in the file names (SUR210819000227: 2021-08-19 00:02:27).
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/SigmetReader.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace atmoglobe::volume {
namespace {

const std::string kPpi = atmoglobe_test::testDataPath("radar_sigmet/SUR210819000227.RAWKPJV");
const std::string kRhi = atmoglobe_test::testDataPath("radar_sigmet/SUR210819000847.RAWKPL0");

std::vector<unsigned char> readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// ------------------------------------------------------------ independent decoding (the spec)
struct HandRay {
  bool present = false;
  std::vector<std::uint16_t> words;  // expanded: 6 header words then the bins
};

/// All rays of one sweep (1-based sweep number) for every data type, [rayIndex][typeIndex].
/// Record size 6144; each record of the sweep starts with a 12-byte raw_prod_bhdr whose second
/// SINT2 is the sweep number; the first record then holds `types` 76-byte ingest_data_headers.
std::vector<std::vector<HandRay>> handDecodeSweep(const std::vector<unsigned char>& f, int sweep, int types,
                                                  int* raysExpected) {
  std::vector<std::uint16_t> stream;
  bool first = true;
  for (std::size_t rec = 2; (rec + 1) * 6144 <= f.size(); ++rec) {
    const unsigned char* r = f.data() + rec * 6144;
    const int sw = static_cast<std::int16_t>(r[2] | (r[3] << 8));
    if (sw != sweep) {
      if (!first) break;
      continue;
    }
    std::size_t start = 12;
    if (first) {
      *raysExpected = static_cast<std::int16_t>(r[12 + 30] | (r[12 + 31] << 8));  // number of rays expected
      start += 76 * static_cast<std::size_t>(types);
      first = false;
    }
    for (std::size_t i = start; i + 1 < 6144; i += 2)
      stream.push_back(static_cast<std::uint16_t>(r[i] | (r[i + 1] << 8)));
  }
  std::vector<std::vector<HandRay>> rays(static_cast<std::size_t>(*raysExpected), std::vector<HandRay>(types));
  std::size_t p = 0;
  for (auto& ray : rays) {
    for (HandRay& hr : ray) {
      std::uint16_t c = stream.at(p++);
      if (c == 1) continue;  // absent ray
      hr.present = true;
      while (c != 1) {
        if (c & 0x8000) {
          for (int k = 0; k < (c & 0x7FFF); ++k) hr.words.push_back(stream.at(p++));
        } else {
          hr.words.insert(hr.words.end(), c, 0);
        }
        c = stream.at(p++);
      }
    }
  }
  return rays;
}

double bin2Deg(std::uint16_t v) { return v * 360.0 / 65536.0; }

/// (N - 32768) / 100 for DBZ2/VEL2/ZDR2/KDP2; 0 no echo, 65535 no data.
float handCentred(std::uint16_t n) {
  if (n == 0) return -INFINITY;
  if (n == 65535) return NAN;
  return static_cast<float>((n - 32768.0) / 100.0);
}

// Types of both files' DSP mask, in mask order: XHDR(0) DBT2(8) DBZ2(9) VEL2(10) WIDTH2(11) ZDR2(12)
// KDP2(15) RHOHV2(20) SQI2(23) PHIDP2(24) HCLASS2(56) [+ SNR16(66) in the PPI file].
constexpr int kDbz2Index = 2, kVel2Index = 3;

TEST(SigmetReader, PpiFactsAndFields) {
  SKIP_WITHOUT_TEST_DATA(kPpi);
  auto fmt = detectRadarFormat(kPpi);
  ASSERT_TRUE(fmt.ok()) << fmt.error();
  EXPECT_EQ(*fmt, RadarFormat::SigmetIris);
  ReadOptions meta;
  meta.loadValues = false;
  auto v = readRadarVolume(kPpi, meta);
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->format, "Sigmet/IRIS RAW");
  EXPECT_EQ(v->site.name, "Surgavere, Radar");
  // Sürgavere: 58.482 N 25.519 E (README); the file's BIN4 angles give 58.48231, 25.51866.
  EXPECT_NEAR(v->site.latDeg, 58.482, 0.001);
  EXPECT_NEAR(v->site.lonDeg, 25.519, 0.001);
  // 157 m = ground 128 m + 29 m tower (ingest_configuration, both given; altitude 15700 cm).
  EXPECT_DOUBLE_EQ(v->site.antennaHeightMeters, 157.0);
  EXPECT_EQ(v->site.heightDatum, HeightDatum::MeanSeaLevel);
  EXPECT_EQ(v->timeIso8601, "2021-08-19T00:02:27Z");
  EXPECT_NEAR(v->beamWidthDeg, 0.95, 1e-6);
  // Task PPI1_H: one PPI at 0.5 deg (BIN2 0.49988 deg), 360 rays expected, 359 written.
  ASSERT_EQ(v->sweeps.size(), 1u);
  const Sweep& s = v->sweeps[0];
  EXPECT_EQ(s.mode, SweepMode::Ppi);
  EXPECT_NEAR(s.fixedAngleDeg, 0.5, 0.001);
  EXPECT_EQ(s.rayCount(), 359u);
  EXPECT_EQ(s.gateCount, 833u);                  // 833 output bins (250 km / 300 m)
  EXPECT_DOUBLE_EQ(s.gateSpacingMeters, 300.0);  // step_output_bins 30000 cm
  EXPECT_DOUBLE_EQ(s.firstGateRangeMeters, 0.0);
  EXPECT_TRUE(s.values.empty());
  std::vector<std::string> names;
  for (const FieldInfo& f : v->fields) names.push_back(f.name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"DBT2", "DBZ2", "VEL2", "WIDTH2", "ZDR2", "KDP2", "RHOHV2", "SQI2", "PHIDP2"}));
  EXPECT_EQ(v->fields[1].units, "dBZ");
  EXPECT_EQ(v->fields[2].units, "m/s");
  // Default: the corrected reflectivity by its standard name, not the total power DBT2 first in the file.
  EXPECT_EQ(chooseDefaultField(v->fields), "DBZ2");
  // Nyquist = wavelength 5.34 cm x PRF 570 Hz / 4 = 7.61 m/s (single PRF).
  EXPECT_NEAR(v->nyquistVelocityMps, 0.0534 * 570 / 4, 1e-9);
}

TEST(SigmetReader, PpiValuesMatchAnIndependentDecoding) {
  SKIP_WITHOUT_TEST_DATA(kPpi);
  const std::vector<unsigned char> f = readAll(kPpi);
  int expected = 0;
  const auto rays = handDecodeSweep(f, 1, 12, &expected);
  ASSERT_EQ(expected, 360);
  for (const auto& [field, typeIndex] : {std::pair<std::string, int>{"DBZ2", kDbz2Index}, {"VEL2", kVel2Index}}) {
    ReadOptions ro;
    ro.fieldName = field;
    auto v = readRadarVolume(kPpi, ro);
    ASSERT_TRUE(v.ok()) << v.error();
    const Sweep& s = v->sweeps.at(0);
    std::size_t out = 0, compared = 0, echo = 0, noEcho = 0, mismatches = 0;
    for (const auto& ray : rays) {
      const HandRay& hr = ray[static_cast<std::size_t>(typeIndex)];
      if (!hr.present) continue;  // absent rays are dropped by the reader
      ASSERT_LT(out, s.rayCount());
      // Ray angles: circular mid-point of the BIN2 start/end azimuths (within float rounding).
      double a0 = bin2Deg(hr.words[0]), a1 = bin2Deg(hr.words[2]);
      if (a1 < a0 - 180) a1 += 360;
      const double az = std::fmod((a0 + a1) / 2, 360.0);
      EXPECT_NEAR(s.azimuthDeg[out], az, 1e-4) << "ray " << out;
      const int bins = hr.words[4];
      for (std::uint32_t g = 0; g < s.gateCount; ++g) {
        const float want = g < static_cast<std::uint32_t>(bins) && 6 + g < hr.words.size()
                               ? handCentred(hr.words[6 + g])
                           : g < static_cast<std::uint32_t>(bins) ? -INFINITY  // run of zeros
                                                                  : NAN;
        const float got = s.value(out, g);
        const bool same = (std::isnan(want) && std::isnan(got)) || want == got;
        mismatches += same ? 0 : 1;
        ++compared;
        echo += std::isfinite(got) ? 1 : 0;
        noEcho += isNoEcho(got) ? 1 : 0;
      }
      ++out;
    }
    EXPECT_EQ(out, s.rayCount());
    EXPECT_EQ(mismatches, 0u) << field;
    // A real night-time PPI: some echo, mostly clear air.
    EXPECT_GT(echo, 1000u) << field;
    EXPECT_GT(noEcho, echo) << field;
    std::printf("[ sigmet ] %s: %zu gates compared with the hand decoding (%zu echo, %zu no echo)\n", field.c_str(),
                compared, echo, noEcho);
  }
}

TEST(SigmetReader, RhiTaskIsReadAndDescribed) {
  SKIP_WITHOUT_TEST_DATA(kRhi);
  auto v = readRadarVolume(kRhi, {});
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->timeIso8601, "2021-08-19T00:08:47Z");
  // Task RHI_120: two RHIs, at azimuths 150 and 270 deg (task list of azimuths), 0..60 deg.
  ASSERT_EQ(v->sweeps.size(), 2u);
  EXPECT_NEAR(v->sweeps[0].fixedAngleDeg, 150.0, 0.01);
  EXPECT_NEAR(v->sweeps[1].fixedAngleDeg, 270.0, 0.01);
  for (const Sweep& s : v->sweeps) {
    EXPECT_EQ(s.mode, SweepMode::Rhi);
    EXPECT_EQ(s.gateCount, 400u);  // 120 km / 300 m
    EXPECT_DOUBLE_EQ(s.gateSpacingMeters, 300.0);
    float minEl = 90, maxEl = -90;
    for (std::size_t r = 0; r < s.rayCount(); ++r) {
      // Every ray of an RHI points along its fixed azimuth (within 0.5 deg of antenna jitter).
      EXPECT_NEAR(s.azimuthDeg[r], s.fixedAngleDeg, 0.5) << r;
      minEl = std::min(minEl, s.elevationDeg[r]);
      maxEl = std::max(maxEl, s.elevationDeg[r]);
    }
    EXPECT_LT(minEl, 1.0F);
    EXPECT_GT(maxEl, 55.0F);
  }
  EXPECT_EQ(v->sweeps[0].rayCount(), 583u);  // 583 of 601 expected rays written
  const std::string text = describeVolumeText(*v);
  EXPECT_NE(text.find("150.00a RHI"), std::string::npos) << text;
  EXPECT_NE(text.find("the fixed angle of an RHI sweep is its azimuth"), std::string::npos);

  // Values of the first RHI against the hand decoding (DBZ2, the default).
  const std::vector<unsigned char> f = readAll(kRhi);
  int expected = 0;
  const auto rays = handDecodeSweep(f, 1, 11, &expected);
  ASSERT_EQ(expected, 601);
  const Sweep& s = v->sweeps[0];
  std::size_t out = 0, mismatches = 0, compared = 0;
  for (const auto& ray : rays) {
    const HandRay& hr = ray[kDbz2Index];
    if (!hr.present) continue;
    const int bins = hr.words[4];
    for (int g = 0; g < bins && 6 + static_cast<std::size_t>(g) < hr.words.size(); ++g) {
      const float want = handCentred(hr.words[6 + static_cast<std::size_t>(g)]);
      const float got = s.value(out, static_cast<std::uint32_t>(g));
      mismatches += ((std::isnan(want) && std::isnan(got)) || want == got) ? 0 : 1;
      ++compared;
    }
    // BIN2 elevations above 180 deg are negative (an RHI starts just below the horizon).
    const auto signedEl = [](double a) { return a > 180 ? a - 360 : a; };
    const double el = (signedEl(bin2Deg(hr.words[1])) + signedEl(bin2Deg(hr.words[3]))) / 2;
    EXPECT_NEAR(s.elevationDeg[out], el, 1e-4);
    ++out;
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_GT(compared, 100000u);
  std::printf("[ sigmet ] RHI DBZ2: %zu gates compared with the hand decoding\n", compared);
}

TEST(SigmetReader, FieldSelectionAndErrors) {
  SKIP_WITHOUT_TEST_DATA(kPpi);
  ReadOptions ro;
  ro.fieldName = "RHOHV2";
  auto v = readRadarVolume(kPpi, ro);
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->loadedField.name, "RHOHV2");
  std::size_t inRange = 0, finite = 0;
  for (float x : v->sweeps[0].values) {
    if (!std::isfinite(x)) continue;
    ++finite;
    inRange += (x >= 0.0F && x <= 1.0F) ? 1 : 0;  // (N-1)/65533 for N in 1..65534
  }
  EXPECT_GT(finite, 0u);
  EXPECT_EQ(inRange, finite);
  ro.fieldName = "NOPE";
  auto bad = readRadarVolume(kPpi, ro);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find(kPpi + ": no field 'NOPE' (the file has: DBT2, DBZ2"), std::string::npos) << bad.error();
}

TEST(SigmetReader, TruncatedAtManyOffsetsGivesErrorsNoCrash) {
  SKIP_WITHOUT_TEST_DATA(kPpi);
  const std::vector<unsigned char> f = readAll(kPpi);
  std::size_t errors = 0, reads = 0;
  for (std::size_t cut : {std::size_t{0}, std::size_t{25}, std::size_t{640}, std::size_t{6144}, std::size_t{8000},
                          std::size_t{12288}, std::size_t{12300}, std::size_t{13000}, std::size_t{20000}, f.size() / 3,
                          f.size() / 2, f.size() - 6144, f.size() - 1}) {
    const std::vector<unsigned char> part(f.begin(), f.begin() + static_cast<long>(cut));
    auto v = readSigmetIris("cut" + std::to_string(cut), part, {});
    if (v.ok()) {
      ++reads;  // a cut on a record boundary after the data: fewer rays, still a valid volume
      continue;
    }
    ++errors;
    EXPECT_EQ(v.error().rfind("cut" + std::to_string(cut) + ": ", 0), 0u) << v.error();
  }
  EXPECT_GE(errors, 10u);
  std::printf("[ sigmet ] truncations: %zu errors, %zu reads\n", errors, reads);
  // Flipped run-length codes must not crash either (errors or odd values, both fine).
  std::vector<unsigned char> g = f;
  for (std::size_t i = 2 * 6144 + 12 + 76 * 12; i < g.size(); i += 997) g[i] = 0xFF;
  auto v = readSigmetIris("flipped", g, {});
  if (!v.ok()) {
    EXPECT_EQ(v.error().rfind("flipped: Sigmet/IRIS", 0), 0u) << v.error();
  }
}

}  // namespace
}  // namespace atmoglobe::volume
