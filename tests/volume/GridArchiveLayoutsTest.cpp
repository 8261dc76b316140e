// The forecast-grid reader on layouts real archives use, each in a small netCDF file written
// here: extra index dimensions (ensemble members, months), geopotential packed in shorts with a
// negative scale_factor on a north-to-south, top-first pressure grid (ERA5 style), CAM/NCL
// hybrid levels named by A_var/B_var/P0_var/PS_var, and a `coordinates` attribute naming
// variables the file lacks.
#include "NcTestFile.h"

#include <atmoglobe/volume/GridReader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
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
