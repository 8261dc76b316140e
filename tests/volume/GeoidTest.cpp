// EGM96 geoid undulation from the proj-data .gtx grid, against PROJ's own interpolation.
#include <atmoglobe/volume/Geoid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace atmoglobe::volume {
namespace {

struct GeoidCase {
  double latDeg, lonDeg, undulationMeters;
};

// Reference values: PROJ 9 vgridshift on the same grid, e.g.
//   echo "9 48 0 0" | cct -d 6 +proj=vgridshift +grids=egm96_15.gtx +multiplier=1
// (input lon lat; output height = 0 + N). The grid is NGA/NASA's EGM96 (Lemoine et al. 1998,
// NASA/TP-1998-206861) at 15' spacing, as PROJ distributes it.
constexpr GeoidCase kPrjCases[] = {
    {48.0, 9.0, 48.101185},            // the wradlib test site (GeolocationTest.cpp)
    {33.6541, -101.8142, -26.177516},  // KLBB, Lubbock TX
    {89.99, 0.0, 13.618102},           // near the north pole (last grid row)
    {-89.99, 45.0, -29.539210},        // near the south pole (first grid row)
    {0.0, 180.0, 21.153330},           // on the antimeridian, east side
    {0.0, -180.0, 21.153330},          // same point, west side
    {10.0, 179.9, 12.777215},          // between the last column and the wrap to the first
    {-60.0, -179.95, -46.300868},      // just east of the antimeridian
    {46.041, 8.833, 48.247419},        // Monte Lema (CfRadial sample)
    {-35.661, 149.512, 18.879732},     // Captains Flat (ODIM sample)
};

TEST(Geoid, MatchesProjVgridshift) {
  const Result<GeoidGrid>& grid = defaultEgm96Grid();
  ASSERT_TRUE(grid.ok()) << grid.error();
  for (const GeoidCase& c : kPrjCases) {
    // Both sides interpolate the same float32 grid bilinearly in double; PROJ prints 6 decimals.
    // 1e-5 m allows the print rounding plus arithmetic order, and would catch any cell/axis error
    // (neighbouring grid values differ by centimetres to metres).
    EXPECT_NEAR(grid->undulationMeters(c.latDeg, c.lonDeg), c.undulationMeters, 1e-5)
        << "lat " << c.latDeg << " lon " << c.lonDeg;
  }
}

TEST(Geoid, LongitudeWrapsBeyondPlusMinus180) {
  const Result<GeoidGrid>& grid = defaultEgm96Grid();
  ASSERT_TRUE(grid.ok()) << grid.error();
  EXPECT_NEAR(grid->undulationMeters(48.0, 9.0 + 360.0), 48.101185, 1e-5);
  EXPECT_NEAR(grid->undulationMeters(-60.0, 180.05), -46.300868, 1e-5);
}

TEST(Geoid, MissingGridIsAClearError) {
  const std::string path = "/nonexistent/egm96_15.gtx";
  Result<GeoidGrid> g = GeoidGrid::load(path);
  ASSERT_FALSE(g.ok());
  EXPECT_NE(g.error().find(path), std::string::npos) << g.error();
}

TEST(Geoid, TruncatedGridIsAClearError) {
  const std::filesystem::path dir = std::filesystem::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "geoid";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "truncated.gtx").string();
  {
    // Header of the real grid (721 x 1440), then only 100 bytes of values.
    std::ifstream in(kDefaultEgm96GridPath, std::ios::binary);
    ASSERT_TRUE(in.good());
    std::string bytes(140, '\0');
    in.read(bytes.data(), 140);
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), 140);
  }
  Result<GeoidGrid> g = GeoidGrid::load(path);
  ASSERT_FALSE(g.ok());
  EXPECT_NE(g.error().find("truncated"), std::string::npos) << g.error();
}

}  // namespace
}  // namespace atmoglobe::volume
