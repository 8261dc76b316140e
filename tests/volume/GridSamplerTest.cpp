// The forecast grid's CPU sampler (GridSampler.h): linear fields reproduced exactly in the grid's
// own geometry (terrain-following levels, rectilinear and curvilinear), no data outside, a global
// grid closed across the antimeridian and over the poles, its empty-space grid conservative, and
// the reference renderer's DVR of a uniform slab against its closed form.
#include "SyntheticGridVolume.h"

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/AnalyticVolume.h>
#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/ReferenceRenderer.h>
#include <atmoglobe/volume/RenderCamera.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <string>

namespace {

using namespace atmoglobe;
using volume::GridVolume;
using volume::Interpolation;
using volume::VolumeSample;

}  // namespace

// A field linear in longitude, latitude and height on terrain-following levels is reproduced at
// any point inside: bilinear in a uniform rectilinear grid is linear in lon/lat, the level
// heights blend like the values, and the sample is linear in height between levels.
TEST(GridSampler, LinearFieldIsReproducedOnTerrainFollowingLevels) {
  auto surface = [](double lat, double lon) { return 300.0 + 20.0 * (lat - 40.0) + 15.0 * (lon - 10.0); };
  auto field = [](double lat, double lon, double h) { return 2.0 * lon - 3.0 * lat + 0.004 * h; };
  const GridVolume g =
      testutil::rectilinearGrid(testutil::evenlySpaced(10.0, 0.25, 41), testutil::evenlySpaced(40.0, 0.25, 41),
                                {0.0, 100.0, 300.0, 700.0, 1500.0, 3000.0, 6000.0, 12000.0}, surface, field);
  const volume::GridSampler s(g);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> lat(40.0, 50.0), lon(10.0, 20.0), u(0.0, 1.0);
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n) {
    const double la = lat(rng), lo = lon(rng);
    const double h = surface(la, lo) + u(rng) * 12000.0;
    const VolumeSample v = s.sample(globe::geodeticToEcef({la, lo, h}), Interpolation::Linear);
    ASSERT_EQ(v.state, VolumeSample::State::Echo) << la << " " << lo << " " << h;
    worst = std::max(worst, std::abs(v.value - field(la, lo, h)));
  }
  std::cout << "linear field: worst |sample - exact| " << worst << "\n";
  // Values and heights are stored as float (relative 6e-8 of ~100 and of 12 km: 6e-6 and
  // 0.7 mm -> 3e-6 in the field) plus the ECEF round trip (~1e-9 m).
  EXPECT_LT(worst, 5e-5);
  // Below the lowest level, above the highest, outside the box: no data.
  EXPECT_EQ(s.sample(globe::geodeticToEcef({45.0, 15.0, surface(45, 15) - 1.0}), Interpolation::Linear).state,
            VolumeSample::State::NoData);
  EXPECT_EQ(s.sample(globe::geodeticToEcef({45.0, 15.0, surface(45, 15) + 12001.0}), Interpolation::Linear).state,
            VolumeSample::State::NoData);
  EXPECT_EQ(s.sample(globe::geodeticToEcef({45.0, 20.01, 5000.0}), Interpolation::Linear).state,
            VolumeSample::State::NoData);
  EXPECT_EQ(s.sample(globe::geodeticToEcef({39.99, 15.0, 5000.0}), Interpolation::Linear).state,
            VolumeSample::State::NoData);
  // Nearest: a grid point's own value at the grid point's position and level height.
  const double h = g.heightMeters(3, 8, 12);
  const VolumeSample nearest = s.sample(globe::geodeticToEcef({g.latDeg[8], g.lonDeg[12], h}), Interpolation::Nearest);
  ASSERT_EQ(nearest.state, VolumeSample::State::Echo);
  EXPECT_FLOAT_EQ(static_cast<float>(nearest.value), g.value(3, 8, 12));
  // A missing value makes the samples that need it no data, not zero.
  GridVolume holed = g;
  holed.values[holed.index(3, 8, 12)] = NAN;
  const volume::GridSampler sh(holed);
  EXPECT_EQ(sh.sampleGeodetic(g.latDeg[8] + 0.1, g.lonDeg[12] + 0.1, h, Interpolation::Linear).state,
            VolumeSample::State::NoData);
}

// The bounding sphere holds every grid point (bottom and top), and ray intervals hold the grid.
TEST(GridSampler, BoundingSphereHoldsTheGrid) {
  const GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(-30.0, 0.5, 121), testutil::evenlySpaced(20.0, 0.5, 61), {0.0, 5000.0, 20000.0},
      [](double, double) { return 0.0; }, [](double, double, double) { return 1.0; });
  const volume::GridSampler s(g);
  const volume::BoundingSphere b = s.boundingSphere();
  double worstInside = -1e300;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i)
      for (double h : {0.0, 20000.0})
        worstInside =
            std::max(worstInside,
                     glm::length(globe::geodeticToEcef({g.latDeg[j], g.lonDeg[i], h}) - b.centreEcef) - b.radiusMeters);
  EXPECT_LE(worstInside, 0.0) << "a grid point lies outside the bounding sphere";
}

// A global grid: continuous across the antimeridian and its own seam (last column to the first),
// closed over both poles (no hole, one value at the pole whatever the longitude).
TEST(GridSampler, GlobalGridHasNoSeamAtTheAntimeridianAndNoHoleAtThePoles) {
  auto field = [](double lat, double lon, double) {
    return std::cos(lon * kPi / 180.0) * std::cos(lat * kPi / 180.0) + 0.5 * std::sin(lat * kPi / 180.0);
  };
  GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 2.5, 144), testutil::evenlySpaced(-88.75, 2.5, 72), {0.0, 10000.0},
      [](double, double) { return 0.0; }, field);
  g.wrapsLongitude = true;
  const volume::GridSampler s(g);
  // Across the antimeridian and across the seam between 357.5 and 360 (= 0): every sample is
  // data, and neighbouring samples differ by no more than the field's change (bilinear in a
  // smooth field: steps of 0.01 deg change it by < 2e-4).
  double prev = NAN, worstJump = 0.0;
  for (double lon = 175.0; lon <= 185.0; lon += 0.01) {
    const VolumeSample v = s.sampleGeodetic(30.0, lon > 180.0 ? lon - 360.0 : lon, 5000.0, Interpolation::Linear);
    ASSERT_EQ(v.state, VolumeSample::State::Echo) << lon;
    if (std::isfinite(prev)) worstJump = std::max(worstJump, std::abs(v.value - prev));
    prev = v.value;
  }
  prev = NAN;
  for (double lon = 355.0; lon <= 365.0; lon += 0.01) {
    const VolumeSample v = s.sampleGeodetic(30.0, lon, 5000.0, Interpolation::Linear);
    ASSERT_EQ(v.state, VolumeSample::State::Echo) << lon;
    if (std::isfinite(prev)) worstJump = std::max(worstJump, std::abs(v.value - prev));
    prev = v.value;
  }
  EXPECT_LT(worstJump, 2e-4);
  // Poles: data everywhere in the caps; at the pole one value, whatever the longitude; the cap
  // joins the last row continuously.
  for (double lat : {88.75, 89.0, 89.9, 90.0, -88.75, -89.5, -90.0}) {
    double lo = 1e300, hi = -1e300;
    for (double lon = -180.0; lon < 180.0; lon += 7.3) {
      const VolumeSample v = s.sampleGeodetic(lat, lon, 5000.0, Interpolation::Linear);
      ASSERT_EQ(v.state, VolumeSample::State::Echo) << lat << " " << lon;
      lo = std::min(lo, v.value);
      hi = std::max(hi, v.value);
    }
    if (std::abs(lat) == 90.0) {
      EXPECT_LT(hi - lo, 1e-6) << "one value at the pole " << lat;
    }
  }
  const double atRow = s.sampleGeodetic(88.75, 40.0, 5000.0, Interpolation::Linear).value;
  const double justAbove = s.sampleGeodetic(88.7501, 40.0, 5000.0, Interpolation::Linear).value;
  EXPECT_NEAR(atRow, justAbove, 1e-4);
  // The sphere of a global grid is the whole atmosphere.
  EXPECT_EQ(s.boundingSphere().centreEcef, glm::dvec3(0.0));
}

// The grid's empty-space grid (built in volume, uploaded by GridVolumeGL) is conservative: a
// point whose sample is Echo with value v lies in a cell whose value is >= v. A regional grid on
// terrain (ENU frame) and a global one (ECEF axes; the seam and the pole caps closed).
TEST(GridOccupancy, IsConservativeForRandomPointsInsideTheGrid) {
  auto field = [](double lat, double lon, double h) {
    return 40.0 * std::sin(lat * 0.3) * std::cos(lon * 0.2) - h / 1000.0;
  };
  for (const bool global : {false, true}) {
    GridVolume g = global ? testutil::rectilinearGrid(
                                testutil::evenlySpaced(0.0, 2.5, 144), testutil::evenlySpaced(-88.75, 2.5, 72),
                                {0.0, 3000.0, 6000.0, 9000.0, 12000.0}, [](double, double) { return 0.0; }, field)
                          : testutil::rectilinearGrid(
                                testutil::evenlySpaced(-100.0, 0.05, 60), testutil::evenlySpaced(30.0, 0.05, 50),
                                {0.0, 500.0, 1500.0, 3000.0, 6000.0, 9000.0, 12000.0},
                                [](double lat, double lon) { return 300.0 + 200.0 * std::sin(lat * 7.0 + lon * 5.0); },
                                field);
    g.wrapsLongitude = global;
    const volume::GridSampler s(g);
    const volume::OccupancyGrid occ = volume::buildOccupancyGrid(s);
    ASSERT_EQ(occ.cells, glm::ivec3(128, 128, 32));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> lat(global ? -90.0 : 29.9, global ? 90.0 : 32.55),
        lon(global ? -180.0 : -100.1, global ? 180.0 : -96.95), h(-100.0, 12600.0);
    int echoes = 0, violations = 0;
    for (int n = 0; n < 100000; ++n) {
      const double la = lat(rng), lo = lon(rng), hm = h(rng);
      const VolumeSample v = s.sampleGeodetic(la, lo, hm, Interpolation::Linear);
      if (v.state != VolumeSample::State::Echo) continue;
      ++echoes;
      const glm::dvec3 local = occ.localOfEcef(globe::geodeticToEcef({la, lo, hm}));
      if (occ.maxAtLocal(local) < static_cast<float>(v.value)) ++violations;
    }
    std::cout << (global ? "global" : "regional") << ": " << echoes << " echo points, " << violations
              << " in a cell below their value\n";
    EXPECT_GT(echoes, 20000);
    EXPECT_EQ(violations, 0);
  }
}

// A curvilinear grid (rotated and sheared latitude/longitude, as a Lambert or Mercator model
// domain is in degrees): the inverse map is exact to rounding, so a field linear in the grid
// indices is reproduced at the position of any fractional index.
TEST(GridSampler, CurvilinearInverseMapIsExact) {
  GridVolume g;
  g.curvilinear = true;
  g.nx = 60;
  g.ny = 50;
  g.nz = 3;
  auto latOf = [](double i, double j) { return 25.0 + 0.09 * j + 0.02 * i + 0.0004 * i * j; };
  auto lonOf = [](double i, double j) { return -95.0 + 0.1 * i - 0.03 * j; };
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      g.latDeg.push_back(latOf(double(i), double(j)));
      g.lonDeg.push_back(lonOf(double(i), double(j)));
    }
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i) {
        g.heightAboveEllipsoidMeters.push_back(static_cast<float>(1000.0 * static_cast<double>(k)));
        g.values.push_back(
            static_cast<float>(3.0 * static_cast<double>(i) + 7.0 * static_cast<double>(j) + static_cast<double>(k)));
      }
  g.valueMin = 0.0f;
  g.valueMax = 3.0f * 59 + 7.0f * 49 + 2.0f;
  const volume::GridSampler s(g);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ui(0.0, 59.0), uj(0.0, 49.0);
  double worst = 0.0;
  for (int n = 0; n < 3000; ++n) {
    const double i = ui(rng), j = uj(rng);
    // latOf and lonOf are bilinear within each cell (a + b i + c j + d i j), so the grid's own
    // map (the bilinear blend of a cell's corners) puts index (i, j) exactly at (latOf, lonOf).
    const std::optional<glm::dvec2> ij = s.horizontalIndex(latOf(i, j), lonOf(i, j));
    ASSERT_TRUE(ij) << i << " " << j;
    worst = std::max(worst, glm::length(*ij - glm::dvec2(i, j)));
    const VolumeSample v = s.sampleGeodetic(latOf(i, j), lonOf(i, j), 500.0, Interpolation::Linear);
    ASSERT_EQ(v.state, VolumeSample::State::Echo);
    EXPECT_NEAR(v.value, 3.0 * i + 7.0 * j + 0.5, 1e-4);
  }
  std::cout << "curvilinear inverse: worst index error " << worst << " cells\n";
  EXPECT_LT(worst, 1e-8);
  EXPECT_FALSE(s.horizontalIndex(latOf(-1.0, 10.0), lonOf(-1.0, 10.0))) << "outside the domain";
}

// The reference renderer draws a grid through the same interface as a radar: a uniform value in
// a slab between two heights, looked at straight down, has the closed-form opacity of a uniform
// medium over the slab's thickness (Max 1995).
TEST(GridSampler, ReferenceDvrOfAUniformSlabMatchesTheClosedForm) {
  const GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(9.0, 0.5, 9), testutil::evenlySpaced(44.0, 0.5, 9), {2000.0, 4000.0, 6000.0},
      [](double, double) { return 0.0; }, [](double, double, double) { return 40.0; });
  const volume::GridSampler s(g);
  volume::VolumeRenderSettings settings;
  settings.transfer = volume::defaultReflectivityTransfer();
  settings.stepMeters = 10.0;
  const glm::dvec3 eye = globe::geodeticToEcef({46.0, 11.0, 30000.0});
  const glm::dvec3 target = globe::geodeticToEcef({46.0, 11.0, 0.0});
  const volume::RenderCamera cam = volume::makeLookAtCamera(eye, target, glm::dvec3(0, 0, 1), 1.0, 3, 3);
  const volume::VolumeImage img = volume::renderReference({{&s, settings}}, cam, true, 1);
  const double pathMeters = 4000.0;  // straight down through 2000..6000 m
  const glm::dvec4 exact = volume::uniformShellDvrClosedForm(settings.transfer, 40.0, pathMeters);
  const glm::dvec4 got = img.at(1, 1);
  std::cout << "uniform slab: reference alpha " << got.a << ", closed form " << exact.a << "\n";
  // The sample grid (10 m) puts 400 +- 1 samples in the slab: the optical depth is right to
  // 1/400 of itself; alpha's sensitivity to it is exp(-tau) tau <= 0.37.
  EXPECT_NEAR(got.a, exact.a, 0.37 / 400.0 + 1e-9);
}

// The real WRF file (curvilinear Mercator nest, eta levels): at every grid point of a few levels,
// the sampler at that point's latitude, longitude and level height returns the point's value.
TEST(GridSampler, RealWrfGridPointsSampleToTheirValues) {
  const std::string path = atmoglobe_test::testDataDir() + "/grids/wrf_python_ci_test_file.nc";
  SKIP_WITHOUT_TEST_DATA(path);
  volume::GridReadOptions o;
  o.variable = "T";
  auto g = volume::readGridVolume(path, o);
  ASSERT_TRUE(g) << g.error();
  ASSERT_TRUE(g->curvilinear);
  const volume::GridSampler s(*g);
  double worst = 0.0;
  int checked = 0;
  for (std::size_t k : {std::size_t{0}, g->nz / 2, g->nz - 1})
    for (std::size_t j = 1; j + 1 < g->ny; j += 5)
      for (std::size_t i = 1; i + 1 < g->nx; i += 5) {
        const VolumeSample v =
            s.sampleGeodetic(g->latDegAt(j, i), g->lonDegAt(j, i), g->heightMeters(k, j, i), Interpolation::Linear);
        ASSERT_EQ(v.state, VolumeSample::State::Echo) << k << " " << j << " " << i;
        worst = std::max(worst, std::abs(v.value - g->value(k, j, i)));
        ++checked;
      }
  std::cout << "WRF T: " << checked << " grid points, worst |sample - value| " << worst << " K\n";
  // At a grid point the weights are 1 and 0 up to the inverse map's rounding (1e-12 of a cell):
  // the value itself, to float rounding of ~300 K (3e-5).
  EXPECT_LT(worst, 1e-4);
}

// ---------------------------------------------------------------- reduced grids

namespace {

// A smooth field of latitude, longitude and height for the reduced-grid tests.
double reducedField(double lat, double lon, double h) {
  return 10.0 + 5.0 * std::sin(lat * 0.05) * std::cos(degreesToRadians(lon)) + 3.0 * std::sin(degreesToRadians(lon)) +
         0.001 * h;
}

// Row j's value at level k at longitude `lon`, linear between its two points around it (across
// the seam of a wrapping grid): the sampling rule written out independently.
double rowValue(const GridVolume& g, std::size_t k, std::size_t j, double lon) {
  const double first = g.rowFirstLonDeg[j], step = g.rowSpacingDeg[j];
  const std::size_t n = g.rowLengthPoints[j];
  const double x = std::fmod(std::fmod(lon - first, 360.0) + 360.0, 360.0) / step;
  const std::size_t a = static_cast<std::size_t>(std::floor(x)) % n;
  const double t = x - std::floor(x);
  return (1.0 - t) * g.value(k, j, a) + t * g.value(k, j, (a + 1) % n);
}

}  // namespace

// A global reduced grid (rows of 8 .. 96 points, each starting at 0 degrees): exact at every grid
// point, linear along a row between its own points (across the seam too), linear in latitude
// between two rows each taken at its own column, one value at the poles (the end rows' means),
// and the column index on the reference axis (the longest row's spacing).
TEST(GridSampler, ReducedGridSamplesEachRowByItsOwnColumns) {
  const std::vector<double> levels{0.0, 2000.0, 5000.0, 9000.0};
  const GridVolume g = testutil::globalReducedGrid(
      24, 0.0, levels, [](double, double) { return 0.0; }, reducedField);
  ASSERT_TRUE(g.reduced());
  ASSERT_EQ(g.nx, 96u);
  ASSERT_EQ(g.rowLengthPoints.front(), 8u);
  const volume::GridSampler s(g);
  ASSERT_TRUE(s.hasPoleCaps());
  EXPECT_EQ(s.closedSize(), glm::ivec3(97, 26, 4));
  // Exact at grid points, at every level's height.
  double worstPoint = 0.0;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.rowLengthPoints[j]; i += 3)
      for (std::size_t k = 0; k < g.nz; ++k) {
        const VolumeSample v = s.sampleGeodetic(g.latDeg[j], g.lonDegAt(j, i), levels[k], Interpolation::Linear);
        ASSERT_EQ(v.state, VolumeSample::State::Echo) << j << " " << i << " " << k;
        worstPoint = std::max(worstPoint, std::abs(v.value - g.value(k, j, i)));
        // Nearest at a grid point: its own value.
        const VolumeSample n = s.sampleGeodetic(g.latDeg[j], g.lonDegAt(j, i), levels[k], Interpolation::Nearest);
        EXPECT_FLOAT_EQ(static_cast<float>(n.value), g.value(k, j, i));
      }
  EXPECT_LT(worstPoint, 1e-9);
  // Linear along a row between its own points, across the seam from the last point to the first
  // too, and linear in height between levels (3000 m: a third of the way from 2000 to 5000 m).
  double worstRow = 0.0;
  for (std::size_t j : {std::size_t{0}, std::size_t{5}, std::size_t{12}, std::size_t{23}}) {
    const std::size_t n = g.rowLengthPoints[j];
    for (std::size_t i : {std::size_t{0}, n / 2, n - 1})
      for (double t : {0.1, 0.37, 0.5, 0.93}) {
        const double lon = g.lonDegAt(j, i) + t * g.rowSpacingDeg[j];
        const double a = (1.0 - t) * g.value(1, j, i) + t * g.value(1, j, (i + 1) % n);
        const double b = (1.0 - t) * g.value(2, j, i) + t * g.value(2, j, (i + 1) % n);
        const VolumeSample v =
            s.sampleGeodetic(g.latDeg[j], lon > 180.0 ? lon - 360.0 : lon, 3000.0, Interpolation::Linear);
        ASSERT_EQ(v.state, VolumeSample::State::Echo);
        worstRow = std::max(worstRow, std::abs(v.value - (a + (b - a) / 3.0)));
      }
  }
  EXPECT_LT(worstRow, 1e-9);
  // Between rows of different lengths: each row at its own column, then linear in latitude.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0), lonDist(-180.0, 180.0);
  double worstBetween = 0.0;
  for (int m = 0; m < 500; ++m) {
    const std::size_t j = static_cast<std::size_t>(u(rng) * static_cast<double>(g.ny - 1));
    const double f = u(rng), lon = lonDist(rng);
    const double lat = g.latDeg[j] + f * (g.latDeg[j + 1] - g.latDeg[j]);
    const double expected = (1.0 - f) * rowValue(g, 2, j, lon) + f * rowValue(g, 2, j + 1, lon);
    const VolumeSample v = s.sampleGeodetic(lat, lon, 5000.0, Interpolation::Linear);
    ASSERT_EQ(v.state, VolumeSample::State::Echo);
    worstBetween = std::max(worstBetween, std::abs(v.value - expected));
    // The column index: the longitude on the reference axis (the 96-point row's spacing).
    const auto ij = s.horizontalIndex(lat, lon);
    ASSERT_TRUE(ij.has_value());
    EXPECT_NEAR(ij->x, std::fmod(lon + 360.0, 360.0) / 3.75, 1e-9);
    EXPECT_NEAR(ij->y, static_cast<double>(j) + f, 1e-9);
  }
  std::cout << "reduced grid: worst |sample - rule| at grid points " << worstPoint << ", along rows " << worstRow
            << ", between rows " << worstBetween << "\n";
  EXPECT_LT(worstBetween, 1e-9);
  // Poles: one value, the mean of the end row; no hole in the caps.
  double mean = 0.0;
  for (std::size_t i = 0; i < g.rowLengthPoints.back(); ++i) mean += g.value(2, g.ny - 1, i);
  mean /= static_cast<double>(g.rowLengthPoints.back());
  for (double lon = -180.0; lon < 180.0; lon += 17.0) {
    const VolumeSample p = s.sampleGeodetic(90.0, lon, 5000.0, Interpolation::Linear);
    ASSERT_EQ(p.state, VolumeSample::State::Echo);
    EXPECT_NEAR(p.value, mean, 1e-6);
    EXPECT_EQ(s.sampleGeodetic(-89.9, lon, 5000.0, Interpolation::Linear).state, VolumeSample::State::Echo);
  }
  // A missing point makes the samples that need it no data, the others keep theirs.
  GridVolume holed = g;
  holed.values[holed.index(2, 10, 4)] = NAN;
  const volume::GridSampler sh(holed);
  const double lon4 = g.lonDegAt(10, 4);
  EXPECT_EQ(sh.sampleGeodetic(g.latDeg[10], lon4 + 0.3 * g.rowSpacingDeg[10], 5000.0, Interpolation::Linear).state,
            VolumeSample::State::NoData);
  EXPECT_EQ(sh.sampleGeodetic(g.latDeg[10], lon4 + 1.0 * g.rowSpacingDeg[10], 5000.0, Interpolation::Linear).state,
            VolumeSample::State::Echo);
  // The closed layout: each row closed by a copy of its column 0, padding beyond.
  EXPECT_EQ(s.closedColumn(8, 1), static_cast<int>(0 * g.nx));  // closed row 1 = grid row 0 (8 points)
  EXPECT_EQ(s.closedColumn(9, 1), volume::GridColumns::kPadding);
  EXPECT_EQ(s.closedRow(1).columns, 9);
  EXPECT_EQ(s.closedRow(0).columns, 2);  // a pole row
  EXPECT_TRUE(std::isnan(s.columnValue(volume::GridColumns::kPadding, 0)));
}

// A regional reduced grid (rows of different lengths over one longitude range, not wrapping): no
// data west or east of a row, the bounding sphere holds its points, and ray intervals exist.
TEST(GridSampler, RegionalReducedGridEndsAtItsRows) {
  std::vector<std::size_t> lengths;
  std::vector<double> lat, first, spacing;
  for (int j = 0; j < 21; ++j) {
    lat.push_back(40.0 + 0.5 * j);
    lengths.push_back(static_cast<std::size_t>(41 - j));  // 41 .. 21 points over 20 degrees
    first.push_back(-10.0);
    spacing.push_back(20.0 / static_cast<double>(lengths.back() - 1));
  }
  const GridVolume g = testutil::reducedGrid(
      lengths, lat, first, false, spacing, {0.0, 4000.0, 9000.0}, [](double, double) { return 100.0; }, reducedField);
  ASSERT_FALSE(g.wrapsLongitude);
  EXPECT_DOUBLE_EQ(g.reducedWestDeg(), -10.0);
  EXPECT_DOUBLE_EQ(g.reducedSpacingDeg(), 0.5);
  EXPECT_DOUBLE_EQ(g.reducedEastDeg(), 10.0);
  const volume::GridSampler s(g);
  EXPECT_FALSE(s.hasPoleCaps());
  EXPECT_EQ(s.closedSize(), glm::ivec3(41, 21, 3));
  EXPECT_EQ(s.sampleGeodetic(45.0, 9.99, 3000.0, Interpolation::Linear).state, VolumeSample::State::Echo);
  EXPECT_EQ(s.sampleGeodetic(45.0, 10.01, 3000.0, Interpolation::Linear).state, VolumeSample::State::NoData);
  EXPECT_EQ(s.sampleGeodetic(45.0, -10.01, 3000.0, Interpolation::Linear).state, VolumeSample::State::NoData);
  EXPECT_EQ(s.sampleGeodetic(50.01, 0.0, 3000.0, Interpolation::Linear).state, VolumeSample::State::NoData);
  EXPECT_FALSE(s.horizontalIndex(45.0, 10.01).has_value());
  // Exact at a grid point of a short row.
  EXPECT_NEAR(s.sampleGeodetic(g.latDeg[20], g.lonDegAt(20, 7), 4100.0, Interpolation::Linear).value, g.value(1, 20, 7),
              1e-9);
  const volume::BoundingSphere b = s.boundingSphere();
  double worstInside = -1e300;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.rowLengthPoints[j]; ++i)
      for (double h : {100.0, 9100.0})
        worstInside = std::max(
            worstInside,
            glm::length(globe::geodeticToEcef({g.latDeg[j], g.lonDegAt(j, i), h}) - b.centreEcef) - b.radiusMeters);
  EXPECT_LE(worstInside, 0.0) << "a grid point lies outside the bounding sphere";
}

// The empty-space grid of a reduced grid is conservative, global (ECEF axes, seam and caps) and
// regional.
TEST(GridOccupancy, IsConservativeForReducedGrids) {
  auto field = [](double lat, double lon, double h) {
    return 40.0 * std::sin(lat * 0.3) * std::cos(lon * 0.2) - h / 1000.0;
  };
  std::vector<std::size_t> lengths;
  std::vector<double> lat, first, spacing;
  for (int j = 0; j < 50; ++j) {
    lat.push_back(30.0 + 0.05 * j);
    lengths.push_back(static_cast<std::size_t>(60 - j / 2));
    first.push_back(-100.0);
    spacing.push_back(3.0 / static_cast<double>(lengths.back() - 1));
  }
  // A crop of a global grid nearly round the circle (as the reader makes it, ReducedGrib.Crops...):
  // rows start one spacing west of 0 degrees; the short ones hold the whole circle and their first
  // point again, the long ones stop short of it.
  std::vector<std::size_t> cropLengths;
  std::vector<double> cropLat, cropFirst, cropSpacing;
  for (int j = 0; j < 36; ++j) {
    cropLat.push_back(-87.5 + 5.0 * j);
    const auto n =
        static_cast<std::size_t>(std::max(8.0, 4.0 * std::round(36.0 * std::cos(degreesToRadians(cropLat.back())))));
    cropSpacing.push_back(360.0 / static_cast<double>(n));
    cropFirst.push_back(-cropSpacing.back());
    cropLengths.push_back(n <= 40 ? n + 1 : n - 2);
  }
  const std::vector<double> levels{0.0, 3000.0, 6000.0, 9000.0, 12000.0};
  for (const std::string kind : {"regional", "global", "cropped"}) {
    const bool global = kind == "global", cropped = kind == "cropped";
    const GridVolume g =
        global ? testutil::globalReducedGrid(
                     72, 0.0, levels, [](double, double) { return 0.0; }, field)
        : cropped ? testutil::reducedGrid(
                        cropLengths, cropLat, cropFirst, false, cropSpacing, levels, [](double, double) { return 0.0; },
                        field)
                  : testutil::reducedGrid(
                        lengths, lat, first, false, spacing, levels,
                        [](double la, double lo) { return 300.0 + 200.0 * std::sin(la * 7.0 + lo * 5.0); }, field);
    const volume::GridSampler s(g);
    const volume::OccupancyGrid occ = volume::buildOccupancyGrid(s);
    ASSERT_EQ(occ.cells, glm::ivec3(128, 128, 32));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> la(global || cropped ? -90.0 : 29.9, global || cropped ? 90.0 : 32.55),
        lo(global || cropped ? -180.0 : -100.1, global || cropped ? 180.0 : -96.9), h(-100.0, 12600.0);
    int echoes = 0, violations = 0;
    for (int n = 0; n < 100000; ++n) {
      const double a = la(rng), b = lo(rng), hm = h(rng);
      const VolumeSample v = s.sampleGeodetic(a, b, hm, Interpolation::Linear);
      if (v.state != VolumeSample::State::Echo) continue;
      ++echoes;
      if (occ.maxAtLocal(occ.localOfEcef(globe::geodeticToEcef({a, b, hm}))) < static_cast<float>(v.value))
        ++violations;
    }
    std::cout << "reduced " << kind << ": " << echoes << " echo points, " << violations
              << " in a cell below their value\n";
    EXPECT_GT(echoes, 20000);
    EXPECT_EQ(violations, 0);
  }
}

// The lower-resolution copy of a reduced grid (the GPU's out-of-memory fallback) stays a valid
// reduced grid that wraps, keeping the rows' own points where their lengths allow.
TEST(GridSampler, DecimatedReducedGridStaysWrapping) {
  GridVolume g = testutil::globalReducedGrid(
      24, 0.0, {0.0, 5000.0}, [](double, double) { return 0.0; }, reducedField);
  g.rowLengthPoints[3] = 45;  // an odd row: resampled along the row
  g.rowSpacingDeg[3] = 8.0;
  for (std::size_t i = 0; i < 45; ++i)
    for (std::size_t k = 0; k < 2; ++k) {
      g.values[g.index(k, 3, i)] =
          static_cast<float>(reducedField(g.latDeg[3], 8.0 * static_cast<double>(i), 5000.0 * static_cast<double>(k)));
      g.heightAboveEllipsoidMeters[g.index(k, 3, i)] = static_cast<float>(5000.0 * static_cast<double>(k));
    }
  for (std::size_t i = 45; i < g.nx; ++i)
    for (std::size_t k = 0; k < 2; ++k)
      g.values[g.index(k, 3, i)] = g.heightAboveEllipsoidMeters[g.index(k, 3, i)] = NAN;
  ASSERT_TRUE(volume::finishReducedGrid(g));
  const GridVolume d = volume::decimateGrid(g, 2);
  ASSERT_TRUE(d.reduced());
  EXPECT_TRUE(d.wrapsLongitude);
  EXPECT_EQ(d.ny, 13u);
  EXPECT_EQ(d.nx, 48u);
  GridVolume check = d;
  EXPECT_TRUE(volume::finishReducedGrid(check)) << "a valid reduced grid";
  // Row 0 (8 points) keeps points 0, 2, 4, 6.
  EXPECT_EQ(d.rowLengthPoints[0], 4u);
  EXPECT_EQ(d.value(1, 0, 1), g.value(1, 0, 2));
  const volume::GridSampler s(d);
  EXPECT_EQ(s.sampleGeodetic(0.0, 179.0, 2500.0, Interpolation::Linear).state, VolumeSample::State::Echo);
}
