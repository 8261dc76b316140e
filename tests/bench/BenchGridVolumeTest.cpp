// The grid bench's pieces that need no GL and no timing (tools/bench: PeerGrid.h's sampler
// resampler and its error bound, GridViews.h's visible crop, GridLoad.h's hyperslabs, Report.h's
// comparison with the peer, Cells.h's grid cells).
#include <atmoglobe/bench/Cells.h>
#include <atmoglobe/bench/GridLoad.h>
#include <atmoglobe/bench/GridViews.h>
#include <atmoglobe/bench/PeerGrid.h>
#include <atmoglobe/bench/Report.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/SyntheticGrid.h>

#include "../TestOutputDir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <sstream>

namespace atmoglobe::bench {
namespace {

/// An analytic field f(enu) in a frame, Echo everywhere inside a sphere of 60 km.
class AnalyticSampler final : public volume::VolumeSampler {
 public:
  AnalyticSampler(PeerFrame frame, std::function<double(const glm::dvec3&)> f) : frame_(frame), f_(std::move(f)) {}
  volume::RayInterval rayInterval(const glm::dvec3& eye, const glm::dvec3& dir) const override {
    return volume::raySphereInterval(eye, dir, frame_.originEcef, 6e4);
  }
  volume::VolumeSample sample(const glm::dvec3& ecef, volume::Interpolation) const override {
    const glm::dvec3 p = frame_.toEnu(ecef);
    if (glm::length(p) > 6e4) return {};
    return {volume::VolumeSample::State::Echo, f_(p)};
  }
  volume::ValueRange valueRange() const override { return {-1e9, 1e9}; }
  volume::BoundingSphere boundingSphere() const override { return {frame_.originEcef, 6e4}; }
  std::string description() const override { return "analytic"; }

 private:
  PeerFrame frame_;
  std::function<double(const glm::dvec3&)> f_;
};

// A field linear in the frame coordinates is reproduced by trilinear interpolation exactly (to
// float32 storage: values up to ~60 here, float spacing 4e-6); a misplaced voxel (wrong origin,
// spacing or axis order) would be off by the gradient times the shift, >= 0.01 for any shift
// above 1 m.
TEST(BenchGridPeer, LinearFieldIsReproducedExactly) {
  const PeerFrame frame = enuFrameAt(35.0, -97.0, 0.0);
  AnalyticSampler s(frame, [](const glm::dvec3& p) { return 0.001 * p.x - 0.0005 * p.y + 0.002 * p.z + 3.0; });
  PeerGrid g = layoutPeerGrid(glm::dvec3(-2e4, -1.5e4, 0.0), glm::dvec3(2e4, 1.5e4, 1e4), 500.0, 1e9);
  std::vector<float> values;
  resampleSampler(s, frame, g, -100.0, 2, &values);
  ASSERT_EQ(values.size(), static_cast<std::size_t>(g.nx) * g.ny * g.nz);
  measureReconstructionError(s, frame, g, values, -100.0, -1e9, 5000);
  EXPECT_EQ(g.reconstructionPoints, 5000);
  EXPECT_LT(g.maxReconstructionError, 1e-4);
  // Outside the box: the empty value.
  EXPECT_EQ(trilinearAt(g, values, glm::dvec3(3e4, 0, 0), -100.0), -100.0);
}

// A quadratic field: the trilinear error stays within the classical bound h^2/8 (|f_xx| + |f_yy|
// + |f_zz|), and is not far below it (the bound is reached at cell centres: at least a quarter of
// it over 5000 random points, else the grid would be finer than claimed).
TEST(BenchGridPeer, QuadraticFieldErrorWithinTheTrilinearBound) {
  const PeerFrame frame = enuFrameAt(-20.0, 150.0, 0.0);
  const double a = 2e-7, b = 1e-7, c = 5e-6;  // f = a x^2 + b y^2 + c z^2: f_xx = 2a, ...
  AnalyticSampler s(frame, [&](const glm::dvec3& p) { return a * p.x * p.x + b * p.y * p.y + c * p.z * p.z; });
  PeerGrid g = layoutPeerGrid(glm::dvec3(-2e4, -2e4, 0.0), glm::dvec3(2e4, 2e4, 5e3), 400.0, 1e9);
  std::vector<float> values;
  resampleSampler(s, frame, g, 0.0, 2, &values);
  measureReconstructionError(s, frame, g, values, 0.0, -1e9, 5000);
  const double bound = trilinearErrorBound(g.spacingMeters, 2 * a + 2 * b + 2 * c);
  EXPECT_LE(g.maxReconstructionError, bound * 1.0001 + 1e-3);  // + float32 storage of values up to ~130
  EXPECT_GT(g.maxReconstructionError, 0.25 * bound);
}

// The cap coarsens uniformly and says why.
TEST(BenchGridPeer, LayoutCoarsensToTheCap) {
  const PeerGrid g = layoutPeerGrid(glm::dvec3(0.0), glm::dvec3(1e5, 1e5, 1e4), 100.0, 1e6);
  EXPECT_GT(g.spacingMeters, 100.0);
  // The box in voxels is at the cap (the counts round each side up to whole voxels, + 1 for the
  // last centre).
  EXPECT_NEAR(1e5 / g.spacingMeters * 1e5 / g.spacingMeters * 1e4 / g.spacingMeters, 1e6, 1.0);
  EXPECT_EQ(g.nz, static_cast<int>(std::ceil(1e4 / g.spacingMeters)) + 1);
  EXPECT_NE(g.coarsenedReason.find("native 100 m"), std::string::npos);
}

volume::GridVolume smallGlobalGrid(const std::string& dir) {
  const std::string path = dir + "/global.nc";
  volume::SyntheticGlobalGridOptions o;
  o.nx = 144, o.ny = 73;
  EXPECT_TRUE(volume::writeSyntheticGlobalGrid(path, o).ok());
  auto g = volume::readGridVolume(path, {});
  EXPECT_TRUE(g.ok()) << (g ? "" : g.error());
  return g ? std::move(*g) : volume::GridVolume{};
}

// A view straight down over a point sees a crop around it, far smaller than the globe; a view of
// the sky sees nothing; a view over the antimeridian gets a crop across it.
TEST(BenchGridCrop, VisibleCropHoldsWhatTheCameraSees) {
  const volume::GridVolume g = smallGlobalGrid(atmoglobe_test::freshTestDir("bench_grid_crop"));
  ASSERT_EQ(g.nx, 144u);
  engine::CameraPose down;
  down.latDeg = 40.0, down.lonDeg = 10.0, down.heightMeters = 1e6, down.pitchDeg = -90.0;
  const volume::GridCrop c = visibleCrop(engine::Camera(down, 50.0, 320, 180), g);
  EXPECT_LT(c.southDeg, 40.0);
  EXPECT_GT(c.northDeg, 40.0);
  EXPECT_LT(c.westDeg, 10.0);
  EXPECT_GT(c.eastDeg, 10.0);
  // 1000 km up, fovY 50: about 930 x 1650 km on the ground = 8 x 19 degrees; a stride of 2.5
  // degrees of margin on each side.
  EXPECT_LT(c.northDeg - c.southDeg, 20.0);
  EXPECT_LT(c.eastDeg - c.westDeg, 40.0);
  engine::CameraPose sky = down;
  sky.pitchDeg = 80.0;
  sky.heightMeters = 1e5;
  const volume::GridCrop none = visibleCrop(engine::Camera(sky, 20.0, 320, 180), g);
  EXPECT_GT(none.southDeg, none.northDeg);
  engine::CameraPose seam = down;
  seam.lonDeg = 179.0;
  const volume::GridCrop across = visibleCrop(engine::Camera(seam, 50.0, 320, 180), g);
  EXPECT_GT(across.westDeg, across.eastDeg);  // east < west: across the antimeridian
}

// The hyperslabs of a crop across the seam of a global grid file (0 = 360 degrees): two per variable (the variable and
// its geopotential), columns adding up to the crop's, rows and levels as read.
TEST(BenchGridLoad, CropAcrossTheSeamIsTwoSlabsPerVariable) {
  const std::string dir = atmoglobe_test::freshTestDir("bench_grid_load");
  volume::SyntheticGlobalGridOptions o;
  o.nx = 144, o.ny = 73;
  ASSERT_TRUE(volume::writeSyntheticGlobalGrid(dir + "/g.nc", o).ok());
  volume::GridReadOptions r;
  r.crop.southDeg = -10, r.crop.northDeg = 20, r.crop.westDeg = -10,
  r.crop.eastDeg = 10;  // across the file's 0/360 seam
  auto g = volume::readGridVolume(dir + "/g.nc", r);
  ASSERT_TRUE(g.ok()) << g.error();
  auto slabs = cropHyperslabs(dir + "/g.nc", *g, {"/z"});
  ASSERT_TRUE(slabs.ok()) << slabs.error();
  ASSERT_EQ(slabs->size(), 4u);
  std::size_t columns = 0;
  for (const Hyperslab& s : *slabs) {
    ASSERT_EQ(s.count.size(), 4u);
    EXPECT_EQ(s.count[1], 37u);    // every level
    EXPECT_EQ(s.count[2], g->ny);  // the crop's rows
    if (s.variable == "/dbz") columns += s.count[3];
  }
  EXPECT_EQ(columns, g->nx);
  EXPECT_EQ((*slabs)[0].start[3] + (*slabs)[0].count[3], 144u);  // up to the last column, then from 0
  EXPECT_EQ((*slabs)[1].start[3], 0u);
}

// Grid cells: no beam axis (4/3 only, printed "-"): 7 steps x 3 scales x (nearest, linear, linear
// pre-integrated) + adaptive refinement 7 x 2 scales x 2 thresholds x 2 classifications + MIP + ISO
// = 121; quick 2 x 2 x 3 + 2 x 1 x 1 x 2 + 2 = 18; one engine default among the DVR. With the step
// rule at 1 and 2 samples per cell, each point refinement cell again at each: 28 more.
TEST(BenchGridReport, GridCellsAndThePeerComparison) {
  const std::vector<Cell> cells = gridCells(standardAxes(false, {}), false);
  EXPECT_EQ(cells.size(), 121u);
  EXPECT_EQ(gridCells(standardAxes(true, {}), false).size(), 18u);
  const std::vector<Cell> ruled = gridCells(standardAxes(false, {}), false, {1.0, 2.0});
  const auto refinedWithRule = std::count_if(
      ruled.begin(), ruled.end(), [](const Cell& c) { return c.refineThreshold >= 0.0 && c.samplesPerCell > 0.0; });
  EXPECT_EQ(refinedWithRule, 7 * 2 * 2 * 2);
  for (const Cell& c : cells) EXPECT_STREQ(beamName(c), "-");
  EXPECT_EQ(cellLabel(cells.front()), "dvr step 125 m, scale 1, nearest");

  Row fast, slow, wrongView;
  fast.view = slow.view = "v", wrongView.view = "w";
  fast.medianMs = 10, fast.error.meanAbs = 0.5;
  slow.medianMs = 30, slow.error.meanAbs = 0.1;
  wrongView.medianMs = 1, wrongView.error.meanAbs = 0.0;
  const std::vector<Row> rows = {slow, fast, wrongView};
  ASSERT_NE(fastestAtOrBelowError(rows, "v", 0.6), nullptr);
  EXPECT_EQ(fastestAtOrBelowError(rows, "v", 0.6)->medianMs, 10.0);
  EXPECT_EQ(fastestAtOrBelowError(rows, "v", 0.2)->medianMs, 30.0);
  EXPECT_EQ(fastestAtOrBelowError(rows, "v", 0.05), nullptr);

  // The markdown says "met" only when ours is faster and the grid at least 10x our volume.
  BenchReport r;
  r.kind = "grid";
  Row ours = fast;
  ours.gpuBytes = 10'000'000;
  r.rows = {ours};
  PeerGrid g;
  g.nx = g.ny = g.nz = 300;  // 108 MB: 10.8x
  r.peer.grids["v"] = g;
  PeerResult p;
  p.view = "v", p.mapper = "gpu", p.medianMs = 20, p.ok = true, p.error.meanAbs = 0.6;
  r.peer.results = {p};
  std::ostringstream md;
  writeGridMarkdown(md, r);
  EXPECT_NE(md.str().find("| 2x | 10.8x | met |"), std::string::npos) << md.str();
  r.peer.grids["v"].nx = 100;  // 36 MB: 3.6x
  std::ostringstream md2;
  writeGridMarkdown(md2, r);
  EXPECT_NE(md2.str().find("| not met |"), std::string::npos);
}

}  // namespace
}  // namespace atmoglobe::bench
