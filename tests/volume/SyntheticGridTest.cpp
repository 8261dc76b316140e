// The SYNTHETIC forecast grid of `atmoglobe synth --grid`: labelled, read back by the grid reader
// as the forecast-like file it claims to be, its storm where the synthetic radar sees it, and a
// crop of the default-size file costing a small fraction of the variable.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/SyntheticGrid.h>

#include <gtest/gtest.h>
#include <netcdf.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

using namespace atmoglobe;
using namespace atmoglobe::volume;

namespace {

std::string text(int nc, int var, const char* name) {
  std::size_t len = 0;
  if (nc_inq_attlen(nc, var, name, &len) != NC_NOERR) return {};
  std::string s(len, '\0');
  nc_get_att_text(nc, var, name, s.data());
  return s;
}

std::vector<double> coordinate(const std::string& path, const char* name) {
  int nc = -1, id = -1, dim = -1;
  std::size_t n = 0;
  EXPECT_EQ(nc_open(path.c_str(), NC_NOWRITE, &nc), NC_NOERR);
  nc_inq_varid(nc, name, &id);
  nc_inq_vardimid(nc, id, &dim);
  nc_inq_dimlen(nc, dim, &n);
  std::vector<double> v(n);
  nc_get_var_double(nc, id, v.data());
  nc_close(nc);
  return v;
}

}  // namespace

TEST(SyntheticGrid, SmallGridIsLabelledAndReadsBackAsAForecast) {
  const std::string path = atmoglobe_test::freshTestDir("synthetic_grid") + "/small.nc";
  SyntheticGridOptions o;
  o.nx = 60;
  o.ny = 50;
  o.levels = 20;
  o.times = 5;
  SyntheticGridSummary s;
  ASSERT_TRUE(writeSyntheticGrid(path, o, &s).ok());
  EXPECT_EQ(s.fileBytes, std::filesystem::file_size(path));
  EXPECT_GT(s.echoValues, 0u);
  EXPECT_GT(s.maxDbz, 50.0);
  EXPECT_LT(s.maxDbz, 70.0);
  {
    int nc = -1, dbz = -1;
    ASSERT_EQ(nc_open(path.c_str(), NC_NOWRITE, &nc), NC_NOERR);
    for (const char* a : {"title", "source", "comment"})
      EXPECT_NE(text(nc, NC_GLOBAL, a).find("SYNTHETIC"), std::string::npos) << a;
    ASSERT_EQ(nc_inq_varid(nc, "dbz", &dbz), NC_NOERR);
    EXPECT_NE(text(nc, dbz, "comment").find("SYNTHETIC"), std::string::npos);
    nc_close(nc);
  }
  // Written the GRIB-converted way: north to south, 0..360.
  const std::vector<double> lat = coordinate(path, "lat"), lon = coordinate(path, "lon");
  EXPECT_GT(lat.front(), lat.back());
  EXPECT_GT(lon.front(), 180.0);

  GridReadOptions ro;
  ro.timeIso8601 = "2020-05-01T21:00:00Z";  // the synthetic radar volume's time
  auto r = readGridVolume(path, ro);
  ASSERT_TRUE(r.ok()) << r.error();
  const GridVolume& g = *r;
  EXPECT_EQ(g.variable, "/dbz");
  EXPECT_EQ(g.units, "dBZ");
  EXPECT_EQ(g.timeIndex, 3u);
  EXPECT_EQ(g.verticalKind, VerticalKind::HeightAboveGround);
  EXPECT_FALSE(g.approximateHeights);
  EXPECT_NE(g.heightNote.find("'/orog'"), std::string::npos) << g.heightNote;
  EXPECT_LT(g.latDeg.front(), g.latDeg.back());
  EXPECT_NEAR(g.lonDeg[g.nx / 2], o.centerLonDeg, 0.1) << "0..360 read back as -180..180";
  EXPECT_FLOAT_EQ(g.valueMin, -30.0f) << "clear air";
  // The strongest echo at 21Z: the radar model's core, 50 km W and 36 km S of KTLX (SyntheticRadar.h).
  std::size_t bk = 0, bj = 0, bi = 0;
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i)
        if (g.value(k, j, i) > g.value(bk, bj, bi)) {
          bk = k;
          bj = j;
          bi = i;
        }
  const globe::GeodesicLine d =
      globe::geodesicInverse(o.storm.siteLatDeg, o.storm.siteLonDeg, g.latDegAt(bj, bi), g.lonDegAt(bj, bi));
  const double az = d.azimuth1Deg * 3.14159265358979323846 / 180.0;
  // Within 10 km: the grid's 5 km spacing plus the core's tilt with height.
  EXPECT_NEAR(d.distanceMeters / 1000.0 * std::sin(az), o.storm.stormEastKm, 10.0);
  EXPECT_NEAR(d.distanceMeters / 1000.0 * std::cos(az), o.storm.stormNorthKm, 10.0);
  EXPECT_GT(g.value(bk, bj, bi), 55.0f);
  // Echo tops of a supercell: nothing above 16 km.
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i)
        if (g.heightMeters(k, j, i) > 16000.0f) {
          ASSERT_LT(g.value(k, j, i), 5.0f);
        }
  // Hours later the system has moved on east-north-east (36, 18 km/h).
  ro.timeIso8601 = "2020-05-01T22:00:00Z";
  auto later = readGridVolume(path, ro);
  ASSERT_TRUE(later.ok()) << later.error();
  EXPECT_NE(later->values, g.values);
}

TEST(SyntheticGrid, DefaultGridIsSmallAndACropReadsLittleOfIt) {
  const std::string path = atmoglobe_test::freshTestDir("synthetic_grid") + "/default.nc";
  const SyntheticGridOptions o;
  ASSERT_TRUE(writeSyntheticGrid(path, o).ok());
  EXPECT_LT(std::filesystem::file_size(path), 20u << 20) << "a few MB, not the 145 MB of raw shorts";
  auto info = describeGridFile(path);
  ASSERT_TRUE(info.ok()) << info.error();
  EXPECT_EQ(info->nx, 400u);
  EXPECT_EQ(info->ny, 400u);
  EXPECT_EQ(info->nz, 35u);
  EXPECT_EQ(info->times.size(), 13u);
  EXPECT_NEAR(info->meanSpacingKm, 5.0, 0.1);
  // A 1 x 1 degree box around KTLX, the lowest 10 levels, one step.
  GridReadOptions ro;
  ro.timeIndex = 3;
  ro.crop.southDeg = 34.8;
  ro.crop.northDeg = 35.8;
  ro.crop.westDeg = -97.8;
  ro.crop.eastDeg = -96.8;
  ro.crop.levelCount = 10;
  auto crop = readGridVolume(path, ro);
  ASSERT_TRUE(crop.ok()) << crop.error();
  EXPECT_LE(crop->nx * crop->ny, 26u * 26u);
  const std::uint64_t wholeVariable = 400ull * 400 * 35 * 13 * 2;  // shorts
  EXPECT_LT(crop->bytesRead, wholeVariable / 1000) << crop->bytesRead;
  GridReadOptions step;
  step.timeIndex = 3;
  auto full = readGridVolume(path, step);
  ASSERT_TRUE(full.ok());
  EXPECT_LT(full->bytesRead, wholeVariable / 10) << "one step of 13, plus coordinates";
  EXPECT_LT(crop->bytesRead, full->bytesRead / 100);
}

TEST(SyntheticGrid, OptionsAreChecked) {
  const std::string path = atmoglobe_test::freshTestDir("synthetic_grid") + "/bad.nc";
  SyntheticGridOptions o;
  o.nx = 1;
  auto st = writeSyntheticGrid(path, o);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("nx and ny"), std::string::npos) << st.error();
  o = SyntheticGridOptions{};
  o.spacingKm = 0;
  EXPECT_FALSE(writeSyntheticGrid(path, o).ok());
  o = SyntheticGridOptions{};
  o.centerLatDeg = 84.0;
  EXPECT_FALSE(writeSyntheticGrid(path, o).ok());
  o = SyntheticGridOptions{};
  o.startTimeIso8601 = "noon";
  EXPECT_FALSE(writeSyntheticGrid(path, o).ok());
  EXPECT_FALSE(std::filesystem::exists(path)) << "nothing written on bad options";
}

// The SYNTHETIC global grid (the grid bench's global case): ERA5's layout read back as a global
// pressure-level grid with heights from its geopotential, and weather with structure.
TEST(SyntheticGrid, GlobalGridReadsBackAsAGlobalPressureLevelGrid) {
  const std::string path = atmoglobe_test::freshTestDir("synthetic_global_grid") + "/global.nc";
  SyntheticGlobalGridOptions o;
  o.nx = 144;
  o.ny = 73;
  SyntheticGridSummary s;
  ASSERT_TRUE(writeSyntheticGlobalGrid(path, o, &s).ok());
  EXPECT_EQ(s.levels, 37u);
  EXPECT_GT(s.echoValues, 0u);
  EXPECT_GT(s.maxDbz, 45.0);  // cyclone eyewalls and ITCZ cells
  EXPECT_LT(s.maxDbz, 65.0);
  auto g = readGridVolume(path, {});
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->variable, "/dbz");
  EXPECT_EQ(g->nx, 144u);
  EXPECT_EQ(g->ny, 73u);
  EXPECT_EQ(g->nz, 37u);
  EXPECT_TRUE(g->wrapsLongitude);
  EXPECT_DOUBLE_EQ(g->latDeg.front(), -90.0);  // turned round: row 0 the south pole
  EXPECT_DOUBLE_EQ(g->latDeg.back(), 90.0);
  EXPECT_EQ(g->verticalKind, VerticalKind::Pressure);
  EXPECT_EQ(g->heightSource, HeightSource::GeopotentialField);
  EXPECT_FALSE(g->approximateHeights);
  EXPECT_EQ(g->fileLevelStep, -1);  // written top first, as ERA5
  EXPECT_DOUBLE_EQ(g->levelValues.front(), 100000.0);
  // 500 hPa: the standard atmosphere's 5574 m, 4.5 % higher at the equator and lower at the
  // poles (+- the geoid, < 110 m, and the wave term, 1 %).
  const std::size_t k500 = 15;
  ASSERT_DOUBLE_EQ(g->levelValues[k500], 50000.0);
  const double hEq = g->heightMeters(k500, 36, 0), hPole = g->heightMeters(k500, 72, 0);
  EXPECT_NEAR(hEq, 5574.0 * 1.045, 120.0);
  EXPECT_NEAR(hPole, 5574.0 * 0.955, 120.0);
  // Values: clear air is -30 dBZ, nothing missing.
  EXPECT_FLOAT_EQ(g->valueMin, -30.0f);
  for (float v : g->values) ASSERT_TRUE(std::isfinite(v));
}

// The field's shapes, through its public formula: a cyclone's eye is clear and its eyewall
// strong; far from every system it is clear air; a frontal band has a bright band at 2.5 km.
TEST(SyntheticGrid, GlobalFieldHasCyclonesAndFrontsWhereItSays) {
  EXPECT_LT(syntheticGlobalDbz(19.0, -62.0, 1000.0, 0.0, 7), 30.0);                       // the eye
  const double eyewall = syntheticGlobalDbz(19.0 + 35.0 / 111.0, -62.0, 1000.0, 0.0, 7);  // 35 km north
  EXPECT_GT(eyewall, 45.0);
  EXPECT_LT(syntheticGlobalDbz(19.0 + 35.0 / 111.0, -62.0, 17000.0, 0.0, 7), eyewall - 20.0);
  EXPECT_DOUBLE_EQ(syntheticGlobalDbz(-35.0, -120.0, 1000.0, 0.0, 7), -30.0);  // the south Pacific subtropics
  // The northern storm track at longitude 60 E, where the band is active (3 lon + 50 = 230 deg:
  // sin = -0.77, active 0.12 < 0.2) -- use 20 E instead: 110 deg, active 0.97.
  const double lon = 20.0;
  const double track =
      47.0 + 7.0 * std::sin((4.0 * lon + 30.0) * M_PI / 180.0) + 3.0 * std::sin(7.0 * lon * M_PI / 180.0);
  EXPECT_GT(syntheticGlobalDbz(track, lon, 2500.0, 0.0, 7), syntheticGlobalDbz(track, lon, 1500.0, 0.0, 7) + 4.0);
  EXPECT_GT(syntheticGlobalDbz(track, lon, 1500.0, 0.0, 7), 25.0);
  // Geopotential increases upwards in every column (levels must be monotonic).
  for (double lat : {-90.0, -45.0, 0.0, 60.0, 90.0})
    for (std::size_t k = 1; k < era5PressureLevelsHpa().size(); ++k)
      EXPECT_LT(syntheticGlobalGeopotential(lat, 33.0, era5PressureLevelsHpa()[k]),
                syntheticGlobalGeopotential(lat, 33.0, era5PressureLevelsHpa()[k - 1]));
}
