// Between time steps of a grid: values and heights linear in time, no value invented where a
// step has none, the time label interpolated.
#include "SyntheticGridVolume.h"

#include <atmoglobe/volume/GridVolume.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace atmoglobe;

namespace {
volume::GridVolume step(double valueOffset, double heightOffset, const char* time) {
  auto g = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 1.0, 4), testutil::evenlySpaced(40.0, 1.0, 3), testutil::evenlySpaced(0.0, 1000.0, 5),
      [heightOffset](double, double) { return heightOffset; },
      [valueOffset](double lat, double lon, double h) { return valueOffset + lat + lon + h / 1000.0; });
  g.validTime = time;
  g.variable = "/t";
  return g;
}
}  // namespace

TEST(GridTime, ValuesAndHeightsAreLinearInTime) {
  auto a = step(0.0, 100.0, "2020-05-01T18:00:00Z");
  auto b = step(10.0, 300.0, "2020-05-01T19:00:00Z");
  a.values[5] = NAN;  // a step without a value there: none in between either
  auto mid = volume::interpolateGridSteps(a, b, 0.25);
  ASSERT_TRUE(mid) << mid.error();
  for (std::size_t n = 0; n < mid->values.size(); ++n) {
    if (n == 5) {
      EXPECT_TRUE(std::isnan(mid->values[n]));
      continue;
    }
    // b is a + 10 (value) and + 200 m (height, so + 0.2 in the field): 0.25 of that. Float
    // storage of values below 60: 4e-6.
    const double expected = 0.75 * a.values[n] + 0.25 * b.values[n];
    EXPECT_NEAR(mid->values[n], expected, 4e-6);
    EXPECT_NEAR(mid->heightAboveEllipsoidMeters[n], a.heightAboveEllipsoidMeters[n] + 50.0, 1e-3);
  }
  EXPECT_EQ(mid->validTime, "2020-05-01T18:15:00Z");
  EXPECT_FLOAT_EQ(mid->valueMin, 0.75f * a.values[0] + 0.25f * b.values[0]);
  // The ends are the steps themselves.
  auto end = volume::interpolateGridSteps(a, b, 1.0);
  ASSERT_TRUE(end);
  EXPECT_EQ(end->values[7], b.values[7]);
  EXPECT_EQ(end->validTime, "2020-05-01T19:00:00Z");
}

TEST(GridTime, MismatchedStepsAreRefused) {
  auto a = step(0.0, 0.0, "2020-05-01T18:00:00Z");
  auto b = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 1.0, 5), testutil::evenlySpaced(40.0, 1.0, 3), testutil::evenlySpaced(0.0, 1000.0, 5),
      [](double, double) { return 0.0; }, [](double, double, double) { return 1.0; });
  b.variable = "/t";
  EXPECT_FALSE(volume::interpolateGridSteps(a, b, 0.5));
  EXPECT_FALSE(volume::interpolateGridSteps(a, a, 1.5));
  EXPECT_FALSE(volume::interpolateGridSteps(a, a, NAN));
}

TEST(GridTime, IsoTimesInterpolateAcrossDays) {
  EXPECT_EQ(volume::interpolateIsoTime("2020-12-31T23:00:00Z", "2021-01-01T01:00:00Z", 0.5), "2021-01-01T00:00:00Z");
  EXPECT_EQ(volume::interpolateIsoTime("2020-02-28T00:00:00Z", "2020-03-01T00:00:00Z", 0.5), "2020-02-29T00:00:00Z");
  EXPECT_EQ(volume::interpolateIsoTime("not a time", "2020-03-01T00:00:00Z", 0.5), "");
}
