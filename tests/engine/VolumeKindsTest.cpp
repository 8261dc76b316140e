// One marcher for every volume kind: the analytic shell (a second kind) through the GPU and the
// CPU reference against its closed form, and overlapping volumes marched together (two radars
// 150 km apart) against the reference and against each radar alone where they do not overlap.
#include "GLTestUtil.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/ShellVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/AnalyticVolume.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <tuple>

namespace {

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;

// A synthetic radar (10 PPI sweeps 0.5..9.5 deg, 360 rays, 400 gates of 250 m from 2125 m, to
// ~102 km) with a Gaussian storm at (range, azimuth), centred at 3 deg elevation.
volume::PolarVolume syntheticRadarAt(double latDeg, double lonDeg, double stormRangeMeters, double stormAzimuthDeg) {
  testutil::SyntheticPolarGeometry g;
  g.latDeg = latDeg;
  g.lonDeg = lonDeg;
  g.antennaHeightMeters = 1000.0;
  return testutil::polarOf(testutil::syntheticRadarVolume(g, [&](double r, double az, double el) {
    double dAz = std::abs(az - stormAzimuthDeg);
    dAz = std::min(dAz, 360.0 - dAz);
    const double x = 60.0 * std::exp(-std::pow((r - stormRangeMeters) / 20e3, 2) - std::pow(dAz / 15.0, 2) -
                                     std::pow((el - 3.0) / 4.0, 2));
    return x < 5.0 ? volume::kNoEcho : static_cast<float>(x);
  }));
}

// The radars' test view: 150 km south of 35 N 98 W, 25 km up, looking north 6 deg down.
Camera fromSouthOfTheRadar(int widthPx, int heightPx) {
  const globe::GeodesicPoint eye = globe::geodesicDirect(35.0, -98.0, 180.0, 150e3);
  return Camera(CameraPose{eye.latDeg, eye.lonDeg, 25e3, 0.0, -6.0, 0.0}, 40.0, widthPx, heightPx);
}

}  // namespace

// The analytic shell: the reference against the closed form, the GPU against the reference.
TEST(VolumeKinds, AnalyticShellMatchesItsClosedFormOnGpuAndReference) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  volume::UniformShell shell;
  shell.centre = {40.0, 10.0, 12000.0};
  shell.innerRadiusMeters = 8000.0;
  shell.outerRadiusMeters = 20000.0;
  shell.value = 40.0;
  const volume::UniformShellSampler sampler(shell);
  const engine::ShellVolumeGL gl(shell);
  // 90 km south of the centre, level with it, looking north.
  const globe::GeodesicPoint from = globe::geodesicDirect(40.0, 10.0, 180.0, 90e3);
  const Camera camera(CameraPose{from.latDeg, from.lonDeg, 12000.0, 0.0, 0.0, 0.0}, 30.0, 64, 48);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 50.0;
  options.render.earlyTerminationAlpha = 2.0;  // never: the closed form has no termination
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  const volume::VolumeImage ref = volume::renderReference({{&sampler, options.render}}, rc, false, 2);
  // Per pixel: the sampled path differs from the exact chord by at most one step at each of the
  // (up to four) sphere crossings, so alpha differs by at most 1 - exp(-k 4 step) <= 4 k step,
  // k = the shell's extinction (40 dBZ: 0.48 per km -> 6.5e-4 / m; 4 k step = 0.13).
  const double k = options.render.transfer.extinctionPerMeter(options.render.transfer.classify(shell.value).a);
  double maxAlphaError = 0.0, sumAlphaError = 0.0;
  int inside = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const glm::dvec3 dir = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      const double length = sampler.pathLengthInside(rc.eyeEcef, dir, 0.0, 1e30);
      const glm::dvec4 exact = volume::uniformShellDvrClosedForm(options.render.transfer, shell.value, length);
      const double e = std::abs(ref.at(x, y).a - exact.a);
      maxAlphaError = std::max(maxAlphaError, e);
      sumAlphaError += e;
      inside += length > 0.0;
    }
  std::cout << "shell: reference vs closed form: max |alpha| " << maxAlphaError << ", mean "
            << sumAlphaError / (64 * 48) << " over " << inside << " pixels inside\n";
  ASSERT_GT(inside, 500) << "the shell must fill a good part of the view";
  EXPECT_LE(maxAlphaError, 4.0 * k * options.render.stepMeters);
  // The mean error is far below the worst case (the sampling error averages out): a tenth of it.
  EXPECT_LE(sumAlphaError / (64 * 48), 0.4 * k * options.render.stepMeters);
  const volume::VolumeImage gpu = testutil::renderVolumesGpu(**renderer, camera, {{&gl, options}});
  const volume::ImageError e = volume::compareImages(gpu, ref);
  std::cout << "shell: GPU vs reference: mean " << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb << " dB\n";
  // Same samples at the same t_i; float32 positions move a sample across a sphere only where the
  // sphere is within millimetres of it: a few pixels by one sample's opacity (~8 of 255).
  EXPECT_LT(e.meanAbs, 0.5);
  EXPECT_GT(e.psnrDb, 35.0);
}

// Two radars 150 km apart with storms that overlap half way: one march of both against the
// reference of both; away from the overlap each against itself alone.
TEST(VolumeKinds, OverlappingRadarsAreIntegratedTogether) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const double latDeg = 35.0, lonA = -98.0;
  const globe::GeodesicPoint b = globe::geodesicDirect(latDeg, lonA, 90.0, 150e3);
  // A's storm 75 km east (half way), B's 75 km west: the same place.
  const volume::PolarVolume a = syntheticRadarAt(latDeg, lonA, 75e3, 90.0);
  const volume::PolarVolume bv = syntheticRadarAt(b.latDeg, b.lonDeg, 75e3, 270.0);
  auto glA = engine::RadarVolumeGL::create(a);
  auto glB = engine::RadarVolumeGL::create(bv);
  ASSERT_TRUE(glA && glB);
  const volume::PolarSampler sa(a), sb(bv);
  // Looking north at the pair from 200 km south of the midpoint, 60 km up.
  const globe::GeodesicPoint mid = globe::geodesicDirect(latDeg, lonA, 90.0, 75e3);
  const globe::GeodesicPoint eye = globe::geodesicDirect(mid.latDeg, mid.lonDeg, 180.0, 200e3);
  const Camera camera(CameraPose{eye.latDeg, eye.lonDeg, 6e4, 0.0, -15.0, 0.0}, 50.0, 96, 48);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  options.skipEmptySpace = false;
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
    options.render.mode = mode;
    const volume::VolumeImage ref =
        volume::renderReference({{&sa, options.render}, {&sb, options.render}}, rc, false, 2);
    const volume::VolumeImage gpu =
        testutil::renderVolumesGpu(**renderer, camera, {{glA->get(), options}, {glB->get(), options}});
    const volume::ImageError e = volume::compareImages(gpu, ref);
    std::cout << "two radars, mode " << static_cast<int>(mode) << ": GPU vs reference mean " << e.meanAbs << " max "
              << e.maxAbs << " PSNR " << e.psnrDb << " dB\n";
    // As for one radar (RadarMarch.GpuMatchesTheReferenceInEveryMode): mean below one 8-bit
    // step, 30 dB.
    EXPECT_LT(e.meanAbs, 1.0);
    EXPECT_GT(e.psnrDb, 30.0);
    // Skipping (each volume's own grid) does not change the picture.
    engine::VolumeRenderOptions skipping = options;
    skipping.skipEmptySpace = true;
    const volume::VolumeImage gpuSkip =
        testutil::renderVolumesGpu(**renderer, camera, {{glA->get(), skipping}, {glB->get(), skipping}});
    EXPECT_LE(volume::compareImages(gpuSkip, gpu).maxAbs, 1.0) << "skipping changed the picture";
    // Where a ray crosses only one radar's clip sphere, the pair's picture is that radar's alone.
    const volume::VolumeImage onlyA = testutil::renderVolumesGpu(**renderer, camera, {{glA->get(), options}});
    const volume::VolumeImage onlyB = testutil::renderVolumesGpu(**renderer, camera, {{glB->get(), options}});
    int single = 0, overlap = 0, drawnInOverlap = 0;
    double maxDiff = 0.0;
    for (int y = 0; y < camera.heightPx(); ++y)
      for (int x = 0; x < camera.widthPx(); ++x) {
        const glm::dvec3 dir = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
        const bool inA = !sa.rayInterval(rc.eyeEcef, dir).empty(), inB = !sb.rayInterval(rc.eyeEcef, dir).empty();
        if (inA && inB) {
          ++overlap;
          drawnInOverlap += gpu.at(x, y).a > 0.05;
          continue;
        }
        if (!inA && !inB) continue;
        ++single;
        const glm::dvec4 alone = inA ? onlyA.at(x, y) : onlyB.at(x, y);
        for (int c = 0; c < 4; ++c) maxDiff = std::max(maxDiff, std::abs(gpu.at(x, y)[c] - alone[c]));
      }
    ASSERT_GT(single, 100);
    ASSERT_GT(overlap, 100);
    // The storm where the two volumes overlap must be drawn (DVR: ~100 pixels; the iso surface at
    // 40 dBZ covers only its core: ~12).
    EXPECT_GT(drawnInOverlap, 8) << "the overlapping storm must be drawn";
    // Half-float image: one unit of its 11-bit mantissa at 1.0.
    EXPECT_LE(maxDiff, 1e-3) << "mode " << static_cast<int>(mode);
  }
  // Order does not matter: the reference of (B, A) equals that of (A, B) to rounding.
  options.render.mode = volume::VolumeRenderMode::Dvr;
  const volume::VolumeImage ab = volume::renderReference({{&sa, options.render}, {&sb, options.render}}, rc, false, 2);
  const volume::VolumeImage ba = volume::renderReference({{&sb, options.render}, {&sa, options.render}}, rc, false, 2);
  EXPECT_LE(volume::compareImages(ab, ba).maxAbs, 1.0);
}

// `render --reference`: the whole frame (globe, site markers and their labels, other markers) as
// a GPU frame, with only the volumes drawn by the CPU reference in the marcher's place, occluded
// by the same depth. Outside the volumes the two frames are the same pixels; inside they differ
// only by the marcher's error.
TEST(VolumeKinds, ReferenceFrameDiffersFromTheGpuFrameOnlyInTheVolumes) {
  testutil::glContext();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader) << loader.error();
  auto scene = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(scene) << scene.error();
  const double latDeg = 35.0, lonA = -98.0;
  const globe::GeodesicPoint b = globe::geodesicDirect(latDeg, lonA, 90.0, 150e3);
  const globe::GeodesicPoint mid = globe::geodesicDirect(latDeg, lonA, 90.0, 75e3);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  for (const auto& [lat, lon, az] : {std::tuple{latDeg, lonA, 90.0}, std::tuple{b.latDeg, b.lonDeg, 270.0}}) {
    auto gl = engine::RadarVolumeGL::create(syntheticRadarAt(lat, lon, 75e3, az));
    ASSERT_TRUE(gl) << gl.error();
    (*scene)->addSource(engine::RadarSourceGL::fromVolume(
        std::move(*gl), options, engine::Marker{lat, lon, 1000.0, glm::vec3(1.0f), 12.0f, "SITE"}));
  }
  // A station between the radars, inside the storm's column: drawn over the volumes in both.
  const std::vector<engine::Marker> markers = {
      engine::Marker{mid.latDeg, mid.lonDeg, 0.0, glm::vec3(1, 0, 1), 10.0f, "STN"}};
  // From 100 km south of the pair, 15 km up, looking north just below the horizon: the storms
  // stand on the globe, whose depth hides their lower parts behind the curvature.
  const globe::GeodesicPoint eye = globe::geodesicDirect(mid.latDeg, mid.lonDeg, 180.0, 100e3);
  const Camera camera(CameraPose{eye.latDeg, eye.lonDeg, 15e3, 0.0, -5.0, 0.0}, 50.0, 160, 80);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto gpuFrame = (*scene)->renderToImage(camera, markers, **fb);
  ASSERT_TRUE(gpuFrame) << gpuFrame.error();
  const std::vector<glm::vec4> gpuVolume = (*scene)->volumeRenderer().readVolumeImage();
  (*scene)->setReferenceVolumes(2);
  engine::SceneFrameStats stats;
  auto refFrame = (*scene)->renderToImage(camera, markers, **fb, 64, &stats);
  ASSERT_TRUE(refFrame) << refFrame.error();
  const volume::VolumeImage& refVolume = (*scene)->volumeRenderer().lastReferenceImage();
  // For a look: the two frames side by side in the test output directory.
  EXPECT_TRUE(globe::writePng(testutil::testOutputDir() + "/reference_frame_gpu.png", *gpuFrame));
  EXPECT_TRUE(globe::writePng(testutil::testOutputDir() + "/reference_frame_reference.png", *refFrame));
  ASSERT_EQ(refVolume.widthPx, camera.widthPx());
  ASSERT_EQ(gpuVolume.size(), refVolume.rgbaPremultiplied.size());
  EXPECT_GT(stats.referenceSeconds, 0.0);
  int outside = 0, inside = 0, outsideDiffering = 0;
  double sumDiff = 0.0;
  for (int y = 0; y < camera.heightPx(); ++y)
    for (int x = 0; x < camera.widthPx(); ++x) {
      const glm::ivec4 g(gpuFrame->at(x, y)), r(refFrame->at(x, y));
      const glm::ivec4 d = glm::abs(g - r);
      sumDiff += d.r + d.g + d.b;
      const bool volumeHere = gpuVolume[static_cast<std::size_t>(y * camera.widthPx() + x)].a > 0.0f ||
                              refVolume.at(x, y).a > 0.0;
      if (volumeHere) {
        ++inside;
      } else {
        ++outside;
        outsideDiffering += d != glm::ivec4(0);
      }
    }
  std::cout << "reference frame: " << inside << " volume pixels, " << outside << " others, reference "
            << stats.referenceSeconds << " s, mean |GPU - reference| "
            << sumDiff / (3.0 * camera.widthPx() * camera.heightPx()) << " (8-bit)\n";
  ASSERT_GT(inside, 500) << "the storms must be in view";
  ASSERT_GT(outside, 2000);
  // Globe, markers, labels: the same pixels (the old --reference dropped the site markers and
  // laid the volumes over the labels).
  EXPECT_EQ(outsideDiffering, 0);
  // The volumes: the marcher's error, as in OverlappingRadarsAreIntegratedTogether (mean below
  // one 8-bit step; that test measures 0.0004 of 1 in DVR).
  EXPECT_LT(sumDiff / (3.0 * camera.widthPx() * camera.heightPx()), 1.0);
  // Markers are drawn after the volumes in both frames: the station's pixel is the same.
  const auto px =
      volume::projectToPixel(engine::referenceCameraFor(camera), globe::geodeticToEcef({mid.latDeg, mid.lonDeg, 0.0}));
  ASSERT_TRUE(px);
  const int sx = static_cast<int>(px->x), sy = static_cast<int>(px->y);
  EXPECT_EQ(glm::ivec4(gpuFrame->at(sx, sy)), glm::ivec4(refFrame->at(sx, sy)));
  EXPECT_EQ(glm::ivec4(refFrame->at(sx, sy)), glm::ivec4(255, 0, 255, 255)) << "the station marker must be drawn";
}

// Uniforms are set once per change: a second draw of the same frame issues no glUniform call; a
// camera move sets the camera and eye uniforms only; a beam change sets that volume's sampler
// uniforms again; and the pictures are those of a fresh renderer.
TEST(VolumeKinds, UniformsAreSetOncePerChange) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const globe::GeodesicPoint b = globe::geodesicDirect(35.0, -98.0, 90.0, 150e3);
  auto glA = engine::RadarVolumeGL::create(syntheticRadarAt(35.0, -98.0, 75e3, 90.0));
  auto glB = engine::RadarVolumeGL::create(syntheticRadarAt(b.latDeg, b.lonDeg, 75e3, 270.0));
  ASSERT_TRUE(glA && glB);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  const std::vector<engine::VolumeLayerGL> layers = {{glA->get(), options}, {glB->get(), options}};
  const Camera camera(CameraPose{34.0, -97.2, 6e4, 0.0, -15.0, 0.0}, 50.0, 64, 32);
  const Camera moved(CameraPose{34.0, -97.1, 6e4, 0.0, -15.0, 0.0}, 50.0, 64, 32);
  const volume::VolumeImage first = testutil::renderVolumesGpu(**renderer, camera, layers);
  const std::uint64_t afterFirst = (*renderer)->uniformUploads();
  EXPECT_GT(afterFirst, 0u);
  const volume::VolumeImage again = testutil::renderVolumesGpu(**renderer, camera, layers);
  EXPECT_EQ((*renderer)->uniformUploads(), afterFirst) << "an unchanged frame must set no uniform";
  EXPECT_EQ(volume::compareImages(first, again).maxAbs, 0.0);
  // A camera move: the 7 shared uniforms and each volume's 12 generic ones (eye), no sampler's.
  testutil::renderVolumesGpu(**renderer, moved, layers);
  EXPECT_EQ((*renderer)->uniformUploads(), afterFirst + 7 + 2 * 12);
  const std::uint64_t afterMove = (*renderer)->uniformUploads();
  // A beam change compiles another variant (BEAM is a define): a program of its own, set in full.
  (*glA)->setBeamApproximation(engine::BeamApproximation::StraightLine);
  testutil::renderVolumesGpu(**renderer, moved, layers);
  EXPECT_GT((*renderer)->uniformUploads(), afterMove);
  (*glA)->setBeamApproximation(engine::BeamApproximation::EffectiveEarthLocalSphere);
  // Back to the first program and camera: A's version changed, so its sampler uniforms are set
  // again (1), the camera and both volumes' eyes too; the picture is the first one.
  const std::uint64_t beforeBack = (*renderer)->uniformUploads();
  const volume::VolumeImage back = testutil::renderVolumesGpu(**renderer, camera, layers);
  EXPECT_EQ((*renderer)->uniformUploads(), beforeBack + 7 + 2 * 12 + 1);
  EXPECT_EQ(volume::compareImages(first, back).maxAbs, 0.0);
  // A fresh renderer draws the same picture.
  auto fresh = engine::VolumeRendererGL::create();
  ASSERT_TRUE(fresh);
  EXPECT_EQ(volume::compareImages(first, testutil::renderVolumesGpu(**fresh, camera, layers)).maxAbs, 0.0);
}

// Radars whose clip spheres are apart are drawn in separate passes, back to front: seen so that
// rays cross both (one behind the other), the picture equals the reference of both together, in
// either layer order.
TEST(VolumeKinds, ApartVolumesAreDrawnBackToFront) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  // Near: storm 60 km north of (35 N, 98 W); far: a radar 300 km further north, storm 60 km
  // south of it. Clip spheres ~102 km: 300 km apart, disjoint.
  const globe::GeodesicPoint farSite = globe::geodesicDirect(35.0, -98.0, 0.0, 300e3);
  const volume::PolarVolume nearV = syntheticRadarAt(35.0, -98.0, 60e3, 0.0);
  const volume::PolarVolume farV = syntheticRadarAt(farSite.latDeg, farSite.lonDeg, 60e3, 180.0);
  auto glNear = engine::RadarVolumeGL::create(nearV);
  auto glFar = engine::RadarVolumeGL::create(farV);
  ASSERT_TRUE(glNear && glFar);
  const volume::PolarSampler sNear(nearV), sFar(farV);
  // From 150 km south of the near radar, 25 km up, looking north along the pair.
  const Camera camera = fromSouthOfTheRadar(96, 48);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  const volume::VolumeImage ref =
      volume::renderReference({{&sNear, options.render}, {&sFar, options.render}}, rc, false, 2);
  int both = 0;
  for (int y = 0; y < camera.heightPx(); ++y)
    for (int x = 0; x < camera.widthPx(); ++x) {
      const glm::dvec3 dir = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      both += !sNear.rayInterval(rc.eyeEcef, dir).empty() && !sFar.rayInterval(rc.eyeEcef, dir).empty();
    }
  ASSERT_GT(both, 500) << "rays must cross both volumes";
  for (bool farFirst : {false, true}) {
    const std::vector<engine::VolumeLayerGL> layers =
        farFirst ? std::vector<engine::VolumeLayerGL>{{glFar->get(), options}, {glNear->get(), options}}
                 : std::vector<engine::VolumeLayerGL>{{glNear->get(), options}, {glFar->get(), options}};
    auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    ASSERT_TRUE(fb);
    (*fb)->bind();
    glClearDepth(0.0);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    (*renderer)->draw(camera, layers, **fb);
    // The frame (8-bit, both passes composited) against the reference over black.
    const globe::ImageRGBA8 frame = (*fb)->readColor();
    double sum = 0.0, maxDiff = 0.0;
    for (int y = 0; y < camera.heightPx(); ++y)
      for (int x = 0; x < camera.widthPx(); ++x)
        for (int c = 0; c < 3; ++c) {
          const double d = std::abs(frame.at(x, y)[c] / 255.0 - std::clamp(ref.at(x, y)[c], 0.0, 1.0));
          sum += d;
          maxDiff = std::max(maxDiff, d);
        }
    const double mean = sum / (3.0 * camera.widthPx() * camera.heightPx());
    std::cout << "apart radars, far first " << farFirst << ": mean |GPU - reference| " << mean * 255.0
              << " (8-bit), max " << maxDiff * 255.0 << "\n";
    // As for overlapping radars: mean below one 8-bit step. Composited the wrong way round the
    // far storm would cover the near one where they overlap on screen.
    EXPECT_LT(mean * 255.0, 1.0);
  }
}

// Progressive refinement (the viewer at rest): tile by tile over several calls, the finished
// frame is draw()'s pixel for pixel, with two passes (radars apart) and one (a radar alone); the
// frames before show the coarse preview where tiles are not marched yet; a change of the camera
// starts again.
TEST(VolumeKinds, ProgressiveRefinementEndsInTheOneShotFrame) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  const globe::GeodesicPoint farSite = globe::geodesicDirect(35.0, -98.0, 0.0, 300e3);
  auto glNear = engine::RadarVolumeGL::create(syntheticRadarAt(35.0, -98.0, 60e3, 0.0));
  auto glFar = engine::RadarVolumeGL::create(syntheticRadarAt(farSite.latDeg, farSite.lonDeg, 60e3, 180.0));
  ASSERT_TRUE(glNear && glFar);
  const Camera camera = fromSouthOfTheRadar(300, 150);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  auto frameOf = [&](const std::vector<engine::VolumeLayerGL>& layers, bool progressive, int* calls,
                     std::vector<globe::ImageRGBA8>* partial) {
    auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    EXPECT_TRUE(fb);
    for (int n = 1;; ++n) {
      (*fb)->bind();
      glClearDepth(0.0);
      glClearColor(0, 0, 0, 0);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      if (!progressive) {
        (*renderer)->draw(camera, layers, **fb);
        return (*fb)->readColor();
      }
      // A budget of 0: one tile per call.
      const bool done = (*renderer)->drawProgressive(camera, layers, **fb, 0.0);
      if (done || n > 1000) {
        *calls = n;
        return (*fb)->readColor();
      }
      if (partial) partial->push_back((*fb)->readColor());
    }
  };
  auto differing = [](const globe::ImageRGBA8& a, const globe::ImageRGBA8& b) {
    int n = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) n += a.at(x, y) != b.at(x, y);
    return n;
  };
  const std::vector<engine::VolumeLayerGL> two{{glNear->get(), options}, {glFar->get(), options}};
  const std::vector<engine::VolumeLayerGL> one{{glNear->get(), options}};
  for (const auto* layers : {&two, &one}) {
    int calls = 0;
    std::vector<globe::ImageRGBA8> partial;
    const globe::ImageRGBA8 oneShot = frameOf(*layers, false, nullptr, nullptr);
    (*renderer)->restartProgressive();
    const globe::ImageRGBA8 refined = frameOf(*layers, true, &calls, &partial);
    const auto [marched, tiles] = (*renderer)->progressiveTiles();
    std::cout << layers->size() << " layer(s): " << tiles << " tiles in " << calls << " calls\n";
    EXPECT_EQ(marched, tiles);
    EXPECT_EQ(static_cast<std::size_t>(calls), tiles);  // one tile per call at a budget of 0
    EXPECT_GT(tiles, 8u);
    EXPECT_EQ(differing(refined, oneShot), 0) << "the refined frame differs from the one-shot frame";
    // Before the end the preview shows (coarser, so different), and the picture has volume in it
    // (the storms cover 430-490 of its 45,000 pixels).
    ASSERT_FALSE(partial.empty());
    EXPECT_GT(differing(partial.front(), oneShot), 100);
    EXPECT_GT(differing(oneShot, globe::ImageRGBA8::filled(oneShot.width, oneShot.height, {0, 0, 0, 0})), 300);
  }
  // After a frame drawn at the preview scale (the viewer's last moving frame) the refinement takes
  // that image as its preview instead of marching one, and still ends in the one-shot frame.
  {
    engine::VolumeRenderOptions quarter = options;
    quarter.imageScale = engine::VolumeRendererGL::kPreviewScale;
    const globe::ImageRGBA8 oneShot = frameOf(one, false, nullptr, nullptr);
    auto fbq = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    ASSERT_TRUE(fbq);
    (*fbq)->bind();
    glClearDepth(0.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    (*renderer)->draw(camera, {{glNear->get(), quarter}}, **fbq);
    const std::size_t reused = (*renderer)->previewsReused();
    int calls = 0;
    (*renderer)->restartProgressive();
    std::vector<globe::ImageRGBA8> partial;
    const globe::ImageRGBA8 refined = frameOf(one, true, &calls, &partial);
    EXPECT_EQ((*renderer)->previewsReused(), reused + 1);
    EXPECT_EQ(differing(refined, oneShot), 0);
  }
  // The same camera again: nothing left to march (one call, complete); another camera: again.
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  EXPECT_TRUE((*renderer)->drawProgressive(camera, one, **fb, 0.0));
  CameraPose raised = camera.pose();
  raised.heightMeters = 26e3;
  const Camera moved(raised, 40.0, 300, 150);
  EXPECT_FALSE((*renderer)->drawProgressive(moved, one, **fb, 0.0));
}

// Adaptive refinement (VolumeRenderOptions::refineThreshold): marched at a quarter of the
// resolution, then again at full resolution where the small image varies. At a threshold of 0
// only pixels between four identical small-image pixels are interpolated, so the frame is the
// full-resolution one but for features narrower than the small image's pixels; at 255 every
// pixel is interpolated, which is the quarter-scale frame; progressive refinement of an adaptive
// layer ends in draw()'s frame, pixel for pixel.
TEST(VolumeKinds, AdaptiveRefinementMarchesWhereTheSmallImageVaries) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  auto gl = engine::RadarVolumeGL::create(syntheticRadarAt(35.0, -98.0, 60e3, 0.0));
  ASSERT_TRUE(gl);
  const Camera camera = fromSouthOfTheRadar(400, 200);
  engine::VolumeRenderOptions full;
  full.render.transfer = volume::defaultReflectivityTransfer();
  full.render.stepMeters = 500.0;
  auto frameOf = [&](const engine::VolumeRenderOptions& o, bool progressive) {
    auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    EXPECT_TRUE(fb);
    (*renderer)->restartProgressive();
    for (int n = 0; n < 10000; ++n) {
      (*fb)->bind();
      glClearDepth(0.0);
      glClearColor(0, 0, 0, 0);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      if (!progressive) {
        (*renderer)->draw(camera, {{gl->get(), o}}, **fb);
        break;
      }
      if ((*renderer)->drawProgressive(camera, {{gl->get(), o}}, **fb, 0.0)) break;
    }
    return (*fb)->readColor();
  };
  struct Diff {
    int pixels = 0;
    double meanSteps = 0.0;
    int maxSteps = 0;
  };
  auto compare = [](const globe::ImageRGBA8& a, const globe::ImageRGBA8& b) {
    Diff d;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        d.pixels += a.at(x, y) != b.at(x, y);
        for (int c = 0; c < 3; ++c) {
          const int e = std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
          d.meanSteps += e;
          d.maxSteps = std::max(d.maxSteps, e);
        }
      }
    d.meanSteps /= 3.0 * a.width * a.height;
    return d;
  };
  const globe::ImageRGBA8 reference = frameOf(full, false);
  engine::VolumeRenderOptions quarter = full;
  quarter.imageScale = 0.25;
  const globe::ImageRGBA8 small = frameOf(quarter, false);
  engine::VolumeRenderOptions exact = quarter, loose = quarter, everything = quarter;
  exact.refineThreshold = 0.0;
  loose.refineThreshold = 8.0;
  everything.refineThreshold = 255.0;
  const globe::ImageRGBA8 adaptiveExact = frameOf(exact, false);
  const std::vector<glm::vec4> image = (*renderer)->readVolumeImage();
  EXPECT_EQ(image.size(), std::size_t(camera.widthPx()) * std::size_t(camera.heightPx()));  // the full-size image
  const globe::ImageRGBA8 adaptiveLoose = frameOf(loose, false);
  const globe::ImageRGBA8 adaptiveAll = frameOf(everything, false);
  const Diff dSmall = compare(small, reference), dExact = compare(adaptiveExact, reference),
             dLoose = compare(adaptiveLoose, reference), dAll = compare(adaptiveAll, small);
  std::cout << "against full resolution (8-bit steps): quarter scale mean " << dSmall.meanSteps << " max "
            << dSmall.maxSteps << " (" << dSmall.pixels << " px); adaptive 0: mean " << dExact.meanSteps << " max "
            << dExact.maxSteps << " (" << dExact.pixels << " px); adaptive 8: mean " << dLoose.meanSteps << " max "
            << dLoose.maxSteps << "; adaptive 255 against quarter scale: mean " << dAll.meanSteps << " max "
            << dAll.maxSteps << "\n";
  // The quarter-scale frame differs visibly (the storms' edges are blurred over 4 pixels).
  ASSERT_GT(dSmall.pixels, 300);
  // Threshold 0: the synthetic storms are kilometres wide, far wider than a small-image pixel
  // (about 4 pixels, ~1 km here), so every pixel the storms touch is marched again: the frame is
  // the full-resolution one.
  EXPECT_EQ(dExact.pixels, 0);
  // Threshold 8: an interpolated pixel lies between four values within 8 steps of each other; on
  // these smooth storms (Gaussian cells kilometres wide, a small-image pixel ~1 km) the field
  // between them stays within about that band, and the composite adds at most 1 step of rounding.
  EXPECT_LE(dLoose.maxSteps, 9);
  EXPECT_LT(dLoose.meanSteps, dSmall.meanSteps);
  // Threshold 255: every pixel interpolated, as the composite pass upsamples the small image
  // (the shader's bilinear weights are exact, the texture unit's have 8 bits: 1 step).
  EXPECT_LE(dAll.maxSteps, 1);
  // Progressive refinement of an adaptive layer: draw()'s frame.
  EXPECT_EQ(compare(frameOf(loose, true), adaptiveLoose).pixels, 0);
}

// A preview marched at rest fits the call's budget: the first (no cost known) at the least scale
// whatever the budget, then at the preview scale where an ample budget fits it, and at the least
// scale again where a budget of a microsecond fits nothing.
TEST(VolumeKinds, APreviewFitsTheBudgetOnceItsCostIsKnown) {
  testutil::glContext();
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  auto radar = engine::RadarVolumeGL::create(syntheticRadarAt(35.0, -98.0, 60e3, 0.0));
  ASSERT_TRUE(radar);
  const Camera camera = fromSouthOfTheRadar(320, 160);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  const auto previewAt = [&](double budgetMs) {
    (*renderer)->restartProgressive();
    (*fb)->bind();
    glClearDepth(0.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    (*renderer)->drawProgressive(camera, {{radar->get(), options}}, **fb, budgetMs);
    return (*renderer)->lastPreviewScale();
  };
  using R = engine::VolumeRendererGL;
  EXPECT_EQ(previewAt(1e6), R::kMinPreviewScale) << "no cost known yet: the least scale, whatever the budget";
  EXPECT_EQ((*renderer)->previewsMarched(), 1u);
  EXPECT_EQ(previewAt(1e6), R::kPreviewScale) << "a budget that fits it: the preview scale";
  EXPECT_EQ(previewAt(1e-3), R::kMinPreviewScale) << "a microsecond fits no preview: the least scale";
  EXPECT_EQ((*renderer)->previewsMarched(), 3u);
}

// The viewer at rest while a volume refines: frames that start from the background kept from the
// last refining frame (SceneRendererGL::setBackgroundReuse) end in the frame drawn whole, pixel for
// pixel; a camera moved or a scene changed draws the background again.
TEST(VolumeKinds, RefiningFramesFromTheKeptBackgroundEndInTheWholeFrame) {
  testutil::glContext();
  auto loader =
      engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, testutil::worldPyramidDir()}}, {});
  ASSERT_TRUE(loader) << loader.error();
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 500.0;
  // A radar over the globe with coastlines and borders, seen obliquely: the storm stands on the
  // globe, whose depth (kept with the colour) hides what is below the ground.
  const auto sceneWithRadar = [&] {
    auto scene = engine::SceneRendererGL::create(*loader);
    EXPECT_TRUE(scene) << scene.error();
    EXPECT_TRUE((*scene)->setMapContext(true));
    auto gl = engine::RadarVolumeGL::create(syntheticRadarAt(35.0, -98.0, 60e3, 0.0));
    EXPECT_TRUE(gl) << gl.error();
    (*scene)->addSource(engine::RadarSourceGL::fromVolume(
        std::move(*gl), options, engine::Marker{35.0, -98.0, 1000.0, glm::vec3(1.0f), 12.0f, "SITE"}));
    return std::move(*scene);
  };
  const globe::GeodesicPoint eye = globe::geodesicDirect(35.0, -98.0, 180.0, 120e3);
  const Camera camera(CameraPose{eye.latDeg, eye.lonDeg, 40e3, 0.0, -25.0, 0.0}, 50.0, 200, 100);
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  ASSERT_TRUE(fb);
  auto whole = sceneWithRadar();
  const auto oneShot = whole->renderToImage(camera, {}, **fb);
  ASSERT_TRUE(oneShot) << oneShot.error();

  auto refining = sceneWithRadar();
  refining->setProgressiveBudget(1e-3);  // one tile a frame
  // The first frame at rest draws its background (the imagery loaded first) and keeps it ...
  ASSERT_TRUE(refining->renderToImage(camera, {}, **fb));
  ASSERT_FALSE(refining->volumesComplete()) << "one tile a frame: the volume must take several frames";
  // ... the next ones start from it. The target is filled with other values before each, so
  // that every pixel's colour and depth must come from the kept background.
  const auto scribble = [&] {
    (*fb)->bind();
    glClearColor(1.0f, 0.0f, 1.0f, 1.0f);
    glClearDepth(0.5);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  };
  // Frames until the volume is complete (at most 1000); how many.
  const auto refineUntilComplete = [&](const Camera& c) {
    int n = 0;
    for (; n < 1000 && !refining->volumesComplete(); ++n) {
      scribble();
      refining->renderFrame(c, {}, **fb);
    }
    return n;
  };
  const auto differingPixels = [](const globe::ImageRGBA8& a, const globe::ImageRGBA8& b) {
    int n = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) n += a.at(x, y) != b.at(x, y);
    return n;
  };
  refining->setBackgroundReuse(true);
  const int frames = 1 + refineUntilComplete(camera);
  ASSERT_TRUE(refining->volumesComplete());
  std::cout << "refined in " << frames << " frames, " << refining->backgroundsReused() << " from the kept background\n";
  EXPECT_EQ(refining->backgroundsReused(), static_cast<std::size_t>(frames - 1));
  EXPECT_GE(frames, 4);
  const globe::ImageRGBA8 refined = (*fb)->readColor();
  EXPECT_TRUE(globe::writePng(testutil::testOutputDir() + "/kept_background_refined.png", refined));
  int ground = 0;
  for (int y = 0; y < refined.height; ++y)
    for (int x = 0; x < refined.width; ++x) ground += refined.at(x, y) != glm::u8vec4(0, 0, 0, 255);
  ASSERT_GT(ground, refined.width * refined.height / 2) << "the globe must fill most of the view";
  EXPECT_EQ(differingPixels(refined, *oneShot), 0) << "the refined frame must be the frame drawn whole";

  // Another camera: the background is drawn again, not taken from the one kept (renderToImage
  // waits for the imagery, then draws the frame and keeps its background) ...
  const std::size_t reused = refining->backgroundsReused();
  const Camera turned(CameraPose{eye.latDeg, eye.lonDeg, 40e3, 10.0, -25.0, 0.0}, 50.0, 200, 100);
  ASSERT_TRUE(refining->renderToImage(turned, {}, **fb));
  EXPECT_EQ(refining->backgroundsReused(), reused);
  refining->renderFrame(turned, {}, **fb);
  EXPECT_EQ(refining->backgroundsReused(), reused + 1);
  // ... and so it is when the scene changed (the map lines off), the camera kept: the refined
  // frame is then the whole frame without the lines.
  ASSERT_TRUE(refining->setMapContext(false));
  scribble();
  refining->renderFrame(turned, {}, **fb);
  EXPECT_EQ(refining->backgroundsReused(), reused + 1) << "the background kept with the lines was reused";
  // The frames after start from the background kept without them.
  refineUntilComplete(turned);
  EXPECT_GT(refining->backgroundsReused(), reused + 1);
  ASSERT_TRUE(whole->setMapContext(false));
  const auto turnedWhole = whole->renderToImage(turned, {}, **fb);
  ASSERT_TRUE(turnedWhole) << turnedWhole.error();
  ASSERT_TRUE(refining->volumesComplete());
  refining->renderFrame(turned, {}, **fb);  // complete: the same frame again
  EXPECT_EQ(differingPixels((*fb)->readColor(), *turnedWhole), 0);
}
