// NRRD export: the resampled values are the sampler's, the header says what teem reads, and
// the gzip stream is what teem decodes (read back with Debian teem-apps' `teem-unu`).
#include "NcTestFile.h"
#include "SyntheticGridVolume.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/NrrdExport.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace {

using namespace atmoglobe;
using namespace atmoglobe::volume;

// A 1 x 1 degree regional grid, 10 levels 500 m apart over a sloping surface, with a smooth
// field (value = a function of position) so every resampled node has a distinct value.
GridVolume testGrid() {
  return testutil::rectilinearGrid(
      testutil::evenlySpaced(10.0, 0.1, 11), testutil::evenlySpaced(45.0, 0.1, 11),
      testutil::evenlySpaced(0.0, 500.0, 10),
      [](double lat, double lon) { return 100.0 * (lat - 45.0) + 50.0 * (lon - 10.0); },
      [](double lat, double lon, double h) { return 10.0 * (lat - 45.0) + 3.0 * (lon - 10.0) + h / 1000.0; });
}

RegularGridSpec smallSpec() {
  RegularGridSpec s;
  s.kind = RegularGridKind::Geographic;
  s.datum = HeightDatum::Ellipsoid;
  s.westDeg = 10.05;
  s.eastDeg = 10.95;
  s.southDeg = 45.05;
  s.northDeg = 45.95;
  s.bottomMeters = 0.0;
  s.topMeters = 4800.0;
  s.nx = 7;
  s.ny = 5;
  s.nz = 9;
  return s;
}

std::string run(const std::string& command) {
  std::string out;
  std::FILE* p = ::popen(command.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  ::pclose(p);
  return out;
}

bool haveUnu() { return std::filesystem::exists("/usr/bin/teem-unu"); }

}  // namespace

TEST(NrrdExport, ResampledNodesAreTheSamplersValues) {
  const GridVolume grid = testGrid();
  const GridSampler sampler(grid);
  const RegularGridSpec spec = smallSpec();
  auto values = resampleRegular(sampler, spec, Interpolation::Linear, nullptr, 2);
  ASSERT_TRUE(values) << values.error();
  ASSERT_EQ(values->size(), spec.sampleCount());
  std::size_t echoes = 0;
  for (std::size_t k = 0; k < spec.nz; ++k)
    for (std::size_t j = 0; j < spec.ny; ++j)
      for (std::size_t i = 0; i < spec.nx; ++i) {
        const double lon = spec.westDeg + (spec.eastDeg - spec.westDeg) * static_cast<double>(i) / 6.0;
        const double lat = spec.southDeg + (spec.northDeg - spec.southDeg) * static_cast<double>(j) / 4.0;
        const double h = spec.bottomMeters + (spec.topMeters - spec.bottomMeters) * static_cast<double>(k) / 8.0;
        const VolumeSample s = sampler.sampleGeodetic(lat, lon, h, Interpolation::Linear);
        const float v = (*values)[(k * spec.ny + j) * spec.nx + i];
        if (s.state == VolumeSample::State::Echo) {
          ++echoes;
          // Float storage of a double sample: half an ulp of values below 20.
          EXPECT_NEAR(v, s.value, 2e-6) << i << "," << j << "," << k;
        } else {
          EXPECT_TRUE(std::isnan(v)) << i << "," << j << "," << k;
        }
      }
  // Most nodes lie inside the grid (the top level is 4500 m over a surface up to 145 m).
  EXPECT_GT(echoes, spec.sampleCount() * 3 / 4);
  EXPECT_LT(echoes, spec.sampleCount());  // and the top nodes above the top level centre are not
}

TEST(NrrdExport, CartesianNodesFollowTheLocalFrame) {
  const GridVolume grid = testGrid();
  const GridSampler sampler(grid);
  RegularGridSpec spec;
  spec.kind = RegularGridKind::LocalCartesian;
  spec.centerLatDeg = 45.5;
  spec.centerLonDeg = 10.5;
  spec.xMinMeters = -20000;
  spec.xMaxMeters = 20000;
  spec.yMinMeters = -30000;
  spec.yMaxMeters = 30000;
  spec.zMinMeters = 1000;
  spec.zMaxMeters = 3000;
  spec.nx = 5;
  spec.ny = 4;
  spec.nz = 3;
  auto values = resampleRegular(sampler, spec, Interpolation::Nearest, nullptr, 1);
  ASSERT_TRUE(values) << values.error();
  const glm::dmat4 enu = globe::enuToEcef({45.5, 10.5, 0.0});
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t j = 0; j < 4; ++j)
      for (std::size_t i = 0; i < 5; ++i) {
        const glm::dvec3 p(enu * glm::dvec4(-20000.0 + 10000.0 * static_cast<double>(i),
                                            -30000.0 + 20000.0 * static_cast<double>(j),
                                            1000.0 + 1000.0 * static_cast<double>(k), 1.0));
        const VolumeSample s = sampler.sample(p, Interpolation::Nearest);
        const float v = (*values)[(k * 4 + j) * 5 + i];
        if (s.state == VolumeSample::State::Echo) EXPECT_EQ(v, static_cast<float>(s.value));
        else EXPECT_TRUE(std::isnan(v));
      }
}

TEST(NrrdExport, RawFileHoldsTheHeaderAndTheValues) {
  const RegularGridSpec spec = smallSpec();
  std::vector<float> values(spec.sampleCount());
  for (std::size_t n = 0; n < values.size(); ++n) values[n] = static_cast<float>(n) * 0.5f - 7.0f;
  values[3] = std::numeric_limits<float>::quiet_NaN();
  const std::string path = atmoglobe_test::freshTestDir("nrrd") + "/raw.nrrd";
  NrrdMetadata meta;
  meta.content = "test field";
  meta.valueUnits = "K";
  meta.keyValues.emplace_back("valid:time", "2020-05-01T18:00:00Z\nsecond line");
  ASSERT_TRUE(writeNrrd(path, spec, values, meta, false));
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t end = bytes.find("\n\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = bytes.substr(0, end + 1);
  EXPECT_EQ(header.rfind("NRRD0004\n", 0), 0u);
  EXPECT_NE(header.find("sizes: 7 5 9\n"), std::string::npos);
  EXPECT_NE(header.find("encoding: raw\n"), std::string::npos);
  EXPECT_NE(header.find("units: \"deg\" \"deg\" \"m\"\n"), std::string::npos);
  EXPECT_NE(header.find("value_units:=K\n"), std::string::npos);
  // A key may not hold ':' before ":=" and a value no newline: both are made safe.
  EXPECT_NE(header.find("valid_time:=2020-05-01T18:00:00Z second line\n"), std::string::npos);
  ASSERT_EQ(bytes.size() - (end + 2), values.size() * sizeof(float));
  EXPECT_EQ(std::memcmp(bytes.data() + end + 2, values.data(), values.size() * sizeof(float)), 0);
}

TEST(NrrdExport, TeemReadsTheGzipFile) {
  if (!haveUnu()) GTEST_SKIP() << "teem-unu not installed (Debian teem-apps; scripts/install-deps.sh installs it)";
  const GridVolume grid = testGrid();
  const GridSampler sampler(grid);
  const RegularGridSpec spec = smallSpec();
  auto values = resampleRegular(sampler, spec, Interpolation::Linear, nullptr, 2);
  ASSERT_TRUE(values);
  const std::string dir = atmoglobe_test::freshTestDir("nrrd");
  const std::string path = dir + "/grid.nrrd";
  NrrdMetadata meta;
  meta.valueUnits = "dBZ";
  ASSERT_TRUE(writeNrrd(path, spec, *values, meta, true));

  const std::string head = run("/usr/bin/teem-unu head " + path + " 2>&1");
  EXPECT_NE(head.find("sizes: 7 5 9"), std::string::npos) << head;
  EXPECT_NE(head.find("encoding: gzip"), std::string::npos) << head;
  EXPECT_NE(head.find("axis mins: 10.050000000000001 45.049999999999997 0"), std::string::npos) << head;

  float lo = INFINITY, hi = -INFINITY;
  for (float v : *values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  const std::string mm = run("/usr/bin/teem-unu minmax " + path + " 2>&1");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(mm, m, std::regex("min: ([-0-9.e+]+)\\s+max: ([-0-9.e+]+)"))) << mm;
  // teem prints the float extremes as doubles with 17 digits: equal to the float values.
  EXPECT_EQ(static_cast<float>(std::stod(m[1].str())), lo) << mm;
  EXPECT_EQ(static_cast<float>(std::stod(m[2].str())), hi) << mm;
  EXPECT_NE(mm.find("non-existent"), std::string::npos) << "the NaN nodes above the top level: " << mm;

  // teem decodes the gzip stream to exactly our floats.
  const std::string raw = dir + "/decoded.raw";
  run("/usr/bin/teem-unu save -f nrrd -e raw -i " + path + " -o " + dir + "/decoded.nhdr 2>&1");
  std::ifstream in(raw, std::ios::binary);
  ASSERT_TRUE(in) << "teem-unu save wrote no " << raw;
  std::vector<float> decoded(values->size());
  in.read(reinterpret_cast<char*>(decoded.data()), static_cast<std::streamsize>(decoded.size() * sizeof(float)));
  ASSERT_EQ(static_cast<std::size_t>(in.gcount()), decoded.size() * sizeof(float));
  EXPECT_EQ(std::memcmp(decoded.data(), values->data(), decoded.size() * sizeof(float)), 0);
}

TEST(NrrdExport, BadSpecsAreRefused) {
  RegularGridSpec s = smallSpec();
  EXPECT_TRUE(validateRegularGridSpec(s, 1000));
  s.nz = 0;
  EXPECT_FALSE(validateRegularGridSpec(s, 1000));
  s = smallSpec();
  auto tooMany = validateRegularGridSpec(s, 100);
  ASSERT_FALSE(tooMany);
  EXPECT_NE(tooMany.error().find("7 x 5 x 9"), std::string::npos) << tooMany.error();
  s = smallSpec();
  s.northDeg = 95.0;
  EXPECT_FALSE(validateRegularGridSpec(s, 1000));
  s = smallSpec();
  s.eastDeg = 9.0;  // backwards
  EXPECT_FALSE(validateRegularGridSpec(s, 1000));
  s = smallSpec();
  s.topMeters = NAN;
  EXPECT_FALSE(validateRegularGridSpec(s, 1000));
  // Heights above sea level without a geoid grid.
  s = smallSpec();
  s.datum = HeightDatum::MeanSeaLevel;
  const GridVolume grid = testGrid();
  EXPECT_FALSE(resampleRegular(GridSampler(grid), s, Interpolation::Linear, nullptr, 1));
}

TEST(NrrdExport, ErrorsNameTheFileAndKeepThePreviousOutput) {
  const std::string dir = atmoglobe_test::freshTestDir("nrrd");
  const std::string out = dir + "/keep.nrrd";
  { std::ofstream(out) << "previous"; }
  NrrdExportOptions o;
  o.inputPath = dir + "/no_such_file.nc";
  o.outputPath = out;
  auto r = exportNrrd(o);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("no_such_file.nc"), std::string::npos) << r.error();
  std::ifstream in(out);
  std::string text;
  std::getline(in, text);
  EXPECT_EQ(text, "previous");
}

// A box whose edges lie on grid lines of a global file (here 2.5 degrees, latitudes north to
// south, longitudes 0..357.5): every node of the box is inside the file's coverage, so every
// node gets a value, the edges included. The field is linear in latitude, longitude (as the
// file counts it, 0..360) and height, so linear interpolation gives it back exactly at any node.
TEST(NrrdExport, CropBoxOnGridLinesHasDataOnEveryEdge) {
  const std::string dir = atmoglobe_test::freshTestDir("nrrd");
  const std::string path = dir + "/global_2p5.nc";
  std::vector<double> lat, lon, lev;
  for (int j = 0; j < 73; ++j) lat.push_back(90.0 - 2.5 * j);
  for (int i = 0; i < 144; ++i) lon.push_back(2.5 * i);
  for (int k = 0; k < 11; ++k) lev.push_back(2000.0 * k);  // 0 .. 20 km above the ellipsoid
  auto field = [](double latDeg, double lon0To360Deg, double hMeters) {
    return 3.0 * latDeg + 0.5 * lon0To360Deg + hMeters / 1000.0;
  };
  {
    atmoglobe_test::NcTestFile f(path, 0);
    f.globalText("Conventions", "CF-1.6");
    f.dim("lev", lev.size());
    f.dim("lat", lat.size());
    f.dim("lon", lon.size());
    auto vz = f.var("lev", NC_DOUBLE, {"lev"});
    f.text(vz, "units", "m");
    f.text(vz, "standard_name", "height_above_reference_ellipsoid");
    auto vy = f.var("lat", NC_DOUBLE, {"lat"});
    f.text(vy, "units", "degrees_north");
    auto vx = f.var("lon", NC_DOUBLE, {"lon"});
    f.text(vx, "units", "degrees_east");
    auto vq = f.var("q", NC_DOUBLE, {"lev", "lat", "lon"});
    f.put(vz, lev);
    f.put(vy, lat);
    f.put(vx, lon);
    std::vector<double> q;
    for (double h : lev)
      for (double la : lat)
        for (double lo : lon) q.push_back(field(la, lo, h));
    f.put(vq, q);
  }
  // The reported case: 13 x 9 x 12 nodes over the USA, 25..45 N, 125..95 W (235..265 in the file).
  NrrdExportOptions o;
  o.inputPath = path;
  o.outputPath = dir + "/usa.nrrd";
  o.cropSouthNorthWestEastDeg = std::array<double, 4>{25.0, 45.0, -125.0, -95.0};
  o.heightRangeMeters = std::array<double, 2>{1000.0, 12000.0};
  o.size = std::array<std::size_t, 3>{13, 9, 12};
  o.datum = HeightDatum::Ellipsoid;
  o.gzip = false;
  o.threads = 1;
  auto r = exportNrrd(o);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->finiteValues, 13u * 9u * 12u);
  std::ifstream in(o.outputPath, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t end = bytes.find("\n\n");
  ASSERT_NE(end, std::string::npos);
  ASSERT_EQ(bytes.size() - (end + 2), 13u * 9u * 12u * sizeof(float));
  std::vector<float> v(13 * 9 * 12);
  std::memcpy(v.data(), bytes.data() + end + 2, v.size() * sizeof(float));
  for (std::size_t k = 0; k < 12; ++k)
    for (std::size_t j = 0; j < 9; ++j)
      for (std::size_t i = 0; i < 13; ++i) {
        const double la = 25.0 + 2.5 * static_cast<double>(j);
        const double lo = 235.0 + 2.5 * static_cast<double>(i);
        const double h = 1000.0 + 1000.0 * static_cast<double>(k);
        // Tolerance: the values are floats (about 3e-5 at |f| < 300) and each node goes through
        // ECEF and back (1e-9 degree, 1e-8 m): 1e-3 of the field's units covers both.
        ASSERT_NEAR(v[(k * 9 + j) * 13 + i], field(la, lo, h), 1e-3) << "node " << i << ", " << j << ", " << k;
      }
  // Without a size: the data's 2.5-degree spacing over the box, 13 x 9 nodes, all with a value.
  o.size.reset();
  o.outputPath = dir + "/usa_default.nrrd";
  auto d = exportNrrd(o);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->spec.nx, 13u);
  EXPECT_EQ(d->spec.ny, 9u);
  EXPECT_EQ(d->finiteValues, d->spec.sampleCount());
  // The read kept the grid lines beyond the box on every side (where the file has them), so
  // that a node on the box's edge lies inside the data, not on its rounded border.
  GridReadOptions read;
  read.crop = {25.0, 45.0, -125.0, -95.0};
  auto g = readGridVolume(path, read);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_DOUBLE_EQ(g->latDeg.front(), 22.5);
  EXPECT_DOUBLE_EQ(g->latDeg.back(), 47.5);
  EXPECT_DOUBLE_EQ(g->lonDeg.front(), -127.5);
  EXPECT_DOUBLE_EQ(g->lonDeg.back(), -92.5);
}
