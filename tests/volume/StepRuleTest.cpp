// The step rule (volume/StepRule.h): levels from a crossing, alignment, a grid's cell scale, and
// the walk the reference renderer takes.
#include "SyntheticGridVolume.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/StepRule.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {
using namespace atmoglobe;

TEST(StepRule, LevelIsTheLargestPowerOfTwoOfStepsInTheSpacingAsked) {
  // 2 samples per cell of 1000 m at a 100 m step: 500 m asked, 4 steps of 100 m fit (level 2).
  EXPECT_EQ(volume::stepLevel(1000.0, 100.0, 2.0), 2);
  EXPECT_EQ(volume::stepLevel(800.0, 100.0, 2.0), 2);  // 400 m: exactly 4 steps
  EXPECT_EQ(volume::stepLevel(799.0, 100.0, 2.0), 1);  // 399.5 m: 2 steps
  EXPECT_EQ(volume::stepLevel(399.0, 100.0, 2.0), 0);  // less than 2 steps asked: the step itself
  EXPECT_EQ(volume::stepLevel(1e9, 100.0, 1.0), volume::kMaxStepLevel);
  EXPECT_EQ(volume::stepLevel(1000.0, 100.0, 0.0), 0);  // the rule off
  EXPECT_EQ(volume::stepLevel(0.0, 100.0, 2.0), 0);     // a kind without cells
  EXPECT_EQ(volume::alignUp(13, 2), 16);
  EXPECT_EQ(volume::alignUp(16, 2), 16);
  EXPECT_EQ(volume::alignUp(13, 0), 13);
  EXPECT_EQ(volume::alignUp(-3, 2), 0);
}

TEST(StepRule, CellScaleOfLevelsTakesTheFinestSpacingOfEachHeightBin) {
  // Levels 0, 100, 300, 700, ..., doubling spacing up to 25,500 m: 8 intervals.
  std::vector<double> levels{0.0};
  for (double dz = 100.0; levels.back() < 25000.0; dz *= 2.0) levels.push_back(levels.back() + dz);
  const volume::CellScale c = volume::cellScaleFromLevels(levels, 0.0, levels.back(), 25000.0);
  ASSERT_EQ(c.levelSpacingMeters.size(), static_cast<std::size_t>(volume::CellScale::kEntries));
  EXPECT_DOUBLE_EQ(c.levelSpacingMeters.front(), 100.0);  // the bin [0, 797 m) meets 0..100..300..700
  EXPECT_DOUBLE_EQ(c.levelSpacingMeters.back(), 12800.0);
  for (std::size_t e = 1; e < c.levelSpacingMeters.size(); ++e)
    EXPECT_GE(c.levelSpacingMeters[e], c.levelSpacingMeters[e - 1]);  // coarser upwards, as the levels
  // Straight down at 20 km: the spacing there; a horizontal ray: the column spacing.
  const glm::dvec3 down(0.0, 0.0, -1.0);
  const glm::dvec3 at20km(0.0, 0.0, globe::kWgs84B + 20000.0);
  const double spacing20 = c.levelSpacingMeters[static_cast<std::size_t>(20000.0 * c.entriesPerMeter)];
  EXPECT_NEAR(volume::cellCrossingMeters(c, at20km, down), spacing20, 1e-6);
  EXPECT_NEAR(volume::cellCrossingMeters(c, at20km, glm::dvec3(1.0, 0.0, 0.0)), 25000.0, 1e-6);
  // 60 degrees from the vertical: 100 m levels take 200 m of ray, 25 km columns 28.9 km.
  const glm::dvec3 at0(globe::kWgs84A + 10.0, 0.0, 0.0);
  const glm::dvec3 slant(-0.5, std::sqrt(0.75), 0.0);
  EXPECT_NEAR(volume::cellCrossingMeters(c, at0, slant), 200.0, 1e-6);
  // One level: no rule.
  EXPECT_TRUE(volume::cellScaleFromLevels({500.0}, 500.0, 500.0, 1000.0).levelSpacingMeters.empty());
  EXPECT_EQ(volume::cellCrossingMeters(volume::CellScale{}, at0, slant), 0.0);
}

TEST(StepRule, ApproximateHeightIsWithinMetresOfTheGeodeticHeight) {
  // The rule's height (distance from the centre less the ellipse's radius at the geocentric
  // latitude) against GeographicLib's geodetic height, at the heights of the atmosphere: within
  // 10 m (it decides a 32-bin table's entry, whose bins are hundreds of metres or more tall).
  double worst = 0.0;
  for (double lat = -90.0; lat <= 90.0; lat += 7.5)
    for (double h : {-500.0, 0.0, 5000.0, 20000.0, 80000.0}) {
      const glm::dvec3 p = globe::geodeticToEcef({lat, 33.0, h});
      worst = std::max(worst, std::abs(volume::approximateHeightMeters(p) - h));
    }
  std::cout << "approximate height: worst error " << worst << " m\n";
  EXPECT_LT(worst, 10.0);
}

TEST(StepRule, GridSamplerHasTheCellScaleOfItsGrid) {
  // 0.25 deg columns at the equator (27.8 km apart) and levels 0..14 km as blobGrid's.
  auto grid = testutil::rectilinearGrid(
      testutil::evenlySpaced(-10.0, 0.25, 81), testutil::evenlySpaced(-10.0, 0.25, 81),
      {0.0, 150.0, 400.0, 800.0, 1500.0, 2500.0, 4000.0, 6000.0, 8500.0, 11000.0, 14000.0},
      [](double, double) { return 0.0; }, [](double, double, double) { return 1.0; });
  const volume::GridSampler s(grid);
  const volume::CellScale& c = s.cellScale();
  ASSERT_FALSE(c.levelSpacingMeters.empty());
  // The nearer neighbour: 0.25 deg of latitude at the equator (meridional radius 6,335.4 km:
  // 27,643.6 m) rather than of longitude (27,829.9 m).
  EXPECT_NEAR(c.columnSpacingMeters, 27643.6, 1.0);
  EXPECT_DOUBLE_EQ(c.levelSpacingMeters.front(), 150.0);
  EXPECT_DOUBLE_EQ(c.levelSpacingMeters.back(), 3000.0);
}

TEST(StepRule, RadarCellsAreTheGateAlongTheBeamAndTheBeamWidthAcrossIt) {
  // 720 rays (0.5 deg apart), sweeps 1 deg apart, a 1 deg beam, 250 m gates: the finest angle
  // across the beam is the rays' 0.5 deg.
  testutil::SyntheticPolarGeometry g;
  g.rays = 720;
  const volume::PolarVolume pv =
      testutil::polarOf(testutil::syntheticRadarVolume(g, [](double, double, double) { return 20.0f; }));
  const volume::PolarCellScale c = volume::polarCellScale(pv);
  EXPECT_DOUBLE_EQ(c.gateMeters, 250.0);
  EXPECT_NEAR(c.acrossRad, 0.5 * M_PI / 180.0, 1e-9);
  // Along the beam: one gate. Across it at 60 km: 60 km x 0.5 deg = 523.6 m. At 60 degrees
  // from the beam: min(250 / 0.5, 523.6 / 0.866) = 500 m. At the antenna: no rule.
  const glm::dvec3 at60km(60000.0, 0.0, 0.0);
  EXPECT_NEAR(volume::polarCellCrossingMeters(c, at60km, glm::dvec3(-1.0, 0.0, 0.0)), 250.0, 1e-9);
  EXPECT_NEAR(volume::polarCellCrossingMeters(c, at60km, glm::dvec3(0.0, 0.0, 1.0)), 60000.0 * c.acrossRad, 1e-6);
  EXPECT_NEAR(volume::polarCellCrossingMeters(c, at60km, glm::dvec3(0.5, std::sqrt(0.75), 0.0)), 500.0, 1e-6);
  EXPECT_EQ(volume::polarCellCrossingMeters(c, glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0)), 0.0);
  EXPECT_EQ(volume::polarCellCrossingMeters(volume::PolarCellScale{}, at60km, glm::dvec3(0.0, 0.0, 1.0)), 0.0);
  // The sampler measures from its antenna.
  const volume::PolarSampler sampler(pv);
  const glm::dvec3 up = globe::enuAxes(g.latDeg, g.lonDeg)[2];
  const glm::dvec3 east = globe::enuAxes(g.latDeg, g.lonDeg)[0];
  EXPECT_NEAR(sampler.cellCrossingMeters(sampler.antennaEcef() + 60000.0 * east, up), 60000.0 * c.acrossRad, 1e-3);
  EXPECT_NEAR(sampler.cellCrossingMeters(sampler.antennaEcef() + 60000.0 * east, east), 250.0, 1e-3);
  // Sweeps closer than the rays: their gap decides.
  g.sweeps = 3;
  volume::RadarVolume close = testutil::syntheticRadarVolume(g, [](double, double, double) { return 20.0f; });
  close.sweeps[1].fixedAngleDeg = 0.7;
  for (auto& a : close.sweeps[1].elevationDeg) a = 0.7f;
  EXPECT_NEAR(volume::polarCellScale(testutil::polarOf(close)).acrossRad, 0.2 * M_PI / 180.0, 1e-7);
}

}  // namespace
