// Volumes split over files (RadarVolumeSet.h) on the real ODIM files, and the warnings the
// readers give instead of repairing silently.
//
// Facts from the files (ncdump -h FILE | grep -E "object|date|time|source|elangle|quantity"):
//  - behel_loop: 8 times 13:00-13:35Z, each a DBZH file (source NOD:behel ...) and a VRAD file
//    (source WMO:06475), same /where lat 51.069072 lon 5.4064 height 140, same /what date/time
//    (13:00:05Z for the first), 12 datasets each.
//  - lfpw_scans: SCAN files of frave (50.12832, 3.81181, 208.8 m); dataset1/what starttime:
//    cycle 06:55: A 06:55:01 (6.0 deg), B 06:55:44 (2.6), C 06:56:27 (1.6), D 06:57:29 (1.0),
//    E 06:58:45 (0.4); cycle 06:50: B 06:50:44 (3.6), C 06:51:28 (1.6), D 06:52:29 (1.0),
//    E 06:53:44 (0.4); the A scan of 06:50 is not in the directory.
#include <atmoglobe/volume/OdimReader.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace atmoglobe::volume;
namespace fs = std::filesystem;

namespace {
const std::string kOdim = atmoglobe_test::testDataPath("radar_odim");
const std::string kBehel = kOdim + "/behel_loop";
const std::string kLfpw = kOdim + "/lfpw_scans";
const std::string kAu40 = kOdim + "/40_20181220_060630.pvol.h5";
const std::string kBehelDbzh = kBehel + "/20200207130000.rad.behel.pvol.dbzh.scanz.hdf";
const std::string kBehelVrad = kBehel + "/20200207130000.rad.behel.pvol.vrad.scanz.hdf";
const std::string kKaSacr = atmoglobe_test::testDataPath("radar_cfradial/example_plot_ppi_single_sweep.nc");
const std::string kKlbb = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");

std::vector<std::string> expand(const std::string& spec) {
  auto r = expandRadarPaths(spec);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  return r.ok() ? *r : std::vector<std::string>{};
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += x + "\n";
  return s;
}

fs::path emptyDir(const std::string& name) {
  const fs::path d = fs::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "radar_set" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST(RadarVolumeSet, BehelLoopIsEightVolumesOfTwoFields) {
  SKIP_WITHOUT_TEST_DATA(kBehel);
  const std::vector<std::string> files = expand(kBehel);
  ASSERT_EQ(files.size(), 16u);
  RadarSetOptions o;
  o.read.loadValues = false;
  auto volumes = readRadarVolumeGroups(files, o);
  ASSERT_TRUE(volumes.ok()) << volumes.error();
  ASSERT_EQ(volumes->size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    const RadarVolume& v = (*volumes)[i];
    SCOPED_TRACE(v.timeIso8601);
    ASSERT_EQ(v.fields.size(), 2u);
    EXPECT_EQ(v.fields[0].name, "DBZH");
    EXPECT_EQ(v.fields[1].name, "VRAD");
    EXPECT_EQ(v.sweeps.size(), 12u);
    ASSERT_EQ(v.sourceFiles.size(), 2u);
    EXPECT_NE(v.sourceFiles[0].find("dbzh"), std::string::npos);
    EXPECT_NE(v.sourceFiles[1].find("vrad"), std::string::npos);
    EXPECT_EQ(v.site.name, "behel");  // the name of the file holding the loaded field (DBZH)
    // The two files name the site differently: said, and matched by position.
    EXPECT_NE(joined(v.warnings).find("'behel'"), std::string::npos) << joined(v.warnings);
    EXPECT_NE(joined(v.warnings).find("'06475'"), std::string::npos) << joined(v.warnings);
  }
  EXPECT_EQ((*volumes)[0].timeIso8601, "2020-02-07T13:00:05Z");
  EXPECT_EQ((*volumes)[7].timeIso8601.substr(0, 16), "2020-02-07T13:35");
}

TEST(RadarVolumeSet, BehelOneTimeAssemblesBothQuantities) {
  SKIP_WITHOUT_TEST_DATA(kBehelDbzh, kBehelVrad);
  const std::vector<std::string> files = expand(kBehel + "/20200207130000*");
  ASSERT_EQ(files.size(), 2u);
  for (const char* field : {"DBZH", "VRAD"}) {
    SCOPED_TRACE(field);
    RadarSetOptions o;
    o.read.fieldName = field;
    auto set = readRadarVolumeSet(files, o);
    ASSERT_TRUE(set.ok()) << set.error();
    ReadOptions ro;
    ro.fieldName = field;
    auto single = readOdimH5(std::string(field) == "DBZH" ? kBehelDbzh : kBehelVrad, ro);
    ASSERT_TRUE(single.ok()) << single.error();
    EXPECT_EQ(set->loadedField.name, field);
    ASSERT_EQ(set->sweeps.size(), single->sweeps.size());
    for (std::size_t k = 0; k < set->sweeps.size(); ++k) {
      EXPECT_EQ(set->sweeps[k].fixedAngleDeg, single->sweeps[k].fixedAngleDeg);
      EXPECT_EQ(set->sweeps[k].azimuthDeg, single->sweeps[k].azimuthDeg);
      EXPECT_TRUE(sameBits(set->sweeps[k].values, single->sweeps[k].values)) << k;
    }
    EXPECT_EQ(set->site.latDeg, single->site.latDeg);
    EXPECT_EQ(set->site.antennaHeightMeters, single->site.antennaHeightMeters);
  }
  // The default field is chosen over both files: DBZH (reflectivity), not VRAD.
  RadarSetOptions o;
  auto set = readRadarVolumeSet(files, o);
  ASSERT_TRUE(set.ok()) << set.error();
  EXPECT_EQ(set->loadedField.name, "DBZH");
  // A field neither file has: the error lists what the set has.
  o.read.fieldName = "ZDR";
  auto bad = readRadarVolumeSet(files, o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("'ZDR'"), std::string::npos) << bad.error();
  EXPECT_NE(bad.error().find("DBZH, VRAD"), std::string::npos) << bad.error();
}

TEST(RadarVolumeSet, LfpwScanCyclesAndTheMissingScan) {
  SKIP_WITHOUT_TEST_DATA(kLfpw);
  const std::vector<std::string> files = expand(kLfpw);
  ASSERT_EQ(files.size(), 9u);
  RadarSetOptions o;
  auto volumes = readRadarVolumeGroups(files, o);
  ASSERT_TRUE(volumes.ok()) << volumes.error();
  ASSERT_EQ(volumes->size(), 2u);
  const RadarVolume& early = (*volumes)[0];
  const RadarVolume& late = (*volumes)[1];
  // Cycle times: the earliest scan start of each cycle.
  EXPECT_EQ(early.timeIso8601, "2023-04-20T06:50:44Z");
  EXPECT_EQ(late.timeIso8601, "2023-04-20T06:55:01Z");
  const std::vector<double> lateEl = {0.4, 1.0, 1.6, 2.6, 6.0};
  const std::vector<double> earlyEl = {0.4, 1.0, 1.6, 3.6};
  ASSERT_EQ(late.sweeps.size(), lateEl.size());
  ASSERT_EQ(early.sweeps.size(), earlyEl.size());
  for (std::size_t k = 0; k < lateEl.size(); ++k) EXPECT_DOUBLE_EQ(late.sweeps[k].fixedAngleDeg, lateEl[k]);
  for (std::size_t k = 0; k < earlyEl.size(); ++k) EXPECT_DOUBLE_EQ(early.sweeps[k].fixedAngleDeg, earlyEl[k]);
  EXPECT_EQ(late.sourceFiles.size(), 5u);
  EXPECT_EQ(early.sourceFiles.size(), 4u);
  // Each sweep's values are those of its own file.
  for (const Sweep& s : late.sweeps) EXPECT_EQ(s.values.size(), 360u * 267u);
  // The complete cycle has no warning of anything missing; the early one names what is.
  EXPECT_EQ(joined(late.warnings).find("missing"), std::string::npos) << joined(late.warnings);
  const std::string w = joined(early.warnings);
  EXPECT_NE(w.find("incomplete cycle: 4 elevations"), std::string::npos) << w;
  EXPECT_NE(w.find("not here: 2.60, 6.00 deg"), std::string::npos) << w;
  EXPECT_NE(w.find("no scan from 2023-04-20T06:50:00Z to 2023-04-20T06:50:44Z"), std::string::npos) << w;

  // The early cycle alone still says a scan may be missing (the gap at its start).
  std::vector<std::string> earlyFiles;
  for (const std::string& f : files)
    if (f.find("202304200655") == std::string::npos && f.find("202304200656") == std::string::npos &&
        f.find("202304200657") == std::string::npos && f.find("202304200658") == std::string::npos &&
        f.find("202304200659") == std::string::npos)
      earlyFiles.push_back(f);
  ASSERT_EQ(earlyFiles.size(), 4u);
  auto alone = readRadarVolumeSet(earlyFiles, o);
  ASSERT_TRUE(alone.ok()) << alone.error();
  EXPECT_NE(joined(alone->warnings).find("a scan may be missing"), std::string::npos) << joined(alone->warnings);

  // One volume asked of the whole directory: the latest cycle, saying the other exists.
  auto one = readRadarVolumeSet(files, o);
  ASSERT_TRUE(one.ok()) << one.error();
  EXPECT_EQ(one->sweeps.size(), 5u);
  EXPECT_NE(one->warnings.front().find("the latest (2023-04-20T06:55:00Z) is read"), std::string::npos)
      << one->warnings.front();
  o.latestWhenSeveralTimes = false;
  auto refused = readRadarVolumeSet(files, o);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("2 volumes (one site at different times)"), std::string::npos) << refused.error();
}

TEST(RadarVolumeSet, DifferentSitesAreNeverMerged) {
  SKIP_WITHOUT_TEST_DATA(kBehelDbzh, kAu40);
  RadarSetOptions o;
  o.label = "mixed";
  auto r = readRadarVolumeSet({kBehelDbzh, kAu40}, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("mixed: the files hold 2 volumes (different sites or times)"), std::string::npos)
      << r.error();
  EXPECT_NE(r.error().find("40_20181220_060630.pvol.h5"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("behel at 51.0691, 5.4064"), std::string::npos) << r.error();
  // Through loadRadar with a comma-separated list: the same refusal.
  auto l = loadRadar(kBehelDbzh + "," + kAu40, RadarLoadOptions{});
  ASSERT_FALSE(l.ok());
  EXPECT_NE(l.error().find("never merged"), std::string::npos) << l.error();
  // The same file twice is one file.
  auto same = expandRadarPaths(kBehelDbzh + "," + kBehelDbzh);
  ASSERT_TRUE(same.ok()) << same.error();
  EXPECT_EQ(same->size(), 1u);
}

TEST(RadarVolumeSet, BadSpecsAreClearErrors) {
  const fs::path empty = emptyDir("empty");
  auto a = expandRadarPaths(empty.string());
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find(empty.string() + ": the directory holds no files"), std::string::npos) << a.error();
  const std::string pattern = (empty / "*.h5").string();
  EXPECT_TRUE(isRadarFileSet(pattern));
  auto b = expandRadarPaths(pattern);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().find(pattern + ": no file matches the pattern"), std::string::npos) << b.error();
  auto c = expandRadarPaths((empty / "a.h5").string() + "," + (empty / "b.h5").string());
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().find("a.h5: no such file or directory"), std::string::npos) << c.error();
  // loadRadar on them: the same messages, no crash.
  auto d = loadRadar(pattern, RadarLoadOptions{});
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().find("no file matches"), std::string::npos) << d.error();
  // A directory holding something that is not radar data names it.
  const fs::path junk = emptyDir("junk");
  std::ofstream(junk / "notes.txt") << "not a radar file\n";
  auto e = readRadarVolumeSet(expandRadarPaths(junk.string()).value(), RadarSetOptions{});
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.error().find("notes.txt"), std::string::npos) << e.error();
  // A plain file is not a set, even with a comma in its name.
  std::ofstream(junk / "a,b.h5") << "x";
  EXPECT_FALSE(isRadarFileSet((junk / "a,b.h5").string()));
}

TEST(RadarReaderWarnings, RealFilesSayWhatWasLeftOut) {
  SKIP_WITHOUT_TEST_DATA(kKaSacr, kKlbb, kAu40);
  // KaSACR: 1485 rays in the file, the four sweeps' index ranges cover 1438 (ncdump -v
  // sweep_start_ray_index,sweep_end_ray_index: 28-389, 394-755, 763-1122, 1131-1484 -> 362,
  // 362, 360, 354): 28 + 4 + 7 + 8 = 47 transition rays left out.
  auto k = readRadarVolume(kKaSacr, ReadOptions{});
  ASSERT_TRUE(k.ok()) << k.error();
  std::size_t rays = 0;
  for (const Sweep& s : k->sweeps) rays += s.rayCount();
  EXPECT_EQ(rays + 47, 1485u);
  ASSERT_EQ(k->warnings.size(), 1u);
  EXPECT_NE(k->warnings[0].find("47 of the file's 1485 rays"), std::string::npos) << k->warnings[0];
  // KLBB VEL: the surveillance halves of the split cuts (cuts 1 and 3) hold no VEL.
  ReadOptions vel;
  vel.fieldName = "VEL";
  auto n = readRadarVolume(kKlbb, vel);
  ASSERT_TRUE(n.ok()) << n.error();
  ASSERT_EQ(n->warnings.size(), 1u);
  EXPECT_NE(n->warnings[0].find("elevation cuts 1 (0.48 deg), 3 (1.45 deg) hold no VEL"), std::string::npos)
      << n->warnings[0];
  // KLBB REF: every cut has REF, the volume is complete: nothing to say.
  auto r = readRadarVolume(kKlbb, ReadOptions{});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(r->warnings.empty()) << joined(r->warnings);
  // AU40 DBZH: nodata = undetect = 0 (h5dump -a /dataset1/data1/what/nodata, undetect): said.
  auto a = readRadarVolume(kAu40, ReadOptions{});
  ASSERT_TRUE(a.ok()) << a.error();
  EXPECT_NE(joined(a->warnings).find("nodata and undetect are the same code"), std::string::npos)
      << joined(a->warnings);
}
