// The forecast-grid reader on layouts real archives use, each in a small netCDF file written
// here: extra index dimensions (ensemble members, months), geopotential packed in shorts with a
// negative scale_factor on a north-to-south, top-first pressure grid (ERA5 style), CAM/NCL
// hybrid levels named by A_var/B_var/P0_var/PS_var, and a `coordinates` attribute naming
// variables the file lacks.
#include "NcTestFile.h"

#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/SliceSource.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace atmoglobe::volume;
using atmoglobe_test::NcTestFile;

namespace {

std::string testDir() { return atmoglobe_test::freshTestDir("grid_archive_layouts"); }

bool mentions(const std::string& message, std::initializer_list<std::string> parts) {
  for (const auto& p : parts)
    if (message.find(p) == std::string::npos) return false;
  return true;
}

// ---------------------------------------------------------------- an independent height rule

// WGS84 defining and derived constants (NIMA TR8350.2, 3rd ed., tables 3.1-3.4), written out here
// rather than taken from the library, so that the reference below shares no code with it.
constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
constexpr double kGM = 3.986004418e14;
constexpr double kOmega = 7292115.0e-11;
constexpr double kGammaEquator = 9.7803253359, kGammaPole = 9.8321849378;
constexpr double kG0 = 9.80665;  // standard gravity: geopotential / g0 = geopotential height

/// Geometric height above sea level (m) of geopotential height `gpm` at latitude `latDeg`:
/// g0 H = integral from 0 to z of gamma(lat) (1 - 2/a (1 + f + m - 2 f sin^2 lat) z + 3 z^2/a^2) dz
/// (TR8350.2 eq. 4-3), gamma(lat) by Somigliana's formula with k from the polar gravity, the
/// cubic solved by bisection.
double referenceGeometricHeight(double gpm, double latDeg) {
  const double b = kA * (1.0 - kF);
  const double e2 = kF * (2.0 - kF);
  const double m = kOmega * kOmega * kA * kA * b / kGM;
  const double k = b * kGammaPole / (kA * kGammaEquator) - 1.0;
  const double s2 = std::pow(std::sin(latDeg * M_PI / 180.0), 2);
  const double gamma = kGammaEquator * (1.0 + k * s2) / std::sqrt(1.0 - e2 * s2);
  const double c1 = (1.0 + kF + m - 2.0 * kF * s2) / kA;
  auto integral = [&](double z) { return gamma * (z - c1 * z * z + z * z * z / (kA * kA)); };
  double lo = -1000.0, hi = 200000.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (integral(mid) < kG0 * gpm ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// ---------------------------------------------------------------- ERA5-style pressure levels

/// ERA5 as the CDS writes it: latitude north to south, levels top first (200, 500, 850 hPa),
/// `z` and `t` shorts packed with scale_factor/add_offset; `negativeScale` packs z with a
/// negative scale_factor (the largest value stored as -32766).
struct Era5Like {
  std::vector<double> lat = {50.0, 47.5, 45.0};
  std::vector<double> lon = {350.0, 352.5, 355.0, 357.5};
  std::vector<double> levHpa = {200.0, 500.0, 850.0};
  bool negativeScale = true;
  /// Geopotential (m2 s-2) at file level k, row j, column i: about 11.8, 5.6 and 1.5 km.
  static double z(std::size_t k, std::size_t j, std::size_t i) {
    static const double base[] = {115500.0, 55400.0, 14300.0};
    return base[k] - 20.0 * static_cast<double>(j) + 35.0 * static_cast<double>(i);
  }
  double zScale = 0, zOffset = 0;
  /// The packed short of z and what the reader must unpack it to.
  short zPacked(std::size_t k, std::size_t j, std::size_t i) const {
    return static_cast<short>(std::lround((z(k, j, i) - zOffset) / zScale));
  }
  double zUnpacked(std::size_t k, std::size_t j, std::size_t i) const {
    return static_cast<double>(zPacked(k, j, i)) * zScale + zOffset;
  }
};

void writeEra5Like(const std::string& path, Era5Like& e) {
  // The CDS's packing: offset the middle of the range, scale spreading it over +-32766.
  double zMin = HUGE_VAL, zMax = -HUGE_VAL;
  for (std::size_t k = 0; k < e.levHpa.size(); ++k)
    for (std::size_t j = 0; j < e.lat.size(); ++j)
      for (std::size_t i = 0; i < e.lon.size(); ++i) {
        zMin = std::min(zMin, Era5Like::z(k, j, i));
        zMax = std::max(zMax, Era5Like::z(k, j, i));
      }
  e.zOffset = 0.5 * (zMin + zMax);
  e.zScale = (zMax - zMin) / (2.0 * 32766.0) * (e.negativeScale ? -1.0 : 1.0);
  NcTestFile f(path, 0);  // classic, as the CDS's netCDF3 files
  f.globalText("Conventions", "CF-1.6");
  f.dim("longitude", e.lon.size());
  f.dim("latitude", e.lat.size());
  f.dim("level", e.levHpa.size());
  f.dim("time", NC_UNLIMITED);
  auto vx = f.var("longitude", NC_FLOAT, {"longitude"});
  f.text(vx, "units", "degrees_east");
  auto vy = f.var("latitude", NC_FLOAT, {"latitude"});
  f.text(vy, "units", "degrees_north");
  auto vl = f.var("level", NC_INT, {"level"});
  f.text(vl, "units", "millibars");
  f.text(vl, "long_name", "pressure_level");
  auto vt = f.var("time", NC_INT, {"time"});
  f.text(vt, "units", "hours since 1900-01-01 00:00:00.0");
  f.text(vt, "calendar", "gregorian");
  auto vz = f.var("z", NC_SHORT, {"time", "level", "latitude", "longitude"});
  f.number(vz, "scale_factor", NC_DOUBLE, {e.zScale});
  f.number(vz, "add_offset", NC_DOUBLE, {e.zOffset});
  f.number(vz, "_FillValue", NC_SHORT, {-32767});
  f.number(vz, "missing_value", NC_SHORT, {-32767});
  f.text(vz, "units", "m**2 s**-2");
  f.text(vz, "long_name", "Geopotential");
  f.text(vz, "standard_name", "geopotential");
  auto vta = f.var("t", NC_SHORT, {"time", "level", "latitude", "longitude"});
  f.number(vta, "scale_factor", NC_DOUBLE, {0.002});
  f.number(vta, "add_offset", NC_DOUBLE, {250.0});
  f.number(vta, "_FillValue", NC_SHORT, {-32767});
  f.text(vta, "units", "K");
  f.text(vta, "standard_name", "air_temperature");
  f.put(vx, e.lon);
  f.put(vy, e.lat);
  f.put(vl, e.levHpa);
  f.put(vt, {0}, {1}, {1063776.0});
  std::vector<double> zs, ts;
  for (std::size_t k = 0; k < e.levHpa.size(); ++k)
    for (std::size_t j = 0; j < e.lat.size(); ++j)
      for (std::size_t i = 0; i < e.lon.size(); ++i) {
        zs.push_back(e.zPacked(k, j, i));
        ts.push_back(static_cast<double>(k * 100 + j * 10 + i));  // 250 + 0.002 * code K
      }
  const std::size_t nl = e.levHpa.size(), ny = e.lat.size(), nx = e.lon.size();
  f.put(vz, {0, 0, 0, 0}, {1, nl, ny, nx}, zs);
  f.put(vta, {0, 0, 0, 0}, {1, nl, ny, nx}, ts);
}

}  // namespace

// ---------------------------------------------------------------- geopotential packed with a negative scale

TEST(GridArchiveLayouts, HeightsFromGeopotentialPackedWithANegativeScaleFactor) {
  for (bool negative : {true, false}) {
    SCOPED_TRACE(negative ? "negative scale_factor" : "positive scale_factor");
    const std::string path = testDir() + (negative ? "/era5_negative_scale.nc" : "/era5_positive_scale.nc");
    Era5Like e;
    e.negativeScale = negative;
    writeEra5Like(path, e);
    for (const char* variable : {"t", "z"}) {
      SCOPED_TRACE(variable);
      GridReadOptions o;
      o.variable = variable;
      o.useGeoid = false;  // heights above sea level, so that the reference needs no geoid
      auto r = readGridVolume(path, o);
      ASSERT_TRUE(r.ok()) << r.error();
      const GridVolume& g = *r;
      EXPECT_EQ(g.heightSource, HeightSource::GeopotentialField);
      EXPECT_FALSE(g.approximateHeights);
      ASSERT_EQ(g.nz, 3u);
      ASSERT_EQ(g.ny, 3u);
      ASSERT_EQ(g.nx, 4u);
      EXPECT_EQ(g.fileLevelStep, -1);
      EXPECT_EQ(g.fileRowStep, -1);
      for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t j = 0; j < 3; ++j)
          for (std::size_t i = 0; i < 4; ++i) {
            const std::size_t kf = 2 - k, jf = 2 - j;  // bottom first, south first
            ASSERT_DOUBLE_EQ(g.latDeg[j], e.lat[jf]);
            // Hand computation: unpacked z / g0 = geopotential height, then geometric height.
            // Tolerance: the reader stores heights as float (1 ms at 16 km: 2 mm spacing) and
            // solves the same cubic by Newton to below 1e-6 m; 4 mm covers both.
            const double expected = referenceGeometricHeight(e.zUnpacked(kf, jf, i) / kG0, e.lat[jf]);
            ASSERT_NEAR(g.heightMeters(k, j, i), expected, 4e-3) << k << " " << j << " " << i;
            // And the packing itself: within half a packing step of the value written.
            ASSERT_NEAR(e.zUnpacked(kf, jf, i), Era5Like::z(kf, jf, i), 0.5 * std::fabs(e.zScale) + 1e-9);
            if (std::string(variable) == "t") {
              ASSERT_NEAR(g.value(k, j, i), 250.0 + 0.002 * static_cast<double>(kf * 100 + jf * 10 + i), 1e-4);
            }
          }
      // The file's 850 hPa at about 1.4 km, 200 hPa at about 11.8 km (a real atmosphere's).
      EXPECT_GT(g.heightMeters(0, 0, 0), 1000.0);
      EXPECT_LT(g.heightMeters(0, 0, 0), 2000.0);
      EXPECT_GT(g.heightMeters(2, 0, 0), 11000.0);
      EXPECT_LT(g.heightMeters(2, 0, 0), 12500.0);
    }
  }
}

// ---------------------------------------------------------------- extra index dimensions

namespace {

/// An ensemble on pressure levels as grib_to_netcdf writes it: t and z on (time, number, level,
/// latitude, longitude), `number` an int coordinate with long_name "ensemble_member" (values
/// 10, 11, 12 here, so that a member's value and index differ), levels bottom first.
struct Ensemble {
  static constexpr std::size_t kMembers = 3, kLevels = 2, kRows = 3, kCols = 4;
  std::vector<double> lat = {40.0, 42.5, 45.0};
  std::vector<double> lon = {10.0, 12.5, 15.0, 17.5};
  /// Geopotential (m2 s-2): each member's column a little higher than the last.
  static double z(std::size_t t, std::size_t m, std::size_t k, std::size_t j, std::size_t i) {
    return (k == 0 ? 14000.0 : 55000.0) + 100.0 * static_cast<double>(m) + 10.0 * static_cast<double>(t) +
           static_cast<double>(j + i);
  }
  /// Temperature code: where the value came from.
  static double t(std::size_t t, std::size_t m, std::size_t k, std::size_t j, std::size_t i) {
    return 1e4 * static_cast<double>(t) + 1e3 * static_cast<double>(m) + 100.0 * static_cast<double>(k) +
           10.0 * static_cast<double>(j) + static_cast<double>(i);
  }
};

void writeEnsemble(const std::string& path) {
  Ensemble e;
  NcTestFile f(path);
  f.globalText("Conventions", "CF-1.6");
  f.dim("longitude", Ensemble::kCols);
  f.dim("latitude", Ensemble::kRows);
  f.dim("level", Ensemble::kLevels);
  f.dim("number", Ensemble::kMembers);
  f.dim("time", 2);
  auto vx = f.var("longitude", NC_FLOAT, {"longitude"});
  f.text(vx, "units", "degrees_east");
  auto vy = f.var("latitude", NC_FLOAT, {"latitude"});
  f.text(vy, "units", "degrees_north");
  auto vl = f.var("level", NC_INT, {"level"});
  f.text(vl, "units", "millibars");
  auto vn = f.var("number", NC_INT, {"number"});
  f.text(vn, "long_name", "ensemble_member");
  auto vt = f.var("time", NC_INT, {"time"});
  f.text(vt, "units", "hours since 2017-01-01 00:00:00");
  auto vz = f.var("z", NC_DOUBLE, {"time", "number", "level", "latitude", "longitude"});
  f.text(vz, "units", "m**2 s**-2");
  f.text(vz, "standard_name", "geopotential");
  auto vta = f.var("t", NC_FLOAT, {"time", "number", "level", "latitude", "longitude"});
  f.text(vta, "units", "K");
  f.put(vx, e.lon);
  f.put(vy, e.lat);
  f.put(vl, {850, 500});
  f.put(vn, {10, 11, 12});
  f.put(vt, {0, 12});
  std::vector<double> zs, ts;
  for (std::size_t t = 0; t < 2; ++t)
    for (std::size_t m = 0; m < Ensemble::kMembers; ++m)
      for (std::size_t k = 0; k < Ensemble::kLevels; ++k)
        for (std::size_t j = 0; j < Ensemble::kRows; ++j)
          for (std::size_t i = 0; i < Ensemble::kCols; ++i) {
            zs.push_back(Ensemble::z(t, m, k, j, i));
            ts.push_back(Ensemble::t(t, m, k, j, i));
          }
  f.put(vz, zs);
  f.put(vta, ts);
}

/// Checks that `g` holds member index `m` at time `t`: values and heights from that member's z.
void expectMember(const GridVolume& g, std::size_t t, std::size_t m) {
  Ensemble e;
  ASSERT_EQ(g.nz, Ensemble::kLevels);
  ASSERT_EQ(g.ny, Ensemble::kRows);
  ASSERT_EQ(g.nx, Ensemble::kCols);
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i) {
        ASSERT_EQ(g.value(k, j, i), static_cast<float>(Ensemble::t(t, m, k, j, i))) << k << " " << j << " " << i;
        // Same tolerance as above: float heights (2 mm at 6 km) and the reader's Newton solution.
        ASSERT_NEAR(g.heightMeters(k, j, i), referenceGeometricHeight(Ensemble::z(t, m, k, j, i) / kG0, e.lat[j]), 4e-3)
            << k << " " << j << " " << i;
      }
}

}  // namespace

TEST(GridArchiveLayouts, EnsembleDimensionIsAnIndexNotTheVerticalOne) {
  const std::string path = testDir() + "/ensemble.nc";
  writeEnsemble(path);
  GridReadOptions o;
  o.variable = "t";
  o.useGeoid = false;
  // Default: the first member.
  auto first = readGridVolume(path, o);
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(first->verticalKind, VerticalKind::Pressure);
  EXPECT_EQ(first->verticalVariable, "/level");
  EXPECT_EQ(first->heightSource, HeightSource::GeopotentialField);
  EXPECT_EQ(first->member, 10);
  ASSERT_EQ(first->extraDimensions.size(), 1u);
  EXPECT_EQ(first->extraDimensions[0].name, "number");
  EXPECT_EQ(first->extraDimensions[0].length, 3u);
  EXPECT_EQ(first->extraDimensions[0].index, 0u);
  EXPECT_EQ(first->extraDimensions[0].value, 10.0);
  EXPECT_TRUE(first->extraDimensions[0].ensemble);
  expectMember(*first, 0, 0);
  // By member (the coordinate's value) at time 1: index 2, its own geopotential.
  o.member = 12;
  o.timeIndex = 1;
  auto m12 = readGridVolume(path, o);
  ASSERT_TRUE(m12.ok()) << m12.error();
  EXPECT_EQ(m12->member, 12);
  EXPECT_EQ(m12->extraDimensions[0].index, 2u);
  expectMember(*m12, 1, 2);
  // By index along the dimension's name: outranks member.
  o.extraIndex["number"] = 1;
  auto i1 = readGridVolume(path, o);
  ASSERT_TRUE(i1.ok()) << i1.error();
  EXPECT_EQ(i1->member, 11);
  expectMember(*i1, 1, 1);
  // A crop reads the same member: 41..44 N keeps rows 40 .. 45, 11..13 E columns 10 .. 15.
  o.crop = {41.0, 44.0, 11.0, 13.0};
  auto crop = readGridVolume(path, o);
  ASSERT_TRUE(crop.ok()) << crop.error();
  ASSERT_EQ(crop->ny, 3u);
  ASSERT_EQ(crop->nx, 3u);
  for (std::size_t k = 0; k < crop->nz; ++k)
    for (std::size_t j = 0; j < crop->ny; ++j)
      for (std::size_t i = 0; i < crop->nx; ++i)
        ASSERT_EQ(crop->value(k, j, i), i1->value(k, j, i)) << k << " " << j << " " << i;
}

TEST(GridArchiveLayouts, ExtraDimensionErrorsSayWhatThereIs) {
  const std::string path = testDir() + "/ensemble.nc";
  writeEnsemble(path);
  GridReadOptions o;
  o.variable = "t";
  o.member = 7;
  auto r = readGridVolume(path, o);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "'/t'", "no ensemble member 7", "'number'", "10, 11, 12"})) << r.error();
  o.member = -1;
  o.extraIndex["number"] = 3;
  r = readGridVolume(path, o);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "'/t'", "index 3", "'number'", "3 values"})) << r.error();
  o.extraIndex.clear();
  o.extraIndex["month"] = 1;
  r = readGridVolume(path, o);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "'/t'", "no dimension 'month'", "'number' (3)"})) << r.error();
  // A file without an ensemble dimension refuses a member, naming the variable.
  Era5Like e;
  const std::string era = testDir() + "/era5.nc";
  writeEra5Like(era, e);
  GridReadOptions m;
  m.variable = "t";
  m.member = 1;
  r = readGridVolume(era, m);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {era, "'/t'", "no ensemble dimension", "member 1"})) << r.error();
}

// Ensemble statistics (GridReadOptions::ensemble) against the members read one by one and
// reduced in the test, value for value.
TEST(GridArchiveLayouts, EnsembleStatisticsEqualTheMembersReducedByHand) {
  const std::string path = testDir() + "/ensemble_stats.nc";
  writeEnsemble(path);
  GridReadOptions o;
  o.variable = "t";
  o.useGeoid = false;
  o.timeIndex = 1;
  std::vector<GridVolume> members;
  for (std::size_t m = 0; m < Ensemble::kMembers; ++m) {
    GridReadOptions one = o;
    one.extraIndex["number"] = m;
    auto g = readGridVolume(path, one);
    ASSERT_TRUE(g.ok()) << g.error();
    members.push_back(std::move(*g));
  }
  const std::size_t n = members[0].values.size();
  for (const char* text : {"mean", "spread", "min", "max", "prob:>=11500", "prob:<11500", "prob:>12000"}) {
    auto stat = parseEnsembleStatistic(text);
    ASSERT_TRUE(stat.ok()) << stat.error();
    EXPECT_EQ(toString(*stat), text);
    GridReadOptions s = o;
    s.ensemble = *stat;
    auto g = readGridVolume(path, s);
    ASSERT_TRUE(g.ok()) << g.error();
    EXPECT_EQ(g->ensembleStatistic, text);
    EXPECT_EQ(g->ensembleMembers, (std::vector<long>{10, 11, 12}));
    EXPECT_EQ(g->member, -1);
    EXPECT_EQ(memberText(*g), std::string(text) + " of 3 members");
    ASSERT_EQ(g->values.size(), n);
    // Heights: the first member's.
    EXPECT_EQ(g->heightAboveEllipsoidMeters, members[0].heightAboveEllipsoidMeters);
    for (std::size_t i = 0; i < n; ++i) {
      double sum = 0.0, lo = 1e300, hi = -1e300;
      int passing = 0;
      for (const GridVolume& m : members) {
        const double x = m.values[i];
        sum += x;
        lo = std::min(lo, x);
        hi = std::max(hi, x);
        const std::string t = text;
        passing += t == "prob:>=11500" ? x >= 11500 : t == "prob:<11500" ? x < 11500 : x > 12000;
      }
      const double mean = sum / 3.0;
      double squares = 0.0;  // two passes, as written in the docs: sqrt(sum (x - mean)^2 / N)
      for (const GridVolume& m : members) squares += (m.values[i] - mean) * (m.values[i] - mean);
      const std::string t = text;
      if (t == "mean") {
        ASSERT_EQ(g->values[i], static_cast<float>(mean)) << i;
      } else if (t == "spread") {
        // The reader sums x and x^2 in one pass; against two passes in double the difference is
        // ~1e-12 relative before the cast to float: within one float step of the value.
        const float expected = static_cast<float>(std::sqrt(squares / 3.0));
        const float ulp = std::nextafter(expected, 1e30f) - expected;
        ASSERT_NEAR(g->values[i], expected, 2.0f * ulp) << i;
        ASSERT_GT(expected, 800.0f);  // the members differ by 1000 (a real spread, not 0)
      } else if (t == "min") {
        ASSERT_EQ(g->values[i], static_cast<float>(lo)) << i;
      } else if (t == "max") {
        ASSERT_EQ(g->values[i], static_cast<float>(hi)) << i;
      } else {
        ASSERT_EQ(g->values[i], static_cast<float>(100.0 * passing / 3.0)) << i;
        EXPECT_EQ(g->units, "%");
      }
    }
  }
  // What cannot be asked together, and a file without members.
  GridReadOptions both = o;
  both.ensemble = *parseEnsembleStatistic("mean");
  both.member = 11;
  auto r = readGridVolume(path, both);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "mean", "member 11", "one or the other"})) << r.error();
  both.member = -1;
  both.extraIndex["number"] = 1;
  r = readGridVolume(path, both);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "index 1 along 'number'"})) << r.error();
  Era5Like e;
  const std::string era = testDir() + "/era5_no_members.nc";
  writeEra5Like(era, e);
  GridReadOptions none;
  none.variable = "t";
  none.ensemble = *parseEnsembleStatistic("spread");
  r = readGridVolume(era, none);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {era, "no ensemble members", "spread"})) << r.error();
  for (const char* bad : {"median", "prob:", "prob:>=", "prob:=5", "prob:>=abc", "prob:>=1e999", "MEAN"}) {
    auto p = parseEnsembleStatistic(bad);
    ASSERT_FALSE(p.ok()) << bad;
    EXPECT_NE(p.error().find("expected mean, spread, min, max or prob:"), std::string::npos) << p.error();
  }
}

// An isobaric section (samplePressureSection): on a level, that level's values; between levels,
// the two interpolated in ln(p); horizontally the grid's bilinear weights. The ensemble's t codes
// are linear in the row and column (10 j + i) and in the level (100 k), so every pixel's value is
// known exactly.
TEST(GridArchiveLayouts, PressureSectionsInterpolateInLogPressure) {
  const std::string path = testDir() + "/ensemble_pressure.nc";
  writeEnsemble(path);
  SliceSourceOptions so;
  so.kind = SliceSourceOptions::Kind::Grid;
  so.path = path;
  so.field = "t";
  so.useGeoid = false;
  auto source = SliceSource::load(so);
  ASSERT_TRUE(source.ok()) << source.error();
  for (double hPa : {850.0, 700.0, 500.0}) {
    SliceRequest request;
    request.pressurePa = hPa * 100.0;
    request.box = LatLonBox{40.5, 44.5, 10.5, 17.0};
    request.columns = 26;
    request.rows = 16;
    auto geometry = sliceGeometryFor(**source, request);
    ASSERT_TRUE(geometry.ok()) << geometry.error();
    ASSERT_TRUE(geometry->pressurePa());
    auto raster = sampleSource(**source, *geometry);
    ASSERT_TRUE(raster.ok()) << raster.error();
    ASSERT_EQ(raster->echoCount, 26u * 16u);
    const double f = std::log(850.0 / hPa) / std::log(850.0 / 500.0);  // 0 at 850, 1 at 500
    for (int j = 0; j < raster->rows; ++j)
      for (int i = 0; i < raster->columns; ++i) {
        const atmoglobe::globe::Geodetic g = geometry->geodeticAt(i + 0.5, j + 0.5);
        const double expected = 100.0 * f + 10.0 * (g.latDeg - 40.0) / 2.5 + (g.lonDeg - 10.0) / 2.5;
        // Float values of codes below 200, a float weight: 1e-4.
        ASSERT_NEAR(raster->at(i, j), expected, 1e-4) << hPa << " hPa, pixel " << i << " " << j;
      }
  }
  // Outside the levels, and a grid not on pressure levels.
  SliceRequest low;
  low.pressurePa = 100000.0;
  auto outside = sliceGeometryFor(**source, low);
  ASSERT_FALSE(outside.ok());
  EXPECT_TRUE(mentions(outside.error(), {path, "1000 hPa is outside the levels", "850 to 500 hPa"})) << outside.error();
}

TEST(GridArchiveLayouts, LeadingMonthDimensionOfAClimatologyAndWhatInfoSays) {
  // A monthly climatology: t(month, level, lat, lon), month an int coordinate 1..12 without
  // units; level heights above sea level. The month is never the vertical dimension.
  const std::string path = testDir() + "/climatology.nc";
  {
    NcTestFile f(path, 0);
    f.globalText("Conventions", "CF-1.7");
    f.dim("month", 12);
    f.dim("level", 3);
    f.dim("lat", 2);
    f.dim("lon", 3);
    auto vm = f.var("month", NC_INT, {"month"});
    f.text(vm, "long_name", "month of the year");
    auto vl = f.var("level", NC_DOUBLE, {"level"});
    f.text(vl, "units", "km");
    f.text(vl, "standard_name", "altitude");
    auto vy = f.var("lat", NC_DOUBLE, {"lat"});
    f.text(vy, "units", "degrees_north");
    auto vx = f.var("lon", NC_DOUBLE, {"lon"});
    f.text(vx, "units", "degrees_east");
    auto vt = f.var("t", NC_FLOAT, {"month", "level", "lat", "lon"});
    f.text(vt, "units", "K");
    f.put(vm, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    f.put(vl, {1.0, 5.0, 10.0});
    f.put(vy, {-10.0, 10.0});
    f.put(vx, {100.0, 110.0, 120.0});
    std::vector<double> v;
    for (int m = 0; m < 12; ++m)
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 3; ++i) v.push_back(1000 * m + 100 * k + 10 * j + i);
    f.put(vt, v);
  }
  GridReadOptions o;
  o.useGeoid = false;
  auto jan = readGridVolume(path, o);
  ASSERT_TRUE(jan.ok()) << jan.error();
  EXPECT_EQ(jan->verticalKind, VerticalKind::HeightAboveSeaLevel);
  EXPECT_EQ(jan->verticalVariable, "/level");
  EXPECT_EQ(jan->member, -1);  // a month is not an ensemble member
  ASSERT_EQ(jan->nz, 3u);
  // Altitudes in km, as given (no geoid): 1, 5, 10 km.
  EXPECT_FLOAT_EQ(jan->heightMeters(2, 1, 2), 10000.0f);
  EXPECT_EQ(jan->value(2, 1, 2), 212.0f);
  o.extraIndex["month"] = 6;  // July
  auto jul = readGridVolume(path, o);
  ASSERT_TRUE(jul.ok()) << jul.error();
  ASSERT_EQ(jul->extraDimensions.size(), 1u);
  EXPECT_EQ(jul->extraDimensions[0].value, 7.0);
  EXPECT_FALSE(jul->extraDimensions[0].ensemble);
  EXPECT_EQ(jul->value(2, 1, 2), 6212.0f);
  EXPECT_EQ(jul->value(0, 0, 0), 6000.0f);
  // info: which extra dimension, its size, the index described.
  GridReadOptions d;
  d.extraIndex["month"] = 6;
  auto info = describeGridFile(path, d);
  ASSERT_TRUE(info.ok()) << info.error();
  const std::string text = describeGridText(*info);
  EXPECT_TRUE(mentions(text, {"month (12 values)", "index 6 (7)"})) << text;
  EXPECT_EQ(info->zDimension, "level");
  const std::string json = describeGridJson(*info);
  EXPECT_TRUE(mentions(json, {"\"extra_dimensions\"", "\"name\": \"month\"", "\"length\": 12", "\"index\": 6"}))
      << json;
  // The default description says index 0.
  auto info0 = describeGridFile(path);
  ASSERT_TRUE(info0.ok()) << info0.error();
  EXPECT_TRUE(mentions(describeGridText(*info0), {"month (12 values): described at index 0 (1)"}))
      << describeGridText(*info0);
}

// ---------------------------------------------------------------- CAM/NCL hybrid levels

namespace {

// CAM's hybrid levels, top first (hyam, hybm: p = hyam P0 + hybm PS).
const std::vector<double> kHyam = {0.2, 0.1, 0.02, 0.0};
const std::vector<double> kHybm = {0.0, 0.3, 0.75, 0.985};
double camSurfacePressurePa(std::size_t j, std::size_t i) {
  return 100500.0 - 900.0 * static_cast<double>(j) - 250.0 * static_cast<double>(i);
}

/// A CAM history file: lev with units "hybrid_sigma_pressure" and A_var/B_var/P0_var/PS_var
/// naming hyam, hybm, P0, PS (no formula_terms); `p0Pa` < 0: no P0 variable.
void writeCam(const std::string& path, double p0Pa, const std::string& aVar = "hyam") {
  NcTestFile f(path, 0);
  f.globalText("Conventions", "CF-1.0");
  f.globalText("source", "CAM");
  f.dim("time", 1);
  f.dim("lev", kHyam.size());
  f.dim("lat", 3);
  f.dim("lon", 4);
  auto vt = f.var("time", NC_DOUBLE, {"time"});
  f.text(vt, "units", "days since 2000-01-01 00:00:00");
  f.text(vt, "calendar", "noleap");
  auto vl = f.var("lev", NC_DOUBLE, {"lev"});
  f.text(vl, "long_name", "hybrid level at midpoints (1000*(A+B))");
  f.text(vl, "units", "hybrid_sigma_pressure");
  f.text(vl, "positive", "down");
  f.text(vl, "A_var", aVar);
  f.text(vl, "B_var", "hybm");
  f.text(vl, "P0_var", "P0");
  f.text(vl, "PS_var", "PS");
  auto vy = f.var("lat", NC_DOUBLE, {"lat"});
  f.text(vy, "units", "degrees_north");
  auto vx = f.var("lon", NC_DOUBLE, {"lon"});
  f.text(vx, "units", "degrees_east");
  auto va = f.var("hyam", NC_DOUBLE, {"lev"});
  f.text(va, "long_name", "hybrid A coefficient at layer midpoints");
  auto vb = f.var("hybm", NC_DOUBLE, {"lev"});
  f.text(vb, "long_name", "hybrid B coefficient at layer midpoints");
  NcTestFile::Var vp0;
  if (p0Pa >= 0) {
    vp0 = f.var("P0", NC_DOUBLE, {});
    f.text(vp0, "units", "Pa");
  }
  auto vps = f.var("PS", NC_FLOAT, {"time", "lat", "lon"});
  f.text(vps, "units", "Pa");
  auto vT = f.var("T", NC_FLOAT, {"time", "lev", "lat", "lon"});
  f.text(vT, "units", "K");
  f.put(vt, {31.0});
  std::vector<double> lev;
  for (std::size_t k = 0; k < kHyam.size(); ++k) lev.push_back(1000.0 * (kHyam[k] + kHybm[k]));
  f.put(vl, lev);
  f.put(vy, {40.0, 44.0, 48.0});
  f.put(vx, {0.0, 5.0, 10.0, 15.0});
  f.put(va, kHyam);
  f.put(vb, kHybm);
  if (p0Pa >= 0) f.put(vp0, {p0Pa});
  std::vector<double> ps, t;
  for (std::size_t j = 0; j < 3; ++j)
    for (std::size_t i = 0; i < 4; ++i) ps.push_back(camSurfacePressurePa(j, i));
  for (std::size_t k = 0; k < kHyam.size(); ++k)
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t i = 0; i < 4; ++i) t.push_back(static_cast<double>(100 * k + 10 * j + i));
  f.put(vps, ps);
  f.put(vT, t);
}

/// The U.S. Standard Atmosphere 1976 below 11 km by its closed form (REFERENCE.md section 4 and
/// the standard's troposphere: T0 = 288.15 K, lapse 6.5 K/km, p0 = 101325 Pa), geopotential
/// metres of pressure `p` (Pa): H = T0 / L (1 - (p / p0)^(R L / g0)), R = 287.05287.
double troposphereGeopotentialHeight(double pPa) {
  constexpr double kT0 = 288.15, kL = 0.0065, kP0 = 101325.0, kR = 287.05287;
  return kT0 / kL * (1.0 - std::pow(pPa / kP0, kR * kL / kG0));
}

}  // namespace

TEST(GridArchiveLayouts, CamHybridLevelsNamedByAttributesWithTheDefaultP0) {
  const std::string dir = testDir();
  writeCam(dir + "/cam_no_p0.nc", -1.0);
  writeCam(dir + "/cam_p0.nc", 100000.0);
  GridReadOptions o;
  o.useGeoid = false;
  auto r = readGridVolume(dir + "/cam_no_p0.nc", o);
  ASSERT_TRUE(r.ok()) << r.error();
  const GridVolume& g = *r;
  EXPECT_EQ(g.variable, "/T");
  EXPECT_EQ(g.verticalKind, VerticalKind::HybridSigmaPressure);
  EXPECT_EQ(g.heightSource, HeightSource::StandardAtmosphere);
  EXPECT_TRUE(g.approximateHeights);
  EXPECT_EQ(g.fileLevelStep, -1);  // top-first levels come out bottom first
  EXPECT_TRUE(mentions(g.heightNote, {"100000 Pa", "CAM", "'P0'", "A_var"})) << g.heightNote;
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t i = 0; i < 4; ++i) {
        const std::size_t kf = 3 - k;
        // Hand computation of the pressure: p = A P0 + B PS with CAM's P0 = 1000 hPa (PS as
        // stored, a float).
        const double ps = static_cast<double>(static_cast<float>(camSurfacePressurePa(j, i)));
        const double p = kHyam[kf] * 100000.0 + kHybm[kf] * ps;
        // Every level here is below 11 km (p >= 200 hPa at the top: 11.8 km in the standard
        // atmosphere is 226 hPa; the top level is 200 hPa at j = i = 0 only, hence > 22632 Pa is
        // checked). The standard's troposphere formula gives geopotential height; geometric
        // height differs by H^2 / r (<= 19 m at 11 km) and by the latitude's gravity (at 40-48 N,
        // g within 0.1 % of g0: <= 11 m): 30 m covers both.
        ASSERT_EQ(g.value(k, j, i), static_cast<float>(100 * kf + 10 * j + i));
        if (p > 22632.0) {
          ASSERT_NEAR(g.heightMeters(k, j, i), troposphereGeopotentialHeight(p), 30.0) << k << " " << j << " " << i;
          // And the geometric conversion by the independent rule above: 0.05 m covers the float
          // storage of heights (1 mm) and the standard's constants (R, T0) as the reader writes
          // them (to 1e-6).
          ASSERT_NEAR(g.heightMeters(k, j, i), referenceGeometricHeight(troposphereGeopotentialHeight(p), g.latDeg[j]),
                      0.05)
              << k << " " << j << " " << i;
        }
      }
  // P0 given as a variable of 100000 Pa: the same heights, and the note names it.
  auto withP0 = readGridVolume(dir + "/cam_p0.nc", o);
  ASSERT_TRUE(withP0.ok()) << withP0.error();
  EXPECT_TRUE(mentions(withP0->heightNote, {"'/P0'"})) << withP0->heightNote;
  EXPECT_EQ(withP0->heightNote.find("default"), std::string::npos) << withP0->heightNote;
  ASSERT_EQ(withP0->heightAboveEllipsoidMeters, g.heightAboveEllipsoidMeters);
}

TEST(GridArchiveLayouts, CamHybridLevelsNamingAMissingVariableAreAnError) {
  const std::string path = testDir() + "/cam_bad.nc";
  writeCam(path, 100000.0, "hyai");
  GridReadOptions o;
  o.variable = "T";
  auto r = readGridVolume(path, o);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "'/lev'", "A_var", "'hyai'", "not in the file"})) << r.error();
  // With no variable named: the same reason, from the 4-D variable (not the 2-D field PS).
  r = readGridVolume(path);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "'/lev'", "'hyai'"})) << r.error();
}

// ---------------------------------------------------------------- coordinates naming missing variables

TEST(GridArchiveLayouts, CoordinatesAttributeNamingMissingVariablesIsAnError) {
  const std::string path = testDir() + "/missing_coordinates.nc";
  {
    NcTestFile f(path);
    f.globalText("Conventions", "CF-1.8");
    f.dim("lev", 2);
    f.dim("y", 3);
    f.dim("x", 4);
    auto vl = f.var("lev", NC_DOUBLE, {"lev"});
    f.text(vl, "units", "hPa");
    auto vq = f.var("q", NC_FLOAT, {"lev", "y", "x"});
    f.text(vq, "coordinates", "lev XLAT_M XLONG_M");
    f.put(vl, {850.0, 500.0});
    f.put(vq, std::vector<double>(24, 1.0));
  }
  GridReadOptions o;
  o.variable = "q";
  auto r = readGridVolume(path, o);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(mentions(r.error(), {path, "'/q'", "coordinates", "'XLAT_M', 'XLONG_M'", "lacks"})) << r.error();
  auto d = describeGridFile(path, "q");
  ASSERT_FALSE(d.ok());
  EXPECT_TRUE(mentions(d.error(), {path, "'/q'", "'XLAT_M'"})) << d.error();
  // Named by nobody: the file holds no grid this reader can read, and says why.
  auto any = readGridVolume(path);
  ASSERT_FALSE(any.ok());
  EXPECT_TRUE(mentions(any.error(), {path, "'XLAT_M'"})) << any.error();
  EXPECT_FALSE(isGridFile(path));
}

// ---------------------------------------------------------------- packed geopotential, random layouts

// Round trips over random layouts of the packed-geopotential file: rows north to south or south
// to north, levels top or bottom first, a negative or positive scale_factor, classic or netCDF-4,
// a fixed or unlimited time axis, global or regional, whole or cropped (levels too); the
// variable read is t, its heights come from z. Every height is checked against the hand rule
// (unpacked z / g0, TR8350.2 solved by bisection) at the file indices its coordinates say.
TEST(GridArchiveLayouts, PackedGeopotentialHeightsOverRandomLayouts) {
  std::mt19937 rng(20261127);
  auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  auto pick = [&](int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); };
  const std::vector<double> pressures = {1000, 925, 850, 700, 500, 300, 200, 100};
  const std::string dir = testDir();
  for (int layout = 0; layout < 24; ++layout) {
    SCOPED_TRACE("layout " + std::to_string(layout));
    const bool northToSouth = pick(0, 1), topFirst = pick(0, 1), negative = pick(0, 1), global = pick(0, 1);
    const double step = global ? std::vector<double>{2.5, 3.0, 5.0}[static_cast<std::size_t>(pick(0, 2))]
                               : uniform(0.2, 2.0);
    const std::size_t ny = global ? static_cast<std::size_t>(std::lround(180.0 / step)) + 1
                                  : static_cast<std::size_t>(pick(2, 30));
    const std::size_t nx = global ? static_cast<std::size_t>(std::lround(360.0 / step))
                                  : static_cast<std::size_t>(pick(2, 30));
    const std::size_t nz = static_cast<std::size_t>(pick(2, 6)), nt = static_cast<std::size_t>(pick(1, 2));
    const double south = global ? -90.0 : uniform(-80.0, 80.0 - step * static_cast<double>(ny));
    const double west = global ? (pick(0, 1) ? -180.0 : 0.0) : uniform(-180.0, 180.0);
    std::vector<double> lat(ny), lon(nx), lev(pressures.begin(), pressures.begin() + static_cast<long>(nz));
    for (std::size_t j = 0; j < ny; ++j) lat[j] = south + step * static_cast<double>(northToSouth ? ny - 1 - j : j);
    for (std::size_t i = 0; i < nx; ++i) lon[i] = west + step * static_cast<double>(i);
    if (topFirst) std::reverse(lev.begin(), lev.end());
    // Geopotential near the standard atmosphere's (REFERENCE.md section 4) with waves on it.
    auto z = [&](std::size_t t, std::size_t k, std::size_t j, std::size_t i) {
      return kG0 * (44331.5 - 4946.62 * std::pow(100.0 * lev[k], 0.190263)) +
             300.0 * std::sin(0.05 * static_cast<double>(j) + 0.3 * static_cast<double>(t)) +
             200.0 * std::cos(0.07 * static_cast<double>(i));
    };
    double zMin = HUGE_VAL, zMax = -HUGE_VAL;
    for (std::size_t t = 0; t < nt; ++t)
      for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t j = 0; j < ny; ++j)
          for (std::size_t i = 0; i < nx; ++i) {
            zMin = std::min(zMin, z(t, k, j, i));
            zMax = std::max(zMax, z(t, k, j, i));
          }
    // grib_to_netcdf's packing: the extremes at -32766 and 32767, clear of the fill -32767.
    const double scale = (zMax - zMin) / 65533.0 * (negative ? -1.0 : 1.0);
    const double offset = (negative ? zMax : zMin) + 32766.0 * scale;
    auto packed = [&](std::size_t t, std::size_t k, std::size_t j, std::size_t i) {
      return static_cast<double>(std::lround((z(t, k, j, i) - offset) / scale));
    };
    const std::string path = dir + "/layout" + std::to_string(layout) + ".nc";
    {
      NcTestFile f(path, pick(0, 1) ? NC_NETCDF4 : 0);
      f.dim("longitude", nx);
      f.dim("latitude", ny);
      f.dim("level", nz);
      f.dim("time", pick(0, 1) ? NC_UNLIMITED : nt);
      auto vx = f.var("longitude", NC_FLOAT, {"longitude"});
      f.text(vx, "units", "degrees_east");
      auto vy = f.var("latitude", NC_FLOAT, {"latitude"});
      f.text(vy, "units", "degrees_north");
      auto vl = f.var("level", NC_INT, {"level"});
      f.text(vl, "units", "millibars");
      auto vt = f.var("time", NC_INT, {"time"});
      f.text(vt, "units", "hours since 1900-01-01 00:00:00.0");
      auto vz = f.var("z", NC_SHORT, {"time", "level", "latitude", "longitude"});
      f.number(vz, "scale_factor", NC_DOUBLE, {scale});
      f.number(vz, "add_offset", NC_DOUBLE, {offset});
      f.number(vz, "_FillValue", NC_SHORT, {-32767});
      f.number(vz, "missing_value", NC_SHORT, {-32767});
      f.text(vz, "units", "m**2 s**-2");
      f.text(vz, "standard_name", "geopotential");
      auto vta = f.var("t", NC_FLOAT, {"time", "level", "latitude", "longitude"});
      f.put(vx, lon);
      f.put(vy, lat);
      f.put(vl, lev);
      for (std::size_t t = 0; t < nt; ++t) {
        f.put(vt, {t}, {1}, {1.0e6 + 6.0 * static_cast<double>(t)});
        std::vector<double> zs, ts;
        for (std::size_t k = 0; k < nz; ++k)
          for (std::size_t j = 0; j < ny; ++j)
            for (std::size_t i = 0; i < nx; ++i) {
              zs.push_back(packed(t, k, j, i));
              ts.push_back(static_cast<double>(1000 * k + j));
            }
        f.put(vz, {t, 0, 0, 0}, {1, nz, ny, nx}, zs);
        f.put(vta, {t, 0, 0, 0}, {1, nz, ny, nx}, ts);
      }
    }
    auto described = describeGridFile(path, "t");
    ASSERT_TRUE(described.ok()) << described.error();
    for (int read = 0; read < 3; ++read) {
      GridReadOptions o;
      o.variable = "t";
      o.useGeoid = false;
      o.timeIndex = static_cast<std::size_t>(pick(0, static_cast<int>(nt) - 1));
      if (read > 0) {  // a crop inside the grid's latitudes, any longitudes, some levels
        const double s = uniform(std::min(lat.front(), lat.back()), std::max(lat.front(), lat.back()));
        o.crop.southDeg = s;
        o.crop.northDeg = std::min(90.0, s + uniform(0.0, 20.0));
        o.crop.westDeg = global ? uniform(-180.0, 180.0) : west + uniform(0.0, step * static_cast<double>(nx - 1));
        o.crop.eastDeg = o.crop.westDeg + uniform(0.0, 40.0);
        if (o.crop.eastDeg > 180.0) o.crop.eastDeg -= 360.0;
        o.crop.firstLevel = static_cast<std::size_t>(pick(0, static_cast<int>(nz) - 1));
        o.crop.levelCount = static_cast<std::size_t>(pick(1, static_cast<int>(nz)));
      }
      auto r = readGridVolume(path, o);
      ASSERT_TRUE(r.ok()) << r.error();
      const GridVolume& g = *r;
      // File indices from the coordinates the volume reports (exact: the file's floats).
      auto fileIndex = [](const std::vector<double>& axis, double v, bool longitude) {
        for (std::size_t q = 0; q < axis.size(); ++q) {
          const double a = static_cast<double>(static_cast<float>(axis[q]));
          if (longitude ? std::fabs(std::remainder(a - v, 360.0)) < 1e-9 : a == v) return q;
        }
        return axis.size();
      };
      std::vector<std::size_t> cols(g.nx);
      for (std::size_t i = 0; i < g.nx; ++i) cols[i] = fileIndex(lon, g.lonDeg[i], true);
      for (std::size_t k = 0; k < g.nz; ++k) {
        const std::size_t kf = fileIndex(lev, g.levelValues[k] / 100.0, false);
        ASSERT_LT(kf, nz);
        for (std::size_t j = 0; j < g.ny; ++j) {
          const std::size_t jf = fileIndex(lat, g.latDeg[j], false);
          ASSERT_LT(jf, ny);
          for (std::size_t i = 0; i < g.nx; ++i) {
            ASSERT_LT(cols[i], nx);
            const double zUnpacked = packed(o.timeIndex, kf, jf, cols[i]) * scale + offset;
            // 4 mm: float heights and the reader's Newton solution, as in the tests above.
            ASSERT_NEAR(g.heightMeters(k, j, i), referenceGeometricHeight(zUnpacked / kG0, g.latDeg[j]), 4e-3)
                << "read " << read << ", level " << k << ", row " << j << ", column " << i;
            ASSERT_EQ(g.value(k, j, i), static_cast<float>(1000 * kf + jf));
          }
        }
      }
    }
  }
}
