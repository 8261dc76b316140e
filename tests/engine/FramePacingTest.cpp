// The viewer's moving image scale (engine/FramePacing.h) against a frame-cost model, and the
// frame-time summary.
#include <atmoglobe/engine/FramePacing.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {
using atmoglobe::engine::FrameTimeSummary;
using atmoglobe::engine::MovingImageScale;

// A frame of `fixedMs` that does not shrink with the scale (globe, map lines) plus a volume
// march that goes with its pixels: volumeMsAtQuarter at scale 0.25.
double frameMs(double scale, double fixedMs, double volumeMsAtQuarter) {
  return fixedMs + volumeMsAtQuarter * (scale / 0.25) * (scale / 0.25);
}

TEST(FramePacing, AnExpensiveSceneComesUnderTheTargetWithinAFewFrames) {
  // The global grid from space on llvmpipe: ~20 ms of globe and lines, ~135 ms of march at 0.25.
  MovingImageScale pacing;
  int framesOver = 0;
  for (int f = 0; f < 20; ++f) {
    const double t = frameMs(pacing.scale(), 20.0, 135.0);
    if (f >= 4) framesOver += t > MovingImageScale::kTargetMs;
    pacing.reportMovingFrame(t);
  }
  EXPECT_EQ(framesOver, 0) << "from the fifth frame on every frame is within the target";
  EXPECT_LT(pacing.scale(), 0.125);
  EXPECT_GE(pacing.scale(), MovingImageScale::kMinScale);
  // Settled: it no longer oscillates (the next frames keep one scale).
  const double settled = pacing.scale();
  for (int f = 0; f < 5; ++f) pacing.reportMovingFrame(frameMs(pacing.scale(), 20.0, 135.0));
  EXPECT_DOUBLE_EQ(pacing.scale(), settled);
}

TEST(FramePacing, ACheapSceneKeepsTheQuarterScaleAndAnImpossibleOneTheFloor) {
  MovingImageScale cheap;
  for (int f = 0; f < 10; ++f) cheap.reportMovingFrame(frameMs(cheap.scale(), 5.0, 10.0));
  EXPECT_DOUBLE_EQ(cheap.scale(), MovingImageScale::kMaxScale);
  // Slower than the target even with no volume at all: the floor, never below.
  MovingImageScale slow;
  for (int f = 0; f < 20; ++f) slow.reportMovingFrame(frameMs(slow.scale(), 60.0, 40.0));
  EXPECT_DOUBLE_EQ(slow.scale(), MovingImageScale::kMinScale);
  // Once the scene gets cheap again the scale climbs back to the quarter.
  for (int f = 0; f < 20; ++f) slow.reportMovingFrame(frameMs(slow.scale(), 5.0, 10.0));
  EXPECT_DOUBLE_EQ(slow.scale(), MovingImageScale::kMaxScale);
  // Nonsense times change nothing.
  slow.reportMovingFrame(std::nan(""));
  slow.reportMovingFrame(-1.0);
  EXPECT_DOUBLE_EQ(slow.scale(), MovingImageScale::kMaxScale);
}

TEST(FramePacing, SummaryGivesCountMedianP90AndMaxOfEachPart) {
  FrameTimeSummary s;
  EXPECT_EQ(s.text(), "");
  for (int i = 1; i <= 10; ++i) s.add(true, 10.0 * i);
  s.add(false, 7.0);
  EXPECT_EQ(s.text(),
            "moving: 10 frames, median 55.0 ms (p90 90.0, max 100.0); at rest: 1 frame, median 7.0 ms "
            "(p90 7.0, max 7.0)");
}

}  // namespace

TEST(FramePacing, AMotionStartsAtTheScaleTheLastFullMarchAsks) {
  MovingImageScale pacing(40.0);
  // 1,500 ms for the full-quality march: (40 - 20) ms left for it, sqrt(20 / 1500) = 0.115,
  // rounded down to 7/64.
  pacing.seedFromFullMarch(1500.0);
  EXPECT_DOUBLE_EQ(pacing.scale(), 7.0 / 64.0);
  // A cheap march keeps the quarter; an unknown one (0) leaves the scale as it is.
  pacing.seedFromFullMarch(100.0);
  EXPECT_DOUBLE_EQ(pacing.scale(), MovingImageScale::kMaxScale);
  pacing.reportMovingFrame(200.0);
  const double after = pacing.scale();
  pacing.seedFromFullMarch(0.0);
  EXPECT_DOUBLE_EQ(pacing.scale(), after);
  // A very expensive one: the floor.
  pacing.seedFromFullMarch(1.0e6);
  EXPECT_DOUBLE_EQ(pacing.scale(), MovingImageScale::kMinScale);
  // The frame at the seeded scale of the cost model of the tests above is within the target:
  // 20 ms of globe plus the march at scale^2 of 1,500 ms.
  pacing.seedFromFullMarch(1500.0);
  EXPECT_LE(20.0 + 1500.0 * pacing.scale() * pacing.scale(), 40.0);
}
