// The GPU ray marcher against the CPU reference (double precision, exact inverse), the
// GLSL beam-model inverse against the exact one, a point echo at its geolocated pixel, and
// cameras inside, at and above the volume.
#include "GLTestUtil.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace {

using namespace atmoglobe;
using engine::Camera;
using engine::CameraPose;

// A synthetic radar at Lubbock's coordinates: 10 PPI sweeps 0.5..9.5 deg, 360 rays,
// 400 gates of 250 m from 2125 m (to ~102 km), a smooth storm in antenna coordinates.
volume::RadarVolume syntheticRadar(float (*field)(double r, double az, double el)) {
  return testutil::syntheticRadarVolume(testutil::SyntheticPolarGeometry{}, field);
}

float storm(double r, double az, double el) {
  const double v = 62.0 * std::exp(-std::pow((r - 55e3) / 18e3, 2) - std::pow((az - 20.0) / 18.0, 2) -
                                   std::pow((el - 3.0) / 4.0, 2));
  return v < 5.0 ? volume::kNoEcho : static_cast<float>(v);
}

volume::PolarVolume polar(const volume::RadarVolume& radar) { return testutil::polarOf(radar); }

class RadarMarch : public ::testing::Test {
 protected:
  void SetUp() override {
    testutil::glContext();
    auto r = engine::VolumeRendererGL::create();
    ASSERT_TRUE(r) << r.error();
    renderer_ = std::move(*r);
  }

  /// GPU volume image for a camera (no globe: empty depth), composited over black.
  volume::VolumeImage renderGpu(const Camera& camera, const engine::VolumeGL& gl,
                                const engine::VolumeRenderOptions& options) {
    return testutil::renderVolumesGpu(*renderer_, camera, {engine::VolumeLayerGL{&gl, options}});
  }

  std::unique_ptr<engine::VolumeRendererGL> renderer_;
};

// The largest differences between the shader's coordinates and expected ones.
struct InverseErrors {
  double rangeMeters = 0.0, azimuthDeg = 0.0, elevationDeg = 0.0;
  void add(const glm::vec4& shader, const volume::AntennaCoordinates& expected) {
    rangeMeters = std::max(rangeMeters, std::abs(shader.x - expected.rangeMeters));
    const double dAz = std::abs(shader.y - expected.azimuthDeg);
    azimuthDeg = std::max(azimuthDeg, std::min(dAz, 360.0 - dAz));
    elevationDeg = std::max(elevationDeg, std::abs(shader.z - expected.elevationDeg));
  }
};

// 120 km south of the radar, 60 km up, looking north and down at the storm.
const CameraPose kObliquePose{32.6, -101.814, 6e4, 10.0, -25.0, 0.0};

}  // namespace

TEST_F(RadarMarch, GlslInverseAgreesWithTheExactInverse) {
  const volume::RadarVolume radar = syntheticRadar(storm);
  const volume::PolarVolume pv = polar(radar);
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  const Camera camera(kObliquePose, 50.0, 64, 48);
  InverseErrors errors;
  for (double t : {80e3, 120e3, 160e3}) {
    const auto coords = renderer_->debugCoordinatesAt(camera, **gl, t);
    ASSERT_EQ(coords.size(), 64u * 48u);
    for (int y = 0; y < 48; ++y) {
      for (int x = 0; x < 64; ++x) {
        const glm::dvec3 p = camera.eyeEcef() + t * camera.pixelRayDirection(x + 0.5, y + 0.5);
        const volume::AntennaCoordinates exact = volume::antennaCoordinatesExact(pv.site, pv.beam, p);
        if (exact.rangeMeters > 460e3 || exact.rangeMeters < 1e3) continue;
        errors.add(coords[static_cast<std::size_t>(y) * 64 + x], exact);
      }
    }
  }
  const double maxRange = errors.rangeMeters, maxAz = errors.azimuthDeg, maxEl = errors.elevationDeg;
  std::cout << "GLSL inverse vs exact: max |range| " << maxRange << " m, |azimuth| " << maxAz << " deg, |elevation| "
            << maxEl << " deg\n";
  RecordProperty("max_range_error_m", std::to_string(maxRange));
  RecordProperty("max_elevation_error_deg", std::to_string(maxEl));
  // Bounds from the data's resolution, not from the measurement: the approximation must be
  // well below what a gate resolves: a tenth of a 250 m gate in range, a twentieth of a
  // 1 deg beam in angle.
  EXPECT_LT(maxRange, 25.0);
  EXPECT_LT(maxAz, 0.05);
  EXPECT_LT(maxEl, 0.05);
  // The straight-line model (no refraction, no curvature) is measurably worse: at 100+ km
  // its elevation error is tenths of a degree.
  (*gl)->setBeamApproximation(engine::BeamApproximation::StraightLine);
  const auto straight = renderer_->debugCoordinatesAt(camera, **gl, 160e3);
  const glm::dvec3 p = camera.eyeEcef() + 160e3 * camera.pixelRayDirection(32.5, 24.5);
  const volume::AntennaCoordinates exact = volume::antennaCoordinatesExact(pv.site, pv.beam, p);
  EXPECT_GT(std::abs(straight[24 * 64 + 32].z - exact.elevationDeg), 10.0 * maxEl);
}

// The GLSL inverse takes the arc and the half earth angle by their Taylor series (polar_beam.glsl),
// meant to hold to 2,500 km from the antenna; a radar's gates end well inside that, but the far
// field and a network's shell ask at points hundreds of km beyond them. From 4,000 km up, straight
// down, the points 3,990 km from the eye lie 300 to 3,300 km from the antenna. Against the same
// model in double (volume::LocalSphereBeam; the local sphere itself leaves the ellipsoid's exact
// inverse by ~300 m in range out there, so the exact path would measure the model, not the
// series).
TEST_F(RadarMarch, GlslInverseHoldsFarFromTheAntenna) {
  const volume::RadarVolume radar = syntheticRadar(storm);
  const volume::PolarVolume pv = polar(radar);
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  const volume::LocalSphereBeam model = volume::localSphereBeam(pv.site, pv.beam);
  const Camera camera(CameraPose{33.654, -101.814, 4e6, 0.0, -90.0, 0.0}, 80.0, 64, 64);
  const double t = 3.99e6;
  const auto coords = renderer_->debugCoordinatesAt(camera, **gl, t);
  ASSERT_EQ(coords.size(), 64u * 64u);
  InverseErrors errors;
  double farthest = 0.0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const glm::dvec3 p = camera.eyeEcef() + t * camera.pixelRayDirection(x + 0.5, y + 0.5);
      const volume::AntennaCoordinates expected = model.antennaCoordinates(model.enuOfEcef(p));
      if (expected.rangeMeters > 2.5e6) continue;
      farthest = std::max(farthest, expected.rangeMeters);
      errors.add(coords[static_cast<std::size_t>(y) * 64 + x], expected);
    }
  }
  const double maxRange = errors.rangeMeters, maxAz = errors.azimuthDeg, maxEl = errors.elevationDeg;
  std::cout << "GLSL inverse vs the local sphere in double, to " << farthest << " m: max |range| " << maxRange
            << " m, |azimuth| " << maxAz << " deg, |elevation| " << maxEl << " deg\n";
  EXPECT_GT(farthest, 2.3e6);  // the test reaches the series' far end
  // As close by: a tenth of a 250 m gate, a twentieth of a 1 deg beam.
  EXPECT_LT(maxRange, 25.0);
  EXPECT_LT(maxAz, 0.05);
  EXPECT_LT(maxEl, 0.05);
}

// The count of samples the march takes (VolumeRendererGL::sampleCounts, the measure of samples
// per second in docs/bench-volume.md): from 20 km north of the antenna, 600 m above it, looking
// north 1-3 deg up, every ray stays inside the band of straight elevations that holds the beams,
// so the march's interval is the clip sphere's from the eye: without skipping or early
// termination, the samples t_i = (i + 0.5) step with t_i up to the sphere's exit, computed here
// in double. Skipping then takes fewer samples, and the picture is the same (GpuMatchesTheReference...).
TEST_F(RadarMarch, SampleCountsAreTheSamplesOfTheMarch) {
  const volume::RadarVolume radar = syntheticRadar(storm);
  const volume::PolarVolume pv = polar(radar);
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  const double siteHeight = pv.site.antennaHeightEllipsoidMeters;
  const Camera camera(CameraPose{pv.site.latDeg + 0.18, pv.site.lonDeg, siteHeight + 600.0, 0.0, 2.0, 0.0}, 2.0, 32,
                      18);
  engine::VolumeRenderOptions options;
  options.render.earlyTerminationAlpha = 2.0;  // never: every sample of the interval is taken
  options.skipEmptySpace = false;
  const std::vector<float> counts = renderer_->sampleCounts(camera, {engine::VolumeLayerGL{gl->get(), options}});
  ASSERT_EQ(counts.size(), 32u * 18u);
  const double step = options.render.stepMeters;
  double sumGpu = 0.0, sumExpected = 0.0, worst = 0.0;
  for (int y = 0; y < 18; ++y) {
    for (int x = 0; x < 32; ++x) {
      const glm::dvec3 dir = camera.pixelRayDirection(x + 0.5, y + 0.5);
      const volume::RayInterval in = (*gl)->referenceSampler().rayInterval(camera.eyeEcef(), dir);
      ASSERT_FALSE(in.empty());
      const double first = std::ceil(std::max(in.tEnterMeters, 0.0) / step - 0.5);
      const double last = std::floor(in.tExitMeters / step - 0.5);
      const double expected = std::max(0.0, last - first + 1.0);
      const double gpu = counts[static_cast<std::size_t>(y) * 32 + x];
      sumGpu += gpu;
      sumExpected += expected;
      worst = std::max(worst, std::abs(gpu - expected));
    }
  }
  std::cout << "samples: " << sumGpu << " counted, " << sumExpected << " expected, worst pixel off by " << worst
            << "\n";
  // At most the sample at either end of a ~100 km interval, where float rounds the sphere's exit.
  EXPECT_LE(worst, 1.0);
  EXPECT_GT(sumExpected, 32.0 * 18.0 * 100.0);  // hundreds of samples a ray: the count is not trivially small
  EXPECT_NEAR(sumGpu, sumExpected, 0.001 * sumExpected);

  options.skipEmptySpace = true;
  const std::vector<float> skipped = renderer_->sampleCounts(camera, {engine::VolumeLayerGL{gl->get(), options}});
  double sumSkipped = 0.0;
  for (float c : skipped) sumSkipped += c;
  std::cout << "with empty-space skipping: " << sumSkipped << "\n";
  EXPECT_LT(sumSkipped, 0.9 * sumGpu);
  EXPECT_GT(sumSkipped, 0.0);
}

// The marcher is specialised per (mode, skipping, classification, volumes and their sampler
// constants) and compiled on first use: every one-radar variant (mode, interpolation, beam,
// skipping, classification: 40) and mixed multi-volume variants must compile and link.
TEST_F(RadarMarch, EveryMarchVariantCompiles) {
  auto renderer = engine::VolumeRendererGL::create();
  ASSERT_TRUE(renderer) << renderer.error();
  for (int mode = 0; mode < 4; ++mode)
    for (int interpolation = 0; interpolation < 2; ++interpolation)
      for (int beam = 0; beam < 2; ++beam)
        for (int skip = 0; skip < 2; ++skip)
          for (int preintegrated = 0; preintegrated < (mode == 0 ? 2 : 1); ++preintegrated) {
            engine::MarchVariant v;
            v.mode = mode;
            v.skipEmpty = skip == 1;
            v.preintegrated = preintegrated == 1;
            v.volumes.push_back({"sample_polar.glsl",
                                 {"INTERPOLATION " + std::to_string(interpolation), "BEAM " + std::to_string(beam)}});
            EXPECT_NE((*renderer)->marchProgram(v), nullptr)
                << mode << " " << interpolation << " " << beam << " " << skip << " " << preintegrated;
          }
  for (int mode = 0; mode < 3; ++mode)
    for (int preintegrated = 0; preintegrated < (mode == 0 ? 2 : 1); ++preintegrated) {
      engine::MarchVariant v;
      v.mode = mode;
      v.preintegrated = preintegrated == 1;
      v.stepRule = true;  // the step rule's code with every kind (radars and shells take level 0)
      for (int k = 0; k < engine::MarchConstants::kMaxVolumes; ++k)
        v.volumes.push_back(k % 2 ? std::pair<std::string, std::vector<std::string>>{"sample_shell.glsl", {}}
                                  : std::pair<std::string, std::vector<std::string>>{
                                        "sample_polar.glsl", {"INTERPOLATION 1", "BEAM 0", "EXAGGERATED 0"}});
      EXPECT_NE((*renderer)->marchProgram(v), nullptr) << "8 mixed volumes, mode " << mode << " " << preintegrated;
    }
}

namespace {
float uniform40(double, double, double) { return 40.0f; }
// Strong echo out to 50 km, weak (measured, below the 10 dBZ zero-opacity value) beyond: the
// empty-space grid skips the weak part, so a run of strong samples ends at a skip there.
float strongThenWeak(double r, double, double) { return r < 50e3 ? 40.0f : 5.0f; }
}  // namespace

// Pre-integrated classification: a uniform field gives the point-classified picture (the
// half steps at the ends of a run of samples make the same path length); on the smooth storm
// at a coarse step it is closer to a fine reference than point classification; empty-space
// skipping does not change its picture.
TEST_F(RadarMarch, PreintegrationKeepsUniformFieldsAndHelpsCoarseSteps) {
  const Camera camera(kObliquePose, 40.0, 64, 48);
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.render.stepMeters = 1000.0;
  {
    const volume::PolarVolume pv = polar(syntheticRadar(uniform40));
    auto gl = engine::RadarVolumeGL::create(pv);
    ASSERT_TRUE(gl) << gl.error();
    options.classification = engine::Classification::Point;
    const volume::VolumeImage point = renderGpu(camera, **gl, options);
    options.classification = engine::Classification::Preintegrated;
    const volume::VolumeImage pre = renderGpu(camera, **gl, options);
    // Float rounding of exp(-sigma d) against the CPU's pow for the point table: well below
    // one 8-bit step anywhere. A missing half step would differ by ~0.08 in alpha (20 steps).
    EXPECT_LE(volume::compareImages(pre, point).maxAbs, 1.0);
  }
  const volume::PolarVolume pv = polar(syntheticRadar(storm));
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  volume::VolumeRenderSettings fine = options.render;
  fine.stepMeters = 100.0;
  const volume::VolumeImage ref = volume::renderReference(pv, fine, engine::referenceCameraFor(camera), false, 2);
  options.classification = engine::Classification::Point;
  const volume::ImageError ePoint = volume::compareImages(renderGpu(camera, **gl, options), ref);
  options.classification = engine::Classification::Preintegrated;
  const volume::VolumeImage pre = renderGpu(camera, **gl, options);
  const volume::ImageError ePre = volume::compareImages(pre, ref);
  std::cout << "1000 m against a 100 m reference: point mean " << ePoint.meanAbs << " PSNR " << ePoint.psnrDb
            << " dB; pre-integrated mean " << ePre.meanAbs << " PSNR " << ePre.psnrDb << " dB\n";
  EXPECT_LT(ePre.meanAbs, ePoint.meanAbs);
  EXPECT_GT(ePre.psnrDb, ePoint.psnrDb);
  options.skipEmptySpace = false;
  EXPECT_LE(volume::compareImages(renderGpu(camera, **gl, options), pre).maxAbs, 1.0) << "skipping changed the picture";
  // Where strong echo meets weak echo that the grid skips, skipping must not change the runs
  // (with runs ending at a skip instead of at the first weak sample, this image differed by 43
  // of 255).
  const volume::PolarVolume pvStep = polar(syntheticRadar(strongThenWeak));
  auto glStep = engine::RadarVolumeGL::create(pvStep);
  ASSERT_TRUE(glStep) << glStep.error();
  const volume::VolumeImage noSkip = renderGpu(camera, **glStep, options);
  options.skipEmptySpace = true;
  EXPECT_LE(volume::compareImages(renderGpu(camera, **glStep, options), noSkip).maxAbs, 1.0)
      << "skipping changed the picture at a strong/weak echo boundary";
}

TEST_F(RadarMarch, GpuMatchesTheReferenceInEveryMode) {
  const volume::PolarVolume pv = polar(syntheticRadar(storm));
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  const Camera camera(kObliquePose, 40.0, 80, 60);
  for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
    for (auto interp : {volume::Interpolation::Nearest, volume::Interpolation::Linear}) {
      engine::VolumeRenderOptions options;
      options.render.mode = mode;
      options.render.interpolation = interp;
      options.render.stepMeters = 500.0;
      options.render.transfer = volume::defaultReflectivityTransfer();
      options.skipEmptySpace = false;
      const volume::VolumeImage gpu = renderGpu(camera, **gl, options);
      const volume::VolumeImage ref =
          volume::renderReference(pv, options.render, engine::referenceCameraFor(camera), false, 2);
      const volume::ImageError e = volume::compareImages(gpu, ref);
      std::cout << "mode " << static_cast<int>(mode) << " interp " << static_cast<int>(interp) << ": mean " << e.meanAbs
                << " max " << e.maxAbs << " PSNR " << e.psnrDb << " dB\n";
      // Where GPU and reference differ: float32 positions (mm), the GLSL inverse (< 0.05 deg,
      // tested above), half-float values (0.03 dBZ) and a tabulated transfer function
      // (0.03 dBZ). These move a sample across a gate/sweep/colour-band edge only in a few
      // pixels; the image as a whole must agree to a mean of 1 step of 255 and 30 dB PSNR.
      EXPECT_LT(e.meanAbs, 1.0);
      EXPECT_GT(e.psnrDb, 30.0);
      // Empty-space skipping must not change the picture: it only drops samples that cannot
      // contribute (DVR: below the zero-opacity value, whose table entry may still hold an
      // alpha of ~1e-5 for values within 0.015 dBZ below it; MIP: not above the maximum so
      // far; iso: below the iso value), so against the unskipped GPU image at most one 8-bit
      // step anywhere.
      options.skipEmptySpace = true;
      const volume::VolumeImage skipped = renderGpu(camera, **gl, options);
      const volume::ImageError es = volume::compareImages(skipped, ref);
      EXPECT_LT(es.meanAbs, 1.0) << "with empty-space skipping";
      EXPECT_GT(es.psnrDb, 30.0) << "with empty-space skipping";
      EXPECT_LE(volume::compareImages(skipped, gpu).maxAbs, 1.0) << "skipping changed the picture";
    }
  }
}

// The step rule for radars (volume/StepRule.h: the gate along the beam, the beam's width across
// it) at 1 sample per cell from a 125 m step, straight down from 150 km over the storm (where
// rays cross the beams and the rule takes steps of up to 4 fine ones) and from the oblique pose:
// the GPU against the reference taking the same samples, in every mode, within the fixed step's
// bounds (mean below one 8-bit step, 30 dB); the rule changes the picture against the fixed step
// (it is on) while staying close to it, and skipping on or off does not change it.
TEST_F(RadarMarch, StepRuleGpuMatchesTheReferenceInEveryMode) {
  const volume::PolarVolume pv = polar(syntheticRadar(storm));
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  // 55 km from the antenna at azimuth 20 deg: the storm's core.
  const CameraPose downPose{33.654 + 0.4647, -101.814 + 0.2029, 1.5e5, 0.0, -90.0, 0.0};
  for (const auto& [name, pose] : {std::pair{"down", downPose}, std::pair{"oblique", kObliquePose}}) {
    const Camera camera(pose, 40.0, 80, 60);
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
      engine::VolumeRenderOptions fixed;
      fixed.render.mode = mode;
      fixed.render.stepMeters = 125.0;
      fixed.render.transfer = volume::defaultReflectivityTransfer();
      engine::VolumeRenderOptions o = fixed;
      o.render.samplesPerCell = 1.0;
      const volume::VolumeImage gpu = renderGpu(camera, **gl, o);
      engine::VolumeRenderOptions noSkip = o;
      noSkip.skipEmptySpace = false;
      const volume::VolumeImage gpuNoSkip = renderGpu(camera, **gl, noSkip);
      const volume::VolumeImage ref =
          volume::renderReference(pv, o.render, engine::referenceCameraFor(camera), false, 2);
      const volume::VolumeImage refFixed =
          volume::renderReference(pv, fixed.render, engine::referenceCameraFor(camera), false, 2);
      const volume::ImageError e = volume::compareImages(gpu, ref);
      const volume::ImageError skip = volume::compareImages(gpu, gpuNoSkip);
      const volume::ImageError rule = volume::compareImages(ref, refFixed);
      int drawn = 0;
      for (const glm::dvec4& p : ref.rgbaPremultiplied) drawn += p.a > 0.05;
      std::cout << "radar step rule, " << name << ", mode " << static_cast<int>(mode) << ": " << drawn
                << " pixels drawn, GPU vs reference mean " << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb
                << " dB; skipping on vs off mean " << skip.meanAbs << " max " << skip.maxAbs
                << "; rule vs fixed step (reference) mean " << rule.meanAbs << " max " << rule.maxAbs << " PSNR "
                << rule.psnrDb << " dB\n";
      // The isosurface is the 40 dBZ core only.
      EXPECT_GT(drawn, mode == volume::VolumeRenderMode::Iso ? 20 : 100) << name << " must show the storm";
      EXPECT_LT(e.meanAbs, 1.0) << name;
      EXPECT_GT(e.psnrDb, 30.0) << name;
      EXPECT_LT(skip.meanAbs, 1.0) << name;
      if (mode == volume::VolumeRenderMode::Dvr && std::string(name) == "down") {
        EXPECT_GT(rule.maxAbs, 0.0) << name << ": the rule must take other samples";
      }
    }
  }
}

namespace {
// One hot gate (60 dBZ) at sweep 3 (3.5 deg), ray 40 (azimuth 40.5), gate 200 (52.1 km);
// everything else measured but empty.
float pointEcho(double r, double az, double el) {
  const bool hot = std::abs(el - 3.5) < 1e-9 && std::abs(az - 40.5) < 1e-9 &&
                   std::abs(r - (2125.0 + 200 * 250.0)) < 1e-6;
  return hot ? 60.0f : volume::kNoEcho;
}
}  // namespace

TEST_F(RadarMarch, PointEchoAppearsWhereGeolocationPutsIt) {
  const volume::PolarVolume pv = polar(syntheticRadar(pointEcho));
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  // Predicted position: the gate centre geolocated with the exact forward model.
  const volume::GatePosition gate = volume::geolocateGateExact(pv.site, pv.beam, 40.5, 3.5, 2125.0 + 200 * 250.0);
  // A camera 20 km from the gate, looking at it from the south-west and above.
  const globe::GeodesicPoint from = globe::geodesicDirect(gate.latDeg, gate.lonDeg, 225.0, 20e3);
  const double heading = globe::geodesicInverse(from.latDeg, from.lonDeg, gate.latDeg, gate.lonDeg).azimuth1Deg;
  const CameraPose pose{
      from.latDeg, from.lonDeg, gate.heightMeters + 8e3, heading, -radiansToDegrees(std::atan2(8e3, 20e3)), 0.0};
  const Camera camera(pose, 30.0, 96, 96);
  const auto predicted = camera.projectToPixel(gate.ecef);
  ASSERT_TRUE(predicted);
  engine::VolumeRenderOptions options;
  options.render.mode = volume::VolumeRenderMode::Mip;
  options.render.interpolation = volume::Interpolation::Nearest;
  options.render.stepMeters = 20.0;
  options.render.transfer = volume::defaultReflectivityTransfer();
  const volume::VolumeImage img = renderGpu(camera, **gl, options);
  // Centroid of the lit pixels (the gate is a ~250 m x 900 m x 900 m box: a few pixels).
  double sx = 0, sy = 0, sw = 0;
  for (int y = 0; y < 96; ++y) {
    for (int x = 0; x < 96; ++x) {
      const double a = img.at(x, y).a;
      sx += a * (x + 0.5);
      sy += a * (y + 0.5);
      sw += a;
    }
  }
  ASSERT_GT(sw, 0.5) << "the echo was not drawn";
  // 1 px: the gate's footprint is symmetric about its centre to within the beam's bending
  // over 900 m (< 0.1 px here).
  EXPECT_NEAR(sx / sw, predicted->x, 1.0);
  EXPECT_NEAR(sy / sw, predicted->y, 1.0);
}

TEST_F(RadarMarch, CameraInsideAtTheSiteAndStraightDownRenderCleanly) {
  const volume::PolarVolume pv = polar(syntheticRadar(storm));
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  const globe::GeodesicPoint stormCentre = globe::geodesicDirect(pv.site.latDeg, pv.site.lonDeg, 20.0, 55e3);
  struct View {
    const char* name;
    CameraPose pose;
    bool expectEcho;
  };
  const View views[] = {
      {"inside the storm, looking along it", {stormCentre.latDeg, stormCentre.lonDeg, 3000.0, 200.0, 0.0, 0.0}, true},
      {"at the antenna, looking out",
       {pv.site.latDeg, pv.site.lonDeg, pv.site.antennaHeightEllipsoidMeters, 20.0, 3.0, 0.0},
       true},
      {"at the antenna, looking up the cone of silence",
       {pv.site.latDeg, pv.site.lonDeg, pv.site.antennaHeightEllipsoidMeters + 1.0, 0.0, 90.0, 0.0},
       false},
      {"straight down on the site from 120 km", {pv.site.latDeg, pv.site.lonDeg, 1.2e5, 0.0, -90.0, 0.0}, true},
  };
  for (const View& v : views) {
    const Camera camera(v.pose, 60.0, 64, 48);
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
      engine::VolumeRenderOptions options;
      options.render.mode = mode;
      options.render.transfer = volume::defaultReflectivityTransfer();
      const volume::VolumeImage img = renderGpu(camera, **gl, options);
      int lit = 0;
      for (const glm::dvec4& c : img.rgbaPremultiplied) {
        ASSERT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && std::isfinite(c.a)) << v.name;
        ASSERT_GE(c.a, 0.0) << v.name;
        ASSERT_LE(c.a, 1.0 + 1e-3) << v.name;
        if (c.a > 0.05) ++lit;
      }
      if (v.expectEcho) {
        EXPECT_GT(lit, 20) << v.name << " mode " << static_cast<int>(mode) << " lit " << lit;
      } else {
        EXPECT_EQ(lit, 0) << v.name << " mode " << static_cast<int>(mode) << ": the cone of silence must stay empty";
      }
    }
  }
}
