// Contour lines through GDAL (map/Contours.h): lines of analytic fields where they must be, bad
// input refused.
#include <atmoglobe/map/Contours.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace {
using namespace atmoglobe::map;

// A raster over 10..30 E, 40..50 N of 200 x 100 pixels of 0.1 deg, filled by f(lon, lat) at the
// pixel centres.
template <class F>
std::vector<float> fill(const ContourRaster& r, F f) {
  std::vector<float> v(static_cast<std::size_t>(r.columns) * r.rows);
  for (int j = 0; j < r.rows; ++j)
    for (int i = 0; i < r.columns; ++i)
      v[static_cast<std::size_t>(j) * r.columns + i] =
          static_cast<float>(f(r.westDeg + (i + 0.5) * r.dxDeg, r.northDeg - (j + 0.5) * r.dyDeg));
  return v;
}

ContourRaster box() {
  ContourRaster r;
  r.columns = 200;
  r.rows = 100;
  r.westDeg = 10.0;
  r.northDeg = 50.0;
  r.dxDeg = r.dyDeg = 0.1;
  return r;
}

TEST(Contours, ALinearFieldGivesStraightLinesWhereItTakesTheValue) {
  // v = 3 (lon - 10): the line of value c is the meridian lon = 10 + c / 3. Marching squares
  // interpolate linearly between pixel centres, so on a linear field a line is exact up to float
  // rounding of the values (1e-6 relative of 60).
  ContourRaster r = box();
  const std::vector<float> v = fill(r, [](double lon, double) { return 3.0 * (lon - 10.0); });
  r.values = v.data();
  ContourLevels levels;
  levels.interval = 7.5;  // the centres run from 0.15 to 59.85: 7.5, 15 ... 52.5
  auto lines = contourLines(r, levels);
  ASSERT_TRUE(lines.ok()) << lines.error();
  ASSERT_EQ(lines->size(), 7u);  // 7.5 .. 52.5
  double worstPx = 0.0;
  for (const ContourLine& c : *lines) {
    const double lon = 10.0 + c.value / 3.0;
    double south = 90.0, north = -90.0;
    for (const auto& p : c.line.lonLatDeg) {
      worstPx = std::max(worstPx, std::abs(p.x - lon) / r.dxDeg);
      south = std::min(south, p.y);
      north = std::max(north, p.y);
    }
    // From edge to edge: GDAL takes the edge pixels' values out to the raster's border.
    EXPECT_NEAR(north, 50.0, 1e-9) << c.value;
    EXPECT_NEAR(south, 40.0, 1e-9) << c.value;
  }
  EXPECT_LT(worstPx, 1e-4) << "a line is off its meridian (0.5 would mean pixel corners taken for centres)";
}

TEST(Contours, ARadialFieldGivesCirclesOfItsRadius) {
  // v = distance from (20 E, 45 N) in pixels (a plane field on the raster's own axes): the line of
  // value c is the circle of c pixels. Linear interpolation of a distance between pixel centres
  // errs by at most 1 / (8 c) px (the chord of a curved level set): under 0.01 px at 15 px.
  ContourRaster r = box();
  const std::vector<float> v =
      fill(r, [](double lon, double lat) { return std::hypot((lon - 20.0) / 0.1, (lat - 45.0) / 0.1); });
  r.values = v.data();
  ContourLevels levels;
  levels.values = {15.0, 30.0, 45.0};
  auto lines = contourLines(r, levels);
  ASSERT_TRUE(lines.ok()) << lines.error();
  ASSERT_EQ(lines->size(), 3u);  // closed circles, one line each
  for (const ContourLine& c : *lines) {
    double worst = 0.0;
    for (const auto& p : c.line.lonLatDeg)
      worst = std::max(worst, std::abs(std::hypot((p.x - 20.0) / 0.1, (p.y - 45.0) / 0.1) - c.value));
    EXPECT_LT(worst, 1.0 / (8.0 * c.value) + 1e-4) << c.value;
    EXPECT_EQ(c.line.lonLatDeg.front(), c.line.lonLatDeg.back()) << "a closed ring";
    EXPECT_GT(c.line.lonLatDeg.size(), 20u);
  }
}

TEST(Contours, MissingValuesBreakLinesAndBadInputIsRefused) {
  ContourRaster r = box();
  std::vector<float> v = fill(r, [](double lon, double) { return lon; });
  // A missing band of columns 95..104 (19.5 .. 20.5 E): the line at 20 E has nowhere to run.
  for (int j = 0; j < r.rows; ++j)
    for (int i = 95; i < 105; ++i) v[static_cast<std::size_t>(j) * r.columns + i] = std::nanf("");
  v[0] = std::numeric_limits<float>::infinity();  // no-echo: missing too
  r.values = v.data();
  ContourLevels levels;
  levels.values = {15.0, 20.0};
  auto lines = contourLines(r, levels);
  ASSERT_TRUE(lines.ok()) << lines.error();
  ASSERT_EQ(lines->size(), 1u);
  EXPECT_EQ(lines->front().value, 15.0);

  ContourLevels tooMany;
  tooMany.interval = 0.001;  // 20000 lines over 10..30
  auto many = contourLines(r, tooMany);
  ASSERT_FALSE(many.ok());
  EXPECT_NE(many.error().find("at most 1000"), std::string::npos) << many.error();
  ContourRaster tiny = r;
  tiny.columns = 1;
  EXPECT_FALSE(contourLines(tiny, levels).ok());

  EXPECT_TRUE(parseContourLevels("5", "").ok());
  EXPECT_EQ(parseContourLevels("", "5400, 5520,5400").value().values, (std::vector<double>{5400, 5520}));
  for (auto [interval, values] : std::vector<std::pair<std::string, std::string>>{
           {"0", ""}, {"-2", ""}, {"abc", ""}, {"", "1,x"}, {"", ","}, {"5", "1,2"}, {"", ""}}) {
    auto p = parseContourLevels(interval, values);
    EXPECT_FALSE(p.ok()) << interval << " / " << values;
  }
  EXPECT_EQ(contourLabel(5640.0), "5640");
  EXPECT_EQ(contourLabel(-2.5), "-2.5");
}

}  // namespace
