// Wind components turned east and north (volume/Wind.h) against the rotation worked out by hand
// for a Lambert conformal grid, and the parts of a wind barb.
#include <atmoglobe/volume/Wind.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

namespace {
using namespace atmoglobe;
constexpr double kDeg = std::numbers::pi / 180.0;

// A Lambert conformal grid tangent at 40 N (cone constant n = sin 40 deg), central meridian
// 100 W, 30 km spacing, on a sphere of 6371 km (the inverse projection written out: Snyder 1987,
// eqs. 15-1 to 15-3 and 14-4 to 14-11). Its x axis at a point of longitude lon is turned from
// east by alpha = -n (lon - lon0): the map's north there is the direction toward the cone's apex,
// (-sin theta, cos theta) with theta = n (lon - lon0), so east is (cos theta, sin theta) and the
// x axis (1, 0) has east component cos theta and north component -sin theta.
volume::GridVolume lambertGrid(double uGrid, bool gridRelative) {
  const double R = 6371000.0, phi0 = 40.0 * kDeg, lon0 = -100.0;
  const double n = std::sin(phi0);
  const double F = std::cos(phi0) * std::pow(std::tan(std::numbers::pi / 4 + phi0 / 2), n) / n;
  const double rho0 = R * F / std::pow(std::tan(std::numbers::pi / 4 + phi0 / 2), n);
  volume::GridVolume g;
  g.path = "lambert.grib";
  g.variable.assign(1, 'u');  // not = "u": GCC 12 gives a false -Wrestrict there
  g.curvilinear = true;
  g.nx = 81;
  g.ny = 61;
  g.nz = 1;
  g.vectorsRelativeToGrid = gridRelative;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.nx; ++i) {
      const double x = (static_cast<double>(i) - 40.0) * 30000.0, y = (static_cast<double>(j) - 30.0) * 30000.0;
      const double rho = std::sqrt(x * x + (rho0 - y) * (rho0 - y));
      const double theta = std::atan2(x, rho0 - y);
      const double phi = 2.0 * std::atan(std::pow(R * F / rho, 1.0 / n)) - std::numbers::pi / 2;
      g.latDeg.push_back(phi / kDeg);
      g.lonDeg.push_back(lon0 + theta / n / kDeg);
    }
  g.values.assign(g.nx * g.ny, static_cast<float>(uGrid));
  return g;
}

TEST(Wind, GridRelativeLambertWindIsTurnedByTheConeAngle) {
  const double n = std::sin(40.0 * kDeg);
  // A grid-relative wind of 10 m/s along the grid's x axis, and one of 10 m/s along its y axis.
  for (const auto& [uGrid, vGrid] : {std::pair{10.0, 0.0}, std::pair{0.0, 10.0}, std::pair{6.0, -8.0}}) {
    volume::GridVolume u = lambertGrid(uGrid, true);
    volume::GridVolume v = u;
    v.variable.assign(1, 'v');
    v.values.assign(v.nx * v.ny, static_cast<float>(vGrid));
    auto w = volume::earthRelativeWind(u, v);
    ASSERT_TRUE(w) << w.error();
    double worstDeg = 0.0, worstSpeed = 0.0;
    for (std::size_t c = 0; c < u.nx * u.ny; ++c) {
      const double theta = n * (u.lonDeg[c] + 100.0) * kDeg;
      // By hand (NCEP's rotation of grid-relative winds): east = cos(theta) u + sin(theta) v,
      // north = -sin(theta) u + cos(theta) v.
      const double east = std::cos(theta) * uGrid + std::sin(theta) * vGrid;
      const double north = -std::sin(theta) * uGrid + std::cos(theta) * vGrid;
      const double dirErr =
          std::remainder(std::atan2(w->northMps[c], w->eastMps[c]) - std::atan2(north, east), 2.0 * std::numbers::pi) /
          kDeg;
      worstDeg = std::max(worstDeg, std::abs(dirErr));
      worstSpeed = std::max(worstSpeed, std::abs(std::hypot(w->eastMps[c], w->northMps[c]) - 10.0));
    }
    std::cout << "Lambert grid-relative (" << uGrid << ", " << vGrid << "): worst direction error " << worstDeg
              << " deg, speed " << worstSpeed << " m/s\n";
    // The grid was made on a sphere and its angles are measured on the WGS84 ellipsoid, whose
    // meridional and prime-vertical radii differ by up to 0.7 %: a direction theta from east moves
    // by at most ~0.7 % of sin(2 theta) / 2 rad, under 0.1 deg where theta reaches 14 deg at the
    // grid's edges; the speed is kept (a rotation) to float rounding.
    EXPECT_LT(worstDeg, 0.15);
    EXPECT_LT(worstSpeed, 1e-4);
  }
  // The angle at the central meridian is 0, and at 20 degrees east of it -n x 20 degrees.
  const volume::GridVolume g = lambertGrid(1.0, true);
  const std::vector<double> alpha = volume::gridColumnAngles(g);
  EXPECT_NEAR(alpha[30 * g.nx + 40], 0.0, 1e-9);
  // Earth-relative components stay as they are.
  volume::GridVolume u = lambertGrid(10.0, false), v = u;
  v.values.assign(v.nx * v.ny, 0.0f);
  auto w = volume::earthRelativeWind(u, v);
  ASSERT_TRUE(w);
  EXPECT_EQ(w->eastMps[0], 10.0f);
  EXPECT_EQ(w->northMps[0], 0.0f);
  // Components on different grids are refused.
  v.nx = 80;
  EXPECT_FALSE(volume::earthRelativeWind(u, v));
}

TEST(Wind, BarbPartsRoundToFiveKnots) {
  const auto parts = [](double kt) {
    const volume::BarbParts p = volume::barbParts(kt);
    return std::vector<int>{p.pennants, p.full, p.half, p.calm ? 1 : 0};
  };
  EXPECT_EQ(parts(0.0), (std::vector<int>{0, 0, 0, 1}));
  EXPECT_EQ(parts(2.4), (std::vector<int>{0, 0, 0, 1}));
  EXPECT_EQ(parts(3.0), (std::vector<int>{0, 0, 1, 0}));   // 5 kt: one half barb
  EXPECT_EQ(parts(65.0), (std::vector<int>{1, 1, 1, 0}));  // the 50 + 10 + 5 of the usual sketch
  EXPECT_EQ(parts(12.4), (std::vector<int>{0, 1, 0, 0}));
  EXPECT_EQ(parts(12.6), (std::vector<int>{0, 1, 1, 0}));
  EXPECT_EQ(parts(103.0), (std::vector<int>{2, 0, 1, 0}));
}

TEST(Wind, BarbPointsWhereTheWindComesFromWithItsPartsOnTheLowPressureSide) {
  // A westerly of 65 kt (33.4 m/s): the shaft to the west, a pennant, a barb and a half barb,
  // all north of the shaft in the northern hemisphere and south of it in the southern.
  const double mps = 65.0 / volume::kKnotsPerMps;
  for (bool south : {false, true}) {
    const auto lines = volume::barbPolylines(mps, 0.0, south);
    ASSERT_EQ(lines.size(), 4u);  // shaft, pennant, barb, half barb
    EXPECT_NEAR(lines[0][1].x, -1.0, 1e-12);
    EXPECT_NEAR(lines[0][1].y, 0.0, 1e-12);
    EXPECT_EQ(lines[1].size(), 4u);  // the pennant, closed
    for (std::size_t k = 1; k < lines.size(); ++k) {
      double far = 0.0;
      for (const glm::dvec2& p : lines[k]) far = std::abs(p.y) > std::abs(far) ? p.y : far;
      EXPECT_GT(south ? -far : far, 0.15) << "part " << k << (south ? " (south)" : " (north)");
    }
  }
  // A southerly of 10 kt: the shaft to the south, one full barb; calm: a circle.
  const auto southerly = volume::barbPolylines(0.0, 10.0 / volume::kKnotsPerMps, false);
  ASSERT_EQ(southerly.size(), 2u);
  EXPECT_NEAR(southerly[0][1].y, -1.0, 1e-12);
  EXPECT_LT(southerly[1][1].x, -0.3);  // right of the shaft seen from the station looking south: west
  EXPECT_EQ(volume::barbPolylines(0.5, 0.5, false).size(), 1u);
}

}  // namespace
