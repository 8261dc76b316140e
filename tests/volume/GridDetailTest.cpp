// Level of detail for grids (volume/GridDetail.h): block means written out by hand, the missing
// rule, wrapping, the level chosen by the pixel footprint.
#include "SyntheticGridVolume.h"

#include <atmoglobe/volume/GridDetail.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace atmoglobe;
using namespace atmoglobe::volume;

namespace {

// 5 x 4 columns, 4 levels; value = 100 k + 10 j + i (k level, j row, i column), heights 1000 (k + 1)
// + 7 i + 3 j.
GridVolume smallGrid() {
  GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(10.0, 1.0, 5), testutil::evenlySpaced(40.0, 0.5, 4), {1000.0, 2000.0, 3000.0, 4000.0},
      [](double lat, double lon) { return 7.0 * (lon - 10.0) + 3.0 * (lat - 40.0) / 0.5; },
      [](double, double, double) { return 0.0; });
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i)
        g.values[g.index(k, j, i)] =
            static_cast<float>(100.0 * static_cast<double>(k) + 10.0 * static_cast<double>(j) + static_cast<double>(i));
  g.path = "small.nc";
  g.variable = "/t";
  g.levelValues = {1000.0, 850.0, 700.0, 500.0};
  setValueRange(g);
  return g;
}

}  // namespace

TEST(GridDetail, BlockMeansOfPositionsHeightsAndValues) {
  const GridVolume g = smallGrid();
  auto c = coarsenGrid(g, 2, 2);
  ASSERT_TRUE(c) << c.error();
  // 5 columns -> 3 blocks (the last holds column 4 alone), 4 rows -> 2, 4 levels -> 2.
  ASSERT_EQ(c->nx, 3u);
  ASSERT_EQ(c->ny, 2u);
  ASSERT_EQ(c->nz, 2u);
  EXPECT_EQ(c->lonDeg, (std::vector<double>{10.5, 12.5, 14.0}));
  EXPECT_EQ(c->latDeg, (std::vector<double>{40.25, 41.25}));
  EXPECT_EQ(c->levelValues, (std::vector<double>{925.0, 600.0}));
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t j = 0; j < 2; ++j)
      for (std::size_t i = 0; i < 3; ++i) {
        // The mean of 100 kk + 10 jj + ii over the block, and of its heights.
        double value = 0.0, height = 0.0, n = 0.0;
        for (std::size_t kk = 2 * k; kk < 2 * k + 2; ++kk)
          for (std::size_t jj = 2 * j; jj < 2 * j + 2; ++jj)
            for (std::size_t ii = 2 * i; ii < std::min<std::size_t>(2 * i + 2, 5); ++ii) {
              value += 100.0 * static_cast<double>(kk) + 10.0 * static_cast<double>(jj) + static_cast<double>(ii);
              height +=
                  1000.0 * static_cast<double>(kk + 1) + 7.0 * static_cast<double>(ii) + 3.0 * static_cast<double>(jj);
              n += 1.0;
            }
        EXPECT_FLOAT_EQ(c->value(k, j, i), static_cast<float>(value / n)) << k << j << i;
        EXPECT_FLOAT_EQ(c->heightMeters(k, j, i), static_cast<float>(height / n)) << k << j << i;
      }
  EXPECT_FLOAT_EQ(c->valueMin, c->value(0, 0, 0));
  EXPECT_EQ(c->fileColumnStep, 2);
  // Horizontal only: every level kept.
  auto flat = coarsenGrid(g, 2, 1);
  ASSERT_TRUE(flat);
  EXPECT_EQ(flat->nz, 4u);
  EXPECT_FLOAT_EQ(flat->value(3, 0, 0), 300.0f + (0.0f + 1.0f + 10.0f + 11.0f) / 4.0f);
}

TEST(GridDetail, AValueIsMissingWhereMoreThanHalfOfItsBlockIs) {
  GridVolume g = smallGrid();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Block (0, 0, 0) of 2 x 2 x 2: 4 of 8 missing -> the mean of the other 4; block (0, 0, 1):
  // 5 of 8 missing -> missing.
  for (std::size_t i : {0u, 1u}) {
    g.values[g.index(0, 0, i)] = nan;
    g.values[g.index(0, 1, i)] = nan;
  }
  for (std::size_t i : {2u, 3u})
    for (std::size_t j : {0u, 1u}) g.values[g.index(1, j, i)] = nan;
  g.values[g.index(0, 0, 2)] = nan;
  auto c = coarsenGrid(g, 2, 2);
  ASSERT_TRUE(c) << c.error();
  EXPECT_FLOAT_EQ(c->value(0, 0, 0), (100.0f + 101.0f + 110.0f + 111.0f) / 4.0f);
  EXPECT_TRUE(std::isnan(c->value(0, 0, 1)));
  EXPECT_FALSE(std::isnan(c->value(0, 0, 2)));
}

TEST(GridDetail, WrappingGridsKeepWrappingWhenTheirColumnsDivide) {
  GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 10.0, 36), testutil::evenlySpaced(-85.0, 10.0, 18), {1000.0, 5000.0},
      [](double, double) { return 0.0; }, [](double lat, double, double) { return lat; });
  g.wrapsLongitude = true;
  auto two = coarsenGrid(g, 2, 1);
  ASSERT_TRUE(two);
  EXPECT_TRUE(two->wrapsLongitude);
  EXPECT_DOUBLE_EQ(two->lonDeg[1] - two->lonDeg[0], 20.0);
  auto five = coarsenGrid(g, 5, 1);
  ASSERT_TRUE(five);
  EXPECT_FALSE(five->wrapsLongitude) << "36 columns in blocks of 5 leave a gap at the seam";
  // 36 x 18 columns: levels 1 (18 x 9) and 2 (9 x 5 rows: under 8) -> the coarsest is 1.
  EXPECT_EQ(maxDetailLevel(g), 1);
}

TEST(GridDetail, BadRequestsAreRefused) {
  const GridVolume g = smallGrid();
  EXPECT_FALSE(coarsenGrid(g, 0, 1));
  auto tooFew = coarsenGrid(g, 4, 4);
  ASSERT_FALSE(tooFew);
  EXPECT_NE(tooFew.error().find("2 x 2 x 2 needed"), std::string::npos) << tooFew.error();
  GridVolume reduced = g;
  reduced.rowLengthPoints = {5, 5, 5, 5};
  EXPECT_FALSE(coarsenGrid(reduced, 2, 1));
  EXPECT_EQ(maxDetailLevel(reduced), 0);
}

TEST(GridDetail, TheLevelFollowsThePixelFootprint) {
  // 45 deg over 180 px: 2 tan(22.5 deg) / 180 = 4.60e-3 rad a pixel.
  EXPECT_NEAR(pixelFootprintMeters(12.0e6, 45.0, 180, 1.0), 12.0e6 * 2.0 * std::tan(M_PI / 8.0) / 180.0, 1e-6);
  EXPECT_NEAR(pixelFootprintMeters(12.0e6, 45.0, 720, 0.25), pixelFootprintMeters(12.0e6, 45.0, 180, 1.0), 1e-6);
  // Columns 27.7 km apart: a footprint under 55.4 km keeps the grid; 55.4 km: level 1 (cells of
  // one pixel); 110.8 km: level 2 ... up to the coarsest built.
  EXPECT_EQ(gridDetailLevel(27.7e3, 27.7e3, 4), 0);
  EXPECT_EQ(gridDetailLevel(27.7e3, 55.3e3, 4), 0);
  EXPECT_EQ(gridDetailLevel(27.7e3, 55.5e3, 4), 1);
  EXPECT_EQ(gridDetailLevel(27.7e3, 110.7e3, 4), 1);
  EXPECT_EQ(gridDetailLevel(27.7e3, 111.0e3, 4), 2);
  EXPECT_EQ(gridDetailLevel(27.7e3, 1.0e7, 3), 3);
  EXPECT_EQ(gridDetailLevel(27.7e3, 1.0e7, 0), 0);
  EXPECT_EQ(gridDetailLevel(0.0, 1.0e7, 3), 0);
  // Levels halve while 8 remain: 37 -> 19 -> 10, not 5.
  GridVolume tall = smallGrid();
  tall.nz = 37;
  EXPECT_EQ(detailVerticalFactor(tall, 1), 2u);
  EXPECT_EQ(detailVerticalFactor(tall, 2), 4u);
  EXPECT_EQ(detailVerticalFactor(tall, 3), 4u);
  EXPECT_EQ(detailHorizontalFactor(3), 8u);
}
