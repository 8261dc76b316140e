// The polar render layout and the sampling rule (PolarVolume.h), on hand-made tiny volumes whose
// expected samples are worked out by hand in the comments (the rule is the reference; these
// check that the code follows it).
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarReader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <string>

namespace atmoglobe::volume {
namespace {

using State = PolarSample::State;

SiteResolution testSite() {
  SiteResolution s;
  s.site = GeolocationSite{40.0, 10.0, 500.0};
  return s;
}

// A PPI sweep with the given azimuths and gates; value(rayIndexInInput, gate).
Sweep makeSweep(double elevationDeg, const std::vector<float>& azimuthsDeg, std::uint32_t gateCount,
                double firstGateMeters, double spacingMeters,
                const std::function<float(std::size_t, std::uint32_t)>& value) {
  Sweep s;
  s.fixedAngleDeg = elevationDeg;
  s.mode = SweepMode::Ppi;
  s.azimuthDeg = azimuthsDeg;
  s.elevationDeg.assign(azimuthsDeg.size(), static_cast<float>(elevationDeg));
  s.firstGateRangeMeters = firstGateMeters;
  s.gateSpacingMeters = spacingMeters;
  s.gateCount = gateCount;
  for (std::size_t r = 0; r < azimuthsDeg.size(); ++r)
    for (std::uint32_t g = 0; g < gateCount; ++g) s.values.push_back(value(r, g));
  return s;
}

RadarVolume makeVolume(std::vector<Sweep> sweeps, double beamWidthDeg = 1.0) {
  RadarVolume v;
  v.format = "test";
  v.sourcePath = "tiny.nc";
  v.beamWidthDeg = beamWidthDeg;
  v.loadedField = FieldInfo{"DBZH", "dBZ", {}};
  v.fields = {v.loadedField};
  for (std::size_t i = 0; i < sweeps.size(); ++i) sweeps[i].indexInFile = static_cast<int>(i);
  v.sweeps = std::move(sweeps);
  return v;
}

PolarVolume build(const RadarVolume& rv) {
  Result<PolarVolume> pv = buildPolarVolume(rv, testSite(), BeamModel{});
  EXPECT_TRUE(pv.ok()) << (pv.ok() ? "" : pv.error());
  return pv.ok() ? *pv : PolarVolume{};
}

// Four rays at 0/90/180/270, four gates (centres 500, 1500, 2500, 3500 m), value 10 * ray + gate.
RadarVolume fourByFour(double elevationDeg = 1.0, float offset = 0.0f) {
  return makeVolume(
      {makeSweep(elevationDeg, {0.f, 90.f, 180.f, 270.f}, 4, 500.0, 1000.0, [offset](std::size_t r, std::uint32_t g) {
        return offset + 10.0f * static_cast<float>(r) + static_cast<float>(g);
      })});
}

TEST(PolarVolume, LayoutOfATinyVolume) {
  const PolarVolume v = build(fourByFour());
  ASSERT_EQ(v.sweeps.size(), 1u);
  EXPECT_EQ(v.maxRays, 4);
  EXPECT_EQ(v.maxGates, 4);
  EXPECT_EQ(v.values.size(), 16u);
  EXPECT_DOUBLE_EQ(v.maxRangeMeters, 4000.0);  // last centre 3500 + half a gate
  EXPECT_FLOAT_EQ(v.minValue, 0.0f);
  EXPECT_FLOAT_EQ(v.maxValue, 33.0f);
  EXPECT_EQ(v.fieldName, "DBZH");
  EXPECT_FLOAT_EQ(v.value(0, 2, 3), 23.0f);
  // The clip sphere holds the shell: at least maxRange, and not absurdly more (4 km range).
  EXPECT_GE(v.clipRadiusMeters, v.maxRangeMeters);
  EXPECT_LT(v.clipRadiusMeters, v.maxRangeMeters * 1.01);
}

// Nearest vs linear at points worked out by hand (one sweep: vertical weight 1).
TEST(PolarVolume, NearestAndLinearAtKnownPoints) {
  const PolarVolume v = build(fourByFour(1.0));
  // az 45 -> a = 0.5 (half way from ray 0 to ray 1); r 1500 -> g = 1 exactly.
  // Linear: 0.5 * v(0,1) + 0.5 * v(1,1) = 0.5 * 1 + 0.5 * 11 = 6.
  PolarSample s = samplePolar(v, 1500.0, 45.0, 1.0, Interpolation::Linear);
  ASSERT_EQ(s.state, State::Echo);
  EXPECT_NEAR(s.value, 6.0, 1e-12);
  // az 22.5 -> a = 0.25; r 2000 -> g = 1.5: ray 0: (1 + 2) / 2 = 1.5, ray 1: (11 + 12) / 2 = 11.5;
  // 0.75 * 1.5 + 0.25 * 11.5 = 4.
  s = samplePolar(v, 2000.0, 22.5, 1.0, Interpolation::Linear);
  ASSERT_EQ(s.state, State::Echo);
  EXPECT_NEAR(s.value, 4.0, 1e-12);
  // Nearest: a = 44/90 -> ray 0, g = 1.499 -> gate 1: 1. a = 46/90 -> ray 1, g = 1.501 -> gate 2: 12.
  s = samplePolar(v, 1999.0, 44.0, 1.0, Interpolation::Nearest);
  ASSERT_EQ(s.state, State::Echo);
  EXPECT_EQ(s.value, 1.0);
  s = samplePolar(v, 2001.0, 46.0, 1.0, Interpolation::Nearest);
  EXPECT_EQ(s.value, 12.0);
  // Halves round up: a = 0.5 -> ray 1, g = 1.5 -> gate 2.
  s = samplePolar(v, 2000.0, 45.0, 1.0, Interpolation::Nearest);
  EXPECT_EQ(s.value, 12.0);
}

// Between two sweeps: vertical weights (1 - t, t); nearest takes the closer, ties the lower.
TEST(PolarVolume, VerticalInterpolationBetweenSweeps) {
  RadarVolume a = fourByFour(1.0, 0.0f);
  a.sweeps.push_back(fourByFour(3.0, 100.0f).sweeps[0]);
  const PolarVolume v = build(a);
  ASSERT_EQ(v.sweeps.size(), 2u);
  // el 1.5: t = 0.25 -> 0.75 * v0 + 0.25 * (v0 + 100) = v0 + 25; v0 at (ray 1, gate 2) = 12.
  PolarSample s = samplePolar(v, 2500.0, 90.0, 1.5, Interpolation::Linear);
  ASSERT_EQ(s.state, State::Echo);
  EXPECT_NEAR(s.value, 37.0, 1e-12);
  EXPECT_EQ(samplePolar(v, 2500.0, 90.0, 2.0, Interpolation::Nearest).value, 12.0);     // tie -> lower
  EXPECT_EQ(samplePolar(v, 2500.0, 90.0, 2.001, Interpolation::Nearest).value, 112.0);  // closer to 3
  // Below the lowest sweep (but inside its half beam): sweep 0 alone; above the top: sweep 1 alone.
  EXPECT_NEAR(samplePolar(v, 2500.0, 90.0, 0.7, Interpolation::Linear).value, 12.0, 1e-12);
  EXPECT_NEAR(samplePolar(v, 2500.0, 90.0, 3.3, Interpolation::Linear).value, 112.0, 1e-12);
}

// Cyclic wrap between the last ray and the first.
TEST(PolarVolume, AzimuthWrapsBetweenLastAndFirstRay) {
  // Rays at 10, 100, 190, 280; value = 1000 * ray index (sorted order), one gate.
  const PolarVolume v =
      build(makeVolume({makeSweep(1.0, {10.f, 100.f, 190.f, 280.f}, 1, 500.0, 1000.0,
                                  [](std::size_t r, std::uint32_t) { return 1000.0f * static_cast<float>(r); })}));
  // az 325: from ray 3 (280) towards ray 0 (370): a = 3 + 45/90 = 3.5 -> 0.5 * 3000 + 0.5 * 0 = 1500.
  for (double az : {325.0, -35.0, 685.0}) {
    const PolarSample s = samplePolar(v, 500.0, az, 1.0, Interpolation::Linear);
    ASSERT_EQ(s.state, State::Echo) << az;
    EXPECT_NEAR(s.value, 1500.0, 1e-9) << az;
  }
  // az 5 (before the first ray): a = 3 + (365 - 280)/90 -> weight 85/90 on ray 0, 5/90 on ray 3.
  EXPECT_NEAR(samplePolar(v, 500.0, 5.0, 1.0, Interpolation::Linear).value, 3000.0 * 5.0 / 90.0, 1e-9);
  // Nearest: az 330 -> a = 3.556 -> round 4 -> ray 4 mod 4 = 0; az 320 -> a = 3.444 -> ray 3.
  EXPECT_EQ(samplePolar(v, 500.0, 330.0, 1.0, Interpolation::Nearest).value, 0.0);
  EXPECT_EQ(samplePolar(v, 500.0, 320.0, 1.0, Interpolation::Nearest).value, 3000.0);
  EXPECT_EQ(samplePolar(v, 500.0, 359.999, 1.0, Interpolation::Nearest).value, 0.0);
}

// Irregular azimuth spacing (0.5 and 1.5 deg alternating), rays given out of order: each ray holds
// its own azimuth as value, so a linear sample anywhere must return the azimuth itself (the ray
// coordinate follows azimuth, not index). Indexing by a uniform spacing would be off by up to
// 0.5 deg (1.25 deg maps to index 1.25 -> 0.5 + 0.25 * 1.5 = 0.875).
TEST(PolarVolume, IrregularAzimuthSpacingFollowsAzimuth) {
  std::vector<float> az;
  for (int k = 0; k < 180; ++k) {
    az.push_back(2.0f * static_cast<float>(k));
    az.push_back(2.0f * static_cast<float>(k) + 0.5f);
  }
  std::mt19937 rng(7);
  std::shuffle(az.begin(), az.end(), rng);
  const std::vector<float> given = az;
  const PolarVolume v = build(
      makeVolume({makeSweep(0.5, az, 2, 1000.0, 1000.0, [&given](std::size_t r, std::uint32_t) { return given[r]; })}));
  ASSERT_EQ(v.sweeps[0].rayCount, 360);
  EXPECT_TRUE(std::is_sorted(v.sweeps[0].azimuthDeg.begin(), v.sweeps[0].azimuthDeg.end()));
  std::uniform_real_distribution<double> u(0.0, 358.5);  // up to the last ray (358.5); then the wrap
  for (int i = 0; i < 2000; ++i) {
    const double a = u(rng);
    const PolarSample s = samplePolar(v, 1500.0, a, 0.5, Interpolation::Linear);
    ASSERT_EQ(s.state, State::Echo);
    EXPECT_NEAR(s.value, a, 1e-9) << a;  // azimuths 0.5-multiples: exact in float
  }
  EXPECT_NEAR(samplePolar(v, 1500.0, 1.25, 0.5, Interpolation::Linear).value, 1.25, 1e-12);
  // Nearest within a 1.5 deg gap: closer to 0.5 below 1.25, to 2.0 above.
  EXPECT_EQ(samplePolar(v, 1500.0, 1.2, 0.5, Interpolation::Nearest).value, 0.5);
  EXPECT_EQ(samplePolar(v, 1500.0, 1.3, 0.5, Interpolation::Nearest).value, 2.0);
  // In the wrap gap (358.5 -> 360): 359.25 is half way -> 0.5 * 358.5 + 0.5 * 0.
  EXPECT_NEAR(samplePolar(v, 1500.0, 359.25, 0.5, Interpolation::Linear).value, 179.25, 1e-9);
}

// Gate range limits: g in [-0.5, count - 0.5]; outside, NoData.
TEST(PolarVolume, GateRangeLimits) {
  // Gate centres 2000, 3000, 3999... : first 2000, spacing 1000, 4 gates -> r in [1500, 5500].
  const PolarVolume v =
      build(makeVolume({makeSweep(1.0, {0.f, 120.f, 240.f}, 4, 2000.0, 1000.0,
                                  [](std::size_t, std::uint32_t g) { return 20.0f + static_cast<float>(g); })}));
  for (Interpolation in : {Interpolation::Nearest, Interpolation::Linear}) {
    EXPECT_EQ(samplePolar(v, 1499.9, 0.0, 1.0, in).state, State::NoData);
    PolarSample s = samplePolar(v, 1500.0, 0.0, 1.0, in);
    ASSERT_EQ(s.state, State::Echo);
    EXPECT_EQ(s.value, 20.0);  // clamped to gate 0
    s = samplePolar(v, 5500.0, 0.0, 1.0, in);
    ASSERT_EQ(s.state, State::Echo);
    EXPECT_EQ(s.value, 23.0);  // clamped to the last gate
    EXPECT_EQ(samplePolar(v, 5500.1, 0.0, 1.0, in).state, State::NoData);
  }
}

// Vertical limits: above the top sweep + half beam (the cone of silence) and below the lowest
// sweep - half beam: NoData. Beam width from the file (0.96 deg here).
TEST(PolarVolume, ConeOfSilenceAndBelowTheLowestBeam) {
  RadarVolume rv = fourByFour(0.5);
  rv.sweeps.push_back(fourByFour(19.5).sweeps[0]);
  rv.beamWidthDeg = 0.96;
  const PolarVolume v = build(rv);
  EXPECT_DOUBLE_EQ(v.beamWidthDeg, 0.96);
  const double hb = 0.48;
  for (Interpolation in : {Interpolation::Nearest, Interpolation::Linear}) {
    EXPECT_EQ(samplePolar(v, 1500.0, 0.0, 19.5 + hb - 1e-9, in).state, State::Echo);
    EXPECT_EQ(samplePolar(v, 1500.0, 0.0, 19.5 + hb + 1e-9, in).state, State::NoData);
    EXPECT_EQ(samplePolar(v, 1500.0, 0.0, 90.0, in).state, State::NoData);
    EXPECT_EQ(samplePolar(v, 1500.0, 0.0, 0.5 - hb + 1e-9, in).state, State::Echo);
    EXPECT_EQ(samplePolar(v, 1500.0, 0.0, 0.5 - hb - 1e-9, in).state, State::NoData);
    EXPECT_EQ(samplePolar(v, 1500.0, 0.0, -5.0, in).state, State::NoData);
  }
  // No beam width in the file: 1 deg.
  rv.beamWidthDeg = 0.0;
  EXPECT_DOUBLE_EQ(build(rv).beamWidthDeg, 1.0);
}

// The 0.5 rule for mixes of Echo / NoEcho / NoData texels.
TEST(PolarVolume, HalfWeightRuleForNoEchoAndNoDataMixes) {
  // Rays at 0 and 180 (so a = az / 180 on [0, 180]); gates centred at 500 and 1500 (g = (r-500)/1000).
  // ray 0: [30, no echo]; ray 1: [no data, no data].
  const float grid[2][2] = {{30.0f, kNoEcho}, {kNoData, kNoData}};
  const PolarVolume v = build(makeVolume({makeSweep(1.0, {0.f, 180.f}, 2, 500.0, 1000.0,
                                                    [&grid](std::size_t r, std::uint32_t g) { return grid[r][g]; })}));
  // a = 0, g = 0.25: echo weight 0.75 -> Echo, value 30 (normalised by the echo weight).
  PolarSample s = samplePolar(v, 750.0, 0.0, 1.0, Interpolation::Linear);
  ASSERT_EQ(s.state, State::Echo);
  EXPECT_NEAR(s.value, 30.0, 1e-12);
  // a = 0, g = 0.75: echo 0.25, no echo 0.75 -> measured 1 -> NoEcho.
  EXPECT_EQ(samplePolar(v, 1250.0, 0.0, 1.0, Interpolation::Linear).state, State::NoEcho);
  // a = 0.5 (az 90), g = 0: echo 0.5 exactly -> Echo (>= 0.5), value 30.
  s = samplePolar(v, 500.0, 90.0, 1.0, Interpolation::Linear);
  ASSERT_EQ(s.state, State::Echo);
  EXPECT_NEAR(s.value, 30.0, 1e-12);
  // a = 0.6 (az 108), g = 0.4 (r 900): echo 0.4 * 0.6 = 0.24, no echo 0.4 * 0.4 = 0.16 -> 0.4 -> NoData.
  EXPECT_EQ(samplePolar(v, 900.0, 108.0, 1.0, Interpolation::Linear).state, State::NoData);
  // a = 0.25 (az 45), g = 0.6 (r 1100): echo 0.75 * 0.4 = 0.3, no echo 0.75 * 0.6 = 0.45 -> 0.75 -> NoEcho.
  EXPECT_EQ(samplePolar(v, 1100.0, 45.0, 1.0, Interpolation::Linear).state, State::NoEcho);
  // Nearest: the one texel's state.
  EXPECT_EQ(samplePolar(v, 1400.0, 10.0, 1.0, Interpolation::Nearest).state, State::NoEcho);
  EXPECT_EQ(samplePolar(v, 600.0, 170.0, 1.0, Interpolation::Nearest).state, State::NoData);

  // Two echoes of 20 and 40 at weight 0.25 each and 0.5 no echo: echo weight 0.5 -> Echo, value
  // (0.25 * 20 + 0.25 * 40) / 0.5 = 30 (not 15: the value is normalised by the echo weight).
  const float grid2[2][2] = {{20.0f, kNoEcho}, {40.0f, kNoEcho}};
  const PolarVolume v2 = build(makeVolume({makeSweep(
      1.0, {0.f, 180.f}, 2, 500.0, 1000.0, [&grid2](std::size_t r, std::uint32_t g) { return grid2[r][g]; })}));
  s = samplePolar(v2, 1000.0, 90.0, 1.0, Interpolation::Linear);
  ASSERT_EQ(s.state, State::Echo);
  EXPECT_NEAR(s.value, 30.0, 1e-12);
}

// Split cuts: equal fixed angles keep the first sweep that has the field; equal ray azimuths
// keep the first ray.
TEST(PolarVolume, SplitCutsAndDuplicateRaysAreDeduplicated) {
  auto constant = [](double el, float value) {
    return makeSweep(el, {0.f, 120.f, 240.f}, 3, 500.0, 1000.0, [value](std::size_t, std::uint32_t) { return value; });
  };
  PolarVolume v = build(makeVolume({constant(0.5, 10.0f), constant(0.5, 20.0f), constant(1.5, 30.0f)}));
  ASSERT_EQ(v.sweeps.size(), 2u);
  EXPECT_DOUBLE_EQ(v.sweeps[0].elevationDeg, 0.5);
  EXPECT_NEAR(samplePolar(v, 1000.0, 10.0, 0.5, Interpolation::Linear).value, 10.0, 1e-12);
  EXPECT_NEAR(samplePolar(v, 1000.0, 10.0, 1.5, Interpolation::Linear).value, 30.0, 1e-12);

  // The first 0.5 cut without values (field absent in that cut): the second one is kept.
  Sweep empty = constant(0.5, 10.0f);
  empty.values.clear();
  empty.gateCount = 0;
  v = build(makeVolume({empty, constant(0.5, 20.0f), constant(1.5, 30.0f)}));
  ASSERT_EQ(v.sweeps.size(), 2u);
  EXPECT_NEAR(samplePolar(v, 1000.0, 10.0, 0.5, Interpolation::Linear).value, 20.0, 1e-12);

  // Equal azimuths in one sweep: the first ray (in file order) is kept.
  v = build(makeVolume({makeSweep(0.5, {0.f, 90.f, 90.f, 180.f}, 1, 500.0, 1000.0,
                                  [](std::size_t r, std::uint32_t) { return static_cast<float>(r); })}));
  EXPECT_EQ(v.sweeps[0].rayCount, 3);
  EXPECT_EQ(samplePolar(v, 500.0, 90.0, 0.5, Interpolation::Nearest).value, 1.0);
}

TEST(PolarVolume, RhiAndEmptyVolumesAreErrors) {
  RadarVolume rhi = fourByFour();
  rhi.sweeps[0].mode = SweepMode::Rhi;
  Result<PolarVolume> r = buildPolarVolume(rhi, testSite(), BeamModel{});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("RHI"), std::string::npos) << r.error();
  EXPECT_NE(r.error().find("tiny.nc"), std::string::npos) << r.error();

  RadarVolume noValues = fourByFour();
  noValues.loadedField = FieldInfo{};
  r = buildPolarVolume(noValues, testSite(), BeamModel{});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("no field values"), std::string::npos) << r.error();

  RadarVolume badGeometry = fourByFour();
  badGeometry.sweeps[0].gateSpacingMeters = 0.0;
  EXPECT_FALSE(buildPolarVolume(badGeometry, testSite(), BeamModel{}).ok());
  RadarVolume badAzimuth = fourByFour();
  badAzimuth.sweeps[0].azimuthDeg[1] = std::nanf("");
  EXPECT_FALSE(buildPolarVolume(badAzimuth, testSite(), BeamModel{}).ok());
}

// The real RHI file of the shared data is refused with the message.
TEST(PolarVolume, RealRhiFileIsRefused) {
  const std::string path =
      atmoglobe_test::testDataDir() + "/radar_cfradial/cfrad.20211011_201733.023_to_20211011_201745.299_DOW8_RHI.nc";
  SKIP_WITHOUT_TEST_DATA(path);
  Result<RadarVolume> vol = readRadarVolume(path, ReadOptions{});
  ASSERT_TRUE(vol.ok()) << vol.error();
  Result<SiteResolution> site = resolveSite(vol->site, false);
  ASSERT_TRUE(site.ok()) << site.error();
  Result<PolarVolume> pv = buildPolarVolume(*vol, *site, BeamModel{});
  ASSERT_FALSE(pv.ok());
  EXPECT_NE(pv.error().find("RHI volumes cannot be volume-rendered"), std::string::npos) << pv.error();
}

// The GPU's azimuth table (rayCoordinateTable, interpolated linearly as the texture unit does,
// here in float like the shader) against the exact ray coordinate, on every sweep of the real
// KLBB (super-resolution, 720 rays) and AU40 (360 rays) volumes and a hand-made irregular sweep.
// The table is exact between ray centres; in a bin holding a centre between spacings d1 and d2
// the linear interpolation of the kinked function is off by at most
// binDeg x |1/d1 - 1/d2| / 4 rays. Each sweep is held to that bound (from its own spacings)
// plus 2e-4 rays of float rounding (the coordinate near 720 has a float spacing of 6e-5), and
// every file to 0.01 rays (0.005 deg at 0.5 deg spacing, 1/200 of a beam width).
TEST(PolarVolume, AzimuthTableMatchesTheExactRayCoordinate) {
  constexpr int kBins = 8192;
  auto check = [](const PolarVolume& v, const std::string& what) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> azDist(0.0, 360.0);
    double worstFile = 0.0;
    for (const PolarSweepLayout& s : v.sweeps) {
      const std::vector<float> table = rayCoordinateTable(s, kBins);
      ASSERT_EQ(table.size(), static_cast<std::size_t>(kBins) + 1);
      ASSERT_TRUE(std::is_sorted(table.begin(), table.end())) << what;
      ASSERT_GE(table.front(), -1.0f);
      ASSERT_LE(table.back(), static_cast<float>(s.rayCount));
      const int n = s.rayCount;
      double bound = 0.0;
      for (int r = 0; r < n; ++r) {
        const double prev = static_cast<double>(s.azimuthDeg[static_cast<std::size_t>(r)]) -
                            (r > 0 ? static_cast<double>(s.azimuthDeg[static_cast<std::size_t>(r - 1)])
                                   : static_cast<double>(s.azimuthDeg.back()) - 360.0);
        const double next = (r + 1 < n ? static_cast<double>(s.azimuthDeg[static_cast<std::size_t>(r + 1)])
                                       : static_cast<double>(s.azimuthDeg.front()) + 360.0) -
                            static_cast<double>(s.azimuthDeg[static_cast<std::size_t>(r)]);
        bound = std::max(bound, 360.0 / kBins * std::abs(1.0 / prev - 1.0 / next) / 4.0);
      }
      double worst = 0.0;
      for (int i = 0; i < 20000; ++i) {
        // Every ray centre and just past it (the kinks), then random azimuths; in [0, 360) as
        // the shader's atan gives them.
        const double az = i < 2 * n ? std::fmod(static_cast<double>(s.azimuthDeg[static_cast<std::size_t>(i / 2)]) +
                                                    (i % 2 ? 1e-4 : 0.0),
                                                360.0)
                                    : azDist(rng);
        const float x = static_cast<float>(az) * (static_cast<float>(kBins) / 360.0f);
        const int j = std::min(static_cast<int>(x), kBins - 1);
        const float f = x - static_cast<float>(j);
        float a = table[static_cast<std::size_t>(j)] * (1.0f - f) + table[static_cast<std::size_t>(j) + 1] * f;
        if (a < 0.0f) a += static_cast<float>(n);  // before the first ray: the rule's [n - 1, n)
        // Cyclic: n - 1e-7 (row n, the copy of ray 0) and 0 are the same place.
        const double d = std::abs(static_cast<double>(a) - rayCoordinate(s, az));
        worst = std::max(worst, std::min(d, std::abs(d - n)));
      }
      EXPECT_LE(worst, bound + 2e-4) << what << " sweep at " << s.elevationDeg << " deg";
      worstFile = std::max(worstFile, worst);
    }
    EXPECT_LT(worstFile, 0.01) << what;
    std::cout << what << ": azimuth table max error " << worstFile << " rays\n";
  };
  for (const char* rel : {"/radar_nexrad/KLBB20160601_150025_V06", "/radar_odim/40_20181220_060630.pvol.h5"}) {
    const std::string path = atmoglobe_test::testDataDir() + rel;
    SKIP_WITHOUT_TEST_DATA(path);
    Result<RadarVolume> vol = readRadarVolume(path, ReadOptions{});
    ASSERT_TRUE(vol.ok()) << vol.error();
    Result<SiteResolution> site = resolveSite(vol->site, false);
    ASSERT_TRUE(site.ok()) << site.error();
    Result<PolarVolume> pv = buildPolarVolume(*vol, *site, BeamModel{});
    ASSERT_TRUE(pv.ok()) << pv.error();
    check(*pv, rel);
  }
  // Irregular: spacings 1, 1.1, 0.9, ... deg around the circle, first ray off zero.
  std::vector<float> az;
  for (double a = 0.37; a < 360.0; a += (az.size() % 3 == 0 ? 1.0 : az.size() % 3 == 1 ? 1.1 : 0.9))
    az.push_back(static_cast<float>(a));
  check(build(makeVolume({makeSweep(0.5, az, 10, 0.0, 250.0, [](std::size_t, std::uint32_t) { return 1.0f; })})),
        "irregular");
}

// Cartesian-equivalent bytes, worked by hand: one sweep at 0 deg, beam 1 deg, gates 250 m to
// 100 km -> 800 x 800 columns; vertical extent from the -0.5 deg to the +0.5 deg beam edge at
// 100 km, heights from the closed form h = sqrt(r^2 + Re^2 + 2 r Re sin(theta)) - Re.
TEST(PolarVolume, CartesianEquivalentBytes) {
  const PolarVolume v = build(makeVolume(
      {makeSweep(0.0, {0.f, 90.f, 180.f, 270.f}, 400, 125.0, 250.0, [](std::size_t, std::uint32_t) { return 1.0f; })}));
  ASSERT_DOUBLE_EQ(v.maxRangeMeters, 100000.0);
  const double re = 4.0 / 3.0 * globe::geocentricRadiusMeters(40.0);
  auto h = [re](double r, double elDeg) {
    return std::sqrt(r * r + re * re + 2.0 * r * re * std::sin(degreesToRadians(elDeg))) - re;
  };
  const double nz = std::ceil((h(1e5, 0.5) - h(1e5, -0.5)) / 250.0);
  EXPECT_EQ(nz, 7.0);  // ~1745 m of beam at 100 km (2 * 100 km * tan(0.5 deg)) in 250 m voxels
  EXPECT_DOUBLE_EQ(cartesianEquivalentBytes(v, 4.0), 800.0 * 800.0 * nz * 4.0);
  EXPECT_EQ(v.byteSize(), 4u * 400u * 4u);
}

}  // namespace
}  // namespace atmoglobe::volume
