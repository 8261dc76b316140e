// GRIB's projected grids placed through PROJ (volume/src/grid/GribProjection.cpp), on messages made
// here by ecCodes' encoder (no sample data needed): every projection the reader takes, both
// scanning directions, spheres and the WGS84 spheroid, a grid across the antimeridian and one
// around the North Pole. The reference is ecCodes' own geo-iterator (grib_get_data): every
// point within 1e-6 deg, the bound.
#include "GribTestUtil.h"

#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridSampler.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

using namespace atmoglobe::volume;
using namespace atmoglobe_test::grib;

namespace {

struct Case {
  std::string name;
  const char* sample;
  std::vector<GribKey> keys;  ///< the grid keys (Ni, Nj set from nx, ny after these)
  long nx, ny;
  const char* projPrefix;  ///< what the reader's PROJ definition starts with
  /// How close to grib_get_data (deg): the 1e-6, but for rotated grids, where ecCodes'
  /// own unrotation is up to 4e-6 deg (0.4 m) off the exact rotation and rounded to 1e-6 deg
  /// (RotatedGridMatchesTheClosedFormRotation measures both).
  double eccodesToleranceDeg = 1e-6;
};

/// Keys every case shares after its own: a parameter on a height level, so the reader takes it.
std::vector<GribKey> commonKeys(const char* sample) {
  if (std::string(sample) == "GRIB1") return {{"indicatorOfTypeOfLevel", 105L}, {"level", 2L}};
  return {{"typeOfFirstFixedSurface", 103L}, {"scaledValueOfFirstFixedSurface", 2L}};
}

/// A polar stereographic grid of 62 x 62 points 100 km apart, true at 60 N, around the North Pole
/// (its first point at 50 N 45 W, 3060 km west and south of the pole on the plane).
std::vector<GribKey> polarAroundTheNorthPoleKeys() {
  return {{"gridType", std::string("polar_stereographic")},
          {"shapeOfTheEarth", 6L},
          {"Nx", 62L},
          {"Ny", 62L},
          {"latitudeOfFirstGridPointInDegrees", 50.0},
          {"longitudeOfFirstGridPointInDegrees", 315.0},
          {"LaDInDegrees", 60.0},
          {"orientationOfTheGridInDegrees", 0.0},
          {"DxInMetres", 100000.0},
          {"DyInMetres", 100000.0},
          {"projectionCentreFlag", 0L},
          {"iScansNegatively", 0L},
          {"jScansPositively", 1L}};
}

std::vector<Case> cases() {
  std::vector<Case> c;
  // Lambert conformal, secant (30 and 60 N) over North America, on the GRIB2 sphere of 6371229 m.
  c.push_back({"lambert_secant_grib2",
               "GRIB2",
               {{"gridType", std::string("lambert")},
                {"shapeOfTheEarth", 6L},
                {"Nx", 40L},
                {"Ny", 30L},
                {"latitudeOfFirstGridPointInDegrees", 21.5},
                {"longitudeOfFirstGridPointInDegrees", 235.0},
                {"LaDInDegrees", 38.5},
                {"LoVInDegrees", 262.5},
                {"Latin1InDegrees", 30.0},
                {"Latin2InDegrees", 60.0},
                {"DxInMetres", 90000.0},
                {"DyInMetres", 90000.0},
                {"iScansNegatively", 0L},
                {"jScansPositively", 1L}},
               40,
               30,
               "+proj=lcc "});
  // Lambert on the WGS84 spheroid (shape 5).
  c.push_back({"lambert_wgs84",
               "GRIB2",
               {{"gridType", std::string("lambert")},
                {"shapeOfTheEarth", 5L},
                {"Nx", 25L},
                {"Ny", 20L},
                {"latitudeOfFirstGridPointInDegrees", 45.0},
                {"longitudeOfFirstGridPointInDegrees", 2.0},
                {"LaDInDegrees", 50.0},
                {"LoVInDegrees", 10.0},
                {"Latin1InDegrees", 50.0},
                {"Latin2InDegrees", 50.0},
                {"DxInMetres", 25000.0},
                {"DyInMetres", 25000.0},
                {"iScansNegatively", 0L},
                {"jScansPositively", 1L}},
               25,
               20,
               "+proj=lcc "});
  // Polar stereographic around the North Pole (the pole inside the grid), true at 60 N.
  c.push_back({"polar_stereographic_north_pole_inside", "GRIB2", polarAroundTheNorthPoleKeys(), 62, 62,
               "+proj=stere +lat_0=90 "});
  // Polar stereographic GRIB1 (true at 60 N by definition). (With the South Pole on the plane,
  // ecCodes 2.28 keeps the scale true at 60 N, LaDInDegrees = 60, against the GRIB 1 definition
  // (60 S there): its points are then off by degrees; that case is checked against Snyder's
  // formulas below.)
  c.push_back({"polar_stereographic_north_grib1",
               "GRIB1",
               {{"gridType", std::string("polar_stereographic")},
                {"Nx", 30L},
                {"Ny", 25L},
                {"latitudeOfFirstGridPointInDegrees", 40.0},
                {"longitudeOfFirstGridPointInDegrees", 100.0},
                {"orientationOfTheGridInDegrees", 140.0},
                {"DxInMetres", 60000.0},
                {"DyInMetres", 60000.0},
                {"projectionCentreFlag", 0L},
                {"iScansNegatively", 0L},
                {"jScansPositively", 1L}},
               30,
               25,
               "+proj=stere +lat_0=90 "});
  // Mercator across the antimeridian (170 E eastward over 180).
  c.push_back({"mercator_across_the_antimeridian",
               "GRIB2",
               {{"gridType", std::string("mercator")},
                {"shapeOfTheEarth", 6L},
                {"Ni", 30L},
                {"Nj", 20L},
                {"latitudeOfFirstGridPointInDegrees", -10.0},
                {"longitudeOfFirstGridPointInDegrees", 170.0},
                {"LaDInDegrees", 20.0},
                {"DiInMetres", 45000.0},
                {"DjInMetres", 45000.0},
                {"iScansNegatively", 0L},
                {"jScansPositively", 1L}},
               30,
               20,
               "+proj=merc "});
  // Rotated lat/lon (COSMO-EU's pole: the grid's south pole at 40 S 10 E).
  c.push_back({"rotated_ll",
               "GRIB2",
               {{"gridType", std::string("rotated_ll")},
                {"Ni", 36L},
                {"Nj", 24L},
                {"latitudeOfFirstGridPointInDegrees", -6.0},
                {"longitudeOfFirstGridPointInDegrees", -8.0},
                {"latitudeOfLastGridPointInDegrees", 5.5},
                {"longitudeOfLastGridPointInDegrees", 9.5},
                {"iDirectionIncrementInDegrees", 0.5},
                {"jDirectionIncrementInDegrees", 0.5},
                {"latitudeOfSouthernPoleInDegrees", -40.0},
                {"longitudeOfSouthernPoleInDegrees", 10.0},
                {"iScansNegatively", 0L},
                {"jScansPositively", 1L}},
               36,
               24,
               "+proj=ob_tran ",
               5e-6});
  // Lambert azimuthal equal area (an INSPIRE-like European grid).
  c.push_back({"lambert_azimuthal_equal_area",
               "GRIB2",
               {{"gridType", std::string("lambert_azimuthal_equal_area")},
                {"shapeOfTheEarth", 6L},
                {"numberOfPointsAlongXAxis", 30L},
                {"numberOfPointsAlongYAxis", 20L},
                {"latitudeOfFirstGridPointInDegrees", 35.0},
                {"longitudeOfFirstGridPointInDegrees", -5.0},
                {"standardParallelInDegrees", 52.0},
                {"centralLongitudeInDegrees", 10.0},
                {"xDirectionGridLengthInMetres", 100000.0},
                {"yDirectionGridLengthInMetres", 100000.0},
                {"iScansNegatively", 0L},
                {"jScansPositively", 1L}},
               30,
               20,
               "+proj=laea "});
  return c;
}

}  // namespace

TEST(GribProjection, EveryProjectionAgreesWithEccodesGeoIterator) {
  SKIP_WITHOUT_ECCODES_TOOLS();
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    std::vector<GribKey> keys = c.keys;
    for (const GribKey& k : commonKeys(c.sample)) keys.push_back(k);
    const std::size_t n = static_cast<std::size_t>(c.nx * c.ny);
    std::vector<double> values(n);
    for (std::size_t p = 0; p < n; ++p) values[p] = 250.0 + 0.01 * static_cast<double>(p);  // distinct per point
    const std::string message = makeGribMessage(c.sample, keys, values);
    ASSERT_FALSE(message.empty());
    const std::string file = dir + "/" + c.name + (std::string(c.sample) == "GRIB1" ? ".grib1" : ".grib2");
    writeFile(file, message);
    const auto pts = gribGetData(file, "");
    ASSERT_EQ(pts.size(), n) << "grib_get_data does not place this grid";
    auto g = readGridVolume(file, GridReadOptions{});
    ASSERT_TRUE(g.ok()) << g.error();
    ASSERT_TRUE(g->curvilinear);
    EXPECT_EQ(g->projection.rfind(c.projPrefix, 0), 0u) << g->projection;
    ASSERT_EQ(g->nx, static_cast<std::size_t>(c.nx));
    ASSERT_EQ(g->ny, static_cast<std::size_t>(c.ny));
    // ecCodes' geo-iterator lists the points in its own order (west to east, south to north for
    // these grids, whatever the scanning mode), so points are matched by value: each message value
    // is 250 + 0.01 x its index in the message (encoded to 16 bits over a span of 0.01 n: 8e-5 steps,
    // far finer than the 0.01 between points).
    double maxLat = 0, maxLon = 0;
    for (const Point& p : pts) {
      const long index = std::lround((p.value - 250.0) / 0.01);
      ASSERT_TRUE(index >= 0 && index < static_cast<long>(n)) << p.value;
      const std::size_t j = static_cast<std::size_t>(index) / g->nx, i = static_cast<std::size_t>(index) % g->nx;
      ASSERT_NEAR(g->value(0, j, i), p.value, 1e-3) << "row " << j << " column " << i;  // float of ~250: 3e-5
      maxLat = std::max(maxLat, std::fabs(g->latDegAt(j, i) - p.latDeg));
      // At a pole every longitude names the same point.
      if (std::fabs(p.latDeg) < 90.0 - 1e-9) maxLon = std::max(maxLon, std::fabs(lonDiff(g->lonDegAt(j, i), p.lonDeg)));
    }
    EXPECT_LT(maxLat, c.eccodesToleranceDeg);
    EXPECT_LT(maxLon, c.eccodesToleranceDeg);
    std::printf("%-40s %s: latitude %.2e deg, longitude %.2e deg\n", c.name.c_str(), g->projection.c_str(), maxLat,
                maxLon);
  }
}

namespace {

constexpr double kPi = 3.14159265358979323846;
double rad(double d) { return d * kPi / 180.0; }
double deg(double r) { return r * 180.0 / kPi; }

/// The bytes a hexadecimal text spells (a fuzzer's input kept in a test).
std::string bytesOfHex(const std::string& hex) {
  std::string bytes;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2)
    bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return bytes;
}

/// A kept fuzz input (hex) written as dir/name; its size is checked so that a mistyped digit
/// shows. Returns the path.
std::string writeFuzzInput(const std::string& dir, const std::string& name, const std::string& hex,
                           std::size_t expectedBytes) {
  const std::string bytes = bytesOfHex(hex);
  EXPECT_EQ(bytes.size(), expectedBytes);
  const std::string file = dir + "/" + name;
  writeFile(file, bytes);
  return file;
}

/// A spherical projection written out from Snyder, "Map Projections: A Working Manual" (USGS
/// 1987): Lambert conformal conic (eqs. 15-1 to 15-5, 14-4; inverse 14-10, 15-9, 15-10) and polar
/// stereographic (21-33, 21-34 with true scale at latitude `trueDeg`; inverse 20-18, 21-39, 21-40).
struct SphereProjection {
  bool lambert = true;
  double radiusM = 6371229, lat1Deg = 0, lat2Deg = 0, lat0Deg = 0, lon0Deg = 0;
  bool south = false;  ///< polar stereographic: the South Pole on the plane
  double n() const {
    const double p1 = rad(lat1Deg), p2 = rad(lat2Deg);
    if (lat1Deg == lat2Deg) return std::sin(p1);
    return std::log(std::cos(p1) / std::cos(p2)) / std::log(std::tan(kPi / 4 + p2 / 2) / std::tan(kPi / 4 + p1 / 2));
  }
  double F() const { return std::cos(rad(lat1Deg)) * std::pow(std::tan(kPi / 4 + rad(lat1Deg) / 2), n()) / n(); }
  double rho(double latDeg) const { return radiusM * F() / std::pow(std::tan(kPi / 4 + rad(latDeg) / 2), n()); }
  std::pair<double, double> forward(double latDeg, double lonDeg) const {
    const double dl = rad(std::remainder(lonDeg - lon0Deg, 360.0));
    if (lambert) {
      const double r = rho(latDeg), r0 = rho(lat0Deg);
      return {r * std::sin(n() * dl), r0 - r * std::cos(n() * dl)};
    }
    const double k = radiusM * (1 + std::sin(std::fabs(rad(lat1Deg))));  // 2 R k0 at true latitude lat1
    if (!south) {
      const double r = k * std::tan(kPi / 4 - rad(latDeg) / 2);
      return {r * std::sin(dl), -r * std::cos(dl)};
    }
    const double r = k * std::tan(kPi / 4 + rad(latDeg) / 2);
    return {r * std::sin(dl), r * std::cos(dl)};
  }
  std::pair<double, double> inverse(double x, double y) const {  // latitude, longitude (deg)
    if (lambert) {
      const double nn = n(), r0 = rho(lat0Deg), s = nn < 0 ? -1.0 : 1.0;
      const double r = s * std::hypot(x, r0 - y);
      const double theta = std::atan2(s * x, s * (r0 - y));
      return {deg(2 * std::atan(std::pow(radiusM * F() / r, 1 / nn)) - kPi / 2), lon0Deg + deg(theta / nn)};
    }
    const double k = radiusM * (1 + std::sin(std::fabs(rad(lat1Deg))));
    const double r = std::hypot(x, y);
    if (!south) return {90.0 - deg(2 * std::atan(r / k)), lon0Deg + deg(std::atan2(x, -y))};
    return {-90.0 + deg(2 * std::atan(r / k)), lon0Deg + deg(std::atan2(x, y))};
  }
};

/// Reads the one-message file made from `keys` and returns the largest latitude and longitude
/// differences (deg) of its points from `expected(row, column)`.
template <typename Expected>
std::pair<double, double> largestDifference(const std::string& file, const Expected& expected) {
  auto g = readGridVolume(file, GridReadOptions{});
  EXPECT_TRUE(g.ok()) << g.error();
  if (!g.ok()) return {1e9, 1e9};
  double maxLat = 0, maxLon = 0;
  for (std::size_t j = 0; j < g->ny; ++j)
    for (std::size_t i = 0; i < g->nx; ++i) {
      const auto [lat, lon] = expected(j, i);
      maxLat = std::max(maxLat, std::fabs(g->latDegAt(j, i) - lat));
      maxLon = std::max(maxLon, std::fabs(lonDiff(g->lonDegAt(j, i), lon)));
    }
  return {maxLat, maxLon};
}

std::string makeFile(const std::string& dir, const std::string& name, const char* sample, std::vector<GribKey> keys,
                     std::size_t points) {
  for (const GribKey& k : commonKeys(sample)) keys.push_back(k);
  const std::string message = makeGribMessage(sample, keys, std::vector<double>(points, 280.0));
  const std::string file = dir + "/" + name;
  writeFile(file, message);
  return message.empty() ? std::string() : file;
}

// A 300-byte GRIB1 message cut down from a fuzz_grib finding: a reduced Gaussian sub-area whose
// pl has rows of no points. ecCodes asserted ("bottom != 0") and aborted the process when it
// worked out the grid's points. The index skips it, saying why, before that key is asked for.
TEST(GribProjection, AReducedGaussianGridWithARowOfNoPointsIsSkippedBeforeEcCodesAborts) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  const std::string hex =
      "4752494200012c01000034806294ff80a5010000110a120c0001000000000000150000000000000000000000000000000101"
      "020401303030310000000000e0002104ffff00600159fc000000008159fc0576edffff003000000000000014001900240028"
      "002d003247524942ffff000200000000000000bf00000015010062000004000107d703170c00000002000000540300000001"
      "f00000000106ffffffffffffffffffffffffffffff000000100000001f00000000ffffffff03938700000000003000000000"
      "01c9c380001e8480001e848000000000000000000000000000000000220400000000000000ff80000000010000000064ffff"
      "ffffffffffffffff00000000000000000000d900000000000000000000000000000000000c00000000000000000037373737";
  const std::string file = writeFuzzInput(dir, "row_of_no_points.grib", hex, 300);
  auto info = describeGridFile(file);
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.error().find("a reduced Gaussian grid with a row of no points"), std::string::npos) << info.error();
}

}  // namespace

// The first grid point is the first in scanning order, as the GRIB definition says (and wgrib2
// reads it): a grid scanning west (i negative) or south (j negative) extends west or south of it.
// ecCodes 2.28's geo-iterator places Lambert and polar stereographic grids from their first
// point eastward and northward whatever the scanning flags (and reorders the values to match),
// so it cannot be the reference here: Snyder's spherical formulas, written out above, are.
TEST(GribProjection, NegativeScanningExtendsFromTheFirstPointInItsDirections) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  struct Scan {
    long iNegative, jPositive;
  };
  for (const Scan scan : {Scan{1, 0}, Scan{0, 0}, Scan{1, 1}}) {
    SCOPED_TRACE("iScansNegatively " + std::to_string(scan.iNegative) + ", jScansPositively " +
                 std::to_string(scan.jPositive));
    // Lambert conformal, secant at 33 and 45 N, on the sphere of 6371229 m (GRIB2 shape 6).
    const SphereProjection lcc{true, 6371229, 33, 45, 40, 260, false};
    const double lat1 = 49.5, lon1 = 275.0, dxM = 30000, dyM = 20000;
    const long nx = 20, ny = 15;
    const std::string lf = makeFile(dir, "lambert.grib2", "GRIB2",
                                    {{"gridType", std::string("lambert")},
                                     {"shapeOfTheEarth", 6L},
                                     {"Nx", nx},
                                     {"Ny", ny},
                                     {"latitudeOfFirstGridPointInDegrees", lat1},
                                     {"longitudeOfFirstGridPointInDegrees", lon1},
                                     {"LaDInDegrees", 40.0},
                                     {"LoVInDegrees", 260.0},
                                     {"Latin1InDegrees", 33.0},
                                     {"Latin2InDegrees", 45.0},
                                     {"DxInMetres", dxM},
                                     {"DyInMetres", dyM},
                                     {"iScansNegatively", scan.iNegative},
                                     {"jScansPositively", scan.jPositive}},
                                    static_cast<std::size_t>(nx * ny));
    ASSERT_FALSE(lf.empty());
    const auto [x0, y0] = lcc.forward(lat1, lon1);
    const double sx = scan.iNegative ? -dxM : dxM, sy = scan.jPositive ? dyM : -dyM;
    const auto [lat, lon] = largestDifference(lf, [&](std::size_t j, std::size_t i) {
      return lcc.inverse(x0 + static_cast<double>(i) * sx, y0 + static_cast<double>(j) * sy);
    });
    // 1e-9 deg (0.1 mm): double rounding through tan/pow/atan of two implementations.
    EXPECT_LT(lat, 1e-9);
    EXPECT_LT(lon, 1e-9);

    // Polar stereographic, South Pole on the plane, GRIB 1 (true at 60 S by definition; sphere
    // of 6367470 m).
    const SphereProjection ps{false, 6367470, -60, 0, -90, 140, true};
    const std::string pf = makeFile(dir, "polar.grib1", "GRIB1",
                                    {{"gridType", std::string("polar_stereographic")},
                                     {"Nx", nx},
                                     {"Ny", ny},
                                     {"latitudeOfFirstGridPointInDegrees", -40.0},
                                     {"longitudeOfFirstGridPointInDegrees", 100.0},
                                     {"orientationOfTheGridInDegrees", 140.0},
                                     {"DxInMetres", 60000.0},
                                     {"DyInMetres", 60000.0},
                                     {"projectionCentreFlag", 128L},
                                     {"iScansNegatively", scan.iNegative},
                                     {"jScansPositively", scan.jPositive}},
                                    static_cast<std::size_t>(nx * ny));
    ASSERT_FALSE(pf.empty());
    const auto [px0, py0] = ps.forward(-40.0, 100.0);
    const double psx = scan.iNegative ? -60000.0 : 60000.0, psy = scan.jPositive ? 60000.0 : -60000.0;
    const auto [plat, plon] = largestDifference(pf, [&](std::size_t j, std::size_t i) {
      return ps.inverse(px0 + static_cast<double>(i) * psx, py0 + static_cast<double>(j) * psy);
    });
    EXPECT_LT(plat, 1e-9);
    EXPECT_LT(plon, 1e-9);
  }
}

// A rotated grid against the rotation written out here (the grid's point as a unit vector in the
// rotated frame, turned by 90 deg + the south pole's latitude about the y axis, then by the south
// pole's longitude about the polar axis): the reader to 1e-9 deg. ecCodes' geo-iterator on the
// same file is measured too: rounded to 1e-6 deg and up to 4e-6 deg off, which is why the
// comparison with grib_get_data above allows 5e-6 deg for rotated grids.
TEST(GribProjection, RotatedGridMatchesTheClosedFormRotation) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  const double spLat = -40, spLon = 10, lat1 = -6, lon1 = -8, step = 0.25;
  const long ni = 40, nj = 30;
  const std::string file = makeFile(dir, "rotated.grib2", "GRIB2",
                                    {{"gridType", std::string("rotated_ll")},
                                     {"Ni", ni},
                                     {"Nj", nj},
                                     {"latitudeOfFirstGridPointInDegrees", lat1},
                                     {"longitudeOfFirstGridPointInDegrees", lon1},
                                     {"latitudeOfLastGridPointInDegrees", lat1 + step * (nj - 1)},
                                     {"longitudeOfLastGridPointInDegrees", lon1 + step * (ni - 1)},
                                     {"iDirectionIncrementInDegrees", step},
                                     {"jDirectionIncrementInDegrees", step},
                                     {"latitudeOfSouthernPoleInDegrees", spLat},
                                     {"longitudeOfSouthernPoleInDegrees", spLon},
                                     {"iScansNegatively", 0L},
                                     {"jScansPositively", 1L}},
                                    static_cast<std::size_t>(ni * nj));
  ASSERT_FALSE(file.empty());
  auto unrotate = [&](std::size_t j, std::size_t i) {
    const double la = rad(lat1 + step * static_cast<double>(j)), lo = rad(lon1 + step * static_cast<double>(i));
    const double x = std::cos(la) * std::cos(lo), y = std::cos(la) * std::sin(lo), z = std::sin(la);
    const double th = -rad(90 + spLat);
    const double x2 = std::cos(th) * x + std::sin(th) * z, z2 = -std::sin(th) * x + std::cos(th) * z;
    return std::make_pair(deg(std::asin(z2)), deg(std::atan2(y, x2)) + spLon);
  };
  const auto [lat, lon] = largestDifference(file, unrotate);
  EXPECT_LT(lat, 1e-9);
  EXPECT_LT(lon, 1e-9);
  if (haveTool("grib_get_data")) {
    const auto pts = gribGetData(file, "");
    ASSERT_EQ(pts.size(), static_cast<std::size_t>(ni * nj));
    double eLat = 0, eLon = 0;
    for (std::size_t p = 0; p < pts.size(); ++p) {
      const auto [la, lo] = unrotate(p / static_cast<std::size_t>(ni), p % static_cast<std::size_t>(ni));
      eLat = std::max(eLat, std::fabs(pts[p].latDeg - la));
      eLon = std::max(eLon, std::fabs(lonDiff(pts[p].lonDeg, lo)));
    }
    std::printf("grib_get_data against the closed-form rotation: latitude %.2e deg, longitude %.2e deg\n", eLat, eLon);
    EXPECT_LT(std::max(eLat, eLon), 5e-6);
  }
  // An angle of rotation is refused, saying so (decoders disagree on its sense).
  const std::string angled = makeFile(dir, "rotated_angle.grib2", "GRIB2",
                                      {{"gridType", std::string("rotated_ll")},
                                       {"Ni", ni},
                                       {"Nj", nj},
                                       {"latitudeOfSouthernPoleInDegrees", spLat},
                                       {"longitudeOfSouthernPoleInDegrees", spLon},
                                       {"angleOfRotationInDegrees", 15.0}},
                                      static_cast<std::size_t>(ni * nj));
  ASSERT_FALSE(angled.empty());
  auto refused = readGridVolume(angled, GridReadOptions{});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find(angled), std::string::npos) << refused.error();
  EXPECT_NE(refused.error().find("angle of rotation (15 deg) is not read"), std::string::npos) << refused.error();
}

// A polar stereographic grid around the North Pole on three heights above sea level, made here,
// read and sampled: every grid point gives its own value (the sampler's curvilinear lookup finds
// the cells of a grid whose longitudes run all the way round), and the pole itself, inside the
// grid, has data (no hole where the longitudes meet).
TEST(GribProjection, PolarGridAroundThePoleSamplesEverywhere) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  const long nx = 62, ny = 62;
  const double levelsM[] = {1000, 3000, 6000};
  std::string content;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> values(static_cast<std::size_t>(nx * ny));
    for (long j = 0; j < ny; ++j)
      for (long i = 0; i < nx; ++i)
        values[static_cast<std::size_t>(j * nx + i)] =
            250.0 + static_cast<double>(i) + 2.0 * static_cast<double>(j) + 100.0 * k;
    std::vector<GribKey> keys = polarAroundTheNorthPoleKeys();
    keys.push_back({"typeOfFirstFixedSurface", 102L});  // height above mean sea level
    keys.push_back({"scaleFactorOfFirstFixedSurface", 0L});
    keys.push_back({"scaledValueOfFirstFixedSurface", static_cast<long>(levelsM[k])});
    content += makeGribMessage("GRIB2", keys, values);
  }
  const std::string file = dir + "/polar_levels.grib2";
  writeFile(file, content);
  auto g = readGridVolume(file, GridReadOptions{});
  ASSERT_TRUE(g.ok()) << g.error();
  ASSERT_EQ(g->nz, 3u);
  ASSERT_TRUE(g->curvilinear);
  // The messages read (what the bench's ecCodes floor decodes again): the three levels, each once,
  // at the offsets where they were written, adding up to bytesRead.
  ASSERT_EQ(g->gribMessagesRead.size(), 3u);
  std::uint64_t sum = 0;
  for (const auto& m : g->gribMessagesRead) {
    EXPECT_EQ(m.path, file);
    EXPECT_FALSE(m.compressed);
    EXPECT_EQ(content.compare(m.offset, 4, "GRIB"), 0) << m.offset;
    sum += m.length;
  }
  EXPECT_EQ(sum, g->bytesRead);
  EXPECT_EQ(sum, content.size());
  GridSampler s(*g);
  std::size_t checked = 0;
  for (std::size_t k = 0; k < g->nz; ++k)
    for (std::size_t j = 0; j < g->ny; j += 3)
      for (std::size_t i = 0; i < g->nx; i += 3) {
        // 1 cm inside the bottom and top levels: exactly on them, a hair of weight on a
        // neighbour column (the inverse's rounding) puts the point below or above its column.
        // The value moves by 100 x 0.01 / 2000 = 5e-4 there (values are linear in height).
        const double h = g->heightMeters(k, j, i) + (k == 0 ? 0.01 : k + 1 == g->nz ? -0.01 : 0.0);
        auto v = s.sampleGeodetic(g->latDegAt(j, i), g->lonDegAt(j, i), h, Interpolation::Linear);
        ASSERT_EQ(v.state, VolumeSample::State::Echo) << "row " << j << " column " << i << " level " << k;
        // 1e-3: the point's value is a float of ~500; the lookup's Newton inverse is exact to 1e-10 of a cell.
        ASSERT_NEAR(v.value, g->value(k, j, i), 1e-3) << "row " << j << " column " << i << " level " << k;
        ++checked;
      }
  EXPECT_GT(checked, 1000u);
  // The pole: between columns 30 and 31 and rows 30 and 31 (the grid is centred on it to 10 m).
  auto pole = s.sampleGeodetic(90.0, 0.0, 3000.0 + 50.0, Interpolation::Linear);
  ASSERT_EQ(pole.state, VolumeSample::State::Echo);
  EXPECT_GT(pole.value, 350.0 + 30 + 2 * 30 - 1e-3);
  EXPECT_LT(pole.value, 350.0 + 31 + 2 * 31 + 1e-3);
}

// A 191-byte message fuzzing made (fuzz_grib): a rotated grid declaring 16 x 6094860 points (97.5
// million) over a data section of 496. Refused naming the message and both counts before anything
// of the declared size is allocated (it took 2.6 GB before); and a grid whose declared size is
// consistent but beyond the reader's limit (a constant field needs no bytes per point) is refused
// too (a regular grid of 4100 x 4000 points: the limit is 16 million).
TEST(GribProjection, DeclaredGridSizesAreCheckedBeforeAllocating) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  const std::string hex =
      "47524942ffff000200000000000000bf00000015010062000004000107d703170c00000002000000540300000001f0000000"
      "0106ffffffffffffffffffffffffffffff00000010005d000c00000000ffffffff0393870000000000300000000001c9c380"
      "001e8480001e848000000000000000000000000000000000220400000000000000ff80000000010000000064ffffffffffff"
      "ffffffffff0000001505000001f000003f800000800a000000000000000606ff000000050737373737";
  const std::string file = writeFuzzInput(dir, "declared_rows.grib2", hex, 191);
  auto info = describeGridFile(file);
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.error().find(file), std::string::npos) << info.error();
  EXPECT_NE(info.error().find("its grid has 16 x 6094860 points, its data 496 points (numberOfDataPoints)"),
            std::string::npos)
      << info.error();

  // 16.4 million points of one value: the message is a few hundred bytes.
  const std::string big = dir + "/constant_16.4M.grib2";
  writeFile(big, makeGribMessage("GRIB2", {{"Ni", 4100L}, {"Nj", 4000L}}, std::vector<double>(4100 * 4000, 280.0)));
  auto refused = readGridVolume(big, GridReadOptions{});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("a grid of 16400000 points (4100 x 4000 points) is beyond the 16000000 points one "
                                 "message may have here"),
            std::string::npos)
      << refused.error();
}

// A 172-byte message from fuzz_grib with a forecast step of 1.9e9 hours: ecCodes computes its
// validity time a day at a time (over 30 s). The index skips it with a warning naming the step;
// with nothing else in the file, the file is refused at once.
TEST(GribProjection, AnAbsurdForecastStepIsSkippedBeforeTheValidityTimeIsComputed) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  const std::string hex =
      "47524942ffff000200000000000000ac00000015010062000004000107d703170c00000002000000410300000001f0000000"
      "1406ffffffffffffffffffffffffffffff000000100000001f0393870000000000000000000000000000001e8480001e8480"
      "0000000000220400000000000000ff8000006d697373696e67ffffffffffffffffffffff0000001505000001f000003f8000"
      "00800a000000000000000606ff000000050737373737";
  const std::string file = writeFuzzInput(dir, "step.grib2", hex, 172);
  const auto t0 = std::chrono::steady_clock::now();
  auto info = describeGridFile(file);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.error().find(file + ": no readable GRIB message"), std::string::npos) << info.error();
  EXPECT_LT(seconds, 5.0);  // 30 s and more before; 5 s: a loaded machine under ASan
  // Beside a good message, the good one is read and the bad one named in a warning.
  const std::string pair = dir + "/good_and_step.grib2";
  writeFile(pair, makeGribMessage("GRIB2", {}, std::vector<double>(496, 280.0)) + bytesOfHex(hex));
  auto both = describeGridFile(pair);
  ASSERT_TRUE(both.ok()) << both.error();
  ASSERT_EQ(both->warnings.size(), 1u);
  EXPECT_NE(both->warnings[0].find("a forecast step of 1936943470 units; skipped"), std::string::npos)
      << both->warnings[0];
}

// A 107-byte GRIB1 message from fuzz_grib whose step ecCodes cannot represent in its units
// ("unable to represent the step"): endStep reads as nothing, and the validity time computed
// next never ended (over 120 s). The index skips it, saying the step cannot be read.
TEST(GribProjection, AStepEcCodesCannotReadIsSkippedBeforeTheValidityTimeIsComputed) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_projection");
  const std::string hex =
      "4752494200006b01006b0100003480627fff80816401f40603100c0001000000000000150000000000000000000000000000"
      "0001010204013030303100000000002000ff00016800b5015f9000000080815f90057a5803e803e8000000000000000b0080"
      "026e0037373737";
  const std::string file = writeFuzzInput(dir, "unreadable_step.grib", hex, 107);
  const auto t0 = std::chrono::steady_clock::now();
  auto info = describeGridFile(file);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_FALSE(info.ok());
  EXPECT_NE(info.error().find("its forecast step cannot be read"), std::string::npos) << info.error();
  EXPECT_LT(seconds, 5.0);  // over 120 s before; 5 s: a loaded machine under ASan
}
