// The forecast-grid reader on small CF files written here with netCDF-C: every layout the reader
// claims (rectilinear north-to-south, 0..360 and -180..180, regional and global, levels up and
// down, pressure with and without geopotential, hybrid sigma-pressure, sigma, hybrid height,
// height above ground, packed values, netCDF-4 groups, curvilinear 2-D coordinates, calendars).
// Each file's values encode their own file indices, value = 1e6 t + 1e4 k + 100 j + i, so every
// flip, crop and wrap can be checked against where the value came from.
//
// Height tolerances: heights are stored as float; below 20 km a float's spacing is at most
// 2 mm, so 4 mm covers the rounding of both the reader's value and our double reference.
#include "NcTestFile.h"

#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/SyntheticRadar.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

using namespace atmoglobe::volume;
using atmoglobe_test::NcTestFile;

namespace {

constexpr double kHeightTolMeters = 4e-3;  // see the file comment

double code(std::size_t t, std::size_t k, std::size_t j, std::size_t i) {
  return 1e6 * static_cast<double>(t) + 1e4 * static_cast<double>(k) + 100.0 * static_cast<double>(j) +
         static_cast<double>(i);
}

std::vector<double> range(double first, double step, std::size_t n) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = first + step * static_cast<double>(i);
  return v;
}

double geoidAt(double latDeg, double lonDeg) {
  const auto& g = defaultEgm96Grid();
  EXPECT_TRUE(g.ok()) << (g ? "" : g.error());
  return g ? g->undulationMeters(latDeg, lonDeg) : 0.0;
}

bool mentions(const std::string& message, std::initializer_list<std::string> parts) {
  for (const auto& p : parts)
    if (message.find(p) == std::string::npos) return false;
  return true;
}

/// A CF grid: dims time, lev, lat, lon; 1-D coordinates; `ta` float (time, lev, lat, lon) = code().
struct CfGrid {
  std::vector<double> lat = range(60.0, -10.0, 13);  // north to south
  std::vector<double> lon = range(0.0, 10.0, 36);    // 0..350: global
  std::vector<double> lev = {1000, 850, 700, 500, 300};
  std::string levName = "lev", levUnits = "hPa", levStandardName = "air_pressure", levPositive = "down", levLongName,
              levFormulaTerms;
  std::size_t times = 2;
  std::string timeUnits = "hours since 2001-01-01 00:00:00", calendar;
  std::vector<double> timeValues;  ///< default 0, 1, 2 ...
  int mode = NC_NETCDF4;
  std::string group;          ///< "" or "a" or "a/b": where ta goes
  bool latCoordinate = true;  ///< false: no lat variable (bad input)
};

/// Writes the grid; `extra` defines and writes more variables (called before the core data is
/// written, so classic files can still define).
void writeCf(const std::string& path, const CfGrid& g, const std::function<void(NcTestFile&)>& extra = {}) {
  NcTestFile f(path, g.mode);
  f.globalText("Conventions", "CF-1.8");
  f.dim("time", g.times);
  f.dim(g.levName, g.lev.size());
  f.dim("lat", g.lat.size());
  f.dim("lon", g.lon.size());
  auto vt = f.var("time", NC_DOUBLE, {"time"});
  f.text(vt, "units", g.timeUnits);
  if (!g.calendar.empty()) f.text(vt, "calendar", g.calendar);
  auto vz = f.var(g.levName, NC_DOUBLE, {g.levName});
  if (!g.levUnits.empty()) f.text(vz, "units", g.levUnits);
  if (!g.levStandardName.empty()) f.text(vz, "standard_name", g.levStandardName);
  if (!g.levPositive.empty()) f.text(vz, "positive", g.levPositive);
  if (!g.levLongName.empty()) f.text(vz, "long_name", g.levLongName);
  if (!g.levFormulaTerms.empty()) f.text(vz, "formula_terms", g.levFormulaTerms);
  NcTestFile::Var vy;
  if (g.latCoordinate) {
    vy = f.var("lat", NC_DOUBLE, {"lat"});
    f.text(vy, "units", "degrees_north");
  }
  auto vx = f.var("lon", NC_DOUBLE, {"lon"});
  f.text(vx, "units", "degrees_east");
  int grp = -1;
  if (!g.group.empty()) {
    std::string rest = g.group;
    while (!rest.empty()) {
      const auto slash = rest.find('/');
      grp = f.group(rest.substr(0, slash), grp);
      rest = slash == std::string::npos ? "" : rest.substr(slash + 1);
    }
  }
  auto va = f.var("ta", NC_FLOAT, {"time", g.levName, "lat", "lon"}, grp);
  f.text(va, "units", "K");
  f.text(va, "long_name", "air temperature code");
  if (extra) extra(f);
  std::vector<double> tv = g.timeValues;
  if (tv.empty()) tv = range(0.0, 1.0, g.times);
  f.put(vt, tv);
  f.put(vz, g.lev);
  if (g.latCoordinate) f.put(vy, g.lat);
  f.put(vx, g.lon);
  std::vector<double> v;
  for (std::size_t t = 0; t < g.times; ++t)
    for (std::size_t k = 0; k < g.lev.size(); ++k)
      for (std::size_t j = 0; j < g.lat.size(); ++j)
        for (std::size_t i = 0; i < g.lon.size(); ++i) v.push_back(code(t, k, j, i));
  f.put(va, v);
}

/// A field on (time, lev, lat, lon) or (time, lat, lon) from a function of the file indices.
std::vector<double> field4(const CfGrid& g,
                           const std::function<double(std::size_t, std::size_t, std::size_t, std::size_t)>& fn) {
  std::vector<double> v;
  for (std::size_t t = 0; t < g.times; ++t)
    for (std::size_t k = 0; k < g.lev.size(); ++k)
      for (std::size_t j = 0; j < g.lat.size(); ++j)
        for (std::size_t i = 0; i < g.lon.size(); ++i) v.push_back(fn(t, k, j, i));
  return v;
}
std::vector<double> field3(const CfGrid& g, const std::function<double(std::size_t, std::size_t, std::size_t)>& fn) {
  std::vector<double> v;
  for (std::size_t t = 0; t < g.times; ++t)
    for (std::size_t j = 0; j < g.lat.size(); ++j)
      for (std::size_t i = 0; i < g.lon.size(); ++i) v.push_back(fn(t, j, i));
  return v;
}

/// Every column's heights increase strictly upwards.
void expectMonotonic(const GridVolume& g) {
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i)
      for (std::size_t k = 1; k < g.nz; ++k)
        ASSERT_GT(g.heightMeters(k, j, i), g.heightMeters(k - 1, j, i)) << k << " " << j << " " << i;
}

std::string testDir() { return atmoglobe_test::freshTestDir("grid_reader"); }

}  // namespace

// ---------------------------------------------------------------- rectilinear

TEST(GridReaderCf, NorthToSouthAnd0To360GlobalGridIsNormalised) {
  const std::string path = testDir() + "/global.nc";
  CfGrid g;  // lat 60..-60 (N->S), lon 0..350 (global), pressure 1000..300 hPa
  // Geopotential z (m2 s-2) on the levels: standard-atmosphere height of the level + 10 m per file row.
  auto zOf = [&](std::size_t, std::size_t k, std::size_t j, std::size_t) {
    return kStandardGravity *
           (standardAtmosphereGeopotentialHeightMeters(g.lev[k] * 100.0) + 10.0 * static_cast<double>(j));
  };
  writeCf(path, g, [&](NcTestFile& f) {
    auto vz = f.var("z", NC_FLOAT, {"time", "lev", "lat", "lon"});
    f.text(vz, "standard_name", "geopotential");
    f.text(vz, "units", "m2 s-2");
    f.put(vz, field4(g, zOf));
  });
  GridReadOptions o;
  o.timeIndex = 1;
  auto r = readGridVolume(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  const GridVolume& v = *r;
  EXPECT_EQ(v.variable, "/ta");
  EXPECT_FALSE(v.curvilinear);
  ASSERT_EQ(v.nx, 36u);
  ASSERT_EQ(v.ny, 13u);
  ASSERT_EQ(v.nz, 5u);
  EXPECT_TRUE(v.wrapsLongitude);
  EXPECT_EQ(v.latDeg.front(), -60.0) << "row 0 is the southernmost";
  EXPECT_EQ(v.latDeg.back(), 60.0);
  EXPECT_EQ(v.lonDeg.front(), 0.0);
  EXPECT_EQ(v.lonDeg.back(), 350.0) << "continuous, not wrapped to -10";
  EXPECT_EQ(v.fileFirstRow, 12u);
  EXPECT_EQ(v.fileRowStep, -1);
  EXPECT_EQ(v.fileLevelStep, 1);
  EXPECT_EQ(v.verticalKind, VerticalKind::Pressure);
  EXPECT_EQ(v.heightSource, HeightSource::GeopotentialField);
  EXPECT_FALSE(v.approximateHeights);
  EXPECT_EQ(v.verticalVariable, "/lev");
  ASSERT_EQ(v.levelValues.size(), 5u);
  EXPECT_EQ(v.levelValues.front(), 100000.0) << "bottom first, in Pa";
  EXPECT_EQ(v.levelUnits, "Pa");
  ASSERT_EQ(v.times.size(), 2u);
  EXPECT_EQ(v.validTime, "2001-01-01T01:00:00Z");
  for (std::size_t k = 0; k < v.nz; ++k)
    for (std::size_t j = 0; j < v.ny; ++j)
      for (std::size_t i = 0; i < v.nx; ++i) {
        const std::size_t jf = 12 - j;
        ASSERT_EQ(v.value(k, j, i), static_cast<float>(code(1, k, jf, i))) << k << " " << j << " " << i;
        const double expected =
            geometricFromGeopotentialHeightMeters(zOf(1, k, jf, i) / kStandardGravity, v.latDeg[j]) +
            geoidAt(v.latDeg[j], v.lonDeg[i]);
        ASSERT_NEAR(v.heightMeters(k, j, i), expected, kHeightTolMeters) << k << " " << j << " " << i;
      }
  expectMonotonic(v);
  EXPECT_NE(v.heightNote.find("'/z'"), std::string::npos) << v.heightNote;
  EXPECT_NE(v.heightNote.find("EGM96"), std::string::npos) << v.heightNote;
}

TEST(GridReaderCf, CropsAcrossTheAntimeridianAndTheZeroMeridianOfAGlobalGrid) {
  const std::string path = testDir() + "/global.nc";
  CfGrid g;
  writeCf(path, g);
  auto whole = readGridVolume(path);
  ASSERT_TRUE(whole.ok()) << whole.error();
  EXPECT_EQ(whole->heightSource, HeightSource::StandardAtmosphere);
  EXPECT_TRUE(whole->approximateHeights);

  // 172 .. -172: no grid point inside in longitude but 180; 170 and 190 kept as neighbours.
  GridReadOptions o;
  o.crop.westDeg = 172;
  o.crop.eastDeg = -172;
  o.crop.southDeg = -5;
  o.crop.northDeg = 25;
  o.crop.firstLevel = 1;
  o.crop.levelCount = 2;
  auto r = readGridVolume(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_FALSE(r->wrapsLongitude);
  ASSERT_EQ(r->lonDeg, (std::vector<double>{170, 180, 190}));
  ASSERT_EQ(r->latDeg, (std::vector<double>{-10, 0, 10, 20, 30}));
  ASSERT_EQ(r->nz, 2u);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t j = 0; j < 5; ++j)
      for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t jf = 12 - static_cast<std::size_t>((r->latDeg[j] + 60.0) / 10.0);
        ASSERT_EQ(r->value(k, j, i), static_cast<float>(code(0, k + 1, jf, 17 + i)));
      }
  EXPECT_LT(r->bytesRead, whole->bytesRead / 4) << "a crop reads its hyperslab only";

  // -15 .. 15 on a 0..360 grid: file columns 34, 35, 0, 1, 2 as -20 .. 20.
  o = GridReadOptions{};
  o.crop.westDeg = -15;
  o.crop.eastDeg = 15;
  r = readGridVolume(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->lonDeg, (std::vector<double>{-20, -10, 0, 10, 20}));
  const std::size_t fileCols[] = {34, 35, 0, 1, 2};
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(r->value(0, 0, i), static_cast<float>(code(0, 0, 12, fileCols[i])));
  // Heights follow their columns across the seam (the geoid differs from column to column).
  for (std::size_t i = 0; i < 5; ++i)
    EXPECT_NEAR(r->heightMeters(0, 0, i), whole->heightMeters(0, 0, fileCols[i]), kHeightTolMeters);

  // A box wider than the globe keeps it all.
  o.crop.westDeg = -200;
  o.crop.eastDeg = 200;
  r = readGridVolume(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->nx, 36u);
  EXPECT_TRUE(r->wrapsLongitude);
}

TEST(GridReaderCf, RegionalGridWithHeightLevelsRunningDown) {
  const std::string path = testDir() + "/regional.nc";
  CfGrid g;
  g.lat = range(30.0, 1.0, 11);            // south to north
  g.lon = range(-100.0, 1.0, 11);          // -100 .. -90
  g.lev = {12000, 8000, 4000, 1000, 100};  // top first
  g.levUnits = "m";
  g.levStandardName = "altitude";
  g.levPositive = "up";
  writeCf(path, g);
  auto r = readGridVolume(path);
  ASSERT_TRUE(r.ok()) << r.error();
  const GridVolume& v = *r;
  EXPECT_FALSE(v.wrapsLongitude);
  EXPECT_EQ(v.lonDeg.front(), -100.0);
  EXPECT_EQ(v.latDeg.front(), 30.0);
  EXPECT_EQ(v.fileLevelStep, -1);
  EXPECT_EQ(v.fileFirstLevel, 4u);
  EXPECT_EQ(v.verticalKind, VerticalKind::HeightAboveSeaLevel);
  EXPECT_FALSE(v.approximateHeights);
  EXPECT_EQ(v.levelValues, (std::vector<double>{100, 1000, 4000, 8000, 12000}));
  for (std::size_t k = 0; k < 5; ++k)
    for (std::size_t j = 0; j < v.ny; ++j)
      for (std::size_t i = 0; i < v.nx; ++i) {
        ASSERT_EQ(v.value(k, j, i), static_cast<float>(code(0, 4 - k, j, i)));
        ASSERT_NEAR(v.heightMeters(k, j, i), g.lev[4 - k] + geoidAt(v.latDeg[j], v.lonDeg[i]), kHeightTolMeters);
      }
  expectMonotonic(v);

  GridReadOptions o;
  o.useGeoid = false;
  auto flat = readGridVolume(path, o);
  ASSERT_TRUE(flat.ok()) << flat.error();
  EXPECT_EQ(flat->heightMeters(0, 3, 3), 100.0f);
  EXPECT_NE(flat->heightNote.find("no geoid correction"), std::string::npos) << flat->heightNote;

  o = GridReadOptions{};
  o.crop.southDeg = 33.5;
  o.crop.northDeg = 35.2;
  o.crop.westDeg = -95.5;
  o.crop.eastDeg = -95.5;
  auto c = readGridVolume(path, o);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->latDeg, (std::vector<double>{33, 34, 35, 36})) << "inside plus one row each side";
  EXPECT_EQ(c->lonDeg, (std::vector<double>{-96, -95})) << "a zero-width box keeps the two columns around it";

  o.crop.southDeg = 50;
  o.crop.northDeg = 60;
  auto none = readGridVolume(path, o);
  ASSERT_FALSE(none.ok());
  EXPECT_TRUE(mentions(none.error(), {path, "'/lat'", "do not overlap"})) << none.error();
}

TEST(GridReaderCf, DescendingLongitudesAcrossTheAntimeridianAreReversed) {
  const std::string path = testDir() + "/east_to_west.nc";
  CfGrid g;
  g.lat = range(-40.0, 1.0, 3);
  g.lon = {-170, -175, 180, 175, 170};  // east to west, across 180
  writeCf(path, g);
  auto r = readGridVolume(path);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->lonDeg, (std::vector<double>{170, 175, 180, 185, 190}));
  EXPECT_EQ(r->fileColumnStep, -1);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(r->value(0, 0, i), static_cast<float>(code(0, 0, 0, 4 - i)));
  // Longitudes that go back and forth are refused, naming the variable.
  g.lon = {0, 10, 5, 20, 30};
  writeCf(path, g);
  auto bad = readGridVolume(path);
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(mentions(bad.error(), {path, "'/lon'", "not strictly monotonic"})) << bad.error();
}

TEST(GridReaderCf, PressureWithoutGeopotentialUsesTheStandardAtmosphereAndSaysSo) {
  const std::string path = testDir() + "/echam_like.nc";
  CfGrid g;
  g.lev = {100000, 92500, 85000, 70000, 50000, 30000, 10000, 1000};
  g.levUnits = "Pa";
  g.levStandardName = "";
  g.levPositive = "";
  g.mode = 0;  // classic, like the ECHAM file
  writeCf(path, g);
  auto r = readGridVolume(path);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->verticalKind, VerticalKind::Pressure);
  EXPECT_EQ(r->heightSource, HeightSource::StandardAtmosphere);
  EXPECT_TRUE(r->approximateHeights);
  EXPECT_NE(r->heightNote.find("APPROXIMATE"), std::string::npos) << r->heightNote;
  expectMonotonic(*r);
  for (std::size_t j = 0; j < r->ny; ++j)
    for (std::size_t i = 0; i < r->nx; ++i) {
      const double n = geoidAt(r->latDeg[j], r->lonDeg[i]);
      // 500 hPa (level 4) lies at 5574 m' in the standard atmosphere (USSA 1976 table); the
      // geometric height differs by up to 25 m (1/r^2: 5 m; gravity at |lat| <= 60: 15 m).
      EXPECT_NEAR(r->heightMeters(4, j, i) - n, 5574.0, 25.0);
      EXPECT_NEAR(
          r->heightMeters(4, j, i),
          geometricFromGeopotentialHeightMeters(standardAtmosphereGeopotentialHeightMeters(50000.0), r->latDeg[j]) + n,
          kHeightTolMeters);
    }
}

// ---------------------------------------------------------------- parametric coordinates

namespace {
// ECHAM-style hybrid levels, top first: ap (Pa), b; p = ap + b ps.
const std::vector<double> kAp = {20000, 15000, 5000, 0};
const std::vector<double> kB = {0.0, 0.2, 0.6, 1.0};
double surfacePressure(std::size_t t, std::size_t j, std::size_t i) {
  return 101000.0 - 800.0 * static_cast<double>(j) - 150.0 * static_cast<double>(i) + 300.0 * static_cast<double>(t);
}
}  // namespace

TEST(GridReaderCf, HybridSigmaPressureHeightsMatchAnIndependentComputation) {
  const std::string path = testDir() + "/hybrid.nc";
  CfGrid g;
  g.lat = range(40.0, 2.0, 5);
  g.lon = range(10.0, 2.0, 6);
  g.lev = {1, 2, 3, 4};
  g.levUnits = "level";
  g.levStandardName = "atmosphere_hybrid_sigma_pressure_coordinate";
  g.levPositive = "down";
  g.levFormulaTerms = "ap: hyam b: hybm ps: aps";
  writeCf(path, g, [&](NcTestFile& f) {
    auto ap = f.var("hyam", NC_DOUBLE, {"lev"});
    f.text(ap, "units", "Pa");
    auto b = f.var("hybm", NC_DOUBLE, {"lev"});
    auto ps = f.var("aps", NC_FLOAT, {"time", "lat", "lon"});
    f.text(ps, "units", "Pa");
    f.put(ap, kAp);
    f.put(b, kB);
    f.put(ps, field3(g, surfacePressure));
  });
  GridReadOptions o;
  o.timeIndex = 1;
  auto r = readGridVolume(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  const GridVolume& v = *r;
  EXPECT_EQ(v.verticalKind, VerticalKind::HybridSigmaPressure);
  EXPECT_EQ(v.heightSource, HeightSource::StandardAtmosphere);
  EXPECT_TRUE(v.approximateHeights);
  EXPECT_EQ(v.fileLevelStep, -1) << "top-first levels come out bottom first";
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t j = 0; j < v.ny; ++j)
      for (std::size_t i = 0; i < v.nx; ++i) {
        const std::size_t kf = 3 - k;
        const double p = kAp[kf] + kB[kf] * static_cast<double>(static_cast<float>(surfacePressure(1, j, i)));
        const double n = geoidAt(v.latDeg[j], v.lonDeg[i]);
        const double expected =
            geometricFromGeopotentialHeightMeters(standardAtmosphereGeopotentialHeightMeters(p), v.latDeg[j]) + n;
        ASSERT_NEAR(v.heightMeters(k, j, i), expected, kHeightTolMeters) << k << " " << j << " " << i;
        // And, below the tropopause (p > 226.3 hPa), against the reference's troposphere formula
        // (REFERENCE.md section 4), which knows nothing of our code: within 1.5 m (its rounded
        // constants) + 25 m (geometric vs geopotential height below 11 km at 40-48 N).
        if (p > 22700.0) {
          ASSERT_NEAR(v.heightMeters(k, j, i) - n, 44331.5 - 4946.62 * std::pow(p, 0.190263), 26.5);
        }
        ASSERT_EQ(v.value(k, j, i), static_cast<float>(code(1, kf, j, i)));
      }
  expectMonotonic(v);
  EXPECT_NE(v.heightNote.find("'/aps'"), std::string::npos) << v.heightNote;
  // Kept when asked, for isobaric surfaces: each value's p = ap + b ps (float: 1e5 Pa has a
  // spacing of 0.008 Pa).
  EXPECT_TRUE(v.pressurePa.empty());
  o.keepPressure = true;
  auto kept = readGridVolume(path, o);
  ASSERT_TRUE(kept.ok()) << kept.error();
  ASSERT_EQ(kept->pressurePa.size(), kept->values.size());
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t j = 0; j < v.ny; ++j)
      for (std::size_t i = 0; i < v.nx; ++i) {
        const std::size_t kf = 3 - k;
        const double p = kAp[kf] + kB[kf] * static_cast<double>(static_cast<float>(surfacePressure(1, j, i)));
        ASSERT_NEAR(kept->pressurePa[kept->index(k, j, i)], p, 0.01) << k << " " << j << " " << i;
      }
}

TEST(GridReaderCf, HybridWithP0AndSurfacePressureInHectopascals) {
  // The same levels in the "a p0 + b ps" form with ps in hPa: the same heights.
  const std::string dir = testDir();
  CfGrid g;
  g.lat = range(40.0, 2.0, 5);
  g.lon = range(10.0, 2.0, 6);
  g.lev = {1, 2, 3, 4};
  g.levUnits = "1";
  g.levStandardName = "atmosphere_hybrid_sigma_pressure_coordinate";
  g.levFormulaTerms = "ap: hyam b: hybm ps: aps";
  writeCf(dir + "/ap.nc", g, [&](NcTestFile& f) {
    auto ap = f.var("hyam", NC_DOUBLE, {"lev"});
    f.text(ap, "units", "Pa");
    auto b = f.var("hybm", NC_DOUBLE, {"lev"});
    auto ps = f.var("aps", NC_DOUBLE, {"time", "lat", "lon"});
    f.text(ps, "units", "Pa");
    f.put(ap, kAp);
    f.put(b, kB);
    f.put(ps, field3(g, surfacePressure));
  });
  g.levFormulaTerms = "a: hyam b: hybm p0: P0 ps: PS";
  writeCf(dir + "/a_p0.nc", g, [&](NcTestFile& f) {
    auto a = f.var("hyam", NC_DOUBLE, {"lev"});
    auto b = f.var("hybm", NC_DOUBLE, {"lev"});
    auto p0 = f.var("P0", NC_DOUBLE, {});
    f.text(p0, "units", "hPa");
    auto ps = f.var("PS", NC_DOUBLE, {"time", "lat", "lon"});
    f.text(ps, "units", "hPa");
    std::vector<double> aa;
    for (double x : kAp) aa.push_back(x / 50000.0);  // a p0 = ap with p0 = 500 hPa
    f.put(a, aa);
    f.put(b, kB);
    f.put(p0, {500.0});
    f.put(ps, field3(g, [](std::size_t t, std::size_t j, std::size_t i) { return surfacePressure(t, j, i) / 100.0; }));
  });
  auto r1 = readGridVolume(dir + "/ap.nc");
  auto r2 = readGridVolume(dir + "/a_p0.nc");
  ASSERT_TRUE(r1.ok()) << r1.error();
  ASSERT_TRUE(r2.ok()) << r2.error();
  ASSERT_EQ(r1->heightAboveEllipsoidMeters.size(), r2->heightAboveEllipsoidMeters.size());
  for (std::size_t n = 0; n < r1->heightAboveEllipsoidMeters.size(); ++n)
    ASSERT_NEAR(r1->heightAboveEllipsoidMeters[n], r2->heightAboveEllipsoidMeters[n], kHeightTolMeters) << n;
}

TEST(GridReaderCf, HybridWithGeopotentialUsesTheField) {
  const std::string path = testDir() + "/hybrid_z.nc";
  CfGrid g;
  g.lat = range(40.0, 2.0, 3);
  g.lon = range(10.0, 2.0, 4);
  g.lev = {1, 2, 3, 4};
  g.levUnits = "1";
  g.levStandardName = "atmosphere_hybrid_sigma_pressure_coordinate";
  g.levFormulaTerms = "ap: hyam b: hybm ps: aps";
  auto zg = [](std::size_t, std::size_t k, std::size_t j, std::size_t i) {  // gpm, top first
    return 9000.0 - 2500.0 * static_cast<double>(k) + static_cast<double>(j + i);
  };
  writeCf(path, g, [&](NcTestFile& f) {
    auto ap = f.var("hyam", NC_DOUBLE, {"lev"});
    auto b = f.var("hybm", NC_DOUBLE, {"lev"});
    auto ps = f.var("aps", NC_DOUBLE, {"time", "lat", "lon"});
    auto z = f.var("zg", NC_FLOAT, {"time", "lev", "lat", "lon"});
    f.text(z, "standard_name", "geopotential_height");
    f.text(z, "units", "m");
    f.put(ap, kAp);
    f.put(b, kB);
    f.put(ps, field3(g, surfacePressure));
    f.put(z, field4(g, zg));
  });
  auto r = readGridVolume(path);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->heightSource, HeightSource::GeopotentialField);
  EXPECT_FALSE(r->approximateHeights);
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t j = 0; j < r->ny; ++j)
      for (std::size_t i = 0; i < r->nx; ++i)
        ASSERT_NEAR(r->heightMeters(k, j, i),
                    geometricFromGeopotentialHeightMeters(zg(0, 3 - k, j, i), r->latDeg[j]) +
                        geoidAt(r->latDeg[j], r->lonDeg[i]),
                    kHeightTolMeters);
}

TEST(GridReaderCf, SigmaAndHybridHeightCoordinates) {
  const std::string dir = testDir();
  CfGrid g;
  g.lat = range(-10.0, 5.0, 3);
  g.lon = range(100.0, 5.0, 4);
  g.lev = {0.995, 0.9, 0.5, 0.1};  // bottom first
  g.levUnits = "1";
  g.levStandardName = "atmosphere_sigma_coordinate";
  g.levPositive = "down";
  g.levFormulaTerms = "sigma: lev ps: PS ptop: PTOP";
  writeCf(dir + "/sigma.nc", g, [&](NcTestFile& f) {
    auto ps = f.var("PS", NC_DOUBLE, {"time", "lat", "lon"});
    f.text(ps, "units", "Pa");
    auto pt = f.var("PTOP", NC_DOUBLE, {});
    f.text(pt, "units", "Pa");
    f.put(ps, field3(g, surfacePressure));
    f.put(pt, {5000.0});
  });
  auto s = readGridVolume(dir + "/sigma.nc");
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->verticalKind, VerticalKind::Sigma);
  EXPECT_EQ(s->fileLevelStep, 1);
  for (std::size_t k = 0; k < 4; ++k) {
    const double p = 5000.0 + g.lev[k] * (surfacePressure(0, 1, 2) - 5000.0);
    EXPECT_NEAR(s->heightMeters(k, 1, 2),
                geometricFromGeopotentialHeightMeters(standardAtmosphereGeopotentialHeightMeters(p), s->latDeg[1]) +
                    geoidAt(s->latDeg[1], s->lonDeg[2]),
                kHeightTolMeters);
  }

  // Hybrid height: z = a + b orog, above the geoid.
  const std::vector<double> a = {20, 500, 2000, 8000}, b = {0.99, 0.8, 0.4, 0.0};
  g.lev = a;
  g.levUnits = "m";
  g.levStandardName = "atmosphere_hybrid_height_coordinate";
  g.levPositive = "up";
  g.levFormulaTerms = "a: lev b: bcoef orog: orog";
  auto orog = [](std::size_t, std::size_t j, std::size_t i) {
    return 300.0 + 100.0 * static_cast<double>(j) + 10.0 * static_cast<double>(i);
  };
  writeCf(dir + "/hybrid_height.nc", g, [&](NcTestFile& f) {
    auto bv = f.var("bcoef", NC_DOUBLE, {"lev"});
    auto ov = f.var("orog", NC_FLOAT, {"lat", "lon"});
    f.text(ov, "units", "m");
    f.put(bv, b);
    CfGrid one = g;
    one.times = 1;
    f.put(ov, field3(one, orog));
  });
  auto h = readGridVolume(dir + "/hybrid_height.nc");
  ASSERT_TRUE(h.ok()) << h.error();
  EXPECT_EQ(h->verticalKind, VerticalKind::HybridHeight);
  EXPECT_FALSE(h->approximateHeights);
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t j = 0; j < h->ny; ++j)
      for (std::size_t i = 0; i < h->nx; ++i)
        ASSERT_NEAR(h->heightMeters(k, j, i), a[k] + b[k] * orog(0, j, i) + geoidAt(h->latDeg[j], h->lonDeg[i]),
                    kHeightTolMeters);
}

TEST(GridReaderCf, HeightAboveGroundAddsTheSurfaceAltitudeOrSaysItIsMissing) {
  const std::string dir = testDir();
  CfGrid g;
  g.lat = range(35.0, 0.5, 4);
  g.lon = range(250.0, 0.5, 5);  // 0..360 regional
  g.lev = {50, 500, 2000, 6000};
  g.levUnits = "m";
  g.levStandardName = "height";
  g.levPositive = "up";
  auto orog = [](std::size_t, std::size_t j, std::size_t i) { return 1000.0 + 50.0 * static_cast<double>(j * 5 + i); };
  writeCf(dir + "/agl.nc", g, [&](NcTestFile& f) {
    auto ov = f.var("hsurf", NC_FLOAT, {"lat", "lon"});
    f.text(ov, "standard_name", "surface_altitude");
    f.text(ov, "units", "m");
    CfGrid one = g;
    one.times = 1;
    f.put(ov, field3(one, orog));
  });
  auto r = readGridVolume(dir + "/agl.nc");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->verticalKind, VerticalKind::HeightAboveGround);
  EXPECT_FALSE(r->approximateHeights);
  EXPECT_DOUBLE_EQ(r->lonDeg.front(), -110.0) << "0..360 regional longitudes come out in -180..180";
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t j = 0; j < r->ny; ++j)
      for (std::size_t i = 0; i < r->nx; ++i)
        ASSERT_NEAR(r->heightMeters(k, j, i), g.lev[k] + orog(0, j, i) + geoidAt(r->latDeg[j], r->lonDeg[i]),
                    kHeightTolMeters);
  writeCf(dir + "/agl_no_orog.nc", g);
  auto a = readGridVolume(dir + "/agl_no_orog.nc");
  ASSERT_TRUE(a.ok()) << a.error();
  EXPECT_TRUE(a->approximateHeights);
  EXPECT_NE(a->heightNote.find("no surface altitude"), std::string::npos) << a->heightNote;
  // Lengths whose datum nobody states: taken as above sea level, flagged.
  g.levStandardName = "";
  g.levLongName = "level height";
  writeCf(dir + "/no_datum.nc", g);
  auto d = readGridVolume(dir + "/no_datum.nc");
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_TRUE(d->approximateHeights);
  EXPECT_EQ(d->verticalKind, VerticalKind::HeightAboveSeaLevel);
}

// ---------------------------------------------------------------- values, groups, curvilinear, time

TEST(GridReaderCf, PackedValuesWithFillMissingAndValidRange) {
  const std::string path = testDir() + "/packed.nc";
  CfGrid g;
  g.lat = range(0.0, 1.0, 4);
  g.lon = range(0.0, 1.0, 5);
  g.lev = {1000, 500};
  g.times = 1;
  auto raw = [](std::size_t, std::size_t k, std::size_t j, std::size_t i) -> double {
    if (k == 0 && j == 1 && i == 1) return -999;   // _FillValue
    if (k == 0 && j == 2 && i == 2) return -998;   // missing_value
    if (k == 1 && j == 3 && i == 4) return 31000;  // above valid_max
    return static_cast<double>(100 * k + 10 * j + i);
  };
  writeCf(path, g, [&](NcTestFile& f) {
    auto p = f.var("packed", NC_SHORT, {"time", "lev", "lat", "lon"});
    f.number(p, "scale_factor", NC_FLOAT, {0.5});
    f.number(p, "add_offset", NC_FLOAT, {100.0});
    f.number(p, "_FillValue", NC_SHORT, {-999});
    f.number(p, "missing_value", NC_SHORT, {-998});
    f.number(p, "valid_max", NC_SHORT, {30000});
    f.text(p, "units", "K");
    auto u = f.var("ubyte", NC_BYTE, {"time", "lev", "lat", "lon"});
    f.text(u, "_Unsigned", "true");
    f.number(u, "_FillValue", NC_BYTE, {-1});  // 255 as unsigned
    f.put(p, field4(g, raw));
    f.put(u, field4(g, [](std::size_t, std::size_t k, std::size_t j, std::size_t i) -> double {
            if (j == 0 && i == 0) return -1;  // fill
            return k == 1 ? -56.0 : 100.0;    // -56 stored = 200 unsigned
          }));
  });
  GridReadOptions o;
  o.variable = "packed";
  auto r = readGridVolume(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t j = 0; j < 4; ++j)
      for (std::size_t i = 0; i < 5; ++i) {
        const double x = raw(0, k, j, i);  // 1000 hPa first: file level 0 is the bottom
        if (x == -999 || x == -998 || x > 30000) EXPECT_TRUE(std::isnan(r->value(k, j, i))) << k << j << i;
        else EXPECT_EQ(r->value(k, j, i), static_cast<float>(x * 0.5 + 100.0)) << k << j << i;
      }
  EXPECT_EQ(r->valueMin, 100.0f);
  EXPECT_EQ(r->valueMax, static_cast<float>(133 * 0.5 + 100.0)) << "raw 134 is above valid_max (31000 stored)";
  o.variable = "ubyte";
  auto u = readGridVolume(path, o);
  ASSERT_TRUE(u.ok()) << u.error();
  EXPECT_TRUE(std::isnan(u->value(0, 0, 0)));
  EXPECT_EQ(u->value(0, 1, 1), 100.0f) << "the bottom level is file level 0";
  EXPECT_EQ(u->value(1, 1, 1), 200.0f) << "_Unsigned: stored -56 is 200";
}

TEST(GridReaderCf, VariableInANetcdf4Group) {
  const std::string path = testDir() + "/groups.nc";
  CfGrid g;
  g.lat = range(0.0, 1.0, 3);
  g.lon = range(0.0, 1.0, 4);
  g.group = "forecast/member0";
  writeCf(path, g);
  for (const std::string& name :
       {std::string("/forecast/member0/ta"), std::string("forecast/member0/ta"), std::string("ta"), std::string()}) {
    GridReadOptions o;
    o.variable = name;
    auto r = readGridVolume(path, o);
    ASSERT_TRUE(r.ok()) << name << ": " << r.error();
    EXPECT_EQ(r->variable, "/forecast/member0/ta") << name;
    EXPECT_EQ(r->value(0, 2, 3), static_cast<float>(code(0, 0, 2, 3)));
  }
  auto info = describeGridFile(path);
  ASSERT_TRUE(info.ok()) << info.error();
  EXPECT_EQ(info->variable, "/forecast/member0/ta");
  // A second `ta` elsewhere makes the short name ambiguous.
  const std::string two = testDir() + "/two.nc";
  writeCf(two, g, [&](NcTestFile& f) {
    const int other = f.group("analysis");
    f.var("ta", NC_FLOAT, {"time", "lev", "lat", "lon"}, other);
  });
  GridReadOptions o;
  o.variable = "ta";
  auto amb = readGridVolume(two, o);
  ASSERT_FALSE(amb.ok());
  EXPECT_TRUE(mentions(amb.error(), {two, "ambiguous", "/analysis/ta", "/forecast/member0/ta"})) << amb.error();
}

TEST(GridReaderCf, CurvilinearCoordinatesAcrossTheAntimeridian) {
  const std::string path = testDir() + "/curvilinear.nc";
  const std::size_t ny = 6, nx = 8;
  NcTestFile f(path);
  f.dim("time", 1);
  f.dim("lev", 3);
  f.dim("y", ny);
  f.dim("x", nx);
  auto vz = f.var("lev", NC_DOUBLE, {"lev"});
  f.text(vz, "units", "hPa");
  auto la = f.var("lat", NC_DOUBLE, {"y", "x"});
  f.text(la, "units", "degrees_north");
  auto lo = f.var("lon", NC_DOUBLE, {"y", "x"});
  f.text(lo, "units", "degrees_east");
  auto v = f.var("q", NC_FLOAT, {"time", "lev", "y", "x"});
  f.text(v, "coordinates", "lon lat");
  std::vector<double> lat, lon, q;
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      lat.push_back(50.0 + 1.0 * static_cast<double>(j) + 0.2 * static_cast<double>(i));  // a rotated grid
      double x = 176.0 + 1.0 * static_cast<double>(i) - 0.3 * static_cast<double>(j);
      if (x >= 180.0) x -= 360.0;  // the file jumps from 179.x to -179.x
      lon.push_back(x);
    }
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) q.push_back(code(0, k, j, i));
  f.put(vz, {1000, 850, 700});
  f.put(la, lat);
  f.put(lo, lon);
  f.put(v, q);
  f.close();
  auto r = readGridVolume(path);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(r->curvilinear);
  ASSERT_EQ(r->nx, nx);
  ASSERT_EQ(r->ny, ny);
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      EXPECT_EQ(r->latDegAt(j, i), lat[j * nx + i]);
      const double expected = lon[j * nx + i] < 0 ? lon[j * nx + i] + 360.0 : lon[j * nx + i];
      EXPECT_NEAR(r->lonDegAt(j, i), expected, 1e-9) << "continuous across 180";
      EXPECT_EQ(r->value(2, j, i), static_cast<float>(code(0, 2, j, i)));
    }
  // A crop keeps the index box of the points inside, one more on each side.
  GridReadOptions o;
  o.crop.southDeg = 52.5;
  o.crop.northDeg = 53.5;
  o.crop.westDeg = 179.5;
  o.crop.eastDeg = -179.0;
  auto c = readGridVolume(path, o);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_LT(c->nx * c->ny, nx * ny);
  for (std::size_t j = 0; j < c->ny; ++j)
    for (std::size_t i = 0; i < c->nx; ++i) {
      const std::size_t jf = c->fileFirstRow + j, xf = c->fileFirstColumn + i;
      EXPECT_EQ(c->value(0, j, i), static_cast<float>(code(0, 0, jf, xf)));
    }
}

TEST(GridReaderCf, TimeAxisCalendarsAndSelectionByTime) {
  const std::string path = testDir() + "/360day.nc";
  CfGrid g;
  g.lat = range(0.0, 1.0, 2);
  g.lon = range(0.0, 1.0, 2);
  g.times = 3;
  g.timeUnits = "days since 2001-01-01";
  g.calendar = "360_day";
  g.timeValues = {0, 59, 60};
  writeCf(path, g);
  GridReadOptions o;
  o.timeIso8601 = "2001-02-30 00:00";
  auto r = readGridVolume(path, o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->timeIndex, 1u);
  EXPECT_EQ(r->validTime, "2001-02-30T00:00:00Z");
  EXPECT_EQ(r->times,
            (std::vector<std::string>{"2001-01-01T00:00:00Z", "2001-02-30T00:00:00Z", "2001-03-01T00:00:00Z"}));
  EXPECT_EQ(r->value(0, 0, 0), static_cast<float>(code(1, 0, 0, 0)));
  o.timeIso8601 = "2001-02-28T00:00:00Z";
  auto missing = readGridVolume(path, o);
  ASSERT_FALSE(missing.ok());
  EXPECT_TRUE(mentions(missing.error(), {path, "'/ta'", "2001-02-28T00:00:00Z", "3 steps"})) << missing.error();
  o = GridReadOptions{};
  o.timeIndex = 3;
  auto beyond = readGridVolume(path, o);
  ASSERT_FALSE(beyond.ok());
  EXPECT_TRUE(mentions(beyond.error(), {path, "'/ta'", "time index 3"})) << beyond.error();
}

TEST(GridReaderCf, DescribeReadsCoordinatesNotValues) {
  const std::string path = testDir() + "/global.nc";
  CfGrid g;
  writeCf(path, g);
  auto info = describeGridFile(path);
  ASSERT_TRUE(info.ok()) << info.error();
  EXPECT_EQ(info->variable, "/ta");
  EXPECT_EQ(info->nx, 36u);
  EXPECT_EQ(info->ny, 13u);
  EXPECT_EQ(info->nz, 5u);
  EXPECT_EQ(info->southDeg, -60.0);
  EXPECT_EQ(info->northDeg, 60.0);
  EXPECT_TRUE(info->wrapsLongitude);
  EXPECT_TRUE(info->approximateHeights);
  EXPECT_EQ(info->times.size(), 2u);
  EXPECT_EQ(info->timeUnits, "hours since 2001-01-01 00:00:00");
  EXPECT_EQ(info->calendar, "standard");
  // 1000 hPa is at 111 m' in the standard atmosphere, 300 hPa at 9164 m'; the geoid (-106..+85 m)
  // and geometric height (< 60 m at 9 km) move them a little.
  EXPECT_NEAR(info->heightMinMeters, 111.0, 110.0);
  EXPECT_NEAR(info->heightMaxMeters, 9164.0, 160.0);
  // Only coordinates: far less than the 2 x 5 x 13 x 36 floats of `ta`.
  EXPECT_LT(info->bytesRead, 2u * 5 * 13 * 36 * 4);
  bool found = false;
  for (const auto& v : info->variables)
    if (v.name == "/ta") {
      found = true;
      EXPECT_TRUE(v.onGrid);
      EXPECT_EQ(v.units, "K");
    } else {
      EXPECT_FALSE(v.onGrid) << v.name;
    }
  EXPECT_TRUE(found);
  const std::string json = describeGridJson(*info);
  EXPECT_NE(json.find("\"kind\": \"grid\""), std::string::npos);
  EXPECT_NE(json.find("\"approximate\": true"), std::string::npos);
  const std::string text = describeGridText(*info);
  EXPECT_NE(text.find("APPROXIMATE"), std::string::npos) << text;
}

TEST(GridReaderCf, GridFilesAreToldFromRadarFilesByContent) {
  const std::string dir = testDir();
  CfGrid g;
  g.lat = range(0.0, 1.0, 2);
  g.lon = range(0.0, 1.0, 2);
  writeCf(dir + "/grid.nc", g);
  EXPECT_TRUE(isGridFile(dir + "/grid.nc"));
  SyntheticRadarOptions radar;
  radar.elevationsDeg = {0.5, 1.5};
  radar.raysPerSweep = 36;
  radar.maxRangeMeters = 20000;
  ASSERT_TRUE(writeSyntheticCfRadial(dir + "/radar.nc", radar).ok());
  EXPECT_FALSE(isGridFile(dir + "/radar.nc"));
  std::ofstream(dir + "/text.nc") << "not a netCDF file\n";
  EXPECT_FALSE(isGridFile(dir + "/text.nc"));
  EXPECT_FALSE(isGridFile(dir + "/missing.nc"));
}
