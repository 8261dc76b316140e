// ODIM_H5 reader against the real files in ../shared/data/radar_odim.
//
// Reference values come from the HDF5 tools, recorded with their commands:
//   h5dump -a /datasetN/where/elangle FILE           (and nbins, rscale, rstart ...)
//   h5dump -d /datasetN/dataM/data -s RAY,BIN -c 1,1 FILE   (raw stored value)
// and the physical value is gain * raw + offset with gain/offset from
//   h5dump -a /datasetN/dataM/what/gain FILE  (ncdump -h FILE shows the same)
// Tolerance on decoded values: 1e-4 (the model stores floats: 6e-8 relative of < 100 is
// < 1e-5); one raw count is 0.1 or 0.5 dBZ, so any decoding slip fails.
#include <atmoglobe/volume/OdimReader.h>
#include <atmoglobe/volume/RadarReader.h>

#include <gtest/gtest.h>

#include <string>

using namespace atmoglobe::volume;

namespace {
const std::string kDir = atmoglobe_test::testDataPath("radar_odim/");
const std::string kAu40 = kDir + "40_20181220_060630.pvol.h5";
const std::string kBewid = kDir + "bewid.pvol.hdf";
constexpr double kValueTol = 1e-4;

RadarVolume mustRead(const std::string& path, const ReadOptions& o = {}) {
  auto r = readOdimH5(path, o);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  if (!r.ok()) return {};
  return std::move(r).value();
}
}  // namespace

TEST(OdimReader, Au40VolumeGeometry) {
  SKIP_WITHOUT_TEST_DATA(kAu40);
  const RadarVolume v = mustRead(kAu40);
  EXPECT_EQ(v.format, "ODIM_H5");
  // h5dump -a /datasetN/where/elangle, N = 1..14
  const double el[14] = {0.5, 0.9, 1.3, 1.8, 2.4, 3.1, 4.2, 5.6, 7.4, 10, 13.3, 17.9, 23.9, 32};
  ASSERT_EQ(v.sweeps.size(), 14u);
  for (std::size_t s = 0; s < 14; ++s) {
    const Sweep& sw = v.sweeps[s];
    EXPECT_NEAR(sw.fixedAngleDeg, el[s], 1e-12) << s;
    EXPECT_EQ(sw.mode, SweepMode::Ppi);
    EXPECT_EQ(sw.rayCount(), 360u);
    EXPECT_EQ(sw.gateCount, 598u);
    // rstart = 1 (km, start of bin 0), rscale = 500 m: first centre 1000 + 250 m
    EXPECT_DOUBLE_EQ(sw.firstGateRangeMeters, 1250.0);
    EXPECT_DOUBLE_EQ(sw.gateSpacingMeters, 500.0);
    EXPECT_EQ(sw.values.size(), 360u * 598u);
  }
  // datasetN/how/astart = -0.5 (ODIM 2.2: the first ray starts 0.5 deg before north), so
  // with 360 rays of 1 deg the ray centres are at whole degrees.
  EXPECT_NEAR(v.sweeps[0].azimuthDeg[0], 0.0, 1e-4);
  EXPECT_NEAR(v.sweeps[0].azimuthDeg[90], 90.0, 1e-4);
  EXPECT_NEAR(v.sweeps[0].azimuthDeg[359], 359.0, 1e-4);
  EXPECT_FLOAT_EQ(v.sweeps[0].elevationDeg[17], 0.5f);
  // h5dump -a /where/lat, lon, height: -35.661, 149.512, 1383
  EXPECT_DOUBLE_EQ(v.site.latDeg, -35.661);
  EXPECT_DOUBLE_EQ(v.site.lonDeg, 149.512);
  EXPECT_DOUBLE_EQ(v.site.antennaHeightMeters, 1383.0);
  EXPECT_EQ(v.site.heightDatum, HeightDatum::MeanSeaLevel);
  EXPECT_EQ(v.site.name, "AU40");                    // /what/source "RAD:AU40,PLC:CapFlat,..."
  EXPECT_EQ(v.timeIso8601, "2018-12-20T06:06:00Z");  // /what/date 20181220, time 060600
  EXPECT_DOUBLE_EQ(v.beamWidthDeg, 2.0);             // /how/beamwH
  // Quantities of dataset1 (data1..data7), in file order.
  ASSERT_EQ(v.fields.size(), 7u);
  EXPECT_EQ(v.fields[0].name, "DBZH");
  EXPECT_EQ(v.fields[0].units, "dBZ");
  EXPECT_EQ(v.fields[1].name, "VRADH");
  EXPECT_EQ(v.fields[1].units, "m/s");
  EXPECT_EQ(v.fields[5].name, "DBZH_CLEAN");
  EXPECT_EQ(v.fields[6].name, "VRADDH");
  EXPECT_EQ(v.loadedField.name, "DBZH");
}

TEST(OdimReader, Au40DbzhValues) {
  SKIP_WITHOUT_TEST_DATA(kAu40);
  const RadarVolume v = mustRead(kAu40);
  ASSERT_EQ(v.sweeps.size(), 14u);
  const Sweep& s = v.sweeps[0];
  // h5dump -d /dataset1/data1/data -s 69,408 -c 1,1 -> 163; gain 0.5, offset -32
  EXPECT_NEAR(s.value(69, 408), 0.5 * 163 - 32, kValueTol);
  // -s 0,16 -> 68
  EXPECT_NEAR(s.value(0, 16), 0.5 * 68 - 32, kValueTol);
  // -s 0,0 -> 0: nodata = undetect = 0 in this file; reported as no data (see OdimReader.h)
  EXPECT_TRUE(isNoData(s.value(0, 0)));
}

TEST(OdimReader, Au40SixteenBitQuantityWithNoDataAndNoEcho) {
  SKIP_WITHOUT_TEST_DATA(kAu40);
  ReadOptions o;
  o.fieldName = "DBZH_CLEAN";
  const RadarVolume v = mustRead(kAu40, o);
  ASSERT_EQ(v.sweeps.size(), 14u);
  EXPECT_EQ(v.loadedField.name, "DBZH_CLEAN");
  const Sweep& s = v.sweeps[0];
  // /dataset1/data6/what: gain 0.100000001490116, offset -32, nodata 0, undetect 1 (ushort)
  const double gain = 0.100000001490116;
  // h5dump -d /dataset1/data6/data -s 58,494 -c 1,1 -> 765; -s 0,132 -> 393
  EXPECT_NEAR(s.value(58, 494), gain * 765 - 32, kValueTol);
  EXPECT_NEAR(s.value(0, 132), gain * 393 - 32, kValueTol);
  // -s 0,0 -> 0 (nodata); -s 0,32 -> 1 (undetect)
  EXPECT_TRUE(isNoData(s.value(0, 0)));
  EXPECT_TRUE(isNoEcho(s.value(0, 32)));
  EXPECT_FALSE(isNoData(s.value(0, 32)));
}

TEST(OdimReader, BewidBinCountChangesBetweenSweeps) {
  SKIP_WITHOUT_TEST_DATA(kBewid);
  const RadarVolume v = mustRead(kBewid);
  // h5dump -a /datasetN/where/elangle and nbins, N = 1..11; rscale 250, rstart 0 everywhere
  const double el[11] = {0.3, 0.9, 1.5, 2.2, 2.9, 3.8, 4.8, 6.5, 9, 13, 25};
  const unsigned bins[11] = {1000, 1000, 1000, 1000, 1000, 1000, 500, 500, 500, 500, 500};
  ASSERT_EQ(v.sweeps.size(), 11u);
  for (std::size_t s = 0; s < 11; ++s) {
    EXPECT_NEAR(v.sweeps[s].fixedAngleDeg, el[s], 1e-12) << s;
    EXPECT_EQ(v.sweeps[s].gateCount, bins[s]) << s;
    EXPECT_EQ(v.sweeps[s].rayCount(), 360u);
    EXPECT_DOUBLE_EQ(v.sweeps[s].firstGateRangeMeters, 125.0);  // 0 km + 250 m / 2
    EXPECT_DOUBLE_EQ(v.sweeps[s].gateSpacingMeters, 250.0);
    EXPECT_EQ(v.sweeps[s].values.size(), 360u * bins[s]);
    EXPECT_EQ(v.sweeps[s].indexInFile, static_cast<int>(s));  // datasets 1..11 in numeric order
  }
  // No startazA/stopazA/astart: ray i centred at (i + 0.5) deg.
  EXPECT_NEAR(v.sweeps[0].azimuthDeg[0], 0.5, 1e-5);
  EXPECT_NEAR(v.sweeps[0].azimuthDeg[359], 359.5, 1e-4);
  // h5dump -a /where/lat, lon, height: 49.9143, 5.5056, 590
  EXPECT_DOUBLE_EQ(v.site.latDeg, 49.9143);
  EXPECT_DOUBLE_EQ(v.site.lonDeg, 5.5056);
  EXPECT_DOUBLE_EQ(v.site.antennaHeightMeters, 590.0);
  EXPECT_EQ(v.site.name, "bewid");                    // /what/source "...NOD:bewid..."
  EXPECT_EQ(siteTitle(v.site), "bewid (Wideumont)");  // "...PLC:Wideumont..."
  EXPECT_EQ(v.timeIso8601, "2019-06-06T00:00:16Z");
  EXPECT_DOUBLE_EQ(v.beamWidthDeg, 1.0);  // /how/beamwidth
  ASSERT_EQ(v.fields.size(), 1u);
  EXPECT_EQ(v.fields[0].name, "DBZH");
  // DBZH: gain 0.5, offset -32, nodata 255, undetect 0 (uint8)
  // h5dump -d /dataset1/data1/data -s 49,834 -c 1,1 -> 88; -s 0,6 -> 47; -s 0,990 -> 0
  EXPECT_NEAR(v.sweeps[0].value(49, 834), 0.5 * 88 - 32, kValueTol);
  EXPECT_NEAR(v.sweeps[0].value(0, 6), 0.5 * 47 - 32, kValueTol);
  EXPECT_TRUE(isNoEcho(v.sweeps[0].value(0, 990)));
  // h5dump -d /dataset7/data1/data -s 45,369 -c 1,1 -> 65 (4.8 deg sweep, 500 bins)
  EXPECT_NEAR(v.sweeps[6].value(45, 369), 0.5 * 65 - 32, kValueTol);
}

TEST(OdimReader, MetadataOnlyAndMissingQuantity) {
  SKIP_WITHOUT_TEST_DATA(kBewid);
  ReadOptions o;
  o.loadValues = false;
  const RadarVolume v = mustRead(kBewid, o);
  ASSERT_EQ(v.sweeps.size(), 11u);
  for (const Sweep& s : v.sweeps) EXPECT_TRUE(s.values.empty());
  o.loadValues = true;
  o.fieldName = "ZDR";
  auto bad = readOdimH5(kBewid, o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("ZDR"), std::string::npos) << bad.error();
  EXPECT_NE(bad.error().find(kBewid), std::string::npos) << bad.error();
}
