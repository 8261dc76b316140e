// The report (tools/bench: Report.h) from a small hand-made set of rows: the aggregation and the
// Pareto front, and the CSV and markdown text exactly (the format docs/bench-volume.md
// describes; the expected text below is written out by hand from that format).
#include <atmoglobe/bench/Report.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace atmoglobe::bench {
namespace {

Cell defaultDvr() { return Cell{}; }

Cell fastNearestStraight() {
  Cell c;
  c.stepMeters = 1000.0;
  c.imageScale = 0.5;
  c.interpolation = volume::Interpolation::Nearest;
  c.beam = engine::BeamApproximation::StraightLine;
  return c;
}

Cell defaultMip() {
  Cell c;
  c.mode = volume::VolumeRenderMode::Mip;
  return c;
}

Row row(const std::string& view, const Cell& c, double ms, double meanAbs, double maxAbs, double psnr) {
  Row r;
  r.view = view;
  r.volume = "KLBB";
  r.cell = c;
  r.widthPx = 160;
  r.heightPx = 90;
  r.medianMs = ms;
  r.error = {meanAbs, maxAbs, psnr};
  return r;
}

std::vector<Row> threeRows() {
  return {row("KLBB-oblique", defaultDvr(), 9.87654, 0.196123, 20.0, 48.1234),
          row("KLBB-oblique", fastNearestStraight(), 1.5, 2.83, 156.0, 27.2),
          row("KLBB-oblique", defaultMip(), 16.5, 0.195, 113.0, 39.0)};
}

TEST(BenchReport, CsvHasOneRowPerViewAndCell) {
  std::ostringstream csv;
  writeCsv(csv, threeRows());
  EXPECT_EQ(csv.str(),
            "view,volume,mode,step_m,image_scale,interpolation,beam,classification,width_px,height_px,median_ms,"
            "mean_abs,max_abs,psnr_db,engine_default,samples_per_cell,refine_threshold\n"
            "KLBB-oblique,KLBB,dvr,250,1,linear,4/3-earth,point,160,90,9.8765,0.19612,20,48.123,1,0,-1\n"
            "KLBB-oblique,KLBB,dvr,1000,0.5,nearest,straight,point,160,90,1.5,2.83,156,27.2,0,0,-1\n"
            "KLBB-oblique,KLBB,mip,250,1,linear,4/3-earth,-,160,90,16.5,0.195,113,39,1,0,-1\n");
}

// Two views, four cells: A (the default), B (faster, worse), C (slower and worse than A:
// dominated), MIP (not on the DVR front; an identical image, +inf dB, counts 99 dB in the mean).
TEST(BenchReport, AggregatesAreMeansOverViewsWithTheParetoFront) {
  Cell c = defaultDvr();
  c.classification = engine::Classification::Preintegrated;
  const std::vector<Cell> cells = {defaultDvr(), fastNearestStraight(), c, defaultMip()};
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Row> rows = {
      row("v1", cells[0], 10.0, 0.2, 20.0, 48.0), row("v1", cells[1], 2.0, 2.8, 150.0, 27.0),
      row("v1", cells[2], 12.0, 0.5, 30.0, 40.0), row("v1", cells[3], 16.0, 0.1, 100.0, inf),
      row("v2", cells[0], 20.0, 0.4, 25.0, 46.0), row("v2", cells[1], 4.0, 3.0, 160.0, 26.0),
      row("v2", cells[2], 20.0, 0.7, 35.0, 38.0), row("v2", cells[3], 18.0, 0.3, 110.0, 41.0)};
  const std::vector<Aggregate> agg = aggregate(rows, cells);
  ASSERT_EQ(agg.size(), 4u);
  EXPECT_DOUBLE_EQ(agg[0].meanMs, 15.0);
  EXPECT_DOUBLE_EQ(agg[0].meanAbs, 0.3);
  EXPECT_DOUBLE_EQ(agg[0].maxAbs, 25.0);
  EXPECT_DOUBLE_EQ(agg[0].meanPsnrDb, 47.0);
  EXPECT_DOUBLE_EQ(agg[0].minPsnrDb, 46.0);
  EXPECT_TRUE(agg[0].pareto);
  EXPECT_DOUBLE_EQ(agg[1].meanMs, 3.0);
  EXPECT_TRUE(agg[1].pareto);
  EXPECT_DOUBLE_EQ(agg[2].meanMs, 16.0);
  EXPECT_FALSE(agg[2].pareto);                // A is faster (15 < 16 ms) and more accurate (0.3 < 0.6)
  EXPECT_DOUBLE_EQ(agg[3].meanPsnrDb, 70.0);  // (99 + 41) / 2
  EXPECT_DOUBLE_EQ(agg[3].minPsnrDb, 41.0);
  EXPECT_FALSE(agg[3].pareto);  // MIP is not on the DVR front

  // A cell without rows is left out.
  Cell unused = defaultDvr();
  unused.stepMeters = 125.0;
  EXPECT_EQ(aggregate(rows, {unused, cells[0]}).size(), 1u);
}

BenchReport smallReport() {
  BenchReport r;
  r.machine = "CPU: Test CPU, 2 hardware threads; GL: llvmpipe";
  r.widthPx = 160, r.heightPx = 90;
  r.frames = 9;
  r.referenceStepMeters = 100.0;
  r.volumes.push_back({"KLBB", "../shared/data/radar_nexrad/KLBB20160601_150025_V06", "REF", 9, 52100000, 5.2e9});
  BenchView view;
  view.name = "KLBB-oblique";
  view.pose.latDeg = 31.85072;
  view.pose.lonDeg = -101.8142;
  view.pose.heightMeters = 100000.0;
  view.pose.headingDeg = 0.0;
  view.pose.pitchDeg = -27.05;
  view.fovYDeg = 50.0;
  r.views = {view};
  r.referencesRendered = 1, r.referencesCached = 2, r.referenceThreads = 2;
  r.referenceSeconds = 20.78;
  r.referenceCacheDir = "out/bench/reference-cache";
  r.convergence = {{"KLBB-oblique", {0.0512, 3.0, 55.123}}};
  r.rows = threeRows();
  r.aggregates = aggregate(r.rows, {defaultDvr(), fastNearestStraight(), defaultMip()});
  r.big = {{"KLBB-oblique (1 frame, software GL)", 775.4}};
  r.peer.note = "VTK peer for KLBB failed (exit 1); the runs that finished before are below; ";
  PeerGrid g;
  g.nx = 994, g.ny = 1084, g.nz = 31;
  g.spacingMeters = 620.0;
  g.nativeSpacingMeters = 250.0;
  g.coarsenedReason = "limits";
  g.maxRangeErrorMeters = 1.6, g.maxAzimuthErrorDeg = 0.0006, g.maxElevationErrorDeg = 0.004;
  g.resampleSeconds = 2.5;
  r.peer.grids["KLBB"] = g;
  PeerResult cpu;
  cpu.view = "KLBB-oblique";
  cpu.mapper = "vtkFixedPointVolumeRayCastMapper";
  cpu.medianMs = 4.7;
  cpu.peakRssMb = 494.0;
  cpu.error = {1.16, 85.0, 34.0};
  cpu.ok = true;
  PeerResult gpu;
  gpu.view = "KLBB-oblique";
  gpu.mapper = "vtkGPUVolumeRayCastMapper";
  gpu.medianMs = 23.2;
  gpu.peakRssMb = 494.0;
  gpu.note = " (no image)";
  r.peer.results = {cpu, gpu};
  r.totalSeconds = 9.1;
  return r;
}

const char* const kExpectedMarkdown = R"(# atmoglobe bench: radar volume marcher

Machine: CPU: Test CPU, 2 hardware threads; GL: llvmpipe

Image 160x90 px, 9 timed frames per cell (median, glFinish after each, frames taken round-robin over the cells after one untimed round), volume only over black (no globe). Error against the CPU reference (double, exact inverse, linear, step 100 m, full resolution, no empty-space skipping; only samples proven outside the shell skip the inverse, bit-identical): mean / max absolute difference in 8-bit steps over RGB, PSNR in dB. For image scale < 1 the frame is the small image upsampled bilinearly by the composite pass (what the user sees).

## Volumes

| volume | file | field | sweeps | GPU bytes | Cartesian grid at near-range resolution (float32) | ratio |
|---|---|---|---|---|---|---|
| KLBB | ../shared/data/radar_nexrad/KLBB20160601_150025_V06 | REF | 9 | 52.1 MB | 5.2 GB | 99.81x |

## Views

| view | lat | lon | height (m) | heading | pitch | fovY |
|---|---|---|---|---|---|---|
| KLBB-oblique | 31.85072 | -101.8142 | 100000 | 0 | -27.05 | 50 |

References: 1 rendered this run (20.78 s on 2 threads), 2 read from the cache (out/bench/reference-cache).

Reference convergence (DVR, 80x45, step 100 m against 50 m):

| view | mean abs | max abs | PSNR dB |
|---|---|---|---|
| KLBB-oblique | 0.0512 | 3 | 55.1 |

## All settings, mean over views (sorted by time)

| mode | step (m) | scale | interp. | beam | classification | frame (ms) | mean abs | max abs | PSNR mean (dB) | PSNR min (dB) | Pareto | default |
|---|---|---|---|---|---|---|---|---|---|---|---|---|
| dvr | 1000 | 0.5 | nearest | straight | point | 1.5 | 2.83 | 156 | 27.2 | 27.2 | yes |  |
| dvr | 250 | 1 | linear | 4/3-earth | point | 9.877 | 0.196 | 20 | 48.1 | 48.1 | yes | **yes** |
| mip | 250 | 1 | linear | 4/3-earth | - | 16.5 | 0.195 | 113 | 39 | 39 |  | **yes** |

## Per view

| view | setting | frame (ms) | mean abs | max abs | PSNR (dB) |
|---|---|---|---|---|---|
| KLBB-oblique | dvr step 250 m, scale 1, linear, 4/3-earth (default) | 9.877 | 0.196 | 20 | 48.1 |
| KLBB-oblique | dvr step 1000 m, scale 0.5, nearest, straight | 1.5 | 2.83 | 156 | 27.2 |
| KLBB-oblique | mip step 250 m, scale 1, linear, 4/3-earth (default) | 16.5 | 0.195 | 113 | 39 |

## Default setting at 1280x720 (time only)

| view | frame (ms) |
|---|---|
| KLBB-oblique (1 frame, software GL) | 775.4 |

## Peer: Cartesian grid rendered by VTK

VTK peer for KLBB failed (exit 1); the runs that finished before are below; 

- KLBB: grid 994 x 1084 x 31 at 620 m (finest gate spacing 250 m), box = ENU bounding box of the gates above the zero-opacity value, float32: 133.61 MB vs our GPU 52.1 MB (2.56x). Coarsened: limits. Resampled in 2.5 s with the fast inverse (local sphere + closed-form beam model), max error vs the exact inverse over 20000 random voxels: 1.6 m range, 0.0006 deg azimuth, 0.004 deg elevation.

| view | renderer | frame (ms) | mean abs | max abs | PSNR (dB) | note |
|---|---|---|---|---|---|---|
| KLBB-oblique | VTK vtkFixedPointVolumeRayCastMapper | 4.7 | 1.16 | 85 | 34 |  |
| KLBB-oblique | VTK vtkGPUVolumeRayCastMapper | 23.2 | - | - | - |  (no image) |

Ours at the default on the same views:

| view | frame (ms) | mean abs | max abs | PSNR (dB) |
|---|---|---|---|---|
| KLBB-oblique | 9.877 | 0.196 | 20 | 48.1 |

Ours against each VTK run at equal or lower error (the fastest of our DVR cells on that view, at 160x90, whose mean abs error is at most VTK's):

| view | VTK renderer | VTK (ms) | VTK mean abs | ours: setting | ours (ms) | ours mean abs | faster (VTK ms / ours ms) |
|---|---|---|---|---|---|---|---|
| KLBB-oblique | VTK vtkFixedPointVolumeRayCastMapper | 4.7 | 1.16 | dvr step 250 m, scale 1, linear, 4/3-earth | 9.877 | 0.196 | 0.476x |

VTK process peak resident memory: 494 MB.

Total bench time: 9.1 s.
)";

TEST(BenchReport, MarkdownHasEveryTableInTheDocumentedFormat) {
  std::ostringstream md;
  writeMarkdown(md, smallReport());
  EXPECT_EQ(md.str(), kExpectedMarkdown);
}

// Without the peer's runs: its note alone, no peer tables.
TEST(BenchReport, MarkdownWithoutPeerRunsHasTheNoteOnly) {
  BenchReport r = smallReport();
  r.peer = PeerSection{};
  r.peer.note = "peer skipped (--no-peer)";
  r.convergence.clear();
  std::ostringstream md;
  writeMarkdown(md, r);
  const std::string text = md.str();
  EXPECT_NE(
      text.find("## Peer: Cartesian grid rendered by VTK\n\npeer skipped (--no-peer)\n\n\nTotal bench time: 9.1 s.\n"),
      std::string::npos)
      << text;
  EXPECT_EQ(text.find("Reference convergence"), std::string::npos);
  EXPECT_EQ(text.find("VTK process peak"), std::string::npos);
}

TEST(BenchReport, WriteReportWritesTheThreeFiles) {
  const std::string dir = atmoglobe_test::freshTestDir("bench-report");
  std::vector<std::string> written;
  const Status s = writeReport(dir, smallReport(), &written);
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_EQ(written.size(), 3u);
  EXPECT_EQ(written[0], dir + "/volume_bench.md");
  EXPECT_EQ(written[1], dir + "/volume_bench.csv");
  EXPECT_EQ(written[2], dir + "/volume_bench.png");
  std::ifstream md(written[0]);
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, kExpectedMarkdown);
  EXPECT_GT(std::filesystem::file_size(written[2]), 1000u);

  const Status bad = writeReport(dir + "/no/such/dir", smallReport(), &written);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("no/such/dir"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace atmoglobe::bench
