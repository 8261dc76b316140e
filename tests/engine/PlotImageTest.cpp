// The bench's scatter plot: axis ranges follow the 1-2-5 rule (worked by hand below), and a
// point is drawn at the pixel its data coordinates map to.
#include <atmoglobe/engine/PlotImage.h>

#include <gtest/gtest.h>

namespace {

using namespace atmoglobe;

TEST(PlotImage, LogAxisWidensToWholeOneTwoFiveValues) {
  engine::ScatterPlot plot;
  plot.logX = true;
  plot.points.resize(2);
  plot.points[0].x = 3.0, plot.points[0].y = 0.2;
  plot.points[1].x = 70.0, plot.points[1].y = 2.7;
  const engine::PlotFrame f = engine::layoutPlot(plot, 960, 600);
  // By hand: the largest 1-2-5 value <= 3 is 2, the smallest >= 70 is 100.
  EXPECT_DOUBLE_EQ(f.xMin, 2.0);
  EXPECT_DOUBLE_EQ(f.xMax, 100.0);
  // y: range 2.5 / 6 = 0.417 -> nice step 0.5; floor(0.2 / 0.5) * 0.5 = 0, ceil(2.7 / 0.5) * 0.5 = 3.
  EXPECT_DOUBLE_EQ(f.yMin, 0.0);
  EXPECT_DOUBLE_EQ(f.yMax, 3.0);
  // The axis ends map to the plot area's corners; on a log axis sqrt(2 * 100) is the middle.
  EXPECT_DOUBLE_EQ(f.toPixel(2.0, 0.0).x, f.left);
  EXPECT_DOUBLE_EQ(f.toPixel(100.0, 3.0).x, f.right);
  EXPECT_DOUBLE_EQ(f.toPixel(100.0, 3.0).y, f.top);
  EXPECT_NEAR(f.toPixel(std::sqrt(200.0), 0.0).x, 0.5 * (f.left + f.right), 1e-9);
}

TEST(PlotImage, PointIsDrawnWhereItsDataCoordinatesMap) {
  engine::ScatterPlot plot;
  plot.logX = true;
  engine::PlotPoint a;
  a.x = 10.0, a.y = 1.0, a.color = {200, 0, 0, 255}, a.radiusPx = 3;
  engine::PlotPoint b;
  b.x = 50.0, b.y = 2.0, b.color = {0, 0, 200, 255}, b.radiusPx = 3;
  plot.points = {a, b};
  const globe::ImageRGBA8 img = engine::drawScatterPlot(plot, 400, 300);
  ASSERT_EQ(img.width, 400);
  ASSERT_EQ(img.height, 300);
  const engine::PlotFrame f = engine::layoutPlot(plot, 400, 300);
  for (const engine::PlotPoint& p : plot.points) {
    const glm::dvec2 q = f.toPixel(p.x, p.y);
    const int x = static_cast<int>(std::floor(q.x)), y = static_cast<int>(std::floor(q.y));
    EXPECT_EQ(img.at(x, y), p.color);
    // 5 px away (outside the 3 px disc) it is not the point's colour.
    EXPECT_NE(img.at(x, y - 5), p.color);
  }
  // Axis range by the 1-2-5 rule: x 10..50 and y 1..2 exactly, so `a` sits in the bottom-left
  // corner and `b` in the top-right one; the top-left corner's inside is white background.
  EXPECT_DOUBLE_EQ(f.xMin, 10.0);
  EXPECT_DOUBLE_EQ(f.xMax, 50.0);
  EXPECT_EQ(img.at(f.left + 3, f.top + 3), glm::u8vec4(255, 255, 255, 255));
}

}  // namespace
