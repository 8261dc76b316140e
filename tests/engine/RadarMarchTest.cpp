// The GPU ray marcher against the CPU reference (double precision, exact inverse), the
// GLSL beam-model inverse against the exact one, a point echo at its geolocated pixel, and
// cameras inside, at and above the volume.
#include "GLTestUtil.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarVolumeRendererGL.h>
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
  volume::RadarVolume v;
  v.format = "synthetic";
  v.sourcePath = "synthetic";
  v.site = {"TEST", 33.654, -101.814, 1029.0, volume::HeightDatum::Ellipsoid};
  v.beamWidthDeg = 1.0;
  v.loadedField = {"DBZ", "dBZ"};
  v.fields = {v.loadedField};
  for (int k = 0; k < 10; ++k) {
    volume::Sweep s;
    s.indexInFile = k;
    s.fixedAngleDeg = 0.5 + k;
    s.firstGateRangeMeters = 2125.0;
    s.gateSpacingMeters = 250.0;
    s.gateCount = 400;
    for (int ray = 0; ray < 360; ++ray) {
      s.azimuthDeg.push_back(static_cast<float>(ray + 0.5));
      s.elevationDeg.push_back(static_cast<float>(s.fixedAngleDeg));
      for (std::uint32_t g = 0; g < s.gateCount; ++g) {
        s.values.push_back(field(s.gateRangeMeters(g), ray + 0.5, s.fixedAngleDeg));
      }
    }
    v.sweeps.push_back(std::move(s));
  }
  return v;
}

float storm(double r, double az, double el) {
  const double v = 62.0 * std::exp(-std::pow((r - 55e3) / 18e3, 2) - std::pow((az - 20.0) / 18.0, 2) -
                                    std::pow((el - 3.0) / 4.0, 2));
  return v < 5.0 ? volume::kNoEcho : static_cast<float>(v);
}

volume::PolarVolume polar(const volume::RadarVolume& radar) {
  volume::SiteResolution site;
  site.site = {radar.site.latDeg, radar.site.lonDeg, radar.site.antennaHeightMeters};
  auto p = volume::buildPolarVolume(radar, site, volume::BeamModel{});
  EXPECT_TRUE(p) << (p ? "" : p.error());
  return *p;
}

class RadarMarch : public ::testing::Test {
 protected:
  void SetUp() override {
    testutil::glContext();
    auto r = engine::RadarVolumeRendererGL::create();
    ASSERT_TRUE(r) << r.error();
    renderer_ = std::move(*r);
  }

  /// GPU volume image for a camera (no globe: empty depth), composited over black.
  volume::VolumeImage renderGpu(const Camera& camera, const engine::RadarVolumeGL& gl,
                                const engine::RadarRenderOptions& options) {
    auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
    EXPECT_TRUE(fb);
    (*fb)->bind();
    glClearDepth(0.0);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    renderer_->draw(camera, gl, options, **fb);
    const std::vector<glm::vec4> img = renderer_->readVolumeImage();
    volume::VolumeImage out;
    out.widthPx = camera.widthPx();
    out.heightPx = camera.heightPx();
    for (const glm::vec4& c : img) out.rgbaPremultiplied.push_back(glm::dvec4(c));
    return out;
  }

  std::unique_ptr<engine::RadarVolumeRendererGL> renderer_;
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
  double maxRange = 0, maxAz = 0, maxEl = 0;
  for (double t : {80e3, 120e3, 160e3}) {
    const auto coords = renderer_->antennaCoordinatesAt(camera, **gl, engine::BeamApproximation::EffectiveEarthLocalSphere, t);
    ASSERT_EQ(coords.size(), 64u * 48u);
    for (int y = 0; y < 48; ++y) {
      for (int x = 0; x < 64; ++x) {
        const glm::dvec3 p = camera.eyeEcef() + t * camera.pixelRayDirection(x + 0.5, y + 0.5);
        const volume::AntennaCoordinates exact = volume::antennaCoordinatesExact(pv.site, pv.beam, p);
        if (exact.rangeMeters > 460e3 || exact.rangeMeters < 1e3) continue;
        const glm::vec4 g = coords[static_cast<std::size_t>(y) * 64 + x];
        maxRange = std::max(maxRange, std::abs(g.x - exact.rangeMeters));
        double dAz = std::abs(g.y - exact.azimuthDeg);
        dAz = std::min(dAz, 360.0 - dAz);
        maxAz = std::max(maxAz, dAz);
        maxEl = std::max(maxEl, std::abs(g.z - exact.elevationDeg));
      }
    }
  }
  std::cout << "GLSL inverse vs exact: max |range| " << maxRange << " m, |azimuth| " << maxAz
            << " deg, |elevation| " << maxEl << " deg\n";
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
  const auto straight = renderer_->antennaCoordinatesAt(camera, **gl, engine::BeamApproximation::StraightLine, 160e3);
  const glm::dvec3 p = camera.eyeEcef() + 160e3 * camera.pixelRayDirection(32.5, 24.5);
  const volume::AntennaCoordinates exact = volume::antennaCoordinatesExact(pv.site, pv.beam, p);
  EXPECT_GT(std::abs(straight[24 * 64 + 32].z - exact.elevationDeg), 10.0 * maxEl);
}

TEST_F(RadarMarch, GpuMatchesTheReferenceInEveryMode) {
  const volume::PolarVolume pv = polar(syntheticRadar(storm));
  auto gl = engine::RadarVolumeGL::create(pv);
  ASSERT_TRUE(gl) << gl.error();
  const Camera camera(kObliquePose, 40.0, 80, 60);
  for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
    for (auto interp : {volume::Interpolation::Nearest, volume::Interpolation::Linear}) {
      engine::RadarRenderOptions options;
      options.render.mode = mode;
      options.render.interpolation = interp;
      options.render.stepMeters = 500.0;
      options.render.transfer = volume::defaultReflectivityTransfer();
      options.skipEmptySpace = false;
      const volume::VolumeImage gpu = renderGpu(camera, **gl, options);
      const volume::VolumeImage ref =
          volume::renderReference(pv, options.render, engine::referenceCameraFor(camera), false, 2);
      const volume::ImageError e = volume::compareImages(gpu, ref);
      std::cout << "mode " << static_cast<int>(mode) << " interp " << static_cast<int>(interp) << ": mean "
                << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb << " dB\n";
      // Where GPU and reference differ: float32 positions (mm), the GLSL inverse (< 0.05 deg,
      // tested above), half-float values (0.03 dBZ) and a tabulated transfer function
      // (0.03 dBZ). These move a sample across a gate/sweep/colour-band edge only in a few
      // pixels; the image as a whole must agree to a mean of 1 step of 255 and 30 dB PSNR.
      EXPECT_LT(e.meanAbs, 1.0);
      EXPECT_GT(e.psnrDb, 30.0);
      // Empty-space skipping must not change the picture beyond the same bound.
      options.skipEmptySpace = true;
      const volume::ImageError es = volume::compareImages(renderGpu(camera, **gl, options), ref);
      EXPECT_LT(es.meanAbs, 1.0) << "with empty-space skipping";
      EXPECT_GT(es.psnrDb, 30.0) << "with empty-space skipping";
    }
  }
}
