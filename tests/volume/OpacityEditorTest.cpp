// The transfer-function editor's GL-free parts: opacity control points in the transfer function
// (what both renderers classify with), editing the point list, and the value histogram the
// editor draws the points over.
#include <atmoglobe/volume/OpacityEditor.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarVolume.h>
#include <atmoglobe/volume/TransferFunction.h>
#include <atmoglobe/volume/ValueHistogram.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>

namespace {

using namespace atmoglobe;
using glm::dvec2;

// A table whose alpha is 255 everywhere (the NWS table's stops are opaque), so classify's alpha is
// the curve's opacity itself.
volume::TransferFunction opaqueTable() { return volume::defaultReflectivityTransfer(); }

TEST(OpacityPoints, ClassifyFollowsTheControlPoints) {
  const auto tf = volume::withOpacityPoints(opaqueTable(), {{20.0, 0.0}, {40.0, 0.6}, {50.0, 0.2}, {60.0, 0.9}});
  ASSERT_EQ(tf.opacityPoints.size(), 4u);
  EXPECT_DOUBLE_EQ(tf.opacityZeroValue, 20.0);  // the last leading zero point
  EXPECT_DOUBLE_EQ(tf.maxOpacity, 0.9);
  EXPECT_DOUBLE_EQ(tf.opacityFullValue, 60.0);
  // At the points, between them (linear), beyond them (the end points' opacity) and at/below zero.
  EXPECT_DOUBLE_EQ(tf.classify(40.0).a, 0.6);
  EXPECT_DOUBLE_EQ(tf.classify(30.0).a, 0.3);
  EXPECT_NEAR(tf.classify(45.0).a, 0.4, 1e-12);  // falling segment: 0.6 -> 0.2
  EXPECT_DOUBLE_EQ(tf.classify(70.0).a, 0.9);
  EXPECT_DOUBLE_EQ(tf.classify(20.0).a, 0.0);
  EXPECT_DOUBLE_EQ(tf.classify(5.0).a, 0.0);
  // Colours are untouched: the table's.
  EXPECT_EQ(glm::dvec3(tf.classify(45.0)), glm::dvec3(opaqueTable().classify(45.0)));
}

TEST(OpacityPoints, AFirstPointAboveZeroMakesEverythingBelowVisible) {
  const auto tf = volume::withOpacityPoints(opaqueTable(), {{30.0, 0.5}, {10.0, 0.25}});  // unsorted on purpose
  ASSERT_EQ(tf.opacityPoints.size(), 2u);
  EXPECT_DOUBLE_EQ(tf.opacityPoints.front().x, 10.0);
  EXPECT_LE(tf.opacityZeroValue, -1e30);  // the GPU's "echo above opacityZeroValue" passes every value
  EXPECT_DOUBLE_EQ(tf.classify(-5.0).a, 0.25);
  EXPECT_DOUBLE_EQ(tf.classify(20.0).a, 0.375);
}

TEST(OpacityPoints, FewerThanTwoPointsOrARampGoBackToTheRamp) {
  const auto base = opaqueTable();
  const auto one = volume::withOpacityPoints(base, {{30.0, 0.5}});
  EXPECT_TRUE(one.opacityPoints.empty());
  EXPECT_DOUBLE_EQ(one.classify(35.0).a, base.classify(35.0).a);
  const auto edited = volume::withOpacityPoints(base, {{0.0, 0.0}, {30.0, 1.0}});
  const auto ramp = volume::withOpacityRamp(edited, {10.0, 60.0, 0.8});  // the NWS default ramp
  EXPECT_TRUE(ramp.opacityPoints.empty());
  EXPECT_DOUBLE_EQ(ramp.classify(35.0).a, base.classify(35.0).a);
  // Opacities are clamped to [0, 1].
  const auto clamped = volume::withOpacityPoints(base, {{0.0, -1.0}, {30.0, 3.0}});
  EXPECT_DOUBLE_EQ(clamped.opacityPoints[0].y, 0.0);
  EXPECT_DOUBLE_EQ(clamped.opacityPoints[1].y, 1.0);
}

TEST(OpacityPoints, ValueRangeStretchMovesThePointsWithTheColours) {
  const auto tf = volume::withOpacityPoints(opaqueTable(), {{20.0, 0.0}, {40.0, 0.6}});
  const auto wide = volume::withValueRange(tf, -20.0, 140.0);  // the NWS table spans -10..75 (85 dB) -> 160 dB
  // A value and its image under the stretch classify alike (colour and opacity).
  for (double v : {25.0, 30.0, 38.0}) {
    const auto& stops = tf.colors.stops();
    const double a = (stops.front().value - tf.colors.offset()) / tf.colors.scale();
    const double b = (stops.back().value - tf.colors.offset()) / tf.colors.scale();
    const double image = -20.0 + (v - a) / (b - a) * 160.0;
    EXPECT_NEAR(wide.classify(image).a, tf.classify(v).a, 1e-9) << v;
  }
}

TEST(OpacityCurve, TheRampAsTwoPointsOrTheEditedPoints) {
  const auto base = opaqueTable();
  const auto curve = volume::opacityCurveOf(base);
  ASSERT_EQ(curve.size(), 2u);
  EXPECT_EQ(curve[0], dvec2(base.opacityZeroValue, 0.0));
  EXPECT_EQ(curve[1], dvec2(base.opacityFullValue, base.maxOpacity));
  // The ramp as points classifies as the ramp does.
  const auto asPoints = volume::withOpacityPoints(base, curve);
  for (double v = -20.0; v <= 80.0; v += 0.7) EXPECT_NEAR(asPoints.classify(v).a, base.classify(v).a, 1e-12) << v;
}

TEST(OpacityEditor, AddKeepsValueOrderAndReplacesAnEqualValue) {
  std::vector<dvec2> p{{0.0, 0.0}, {50.0, 1.0}};
  EXPECT_EQ(volume::addOpacityPoint(p, {20.0, 0.3}), 1u);
  EXPECT_EQ(volume::addOpacityPoint(p, {60.0, 2.0}), 3u);
  EXPECT_DOUBLE_EQ(p[3].y, 1.0);  // clamped
  EXPECT_EQ(volume::addOpacityPoint(p, {20.0, 0.5}), 1u);
  ASSERT_EQ(p.size(), 4u);
  EXPECT_DOUBLE_EQ(p[1].y, 0.5);
  for (std::size_t i = 1; i < p.size(); ++i) EXPECT_LT(p[i - 1].x, p[i].x);
}

TEST(OpacityEditor, MoveStaysBetweenNeighboursAndDeleteKeepsTwo) {
  std::vector<dvec2> p{{0.0, 0.0}, {20.0, 0.5}, {50.0, 1.0}};
  ASSERT_TRUE(volume::moveOpacityPoint(p, 1, {80.0, 0.7}, 1.0));  // dragged past its right neighbour
  EXPECT_DOUBLE_EQ(p[1].x, 49.0);
  EXPECT_DOUBLE_EQ(p[1].y, 0.7);
  ASSERT_TRUE(volume::moveOpacityPoint(p, 0, {-30.0, -1.0}, 1.0));  // the first point: free to the left
  EXPECT_EQ(p[0], dvec2(-30.0, 0.0));
  EXPECT_FALSE(volume::moveOpacityPoint(p, 7, {1.0, 1.0}, 1.0));
  EXPECT_TRUE(volume::deleteOpacityPoint(p, 1));
  EXPECT_EQ(p.size(), 2u);
  EXPECT_FALSE(volume::deleteOpacityPoint(p, 0)) << "a curve needs two points";
  EXPECT_FALSE(volume::deleteOpacityPoint(p, 5));
}

TEST(OpacityEditor, PickMeasuresInPixels) {
  const std::vector<dvec2> p{{0.0, 0.0}, {10.0, 0.5}, {60.0, 1.0}};
  // 0.25 dBZ and 0.01 opacity per pixel: (10.5, 0.53) is 2 px right and 3 px above point 1.
  const dvec2 perPixel(0.25, 0.01);
  EXPECT_EQ(volume::pickOpacityPoint(p, {10.5, 0.53}, perPixel, 6.0), std::optional<std::size_t>(1));
  EXPECT_EQ(volume::pickOpacityPoint(p, {10.5, 0.53}, perPixel, 3.0), std::nullopt);  // sqrt(13) = 3.6 px
  EXPECT_EQ(volume::pickOpacityPoint(p, {30.0, 0.5}, perPixel, 6.0), std::nullopt);
}

TEST(ValueHistogram, BinsEchoesAndCountsTheRestApart) {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> v{0.0f,  0.5f,   9.99f,           10.0f,           55.0f,           100.0f,
                             -3.0f, 101.0f, volume::kNoEcho, volume::kNoEcho, volume::kNoData, inf};
  const volume::ValueHistogram h = volume::valueHistogram(v, 0.0, 100.0, 10);
  ASSERT_EQ(h.counts.size(), 10u);
  EXPECT_EQ(h.counts[0], 3u);  // 0, 0.5, 9.99
  EXPECT_EQ(h.counts[1], 1u);  // 10: bins are closed on the left
  EXPECT_EQ(h.counts[5], 1u);
  EXPECT_EQ(h.counts[9], 1u);  // 100: the last bin is closed at hi
  EXPECT_EQ(h.below, 1u);
  EXPECT_EQ(h.above, 2u);  // 101 and +inf
  EXPECT_EQ(h.noEcho, 2u);
  EXPECT_EQ(h.noData, 1u);
  EXPECT_EQ(h.largestCount(), 3u);
  const std::uint64_t total =
      std::accumulate(h.counts.begin(), h.counts.end(), std::uint64_t{0}) + h.below + h.above + h.noEcho + h.noData;
  EXPECT_EQ(total, v.size());
}

TEST(ValueHistogram, OfARenderLayoutSpansItsMeasuredValues) {
  volume::PolarVolume pv;
  pv.values = {volume::kNoData, -5.0f, 12.0f, 12.5f, volume::kNoEcho, 40.0f};
  pv.minValue = -5.0f;
  pv.maxValue = 40.0f;
  const volume::ValueHistogram h = volume::valueHistogram(pv, 9);  // 5 dB bins
  EXPECT_DOUBLE_EQ(h.lo, -5.0);
  EXPECT_DOUBLE_EQ(h.hi, 40.0);
  EXPECT_EQ(h.counts[0], 1u);
  EXPECT_EQ(h.counts[3], 2u);  // 12 and 12.5 in [10, 15)
  EXPECT_EQ(h.counts[8], 1u);
  EXPECT_EQ(h.noData + h.noEcho, 2u);
  // One value only: a span of 1 around it, not a division by zero.
  pv.values = {7.0f};
  pv.minValue = pv.maxValue = 7.0f;
  const volume::ValueHistogram one = volume::valueHistogram(pv, 4);
  EXPECT_DOUBLE_EQ(one.lo, 6.5);
  EXPECT_EQ(one.counts[2], 1u);
}

}  // namespace
