// GSHHG coastlines and WDBII borders from the Debian gmt-gshhg files (installed by
// scripts/install-deps.sh; the tests skip with the reason where they are missing).
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/map/Gshhg.h>
#include <atmoglobe/map/MapLod.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

using namespace atmoglobe;

namespace {

#define SKIP_WITHOUT_GSHHG(kind, res)                                                                         \
  do {                                                                                                        \
    if (!std::filesystem::exists(map::gshhgPath(map::defaultGshhgDirectory(), kind, res)))                    \
      GTEST_SKIP() << map::gshhgPath(map::defaultGshhgDirectory(), kind, res) << " missing (apt-get install " \
                   << "gmt-gshhg)";                                                                           \
  } while (false)

// Distance (m) from (lon, lat) to the nearest point of the lines of the bins within 1 degree,
// the lines densified to 20 m (so the nearest point is within 10 m of the nearest line point).
double nearestLineMeters(const map::GshhgFile& f, unsigned levels, double lon, double lat) {
  const glm::dvec3 p = globe::geodeticToEcef({lat, lon, 0.0});
  double best = 1e300;
  for (int b : f.binsOverlapping(lon - 1.0, lat - 1.0, lon + 1.0, lat + 1.0)) {
    auto lines = f.readBin(b, levels);
    EXPECT_TRUE(lines) << lines.error();
    if (!lines) continue;
    for (const map::GeoPolyline& l : *lines) {
      for (std::size_t i = 1; i < l.lonLatDeg.size(); ++i) {
        const glm::dvec3 a = globe::geodeticToEcef({l.lonLatDeg[i - 1].y, l.lonLatDeg[i - 1].x, 0.0});
        const glm::dvec3 c = globe::geodeticToEcef({l.lonLatDeg[i].y, l.lonLatDeg[i].x, 0.0});
        // Nearest point on the chord (segments here are < 30 km: the chord is within 20 m of the arc).
        const glm::dvec3 d = c - a;
        const double t = glm::dot(d, d) > 0.0 ? std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0) : 0.0;
        best = std::min(best, glm::distance(p, a + t * d));
      }
    }
  }
  return best;
}

}  // namespace

TEST(Gshhg, CaboDaRocaIsOnTheCoastAtEveryResolution) {
  // Cabo da Roca lighthouse, the westernmost point of mainland Europe: 38.7804 N, 9.4989 W
  // (Wikipedia / OSM, 1e-4 deg ~ 10 m). GMT states the resolutions as roughly c 25 km, l 5 km,
  // i 1 km, h 0.2 km, f 0.04 km; the tolerances are those, except l (published 5 km; the cape
  // sits on a generalised corner: 6 km) plus the lighthouse's ~150 m back from the cliff edge.
  const double tolerance[] = {25000.0, 6000.0, 1200.0, 400.0, 250.0};
  for (int r = 0; r < 5; ++r) {
    const auto res = static_cast<map::GshhgResolution>(r);
    SKIP_WITHOUT_GSHHG(map::GshhgKind::Shoreline, res);
    auto f = map::GshhgFile::open(map::gshhgPath(map::defaultGshhgDirectory(), map::GshhgKind::Shoreline, res),
                                  map::GshhgKind::Shoreline);
    ASSERT_TRUE(f) << f.error();
    const double d = nearestLineMeters(**f, map::kCoastLevels, -9.4989, 38.7804);
    EXPECT_LT(d, tolerance[r]) << "resolution " << map::gshhgResolutionLetter(res);
    // Madrid, 300 km from the sea: no ocean coast (level 1) within 100 km at any resolution (the
    // check can fail; reservoir shores, level 2, come within 80 km).
    EXPECT_GT(nearestLineMeters(**f, 1u << 1, -3.7038, 40.4168), 100000.0);
  }
}

TEST(Gshhg, BaselTripointIsOnTheNationalBorders) {
  SKIP_WITHOUT_GSHHG(map::GshhgKind::Border, map::GshhgResolution::Intermediate);
  // The France-Germany-Switzerland tripoint in the Rhine at Basel: 47.5899 N, 7.5886 E.
  auto f = map::GshhgFile::open(
      map::gshhgPath(map::defaultGshhgDirectory(), map::GshhgKind::Border, map::GshhgResolution::Intermediate),
      map::GshhgKind::Border);
  ASSERT_TRUE(f) << f.error();
  EXPECT_LT(nearestLineMeters(**f, map::kNationalBorderLevels, 7.5886, 47.5899), 1500.0);  // i: ~1 km
  // Paris is 400 km from any national border; Kansas has state lines (level 2) but no national one.
  EXPECT_GT(nearestLineMeters(**f, map::kNationalBorderLevels, 2.3522, 48.8566), 100000.0);
  EXPECT_GT(nearestLineMeters(**f, map::kNationalBorderLevels, -98.0, 38.5), 100000.0);
  // The Kansas-Oklahoma line (37 N) at 98 W is a state border: within 5 km at i (measured 3.4 km:
  // WDBII's internal borders are coarser than its national ones).
  EXPECT_LT(nearestLineMeters(**f, map::kStateBorderLevels, -98.0, 37.0), 5000.0);
  EXPECT_GT(nearestLineMeters(**f, map::kStateBorderLevels, -98.0, 38.0), 50000.0);  // 111 km north of it
}

TEST(Gshhg, BinsTileTheGlobeAndReadOnlyTheirPoints) {
  SKIP_WITHOUT_GSHHG(map::GshhgKind::Shoreline, map::GshhgResolution::Crude);
  auto f = map::GshhgFile::open(
      map::gshhgPath(map::defaultGshhgDirectory(), map::GshhgKind::Shoreline, map::GshhgResolution::Crude),
      map::GshhgKind::Shoreline);
  ASSERT_TRUE(f) << f.error();
  EXPECT_EQ((*f)->binCount(), 18 * 9);
  EXPECT_EQ((*f)->binSizeDeg(), 20.0);
  // Every point read lies in its bin; every level counts, so the points add up to the file's.
  std::size_t points = 0;
  for (int b = 0; b < (*f)->binCount(); ++b) {
    const map::GshhgBinBox box = (*f)->binBox(b);
    auto lines = (*f)->readBin(b, 0xFFu);
    ASSERT_TRUE(lines) << lines.error();
    for (const auto& l : *lines) {
      points += l.lonLatDeg.size();
      for (const glm::dvec2& p : l.lonLatDeg) {
        ASSERT_GE(p.x, box.westDeg - 1e-9);
        ASSERT_LE(p.x, box.eastDeg + 1e-9);
        ASSERT_GE(p.y, box.southDeg - 1e-9);
        ASSERT_LE(p.y, box.northDeg + 1e-9);
      }
    }
  }
  EXPECT_EQ(points, 14138u);  // N_points_in_file of binned_GSHHS_c.nc (ncdump), GSHHG 2.3.7
  // Across the antimeridian: 170 E..170 W within the row of bins from 10 S to 10 N.
  EXPECT_EQ((*f)->binsOverlapping(170.0, -5.0, -170.0, 5.0).size(), 2u);
}

// binsInside (index arithmetic) lists what binsOverlapping (a scan) lists inside a box of whole
// bins: the globe, every crude (20 deg) bin and every low (10 deg) bin, at every finer level whose
// bins nest in them.
TEST(Gshhg, BinsInsideAreTheBinsOverlappingANestingBox) {
  using R = map::GshhgResolution;
  SKIP_WITHOUT_GSHHG(map::GshhgKind::Shoreline, R::Full);
  std::unique_ptr<map::GshhgFile> files[5];
  for (int r = 0; r < 5; ++r) {
    auto f = map::GshhgFile::open(map::gshhgPath(map::defaultGshhgDirectory(), map::GshhgKind::Shoreline, R(r)),
                                  map::GshhgKind::Shoreline);
    ASSERT_TRUE(f) << f.error();
    files[r] = std::move(*f);
  }
  const auto same = [](const map::GshhgFile& f, const map::GshhgBinBox& box) {
    std::vector<int> inside = f.binsInside(box);
    std::vector<int> scanned =
        f.binsOverlapping(box.westDeg + 1e-6, box.southDeg + 1e-6, box.eastDeg - 1e-6, box.northDeg - 1e-6);
    std::sort(inside.begin(), inside.end());
    std::sort(scanned.begin(), scanned.end());
    return inside == scanned && !inside.empty();
  };
  for (int r = 0; r < 5; ++r) EXPECT_TRUE(same(*files[r], {-180.0, -90.0, 180.0, 90.0})) << "level " << r;
  EXPECT_EQ(files[0]->binsInside({-180.0, -90.0, 180.0, 90.0}).size(), 162u);
  for (int parent = 0; parent < 2; ++parent)
    for (int b = 0; b < files[parent]->binCount(); ++b)
      for (int r = parent + 1; r < 5; ++r) {
        ASSERT_TRUE(same(*files[r], files[parent]->binBox(b))) << "level " << r << " in bin " << b << " of " << parent;
      }
}

TEST(Gshhg, BadFilesAreNamed) {
  const std::string dir = ATMOGLOBE_TEST_OUTPUT_DIR;
  std::filesystem::create_directories(dir);
  const std::string garbage = dir + "/not_gshhg.nc";
  std::ofstream(garbage) << "this is not NetCDF";
  auto f = map::GshhgFile::open(garbage, map::GshhgKind::Shoreline);
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().find(garbage), std::string::npos) << f.error();
  auto missing = map::GshhgFile::open(dir + "/nope.nc", map::GshhgKind::Border);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("nope.nc"), std::string::npos);
}

TEST(MapLod, CoarseFarFineNear) {
  // Metres a pixel spans: the coarsest level whose published point spacing is at most 2 pixels.
  EXPECT_EQ(map::gshhgResolutionForScale(13000.0), map::GshhgResolution::Crude);
  EXPECT_EQ(map::gshhgResolutionForScale(5000.0), map::GshhgResolution::Low);
  EXPECT_EQ(map::gshhgResolutionForScale(1000.0), map::GshhgResolution::Intermediate);
  EXPECT_EQ(map::gshhgResolutionForScale(200.0), map::GshhgResolution::High);
  EXPECT_EQ(map::gshhgResolutionForScale(1e-3), map::GshhgResolution::Full);
  for (int r = 0; r + 1 < 5; ++r)
    EXPECT_GT(map::maxSegmentMetersFor(static_cast<map::GshhgResolution>(r)),
              map::maxSegmentMetersFor(static_cast<map::GshhgResolution>(r + 1)));
}
