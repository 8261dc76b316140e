// The bench's settings grid, views and measures (tools/bench: Cells.h, Views.h, Measure.h),
// without GL: cell counts as docs/bench-volume.md states them, the one engine default, the
// views' cameras looking at the antenna, medians and image conversions.
#include <atmoglobe/bench/Cells.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/bench/Views.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::bench {
namespace {

std::size_t countIf(const std::vector<Cell>& cells, bool (*pred)(const Cell&)) {
  return static_cast<std::size_t>(std::count_if(cells.begin(), cells.end(), pred));
}

// docs/bench-volume.md: 126 DVR cells (7 steps x 3 scales x {nearest, linear} x 2 beams, every
// linear cell again pre-integrated) + 56 of adaptive refinement (7 steps x scales 1/2, 1/4 x
// thresholds 4, 32 x point, pre-integrated; linear, 4/3-Earth) + MIP + ISO = 184 rows per view;
// the quick grid 24 + 4 (2 steps x scale 1/2 x threshold 4 x 2) + 2.
TEST(BenchGrid, CellCountsAndTheEngineDefault) {
  const std::vector<Cell> full = gridCells(standardAxes(false, {}));
  EXPECT_EQ(full.size(), 184u);
  EXPECT_EQ(countIf(full, [](const Cell& c) { return c.mode == volume::VolumeRenderMode::Dvr; }), 182u);
  EXPECT_EQ(countIf(full, [](const Cell& c) { return c.refineThreshold >= 0.0; }), 56u);
  // Refinement only of a smaller image, linear, with the 4/3-Earth beam.
  EXPECT_EQ(countIf(full,
                    [](const Cell& c) {
                      return c.refineThreshold >= 0.0 &&
                             (c.imageScale >= 1.0 || c.interpolation != volume::Interpolation::Linear ||
                              c.beam != engine::BeamApproximation::EffectiveEarthLocalSphere);
                    }),
            0u);
  EXPECT_EQ(countIf(full,
                    [](const Cell& c) {
                      return c.classification == engine::Classification::Preintegrated &&
                             c.interpolation != volume::Interpolation::Linear;
                    }),
            0u);  // pre-integration only with linear interpolation
  EXPECT_EQ(countIf(full, [](const Cell& c) { return c.mode == volume::VolumeRenderMode::Dvr && isEngineDefault(c); }),
            1u);
  const std::vector<Cell> quick = gridCells(standardAxes(true, {}));
  EXPECT_EQ(quick.size(), 30u);
  EXPECT_EQ(quick.back().mode, volume::VolumeRenderMode::Iso);
  EXPECT_TRUE(isEngineDefault(quick.back()));

  const GridAxes steps = standardAxes(true, {1000.0, 250.0, 1000.0});
  EXPECT_EQ(steps.stepsMeters, (std::vector<double>{250.0, 1000.0}));  // sorted, duplicates removed
  EXPECT_EQ(steps.imageScales, (std::vector<double>{1.0, 0.5}));
}

TEST(BenchGrid, NamesAndOptions) {
  Cell c;
  c.stepMeters = 1000.0;
  c.imageScale = 0.5;
  c.classification = engine::Classification::Preintegrated;
  EXPECT_EQ(cellLabel(c), "dvr step 1000 m, scale 0.5, linear, 4/3-earth, pre-integrated");
  EXPECT_STREQ(classificationName(c), "preintegrated");
  c.mode = volume::VolumeRenderMode::Iso;
  EXPECT_STREQ(classificationName(c), "-");
  const engine::VolumeRenderOptions o = optionsFor(c);
  EXPECT_EQ(o.render.stepMeters, 1000.0);
  EXPECT_EQ(o.imageScale, 0.5);
  EXPECT_TRUE(o.skipEmptySpace);
  EXPECT_EQ(o.render.mode, volume::VolumeRenderMode::Iso);
}

TEST(BenchGrid, ViewNamesAndFiles) {
  EXPECT_EQ(benchViewNames(benchFiles(false), false),
            (std::vector<std::string>{"KLBB-oblique", "KLBB-down", "AU40-oblique", "AU40-down"}));
  EXPECT_EQ(benchViewNames(benchFiles(true), true), (std::vector<std::string>{"KLBB-oblique"}));
}

// The oblique camera is 200 km from the antenna along the geodesic, 100 km up, and looks at it.
TEST(BenchGrid, ObliqueViewLooksAtTheAntenna) {
  BenchVolume v;
  v.key = "KLBB";
  v.polar.site = {33.6541, -101.8142, 1000.0};
  const BenchView view = obliqueView("KLBB-oblique", v, 180.0, 200e3, 100e3);
  EXPECT_EQ(view.volume, &v);
  EXPECT_EQ(view.fovYDeg, 50.0);
  EXPECT_EQ(view.pose.heightMeters, 100e3);
  const globe::GeodesicPoint back = globe::geodesicDirect(33.6541, -101.8142, 180.0, 200e3);
  EXPECT_NEAR(view.pose.latDeg, back.latDeg, 1e-12);
  const engine::Camera camera(view.pose, view.fovYDeg, 160, 90);
  const glm::dvec3 site = globe::geodeticToEcef({33.6541, -101.8142, 1000.0});
  const glm::dvec3 toSite = glm::normalize(site - camera.eyeEcef());
  EXPECT_GT(glm::dot(toSite, camera.forwardEcef()), 0.0);
  EXPECT_LT(glm::length(glm::cross(toSite, camera.forwardEcef())), 1e-9);  // sine of the angle between them

  const BenchView down = topDownView("KLBB-down", v, 400e3);
  EXPECT_EQ(down.pose.pitchDeg, -90.0);
  EXPECT_EQ(down.fovYDeg, 60.0);
}

TEST(BenchGrid, MedianAndImageConversions) {
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 2.0, 3.0}), 2.5);
  EXPECT_TRUE(std::isnan(median({})));

  globe::ImageRGBA8 img = globe::ImageRGBA8::filled(2, 1, {0, 0, 0, 0});
  img.set(0, 0, {255, 128, 0, 255});
  img.set(1, 0, {10, 20, 30, 40});
  const volume::VolumeImage v = fromRgba8(img);
  EXPECT_EQ(v.at(0, 0), glm::dvec4(1.0, 128.0 / 255.0, 0.0, 1.0));
  const globe::ImageRGBA8 back = toRgba8(v);  // over black, opaque
  EXPECT_EQ(back.at(0, 0), glm::u8vec4(255, 128, 0, 255));
  EXPECT_EQ(back.at(1, 0), glm::u8vec4(10, 20, 30, 255));
}

}  // namespace
}  // namespace atmoglobe::bench
