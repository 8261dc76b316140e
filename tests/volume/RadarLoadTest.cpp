// The one load path (RadarLoad.h): read + site (geoid or not) + render layout, against the same
// steps called one by one, on a small SYNTHETIC CfRadial file written for the suite (no sample
// data needed) and, labelled realdata, on the NEXRAD, ODIM_H5 and RHI files of the shared data.
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace atmoglobe::volume {
namespace {

namespace fs = std::filesystem;

// A small synthetic volume (4 sweeps, 90 rays, 60 km), written once for the suite.
const std::string& syntheticPath() {
  static const std::string path = [] {
    const fs::path dir = fs::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "radar-load-suite";
    fs::create_directories(dir);
    SyntheticRadarOptions o;
    o.elevationsDeg = {0.5, 1.3, 2.4, 4.0};
    o.raysPerSweep = 90;
    o.maxRangeMeters = 60000.0;
    // The storm near enough to be inside the 60 km.
    o.stormEastKm = -20.0;
    o.stormNorthKm = -15.0;
    const std::string p = (dir / "synthetic_small.nc").string();
    const Status s = writeSyntheticCfRadial(p, o);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error());
    return p;
  }();
  return path;
}

// The steps loadRadar replaces, called one by one.
struct Direct {
  RadarVolume volume;
  SiteResolution site;
  PolarVolume layout;
};
Direct loadDirect(const std::string& path, const std::string& field, bool useGeoid) {
  Direct d;
  ReadOptions ro;
  ro.fieldName = field;
  Result<RadarVolume> v = readRadarVolume(path, ro);
  EXPECT_TRUE(v.ok()) << (v.ok() ? "" : v.error());
  if (!v) return d;
  Result<SiteResolution> s = resolveSite(v->site, useGeoid);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error());
  if (!s) return d;
  Result<PolarVolume> p = buildPolarVolume(*v, *s, BeamModel{});
  if (p) d.layout = *p;
  d.volume = std::move(*v);
  d.site = *s;
  return d;
}

// Bitwise: NaN (no data) and -inf (no echo) must survive as they are (NaN != NaN for ==).
bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void expectSameLayout(const PolarVolume& a, const PolarVolume& b) {
  EXPECT_EQ(a.sourcePath, b.sourcePath);
  EXPECT_EQ(a.fieldName, b.fieldName);
  EXPECT_EQ(a.site.latDeg, b.site.latDeg);
  EXPECT_EQ(a.site.lonDeg, b.site.lonDeg);
  EXPECT_EQ(a.site.antennaHeightEllipsoidMeters, b.site.antennaHeightEllipsoidMeters);
  ASSERT_EQ(a.sweeps.size(), b.sweeps.size());
  EXPECT_EQ(a.maxRays, b.maxRays);
  EXPECT_EQ(a.maxGates, b.maxGates);
  EXPECT_EQ(a.maxRangeMeters, b.maxRangeMeters);
  EXPECT_EQ(a.clipRadiusMeters, b.clipRadiusMeters);
  EXPECT_TRUE(sameBits(a.values, b.values));
}

TEST(RadarLoad, ReadAndSiteWithoutLayout) {
  const std::string& path = syntheticPath();
  RadarLoadOptions o;
  Result<LoadedRadar> r = loadRadar(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  const Direct d = loadDirect(path, "", true);
  EXPECT_FALSE(r->layout.has_value());
  EXPECT_EQ(r->volume.sourcePath, path);
  EXPECT_EQ(r->volume.loadedField.name, "DBZ");
  ASSERT_EQ(r->volume.sweeps.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(r->volume.sweeps[k].values.size(), d.volume.sweeps[k].values.size());  // values kept
    EXPECT_GT(r->volume.sweeps[k].values.size(), 0u);
  }
  // The synthetic file gives its antenna above mean sea level: the geoid is applied by default.
  EXPECT_EQ(r->volume.site.heightDatum, HeightDatum::MeanSeaLevel);
  EXPECT_TRUE(r->site.geoidApplied);
  EXPECT_EQ(r->site.site.antennaHeightEllipsoidMeters, d.site.site.antennaHeightEllipsoidMeters);
  EXPECT_EQ(r->site.datumNote, d.site.datumNote);
}

TEST(RadarLoad, NoGeoidUsesTheSeaLevelHeight) {
  RadarLoadOptions o;
  o.useGeoid = false;
  Result<LoadedRadar> r = loadRadar(syntheticPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_FALSE(r->site.geoidApplied);
  EXPECT_EQ(r->site.site.antennaHeightEllipsoidMeters, r->volume.site.antennaHeightMeters);
  EXPECT_EQ(r->site.site.antennaHeightEllipsoidMeters, SyntheticRadarOptions{}.antennaAltitudeMslMeters);
  EXPECT_NE(r->site.datumNote.find("geoid conversion off"), std::string::npos) << r->site.datumNote;
}

TEST(RadarLoad, LayoutIsTheDirectLayoutAndTheSweepValuesAreHeldOnce) {
  const std::string& path = syntheticPath();
  const Direct d = loadDirect(path, "", true);
  RadarLoadOptions o;
  o.buildRenderLayout = true;
  Result<LoadedRadar> r = loadRadar(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_TRUE(r->layout.has_value());
  expectSameLayout(*r->layout, d.layout);
  for (const Sweep& s : r->volume.sweeps) {
    EXPECT_TRUE(s.values.empty());        // released: the layout holds them
    EXPECT_EQ(s.azimuthDeg.size(), 90u);  // the metadata stay
  }
  o.keepSweepValues = true;
  r = loadRadar(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  for (std::size_t k = 0; k < r->volume.sweeps.size(); ++k)
    EXPECT_TRUE(sameBits(r->volume.sweeps[k].values, d.volume.sweeps[k].values)) << "sweep " << k;
}

TEST(RadarLoad, ErrorsNameTheFileAndTheProblem) {
  const fs::path dir = atmoglobe_test::freshTestDir("radar-load");
  const std::string missing = (dir / "no_such_radar.nc").string();
  Result<LoadedRadar> r = loadRadar(missing, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(missing), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("no such file"), std::string::npos) << r.error();

  const std::string text = (dir / "not_radar.nc").string();
  std::ofstream(text) << "not a radar file at all\n";
  r = loadRadar(text, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(text), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("not a CfRadial, ODIM_H5 or NEXRAD Level II file"), std::string::npos) << r.error();

  RadarLoadOptions o;
  o.fieldName = "VEL";
  o.buildRenderLayout = true;
  r = loadRadar(syntheticPath(), o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(syntheticPath()), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("'VEL'"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("DBZ"), std::string::npos) << r.error();  // lists what the file has
}

// Real files: NEXRAD (MSL antenna height, split cuts merged by the layout) and ODIM_H5 through
// the one path give what the separate steps give; an RHI file loads for `gates`/export but
// has no render layout, and says why naming the file.
TEST(RadarLoad, RealVolumesMatchTheDirectSteps) {
  const std::string klbb = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
  const std::string au40 = atmoglobe_test::testDataPath("radar_odim/40_20181220_060630.pvol.h5");
  SKIP_WITHOUT_TEST_DATA(klbb, au40);
  for (const std::string& path : {klbb, au40}) {
    SCOPED_TRACE(path);
    RadarLoadOptions o;
    o.buildRenderLayout = true;
    Result<LoadedRadar> r = loadRadar(path, o);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_TRUE(r->layout.has_value());
    const Direct d = loadDirect(path, "", true);
    expectSameLayout(*r->layout, d.layout);
    // The note is the datum line, then one line per reader warning (AU40: its DBZH has
    // nodata = undetect = 0, which the ODIM reader reports).
    std::string expectedNote = d.site.datumNote;
    for (const std::string& w : d.volume.warnings) expectedNote += "\nwarning: " + w;
    EXPECT_EQ(r->site.datumNote, expectedNote);
    EXPECT_TRUE(r->site.geoidApplied);
  }
  Result<LoadedRadar> k = loadRadar(klbb, RadarLoadOptions{"REF", true, true, false, {}});
  ASSERT_TRUE(k.ok()) << k.error();
  EXPECT_EQ(k->layout->fieldName, "REF");
  EXPECT_EQ(k->layout->sweeps.size(), 9u);  // 11 cuts, split cuts merged (docs/bench-volume.md)
}

TEST(RadarLoad, RealRhiFileLoadsButHasNoRenderLayout) {
  const std::string rhi =
      atmoglobe_test::testDataPath("radar_cfradial/cfrad.20211011_201733.023_to_20211011_201745.299_DOW8_RHI.nc");
  SKIP_WITHOUT_TEST_DATA(rhi);
  Result<LoadedRadar> r = loadRadar(rhi, {});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_FALSE(r->volume.sweeps.empty());
  RadarLoadOptions o;
  o.buildRenderLayout = true;
  r = loadRadar(rhi, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(rhi), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("RHI volumes cannot be volume-rendered"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace atmoglobe::volume
