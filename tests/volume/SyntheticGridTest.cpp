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
