// Tests of tilesCovering (globe/TileCover.h). Expected tiles are derived by hand from the
// tiling definition in TileId.h (level z: 2^(z+1) columns of 180/2^z degrees from -180,
// 2^z rows from +90), not from the function under test.
#include <atmoglobe/globe/TileCover.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <tuple>

namespace atmoglobe::globe {
namespace {

std::vector<TileId> grid(int level, std::vector<std::uint32_t> xs, std::vector<std::uint32_t> ys) {
  std::vector<TileId> out;
  for (std::uint32_t y : ys) {
    for (std::uint32_t x : xs) out.push_back({level, x, y});
  }
  return out;
}

/// [-180, 180), written out here rather than taken from the library under test.
double wrapLongitudeDegForTest(double lonDeg) {
  while (lonDeg >= 180.0) lonDeg -= 360.0;
  while (lonDeg < -180.0) lonDeg += 360.0;
  return lonDeg;
}

std::vector<std::uint32_t> range(std::uint32_t first, std::uint32_t last) {
  std::vector<std::uint32_t> v;
  for (std::uint32_t i = first; i <= last; ++i) v.push_back(i);
  return v;
}

void expectSortedByRowThenColumn(const std::vector<TileId>& tiles) {
  for (std::size_t i = 1; i < tiles.size(); ++i) {
    EXPECT_LT(std::tie(tiles[i - 1].y, tiles[i - 1].x), std::tie(tiles[i].y, tiles[i].x));
  }
}

TEST(TileCoverTest, AntimeridianBoxGivesBothSidesOnly) {
  const GeoRectangle box{170.0, -10.0, -170.0, 10.0};  // west, south, east, north
  // Level 0: 180 deg tiles; x=1 holds 170..180, x=0 holds -180..-170; one row.
  EXPECT_EQ(tilesCovering(box, 0), grid(0, {0, 1}, {0}));
  // Level 1: 90 deg; columns 0 (-180..-90) and 3 (90..180); rows 0 (90..0) and 1 (0..-90).
  EXPECT_EQ(tilesCovering(box, 1), grid(1, {0, 3}, {0, 1}));
  // Level 4: 11.25 deg; 16 rows, 32 columns. 170 lies in column floor(350/11.25) = 31,
  // -170 in column floor(10/11.25) = 0. Latitude 10 is in row floor(80/11.25) = 7 and -10
  // in row floor(100/11.25) = 8.
  EXPECT_EQ(tilesCovering(box, 4), grid(4, {0, 31}, {7, 8}));
  // Level 6: 2.8125 deg: west 170 -> column floor(350/2.8125) = 124 .. 127; east -170 ->
  // columns 0 .. ceil(10/2.8125)-1 = 3. Rows: floor(80/2.8125) = 28 .. ceil(100/2.8125)-1 = 35.
  const std::vector<TileId> tiles = tilesCovering(box, 6);
  std::vector<std::uint32_t> xs = range(0, 3);
  for (std::uint32_t x : range(124, 127)) xs.push_back(x);
  EXPECT_EQ(tiles, grid(6, xs, range(28, 35)));
  expectSortedByRowThenColumn(tiles);
  for (const TileId& t : tiles) EXPECT_TRUE(t.x <= 3 || t.x >= 124) << "tile in between: x=" << t.x;
}

TEST(TileCoverTest, NorthPolarCapGivesTopRow) {
  // North of 80 deg at level 3 (22.5 deg tiles): only row 0 (90..67.5), every column.
  const std::vector<TileId> tiles = tilesCovering({-180.0, 80.0, 180.0, 90.0}, 3);
  EXPECT_EQ(tiles, grid(3, range(0, 15), {0}));
  // South polar cap: the bottom row.
  EXPECT_EQ(tilesCovering({-180.0, -90.0, 180.0, -80.0}, 3), grid(3, range(0, 15), {7}));
  // Latitudes beyond the poles are clamped.
  EXPECT_EQ(tilesCovering({-180.0, 80.0, 180.0, 95.0}, 3), tiles);
}

TEST(TileCoverTest, WholeWorldGivesEveryTile) {
  for (int level = 0; level <= 5; ++level) {
    const std::vector<TileId> tiles = tilesCovering(GeoRectangle{}, level);
    ASSERT_EQ(tiles.size(), std::size_t{tileColumns(level)} * tileRows(level));
    expectSortedByRowThenColumn(tiles);
    for (const TileId& t : tiles) EXPECT_TRUE(isValid(t));
  }
  // Also when written as a 360-degree span starting elsewhere, or crossing the antimeridian.
  EXPECT_EQ(tilesCovering({0.0, -90.0, 360.0, 90.0}, 2).size(), 32u);
  EXPECT_EQ(tilesCovering({10.0, -90.0, 9.99, 90.0}, 2).size(), 32u);
}

TEST(TileCoverTest, DegenerateAndPointBoxes) {
  // Level 2: 45 deg tiles, 8 columns, 4 rows. Column = floor((lon + 180) / 45),
  // row = floor((90 - lat) / 45); a boundary value goes east / south (TileCover.h).
  EXPECT_EQ(tilesCovering({7.0, 30.0, 7.0, 30.0}, 2), grid(2, {4}, {1}));        // inside one tile
  EXPECT_EQ(tilesCovering({0.0, 45.0, 0.0, 45.0}, 2), grid(2, {4}, {1}));        // on a corner
  EXPECT_EQ(tilesCovering({180.0, -90.0, 180.0, -90.0}, 2), grid(2, {0}, {3}));  // 180 == -180: column 0
  EXPECT_EQ(tilesCovering({-180.0, 90.0, -180.0, 90.0}, 2), grid(2, {0}, {0}));
  EXPECT_EQ(tilesCovering({179.0, -90.0, 179.0, -90.0}, 2), grid(2, {7}, {3}));  // last column, last row
  // Zero-width meridian segment from -30 to 30: column 4, rows 1 (45..0) and 2 (0..-45).
  EXPECT_EQ(tilesCovering({7.0, -30.0, 7.0, 30.0}, 2), grid(2, {4}, {1, 2}));
  // Zero-height segment along the equator at level 1 (90 deg): the row south of it (1),
  // columns floor(190/90) = 2 .. ceil(280/90) - 1 = 3.
  EXPECT_EQ(tilesCovering({10.0, 0.0, 100.0, 0.0}, 1), grid(1, {2, 3}, {1}));
  // Edges exactly on tile boundaries do not pick up the neighbours.
  EXPECT_EQ(tilesCovering({0.0, 0.0, 90.0, 45.0}, 2), grid(2, {4, 5}, {1}));
  EXPECT_EQ(tilesCovering({170.0, 0.0, 180.0, 10.0}, 0), grid(0, {1}, {0}));
  // A sliver across a boundary picks up both sides.
  EXPECT_EQ(tilesCovering({44.999, 10.0, 45.001, 11.0}, 2), grid(2, {4, 5}, {1}));
  // Longitudes outside [-180, 180] are wrapped: -190..-170 crosses the antimeridian.
  EXPECT_EQ(tilesCovering({-190.0, 0.0, -170.0, 10.0}, 0), grid(0, {0, 1}, {0}));
  // South above north: empty.
  EXPECT_TRUE(tilesCovering({0.0, 20.0, 10.0, 10.0}, 3).empty());
}

// Random boxes against a brute force over every tile: a tile is expected iff its interior
// meets the box's interior (longitude checked on the circle, both sides of the antimeridian).
TEST(TileCoverTest, RandomBoxesMatchBruteForce) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> lon(-180.0, 180.0), lat(-90.0, 90.0), span(0.01, 200.0);
  auto overlaps = [](double a0, double a1, double b0, double b1) { return std::min(a1, b1) > std::max(a0, b0); };
  for (int k = 0; k < 400; ++k) {
    const int level = k % 6;
    GeoRectangle box;
    box.westDeg = lon(rng);
    box.eastDeg = wrapLongitudeDegForTest(box.westDeg + span(rng));
    box.southDeg = lat(rng);
    box.northDeg = std::min(90.0, box.southDeg + 0.5 * span(rng));
    std::vector<TileId> expected;
    for (std::uint32_t y = 0; y < tileRows(level); ++y) {
      for (std::uint32_t x = 0; x < tileColumns(level); ++x) {
        const GeoRectangle r = tileRectangle({level, x, y});
        const bool latOk = overlaps(r.southDeg, r.northDeg, box.southDeg, box.northDeg);
        bool lonOk = false;
        if (box.westDeg <= box.eastDeg) {
          lonOk = overlaps(r.westDeg, r.eastDeg, box.westDeg, box.eastDeg);
        } else {
          lonOk = overlaps(r.westDeg, r.eastDeg, box.westDeg, 180.0) ||
                  overlaps(r.westDeg, r.eastDeg, -180.0, box.eastDeg);
        }
        if (latOk && lonOk) expected.push_back({level, x, y});
      }
    }
    ASSERT_EQ(tilesCovering(box, level), expected) << "level " << level << " box " << box.westDeg << " " << box.southDeg
                                                   << " " << box.eastDeg << " " << box.northDeg;
  }
}

}  // namespace
}  // namespace atmoglobe::globe
