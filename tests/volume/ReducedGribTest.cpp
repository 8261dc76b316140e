// GRIB reduced grids (reduced_gg, reduced_ll) read in their own geometry, on files written in the
// test with ecCodes from its samples (ReducedGrib.h; no ../shared data): every point's value and
// position against what ecCodes wrote, both latitude directions, missing points, crops that keep
// rows and per row the points around the box, `info`, the CPU sampler exact at grid points, and
// bad pl arrays refused naming the file. The ../shared samples: GribReaderTest.cpp (realdata).
#include "ReducedGrib.h"

#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridSampler.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

using namespace atmoglobe;
using volume::GridVolume;

namespace {

double field(double lat, double lon, double level) {
  return 280.0 + 10.0 * std::sin(lat * 0.05) * std::cos(lon * 0.0174533) + 2.0 * std::sin(lon * 0.0349) -
         0.0065 * level;
}

bool missingBox(double lat, double lon) { return lat > 10.0 && lat < 20.0 && lon > 100.0 && lon < 130.0; }

/// A fresh directory for this test's files and GRIB index cache.
std::string scratch() {
  const std::string dir = atmoglobe_test::freshTestDir("reduced_grib");
  setenv("ATMOGLOBE_CACHE_DIR", (dir + "/cache").c_str(), 1);
  return dir;
}

/// Every point of the first message of `path` as ecCodes decodes it: latitude, longitude, value
/// (NaN where the bitmap says missing), and pl.
struct Points {
  std::vector<double> lat, lon, value;
  std::vector<long> pl;
};
Points readPoints(const std::string& path) {
  Points p;
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return p;
  int err = 0;
  codes_handle* h = codes_handle_new_from_file(nullptr, f, PRODUCT_GRIB, &err);
  if (h) {
    testutil::gribPoints(h, p.lat, p.lon);
    std::size_t n = p.lat.size();
    p.value.resize(n);
    codes_set_double(h, "missingValue", 1e30);
    codes_get_double_array(h, "values", p.value.data(), &n);
    for (double& v : p.value)
      if (v == 1e30) v = NAN;
    std::size_t rows = 0;
    codes_get_size(h, "pl", &rows);
    p.pl.resize(rows);
    codes_get_long_array(h, "pl", p.pl.data(), &rows);
    codes_handle_delete(h);
  }
  std::fclose(f);
  return p;
}

double lonDiff(double a, double b) { return std::remainder(a - b, 360.0); }

/// Every point of `pts` (file order, rows of pl points) found in the volume at its (row, point):
/// the volume's latitude and longitude there and its value at level k: the field's at the level,
/// and (`sameMessage`: `pts` was read from that level's message) ecCodes' own, NaN where ecCodes'
/// is. Returns the number compared.
int compareEveryPoint(const GridVolume& g, const Points& pts, std::size_t k, double levelValue, bool sameMessage) {
  int compared = 0;
  std::size_t p = 0, fileRow = 0;
  for (long n : pts.pl) {
    if (n == 0) {
      ++fileRow;
      continue;
    }
    // The volume's row of this latitude.
    std::size_t j = g.ny;
    for (std::size_t r = 0; r < g.ny; ++r)
      if (std::abs(g.latDeg[r] - pts.lat[p]) < 1e-9) j = r;
    EXPECT_LT(j, g.ny) << "no row at latitude " << pts.lat[p];
    if (j == g.ny) return compared;
    EXPECT_EQ(g.rowLengthPoints[j], static_cast<std::size_t>(n)) << "row at " << pts.lat[p];
    for (long i = 0; i < n; ++i, ++p) {
      // Rows run east in the volume; find the point by its longitude.
      const double x = std::remainder(pts.lon[p] - g.rowFirstLonDeg[j], 360.0) / g.rowSpacingDeg[j];
      const long at = ((std::lround(x) % n) + n) % n;
      EXPECT_NEAR(lonDiff(g.lonDegAt(j, static_cast<std::size_t>(at)), pts.lon[p]), 0.0, 1e-9);
      const float v = g.value(k, j, static_cast<std::size_t>(at));
      if (std::isnan(pts.value[p])) {
        EXPECT_TRUE(std::isnan(v)) << "missing at " << pts.lat[p] << " " << pts.lon[p];
      } else {
        if (sameMessage) {
          EXPECT_EQ(v, static_cast<float>(pts.value[p])) << pts.lat[p] << " " << pts.lon[p];
        }
        EXPECT_EQ(v, static_cast<float>(field(pts.lat[p], pts.lon[p], levelValue)));
      }
      ++compared;
    }
    ++fileRow;
  }
  // Padding beyond each row: NaN values and heights.
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = g.rowLengthPoints[j]; i < g.nx; ++i) {
      EXPECT_TRUE(std::isnan(g.value(k, j, i)));
      EXPECT_TRUE(std::isnan(g.heightMeters(k, j, i)));
    }
  return compared;
}

}  // namespace

// N32 reduced Gaussian (64 rows of 20 .. 128 points, north to south), four heightAboveSea levels,
// a bitmap of missing points: every value and position as ecCodes wrote them, levels bottom first,
// heights the level + EGM96 (or the level with useGeoid false), the sampler exact at grid points.
TEST(ReducedGrib, GaussianLevelsReadInTheirOwnGeometry) {
  const std::string dir = scratch();
  const std::string path = dir + "/rgg.grib2";
  testutil::ReducedGribSpec spec;
  spec.levels = {3000, 500, 5000, 1500};  // file order not bottom first
  spec.field = field;
  spec.missing = missingBox;
  ASSERT_EQ(testutil::writeReducedGrib(path, spec), "");
  const Points pts = readPoints(path);
  ASSERT_EQ(pts.lat.size(), 6114u);

  volume::GridReadOptions o;
  o.useGeoid = false;
  auto g = volume::readGridVolume(path, o);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_TRUE(g->reduced());
  EXPECT_FALSE(g->curvilinear);
  EXPECT_TRUE(g->wrapsLongitude);
  EXPECT_EQ(g->ny, 64u);
  EXPECT_EQ(g->nx, 128u);
  EXPECT_EQ(g->nz, 4u);
  EXPECT_EQ(g->rowLengthPoints.front(), 20u);
  EXPECT_EQ(g->fileRowStep, -1);  // north to south in the file
  EXPECT_LT(g->latDeg.front(), -87.8);
  EXPECT_EQ(g->levelValues, (std::vector<double>{500, 1500, 3000, 5000}));
  EXPECT_EQ(g->lonDeg.size(), 128u);
  EXPECT_DOUBLE_EQ(g->lonDeg[1] - g->lonDeg[0], 360.0 / 128.0);
  EXPECT_EQ(g->verticalKind, volume::VerticalKind::HeightAboveSeaLevel);
  int compared = 0;
  for (std::size_t k = 0; k < 4; ++k) compared += compareEveryPoint(*g, pts, k, g->levelValues[k], k == 2);
  EXPECT_EQ(compared, 4 * 6114);
  // Heights: the level itself without the geoid, + EGM96 (|N| < 110 m) with it.
  for (std::size_t j = 0; j < g->ny; j += 7)
    for (std::size_t i = 0; i < g->rowLengthPoints[j]; i += 5) EXPECT_EQ(g->heightMeters(2, j, i), 3000.0f);
  auto withGeoid = volume::readGridVolume(path);
  ASSERT_TRUE(withGeoid.ok()) << withGeoid.error();
  EXPECT_LT(std::abs(withGeoid->heightMeters(2, 30, 40) - 3000.0f), 110.0f);
  EXPECT_NE(withGeoid->heightMeters(2, 30, 40), 3000.0f);

  // The CPU sampler: exact at every grid point at its level's height, no data at missing points.
  const volume::GridSampler s(*g);
  double worst = 0.0;
  int echoes = 0, noData = 0;
  for (std::size_t j = 0; j < g->ny; ++j)
    for (std::size_t i = 0; i < g->rowLengthPoints[j]; ++i) {
      const auto v = s.sampleGeodetic(g->latDeg[j], g->lonDegAt(j, i), 1500.0, volume::Interpolation::Linear);
      if (std::isnan(g->value(1, j, i))) {
        EXPECT_EQ(v.state, volume::VolumeSample::State::NoData);
        ++noData;
        continue;
      }
      ASSERT_EQ(v.state, volume::VolumeSample::State::Echo) << j << " " << i;
      worst = std::max(worst, std::abs(v.value - g->value(1, j, i)));
      ++echoes;
    }
  std::cout << "reduced_gg read: " << echoes << " grid points sampled exactly (worst " << worst << "), " << noData
            << " missing\n";
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(noData, 10);

  // info: the grid in its own terms.
  auto info = volume::describeGridFile(path);
  ASSERT_TRUE(info.ok()) << info.error();
  EXPECT_TRUE(info->notReadable.empty()) << info->notReadable;
  EXPECT_TRUE(info->reduced);
  EXPECT_EQ(info->ny, 64u);
  EXPECT_EQ(info->nx, 128u);
  EXPECT_EQ(info->minRowLengthPoints, 20u);
  EXPECT_EQ(info->maxRowLengthPoints, 128u);
  EXPECT_EQ(info->gridPoints, 6114u);
  EXPECT_TRUE(info->wrapsLongitude);
  EXPECT_GT(info->meanSpacingKm, 250.0);
  EXPECT_LT(info->meanSpacingKm, 350.0);
  ASSERT_EQ(info->variables.size(), 1u);
  EXPECT_TRUE(info->variables[0].onGrid);
  EXPECT_EQ(info->variables[0].gridPoints, 6114u);
  const std::string text = volume::describeGridText(*info);
  EXPECT_NE(text.find("reduced_gg (reduced: rows of different lengths), 64 rows of 20 .. 128 points (6114 points)"),
            std::string::npos)
      << text;
  const std::string json = volume::describeGridJson(*info);
  EXPECT_NE(json.find("\"horizontal\": \"reduced\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"min_row_length_points\": 20"), std::string::npos) << json;
}

// Reduced lat/lon (0.36 degrees, rows of no point at both ends) written south to north: rows
// ascend with the file (fileRowStep +1), the empty rows are left out, every value matches.
TEST(ReducedGrib, LatLonSouthToNorthLeavesOutEmptyEndRows) {
  const std::string dir = scratch();
  const std::string path = dir + "/rll.grib2";
  testutil::ReducedGribSpec spec;
  spec.sample = "reduced_ll_sfc_grib2";
  spec.levels = {0, 100};
  spec.southToNorth = true;
  spec.field = field;
  spec.missing = missingBox;
  ASSERT_EQ(testutil::writeReducedGrib(path, spec), "");
  const Points pts = readPoints(path);
  ASSERT_GT(pts.lat.size(), 300000u);
  ASSERT_LT(pts.lat.front(), 0.0) << "south to north";
  volume::GridReadOptions o;
  o.useGeoid = false;
  auto g = volume::readGridVolume(path, o);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_TRUE(g->reduced());
  EXPECT_TRUE(g->wrapsLongitude);
  EXPECT_EQ(g->fileRowStep, 1);
  EXPECT_EQ(g->ny, 443u);  // 501 rows, 58 of no point
  EXPECT_EQ(g->nx, 1000u);
  EXPECT_EQ(compareEveryPoint(*g, pts, 0, 0.0, true), static_cast<int>(pts.lat.size()));
  auto info = volume::describeGridFile(path);
  ASSERT_TRUE(info.ok()) << info.error();
  EXPECT_EQ(info->emptyRowsLeftOut, 58u);
  EXPECT_NE(volume::describeGridText(*info).find("58 empty rows (pl 0) at the grid's ends left out"),
            std::string::npos);
}

// Crops keep the rows inside the box and one beyond each edge and, per row, the points inside
// and one beyond each edge (across the seam too): every kept point is the whole read's, and
// everywhere inside the box the crop samples as the whole grid does.
TEST(ReducedGrib, CropsKeepRowsAndPointsAroundTheBox) {
  const std::string dir = scratch();
  const std::string path = dir + "/rgg.grib2";
  testutil::ReducedGribSpec spec;
  spec.field = field;
  ASSERT_EQ(testutil::writeReducedGrib(path, spec), "");
  auto whole = volume::readGridVolume(path);
  ASSERT_TRUE(whole.ok()) << whole.error();
  const volume::GridSampler all(*whole);
  struct Box {
    double s, n, w, e;
  };
  for (const Box& b : {Box{30.0, 50.0, -20.0, 40.0}, Box{-40.0, -10.0, 170.0, -170.0}, Box{70.0, 90.0, 0.0, 300.0},
                       Box{-5.0, 5.0, 100.0, 101.0}}) {
    SCOPED_TRACE(std::to_string(b.s) + " " + std::to_string(b.n) + " " + std::to_string(b.w) + " " +
                 std::to_string(b.e));
    volume::GridReadOptions o;
    o.crop.southDeg = b.s;
    o.crop.northDeg = b.n;
    o.crop.westDeg = b.w;
    o.crop.eastDeg = b.e;
    o.crop.firstLevel = 1;
    o.crop.levelCount = 2;
    auto g = volume::readGridVolume(path, o);
    ASSERT_TRUE(g.ok()) << g.error();
    ASSERT_TRUE(g->reduced());
    EXPECT_FALSE(g->wrapsLongitude);
    EXPECT_EQ(g->nz, 2u);
    EXPECT_LT(g->latDeg.front(), std::max(b.s, -87.0));
    EXPECT_GT(g->latDeg.back(), std::min(b.n, 87.0));
    const double span = b.e >= b.w ? b.e - b.w : b.e + 360.0 - b.w;
    for (std::size_t j = 0; j < g->ny; ++j) {
      // The row's first point strictly west of the box, its last strictly east of it (or the
      // whole circle from its first point).
      const double first = g->rowFirstLonDeg[j], step = g->rowSpacingDeg[j];
      const double west = std::remainder(first - b.w, 360.0);
      const double east = west + static_cast<double>(g->rowLengthPoints[j] - 1) * step;
      EXPECT_LT(west, 0.0);
      EXPECT_GE(west, -step - 1e-9);
      EXPECT_TRUE(east > span || east >= west + 360.0 - 1e-9) << "row " << j << ": " << east;
      // Its points are the whole read's.
      for (std::size_t i = 0; i < g->rowLengthPoints[j]; ++i) {
        const auto v = all.sampleGeodetic(g->latDeg[j], g->lonDegAt(j, i), g->heightMeters(0, j, i),
                                          volume::Interpolation::Linear);
        ASSERT_EQ(v.state, volume::VolumeSample::State::Echo);
        EXPECT_NEAR(v.value, g->value(0, j, i), 1e-4);
      }
    }
    // Inside the box the crop samples as the whole grid.
    const volume::GridSampler crop(*g);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double worst = 0.0;
    for (int m = 0; m < 3000; ++m) {
      const double lat = b.s + u(rng) * (std::min(b.n, 87.8) - b.s), lon = b.w + u(rng) * span;
      const double h = 2000.0;
      const auto a = crop.sampleGeodetic(lat, lon, h, volume::Interpolation::Linear);
      const auto c = all.sampleGeodetic(lat, lon, h, volume::Interpolation::Linear);
      ASSERT_EQ(a.state, volume::VolumeSample::State::Echo) << lat << " " << lon;
      ASSERT_EQ(c.state, volume::VolumeSample::State::Echo);
      worst = std::max(worst, std::abs(a.value - c.value));
    }
    EXPECT_LT(worst, 1e-9);
  }
}

// Bad reduced grids: an error naming the file and what is wrong, never a crash.
TEST(ReducedGrib, InconsistentPlIsAnErrorNamingTheFile) {
  const std::string dir = scratch();
  struct Case {
    const char* name;
    std::function<void(codes_handle*)> tweak;
    const char* expect;
    const char* prefix;  ///< what the read's error starts with after the path
  };
  auto editPl = [](std::function<void(std::vector<long>&)> edit) {
    return [edit](codes_handle* h) {
      std::size_t n = 0;
      codes_get_size(h, "pl", &n);
      std::vector<long> pl(n);
      codes_get_long_array(h, "pl", pl.data(), &n);
      edit(pl);
      codes_set_long_array(h, "pl", pl.data(), n);
    };
  };
  const std::vector<Case> cases = {
      {"pl_sum.grib2", editPl([](std::vector<long>& pl) { pl[10] += 4; }),
       "the reduced grid's pl counts 6118 points in its 64 rows, the message has 6114",
       ": variable t:heightAboveSea: "},
      {"pl_zero.grib2", editPl([](std::vector<long>& pl) {
         pl[11] += pl[10];
         pl[10] = 0;
       }),
       // A Gaussian row of no points is damage (ecCodes asserted on such a sub-area, fuzz_grib): the
       // index skips the message, and the read says why.
       "damaged GRIB message 1 (at byte 0): a reduced Gaussian grid with a row of no points; skipped",
       ": no readable GRIB message ("},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name;
    testutil::ReducedGribSpec spec;
    spec.levels = {500, 1000};
    spec.field = field;
    spec.tweak = c.tweak;
    ASSERT_EQ(testutil::writeReducedGrib(path, spec), "");
    auto g = volume::readGridVolume(path);
    ASSERT_FALSE(g.ok());
    EXPECT_EQ(g.error().rfind(path + c.prefix, 0), 0u) << g.error();
    EXPECT_NE(g.error().find(c.expect), std::string::npos) << g.error();
    auto info = volume::describeGridFile(path);
    ASSERT_FALSE(info.ok());
    EXPECT_NE(info.error().find(c.expect), std::string::npos) << info.error();
  }
}
