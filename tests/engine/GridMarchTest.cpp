// Forecast grids through the one marcher: the GPU's ECEF-to-grid mapping (float32) against the
// double path (GridSampler::gridIndex) at mid latitudes, across the antimeridian, over a pole and
// from camera heights of 1 m to 1e7 m; GPU images against the CPU reference; a radar and a grid
// marched together.
#include "GLTestUtil.h"
#include "ReducedGrib.h"
#include "SyntheticGridVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GridSourceGL.h>
#include <atmoglobe/engine/GridVolumeGL.h>
#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/ReferenceRenderer.h>
#include <atmoglobe/volume/SyntheticGrid.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <thread>

namespace {

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;

// A smooth 3-D "cloud" field: a Gaussian blob of 60 units at (lat0, lon0, 5 km).
volume::GridVolume blobGrid(std::vector<double> lonAxis, std::vector<double> latAxis, double lat0, double lon0,
                            double radiusDeg) {
  auto surface = [](double lat, double lon) { return 200.0 + 300.0 * std::sin(lat * 0.3) * std::cos(lon * 0.2); };
  auto field = [=](double lat, double lon, double h) {
    double dLon = std::remainder(lon - lon0, 360.0) * std::cos(degreesToRadians(lat));
    const double d2 = ((lat - lat0) * (lat - lat0) + dLon * dLon) / (radiusDeg * radiusDeg);
    return 60.0 * std::exp(-d2 - std::pow((h - 5000.0) / 3000.0, 2));
  };
  return testutil::rectilinearGrid(std::move(lonAxis), std::move(latAxis),
                                   {0.0, 150.0, 400.0, 800.0, 1500.0, 2500.0, 4000.0, 6000.0, 8500.0, 11000.0, 14000.0},
                                   surface, field);
}

// The same field on a reduced grid: global (`rows` rows evenly spaced, about 4 x rows x cos(lat)
// points each, as a reduced Gaussian grid) or, with `regional`, rows of 0.1 degree in latitude
// from `lat0` over [lon0, lon0 + spanDeg], each of its own length (101 .. 201 points).
volume::GridVolume reducedBlobGrid(int rows, double lat0, double lon0, double radiusDeg) {
  auto surface = [](double lat, double lon) { return 200.0 + 300.0 * std::sin(lat * 0.3) * std::cos(lon * 0.2); };
  auto field = [=](double lat, double lon, double h) {
    double dLon = std::remainder(lon - lon0, 360.0) * std::cos(degreesToRadians(lat));
    const double d2 = ((lat - lat0) * (lat - lat0) + dLon * dLon) / (radiusDeg * radiusDeg);
    return 60.0 * std::exp(-d2 - std::pow((h - 5000.0) / 3000.0, 2));
  };
  return testutil::globalReducedGrid(
      rows, 0.0, {0.0, 150.0, 400.0, 800.0, 1500.0, 2500.0, 4000.0, 6000.0, 8500.0, 11000.0, 14000.0}, surface, field);
}
volume::GridVolume regionalReducedBlobGrid(double latSouth, double lonWest, double spanDeg, double lat0, double lon0,
                                           double radiusDeg) {
  auto surface = [](double lat, double lon) { return 200.0 + 300.0 * std::sin(lat * 0.3) * std::cos(lon * 0.2); };
  auto field = [=](double lat, double lon, double h) {
    double dLon = std::remainder(lon - lon0, 360.0) * std::cos(degreesToRadians(lat));
    const double d2 = ((lat - lat0) * (lat - lat0) + dLon * dLon) / (radiusDeg * radiusDeg);
    return 60.0 * std::exp(-d2 - std::pow((h - 5000.0) / 3000.0, 2));
  };
  std::vector<std::size_t> lengths;
  std::vector<double> lat, first, spacing;
  for (int j = 0; j <= 100; ++j) {
    lat.push_back(latSouth + 0.1 * j);
    lengths.push_back(static_cast<std::size_t>(101 + (j * 37) % 101));
    first.push_back(lonWest);
    spacing.push_back(spanDeg / static_cast<double>(lengths.back() - 1));
  }
  return testutil::reducedGrid(lengths, lat, first, false, spacing,
                               {0.0, 150.0, 400.0, 800.0, 1500.0, 2500.0, 4000.0, 6000.0, 8500.0, 11000.0, 14000.0},
                               surface, field);
}

struct MappingError {
  double horizontalCells = 0.0, levels = 0.0;
  int points = 0;
};

// For each pixel, the point at distance t along its ray: the GPU's (column, row, level) against
// the double path's.
MappingError mappingError(engine::VolumeRendererGL& r, const Camera& camera, const engine::GridVolumeGL& gl, double t) {
  const std::vector<glm::vec4> gpu = r.debugCoordinatesAt(camera, gl, t);
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  const auto& sampler = static_cast<const volume::GridSampler&>(gl.referenceSampler());
  MappingError e;
  for (int y = 0; y < camera.heightPx(); ++y)
    for (int x = 0; x < camera.widthPx(); ++x) {
      const glm::dvec3 p = rc.eyeEcef + t * volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      const globe::Geodetic g = globe::ecefToGeodetic(p);
      const auto exact = sampler.gridIndex(g.latDeg, g.lonDeg, g.heightMeters);
      const glm::vec4 got = gpu[static_cast<std::size_t>(y * camera.widthPx() + x)];
      // Only points both paths place inside, away from the grid's edges by a cell and from its
      // lowest and highest level by a level (where float rounding may put a point either side).
      if (!exact || got.x < 0.0f) continue;
      if (exact->z < 1.0 || exact->z > static_cast<double>(gl.grid().nz) - 2.0) continue;
      ++e.points;
      double di = std::abs(double(got.x) - exact->x);
      if (gl.grid().wrapsLongitude) di = std::min(di, std::abs(di - static_cast<double>(gl.grid().nx)));
      e.horizontalCells = std::max(e.horizontalCells, std::max(di, std::abs(double(got.y) - exact->y)));
      e.levels = std::max(e.levels, std::abs(double(got.z) - exact->z));
    }
  return e;
}

}  // namespace

// The mapping's float error against the double path. float32 ECEF near the Earth's radius
// rounds to ~0.5 m, Bowring's height cancels terms of 6.4e6 m (another ~1 m), the angles come
// from atan as differences from the grid's centre (~1 m; from the whole angle they were off by
// 10-30 m on llvmpipe), the lookup tables' float entries hold the index to 1e-5..1e-4. With cells
// of >= 0.1 deg (11 km): a few 1e-4 cells; levels here are >= 150 m apart (1.5 m / 150 m = 0.01
// level). Bounds: 1e-3 cells and 0.02 levels. Measured (printed): 0.4-1.8e-4 cells, 0.0004-0.0037
// levels, the largest 1 m above the model surface where the levels are 150 m apart.
TEST(GridMarch, GpuMappingMatchesTheDoublePathEverywhere) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  struct Case {
    const char* name;
    volume::GridVolume grid;
    CameraPose pose;
    double t;              // distance along the rays (m)
    double fovDeg = 40.0;  // narrow from far away, so that the points at t stay inside the levels
  };
  volume::GridVolume global =
      blobGrid(testutil::evenlySpaced(0.0, 2.5, 144), testutil::evenlySpaced(-88.75, 2.5, 72), 60.0, 180.0, 10.0);
  global.wrapsLongitude = true;
  std::vector<Case> cases;
  cases.push_back(
      {"regional, 1e5 m above",
       blobGrid(testutil::evenlySpaced(-100.0, 0.1, 101), testutil::evenlySpaced(30.0, 0.1, 101), 35.0, -95.0, 1.5),
       {35.0, -95.0, 1e5, 0.0, -90.0, 0.0},
       1e5 - 5000.0});
  // 1 m above the grid's lowest level (the model surface) there, looking north and a little up.
  const double ground = 200.0 + 300.0 * std::sin(35.0 * 0.3) * std::cos(-95.0 * 0.2);
  cases.push_back(
      {"regional, 1 m above the model surface",
       blobGrid(testutil::evenlySpaced(-100.0, 0.1, 101), testutil::evenlySpaced(30.0, 0.1, 101), 35.0, -95.0, 1.5),
       {35.0, -95.0, ground + 1.0, 0.0, 5.0, 0.0},
       20000.0});
  cases.push_back(
      {"across the antimeridian",
       blobGrid(testutil::evenlySpaced(170.0, 0.1, 201), testutil::evenlySpaced(-20.0, 0.1, 101), -15.0, 180.0, 2.0),
       {-15.0, 180.0, 3e5, 0.0, -90.0, 0.0},
       3e5 - 5000.0});
  cases.push_back(
      {"global, over the north pole from 1e7 m", global, {90.0, 0.0, 1e7, 0.0, -90.0, 0.0}, 1e7 - 5000.0, 0.5});
  cases.push_back(
      {"global, the antimeridian from 2e6 m", global, {60.0, 180.0, 2e6, 0.0, -90.0, 0.0}, 2e6 - 5000.0, 2.0});
  for (const Case& c : cases) {
    auto gl = engine::GridVolumeGL::create(c.grid);
    ASSERT_TRUE(gl) << gl.error();
    const Camera camera(c.pose, c.fovDeg, 48, 32);
    const MappingError e = mappingError(**renderer, camera, **gl, c.t);
    std::cout << "grid mapping, " << c.name << ": " << e.points << " points, max " << e.horizontalCells << " cells, "
              << e.levels << " levels\n";
    EXPECT_GT(e.points, 200) << c.name;
    EXPECT_LT(e.horizontalCells, 1e-3) << c.name;
    EXPECT_LT(e.levels, 0.02) << c.name;
  }
}

namespace {
// The blob seen obliquely on a regional grid, and on a global grid over the pole and across the
// antimeridian, at the given steps.
struct BlobCase {
  const char* name;
  volume::GridVolume grid;
  CameraPose pose;
  double stepMeters;
};
std::vector<BlobCase> blobCases(double regionalStepMeters, double globalStepMeters) {
  volume::GridVolume global =
      blobGrid(testutil::evenlySpaced(0.0, 2.5, 144), testutil::evenlySpaced(-88.75, 2.5, 72), 80.0, 180.0, 15.0);
  global.wrapsLongitude = true;
  return {{"regional oblique",
           blobGrid(testutil::evenlySpaced(-100.0, 0.1, 101), testutil::evenlySpaced(30.0, 0.1, 101), 35.0, -95.0, 1.5),
           {33.0, -95.0, 6e4, 0.0, -30.0, 0.0},
           regionalStepMeters},
          {"global, pole and antimeridian", global, {70.0, 180.0, 3e6, 0.0, -70.0, 0.0}, globalStepMeters}};
}
// Their drawing: the reflectivity table (iso at 30) in `mode` at this step.
engine::VolumeRenderOptions blobOptions(volume::VolumeRenderMode mode, double stepMeters,
                                        double opacityReferenceMeters) {
  engine::VolumeRenderOptions o;
  o.render.mode = mode;
  o.render.stepMeters = stepMeters;
  o.render.isoValue = 30.0;
  o.render.transfer = volume::defaultReflectivityTransfer();
  o.render.transfer.opacityReferenceMeters = opacityReferenceMeters;
  return o;
}
}  // namespace

// GPU images against the CPU reference (exact double sampling) in every mode, for a regional and
// a global grid (over the pole and across the antimeridian: no seams or holes to differ).
TEST(GridMarch, GpuMatchesTheReferenceInEveryMode) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  for (const BlobCase& c : blobCases(500.0, 5000.0)) {
    auto gl = engine::GridVolumeGL::create(c.grid);
    ASSERT_TRUE(gl) << gl.error();
    const Camera camera(c.pose, 45.0, 64, 36);
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
      const engine::VolumeRenderOptions o = blobOptions(mode, c.stepMeters, c.stepMeters * 10.0);
      const volume::VolumeImage gpu = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), o}});
      const volume::VolumeImage ref = volume::renderReference({{&(*gl)->referenceSampler(), o.render}},
                                                              engine::referenceCameraFor(camera), true, 2);
      const volume::ImageError e = volume::compareImages(gpu, ref);
      int drawn = 0;
      for (const glm::dvec4& p : ref.rgbaPremultiplied) drawn += p.a > 0.05;
      std::cout << "grid " << c.name << ", mode " << static_cast<int>(mode) << ": " << drawn
                << " pixels drawn, GPU vs reference mean " << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb
                << " dB\n";
      EXPECT_GT(drawn, 50) << c.name << " must show the blob";
      // As for radars (RadarMarch.GpuMatchesTheReferenceInEveryMode): mean below one 8-bit step, 30 dB.
      EXPECT_LT(e.meanAbs, 1.0) << c.name;
      EXPECT_GT(e.psnrDb, 30.0) << c.name;
    }
  }
}

// The step rule (volume/StepRule.h) at 2 samples per cell: the GPU against the CPU reference
// taking the same samples (the positions are the rule's on both), in every mode, with the
// bounds of the fixed step (mean below one 8-bit step, 30 dB); and the picture with empty-space
// skipping off equals the one with it on within the same bound (a jump's target is aligned by
// the rule, so skipping lands where the walk does except where the level changes at the jump).
// The rule must change the picture against the fixed step (it is on) while staying close to it.
TEST(GridMarch, StepRuleGpuMatchesTheReferenceInEveryMode) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  for (const BlobCase& c : blobCases(50.0, 250.0)) {
    auto gl = engine::GridVolumeGL::create(c.grid);
    ASSERT_TRUE(gl) << gl.error();
    const Camera camera(c.pose, 45.0, 64, 36);
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
      engine::VolumeRenderOptions o = blobOptions(mode, c.stepMeters, 5000.0);
      engine::VolumeRenderOptions fixed = o;
      o.render.samplesPerCell = 2.0;
      const volume::VolumeImage gpu = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), o}});
      engine::VolumeRenderOptions noSkip = o;
      noSkip.skipEmptySpace = false;
      const volume::VolumeImage gpuNoSkip = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), noSkip}});
      const volume::VolumeImage ref = volume::renderReference({{&(*gl)->referenceSampler(), o.render}},
                                                              engine::referenceCameraFor(camera), true, 2);
      const volume::VolumeImage refFixed = volume::renderReference({{&(*gl)->referenceSampler(), fixed.render}},
                                                                   engine::referenceCameraFor(camera), true, 2);
      const volume::ImageError e = volume::compareImages(gpu, ref);
      const volume::ImageError skip = volume::compareImages(gpu, gpuNoSkip);
      const volume::ImageError rule = volume::compareImages(ref, refFixed);
      int drawn = 0;
      for (const glm::dvec4& p : ref.rgbaPremultiplied) drawn += p.a > 0.05;
      std::cout << "step rule, grid " << c.name << ", mode " << static_cast<int>(mode) << ": " << drawn
                << " pixels drawn, GPU vs reference mean " << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb
                << " dB; skipping on vs off mean " << skip.meanAbs << " max " << skip.maxAbs
                << "; rule vs fixed step (reference) mean " << rule.meanAbs << " max " << rule.maxAbs << " PSNR "
                << rule.psnrDb << " dB\n";
      EXPECT_GT(drawn, 50) << c.name << " must show the blob";
      EXPECT_LT(e.meanAbs, 1.0) << c.name;
      EXPECT_GT(e.psnrDb, 30.0) << c.name;
      EXPECT_LT(skip.meanAbs, 1.0) << c.name;
      if (mode == volume::VolumeRenderMode::Dvr) {
        EXPECT_GT(rule.maxAbs, 0.0) << c.name << ": the rule must take other samples";
      }
    }
  }
}

// A scene with a radar and a forecast grid (both synthetic, the grid's storm where the radar
// sees it): the scene file's "grids" entry is read (unknown keys and wrong types named), the grid
// is loaded through the scene renderer (only its time step), and where the two volumes overlap
// the frame is their joint integral: the GPU frame against the frame with the CPU reference in
// the volumes' place.
TEST(GridMarch, RadarAndGridInOneScene) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  volume::SyntheticGridOptions go;
  go.nx = go.ny = 80;
  go.levels = 20;
  go.times = 3;
  go.spacingKm = 5.0;
  go.startTimeIso8601 = "2020-05-01T20:00:00Z";
  ASSERT_TRUE(volume::writeSyntheticGrid(dir + "/scene_grid.nc", go));
  volume::SyntheticRadarOptions ro;
  ro.elevationsDeg = {0.5, 1.5, 2.5, 3.5, 5.0, 7.0, 10.0};
  ro.maxRangeMeters = 120e3;
  ASSERT_TRUE(volume::writeSyntheticCfRadial(dir + "/scene_radar.nc", ro));

  // Errors name the JSON path and the problem.
  auto typo = engine::parseSceneJson(R"({"grids": [{"path": "g.nc", "varaible": "dbz"}]})", "s.json", dir, dir);
  ASSERT_FALSE(typo);
  EXPECT_NE(typo.error().find("s.json: /grids/0/varaible: unknown key"), std::string::npos) << typo.error();
  EXPECT_NE(typo.error().find("varaible"), std::string::npos) << typo.error();
  auto wrongType = engine::parseSceneJson(R"({"grids": [{"path": "g.nc", "time": 3}]})", "s.json", dir, dir);
  ASSERT_FALSE(wrongType);
  EXPECT_NE(wrongType.error().find("/grids/0/time: expected a string, got integer"), std::string::npos)
      << wrongType.error();

  auto scene = engine::parseSceneJson(R"({"camera": {"lat_deg": 34.6, "lon_deg": -97.8, "height_m": 60000,
      "heading_deg": 20, "pitch_deg": -40, "roll_deg": 0}, "fov_deg": 50, "size": [96, 54],
      "radars": [{"path": "@data/scene_radar.nc", "step_m": 500}],
      "grids": [{"path": "@data/scene_grid.nc", "variable": "dbz", "time": "2020-05-01T21:00:00Z", "step_m": 500}]})",
                                      "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(engine::volumesOfKind(*scene, engine::VolumeKind::Grid).size(), 1u);
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer) << renderer.error();
  ASSERT_TRUE((*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0]));
  auto grid = (*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0]);
  ASSERT_TRUE(grid) << grid.error();
  EXPECT_EQ(testutil::gridVolumeOf(*grid).validTime, "2020-05-01T21:00:00Z");
  const Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto gpu = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(gpu) << gpu.error();
  (*renderer)->setReferenceVolumes(2);
  auto ref = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(ref) << ref.error();
  // Pixels where both volumes have data along the ray: the reference samplers' intervals.
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  const auto& radarSampler = (*renderer)->layer(0).volume().referenceSampler();
  const auto& gridSampler = (*grid)->volume().referenceSampler();
  const volume::VolumeImage& refVolume = (*renderer)->volumeRenderer().lastReferenceImage();
  int overlapDrawn = 0;
  double sum = 0.0;
  for (int y = 0; y < camera.heightPx(); ++y)
    for (int x = 0; x < camera.widthPx(); ++x) {
      const glm::dvec3 ray = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      if (!radarSampler.rayInterval(rc.eyeEcef, ray).empty() && !gridSampler.rayInterval(rc.eyeEcef, ray).empty() &&
          refVolume.at(x, y).a > 0.05)
        ++overlapDrawn;
      const glm::ivec4 d = glm::abs(glm::ivec4(gpu->at(x, y)) - glm::ivec4(ref->at(x, y)));
      sum += d.r + d.g + d.b;
    }
  const double mean = sum / (3.0 * camera.widthPx() * camera.heightPx());
  std::cout << "radar + grid scene: " << overlapDrawn << " pixels where both can be and the storm shows; "
            << "mean |GPU - reference frame| " << mean << " (8-bit)\n";
  EXPECT_GT(overlapDrawn, 100) << "the view must show the storm where radar and grid overlap";
  // As for two radars (VolumeKinds.OverlappingRadarsAreIntegratedTogether): below one 8-bit step.
  EXPECT_LT(mean, 1.0);

  // A crop box: only its columns are read and drawn (one more on each side).
  auto cropped = engine::parseSceneJson(
      R"({"grids": [{"path": "@data/scene_grid.nc", "time": "1", "crop": [34.8, 35.2, -97.6, -97.0]}]})", "s.json", dir,
      dir);
  ASSERT_TRUE(cropped) << cropped.error();
  // The full grid's figures before another layer is added (before another layer is added).
  const std::size_t fullColumns = testutil::gridVolumeOf(*grid).nx * testutil::gridVolumeOf(*grid).ny;
  const std::uint64_t fullBytes = testutil::gridVolumeOf(*grid).bytesRead;
  auto small = (*renderer)->addVolume(engine::volumesOfKind(*cropped, engine::VolumeKind::Grid)[0]);
  ASSERT_TRUE(small) << small.error();
  const volume::GridVolume& sg = testutil::gridVolumeOf(*small);
  std::cout << "crop: " << sg.nx << " x " << sg.ny << " of " << fullColumns << " columns, " << sg.bytesRead << " of "
            << fullBytes << " bytes read\n";
  EXPECT_LT(sg.nx * sg.ny * 10, fullColumns);
  EXPECT_LT(sg.bytesRead * 5, fullBytes);
  EXPECT_LE(sg.latDeg.front(), 34.8);
  EXPECT_GE(sg.latDeg.back(), 35.2);
  auto badCrop = engine::parseSceneJson(R"({"grids": [{"path": "g.nc", "crop": [35, 34, 0, 1]}]})", "s.json", dir, dir);
  ASSERT_FALSE(badCrop);
  EXPECT_NE(badCrop.error().find("/grids/0: crop latitudes"), std::string::npos) << badCrop.error();
}

// A time series: stepping a grid layer shows exactly what loading that step afresh shows, and a
// frame between steps is the grids interpolated in time (neither end, the time between).
TEST(GridMarch, TimeStepsMatchAFreshLoad) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  volume::SyntheticGridOptions go;
  go.nx = go.ny = 60;
  go.levels = 16;
  go.times = 3;
  go.spacingKm = 5.0;
  go.startTimeIso8601 = "2020-05-01T20:00:00Z";
  ASSERT_TRUE(volume::writeSyntheticGrid(dir + "/series.nc", go));
  auto scene = engine::parseSceneJson(R"({"camera": {"lat_deg": 34.3, "lon_deg": -97.9, "height_m": 120000,
      "heading_deg": 30, "pitch_deg": -45, "roll_deg": 0}, "fov_deg": 50, "size": [96, 54],
      "grids": [{"path": "@data/series.nc", "step_m": 500}]})",
                                      "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto series = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(series);
  ASSERT_TRUE((*series)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0]));
  auto axis = engine::sceneTimeAxis(**series);
  ASSERT_TRUE(axis) << axis.error();
  ASSERT_EQ(axis->times.size(), 3u);
  EXPECT_EQ(axis->times[2], "2020-05-01T22:00:00Z");
  const Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto first = (*series)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(first);

  auto when = engine::showSceneTime(**series, *axis, 2);
  ASSERT_TRUE(when) << when.error();
  EXPECT_EQ(*when, "2020-05-01T22:00:00Z");
  auto stepped = (*series)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(stepped);
  // The same step loaded afresh, with the colours of step 0 (a series keeps the first step's).
  auto fresh = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(fresh);
  engine::VolumeLayerDescription d = engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0];
  d.time.assign(1, '2');  // not = "2": GCC 12 gives a false -Wrestrict there
  auto layer = (*fresh)->addVolume(d);
  ASSERT_TRUE(layer);
  (*fresh)->layer(0).options() = (*series)->layer(0).options();
  auto direct = (*fresh)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(direct);
  EXPECT_EQ(stepped->pixels, direct->pixels) << "a stepped layer must draw as the step loaded directly";
  EXPECT_NE(stepped->pixels, first->pixels) << "the storm moves between steps";

  auto half = engine::showSceneTime(**series, *axis, 1, 0.5);
  ASSERT_TRUE(half) << half.error();
  EXPECT_EQ(*half, "2020-05-01T21:30:00Z");
  EXPECT_EQ(testutil::gridVolumeOf(&(*series)->layer(0)).validTime, "2020-05-01T21:30:00Z");
  auto between = (*series)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(between);
  EXPECT_NE(between->pixels, stepped->pixels);
  EXPECT_FALSE(engine::showSceneTime(**series, *axis, 3));
}

// Range, opacity ramp and crop box are one set of settings for radars and grids: parsed from the
// scene, applied to the data before the GPU and the reference see it (so they still agree).
TEST(GridMarch, CropRangeAndOpacityApplyToRadarsAndGrids) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  volume::SyntheticRadarOptions ro;
  ro.elevationsDeg = {0.5, 1.5, 2.5, 3.5, 5.0, 7.0, 10.0};
  ro.maxRangeMeters = 120e3;
  ASSERT_TRUE(volume::writeSyntheticCfRadial(dir + "/crop_radar.nc", ro));
  const char* json = R"({"camera": {"lat_deg": 34.6, "lon_deg": -97.8, "height_m": 60000,
      "heading_deg": 20, "pitch_deg": -40, "roll_deg": 0}, "fov_deg": 50, "size": [96, 54],
      "radars": [{"path": "@data/crop_radar.nc", "step_m": 500, "crop_heights_m": [0, 5000],
                  "crop": [34.5, 36, -98.5, -97], "range": [0, 80], "opacity": [20, 50, 0.6]}]})";
  auto scene = engine::parseSceneJson(json, "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  const engine::VolumeLayerSettings settings = engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0].settings;
  EXPECT_EQ(settings.crop.topMeters, 5000.0);
  EXPECT_EQ(settings.crop.westDeg, -98.5);
  ASSERT_TRUE(settings.valueRange);
  EXPECT_EQ(settings.opacity.size(), 3u);

  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer);
  auto radar = (*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0]);
  ASSERT_TRUE(radar) << radar.error();
  EXPECT_EQ((*radar)->options().render.transfer.opacityZeroValue, 20.0);
  EXPECT_EQ((*radar)->options().render.transfer.maxOpacity, 0.6);
  // Which gates are cut is checked gate by gate in Crop.RadarGatesOutsideBecomeNoDataByTheExactGeolocation;
  // here: some are left, and the GPU and the reference draw the same cut data.
  const volume::PolarVolume& polar = testutil::polarOf(*radar);
  std::size_t kept = 0;
  for (float v : polar.values) kept += std::isnan(v) ? 0u : 1u;
  EXPECT_GT(kept, 1000u);
  const Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto gpu = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(gpu);
  (*renderer)->setReferenceVolumes(2);
  auto ref = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(ref);
  double sum = 0.0;
  for (std::size_t n = 0; n < gpu->pixels.size(); ++n) sum += std::abs(int(gpu->pixels[n]) - int(ref->pixels[n]));
  const double mean = sum / static_cast<double>(gpu->pixels.size());
  std::cout << "cropped radar: " << kept << " gates kept; mean |GPU - reference| " << mean << " (8-bit)\n";
  EXPECT_LT(mean, 1.0);  // as the uncropped scenes: below one 8-bit step

  // Bad settings name the JSON path and the problem.
  auto bad = engine::parseSceneJson(R"({"radars": [{"path": "r.nc", "opacity": [50, 20]}]})", "s.json", dir, dir);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("/radars/0: opacity zero value must be below the full value"), std::string::npos)
      << bad.error();
  auto badHeights =
      engine::parseSceneJson(R"({"grids": [{"path": "g.nc", "crop_heights_m": [5000, 100]}]})", "s.json", dir, dir);
  ASSERT_FALSE(badHeights);
  EXPECT_NE(badHeights.error().find("/grids/0: crop heights"), std::string::npos) << badHeights.error();
  auto allCut = engine::parseSceneJson(
      R"({"radars": [{"path": "@data/crop_radar.nc", "crop_heights_m": [30000, 40000]}]})", "s.json", dir, dir);
  ASSERT_TRUE(allCut);
  auto none = (*renderer)->addVolume(engine::volumesOfKind(*allCut, engine::VolumeKind::Radar)[0]);
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().find("the crop box leaves no measured value"), std::string::npos) << none.error();
}

// A vertical exaggeration drawn by the GPU matches the reference (which applies it exactly in
// double) for a radar and a grid together, and both move up together.
TEST(GridMarch, VerticalExaggerationKeepsRadarAndGridAligned) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  volume::SyntheticGridOptions go;
  go.nx = go.ny = 60;
  go.levels = 16;
  go.times = 1;
  go.spacingKm = 5.0;
  go.startTimeIso8601 = "2020-05-01T21:00:00Z";
  ASSERT_TRUE(volume::writeSyntheticGrid(dir + "/ex_grid.nc", go));
  volume::SyntheticRadarOptions ro;
  ro.elevationsDeg = {0.5, 1.5, 2.5, 3.5, 5.0, 7.0, 10.0};
  ro.maxRangeMeters = 120e3;
  ASSERT_TRUE(volume::writeSyntheticCfRadial(dir + "/ex_radar.nc", ro));
  auto scene = engine::parseSceneJson(R"({"camera": {"lat_deg": 34.3, "lon_deg": -98.0, "height_m": 40000,
      "heading_deg": 40, "pitch_deg": -20, "roll_deg": 0}, "fov_deg": 50, "size": [96, 54], "vertical_exaggeration": 3,
      "radars": [{"path": "@data/ex_radar.nc", "step_m": 500}],
      "grids": [{"path": "@data/ex_grid.nc", "step_m": 500}]})",
                                      "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_EQ(scene->verticalExaggeration, 3.0);
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE((*renderer)->setVerticalExaggeration(scene->verticalExaggeration));
  ASSERT_TRUE((*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0]));
  auto grid = (*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0]);
  ASSERT_TRUE(grid);
  EXPECT_FALSE((*renderer)->setVerticalExaggeration(2.0)) << "only before layers are added";
  const Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto gpu = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(gpu);
  (*renderer)->setReferenceVolumes(2);
  auto ref = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(ref);
  double sum = 0.0;
  int drawn = 0;
  for (std::size_t n = 0; n < gpu->pixels.size(); n += 4) {
    for (int c = 0; c < 3; ++c) sum += std::abs(int(gpu->pixels[n + c]) - int(ref->pixels[n + c]));
    drawn += ref->pixels[n] + ref->pixels[n + 1] + ref->pixels[n + 2] > 0 ? 1 : 0;
  }
  const double mean = sum / (3.0 * camera.widthPx() * camera.heightPx());
  std::cout << "exaggeration 3: " << drawn << " pixels drawn; mean |GPU - reference| " << mean << " (8-bit)\n";
  EXPECT_GT(drawn, 120);  // the disc is about 16 px across
  EXPECT_LT(mean, 1.0);   // as the true-scale scenes: below one 8-bit step
  // The grid as drawn: every height three times the file's (the reader's heights, re-read).
  volume::GridReadOptions read;
  auto plain = volume::readGridVolume(dir + "/ex_grid.nc", read);
  ASSERT_TRUE(plain);
  EXPECT_FLOAT_EQ(testutil::gridVolumeOf(*grid).heightAboveEllipsoidMeters[123],
                  3.0f * plain->heightAboveEllipsoidMeters[123]);
  auto bad = engine::parseSceneJson(R"({"vertical_exaggeration": 0})", "s.json", dir, dir);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("s.json: /vertical_exaggeration: 0 is out of range 0.1..100"), std::string::npos)
      << bad.error();
}

// The value under the cursor: the first echo along the pixel's ray from the volumes' CPU twins,
// and where the ray meets the ground.
TEST(GridMarch, ReadoutUnderTheCursor) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  volume::SyntheticRadarOptions ro;
  ro.elevationsDeg = {0.5, 1.5, 2.5, 3.5, 5.0, 7.0, 10.0};
  ro.maxRangeMeters = 120e3;
  ASSERT_TRUE(volume::writeSyntheticCfRadial(dir + "/readout_radar.nc", ro));
  auto scene = engine::parseSceneJson(R"({"radars": [{"path": "@data/readout_radar.nc"}]})", "s.json", dir, dir);
  ASSERT_TRUE(scene);
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer);
  auto radar = (*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0]);
  ASSERT_TRUE(radar) << radar.error();
  // Straight down over the synthetic storm's core (50 km west, 36 km south of the site).
  const volume::PolarVolume& p = testutil::polarOf(*radar);
  const globe::GeodesicPoint above = globe::geodesicDirect(p.site.latDeg, p.site.lonDeg, 234.25, 61.6e3);
  const engine::CameraPose pose{above.latDeg, above.lonDeg, 200e3, 0.0, -90.0, 0.0};
  const Camera camera(pose, 30.0, 64, 48);
  const engine::CursorReadout r = engine::readoutAt(**renderer, camera, 32.0, 24.0, 50.0);
  ASSERT_TRUE(r.groundLatLonHeight);
  // Straight down, the centre ray meets the ground below the eye (float-free double path).
  EXPECT_NEAR(r.groundLatLonHeight->x, above.latDeg, 1e-7);
  EXPECT_NEAR(r.groundLatLonHeight->y, above.lonDeg, 1e-7);
  ASSERT_GE(r.lines.size(), 2u);
  std::cout << r.lines[0] << "\n" << r.lines.back() << "\n";
  // The radar line: its value is the reference sampler's at the first echo (searched at 50 m).
  const std::string& line = r.lines[0];
  EXPECT_EQ(line.rfind(testutil::radarOf(*radar).siteName() + " " + p.fieldName + ": ", 0), 0u) << line;
  EXPECT_NE(line.find("azimuth 234."), std::string::npos) << "the gate read lies south-west, below the eye: " << line;
  // The gate read is stored in the volume: its value is one of that sweep's stored values at the
  // printed azimuth (a ray centre) and range (a gate centre), to the print rounding.
  double value = 0, sweepDeg = 0, azimuthDeg = 0, rangeKm = 0;
  const std::size_t colon = line.find(": ");
  ASSERT_EQ(std::sscanf(line.c_str() + colon + 2, "%lf %*s (sweep %lf deg, azimuth %lf deg, range %lf km", &value,
                        &sweepDeg, &azimuthDeg, &rangeKm),
            4)
      << line;
  bool found = false;
  for (int k = 0; k < static_cast<int>(p.sweeps.size()); ++k) {
    const volume::PolarSweepLayout& s = p.sweeps[static_cast<std::size_t>(k)];
    if (std::abs(s.elevationDeg - sweepDeg) > 0.005) continue;  // printed with 2 decimals
    for (int ray = 0; ray < s.rayCount; ++ray) {
      if (std::abs(static_cast<double>(s.azimuthDeg[static_cast<std::size_t>(ray)]) - azimuthDeg) > 0.05) continue;
      const double g = (rangeKm * 1000.0 - s.firstGateRangeMeters) / s.gateSpacingMeters;
      const int gate = static_cast<int>(std::lround(g));
      ASSERT_NEAR(g, gate, 0.5 / s.gateSpacingMeters) << "the range printed to 1 m is a gate centre: " << line;
      const float stored = p.value(k, ray, gate);
      found = found || (volume::isMeasuredValue(stored) && std::abs(static_cast<double>(stored) - value) <= 0.05);
    }
  }
  EXPECT_TRUE(found) << "no stored gate has the readout's value at its sweep, azimuth and range: " << line;
  // Pitched up at the horizon's sky: nothing under the cursor but sky.
  const Camera up(engine::CameraPose{above.latDeg, above.lonDeg, 2000.0, 0.0, 60.0, 0.0}, 30.0, 64, 48);
  const engine::CursorReadout sky = engine::readoutAt(**renderer, up, 32.0, 24.0);
  EXPECT_FALSE(sky.groundLatLonHeight);
  EXPECT_EQ(sky.lines.back(), "sky");
}

// A radar loop: a directory holding several times of one site becomes the scene's time axis;
// stepping shows each volume (the latest first), colours kept.
TEST(GridMarch, RadarLoopFromADirectory) {
  testutil::glContext();
  std::string dir = testutil::testOutputDir();
  dir.append("/loop");
  std::filesystem::create_directories(dir);
  const char* times[] = {"2020-05-01T21:00:00Z", "2020-05-01T21:05:00Z", "2020-05-01T21:10:00Z"};
  for (int k = 0; k < 3; ++k) {
    volume::SyntheticRadarOptions ro;
    ro.elevationsDeg = {0.5, 1.5, 3.0, 6.0};
    ro.maxRangeMeters = 100e3;
    ro.startTimeIso8601 = times[k];
    ro.stormEastKm = -50.0 + 5.0 * k;  // the storm moves east
    std::string file = dir;
    file.append("/v").append(std::to_string(k)).append(".nc");
    ASSERT_TRUE(volume::writeSyntheticCfRadial(file, ro));
  }
  auto scene = engine::parseSceneJson(R"({"camera": {"lat_deg": 34.9, "lon_deg": -97.6, "height_m": 250000,
      "heading_deg": 0, "pitch_deg": -90, "roll_deg": 0}, "fov_deg": 40, "size": [64, 48],
      "radars": [{"path": "loop", "step_m": 1000}]})",
                                      "s.json", testutil::testOutputDir(), testutil::testOutputDir());
  ASSERT_TRUE(scene) << scene.error();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer);
  auto radar = (*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Radar)[0]);
  ASSERT_TRUE(radar) << radar.error();
  ASSERT_EQ((*radar)->times()->size(), 3u);
  EXPECT_EQ((*radar)->step(), 2u);
  EXPECT_EQ(testutil::radarOf(*radar).timeIso8601(), times[2]) << "a loop starts at its latest volume";
  auto axis = engine::sceneTimeAxis(**renderer);
  ASSERT_TRUE(axis) << axis.error();
  EXPECT_EQ((*renderer)->layer(axis->leadLayer).kind(), engine::VolumeKind::Radar);
  ASSERT_EQ(axis->times.size(), 3u);
  const Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto last = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(last);
  const auto colors = (*renderer)->layer(0).options().render.transfer.colors.stops();
  auto when = engine::showSceneTime(**renderer, *axis, 0);
  ASSERT_TRUE(when) << when.error();
  EXPECT_EQ(*when, times[0]);
  EXPECT_EQ(testutil::radarOf(&(*renderer)->layer(0)).timeIso8601(), times[0]);
  EXPECT_EQ((*renderer)->layer(0).options().render.transfer.colors.stops(), colors);
  auto first = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(first);
  EXPECT_NE(first->pixels, last->pixels) << "the storm moved 10 km between the first and the last volume";
}

// fuzz_scene found it: a number beyond double killed the process (std::terminate from an
// uncaught json::out_of_range); it is a "not valid JSON" error naming the scene.
TEST(SceneJson, NumbersBeyondDoubleAreAnError) {
  auto scene = engine::parseSceneJson(R"({"fov_deg": -2e1111111111})", "big.json", ".", ".");
  ASSERT_FALSE(scene);
  EXPECT_NE(scene.error().find("big.json: not valid JSON"), std::string::npos) << scene.error();
}

// A reduced grid's GPU mapping (shader variant VOL_REDUCED: the row by the latitude table, each
// row's column from the row table) against the double path: GridSampler::gridIndex, whose column
// index is the longitude on the reference axis (the finest row spacing, 360 / the longest row for
// a global grid), the GPU's reconstructed from the row of larger weight's own column, so both the
// row table and the float longitude are measured. Same bounds as the rectilinear and curvilinear
// grids (GpuMappingMatchesTheDoublePathEverywhere).
TEST(GridMarch, ReducedGridGpuMappingMatchesTheDoublePath) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  struct Case {
    const char* name;
    volume::GridVolume grid;
    CameraPose pose;
    double t;
    double fovDeg = 40.0;
  };
  const volume::GridVolume global = reducedBlobGrid(72, 60.0, 180.0, 10.0);  // 8 .. 288 points per row
  std::vector<Case> cases;
  cases.push_back(
      {"reduced global, mid latitudes from 1e6 m", global, {45.0, 10.0, 1e6, 0.0, -90.0, 0.0}, 1e6 - 5000.0, 20.0});
  cases.push_back(
      {"reduced global, its seam (0 deg) from 2e6 m", global, {30.0, 0.0, 2e6, 0.0, -90.0, 0.0}, 2e6 - 5000.0, 2.0});
  cases.push_back(
      {"reduced global, over the north pole from 1e7 m", global, {90.0, 0.0, 1e7, 0.0, -90.0, 0.0}, 1e7 - 5000.0, 0.5});
  cases.push_back({"reduced regional across the antimeridian, 3e5 m",
                   regionalReducedBlobGrid(-20.0, 170.0, 20.0, -15.0, 180.0, 2.0),
                   {-15.0, 180.0, 3e5, 0.0, -90.0, 0.0},
                   3e5 - 5000.0});
  const double ground = 200.0 + 300.0 * std::sin(-15.0 * 0.3) * std::cos(180.0 * 0.2);
  cases.push_back({"reduced regional, 1 m above the model surface",
                   regionalReducedBlobGrid(-20.0, 170.0, 20.0, -15.0, 180.0, 2.0),
                   {-15.0, 180.0, ground + 1.0, 0.0, 5.0, 0.0},
                   20000.0});
  for (const Case& c : cases) {
    auto gl = engine::GridVolumeGL::create(c.grid);
    ASSERT_TRUE(gl) << gl.error();
    ASSERT_TRUE((*gl)->grid().reduced());
    const Camera camera(c.pose, c.fovDeg, 48, 32);
    const MappingError e = mappingError(**renderer, camera, **gl, c.t);
    std::cout << "grid mapping, " << c.name << ": " << e.points << " points, max " << e.horizontalCells << " cells, "
              << e.levels << " levels\n";
    EXPECT_GT(e.points, 200) << c.name;
    EXPECT_LT(e.horizontalCells, 1e-3) << c.name;
    EXPECT_LT(e.levels, 0.02) << c.name;
  }
}

// GPU images of reduced grids against the CPU reference in every mode: global (over the pole and
// across its seam and the antimeridian: no holes or seams to differ) and regional.
TEST(GridMarch, ReducedGridGpuMatchesTheReferenceInEveryMode) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  struct Case {
    const char* name;
    volume::GridVolume grid;
    CameraPose pose;
    double stepMeters;
  };
  const std::vector<Case> cases = {
      {"reduced global, pole and antimeridian",
       reducedBlobGrid(72, 80.0, 180.0, 15.0),
       {70.0, 180.0, 3e6, 0.0, -70.0, 0.0},
       5000.0},
      {"reduced global, its seam", reducedBlobGrid(72, 40.0, 0.0, 12.0), {30.0, 0.0, 3e6, 0.0, -60.0, 0.0}, 5000.0},
      {"reduced regional oblique",
       regionalReducedBlobGrid(-20.0, 170.0, 20.0, -15.0, 180.0, 1.5),
       {-17.0, 180.0, 6e4, 0.0, -30.0, 0.0},
       500.0},
  };
  for (const Case& c : cases) {
    auto gl = engine::GridVolumeGL::create(c.grid);
    ASSERT_TRUE(gl) << gl.error();
    const Camera camera(c.pose, 45.0, 64, 36);
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso})
      for (auto interpolation : {volume::Interpolation::Linear, volume::Interpolation::Nearest}) {
        if (interpolation == volume::Interpolation::Nearest && mode != volume::VolumeRenderMode::Dvr) continue;
        engine::VolumeRenderOptions o;
        o.render.mode = mode;
        o.render.interpolation = interpolation;
        o.render.stepMeters = c.stepMeters;
        o.render.isoValue = 30.0;
        o.render.transfer = volume::defaultReflectivityTransfer();
        o.render.transfer.opacityReferenceMeters = c.stepMeters * 10.0;
        const volume::VolumeImage gpu = testutil::renderVolumesGpu(**renderer, camera, {{gl->get(), o}});
        const volume::VolumeImage ref = volume::renderReference({{&(*gl)->referenceSampler(), o.render}},
                                                                engine::referenceCameraFor(camera), true, 2);
        const volume::ImageError e = volume::compareImages(gpu, ref);
        int drawn = 0;
        for (const glm::dvec4& p : ref.rgbaPremultiplied) drawn += p.a > 0.05;
        std::cout << "grid " << c.name << ", mode " << static_cast<int>(mode)
                  << (interpolation == volume::Interpolation::Nearest ? " nearest" : "") << ": " << drawn
                  << " pixels drawn, GPU vs reference mean " << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb
                  << " dB\n";
        EXPECT_GT(drawn, 50) << c.name << " must show the blob";
        EXPECT_LT(e.meanAbs, 1.0) << c.name;
        EXPECT_GT(e.psnrDb, 30.0) << c.name;
      }
  }
}

// A multi-level reduced Gaussian GRIB file (N32, written in the test with ecCodes: a blob of 60
// units over the Alps at 5 km on 12 heightAboveSea levels) loaded as a scene's grid layer: the
// frame over the globe shows it where it is (the drawn pixels' centre at the blob's projection),
// the GPU frame matches the reference frame, and the PNG is kept for a look. The opacity ramp is
// the scene's (0 .. 60 units, 0.5 per km), not the variable's default: the test is about where
// the blob lands, and a smooth field's default shows only its upper half, faintly.
TEST(GridMarch, ReducedGribGridRendersInPlace) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  setenv("ATMOGLOBE_CACHE_DIR", (dir + "/reduced_grib_cache").c_str(), 1);
  const double lat0 = 46.5, lon0 = 10.0;
  testutil::ReducedGribSpec spec;
  spec.levels = {0, 500, 1000, 2000, 3000, 4000, 5000, 6000, 7000, 8000, 10000, 12000};
  spec.field = [=](double lat, double lon, double h) {
    const double dLon = std::remainder(lon - lon0, 360.0) * std::cos(degreesToRadians(lat));
    const double d2 = ((lat - lat0) * (lat - lat0) + dLon * dLon) / (8.0 * 8.0);
    return 60.0 * std::exp(-d2 - std::pow((h - 5000.0) / 3000.0, 2));
  };
  const std::string path = dir + "/reduced_blob.grib2";
  ASSERT_EQ(testutil::writeReducedGrib(path, spec), "");
  auto scene = engine::parseSceneJson(R"({"camera": {"lat_deg": 40.0, "lon_deg": 10.0, "height_m": 5000000,
      "heading_deg": 0, "pitch_deg": -90, "roll_deg": 0}, "fov_deg": 60, "size": [320, 240],
      "grids": [{"path": "@data/reduced_blob.grib2", "step_m": 500, "range": [0, 60], "colors": "turbo",
                 "opacity": [0, 60, 0.5]}]})",
                                      "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  auto loader =
      engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()}}, {});
  ASSERT_TRUE(loader) << loader.error();
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer) << renderer.error();
  const Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto globeOnly = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(globeOnly) << globeOnly.error();
  auto grid = (*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0]);
  ASSERT_TRUE(grid) << grid.error();
  const volume::GridVolume& g = testutil::gridVolumeOf(*grid);
  EXPECT_TRUE(g.reduced());
  EXPECT_EQ(g.nz, 12u);
  auto frame = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(frame) << frame.error();
  EXPECT_TRUE(globe::writePng(dir + "/reduced_grib_blob.png", *frame));
  // The pixels the grid changes, and their centre.
  int changed = 0;
  glm::dvec2 centre(0.0);
  for (int y = 0; y < camera.heightPx(); ++y)
    for (int x = 0; x < camera.widthPx(); ++x) {
      const glm::ivec4 d = glm::abs(glm::ivec4(frame->at(x, y)) - glm::ivec4(globeOnly->at(x, y)));
      if (d.r + d.g + d.b > 30) {
        ++changed;
        centre += glm::dvec2(x + 0.5, y + 0.5);
      }
    }
  ASSERT_GT(changed, 500) << "the blob must show";
  centre /= static_cast<double>(changed);
  const auto expected = camera.projectToPixel(globe::geodeticToEcef({lat0, lon0, 5000.0}));
  ASSERT_TRUE(expected.has_value());
  std::cout << "reduced GRIB blob: " << changed << " pixels changed, centre (" << centre.x << ", " << centre.y
            << "), the blob's centre projects to (" << expected->x << ", " << expected->y << ")\n";
  EXPECT_LT(glm::length(centre - *expected), 8.0);
  (*renderer)->setReferenceVolumes(2);
  auto ref = (*renderer)->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(ref) << ref.error();
  EXPECT_TRUE(globe::writePng(dir + "/reduced_grib_blob_reference.png", *ref));
  double sum = 0.0;
  for (int y = 0; y < camera.heightPx(); ++y)
    for (int x = 0; x < camera.widthPx(); ++x) {
      const glm::ivec4 d = glm::abs(glm::ivec4(frame->at(x, y)) - glm::ivec4(ref->at(x, y)));
      sum += d.r + d.g + d.b;
    }
  const double mean = sum / (3.0 * camera.widthPx() * camera.heightPx());
  std::cout << "reduced GRIB blob: mean |GPU - reference frame| " << mean << " (8-bit)\n";
  EXPECT_LT(mean, 1.0);
}

// Level of detail (volume/GridDetail.h): a global grid seen from far is marched on a block-mean
// copy chosen by the pixel footprint, the GPU frame of that copy agrees with the CPU reference of
// the same copy, a close view and "level_of_detail": false march the grid itself, and the copy is
// kept while the step is shown.
// The SYNTHETIC global grid's dbz with everything above -31 dBZ visible (clear air is -30), so
// the whole shell is drawn.
static engine::VolumeLayerDescription wholeShellLayer(const std::string& path) {
  engine::VolumeLayerDescription d;
  d.kind = engine::VolumeKind::Grid;
  d.path = path;
  d.field = "dbz";
  d.settings.valueRange = glm::dvec2(-31.0, 60.0);
  d.settings.opacity = {-31.0, 40.0, 0.5, 20000.0};
  return d;
}

// Mean |a - b| over the RGB channels of two frames of one size, in 8-bit steps; `differing`: how
// many pixels differ at all.
static double meanFrameDifference(const globe::ImageRGBA8& a, const globe::ImageRGBA8& b, int* differing = nullptr) {
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const glm::ivec4 e = glm::abs(glm::ivec4(a.at(x, y)) - glm::ivec4(b.at(x, y)));
      sum += e.r + e.g + e.b;
      if (e != glm::ivec4(0)) ++n;
    }
  if (differing) *differing = n;
  return sum / (3.0 * a.width * a.height);
}

// A renderer holding the grid layer `d` (with `levelOfDetail`), uploaded under a GPU memory limit of
// `limitBytes` ($ATMOGLOBE_MAX_TEXTURE_BYTES; nullptr: none). Null, with a test failure, when it
// cannot be made.
struct GridUnderLimit {
  std::unique_ptr<engine::SceneRendererGL> renderer;
  engine::GridSourceGL* grid = nullptr;
};
static std::optional<GridUnderLimit> gridUnderLimit(const std::shared_ptr<globe::TileImageLoader>& loader,
                                                    engine::VolumeLayerDescription d, const char* limitBytes,
                                                    bool levelOfDetail, bool nearWindow = true) {
  auto renderer = engine::SceneRendererGL::create(loader);
  if (!renderer) {
    ADD_FAILURE() << renderer.error();
    return std::nullopt;
  }
  d.levelOfDetail = levelOfDetail;
  d.nearWindow = nearWindow;
  if (limitBytes) setenv("ATMOGLOBE_MAX_TEXTURE_BYTES", limitBytes, 1);
  auto layer = (*renderer)->addVolume(d);
  unsetenv("ATMOGLOBE_MAX_TEXTURE_BYTES");
  if (!layer) {
    ADD_FAILURE() << layer.error();
    return std::nullopt;
  }
  return GridUnderLimit{std::move(*renderer), &dynamic_cast<engine::GridSourceGL&>(**layer)};
}

// A SYNTHETIC global grid of 2.5 deg (144 x 73 columns) written to the test directory as
// NAME.nc, as a layer of its whole shell.
static engine::VolumeLayerDescription globalGridLayer(const std::string& name) {
  volume::SyntheticGlobalGridOptions go;
  go.nx = 144;
  go.ny = 73;
  const std::string path = testutil::testOutputDir() + "/" + name + ".nc";
  EXPECT_TRUE(volume::writeSyntheticGlobalGrid(path, go));
  return wholeShellLayer(path);
}

// That layer drawn once from `camera` into `fb`: the picture, the legend's subtitle, the window of
// the columns in view (empty where none) and the grid volume drawn last (a window's, or the grid
// as uploaded; the near window at full resolution comes before it where one is drawn). Null, with
// a test failure, when it cannot be drawn.
struct DrawnUnderLimit {
  GridUnderLimit held;
  globe::ImageRGBA8 image;
  std::string legend;
  volume::GridWindow window;
  const engine::GridVolumeGL* drawn = nullptr;
};
static std::optional<DrawnUnderLimit> drawUnderLimit(const std::shared_ptr<globe::TileImageLoader>& loader,
                                                     const engine::VolumeLayerDescription& d, const char* limitBytes,
                                                     bool levelOfDetail, const Camera& camera,
                                                     engine::FramebufferGL& fb, bool nearWindow = true) {
  auto held = gridUnderLimit(loader, d, limitBytes, levelOfDetail, nearWindow);
  if (!held) return std::nullopt;
  auto image = held->renderer->renderToImage(camera, {}, fb);
  if (!image) {
    ADD_FAILURE() << image.error();
    return std::nullopt;
  }
  const engine::GridSourceGL& grid = *held->grid;
  DrawnUnderLimit out{std::move(*held), std::move(*image), grid.legendPart().subtitle, grid.viewWindow(),
                      dynamic_cast<const engine::GridVolumeGL*>(grid.volumes().back())};
  return out;
}

TEST(GridMarch, LevelOfDetailFollowsThePixelFootprint) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  volume::SyntheticGlobalGridOptions go;
  go.nx = 144;  // 2.5 deg: columns 278 km apart at the equator
  go.ny = 73;
  ASSERT_TRUE(volume::writeSyntheticGlobalGrid(dir + "/lod_global.nc", go));
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer) << renderer.error();
  const engine::VolumeLayerDescription d = wholeShellLayer(dir + "/lod_global.nc");
  auto layer = (*renderer)->addVolume(d);
  ASSERT_TRUE(layer) << layer.error();
  auto& grid = dynamic_cast<engine::GridSourceGL&>(**layer);
  // 35,000 km up, fovY 45 over 36 px: a pixel spans 35,000 km x 2 tan(22.5 deg) / 36 = 805 km at
  // the nearest point, so cells of up to 805 km: level 1 (556 km); 144 x 73 columns allow 3.
  const Camera far(CameraPose{15.0, -40.0, 35.0e6, 0.0, -90.0, 0.0}, 45.0, 64, 36);
  auto fb = engine::FramebufferGL::create(far.widthPx(), far.heightPx());
  ASSERT_TRUE(fb);
  auto gpu = (*renderer)->renderToImage(far, {}, **fb);
  ASSERT_TRUE(gpu) << gpu.error();
  EXPECT_EQ(grid.detailLevel(), 1);
  ASSERT_EQ(grid.volumes().size(), 1u);
  const engine::VolumeGL* coarse = grid.volumes()[0];
  EXPECT_NE(coarse, &grid.volume());
  EXPECT_EQ(dynamic_cast<const engine::GridVolumeGL*>(coarse)->grid().nx, 72u);
  EXPECT_EQ(dynamic_cast<const engine::GridVolumeGL*>(coarse)->grid().nz, 19u);  // 37 levels in pairs
  // The same copy's CPU reference in the marcher's place: as close as for any grid.
  (*renderer)->setReferenceVolumes(2);
  auto ref = (*renderer)->renderToImage(far, {}, **fb);
  ASSERT_TRUE(ref) << ref.error();
  (*renderer)->setReferenceVolumes(0);
  grid.visible = false;
  auto bare = (*renderer)->renderToImage(far, {}, **fb);
  ASSERT_TRUE(bare) << bare.error();
  grid.visible = true;
  double sum = 0.0;
  int drawn = 0;
  for (int y = 0; y < far.heightPx(); ++y)
    for (int x = 0; x < far.widthPx(); ++x) {
      const glm::ivec4 a(gpu->at(x, y)), b(ref->at(x, y));
      const glm::ivec4 e = glm::abs(a - b);
      sum += e.r + e.g + e.b;
      if (a != glm::ivec4(bare->at(x, y))) ++drawn;
    }
  const double mean = sum / (3.0 * far.widthPx() * far.heightPx());
  std::cout << "level of detail 1 from 35,000 km: mean |GPU - reference| " << mean << " of 255 over " << drawn
            << " pixels drawn\n";
  EXPECT_GT(drawn, 120);  // the disc is about 16 px across
  // Below one 8-bit step, as the other scenes with the reference in the marcher's place.
  EXPECT_LT(mean, 1.0);
  // Drawn again: the copy is kept, not made again.
  ASSERT_TRUE((*renderer)->renderToImage(far, {}, **fb));
  EXPECT_EQ(grid.volumes()[0], coarse);
  // Close: the grid itself.
  const Camera close(CameraPose{15.0, -40.0, 2.0e6, 0.0, -90.0, 0.0}, 45.0, 64, 36);
  ASSERT_TRUE((*renderer)->renderToImage(close, {}, **fb));
  EXPECT_EQ(grid.detailLevel(), 0);
  EXPECT_EQ(grid.volumes()[0], &grid.volume());
  // Switched off: the grid itself from far too (an edit of the options only: nothing read again).
  engine::VolumeLayerDescription off = grid.description();
  off.levelOfDetail = false;
  EXPECT_EQ(engine::layerChange(grid.description(), off), engine::LayerChange::Options);
  ASSERT_TRUE((*renderer)->setVolumeDescription(0, off));
  ASSERT_TRUE((*renderer)->renderToImage(far, {}, **fb));
  EXPECT_EQ(grid.detailLevel(), 0);
  EXPECT_EQ(grid.volumes()[0], &grid.volume());
  // In the background (the viewer): the first frame goes on with the grid itself while the copy
  // is made on a worker, a later one takes the copy, and that frame is the synchronous one's.
  auto second = (*renderer)->addVolume(d);
  ASSERT_TRUE(second) << second.error();
  auto& fresh = dynamic_cast<engine::GridSourceGL&>(**second);
  grid.visible = false;
  (*renderer)->setDetailInBackground(true);
  ASSERT_TRUE((*renderer)->renderToImage(far, {}, **fb));
  EXPECT_EQ(fresh.detailLevel(), 0);
  EXPECT_EQ(fresh.volumes()[0], &fresh.volume());
  Result<globe::ImageRGBA8> later = makeError("not drawn");
  for (int frame = 0; frame < 600 && fresh.detailLevel() == 0; ++frame) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    later = (*renderer)->renderToImage(far, {}, **fb);
    ASSERT_TRUE(later) << later.error();
  }
  ASSERT_EQ(fresh.detailLevel(), 1) << "the copy made on the worker within 6 s";
  EXPECT_EQ(later->pixels, gpu->pixels) << "the same picture as the copy made before the frame";
  (*renderer)->setDetailInBackground(false);
  // The scene key.
  auto scene = engine::parseSceneJson(R"({"grids": [{"path": "g.nc", "level_of_detail": false}]})", "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_FALSE(engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0].levelOfDetail);
  EXPECT_NE(engine::sceneToJson(*scene).find("\"level_of_detail\": false"), std::string::npos);
}

// A grid too large for the GPU ($ATMOGLOBE_MAX_TEXTURE_BYTES below its texture): uploaded at half
// the resolution, and drawn from the columns and rows in view at full resolution where the view
// sees a small part of it, as the grid drawn whole without a limit.
TEST(GridMarch, AGridTooLargeForTheGpuIsDrawnFromTheColumnsInView) {
  testutil::glContext();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  const engine::VolumeLayerDescription d = globalGridLayer("window_global");
  // 3,000 km above 15 N 40 W looking down: about 2,500 km of the globe across, 10 of 144 columns.
  const Camera close(CameraPose{15.0, -40.0, 3.0e6, 0.0, -90.0, 0.0}, 45.0, 160, 90);
  auto fb = engine::FramebufferGL::create(close.widthPx(), close.heightPx());
  ASSERT_TRUE(fb);
  auto draw = [&](bool limited, bool levelOfDetail, std::string* legend) -> std::optional<globe::ImageRGBA8> {
    // The whole grid's texels are 3.1 MB.
    auto shown = drawUnderLimit(*loader, d, limited ? "1500000" : nullptr, levelOfDetail, close, **fb);
    if (!shown) return std::nullopt;
    auto& renderer = shown->held.renderer;
    engine::GridSourceGL& grid = *shown->held.grid;
    EXPECT_EQ(grid.gridVolume().grid().nx, limited ? 72u : 144u);  // every 2nd column of a wrapping grid
    if (legend) *legend = shown->legend;
    if (limited && levelOfDetail) {
      const volume::GridWindow& w = shown->window;
      EXPECT_FALSE(w.empty());
      const engine::GridVolumeGL* drawn = shown->drawn;
      EXPECT_NE(drawn, &grid.gridVolume());
      if (drawn) {
        EXPECT_EQ(drawn->grid().nx, w.columnCount);
        EXPECT_EQ(drawn->grid().ny, w.rowCount);
        EXPECT_LT(w.columnCount * w.rowCount * 4, 144u * 73u);
        EXPECT_NEAR(drawn->grid().lonDeg[1] - drawn->grid().lonDeg[0], 2.5, 1e-9);  // full resolution
      }
      // Moved a little (50 km): the same window, not made again.
      const Camera moved(CameraPose{15.0, -39.5, 3.0e6, 0.0, -90.0, 0.0}, 45.0, 160, 90);
      EXPECT_TRUE(renderer->renderToImage(moved, {}, **fb));
      EXPECT_EQ(grid.volumes()[0], drawn);
      // From 35,000 km the view holds half the globe: no window (the coarser copies instead).
      const Camera far(CameraPose{15.0, -40.0, 35.0e6, 0.0, -90.0, 0.0}, 45.0, 160, 90);
      EXPECT_TRUE(renderer->renderToImage(far, {}, **fb));
      EXPECT_TRUE(grid.viewWindow().empty());
    }
    return std::move(shown->image);
  };
  std::string wholeLegend, windowLegend, reducedLegend;
  const auto whole = draw(false, true, &wholeLegend);
  const auto windowed = draw(true, true, &windowLegend);
  const auto reduced = draw(true, false, &reducedLegend);
  ASSERT_TRUE(whole && windowed && reduced);
  int differWindow = 0, differReduced = 0;
  const double window = meanFrameDifference(*windowed, *whole, &differWindow);
  const double half = meanFrameDifference(*reduced, *whole, &differReduced);
  std::cout << "against the whole grid without a limit: the window in view " << window << " of 255 (" << differWindow
            << " pixels differ), the grid at half resolution " << half << " (" << differReduced << ")\n";
  // The same points marched from another origin and tables: float rounding only, well under an
  // 8-bit step on average; the half-resolution grid misses a quarter of the points.
  EXPECT_LT(window, 0.05);
  EXPECT_GT(half, 10.0 * window);
  EXPECT_GT(half, 0.2);
  EXPECT_EQ(wholeLegend.find("resolution"), std::string::npos) << wholeLegend;
  EXPECT_NE(windowLegend.find("the columns in view at full resolution"), std::string::npos) << windowLegend;
  EXPECT_NE(reducedLegend.find("at 1/2 resolution (GPU memory)"), std::string::npos) << reducedLegend;
}

// A grid uploaded at 1/4 of its resolution (limit 0.5 MB, the whole grid's texels 3.1 MB): a view
// whose window does not fit at full resolution takes it at the finest that fits (1/2), which is
// closer to the whole grid drawn without a limit than the 1/4 grid; a closer view makes a window
// at full resolution, and the legend says which.
TEST(GridMarch, AWindowThatFitsOnlyAtACoarserResolutionIsStillFinerThanTheGridAsUploaded) {
  testutil::glContext();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  const engine::VolumeLayerDescription d = globalGridLayer("window_levels");
  const Camera mid(CameraPose{15.0, -40.0, 3.0e6, 0.0, -90.0, 0.0}, 45.0, 160, 90);
  const Camera close(CameraPose{15.0, -40.0, 0.8e6, 0.0, -90.0, 0.0}, 45.0, 160, 90);
  auto fb = engine::FramebufferGL::create(mid.widthPx(), mid.heightPx());
  ASSERT_TRUE(fb);
  auto draw = [&](bool limited, bool levelOfDetail, std::string* legend) -> std::optional<globe::ImageRGBA8> {
    // One resolution throughout (the near window at full resolution: the test below).
    auto shown = drawUnderLimit(*loader, d, limited ? "500000" : nullptr, levelOfDetail, mid, **fb, false);
    if (!shown) return std::nullopt;
    auto& renderer = shown->held.renderer;
    engine::GridSourceGL& grid = *shown->held.grid;
    EXPECT_EQ(grid.gridVolume().grid().nx, limited ? 36u : 144u);  // every 4th column
    if (legend) *legend = shown->legend;
    if (limited && levelOfDetail) {
      const volume::GridWindow& w = shown->window;
      EXPECT_FALSE(w.empty());
      const engine::GridVolumeGL* drawn = shown->drawn;
      EXPECT_NE(drawn, &grid.gridVolume());
      if (drawn) {
        EXPECT_GT(w.columnCount * w.rowCount, 36u * 19u) << "the window does not fit at full resolution";
        EXPECT_NEAR(drawn->grid().lonDeg[1] - drawn->grid().lonDeg[0], 5.0, 1e-9);  // 1/2
      }
      // Closer: a window at full resolution, made anew.
      EXPECT_TRUE(renderer->renderToImage(close, {}, **fb));
      const auto* nearer = dynamic_cast<const engine::GridVolumeGL*>(grid.volumes()[0]);
      EXPECT_NE(nearer, &grid.gridVolume());
      if (nearer) {
        EXPECT_NEAR(nearer->grid().lonDeg[1] - nearer->grid().lonDeg[0], 2.5, 1e-9);
      }
      EXPECT_NE(grid.legendPart().subtitle.find("the columns in view at full resolution"), std::string::npos)
          << grid.legendPart().subtitle;
    }
    return std::move(shown->image);
  };
  std::string windowLegend, quarterLegend;
  const auto whole = draw(false, true, nullptr);
  const auto windowed = draw(true, true, &windowLegend);
  const auto quarter = draw(true, false, &quarterLegend);
  ASSERT_TRUE(whole && windowed && quarter);
  const double half = meanFrameDifference(*windowed, *whole), fourth = meanFrameDifference(*quarter, *whole);
  std::cout << "against the whole grid without a limit: the window in view at 1/2 resolution " << half
            << " of 255, the grid at 1/4 " << fourth << "\n";
  // Every 2nd point against every 4th: the window's frame is the closer of the two by a margin.
  EXPECT_LT(half, 0.7 * fourth);
  EXPECT_NE(windowLegend.find("the columns in view at 1/2 resolution (GPU memory)"), std::string::npos) << windowLegend;
  EXPECT_NE(quarterLegend.find("at 1/4 resolution (GPU memory)"), std::string::npos) << quarterLegend;
}

// A global 2.5-degree grid (2 levels, 0 and 15 km) seen obliquely across the antimeridian: the
// near window holds the visible point nearest the eye, keeps within the cap, crosses the seam,
// and grows with the cap; the view's window holds it. No point in view: empty.
TEST(NearGridWindow, HoldsTheNearestColumnsInViewWithinTheCap) {
  volume::GridVolume g;
  g.nx = 144, g.ny = 73, g.nz = 2;
  for (std::size_t i = 0; i < g.nx; ++i) g.lonDeg.push_back(-180.0 + 2.5 * static_cast<double>(i));
  for (std::size_t j = 0; j < g.ny; ++j) g.latDeg.push_back(-90.0 + 2.5 * static_cast<double>(j));
  g.wrapsLongitude = true;
  g.values.assign(g.nx * g.ny * g.nz, 1.0f);
  g.heightAboveEllipsoidMeters.assign(g.nx * g.ny, 0.0f);
  g.heightAboveEllipsoidMeters.resize(g.nx * g.ny * g.nz, 15000.0f);
  // 2,000 km above 10 N 179 E looking north-east, 35 degrees down.
  const Camera camera(CameraPose{10.0, 179.0, 2.0e6, 45.0, -35.0, 0.0}, 45.0, 160, 90);
  const volume::GridWindow view = engine::visibleGridWindow(camera, g);
  const volume::GridWindow small = engine::nearGridWindow(camera, g, 120);
  const volume::GridWindow large = engine::nearGridWindow(camera, g, 360);
  ASSERT_FALSE(view.empty());
  ASSERT_FALSE(small.empty());
  ASSERT_FALSE(large.empty());
  EXPECT_LE(small.columnCount * small.rowCount, 120u);
  EXPECT_LE(large.columnCount * large.rowCount, 360u);
  EXPECT_GT(large.columnCount * large.rowCount, 2 * small.columnCount * small.rowCount);
  EXPECT_LT(large.columnCount * large.rowCount, view.columnCount * view.rowCount);
  // Columns modulo nx: does `w` hold column i, row j?
  auto holds = [&](const volume::GridWindow& w, std::size_t i, std::size_t j) {
    return j >= w.firstRow && j < w.firstRow + w.rowCount && (i + g.nx - w.firstColumn) % g.nx < w.columnCount;
  };
  // The nearest grid point to the eye among those in view: brute force over every column and row
  // (the ground under the bottom row's middle pixel is seen, and the grid points around it).
  const auto ground = globe::intersectRayEllipsoid(camera.eyeEcef(), camera.pixelRayDirection(80.0, 89.5));
  ASSERT_TRUE(ground);
  const globe::Geodetic under = globe::ecefToGeodetic(*ground);
  const std::size_t i0 = static_cast<std::size_t>(std::lround((under.lonDeg + 180.0) / 2.5)) % g.nx;
  const std::size_t j0 = static_cast<std::size_t>(std::lround((under.latDeg + 90.0) / 2.5));
  EXPECT_TRUE(holds(small, i0, j0)) << under.latDeg << ", " << under.lonDeg;
  EXPECT_TRUE(holds(large, i0, j0));
  EXPECT_TRUE(holds(view, i0, j0));
  // The view reaches both sides of the antimeridian, and so does the larger near window.
  EXPECT_TRUE(holds(large, 0, j0 + 4) && holds(large, g.nx - 1, j0 + 4))
      << large.firstColumn << " + " << large.columnCount << ", rows " << large.firstRow << " + " << large.rowCount;
  // Straight down on the north pole every column is in view: the near window leaves one out (a
  // window of every column would wrap and close a polar cap of its own over the rest of the grid).
  const Camera pole(CameraPose{90.0, 0.0, 2.0e6, 0.0, -90.0, 0.0}, 45.0, 160, 90);
  const volume::GridWindow polar = engine::nearGridWindow(pole, g, 720);
  ASSERT_FALSE(polar.empty());
  EXPECT_EQ(polar.columnCount, g.nx - 1);
  EXPECT_EQ(polar.firstRow + polar.rowCount, g.ny);
  // At most so many columns and rows (what one texture holds), and no curvilinear grids (their
  // windows are not latitude/longitude boxes).
  const volume::GridWindow narrow = engine::nearGridWindow(camera, g, 360, 8, 100);
  ASSERT_FALSE(narrow.empty());
  EXPECT_LE(narrow.columnCount, 8u);
  EXPECT_TRUE(holds(narrow, i0, j0));
  volume::GridVolume curved = g;
  curved.curvilinear = true;
  EXPECT_TRUE(engine::nearGridWindow(camera, curved, 360).empty());
  // Looking away from the Earth: nothing in view.
  const Camera away(CameraPose{10.0, 179.0, 2.0e6, 45.0, 60.0, 0.0}, 45.0, 160, 90);
  EXPECT_TRUE(engine::nearGridWindow(away, g, 800).empty());
  // The scene key that turns it off, written back.
  const std::string dir = testutil::testOutputDir();
  auto scene = engine::parseSceneJson(R"({"grids": [{"path": "g.nc", "near_window": false}]})", "s.json", dir, dir);
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_FALSE(engine::volumesOfKind(*scene, engine::VolumeKind::Grid)[0].nearWindow);
  EXPECT_NE(engine::sceneToJson(*scene).find("\"near_window\": false"), std::string::npos);
  EXPECT_FALSE(engine::parseSceneJson(R"({"grids": [{"path": "g.nc", "near_window": 2}]})", "s.json", dir, dir));
}

// The layer `d` drawn from `camera` into `fb` three ways: the whole grid without a limit, and
// under a 0.5 MB limit at one resolution throughout and near and far (the default).
struct NearAndFar {
  std::optional<DrawnUnderLimit> whole, single, two;
};
static NearAndFar drawNearAndFar(const std::shared_ptr<globe::TileImageLoader>& loader,
                                 const engine::VolumeLayerDescription& d, const Camera& camera,
                                 engine::FramebufferGL& fb) {
  NearAndFar out;
  out.whole = drawUnderLimit(loader, d, nullptr, true, camera, fb);
  out.single = drawUnderLimit(loader, d, "500000", true, camera, fb, false);
  out.two = drawUnderLimit(loader, d, "500000", true, camera, fb);
  return out;
}

// A grid uploaded at 1/4 (limit 0.5 MB) seen obliquely from 3,000 km: the view's window fits only
// at a coarser resolution, so the columns nearest the eye are drawn at full resolution with it in
// one march (two volumes, the coarser one with the near window's box as its hole). Against the
// whole grid drawn without a limit this frame is closer than one resolution throughout; the
// marcher and the CPU reference agree on both levels and their seam; a small move keeps the near
// window; the legend says what is drawn.
TEST(GridMarch, TheColumnsNearestTheEyeAreDrawnAtFullResolutionAndTheRestCoarser) {
  testutil::glContext();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  // At a fixed step: the step rule takes each grid's middle column spacing, which a window
  // changes, so the frames would differ by their steps as well as by their resolutions.
  engine::VolumeLayerDescription d = globalGridLayer("near_window");
  d.stepMeters = 2000.0;
  d.samplesPerCell = 0.0;
  const Camera oblique(CameraPose{0.0, -40.0, 3.0e6, 0.0, -35.0, 0.0}, 45.0, 160, 90);
  auto fb = engine::FramebufferGL::create(oblique.widthPx(), oblique.heightPx());
  ASSERT_TRUE(fb);
  NearAndFar drawn = drawNearAndFar(*loader, d, oblique, **fb);
  ASSERT_TRUE(drawn.whole && drawn.single && drawn.two);
  const auto& whole = drawn.whole;
  const auto& single = drawn.single;
  auto& two = drawn.two;
  engine::GridSourceGL& grid = *two->held.grid;
  const std::vector<const engine::VolumeGL*> volumes = grid.volumes();
  ASSERT_EQ(volumes.size(), 2u);
  const auto* nearest = dynamic_cast<const engine::GridVolumeGL*>(volumes[0]);
  const auto* coarse = dynamic_cast<const engine::GridVolumeGL*>(volumes[1]);
  ASSERT_TRUE(nearest && coarse);
  const volume::GridVolume& n = nearest->grid();
  EXPECT_NEAR(n.lonDeg[1] - n.lonDeg[0], 2.5, 1e-9);  // full resolution
  EXPECT_GT(coarse->grid().lonDeg[1] - coarse->grid().lonDeg[0], 4.9);
  EXPECT_LE(n.nx * n.ny, 36u * 19u) << "no more columns x rows than the grid as uploaded";
  // The hole is the coarser volume's alone, and it is the near window's box.
  const std::optional<volume::LonLatBox> hole = grid.holeOf(coarse);
  ASSERT_TRUE(hole);
  EXPECT_FALSE(grid.holeOf(nearest));
  EXPECT_DOUBLE_EQ(hole->westDeg, n.lonDeg.front());
  EXPECT_DOUBLE_EQ(hole->spanDeg, n.lonDeg.back() - n.lonDeg.front());
  EXPECT_DOUBLE_EQ(hole->southDeg, std::min(n.latDeg.front(), n.latDeg.back()));
  // It holds the ground nearest the eye in view (under the bottom row's middle pixel).
  const auto ground = globe::intersectRayEllipsoid(oblique.eyeEcef(), oblique.pixelRayDirection(80.0, 89.5));
  ASSERT_TRUE(ground);
  const globe::Geodetic g = globe::ecefToGeodetic(*ground);
  EXPECT_TRUE(hole->contains(g.latDeg, g.lonDeg)) << g.latDeg << ", " << g.lonDeg;
  int differSingle = 0, differTwo = 0;
  const double one = meanFrameDifference(single->image, whole->image, &differSingle);
  const double both = meanFrameDifference(two->image, whole->image, &differTwo);
  std::cout << "against the whole grid without a limit: one resolution throughout " << one << " of 255 ("
            << differSingle << " pixels differ), the nearest columns at full resolution " << both << " (" << differTwo
            << ")\n";
  // The near window covers the lower part of the view, where most of the grid's columns are seen
  // closest: the frame is nearer the whole grid's by a margin (a hole that let both levels
  // draw the near box would double its extinction and be further away than either).
  EXPECT_LT(both, 0.7 * one);
  EXPECT_GT(one, 0.2);
  EXPECT_NE(two->legend.find("the nearest columns at full resolution, the rest at 1/"), std::string::npos)
      << two->legend;
  // The CPU reference of the same two volumes and hole (double precision): the marcher's frame
  // within half an 8-bit step on average, the seam included.
  auto& renderer = *two->held.renderer;
  renderer.setReferenceVolumes(2);
  auto reference = renderer.renderToImage(oblique, {}, **fb);
  renderer.setReferenceVolumes(0);
  ASSERT_TRUE(reference) << reference.error();
  EXPECT_EQ(grid.volumes()[0], volumes[0]);
  const double gpuVsReference = meanFrameDifference(two->image, *reference);
  std::cout << "the marcher against the reference: " << gpuVsReference << " of 255\n";
  EXPECT_LT(gpuVsReference, 0.5);
  // The cursor readout near the bottom of the view reads the near window (the first value along
  // the ray lies in its box).
  const glm::dvec3 down = oblique.pixelRayDirection(80.0, 80.0);
  const auto nearHit = engine::firstValueAlong(nearest->referenceSampler(), oblique.eyeEcef(), down, 1e8, 500.0,
                                               volume::Interpolation::Linear);
  ASSERT_TRUE(nearHit);
  const globe::Geodetic at = globe::ecefToGeodetic(nearHit->ecef);
  ASSERT_TRUE(hole->contains(at.latDeg, at.lonDeg));
  const std::optional<std::string> readout = grid.readoutAt(oblique.eyeEcef(), down, 1e8, 500.0);
  ASSERT_TRUE(readout);
  char value[32];
  std::snprintf(value, sizeof value, "%.4g", nearHit->value);
  EXPECT_NE(readout->find(std::string(": ") + value + " "), std::string::npos) << *readout << " / " << value;
  // A 20 km move keeps the near window.
  const Camera moved(CameraPose{0.0, -39.8, 3.0e6, 0.0, -35.0, 0.0}, 45.0, 160, 90);
  EXPECT_TRUE(renderer.renderToImage(moved, {}, **fb));
  ASSERT_EQ(grid.volumes().size(), 2u);
  EXPECT_EQ(grid.volumes()[0], volumes[0]);
}

// The same across the antimeridian and near a pole. Across the seam (the near window's
// longitudes increasing past 180) the frame is nearer the whole grid's than one resolution
// throughout. Looking north from 75 N the near window is a band of high latitudes where this
// field changes little: the frame is no further from the whole grid's. In both, the marcher
// agrees with the reference.
TEST(GridMarch, NearAndFarHoldAcrossTheAntimeridianAndAtAPole) {
  testutil::glContext();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  engine::VolumeLayerDescription d = globalGridLayer("near_window_seam");
  d.stepMeters = 2000.0;  // the fixed step, as above
  d.samplesPerCell = 0.0;
  for (const CameraPose& pose :
       {CameraPose{-5.0, 175.0, 3.0e6, 20.0, -35.0, 0.0}, CameraPose{75.0, -170.0, 3.0e6, 0.0, -50.0, 0.0}}) {
    const bool seam = pose.latDeg < 0.0;
    const Camera camera(pose, 45.0, 160, 90);
    auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    ASSERT_TRUE(fb);
    NearAndFar drawn = drawNearAndFar(*loader, d, camera, **fb);
    ASSERT_TRUE(drawn.whole && drawn.single && drawn.two);
    engine::GridSourceGL& grid = *drawn.two->held.grid;
    ASSERT_EQ(grid.volumes().size(), 2u) << pose.latDeg;
    const auto* nearest = dynamic_cast<const engine::GridVolumeGL*>(grid.volumes()[0]);
    ASSERT_TRUE(nearest);
    const std::optional<volume::LonLatBox> hole = grid.holeOf(grid.volumes()[1]);
    ASSERT_TRUE(hole);
    const double one = meanFrameDifference(drawn.single->image, drawn.whole->image);
    const double both = meanFrameDifference(drawn.two->image, drawn.whole->image);
    auto& renderer = *drawn.two->held.renderer;
    renderer.setReferenceVolumes(2);
    auto reference = renderer.renderToImage(camera, {}, **fb);
    renderer.setReferenceVolumes(0);
    ASSERT_TRUE(reference) << reference.error();
    const double gpuVsReference = meanFrameDifference(drawn.two->image, *reference);
    std::cout << "at " << pose.latDeg << ", " << pose.lonDeg << ": near window longitudes " << hole->westDeg << " + "
              << hole->spanDeg << ", latitudes " << hole->southDeg << " .. " << hole->northDeg
              << "; against the whole grid: one resolution " << one << ", near and far " << both
              << "; the marcher against the reference " << gpuVsReference << "\n";
    if (seam) {
      EXPECT_GT(hole->westDeg + hole->spanDeg, 180.0);  // the box crosses the antimeridian
      EXPECT_LT(both, 0.7 * one);
    } else {
      EXPECT_GE(hole->northDeg, 80.0);
      EXPECT_LE(both, one + 0.01);  // 0.01 of 255: rounding of a few pixels by one step
    }
    EXPECT_LT(gpuVsReference, 0.5);
  }
}

// A reduced (Gaussian) GRIB grid too large for the GPU's limit, as a rectilinear grid: under a
// 0.5 MB limit it is uploaded at 1/2 and a close view draws the columns in view at full
// resolution (a reduced window, above); under 0.2 MB it is uploaded at 1/4 and the same view's
// window fits only at 1/2, each row lengthened so that every 2nd point still reaches the window's
// east edge. At the fixed step (the step rule takes each grid's mean level heights and middle
// column spacing, which a window changes) the full-resolution window's frame equals the whole
// grid's drawn without a limit up to float rounding; the window at 1/2 is closer to it than the
// grid at 1/4.
TEST(GridMarch, AReducedGridTooLargeForTheGpuIsDrawnFromTheColumnsInView) {
  testutil::glContext();
  const std::string dir = testutil::testOutputDir();
  setenv("ATMOGLOBE_CACHE_DIR", (dir + "/reduced_window_cache").c_str(), 1);
  const double lat0 = 46.5, lon0 = 10.0;
  testutil::ReducedGribSpec spec;  // N32: 64 rows of 20 .. 128 points
  spec.levels = {0, 500, 1000, 2000, 3000, 4000, 5000, 6000, 7000, 8000, 10000, 12000};
  spec.field = [=](double lat, double lon, double h) {
    const double dLon = std::remainder(lon - lon0, 360.0) * std::cos(degreesToRadians(lat));
    const double d2 = ((lat - lat0) * (lat - lat0) + dLon * dLon) / (8.0 * 8.0);
    return 60.0 * std::exp(-d2 - std::pow((h - 5000.0) / 3000.0, 2));
  };
  const std::string path = dir + "/reduced_window.grib2";
  ASSERT_EQ(testutil::writeReducedGrib(path, spec), "");
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader);
  engine::VolumeLayerDescription d;
  d.kind = engine::VolumeKind::Grid;
  d.path = path;
  d.settings.valueRange = glm::dvec2(0.0, 60.0);
  d.settings.opacity = {0.0, 40.0, 0.8, 2000.0};  // opaque within a few km: the blob shows plainly
  d.stepMeters = 2000.0;
  d.samplesPerCell = 0.0;
  // 3,000 km above the blob looking down: about 4,500 km across, under half of the 128 columns.
  const Camera close(CameraPose{lat0, lon0, 3.0e6, 0.0, -90.0, 0.0}, 45.0, 160, 90);
  auto fb = engine::FramebufferGL::create(close.widthPx(), close.heightPx());
  ASSERT_TRUE(fb);
  // `limit`: null for none; `uploadedNx`: the longest row as uploaded; `windowFactor`: every how
  // many points the window keeps.
  auto draw = [&](const char* limit, bool levelOfDetail, std::size_t uploadedNx, std::size_t windowFactor,
                  std::string* legend) -> std::optional<globe::ImageRGBA8> {
    auto shown = drawUnderLimit(*loader, d, limit, levelOfDetail, close, **fb);  // the whole grid needs 1.0 MB
    if (!shown) return std::nullopt;
    engine::GridSourceGL& grid = *shown->held.grid;
    EXPECT_TRUE(grid.gridVolume().grid().reduced());
    EXPECT_EQ(grid.gridVolume().grid().nx, uploadedNx);
    if (legend) *legend = shown->legend;
    if (limit && levelOfDetail) {
      const volume::GridWindow& w = shown->window;
      EXPECT_FALSE(w.empty());
      const engine::GridVolumeGL* drawn = shown->drawn;
      EXPECT_NE(drawn, &grid.gridVolume());
      if (drawn) {
        EXPECT_TRUE(drawn->grid().reduced());
        EXPECT_LT(w.columnCount * 2, 128u);  // under half the circle (53 columns when written)
        EXPECT_NEAR(drawn->grid().reducedSpacingDeg(), static_cast<double>(windowFactor) * 360.0 / 128.0, 1e-9);
        // Every row reaches both edges of the window.
        const double west = grid.gridVolume().unreducedGrid()->lonDeg[w.firstColumn];
        const double east = west + static_cast<double>(w.columnCount - 1) * 360.0 / 128.0;
        for (std::size_t r = 0; r < drawn->grid().ny; ++r) {
          EXPECT_LE(drawn->grid().rowFirstLonDeg[r], west + 1e-9) << "row " << r;
          EXPECT_GE(drawn->grid().lonDegAt(r, drawn->grid().rowLengthPoints[r] - 1), east - 1e-9) << "row " << r;
        }
      }
    }
    return std::move(shown->image);
  };
  std::string legend;
  const auto whole = draw(nullptr, true, 128, 1, &legend);
  ASSERT_TRUE(whole);
  EXPECT_EQ(legend.find("resolution"), std::string::npos) << legend;
  struct Case {
    const char* limit;
    std::size_t uploadedNx, windowFactor;
    const char* windowNote;
    const char* gridNote;
  };
  for (const Case& c : {Case{"500000", 64, 1, "the columns in view at full resolution", "at 1/2 resolution"},
                        Case{"200000", 32, 2, "the columns in view at 1/2 resolution", "at 1/4 resolution"}}) {
    SCOPED_TRACE(c.limit);
    std::string windowLegend, gridLegend;
    const auto windowed = draw(c.limit, true, c.uploadedNx, c.windowFactor, &windowLegend);
    const auto uploaded = draw(c.limit, false, c.uploadedNx, c.windowFactor, &gridLegend);
    ASSERT_TRUE(windowed && uploaded);
    EXPECT_TRUE(globe::writePng(dir + "/reduced_window_" + c.limit + ".png", *windowed));
    const double window = meanFrameDifference(*windowed, *whole), grid = meanFrameDifference(*uploaded, *whole);
    std::cout << "reduced grid under " << c.limit
              << " bytes, against the whole grid without a limit: the window in view " << window
              << " of 255, the grid as uploaded " << grid << "\n";
    if (c.windowFactor == 1) {
      EXPECT_LT(window, 0.05);  // the same points marched from another origin and row tables
      EXPECT_GT(grid, 10.0 * window);
    } else {
      EXPECT_LT(window, 0.7 * grid);  // every 2nd point against every 4th
    }
    EXPECT_GT(grid, 0.1);
    EXPECT_NE(windowLegend.find(c.windowNote), std::string::npos) << windowLegend;
    EXPECT_NE(gridLegend.find(c.gridNote), std::string::npos) << gridLegend;
  }
}

// Windows of reduced grids (global across the seam, regional): every row keeps its own points
// from the one at or west of the window's west edge to the one at or east of its east edge, each
// the grid's point (position, value, height), and a sample anywhere between the edges and rows
// equals the grid's (the same neighbours: 1e-6 of values up to 60 covers the longitudes' rounding
// after their +360 shift across the seam).
TEST(GridVolumeWindow, AReducedGridsWindowHoldsItsPointsAndSamplesAsTheGrid) {
  struct Case {
    const char* name;
    volume::GridVolume grid;
    volume::GridWindow window;
  };
  const std::vector<Case> cases = {
      {"global across the seam", reducedBlobGrid(72, 60.0, 0.0, 10.0), {270, 40, 40, 16}},
      {"global, short rows near the pole", reducedBlobGrid(72, 80.0, 100.0, 10.0), {60, 30, 60, 10}},
      {"regional", regionalReducedBlobGrid(-20.0, 170.0, 20.0, -15.0, 180.0, 2.0), {30, 90, 20, 50}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const volume::GridVolume& g = c.grid;
    ASSERT_TRUE(g.reduced());
    auto part = volume::gridWindow(g, c.window);
    ASSERT_TRUE(part) << part.error();
    ASSERT_TRUE(part->reduced());
    EXPECT_FALSE(part->wrapsLongitude);
    ASSERT_EQ(part->ny, c.window.rowCount);
    const double west = g.lonDeg[c.window.firstColumn];
    const double east = west + static_cast<double>(c.window.columnCount - 1) * g.reducedSpacingDeg();
    std::size_t points = 0;
    for (std::size_t r = 0; r < part->ny; ++r) {
      const std::size_t j = c.window.firstRow + r;
      EXPECT_EQ(part->latDeg[r], g.latDeg[j]);
      const std::size_t n = part->rowLengthPoints[r];
      EXPECT_LE(part->rowFirstLonDeg[r], west + 1e-9) << "row " << r;
      EXPECT_GE(part->lonDegAt(r, n - 1), east - 1e-9) << "row " << r;
      EXPECT_GT(part->rowFirstLonDeg[r], west - part->rowSpacingDeg[r] - 1e-9) << "row " << r;
      for (std::size_t q = 0; q < n; ++q, ++points) {
        // The grid's point at that longitude (modulo 360).
        const double lon = part->lonDegAt(r, q);
        const double x = std::remainder(lon - g.rowFirstLonDeg[j], 360.0) / g.rowSpacingDeg[j];
        const double m = static_cast<double>(g.rowLengthPoints[j]);
        const std::size_t i =
            static_cast<std::size_t>(std::llround(std::fmod(std::fmod(x, m) + m, m))) % g.rowLengthPoints[j];
        EXPECT_NEAR(std::remainder(g.lonDegAt(j, i) - lon, 360.0), 0.0, 1e-9);
        for (std::size_t k = 0; k < g.nz; ++k) {
          EXPECT_EQ(part->value(k, r, q), g.value(k, j, i));
          EXPECT_EQ(part->heightMeters(k, r, q), g.heightMeters(k, j, i));
        }
      }
    }
    EXPECT_GT(points, 2 * c.window.rowCount);
    const volume::GridSampler whole(g), windowed(*part);
    const double south = g.latDeg[c.window.firstRow], north = g.latDeg[c.window.firstRow + c.window.rowCount - 1];
    int echoes = 0;
    for (int a = 0; a <= 12; ++a)
      for (int b = 0; b <= 12; ++b)
        for (double h : {1500.0, 5200.0}) {
          const double lat = south + (north - south) * a / 12.0, lon = west + (east - west) * b / 12.0;
          const auto s0 = whole.sampleGeodetic(lat, lon, h, volume::Interpolation::Linear);
          const auto s1 = windowed.sampleGeodetic(lat, lon, h, volume::Interpolation::Linear);
          ASSERT_EQ(s0.state, s1.state) << lat << " " << lon;
          if (s0.state != volume::VolumeSample::State::Echo) continue;
          EXPECT_NEAR(s0.value, s1.value, 1e-6) << lat << " " << lon << " " << h;
          echoes += s0.value > 1.0 ? 1 : 0;
        }
    EXPECT_GT(echoes, 5) << "the windows should hold some of the blob";
    // With a stride of 2 (a window to be drawn at 1/2), every 2nd point of each row still spans
    // the window: the rows are lengthened to an even number of spacings.
    auto strided = volume::gridWindow(g, c.window, 2);
    ASSERT_TRUE(strided) << strided.error();
    const volume::GridVolume half = volume::decimateGrid(*strided, 2);
    for (std::size_t r = 0; r < half.ny; ++r) {
      EXPECT_LE(half.rowFirstLonDeg[r], west + 1e-9) << "row " << r;
      EXPECT_GE(half.lonDegAt(r, half.rowLengthPoints[r] - 1), east - 1e-9) << "row " << r;
    }
  }
  // The whole circle of a wrapping reduced grid as a window: the rows wrap as the grid's do.
  const volume::GridVolume g = reducedBlobGrid(36, 60.0, 0.0, 10.0);
  auto all = volume::gridWindow(g, volume::GridWindow{0, g.nx, 5, 10});
  ASSERT_TRUE(all) << all.error();
  EXPECT_TRUE(all->wrapsLongitude);
  EXPECT_EQ(all->rowLengthPoints[0], g.rowLengthPoints[5]);
}

TEST(GridVolumeWindow, WindowsAcrossTheSeamKeepThePointsAndIncreasingLongitudes) {
  volume::SyntheticGlobalGridOptions go;
  go.nx = 36;  // 10 deg
  go.ny = 19;
  const std::string path = testutil::testOutputDir() + "/window_seam.nc";
  ASSERT_TRUE(volume::writeSyntheticGlobalGrid(path, go));
  volume::GridReadOptions read;
  read.variable = "dbz";
  auto g = volume::readGridVolume(path, read);
  ASSERT_TRUE(g) << g.error();
  ASSERT_TRUE(g->wrapsLongitude);
  const volume::GridWindow w{34, 5, 3, 6};  // columns 34, 35, 0, 1, 2; rows 3..8
  auto part = volume::gridWindow(*g, w);
  ASSERT_TRUE(part) << part.error();
  // The file's row of the window's first row (row 3), whichever way the file's rows run.
  for (int step : {1, -1}) {
    volume::GridVolume rows = *g;
    rows.fileFirstRow = step > 0 ? 0 : 18;  // north-to-south: output row j is file row 18 - j
    rows.fileRowStep = step;
    auto rowsPart = volume::gridWindow(rows, w);
    ASSERT_TRUE(rowsPart) << rowsPart.error();
    EXPECT_EQ(rowsPart->fileFirstRow, step > 0 ? 3u : 15u);
  }
  EXPECT_EQ(part->nx, 5u);
  EXPECT_EQ(part->ny, 6u);
  EXPECT_EQ(part->nz, g->nz);
  EXPECT_FALSE(part->wrapsLongitude);
  for (std::size_t i = 1; i < part->nx; ++i) EXPECT_NEAR(part->lonDeg[i] - part->lonDeg[i - 1], 10.0, 1e-9);
  for (std::size_t k = 0; k < g->nz; ++k)
    for (std::size_t j = 0; j < 6; ++j)
      for (std::size_t i = 0; i < 5; ++i) {
        const std::size_t gi = (34 + i) % 36;
        EXPECT_EQ(part->latDegAt(j, i), g->latDegAt(3 + j, gi));
        const float a = part->value(k, j, i), b = g->value(k, 3 + j, gi);
        EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b)));
        EXPECT_EQ(part->heightMeters(k, j, i), g->heightMeters(k, 3 + j, gi));
      }
  // The whole grid as a window wraps; windows outside the grid are errors that say so.
  auto all = volume::gridWindow(*g, volume::GridWindow{0, 36, 0, 19});
  ASSERT_TRUE(all);
  EXPECT_TRUE(all->wrapsLongitude);
  auto outside = volume::gridWindow(*g, volume::GridWindow{0, 4, 17, 4});
  ASSERT_FALSE(outside);
  EXPECT_NE(outside.error().find("not inside the 36 x 19 grid"), std::string::npos) << outside.error();
}
