// The CPU reference renderer (ReferenceRenderer.h) and the transfer function: closed-form cases
// (a uniform shell's optical depth, hand-worked opacities), a point echo at the pixel the
// geolocation path predicts, awkward cameras, and a real volume.
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

namespace atmoglobe::volume {
namespace {

constexpr double kDeg = kPi / 180.0;

const GeolocationSite kSite{40.0, 10.0, 500.0};

glm::dvec3 antennaEcef(const GeolocationSite& s) {
  return globe::geodeticToEcef(globe::Geodetic{s.latDeg, s.lonDeg, s.antennaHeightEllipsoidMeters});
}
glm::dvec3 localUp(double latDeg, double lonDeg) { return globe::enuAxes(latDeg, lonDeg)[2]; }

// A PPI volume with `elevations`, 360 rays at 0.5, 1.5, ... deg, gates of 250 m from 125 m (so the
// gates cover range [0, gateCount * 250 m]), every gate = value(sweep, ray, gate).
template <class F>
PolarVolume makeVolume(const std::vector<double>& elevations, std::uint32_t gateCount, F value,
                       double beamWidthDeg = 1.0) {
  RadarVolume rv;
  rv.format = "test";
  rv.sourcePath = "synthetic";
  rv.beamWidthDeg = beamWidthDeg;
  rv.loadedField = FieldInfo{"DBZH", "dBZ", {}};
  for (std::size_t k = 0; k < elevations.size(); ++k) {
    Sweep s;
    s.indexInFile = static_cast<int>(k);
    s.fixedAngleDeg = elevations[k];
    s.firstGateRangeMeters = 125.0;
    s.gateSpacingMeters = 250.0;
    s.gateCount = gateCount;
    for (int r = 0; r < 360; ++r) {
      s.azimuthDeg.push_back(static_cast<float>(r) + 0.5f);
      s.elevationDeg.push_back(static_cast<float>(elevations[k]));
      for (std::uint32_t g = 0; g < gateCount; ++g) s.values.push_back(value(k, r, g));
    }
    rv.sweeps.push_back(std::move(s));
  }
  SiteResolution site;
  site.site = kSite;
  Result<PolarVolume> pv = buildPolarVolume(rv, site, BeamModel{});
  EXPECT_TRUE(pv.ok());
  return *pv;
}

// VCP 212 elevation angles (NEXRAD), 100 km of gates, uniform 35 dBZ.
PolarVolume uniformVolume(float value = 35.0f) {
  return makeVolume({0.5, 0.9, 1.3, 1.8, 2.4, 3.1, 4.0, 5.1, 6.4, 8.0, 10.0, 12.5, 15.6, 19.5}, 400,
                    [value](std::size_t, int, std::uint32_t) { return value; });
}

bool allFinite(const VolumeImage& img) {
  for (const glm::dvec4& c : img.rgbaPremultiplied)
    for (int i = 0; i < 4; ++i)
      if (!std::isfinite(c[i]) || c[i] < 0.0 || c[i] > 1.0 + 1e-12) return false;
  return true;
}

// --- Transfer function, worked by hand.
TEST(TransferFunction, ClassifyAndOpacityCorrection) {
  const TransferFunction tf = defaultReflectivityTransfer();
  // 35 dBZ: NWS colour (255, 255, 0) (the NWS reflectivity table, ColorTable.h), ramp (35 - 10) / 50 = 0.5 -> a = 0.4.
  glm::dvec4 c = tf.classify(35.0);
  EXPECT_DOUBLE_EQ(c.r, 1.0);
  EXPECT_DOUBLE_EQ(c.g, 1.0);
  EXPECT_DOUBLE_EQ(c.b, 0.0);
  EXPECT_NEAR(c.a, 0.4, 1e-15);
  EXPECT_EQ(tf.classify(10.0).a, 0.0);  // at the zero value
  EXPECT_EQ(tf.classify(5.0).a, 0.0);
  EXPECT_NEAR(tf.classify(60.0).a, 0.8, 1e-15);
  EXPECT_NEAR(tf.classify(72.0).a, 0.8, 1e-15);
  EXPECT_EQ(tf.classify(-std::numeric_limits<double>::infinity()), glm::dvec4(0.0));
  EXPECT_EQ(tf.classify(std::nan("")), glm::dvec4(0.0));
  // Opacity correction: a full reference length gives a; 250 m gives 1 - 0.2^0.25 = 0.331259695...
  EXPECT_NEAR(tf.correctedOpacity(0.8, 1000.0), 0.8, 1e-15);
  EXPECT_NEAR(tf.correctedOpacity(0.8, 250.0), 1.0 - std::pow(0.2, 0.25), 1e-15);
  EXPECT_NEAR(tf.correctedOpacity(0.8, 250.0), 0.3312596950, 1e-10);
  // Four composited 250 m steps equal one 1000 m step.
  const double a = tf.correctedOpacity(0.8, 250.0);
  EXPECT_NEAR(1.0 - std::pow(1.0 - a, 4.0), 0.8, 1e-14);
  EXPECT_EQ(tf.correctedOpacity(1.0, 10.0), 1.0);
  EXPECT_EQ(tf.correctedOpacity(0.0, 10.0), 0.0);
}

TEST(TransferFunction, ExtinctionAndIntegralTable) {
  const TransferFunction tf = defaultReflectivityTransfer();
  // 0.8 per 1000 m -> -ln(0.2) / 1000 per metre, and a 250 m path has the corrected opacity.
  const double sigma = tf.extinctionPerMeter(0.8);
  EXPECT_NEAR(sigma, -std::log(0.2) / 1000.0, 1e-18);
  EXPECT_NEAR(1.0 - std::exp(-sigma * 250.0), tf.correctedOpacity(0.8, 250.0), 1e-15);
  EXPECT_EQ(tf.extinctionPerMeter(0.0), 0.0);
  EXPECT_TRUE(std::isfinite(tf.extinctionPerMeter(1.0)));  // opaque: clamped, not infinite

  // Over [0, 100] dBZ in 400 bins of 0.25 dBZ (bin centres never on a colour-band edge).
  const std::vector<glm::dvec4> table = transferIntegralTable(tf, 0.0, 100.0, 400);
  ASSERT_EQ(table.size(), 401u);
  EXPECT_EQ(table[0], glm::dvec4(0.0));
  // Below the zero-opacity value (10 dBZ = edge 40) nothing accumulates.
  EXPECT_EQ(table[40], glm::dvec4(0.0));
  // Between two edges above the full-opacity value (60 dBZ) the slope of the extinction
  // integral is the constant extinction, and of the colour integral extinction * colour.
  const double perBin = 0.25;
  for (int k = 261; k < 279; ++k) {  // 65.25 .. 69.75 dBZ
    const glm::dvec4 c = tf.classify((k + 0.5) * perBin);
    EXPECT_NEAR((table[k + 1].a - table[k].a) / perBin, sigma, 1e-15) << k;
    EXPECT_NEAR((table[k + 1].r - table[k].r) / perBin, sigma * c.r, 1e-15) << k;
  }
  // Monotone in the extinction integral, and the total equals the sum over bin centres.
  double sum = 0.0;
  for (int k = 0; k < 400; ++k) {
    EXPECT_LE(table[k].a, table[k + 1].a);
    sum += tf.extinctionPerMeter(tf.classify((k + 0.5) * perBin).a) * perBin;
  }
  EXPECT_NEAR(table[400].a, sum, 1e-15);
}
// --- Image comparison, worked by hand.
TEST(ReferenceRenderer, CompareImages) {
  VolumeImage a;
  a.widthPx = 2;
  a.heightPx = 1;
  a.rgbaPremultiplied = {glm::dvec4(0.5, 0.2, 0.0, 1.0), glm::dvec4(0.0)};
  VolumeImage b = a;
  EXPECT_TRUE(std::isinf(compareImages(a, b).psnrDb));
  EXPECT_EQ(compareImages(a, b).maxAbs, 0.0);
  // Pixel 1 red 10/255 vs 0: 8-bit difference 10 in one of 6 channels.
  b.rgbaPremultiplied[1] = glm::dvec4(10.0 / 255.0, 0.0, 0.0, 10.0 / 255.0);
  const ImageError e = compareImages(a, b);
  EXPECT_DOUBLE_EQ(e.maxAbs, 10.0);
  EXPECT_DOUBLE_EQ(e.meanAbs, 10.0 / 6.0);
  EXPECT_NEAR(e.psnrDb, 10.0 * std::log10(255.0 * 255.0 / (100.0 / 6.0)), 1e-12);
}

// --- Camera helpers: the ray through the projection of a point passes through the point.
TEST(ReferenceRenderer, CameraRayAndProjectionAgree) {
  const glm::dvec3 eye = globe::geodeticToEcef({40.0, 10.0, 20000.0});
  const glm::dvec3 target = globe::geodeticToEcef({40.5, 10.3, 3000.0});
  const RenderCamera cam = makeLookAtCamera(eye, target, localUp(40.0, 10.0), 50.0, 160, 90);
  // The look-at target is the image centre.
  const std::optional<glm::dvec2> c = projectToPixel(cam, target);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->x, 80.0, 1e-9);
  EXPECT_NEAR(c->y, 45.0, 1e-9);
  // Focal length: heightPx / (2 tan(fovY / 2)).
  EXPECT_NEAR(cam.focalLengthPx, 90.0 / (2.0 * std::tan(25.0 * kDeg)), 1e-9);
  const glm::dvec3 p = globe::geodeticToEcef({40.6, 10.1, 9000.0});
  const std::optional<glm::dvec2> px = projectToPixel(cam, p);
  ASSERT_TRUE(px.has_value());
  const glm::dvec3 d = pixelRayDirection(cam, px->x, px->y);
  EXPECT_NEAR(glm::length(glm::cross(d, glm::normalize(p - eye))), 0.0, 1e-12);
  EXPECT_GT(glm::dot(d, p - eye), 0.0);
  // Image up is away from the ground: a higher point projects to a smaller y.
  EXPECT_LT(projectToPixel(cam, target + 1000.0 * localUp(40.5, 10.3))->y, 45.0);
  EXPECT_FALSE(projectToPixel(cam, eye - (target - eye)).has_value());  // behind
}

// Path length of a ray inside the uniform volume's shell, computed independently of the
// renderer's sampling: t in the clip sphere, before the ground, with beam-model elevation in
// [e0 - hb, eTop + hb] and range <= maxRange. Scanned on a 100 m grid, each transition located by
// bisection to 1 mm. Each transition is then checked against the FORWARD model: the point lies on
// geolocateGateExact's beam surface (elevation boundary) or range shell (range boundary), to 1 m.
struct ShellPath {
  double lengthMeters = 0.0;
  int intervals = 0;
};
ShellPath shellPathLength(const PolarVolume& v, const glm::dvec3& eye, const glm::dvec3& dir) {
  const double hb = 0.5 * v.beamWidthDeg;
  const double elLo = v.sweeps.front().elevationDeg - hb, elHi = v.sweeps.back().elevationDeg + hb;
  const glm::dvec3 c = antennaEcef(v.site);
  const double b = glm::dot(eye - c, dir);
  const double disc = b * b - (glm::dot(eye - c, eye - c) - v.clipRadiusMeters * v.clipRadiusMeters);
  ShellPath out;
  if (disc <= 0.0) return out;
  double t0 = std::max(0.0, -b - std::sqrt(disc)), t1 = -b + std::sqrt(disc);
  if (const auto hit = globe::intersectRayEllipsoid(eye, dir)) t1 = std::min(t1, glm::dot(*hit - eye, dir));
  if (t1 <= t0) return out;
  auto inside = [&](double t) {
    const AntennaCoordinates a = antennaCoordinatesExact(v.site, v.beam, eye + t * dir);
    return a.elevationDeg >= elLo && a.elevationDeg <= elHi && a.rangeMeters <= v.maxRangeMeters;
  };
  auto checkBoundary = [&](double t) {
    const glm::dvec3 p = eye + t * dir;
    const AntennaCoordinates a = antennaCoordinatesExact(v.site, v.beam, p);
    // Which boundary: the closest of the three in its own units (deg vs m scaled by 1e-4 deg/m).
    const double dLo = std::abs(a.elevationDeg - elLo), dHi = std::abs(a.elevationDeg - elHi);
    const double dR = std::abs(a.rangeMeters - v.maxRangeMeters) * 1e-4;
    glm::dvec3 q;
    if (dR <= dLo && dR <= dHi) {
      q = geolocateGateExact(v.site, v.beam, a.azimuthDeg, a.elevationDeg, v.maxRangeMeters).ecef;
    } else {
      q = geolocateGateExact(v.site, v.beam, a.azimuthDeg, dLo < dHi ? elLo : elHi, a.rangeMeters).ecef;
    }
    EXPECT_LT(glm::length(q - p), 1.0) << "boundary at t = " << t;
  };
  const double dt = 100.0;
  bool state = inside(t0);
  double start = t0;
  for (double t = t0; t < t1;) {
    const double tn = std::min(t + dt, t1);
    const bool s = inside(tn);
    if (s != state) {
      double lo = t, hi = tn;  // inside(lo) == state, inside(hi) != state
      while (hi - lo > 1e-3) {
        const double mid = 0.5 * (lo + hi);
        (inside(mid) == state ? lo : hi) = mid;
      }
      const double edge = 0.5 * (lo + hi);
      checkBoundary(edge);
      if (state) {
        out.lengthMeters += edge - start;
        ++out.intervals;
      } else {
        start = edge;
      }
      state = s;
    }
    t = tn;
  }
  if (state) {
    out.lengthMeters += t1 - start;
    ++out.intervals;
  }
  return out;
}

// The analytic volume: uniform 35 dBZ in every gate of every sweep, so the field is uniform inside
// the shell and a ray accumulates alpha = 1 - (1 - a)^(L / ref) (a the per-km opacity, L its path
// length in the shell, closed form of front-to-back compositing with corrected opacity). Opacity
// low (0.01 per km) and no early termination so that alpha is not saturated. The step quantises
// each inside interval by at most one step: |n step - L| <= intervals * step, asserted exactly;
// with step 100 m and L >= 30 km on at most 2 intervals that is <= 0.67 %, and alpha's relative
// error is at most L's (d alpha / alpha = -(1-A) ln(1-A) / A * dL / L <= dL / L), so 1 % holds.
TEST(ReferenceRenderer, UniformShellMatchesClosedFormOpticalDepth) {
  const PolarVolume v = uniformVolume(35.0f);
  VolumeRenderSettings st;
  st.mode = VolumeRenderMode::Dvr;
  st.stepMeters = 100.0;
  st.transfer = defaultReflectivityTransfer();
  st.transfer.maxOpacity = 0.02;  // 35 dBZ: ramp 0.5 -> a = 0.01 per km
  st.earlyTerminationAlpha = 2.0;
  const double aPerRef = st.transfer.classify(35.0).a;
  ASSERT_NEAR(aPerRef, 0.01, 1e-15);

  // Camera 150 km from the site (azimuth 200 from it), 8 km up, looking at 3 km over the site.
  const globe::GeodesicPoint g = globe::geodesicDirect(kSite.latDeg, kSite.lonDeg, 200.0, 150e3);
  const glm::dvec3 eye = globe::geodeticToEcef({g.latDeg, g.lonDeg, 8000.0});
  const glm::dvec3 target = globe::geodeticToEcef({kSite.latDeg, kSite.lonDeg, 3000.0});
  const RenderCamera cam = makeLookAtCamera(eye, target, localUp(g.latDeg, g.lonDeg), 30.0, 16, 10);
  const VolumeImage img = renderReference(v, st, cam, true, 2);
  ASSERT_TRUE(allFinite(img));

  int checked = 0, empty = 0;
  double worstRel = 0.0;
  for (int y = 0; y < cam.heightPx; ++y)
    for (int x = 0; x < cam.widthPx; ++x) {
      const glm::dvec3 dir = pixelRayDirection(cam, x + 0.5, y + 0.5);
      const ShellPath path = shellPathLength(v, eye, dir);
      const double alpha = img.at(x, y).a;
      if (path.lengthMeters == 0.0) {
        EXPECT_EQ(alpha, 0.0) << x << "," << y;
        ++empty;
        continue;
      }
      // Steps the renderer took inside: from alpha = 1 - (1 - a_s)^n.
      const double aStep = st.transfer.correctedOpacity(aPerRef, st.stepMeters);
      const double n = std::log1p(-alpha) / std::log1p(-aStep);
      EXPECT_LE(std::abs(n * st.stepMeters - path.lengthMeters), path.intervals * st.stepMeters + 1e-6)
          << x << "," << y << " L = " << path.lengthMeters;
      if (path.lengthMeters < 30e3) continue;
      ASSERT_LE(path.intervals, 2);
      const double expected = 1.0 - std::pow(1.0 - aPerRef, path.lengthMeters / st.transfer.opacityReferenceMeters);
      const double rel = std::abs(alpha - expected) / expected;
      worstRel = std::max(worstRel, rel);
      EXPECT_LT(rel, 0.01) << x << "," << y << " L = " << path.lengthMeters << " alpha " << alpha << " vs " << expected;
      // Uniform colour: premultiplied rgb = alpha * the 35 dBZ colour (1, 1, 0).
      EXPECT_NEAR(img.at(x, y).r, alpha, 1e-12);
      EXPECT_NEAR(img.at(x, y).b, 0.0, 1e-15);
      ++checked;
    }
  std::printf("uniform shell: %d pixels with L >= 30 km, worst relative alpha error %.4f %%, %d empty\n", checked,
              100.0 * worstRel, empty);
  EXPECT_GE(checked, 80);  // most of the 160 rays cross a long stretch of the shell
}

// A point echo: one gate of 50 dBZ in a volume of "no echo", at (r, az, el) = (25125 m, 45.5, 1.5).
// MIP must draw it where geolocateGateExact + the pinhole projection (written out here) put it,
// within 1 px: the lit region is symmetric about the gate in (ray, gate, sweep) coordinates, so its
// centroid is the gate's image up to the curvature of the mapping over ~400 m (far below a pixel).
TEST(ReferenceRenderer, PointEchoAppearsAtTheGeolocatedPixel) {
  const double azDeg = 45.5, elDeg = 1.5, rangeMeters = 25125.0;
  const PolarVolume v = makeVolume({0.5, 1.5, 2.5, 3.5}, 120, [](std::size_t k, int r, std::uint32_t g) {
    return (k == 1 && r == 45 && g == 100) ? 50.0f : kNoEcho;
  });
  ASSERT_EQ(samplePolar(v, rangeMeters, azDeg, elDeg, Interpolation::Linear).value, 50.0);
  const glm::dvec3 gate = geolocateGateExact(kSite, BeamModel{}, azDeg, elDeg, rangeMeters).ecef;
  // Camera inside the volume, 18 deg further round at the same range (~7.8 km away), 200 m higher.
  const GatePosition eyePos = geolocateGateExact(kSite, BeamModel{}, azDeg + 18.0, elDeg, rangeMeters);
  const glm::dvec3 eye = globe::geodeticToEcef({eyePos.latDeg, eyePos.lonDeg, eyePos.heightMeters + 200.0});
  // Aim off-centre so that the prediction is not simply the image centre.
  const glm::dvec3 aim =
      gate + 300.0 * localUp(eyePos.latDeg, eyePos.lonDeg) + 200.0 * glm::normalize(gate - antennaEcef(kSite));
  const RenderCamera cam = makeLookAtCamera(eye, aim, localUp(eyePos.latDeg, eyePos.lonDeg), 8.0, 40, 32);

  // Independent projection: eye-space e = R^T (p - eye); x = w/2 + f e.x / -e.z, y = h/2 - f e.y / -e.z.
  const glm::dvec3 e = glm::transpose(cam.cameraToEcef) * (gate - eye);
  ASSERT_LT(e.z, 0.0);
  const glm::dvec2 predicted(0.5 * cam.widthPx + cam.focalLengthPx * e.x / -e.z,
                             0.5 * cam.heightPx - cam.focalLengthPx * e.y / -e.z);
  ASSERT_GT(glm::length(predicted - glm::dvec2(20.0, 16.0)), 3.0);

  VolumeRenderSettings st;
  st.mode = VolumeRenderMode::Mip;
  st.stepMeters = 20.0;
  st.transfer = defaultReflectivityTransfer();
  for (Interpolation interp : {Interpolation::Linear, Interpolation::Nearest}) {
    st.interpolation = interp;
    const VolumeImage img = renderReference(v, st, cam, true, 2);
    ASSERT_TRUE(allFinite(img));
    glm::dvec2 sum(0.0);
    double count = 0.0;
    for (int y = 0; y < img.heightPx; ++y)
      for (int x = 0; x < img.widthPx; ++x)
        if (img.at(x, y).a > 0.0) {
          // Every lit pixel shows the 50 dBZ colour at its classify alpha: (255, 0, 0), a = 0.64.
          EXPECT_NEAR(img.at(x, y).a, 0.64, 1e-12);
          EXPECT_NEAR(img.at(x, y).r, 0.64, 1e-12);
          sum += glm::dvec2(x + 0.5, y + 0.5);
          count += 1.0;
        }
    ASSERT_GT(count, 4.0);
    const glm::dvec2 centroid = sum / count;
    std::printf("point echo (%s): %g lit px, centroid (%.2f, %.2f), predicted (%.2f, %.2f)\n",
                interp == Interpolation::Linear ? "linear" : "nearest", count, centroid.x, centroid.y, predicted.x,
                predicted.y);
    EXPECT_LT(glm::length(centroid - predicted), 1.0);
  }
}

// Cameras inside the volume, at the site, and looking straight down on it: finite output and the
// coverage the geometry implies.
TEST(ReferenceRenderer, CameraAtTheSiteLookingOutAndUp) {
  const PolarVolume v = uniformVolume();
  VolumeRenderSettings st;
  st.stepMeters = 500.0;
  st.transfer = defaultReflectivityTransfer();
  const glm::dvec3 site = antennaEcef(kSite);
  const glm::dmat3 enu = globe::enuAxes(kSite.latDeg, kSite.lonDeg);
  // Looking north, horizontal, fov 60: row y looks at elevation atan((h/2 - y - 0.5) / f).
  const RenderCamera cam = makeLookAtCamera(site, site + enu[1], enu[2], 60.0, 8, 12);
  const VolumeImage img = renderReference(v, st, cam, true, 2);
  ASSERT_TRUE(allFinite(img));
  for (int y = 0; y < cam.heightPx; ++y) {
    const double elDeg = std::atan((0.5 * cam.heightPx - y - 0.5) / cam.focalLengthPx) / kDeg;
    for (int x = 0; x < cam.widthPx; ++x) {
      const double horizontal = std::atan((x + 0.5 - 0.5 * cam.widthPx) / cam.focalLengthPx);
      const double rayElDeg = std::atan(std::tan(elDeg * kDeg) * std::cos(horizontal)) / kDeg;
      const double a = img.at(x, y).a;
      if (rayElDeg > 1.0 && rayElDeg < 19.0) {
        EXPECT_GT(a, 0.5) << x << "," << y << " el " << rayElDeg;
      }
      if (rayElDeg < -1.0 || rayElDeg > 21.0) {
        EXPECT_EQ(a, 0.0) << x << "," << y << " el " << rayElDeg;
      }
    }
  }
  // Straight up from the antenna: the cone of silence, nothing.
  const RenderCamera up = makeLookAtCamera(site, site + enu[2], enu[1], 20.0, 8, 8);
  const VolumeImage upImg = renderReference(v, st, up, true, 2);
  ASSERT_TRUE(allFinite(upImg));
  for (const glm::dvec4& c : upImg.rgbaPremultiplied) EXPECT_EQ(c.a, 0.0);
  // Inside the shell, 30 km out at 1 km, looking back at the site: finite, the centre lit.
  const globe::GeodesicPoint g = globe::geodesicDirect(kSite.latDeg, kSite.lonDeg, 300.0, 30e3);
  const glm::dvec3 eye = globe::geodeticToEcef({g.latDeg, g.lonDeg, 1000.0});
  const RenderCamera in = makeLookAtCamera(eye, site + 2000.0 * enu[2], localUp(g.latDeg, g.lonDeg), 60.0, 12, 8);
  const VolumeImage inImg = renderReference(v, st, in, true, 2);
  ASSERT_TRUE(allFinite(inImg));
  EXPECT_GT(inImg.at(6, 4).a, 0.5);
}

TEST(ReferenceRenderer, LookingStraightDownOnTheSite) {
  const PolarVolume v = uniformVolume();
  VolumeRenderSettings st;
  st.stepMeters = 500.0;
  st.transfer = defaultReflectivityTransfer();
  const glm::dmat3 enu = globe::enuAxes(kSite.latDeg, kSite.lonDeg);
  const glm::dvec3 eye = globe::geodeticToEcef({kSite.latDeg, kSite.lonDeg, 200e3});
  const RenderCamera cam = makeLookAtCamera(eye, antennaEcef(kSite), enu[1], 90.0, 17, 17);
  const VolumeImage img = renderReference(v, st, cam, true, 2);
  ASSERT_TRUE(allFinite(img));
  // Nadir pixel: straight down through the cone of silence onto the site: nothing.
  EXPECT_EQ(img.at(8, 8).a, 0.0);
  int lit = 0, dark = 0;
  for (int y = 0; y < 17; ++y)
    for (int x = 0; x < 17; ++x) {
      const glm::dvec3 dir = pixelRayDirection(cam, x + 0.5, y + 0.5);
      const auto hit = globe::intersectRayEllipsoid(eye, dir);
      ASSERT_TRUE(hit.has_value());
      const globe::Geodetic gh = globe::ecefToGeodetic(*hit);
      const double d = globe::geodesicInverse(kSite.latDeg, kSite.lonDeg, gh.latDeg, gh.lonDeg).distanceMeters;
      // A near-vertical ray that reaches the ground d from the site crosses the shell (elevations
      // 0..20 deg from the antenna, ~d tan(20 deg) of height) if d is inside the 100 km range.
      if (d > 20e3 && d < 80e3) {
        EXPECT_GT(img.at(x, y).a, 0.5) << x << "," << y << " d " << d;
        ++lit;
      }
      if (d > 120e3) {
        EXPECT_EQ(img.at(x, y).a, 0.0) << x << "," << y << " d " << d;
        ++dark;
      }
    }
  EXPECT_GT(lit, 20);
  EXPECT_GT(dark, 20);
}

// ISO on a field that depends on range only (value = 40 - 0.1 dBZ per gate, every sweep): the
// surface value 30 lies at gate coordinate 100 (range 25125 m). A ray aimed at the antenna from
// outside (values rising inwards) meets it where the beam-model range is 25125 m, within the bisection's resolution
// (step / 2^8) plus the range-to-distance difference of the model (< 0.1 % here); the gradient is radial, so the shade
// is 0.3 + 0.7 |cos| of the angle between the ray and the antenna direction (~1 for a ray straight at the antenna:
// colour = classify(30).rgb).
TEST(ReferenceRenderer, IsoSurfaceOfARangeRamp) {
  const PolarVolume v = makeVolume({0.5, 1.5, 2.5, 3.5, 4.5, 5.5}, 400, [](std::size_t, int, std::uint32_t g) {
    return 40.0f - 0.1f * static_cast<float>(g);
  });
  VolumeRenderSettings st;
  st.mode = VolumeRenderMode::Iso;
  st.isoValue = 30.0;
  st.stepMeters = 250.0;
  st.transfer = defaultReflectivityTransfer();
  const glm::dvec3 antenna = antennaEcef(kSite);
  // From 95 km out (azimuth 70), 6 km up: the ray towards the antenna enters the shell at ~3.6 deg.
  const globe::GeodesicPoint g = globe::geodesicDirect(kSite.latDeg, kSite.lonDeg, 70.0, 95e3);
  const glm::dvec3 eye = globe::geodeticToEcef({g.latDeg, g.lonDeg, 6000.0});
  const glm::dvec3 dir = glm::normalize(antenna - eye);
  const glm::dvec4 c = renderReferenceRay(v, st, eye, dir, true);
  ASSERT_EQ(c.a, 1.0);
  const glm::dvec4 expected = st.transfer.classify(30.0);  // 30 dBZ: NWS (0, 144, 0)
  EXPECT_NEAR(c.g, expected.g, 0.01);                      // |cos| ~ 1: shade within 1 %
  EXPECT_NEAR(c.r, 0.0, 1e-12);
  // The surface point: find it again by bisection on the ray's model range (independent of the
  // renderer's loop) and check that the renderer's ISO value is crossed there: samples 30 m
  // before/after are below/above 30.
  double lo = 0.0, hi = glm::length(antenna - eye);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (antennaCoordinatesExact(kSite, BeamModel{}, eye + mid * dir).rangeMeters > 25125.0 ? lo : hi) = mid;
  }
  const AntennaCoordinates before = antennaCoordinatesExact(kSite, BeamModel{}, eye + (lo - 30.0) * dir);
  const AntennaCoordinates after = antennaCoordinatesExact(kSite, BeamModel{}, eye + (lo + 30.0) * dir);
  EXPECT_LT(samplePolar(v, before.rangeMeters, before.azimuthDeg, before.elevationDeg, Interpolation::Linear).value,
            30.0);
  EXPECT_GT(samplePolar(v, after.rangeMeters, after.azimuthDeg, after.elevationDeg, Interpolation::Linear).value, 30.0);
  // Oblique ray (passes ~19.6 km from the antenna, meets the 25 km sphere at |cos| ~ 0.62, shade
  // ~0.74): darker than head-on.
  const glm::dvec3 side = glm::normalize(antenna + 20e3 * glm::normalize(glm::cross(dir, antenna)) - eye);
  const glm::dvec4 oblique = renderReferenceRay(v, st, eye, side, true);
  ASSERT_EQ(oblique.a, 1.0);
  EXPECT_LT(oblique.g, 0.9 * c.g);
  EXPECT_GE(oblique.g, 0.3 * expected.g - 1e-12);
}

// The real KLBB volume (NEXRAD Level II) of the shared data, laid out for rendering.
Result<PolarVolume> klbbPolarVolume() {
  const std::string path = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
  Result<RadarVolume> vol = readRadarVolume(path, ReadOptions{});
  if (!vol.ok()) return makeError(vol.error());
  Result<SiteResolution> site = resolveSite(vol->site, true);
  if (!site.ok()) return makeError(site.error());
  return buildPolarVolume(*vol, *site, BeamModel{});
}

// The real volume: KLBB (NEXRAD Level II), 64 x 36 DVR from 300 km south at 150 km height, looking
// north and down at the site. Non-empty, NaN-free; the time is printed for the bench budget.
TEST(ReferenceRenderer, RealNexradVolumeSmoke) {
  SKIP_WITHOUT_TEST_DATA(atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06"));
  Result<PolarVolume> pv = klbbPolarVolume();
  ASSERT_TRUE(pv.ok()) << pv.error();
  const GeolocationSite& s = pv->site;
  const globe::GeodesicPoint g = globe::geodesicDirect(s.latDeg, s.lonDeg, 180.0, 300e3);
  const glm::dvec3 eye = globe::geodeticToEcef({g.latDeg, g.lonDeg, 150e3});
  const RenderCamera cam = makeLookAtCamera(eye, antennaEcef(s), localUp(g.latDeg, g.lonDeg), 60.0, 64, 36);
  VolumeRenderSettings st;
  st.transfer = defaultReflectivityTransfer();
  const auto t0 = std::chrono::steady_clock::now();
  const VolumeImage img = renderReference(*pv, st, cam, true, 2);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(allFinite(img));
  int lit = 0;
  for (const glm::dvec4& c : img.rgbaPremultiplied) lit += c.a > 0.01 ? 1 : 0;
  std::printf("KLBB %zu sweeps, %d x %d DVR at %.0f m: %.2f s (2 threads), %d of %d pixels with alpha > 0.01\n",
              pv->sweeps.size(), cam.widthPx, cam.heightPx, st.stepMeters, seconds, lit, cam.widthPx * cam.heightPx);
  EXPECT_GT(lit, 20);
}

// Bit-identical images, and not an empty one (an empty image would prove nothing).
void expectIdenticalAndLit(const VolumeImage& a, const VolumeImage& b, const std::string& what) {
  ASSERT_EQ(a.rgbaPremultiplied.size(), b.rgbaPremultiplied.size()) << what;
  int lit = 0;
  for (std::size_t i = 0; i < a.rgbaPremultiplied.size(); ++i) {
    ASSERT_EQ(a.rgbaPremultiplied[i], b.rgbaPremultiplied[i]) << what << ", pixel " << i;
    lit += a.rgbaPremultiplied[i].a > 0.0 ? 1 : 0;
  }
  EXPECT_GT(lit, 0) << what;
}

// The shell pre-rejection is an acceleration only: on the real KLBB volume, from outside (oblique,
// straight down), from inside the shell and from the antenna itself, in every mode, and with
// other beam models (ke 1 and 2 on the uniform test volume), the image with rejection is
// bit-identical to the image without. The speed-up is printed.
TEST(ReferenceRenderer, ShellRejectionChangesNoPixel) {
  SKIP_WITHOUT_TEST_DATA(atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06"));
  Result<PolarVolume> pv = klbbPolarVolume();
  ASSERT_TRUE(pv.ok()) << pv.error();
  const GeolocationSite& s = pv->site;
  const glm::dvec3 antenna = antennaEcef(s);
  const glm::dmat3 enu = globe::enuAxes(s.latDeg, s.lonDeg);
  const globe::GeodesicPoint south = globe::geodesicDirect(s.latDeg, s.lonDeg, 180.0, 300e3);
  const globe::GeodesicPoint near = globe::geodesicDirect(s.latDeg, s.lonDeg, 45.0, 60e3);
  const std::vector<std::pair<std::string, RenderCamera>> cameras = {
      {"oblique", makeLookAtCamera(globe::geodeticToEcef({south.latDeg, south.lonDeg, 150e3}), antenna,
                                   localUp(south.latDeg, south.lonDeg), 60.0, 40, 24)},
      {"down", makeLookAtCamera(antenna + 400e3 * enu[2], antenna, enu[1], 60.0, 32, 32)},
      {"inside", makeLookAtCamera(globe::geodeticToEcef({near.latDeg, near.lonDeg, 3000.0}), antenna,
                                  localUp(near.latDeg, near.lonDeg), 70.0, 40, 24)},
      {"at the site", makeLookAtCamera(antenna, antenna + enu[1] + 0.05 * enu[2], enu[2], 90.0, 40, 24)}};
  double withS = 0.0, withoutS = 0.0;
  for (const auto& [name, cam] : cameras) {
    for (auto mode : {VolumeRenderMode::Dvr, VolumeRenderMode::Mip, VolumeRenderMode::Iso}) {
      VolumeRenderSettings st;
      st.mode = mode;
      st.stepMeters = 500.0;
      st.transfer = defaultReflectivityTransfer();
      const auto t0 = std::chrono::steady_clock::now();
      const VolumeImage a = renderReference(*pv, st, cam, true, 2, true);
      const auto t1 = std::chrono::steady_clock::now();
      const VolumeImage b = renderReference(*pv, st, cam, true, 2, false);
      const auto t2 = std::chrono::steady_clock::now();
      withS += std::chrono::duration<double>(t1 - t0).count();
      withoutS += std::chrono::duration<double>(t2 - t1).count();
      expectIdenticalAndLit(a, b, name + " mode " + std::to_string(static_cast<int>(mode)));
    }
  }
  std::printf("KLBB reference with shell rejection %.2f s, without %.2f s (%.1fx)\n", withS, withoutS,
              withoutS / withS);
  // Other beam models: ke 1 (no bending) and 2, on the uniform shell volume, looking along it.
  for (double ke : {1.0, 2.0}) {
    PolarVolume v = uniformVolume();
    v.beam.ke = ke;
    VolumeRenderSettings st;
    st.stepMeters = 500.0;
    st.transfer = defaultReflectivityTransfer();
    const glm::dvec3 site0 = antennaEcef(kSite);
    const glm::dmat3 e0 = globe::enuAxes(kSite.latDeg, kSite.lonDeg);
    const RenderCamera cam = makeLookAtCamera(site0 + 20e3 * e0[2] - 150e3 * e0[1], site0, e0[2], 60.0, 32, 24);
    const VolumeImage a = renderReference(v, st, cam, true, 2, true);
    const VolumeImage b = renderReference(v, st, cam, true, 2, false);
    expectIdenticalAndLit(a, b, "ke " + std::to_string(ke));
  }
}

}  // namespace
}  // namespace atmoglobe::volume
