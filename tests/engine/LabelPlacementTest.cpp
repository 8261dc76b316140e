// Label placement (LabelPlacement.h): GL-free, so every rule is checked on boxes.
#include <atmoglobe/engine/LabelPlacement.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace atmoglobe::engine;

namespace {
LabelCandidate label(double x, double y, double priority, double w = 40.0, double h = 16.0) {
  LabelCandidate c;
  c.anchorXPx = x;
  c.anchorYPx = y;
  c.markerRadiusPx = 5.0;
  c.widthPx = w;
  c.heightPx = h;
  c.priority = priority;
  return c;
}
LabelBox disc(const LabelCandidate& c) {
  return {c.anchorXPx - c.markerRadiusPx, c.anchorYPx - c.markerRadiusPx, 2 * c.markerRadiusPx, 2 * c.markerRadiusPx};
}
}  // namespace

TEST(LabelPlacement, LoneLabelGoesRightOfItsMarker) {
  const auto placed = placeLabels({label(100, 100, 1)}, {640, 480, 2.0});
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_EQ(placed[0].slot, LabelSlot::Right);
  EXPECT_DOUBLE_EQ(placed[0].box.leftPx, 100 + 5 + 2);
  EXPECT_DOUBLE_EQ(placed[0].box.topPx, 100 - 8);
}

TEST(LabelPlacement, AtTheRightEdgeTheLabelMovesLeft) {
  const auto placed = placeLabels({label(620, 100, 1)}, {640, 480, 2.0});
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_EQ(placed[0].slot, LabelSlot::Left);
  EXPECT_LE(placed[0].box.leftPx + placed[0].box.widthPx, 620 - 5);
}

TEST(LabelPlacement, HigherPriorityKeepsItsSlotTheOtherMovesOrIsDropped) {
  // Two markers 20 px apart on a row: both want the right slot. B (higher priority, listed
  // second) is placed first and keeps it; A's right slot would cover B's disc, so A moves.
  const std::vector<LabelCandidate> c = {label(100, 100, 1), label(120, 100, 2)};
  const auto placed = placeLabels(c, {640, 480, 2.0});
  ASSERT_EQ(placed.size(), 2u);
  EXPECT_EQ(placed[0].candidate, 1u);  // the higher priority first
  EXPECT_EQ(placed[0].slot, LabelSlot::Right);
  EXPECT_EQ(placed[1].candidate, 0u);
  EXPECT_NE(placed[1].slot, LabelSlot::Right);
  EXPECT_FALSE(placed[0].box.overlaps(placed[1].box));
}

TEST(LabelPlacement, AStackOfMarkersAtOnePointKeepsOnlyWhatFits) {
  // 20 markers at the same pixel: only the eight slots exist, and the side and diagonal slots
  // of one marker overlap each other (the boxes are wider than the disc), so fewer than 8.
  std::vector<LabelCandidate> c;
  for (int i = 0; i < 20; ++i) c.push_back(label(300, 200, i));
  const auto placed = placeLabels(c, {640, 480, 2.0});
  EXPECT_GE(placed.size(), 2u);
  EXPECT_LT(placed.size(), 8u);
  EXPECT_EQ(placed[0].candidate, 19u);  // the highest priority survives
}

TEST(LabelPlacement, RandomMarkersNeverGiveOverlappingLabelsOrCoverAMarker) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(0, 800), y(0, 600), p(0, 10);
  std::vector<LabelCandidate> c;
  for (int i = 0; i < 300; ++i) c.push_back(label(x(rng), y(rng), p(rng), 30 + p(rng) * 4, 17));
  const auto placed = placeLabels(c, {800, 600, 2.0});
  ASSERT_GT(placed.size(), 20u);  // dense, but a good share still fits
  ASSERT_LT(placed.size(), c.size());
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const LabelBox& b = placed[i].box;
    EXPECT_GE(b.leftPx, 0.0);
    EXPECT_GE(b.topPx, 0.0);
    EXPECT_LE(b.leftPx + b.widthPx, 800.0);
    EXPECT_LE(b.topPx + b.heightPx, 600.0);
    EXPECT_EQ(b.widthPx, c[placed[i].candidate].widthPx);
    for (std::size_t j = i + 1; j < placed.size(); ++j) EXPECT_FALSE(b.overlaps(placed[j].box)) << i << " " << j;
    for (std::size_t k = 0; k < c.size(); ++k) {
      // Only markers of lower priority may be covered (the second round of a crowded label).
      if (k != placed[i].candidate && c[k].priority >= c[placed[i].candidate].priority) {
        EXPECT_FALSE(b.overlaps(disc(c[k]))) << "label " << i << " covers marker " << k;
      }
    }
    // Greedy by priority: placed in order of priority.
    if (i > 0) {
      EXPECT_GE(c[placed[i - 1].candidate].priority, c[placed[i].candidate].priority);
    }
  }
}

TEST(LabelPlacement, MarkersWithoutLabelsAreObstacles) {
  LabelCandidate obstacle = label(115, 100, 0, 0.0, 0.0);  // no label, disc right of A
  const auto placed = placeLabels({label(100, 100, 1), obstacle}, {640, 480, 2.0});
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_EQ(placed[0].candidate, 0u);
  EXPECT_NE(placed[0].slot, LabelSlot::Right);
}

TEST(LabelPlacement, AHighPriorityLabelAmongDenseMarkersCoversLowerOnesRatherThanVanish) {
  // A radar (priority 2) ringed by stations (priority 1) 12 px away on all sides: every slot
  // covers a station's disc, so without the second round it would have no label.
  std::vector<LabelCandidate> c{label(200, 200, 2.0)};
  for (int k = 0; k < 16; ++k) {
    const double a = k * 2.0 * 3.141592653589793 / 16.0;
    c.push_back(label(200 + 40 * std::cos(a), 200 + 40 * std::sin(a), 1.0, 0.0, 0.0));  // unlabelled dots
    c.push_back(label(200 + 14 * std::cos(a), 200 + 14 * std::sin(a), 1.0, 0.0, 0.0));
  }
  const auto placed = placeLabels(c, {640, 480, 2.0});
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_EQ(placed[0].candidate, 0u);
  // An equal-priority ring is not covered: the label is dropped.
  for (std::size_t k = 1; k < c.size(); ++k) c[k].priority = 2.0;
  EXPECT_TRUE(placeLabels(c, {640, 480, 2.0}).empty());
}
