// The grid level lookup (GridLevelIndex.h): for any blend of a cell's columns and any height, the
// level the full bisection finds lies in the cell's bracket for that height's bin, with the
// bin computed in double and in float as the shader computes it; brackets stay tight on strong
// terrain and stretched levels; columns the rule cannot index get every level.
#include "SyntheticGridVolume.h"

#include <atmoglobe/volume/GridLevelIndex.h>
#include <atmoglobe/volume/GridSampler.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <vector>

namespace {

using namespace atmoglobe;

// Stretched levels: 20 m apart at the ground, growing by 12 % a level (0 to ~19 km for 40 levels).
std::vector<double> stretchedLevels(int n) {
  std::vector<double> h;
  double z = 10.0, dz = 20.0;
  for (int k = 0; k < n; ++k) {
    h.push_back(z);
    z += dz;
    dz *= 1.12;
  }
  return h;
}

// Mountains of up to 5 km with slopes of several km per cell.
double rugged(double lat, double lon) {
  return std::max(0.0, 2500.0 + 2500.0 * std::sin(lat * 0.9) * std::cos(lon * 1.3) + 800.0 * std::sin(lon * 7.0));
}

// The shader's bin rule in float (sample_grid.glsl, VOL_levelBracket).
int floatBin(const volume::GridLevelIndex& idx, float z) {
  const float perMetre = static_cast<float>((idx.heightEntries() - 1) / (idx.maxHeightMeters - idx.minHeightMeters));
  const float x = std::max(z - static_cast<float>(idx.minHeightMeters), 0.0f) * perMetre;
  const int e = std::min(static_cast<int>(x), idx.heightEntries() - 2);
  const float f = std::clamp(x - static_cast<float>(e), 0.0f, 1.0f);
  const float a = idx.referenceLevelAtHeight[static_cast<std::size_t>(e)];
  const float b = idx.referenceLevelAtHeight[static_cast<std::size_t>(e) + 1];
  const float ref = a + (b - a) * f;
  return std::clamp(static_cast<int>(std::floor(ref * static_cast<float>(idx.binsPerLevel))), 0, idx.bins - 1);
}

struct Outcome {
  bool inside = false;
  int lo = 0;
  bool operator==(const Outcome& o) const { return inside == o.inside && (!inside || lo == o.lo); }
};

// Checks random samples of every kind of cell: the bracket's bisection gives the full one's answer.
void expectBracketsHold(const volume::GridVolume& g, int samples, unsigned seed) {
  const volume::GridSampler s(g);
  const volume::GridLevelIndex idx = volume::buildGridLevelIndex(s, 4096);
  const glm::ivec3 ts = s.closedSize();
  ASSERT_GT(idx.bins, 1);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto height = [&](int tc, int tr, int k) {
    return static_cast<float>(s.columnHeight(s.closedHeightColumn(tc, tr), static_cast<std::size_t>(k)));
  };
  int mismatches = 0, floatMismatches = 0;
  for (int n = 0; n < samples; ++n) {
    // A cell and a blend of its columns (corner list as the shader's).
    int tr = static_cast<int>(u(rng) * (ts.y - 1)), tc = 0, tc1 = 0;
    std::vector<std::pair<glm::ivec2, float>> corners;
    if (idx.rowPairs) {
      const int n0 = s.closedRow(tr).columns, n1 = s.closedRow(tr + 1).columns;
      const int c0 = static_cast<int>(u(rng) * std::max(n0 - 1, 1)),
                c1 = static_cast<int>(u(rng) * std::max(n1 - 1, 1));
      const float fx = static_cast<float>(u(rng)), fy = static_cast<float>(u(rng)), fz = static_cast<float>(u(rng));
      corners = {{{c0, tr}, (1 - fx) * (1 - fz)},
                 {{std::min(c0 + 1, n0 - 1), tr}, fx * (1 - fz)},
                 {{c1, tr + 1}, (1 - fy) * fz},
                 {{std::min(c1 + 1, n1 - 1), tr + 1}, fy * fz}};
      tc = c0;
      tc1 = c1;
    } else {
      tc = static_cast<int>(u(rng) * (ts.x - 1));
      const float fx = static_cast<float>(u(rng)), fy = static_cast<float>(u(rng));
      corners = {{{tc, tr}, (1 - fx) * (1 - fy)},
                 {{tc + 1, tr}, fx * (1 - fy)},
                 {{tc, tr + 1}, (1 - fx) * fy},
                 {{tc + 1, tr + 1}, fx * fy}};
    }
    auto blended = [&](int k) {
      float h = 0.0f;
      for (const auto& [c, w] : corners) h += w * height(c.x, c.y, k);
      return h;
    };
    const float z =
        static_cast<float>(idx.minHeightMeters - 200.0 + u(rng) * (idx.maxHeightMeters - idx.minHeightMeters + 400.0));
    // The full bisection (the rule before the index).
    Outcome full;
    if (z >= blended(0) && z <= blended(ts.z - 1)) {
      int lo = 0, hi = ts.z - 1;
      while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (blended(mid) <= z ? lo : hi) = mid;
      }
      full = {true, lo};
    }
    auto viaBracket = [&](int bin) {
      glm::ivec2 b = idx.bracket(tc, tr, bin);
      if (idx.rowPairs) {
        const glm::ivec2 b1 = idx.bracket(tc1, tr + 1, bin);
        b = glm::ivec2(std::min(b.x, b1.x), std::max(b.y, b1.y));
      }
      int lo = b.x, hi = b.y;
      while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (blended(mid) <= z ? lo : hi) = mid;
      }
      return z < blended(lo) || z > blended(hi) ? Outcome{} : Outcome{true, lo};
    };
    if (!(viaBracket(idx.binOf(z)) == full)) ++mismatches;
    if (!(viaBracket(floatBin(idx, z)) == full)) ++floatMismatches;
  }
  EXPECT_EQ(mismatches, 0) << "of " << samples;
  EXPECT_EQ(floatMismatches, 0) << "of " << samples;
}

}  // namespace

TEST(GridLevelIndex, BracketsHoldTheLevelOfEveryBlendOnTerrainAndStretchedLevels) {
  const auto field = [](double, double, double h) { return h; };
  // A regional rectilinear grid over steep terrain, levels following it.
  expectBracketsHold(
      testutil::rectilinearGrid(testutil::evenlySpaced(5.0, 0.1, 60), testutil::evenlySpaced(40.0, 0.1, 50),
                                stretchedLevels(40), rugged, field),
      60000, 1);
  // A global grid closed across the antimeridian and over the poles.
  volume::GridVolume global = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 5.0, 72), testutil::evenlySpaced(-87.5, 5.0, 36), stretchedLevels(30), rugged, field);
  global.wrapsLongitude = true;
  expectBracketsHold(global, 60000, 2);
  // A reduced global grid: rows of different lengths, cells of two columns per row.
  expectBracketsHold(testutil::globalReducedGrid(24, 0.0, stretchedLevels(25), rugged, field), 60000, 3);
}

TEST(GridLevelIndex, BracketsAreTightOnFollowingLevels) {
  // A bracket cannot be narrower than the levels a cell's columns disagree on, and a bin one
  // reference level deep holds a level's edge in most columns, so one step is the floor. Over
  // smooth terrain (~70 m between neighbouring columns) the columns agree to a level or two but
  // near the ground (20 m levels), over the rugged one (~500 m) to many. The full bisection takes
  // ceil(log2(39)) = 6 steps. Measured: smooth 1.27 mean, rugged 1.74 (both at most 6). Bounds:
  // within half a step of the floor where the terrain is smooth, a third of the full bisection
  // on the rugged one.
  const auto field = [](double, double, double h) { return h; };
  auto stats = [&](const std::function<double(double, double)>& surface) {
    const volume::GridVolume g = testutil::rectilinearGrid(testutil::evenlySpaced(5.0, 0.1, 60),
                                                           testutil::evenlySpaced(40.0, 0.1, 50), stretchedLevels(40),
                                                           surface, field);
    return volume::gridLevelIndexStats(volume::buildGridLevelIndex(volume::GridSampler(g), 4096));
  };
  const volume::GridLevelIndexStats smooth =
      stats([](double lat, double lon) { return 750.0 + 750.0 * std::sin(lat * 0.9) * std::cos(lon * 1.3); });
  const volume::GridLevelIndexStats steep = stats(rugged);
  std::cout << "mean bisection steps: smooth terrain " << smooth.meanSteps << " (most " << smooth.maxSteps
            << "), rugged " << steep.meanSteps << " (most " << steep.maxSteps << ")\n";
  EXPECT_LT(smooth.meanSteps, 1.5);
  EXPECT_LT(steep.meanSteps, 2.0);
}

TEST(GridLevelIndex, ColumnsItCannotIndexGetEveryLevel) {
  const auto field = [](double, double, double h) { return h; };
  // A column whose heights fall: every cell touching it brackets all the levels.
  volume::GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(5.0, 0.1, 8), testutil::evenlySpaced(40.0, 0.1, 8), stretchedLevels(12),
      [](double, double) { return 0.0; }, field);
  g.heightAboveEllipsoidMeters[g.index(5, 3, 3)] = g.heightAboveEllipsoidMeters[g.index(4, 3, 3)] - 1.0f;
  const volume::GridSampler s(g);
  const volume::GridLevelIndex idx = volume::buildGridLevelIndex(s, 64);
  for (int b = 0; b < idx.bins; ++b) {
    for (glm::ivec2 cell : {glm::ivec2(2, 2), glm::ivec2(3, 2), glm::ivec2(2, 3), glm::ivec2(3, 3)})
      EXPECT_EQ(idx.bracket(cell.x, cell.y, b), glm::ivec2(0, 11)) << "bin " << b;
  }
  // A cell away from it: narrower brackets.
  EXPECT_LT(idx.bracket(6, 6, 0).y - idx.bracket(6, 6, 0).x, 11);
  // More levels than 8-bit brackets hold: one bin of all levels.
  std::vector<double> many;
  for (int k = 0; k < 300; ++k) many.push_back(10.0 + 50.0 * k);
  const volume::GridVolume tall = testutil::rectilinearGrid(
      testutil::evenlySpaced(5.0, 0.1, 4), testutil::evenlySpaced(40.0, 0.1, 4), many,
      [](double, double) { return 0.0; }, field);
  const volume::GridLevelIndex all = volume::buildGridLevelIndex(volume::GridSampler(tall), 64);
  EXPECT_EQ(all.bins, 1);
  EXPECT_EQ(all.bracket(1, 1, 0), glm::ivec2(0, 299));
}
