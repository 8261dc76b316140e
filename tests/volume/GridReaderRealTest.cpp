// The forecast-grid reader on the real files of ../shared/data/grids (label realdata):
//   wrf_python_ci_test_file.nc  WRF V3.8.1, 4 times, 14 eta levels, 48 x 48 Mercator, staggered C grid
//   rectilinear_grid_3D.nc      ECHAM5 T63 Gaussian 192 x 96, 17 pressure levels, no geopotential
// The references are computed here from the files with netCDF-C directly (or read by ncdump, an
// independent reader, when it is installed), not through the reader under test.
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/GridReader.h>

#include <gtest/gtest.h>
#include <netcdf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using namespace atmoglobe::volume;

namespace {

std::string wrfPath() { return atmoglobe_test::testDataPath("grids/wrf_python_ci_test_file.nc"); }
std::string echamPath() { return atmoglobe_test::testDataPath("grids/rectilinear_grid_3D.nc"); }

/// A whole float variable, or the hyperslab (start, count), read with netCDF-C.
std::vector<float> ncRead(const std::string& path, const char* name, std::vector<std::size_t> start = {},
                          std::vector<std::size_t> count = {}) {
  int nc = -1, id = -1, ndims = 0;
  EXPECT_EQ(nc_open(path.c_str(), NC_NOWRITE, &nc), NC_NOERR);
  EXPECT_EQ(nc_inq_varid(nc, name, &id), NC_NOERR) << name;
  nc_inq_varndims(nc, id, &ndims);
  if (start.empty()) {
    std::vector<int> dims(static_cast<std::size_t>(ndims));
    nc_inq_vardimid(nc, id, dims.data());
    for (int d : dims) {
      std::size_t len = 0;
      nc_inq_dimlen(nc, d, &len);
      start.push_back(0);
      count.push_back(len);
    }
  }
  std::size_t n = 1;
  for (std::size_t c : count) n *= c;
  std::vector<float> out(n);
  EXPECT_EQ(nc_get_vara_float(nc, id, start.data(), count.data(), out.data()), NC_NOERR) << name;
  nc_close(nc);
  return out;
}

double geoid(double latDeg, double lonDeg) {
  const auto& g = defaultEgm96Grid();
  EXPECT_TRUE(g.ok());
  return g ? g->undulationMeters(latDeg, lonDeg) : 0.0;
}

bool haveNcdump() { return std::system("command -v ncdump > /dev/null 2>&1") == 0; }

/// Values of `var` printed by `ncdump -v VAR -f c -p 9,17 FILE` (9 digits: a float read back
/// exactly), by C index "(t,k,j,i)".
std::map<std::string, double> ncdumpValues(const std::string& path, const std::string& var) {
  std::map<std::string, double> out;
  const std::string cmd = "ncdump -v " + var + " -f c -p 9,17 '" + path + "'";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  if (!pipe) return out;
  const std::string marker = "// " + var + "(";
  char line[4096];
  while (std::fgets(line, sizeof line, pipe.get())) {
    const std::string s(line);
    const auto m = s.find(marker);
    if (m == std::string::npos) continue;
    const auto close = s.find(')', m);
    std::istringstream is(s.substr(0, m));
    double v = 0;
    is >> v;
    out[s.substr(m + marker.size() - 1, close - (m + marker.size() - 1) + 1)] = v;
  }
  return out;
}

std::string idx(std::size_t t, std::size_t k, std::size_t j, std::size_t i) {
  return "(" + std::to_string(t) + "," + std::to_string(k) + "," + std::to_string(j) + "," + std::to_string(i) + ")";
}

}  // namespace

TEST(GridReaderReal, WrfEtaHeightsMatchAnIndependentComputationFromPhAndPhb) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  GridReadOptions o;
  o.variable = "QVAPOR";
  o.timeIndex = 2;
  auto r = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  const GridVolume& g = *r;
  ASSERT_EQ(g.nx, 48u);
  ASSERT_EQ(g.ny, 48u);
  ASSERT_EQ(g.nz, 14u);
  EXPECT_TRUE(g.curvilinear);
  EXPECT_EQ(g.verticalKind, VerticalKind::WrfEta);
  EXPECT_EQ(g.heightSource, HeightSource::WrfGeopotential);
  EXPECT_FALSE(g.approximateHeights);
  const std::vector<float> ph = ncRead(wrfPath(), "PH", {2, 0, 0, 0}, {1, 15, 48, 48});
  const std::vector<float> phb = ncRead(wrfPath(), "PHB", {2, 0, 0, 0}, {1, 15, 48, 48});
  const std::vector<float> lat = ncRead(wrfPath(), "XLAT", {2, 0, 0}, {1, 48, 48});
  const std::vector<float> lon = ncRead(wrfPath(), "XLONG", {2, 0, 0}, {1, 48, 48});
  double maxError = 0;
  for (std::size_t k = 0; k < 14; ++k)
    for (std::size_t j = 0; j < 48; ++j)
      for (std::size_t i = 0; i < 48; ++i) {
        const std::size_t c = j * 48 + i;
        // z = (PH + PHB) / 9.81 on W levels k and k+1 (REFERENCE.md section 4), mean = mass level.
        const double zw0 = (static_cast<double>(ph[k * 2304 + c]) + phb[k * 2304 + c]) / 9.81;
        const double zw1 = (static_cast<double>(ph[(k + 1) * 2304 + c]) + phb[(k + 1) * 2304 + c]) / 9.81;
        const double expected = 0.5 * (zw0 + zw1) + geoid(lat[c], lon[c]);
        maxError = std::max(maxError, std::fabs(g.heightMeters(k, j, i) - expected));
      }
  // Heights up to ~6 km stored as float: 0.5 mm spacing; 1 mm bounds the rounding.
  EXPECT_LT(maxError, 1e-3);
  // Monotonic with the right sign: strictly up, the lowest level within 100 m of the sea
  // surface (the domain is the Gulf of Mexico; the geoid there is about -30..0 m).
  for (std::size_t j = 0; j < 48; ++j)
    for (std::size_t i = 0; i < 48; ++i) {
      EXPECT_GT(g.heightMeters(0, j, i), -60.0f);
      EXPECT_LT(g.heightMeters(0, j, i), 100.0f);
      for (std::size_t k = 1; k < 14; ++k) ASSERT_GT(g.heightMeters(k, j, i), g.heightMeters(k - 1, j, i));
    }
}

TEST(GridReaderReal, WrfLowestWLevelIsTheTerrainHeight) {
  // Why (PH+PHB)/9.81 is read as height above sea level: at the surface W level it equals the
  // terrain height HGT (WRF sets PHB = g HGT there). Relative 1e-6: float rounding of both.
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  const std::vector<float> ph = ncRead(wrfPath(), "PH", {0, 0, 0, 0}, {1, 1, 48, 48});
  const std::vector<float> phb = ncRead(wrfPath(), "PHB", {0, 0, 0, 0}, {1, 1, 48, 48});
  const std::vector<float> hgt = ncRead(wrfPath(), "HGT", {0, 0, 0}, {1, 48, 48});
  int land = 0;
  for (std::size_t c = 0; c < hgt.size(); ++c) {
    const double z = (static_cast<double>(ph[c]) + phb[c]) / 9.81;
    EXPECT_NEAR(z, hgt[c], 1e-6 * std::max(1.0, static_cast<double>(hgt[c])) + 1e-9) << c;
    land += hgt[c] > 0;
  }
  EXPECT_GT(land, 0) << "some columns have terrain above 0, so the check is not only 0 = 0";
}

TEST(GridReaderReal, WrfCornersAreAtXlatXlong) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  auto r = readGridVolume(wrfPath());
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->variable, "/QCLOUD") << "the default variable";
  const std::vector<float> lat = ncRead(wrfPath(), "XLAT", {0, 0, 0}, {1, 48, 48});
  const std::vector<float> lon = ncRead(wrfPath(), "XLONG", {0, 0, 0}, {1, 48, 48});
  for (std::size_t j : {0u, 47u})
    for (std::size_t i : {0u, 47u}) {
      EXPECT_EQ(r->latDegAt(j, i), static_cast<double>(lat[j * 48 + i])) << j << " " << i;
      EXPECT_EQ(r->lonDegAt(j, i), static_cast<double>(lon[j * 48 + i])) << j << " " << i;
    }
  // The Gulf of Mexico nest: south-west corner near 21.8 N 91.7 W.
  EXPECT_NEAR(r->latDegAt(0, 0), 21.8, 0.1);
  EXPECT_NEAR(r->lonDegAt(0, 0), -91.65, 0.1);
}

TEST(GridReaderReal, WrfStaggeredVariablesAreAveragedToMassPoints) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  struct Case {
    const char* name;
    int axis;
    std::vector<std::size_t> count;
  };
  // U is staggered in x (49 columns), V in y (49 rows), W in z (15 levels).
  for (const Case& c : {Case{"U", 3, {1, 14, 48, 49}}, Case{"V", 2, {1, 14, 49, 48}}, Case{"W", 1, {1, 15, 48, 48}}}) {
    GridReadOptions o;
    o.variable = c.name;
    o.timeIndex = 1;
    auto r = readGridVolume(wrfPath(), o);
    ASSERT_TRUE(r.ok()) << c.name << ": " << r.error();
    ASSERT_EQ(r->nx, 48u);
    ASSERT_EQ(r->ny, 48u);
    ASSERT_EQ(r->nz, 14u);
    const std::vector<float> raw = ncRead(wrfPath(), c.name, {1, 0, 0, 0}, c.count);
    const std::size_t nxs = c.count[3], nys = c.count[2];
    auto at = [&](std::size_t k, std::size_t j, std::size_t i) {
      return static_cast<double>(raw[(k * nys + j) * nxs + i]);
    };
    for (std::size_t k = 0; k < 14; ++k)
      for (std::size_t j = 0; j < 48; ++j)
        for (std::size_t i = 0; i < 48; ++i) {
          const double b = c.axis == 3 ? at(k, j, i + 1) : c.axis == 2 ? at(k, j + 1, i) : at(k + 1, j, i);
          ASSERT_FLOAT_EQ(r->value(k, j, i), static_cast<float>(0.5 * (at(k, j, i) + b))) << c.name << k << j << i;
        }
  }
}

TEST(GridReaderReal, WrfValuesAgreeWithNcdump) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  if (!haveNcdump()) GTEST_SKIP() << "ncdump not installed (Debian package netcdf-bin)";
  const auto dump = ncdumpValues(wrfPath(), "QVAPOR");
  ASSERT_EQ(dump.size(), 4u * 14 * 48 * 48);
  GridReadOptions o;
  o.variable = "QVAPOR";
  o.timeIndex = 3;
  auto r = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  // WRF rows run south to north and levels bottom up: the volume keeps the file's indices.
  for (auto [k, j, i] : {std::array<std::size_t, 3>{0, 0, 0}, {0, 47, 47}, {13, 0, 47}, {7, 23, 31}, {13, 47, 0}})
    EXPECT_EQ(r->value(k, j, i), static_cast<float>(dump.at(idx(3, k, j, i)))) << k << " " << j << " " << i;
}

TEST(GridReaderReal, WrfTimesAndSelectionByTime) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  GridReadOptions o;
  o.timeIso8601 = "2005-08-28T18:00:00Z";
  auto r = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->times, (std::vector<std::string>{"2005-08-28T12:00:00Z", "2005-08-28T15:00:00Z", "2005-08-28T18:00:00Z",
                                                "2005-08-28T21:00:00Z"}));
  EXPECT_EQ(r->timeIndex, 2u);
  EXPECT_EQ(r->validTime, "2005-08-28T18:00:00Z");
}

TEST(GridReaderReal, WrfCropReadsFarLessThanTheVariable) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  // Whole QCLOUD: 4 x 14 x 48 x 48 floats = 516,096 bytes.
  const std::uint64_t wholeVariable = 4ull * 14 * 48 * 48 * 4;
  GridReadOptions o;
  o.timeIndex = 1;
  o.crop.southDeg = 23.0;
  o.crop.northDeg = 23.5;
  o.crop.westDeg = -90.0;
  o.crop.eastDeg = -89.5;
  o.crop.levelCount = 5;
  auto r = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_LE(r->nx, 9u);
  EXPECT_LE(r->ny, 9u);
  EXPECT_EQ(r->nz, 5u);
  // The crop: QCLOUD, PH and PHB over its columns (a few kB) + the whole XLAT/XLONG plane of the
  // step (2 x 9216 bytes, needed to find the columns) + Times (76 bytes): under a tenth.
  EXPECT_LT(r->bytesRead, wholeVariable / 10) << r->bytesRead;
  // The crop's values are the full read's at the same file indices, for a staggered variable too.
  for (const char* name : {"QCLOUD", "U", "V", "W"}) {
    GridReadOptions all;
    all.timeIndex = 1;
    all.variable = name;
    auto full = readGridVolume(wrfPath(), all);
    ASSERT_TRUE(full.ok());
    o.variable = name;
    auto c = readGridVolume(wrfPath(), o);
    ASSERT_TRUE(c.ok()) << c.error();
    for (std::size_t k = 0; k < c->nz; ++k)
      for (std::size_t j = 0; j < c->ny; ++j)
        for (std::size_t i = 0; i < c->nx; ++i) {
          ASSERT_EQ(c->value(k, j, i), full->value(k, c->fileFirstRow + j, c->fileFirstColumn + i)) << name;
          ASSERT_EQ(c->heightMeters(k, j, i), full->heightMeters(k, c->fileFirstRow + j, c->fileFirstColumn + i));
        }
  }
}

TEST(GridReaderReal, WrfDescribe) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  auto info = describeGridFile(wrfPath());
  ASSERT_TRUE(info.ok()) << info.error();
  EXPECT_NE(info->format.find("WRF"), std::string::npos);
  EXPECT_NE(info->conventions.find("WRF V3.8.1"), std::string::npos);
  EXPECT_EQ(info->nx, 48u);
  EXPECT_EQ(info->nz, 14u);
  EXPECT_EQ(info->zDimension, "bottom_top");
  EXPECT_EQ(info->times.size(), 4u);
  // 10 km Mercator grid true at the equator, at ~24 N: 10 km x cos(24 deg) = 9.1 km on the ground.
  EXPECT_NEAR(info->meanSpacingKm, 10.0 * std::cos(24.0 * 3.14159265358979 / 180.0), 0.1);
  // The 14 lowest of 29 eta levels reach ~488 hPa: about 5.6 km.
  EXPECT_GT(info->heightMaxMeters, 5000.0);
  EXPECT_LT(info->heightMaxMeters, 6500.0);
  int onGrid = 0;
  for (const auto& v : info->variables) onGrid += v.onGrid;
  EXPECT_EQ(onGrid, 11) << "U V W PH PHB T P PB QVAPOR QCLOUD QRAIN";
}

TEST(GridReaderReal, EchamPressureLevelsAreApproximateAndMonotonic) {
  SKIP_WITHOUT_TEST_DATA(echamPath());
  GridReadOptions o;
  o.variable = "t";
  auto r = readGridVolume(echamPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  const GridVolume& g = *r;
  EXPECT_EQ(g.nx, 192u);
  EXPECT_EQ(g.ny, 96u);
  EXPECT_EQ(g.nz, 17u);
  EXPECT_EQ(g.verticalKind, VerticalKind::Pressure);
  EXPECT_EQ(g.heightSource, HeightSource::StandardAtmosphere);
  EXPECT_TRUE(g.approximateHeights);
  EXPECT_NE(g.heightNote.find("APPROXIMATE"), std::string::npos);
  EXPECT_TRUE(g.wrapsLongitude);
  EXPECT_EQ(g.levelValues.front(), 100000.0);
  EXPECT_EQ(g.levelValues.back(), 1000.0);
  EXPECT_LT(g.latDeg.front(), g.latDeg.back()) << "rows ascend (the file runs north to south)";
  EXPECT_EQ(g.validTime, "2001-01-01T00:00:00Z");
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i)
      for (std::size_t k = 1; k < g.nz; ++k) ASSERT_GT(g.heightMeters(k, j, i), g.heightMeters(k - 1, j, i));
  // 10 hPa in the standard atmosphere: 31 km (USSA 1976: 31,055 m'); geometric and geoid add < 300 m.
  EXPECT_NEAR(g.heightMeters(16, 48, 0), 31055.0, 300.0);
  // Temperatures are Kelvin of the real atmosphere.
  EXPECT_GT(g.valueMin, 150.0f);
  EXPECT_LT(g.valueMax, 330.0f);
}

TEST(GridReaderReal, EchamValuesAgreeWithNcdump) {
  SKIP_WITHOUT_TEST_DATA(echamPath());
  if (!haveNcdump()) GTEST_SKIP() << "ncdump not installed (Debian package netcdf-bin)";
  const auto dump = ncdumpValues(echamPath(), "t");
  ASSERT_EQ(dump.size(), 17u * 96 * 192);
  GridReadOptions o;
  o.variable = "t";
  auto r = readGridVolume(echamPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  // Output row j is file row 95 - j (latitudes north to south in the file); levels keep their
  // order (1000 hPa first is already bottom first); columns keep theirs (-180 .. 178.125).
  for (auto [k, j, i] : {std::array<std::size_t, 3>{0, 0, 0}, {0, 95, 191}, {16, 10, 100}, {8, 48, 96}, {3, 70, 5}})
    EXPECT_EQ(r->value(k, j, i), static_cast<float>(dump.at(idx(0, k, 95 - j, i)))) << k << " " << j << " " << i;
}

TEST(GridReaderReal, EchamCropAcrossTheAntimeridian) {
  SKIP_WITHOUT_TEST_DATA(echamPath());
  GridReadOptions o;
  o.variable = "t";
  o.crop.westDeg = 175.0;
  o.crop.eastDeg = -175.0;
  o.crop.southDeg = -10.0;
  o.crop.northDeg = 10.0;
  auto r = readGridVolume(echamPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_FALSE(r->wrapsLongitude);
  // Columns every 1.875 deg: 174.375 .. 185.625 (= -174.375) continuous, 7 columns.
  ASSERT_EQ(r->nx, 7u);
  EXPECT_DOUBLE_EQ(r->lonDeg.front(), 174.375);
  EXPECT_DOUBLE_EQ(r->lonDeg.back(), 185.625);
  for (std::size_t i = 1; i < r->nx; ++i) EXPECT_NEAR(r->lonDeg[i] - r->lonDeg[i - 1], 1.875, 1e-9);
  // File columns 189, 190, 191, 0, 1, 2, 3 (-180 is column 0).
  GridReadOptions all;
  all.variable = "t";
  auto full = readGridVolume(echamPath(), all);
  ASSERT_TRUE(full.ok());
  const std::size_t cols[] = {189, 190, 191, 0, 1, 2, 3};
  const std::size_t row = static_cast<std::size_t>(std::find(full->latDeg.begin(), full->latDeg.end(), r->latDeg[0]) -
                                                   full->latDeg.begin());
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(r->value(5, 0, i), full->value(5, row, cols[i])) << i;
  EXPECT_LT(r->bytesRead, full->bytesRead / 10);
}

TEST(GridReaderReal, TruncatedRealFiles) {
  SKIP_WITHOUT_TEST_DATA(wrfPath(), echamPath());
  const std::string dir = atmoglobe_test::freshTestDir("grid_real");
  for (const std::string& src : {wrfPath(), echamPath()}) {
    const auto size = std::filesystem::file_size(src);
    for (double fraction : {0.01, 0.2, 0.5, 0.8}) {
      const std::string cut = dir + "/cut_" + std::to_string(static_cast<int>(fraction * 100)) + "_" +
                              std::filesystem::path(src).filename().string();
      std::filesystem::copy_file(src, cut, std::filesystem::copy_options::overwrite_existing);
      std::filesystem::resize_file(cut, static_cast<std::uintmax_t>(static_cast<double>(size) * fraction));
      for (std::size_t t : {0u, 3u}) {
        GridReadOptions o;
        o.timeIndex = t;
        auto r = readGridVolume(cut, o);
        // A classic file keeps its variables one after the other: a cut may leave the first
        // one whole and readable. Any failure names the file; 1 % of a file never reads.
        if (!r.ok()) {
          EXPECT_EQ(r.error().rfind(cut, 0), 0u) << r.error();
        }
        if (fraction <= 0.01) {
          EXPECT_FALSE(r.ok()) << cut;
        }
      }
      // describe reads only coordinates, which a classic file keeps at its start: it may succeed.
      auto d = describeGridFile(cut);
      if (!d.ok()) {
        EXPECT_EQ(d.error().rfind(cut, 0), 0u) << d.error();
      }
    }
  }
}

TEST(GridReaderReal, WrfTemperatureAndGeopotentialAreMadeFromTheModelsPerturbations) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  GridReadOptions o;
  o.timeIndex = 1;
  o.variable = "tk";
  auto tk = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(tk.ok()) << tk.error();
  o.variable = "z";
  auto z = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(z.ok()) << z.error();
  EXPECT_EQ(tk->units, "K");
  EXPECT_EQ(tk->standardName, "air_temperature");
  EXPECT_EQ(z->units, "m2 s-2");
  EXPECT_EQ(z->standardName, "geopotential");
  EXPECT_FALSE(tk->vectorsRelativeToGrid);
  // `info` lists them and describes them on the fields they are made from.
  auto described = describeGridFile(wrfPath(), "tk");
  ASSERT_TRUE(described.ok()) << described.error();
  EXPECT_EQ(described->variable, "/tk");
  EXPECT_EQ(described->nz, 14u);
  const std::string text = describeGridText(*described);
  EXPECT_NE(text.find("* tk  (made from T, P, PB) [K]"), std::string::npos) << text;
  EXPECT_NE(text.find("* z  (made from PH, PHB) [m2 s-2]"), std::string::npos) << text;
  const std::vector<float> t = ncRead(wrfPath(), "T", {1, 0, 0, 0}, {1, 14, 48, 48});
  const std::vector<float> p = ncRead(wrfPath(), "P", {1, 0, 0, 0}, {1, 14, 48, 48});
  const std::vector<float> pb = ncRead(wrfPath(), "PB", {1, 0, 0, 0}, {1, 14, 48, 48});
  const std::vector<float> ph = ncRead(wrfPath(), "PH", {1, 0, 0, 0}, {1, 15, 48, 48});
  const std::vector<float> phb = ncRead(wrfPath(), "PHB", {1, 0, 0, 0}, {1, 15, 48, 48});
  double tMax = 0, zMax = 0;
  for (std::size_t k = 0; k < 14; ++k)
    for (std::size_t c = 0; c < 2304; ++c) {
      const std::size_t n = k * 2304 + c;
      // Potential temperature T + 300 K times the Exner function (p / 1000 hPa)^(Rd/cp), Rd/cp = 287/1004.5.
      const double expectedT =
          (static_cast<double>(t[n]) + 300.0) * std::pow((static_cast<double>(p[n]) + pb[n]) / 1.0e5, 287.0 / 1004.5);
      // Geopotential at a mass level: the mean of the W levels below and above.
      const double expectedZ =
          0.5 * ((static_cast<double>(ph[n]) + phb[n]) + (static_cast<double>(ph[n + 2304]) + phb[n + 2304]));
      tMax = std::max(tMax, std::fabs(tk->values[n] - expectedT));
      zMax = std::max(zMax, std::fabs(z->values[n] - expectedZ));
    }
  // Stored as float: 300 K has a spacing of 3e-5 K, 1e5 m2 s-2 one of 0.008.
  EXPECT_LT(tMax, 1e-4);
  EXPECT_LT(zMax, 0.02);
  // Plausible air: over the Gulf in late August the lowest level is 293-305 K; the top level
  // (about 520 hPa) a few degrees either side of 0 C.
  for (std::size_t c = 0; c < 2304; ++c) {
    ASSERT_GT(tk->values[c], 293.0f) << c;
    ASSERT_LT(tk->values[c], 305.0f) << c;
    ASSERT_GT(tk->values[13 * 2304 + c], 263.0f) << c;
    ASSERT_LT(tk->values[13 * 2304 + c], 283.0f) << c;
  }
}

TEST(GridReaderReal, WrfPressuresAreKeptForIsobaricSurfaces) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  GridReadOptions o;
  o.variable = "QVAPOR";
  o.timeIndex = 3;
  auto plain = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(plain.ok()) << plain.error();
  EXPECT_TRUE(plain->pressurePa.empty()) << "kept only when asked";
  o.keepPressure = true;
  auto r = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->pressurePa.size(), r->values.size());
  const std::vector<float> p = ncRead(wrfPath(), "P", {3, 0, 0, 0}, {1, 14, 48, 48});
  const std::vector<float> pb = ncRead(wrfPath(), "PB", {3, 0, 0, 0}, {1, 14, 48, 48});
  for (std::size_t n = 0; n < p.size(); ++n)
    ASSERT_EQ(r->pressurePa[n], static_cast<float>(static_cast<double>(p[n]) + pb[n])) << n;
  EXPECT_EQ(r->heightAboveEllipsoidMeters, plain->heightAboveEllipsoidMeters) << "heights still from PH and PHB";
}

TEST(GridReaderReal, WrfTwoDimensionalFieldsAreReadAsMapsOnly) {
  SKIP_WITHOUT_TEST_DATA(wrfPath());
  GridReadOptions o;
  o.variable = "T2";
  o.timeIndex = 2;
  auto volume = readGridVolume(wrfPath(), o);
  ASSERT_FALSE(volume.ok());
  EXPECT_NE(volume.error().find("a 2-D field, not a volume (draw it as a map"), std::string::npos) << volume.error();
  o.allowSingleLevel = true;
  auto map = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(map.ok()) << map.error();
  EXPECT_EQ(map->nz, 1u);
  EXPECT_TRUE(map->curvilinear);
  EXPECT_EQ(map->validTime, "2005-08-28T18:00:00Z");
  EXPECT_EQ(map->units, "K");
  const std::vector<float> t2 = ncRead(wrfPath(), "T2", {2, 0, 0}, {1, 48, 48});
  const std::vector<float> lat = ncRead(wrfPath(), "XLAT", {2, 0, 0}, {1, 48, 48});
  ASSERT_EQ(map->values.size(), t2.size());
  for (std::size_t n = 0; n < t2.size(); ++n) {
    ASSERT_EQ(map->values[n], t2[n]) << n;
    ASSERT_DOUBLE_EQ(map->latDeg[n], lat[n]) << n;
  }
  // U10 and V10 are along the model grid's axes (turned east and north for barbs, Wind.h).
  o.variable = "U10";
  auto u10 = readGridVolume(wrfPath(), o);
  ASSERT_TRUE(u10.ok()) << u10.error();
  EXPECT_TRUE(u10->vectorsRelativeToGrid);
}
