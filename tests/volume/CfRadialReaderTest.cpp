// CfRadial reader against the real files in ../shared/data/radar_cfradial.
//
// Reference values come from netCDF-C's own dump tool, recorded here with the command:
//   ncdump -v VAR -f c FILE | grep 'VAR(RAY,GATE)'
// ncdump prints raw (packed) values; the expected physical value is raw * scale_factor +
// add_offset with the attributes as ncdump -h prints them.
//
// Tolerances:
//  - angles, lat/lon: ncdump prints floats with 7 significant digits (error <= 5e-7
//    relative); 1e-5 deg is above that and far below any real mistake (a wrong ray).
//  - values: printed scale/offset carry <= 1.4e-7 relative error and the model stores
//    floats (6e-8 relative); at |value| < 100 dBZ both are < 2e-5, so 1e-4 dB. One raw
//    count is 0.0036 dB (KaSACR) or 0.01 dB (DOW8): any decoding slip fails.
#include <atmoglobe/volume/CfRadialReader.h>
#include <atmoglobe/volume/RadarReader.h>

#include <gtest/gtest.h>

#include <string>

using namespace atmoglobe::volume;

namespace {
const std::string kDir = atmoglobe_test::testDataPath("radar_cfradial/");
const std::string kKaSacr = kDir + "example_plot_ppi_single_sweep.nc";
const std::string kMll = kDir + "MLL2217907250U.003.nc";
const std::string kDow8 = kDir + "cfrad.20211011_201733.023_to_20211011_201745.299_DOW8_RHI.nc";

constexpr double kAngleTol = 1e-5;
constexpr double kValueTol = 1e-4;

RadarVolume mustRead(const std::string& path, const ReadOptions& o = {}) {
  auto r = readCfRadial(path, o);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  if (!r.ok()) return {};
  return std::move(r).value();
}
}  // namespace

TEST(CfRadialReader, KaSacrFourSweepsWithTransitionRaysDropped) {
  SKIP_WITHOUT_TEST_DATA(kKaSacr);
  const RadarVolume v = mustRead(kKaSacr);
  EXPECT_EQ(v.format, "CfRadial");
  ASSERT_EQ(v.sweeps.size(), 4u);
  // ncdump -v fixed_angle: -0.007175555, 0.49271, 1.003582, 1.992367
  const double fixed[4] = {-0.007175555, 0.49271, 1.003582, 1.992367};
  // ncdump -v sweep_start_ray_index,sweep_end_ray_index: 28..389, 394..755, 763..1122, 1131..1484
  const std::size_t rays[4] = {389 - 28 + 1, 755 - 394 + 1, 1122 - 763 + 1, 1484 - 1131 + 1};
  std::size_t total = 0;
  for (int s = 0; s < 4; ++s) {
    EXPECT_NEAR(v.sweeps[s].fixedAngleDeg, fixed[s], kAngleTol) << s;
    EXPECT_EQ(v.sweeps[s].rayCount(), rays[s]) << s;
    EXPECT_EQ(v.sweeps[s].mode, SweepMode::Ppi);  // sweep_mode "azimuth_surveillance"
    EXPECT_EQ(v.sweeps[s].gateCount, 755u);
    // ncdump -v range: 506.949 ... 38180.56 (755 gates, gate centres)
    EXPECT_NEAR(v.sweeps[s].firstGateRangeMeters, 506.949, 1e-3);
    EXPECT_NEAR(v.sweeps[s].gateSpacingMeters, (38180.56 - 506.949) / 754.0, 2e-5);
    EXPECT_EQ(v.sweeps[s].values.size(), rays[s] * 755u);
    total += rays[s];
  }
  EXPECT_EQ(total, 1438u);  // of 1485 rays in the file: 47 transition rays dropped
  // ncdump -v azimuth -f c: azimuth(28) = 240.0199, azimuth(389) = 90.28123, azimuth(1484) = 241.7772
  EXPECT_NEAR(v.sweeps[0].azimuthDeg.front(), 240.0199, 1e-4);
  EXPECT_NEAR(v.sweeps[0].azimuthDeg.back(), 90.28123, 1e-4);
  EXPECT_NEAR(v.sweeps[3].azimuthDeg.back(), 241.7772, 1e-4);
  // ncdump -v elevation -f c: elevation(28) = 0.009304189, elevation(1484) = 1.992367
  EXPECT_NEAR(v.sweeps[0].elevationDeg.front(), 0.009304189, kAngleTol);
  EXPECT_NEAR(v.sweeps[3].elevationDeg.back(), 1.992367, kAngleTol);
  // ncdump -v latitude,longitude,altitude: 69.14128, 15.68417, 2
  EXPECT_NEAR(v.site.latDeg, 69.14128, kAngleTol);
  EXPECT_NEAR(v.site.lonDeg, 15.68417, kAngleTol);
  EXPECT_NEAR(v.site.antennaHeightMeters, 2.0, 1e-6);
  EXPECT_EQ(v.site.heightDatum, HeightDatum::MeanSeaLevel);
  EXPECT_EQ(v.timeIso8601, "2020-03-12T00:30:09Z");
  EXPECT_NEAR(v.beamWidthDeg, 0.314, 1e-6);
  ASSERT_EQ(v.fields.size(), 1u);
  EXPECT_EQ(v.fields[0].name, "reflectivity_at_cor");
  EXPECT_EQ(v.fields[0].units, "dBZ");
  EXPECT_EQ(v.loadedField.name, "reflectivity_at_cor");
}

TEST(CfRadialReader, KaSacrDecodedValuesMatchNcdump) {
  SKIP_WITHOUT_TEST_DATA(kKaSacr);
  const RadarVolume v = mustRead(kKaSacr);
  ASSERT_EQ(v.sweeps.size(), 4u);
  // ncdump -h: scale_factor = 0.003636129f, add_offset = -65.47139f, _FillValue = -32767s
  auto phys = [](double raw) { return raw * 0.003636129 + -65.47139; };
  // ncdump -v reflectivity_at_cor -f c FILE | grep 'reflectivity_at_cor(RAY,GATE)'
  struct Case {
    std::size_t sweep, rayInSweep;
    std::uint32_t gate;
    double raw;
  };
  const Case cases[] = {
      {0, 0, 0, 12784},     // file ray 28 (first ray of sweep 0)
      {0, 0, 100, 8244},    // reflectivity_at_cor(28,100)
      {0, 1, 754, 13631},   // reflectivity_at_cor(29,754)
      {1, 0, 754, 17147},   // reflectivity_at_cor(394,754)
      {2, 0, 1, 9411},      // reflectivity_at_cor(763,1)
      {3, 0, 100, 15955},   // reflectivity_at_cor(1131,100)
      {3, 353, 754, 12121}  // reflectivity_at_cor(1484,754): last ray of the file
  };
  for (const Case& c : cases) {
    EXPECT_NEAR(v.sweeps[c.sweep].value(c.rayInSweep, c.gate), phys(c.raw), kValueTol)
        << "sweep " << c.sweep << " ray " << c.rayInSweep << " gate " << c.gate;
  }
}

TEST(CfRadialReader, MeteoSwissSinglePpiWithFillValues) {
  SKIP_WITHOUT_TEST_DATA(kMll);
  const RadarVolume v = mustRead(kMll);
  ASSERT_EQ(v.sweeps.size(), 1u);
  const Sweep& s = v.sweeps[0];
  EXPECT_NEAR(s.fixedAngleDeg, 0.9997711, kAngleTol);  // ncdump -v fixed_angle
  EXPECT_EQ(s.rayCount(), 360u);
  EXPECT_EQ(s.gateCount, 492u);
  EXPECT_EQ(s.mode, SweepMode::Ppi);
  // ncdump -v range: 249.999, 749.997, ... 245749
  EXPECT_NEAR(s.firstGateRangeMeters, 249.999, 1e-3);
  EXPECT_NEAR(s.gateSpacingMeters, (245749.0 - 249.999) / 491.0, 1e-3);
  // ncdump -v azimuth -f c: azimuth(0) = 0.5300984, azimuth(359) = 359.5358
  EXPECT_NEAR(s.azimuthDeg[0], 0.5300984, kAngleTol);
  EXPECT_NEAR(s.azimuthDeg[359], 359.5358, 1e-4);
  // ncdump -v latitude,longitude,altitude: 46.04076, 8.833217, 1626
  EXPECT_NEAR(v.site.latDeg, 46.04076, kAngleTol);
  EXPECT_NEAR(v.site.lonDeg, 8.833217, kAngleTol);
  EXPECT_NEAR(v.site.antennaHeightMeters, 1626.0, 1e-6);
  EXPECT_EQ(v.timeIso8601, "2022-06-28T07:21:36Z");
  EXPECT_EQ(v.fields.size(), 9u);
  EXPECT_EQ(v.loadedField.name, "reflectivity");  // default: the reflectivity field
  EXPECT_EQ(v.loadedField.units, "dBZ");
  // ncdump -v reflectivity -f c | grep: (0,0) = _ (fill -9999), (0,3) = -2.5, (99,317) = 21,
  // (210,277) = 24.5. Float field, no scale_factor.
  EXPECT_TRUE(isNoData(s.value(0, 0)));
  EXPECT_FALSE(isNoEcho(s.value(0, 0)));
  EXPECT_NEAR(s.value(0, 3), -2.5, kValueTol);
  EXPECT_NEAR(s.value(99, 317), 21.0, kValueTol);
  EXPECT_NEAR(s.value(210, 277), 24.5, kValueTol);
}

TEST(CfRadialReader, MeteoSwissReadsOnlyTheRequestedField) {
  SKIP_WITHOUT_TEST_DATA(kMll);
  ReadOptions o;
  o.fieldName = "velocity";
  const RadarVolume v = mustRead(kMll, o);
  EXPECT_EQ(v.loadedField.name, "velocity");
  EXPECT_EQ(v.loadedField.units, "meters_per_second");
  ASSERT_EQ(v.sweeps.size(), 1u);
  EXPECT_EQ(v.sweeps[0].values.size(), 360u * 492u);
  o.fieldName = "no_such_field";
  auto bad = readCfRadial(kMll, o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("no_such_field"), std::string::npos) << bad.error();
  EXPECT_NE(bad.error().find(kMll), std::string::npos) << bad.error();
}

TEST(CfRadialReader, Dow8RhiIsReadAndDescribedAsRhi) {
  SKIP_WITHOUT_TEST_DATA(kDow8);
  const RadarVolume v = mustRead(kDow8);
  ASSERT_EQ(v.sweeps.size(), 1u);
  const Sweep& s = v.sweeps[0];
  EXPECT_EQ(s.mode, SweepMode::Rhi);                  // ncdump -v sweep_mode: "rhi"
  EXPECT_NEAR(s.fixedAngleDeg, 29.99837, kAngleTol);  // the azimuth of the RHI
  EXPECT_EQ(s.rayCount(), 160u);
  EXPECT_EQ(s.gateCount, 1984u);
  // ncdump -v range: 37.47406 ... 148659.6; range:meters_between_gates = 74.9481096863747.
  // (The shared data README says 37.5 m spacing; the file says 74.95 m with the first gate
  // centre at half a gate, 37.47 m.)
  EXPECT_NEAR(s.firstGateRangeMeters, 37.47406, 1e-4);
  EXPECT_NEAR(s.gateSpacingMeters, 74.9481096863747, 1e-3);
  // ncdump -v elevation,azimuth -f c: elevation(0) = 0.604248, (80) = 30, (159) = 69.5;
  // azimuth(80) = 30.09155
  EXPECT_NEAR(s.elevationDeg[0], 0.604248, kAngleTol);
  EXPECT_NEAR(s.elevationDeg[80], 30.0, kAngleTol);
  EXPECT_NEAR(s.elevationDeg[159], 69.5, kAngleTol);
  EXPECT_NEAR(s.azimuthDeg[80], 30.09155, 1e-4);
  // Per-ray position (latitude(time) ...): first ray: 40.014820098877, -88.3317947387695, 210.999995470047
  EXPECT_NEAR(v.site.latDeg, 40.014820098877, 1e-9);
  EXPECT_NEAR(v.site.lonDeg, -88.3317947387695, 1e-9);
  EXPECT_NEAR(v.site.antennaHeightMeters, 210.999995470047, 1e-6);
  EXPECT_EQ(v.timeIso8601, "2021-10-11T20:17:33Z");
  EXPECT_EQ(v.fields.size(), 8u);
  EXPECT_EQ(v.loadedField.name, "DBZHC");
  // ncdump -v DBZHC -f c: scale_factor 0.01, add_offset 0, _FillValue -32768:
  // (0,0) = -4166, (80,10) = -1699, (159,1983) = -76, (159,500) = _
  EXPECT_NEAR(s.value(0, 0), -41.66, kValueTol);
  EXPECT_NEAR(s.value(80, 10), -16.99, kValueTol);
  EXPECT_NEAR(s.value(159, 1983), -0.76, kValueTol);
  EXPECT_TRUE(isNoData(s.value(159, 500)));
}

TEST(CfRadialReader, MetadataOnlyReadDecodesNothing) {
  SKIP_WITHOUT_TEST_DATA(kKaSacr, kMll, kDow8);
  ReadOptions o;
  o.loadValues = false;
  for (const std::string& p : {kKaSacr, kMll, kDow8}) {
    const RadarVolume v = mustRead(p, o);
    ASSERT_FALSE(v.sweeps.empty()) << p;
    for (const Sweep& s : v.sweeps) {
      EXPECT_TRUE(s.values.empty()) << p;
      EXPECT_GT(s.rayCount(), 0u) << p;
      EXPECT_GT(s.gateCount, 0u) << p;
    }
  }
}
