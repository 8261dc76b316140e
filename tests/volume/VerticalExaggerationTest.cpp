// Vertical exaggeration: one rule (h -> e h above the ellipsoid) for every kind, exact in the
// reference path; the radar's local-sphere twin (what the GPU computes) measured against it.
#include "SyntheticGridVolume.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <gtest/gtest.h>

#include <iostream>
#include <random>

using namespace atmoglobe;

TEST(VerticalExaggeration, SamplerSeesTheTrueVolumeAtTheDrawnHeight) {
  testutil::SyntheticPolarGeometry geo;
  geo.sweeps = 6;
  geo.rays = 120;
  geo.gates = 300;
  geo.gateSpacingMeters = 500.0;
  const auto radar = testutil::syntheticRadarVolume(
      geo, [](double r, double az, double el) { return static_cast<float>(10.0 + r / 5000.0 + az / 36.0 + el); });
  const auto polar = testutil::polarOf(radar);
  const volume::PolarSampler inner(polar);
  const volume::ExaggeratedSampler drawn(inner, 4.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> az(0.0, 360.0), dist(5e3, 140e3), height(0.0, 12e3);
  int echoes = 0;
  const volume::BoundingSphere sphere = drawn.boundingSphere();
  for (int n = 0; n < 2000; ++n) {
    const globe::GeodesicPoint p = globe::geodesicDirect(geo.latDeg, geo.lonDeg, az(rng), dist(rng));
    const double h = height(rng);
    const glm::dvec3 trueEcef = globe::geodeticToEcef({p.latDeg, p.lonDeg, h});
    const glm::dvec3 drawnEcef = globe::geodeticToEcef({p.latDeg, p.lonDeg, 4.0 * h});
    const volume::VolumeSample a = inner.sample(trueEcef, volume::Interpolation::Linear);
    const volume::VolumeSample b = drawn.sample(drawnEcef, volume::Interpolation::Linear);
    ASSERT_EQ(a.state, b.state) << n;
    if (a.state == volume::VolumeSample::State::Echo) {
      ++echoes;
      // The same gate weights to a few nanometres of position: values equal to 1e-9.
      EXPECT_NEAR(a.value, b.value, 1e-9);
      // Every drawn point with data lies inside the drawn bounding sphere.
      EXPECT_LE(glm::length(drawnEcef - sphere.centreEcef), sphere.radiusMeters);
    }
  }
  EXPECT_GT(echoes, 500);
}

TEST(VerticalExaggeration, LocalSphereTwinIsWithinItsStatedBound) {
  // What the GPU does (LocalSphereBeam::unexaggerateEnu) against the exact geodetic path, to
  // 150 km and 15 km drawn height, at e = 5, at three latitudes.
  double worst = 0.0;
  for (double lat : {0.0, 45.0, 80.0}) {
    const volume::GeolocationSite site{lat, 10.0, 300.0};
    const volume::LocalSphereBeam beam = volume::localSphereBeam(site, volume::BeamModel{});
    for (double azDeg = 0.0; azDeg < 360.0; azDeg += 30.0)
      for (double d : {1e3, 50e3, 150e3})
        for (double hDrawn : {0.0, 3e3, 15e3}) {
          const globe::GeodesicPoint p = globe::geodesicDirect(lat, 10.0, azDeg, d);
          const glm::dvec3 drawnEcef = globe::geodeticToEcef({p.latDeg, p.lonDeg, hDrawn});
          const glm::dvec3 exact = globe::geodeticToEcef({p.latDeg, p.lonDeg, hDrawn / 5.0});
          const glm::dvec3 twin =
              beam.antennaEcef + beam.enuToEcef * beam.unexaggerateEnu(beam.enuOfEcef(drawnEcef), 5.0);
          worst = std::max(worst, glm::length(twin - exact));
          // And the two directions are inverses.
          const glm::dvec3 l = beam.enuOfEcef(exact);
          EXPECT_LT(glm::length(beam.unexaggerateEnu(beam.exaggerateEnu(l, 5.0), 5.0) - l), 1e-6);
        }
  }
  std::cout << "local-sphere exaggeration twin vs exact, e = 5, to 150 km: " << worst << " m\n";
  // (1 - 1/e) times the local sphere's height error against the ellipsoid, which grows as d^2:
  // the radar marcher's own inverse has a stated 5 m range bound (kLocalSphereMaxRangeErrorMeters).
  EXPECT_LT(worst, volume::kLocalSphereMaxRangeErrorMeters);
}

TEST(VerticalExaggeration, GridHeightsScaleAndFactorsAreChecked) {
  auto g = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 1.0, 3), testutil::evenlySpaced(40.0, 1.0, 3), testutil::evenlySpaced(0.0, 1000.0, 4),
      [](double, double) { return 100.0; }, [](double, double, double h) { return h; });
  const auto before = g.heightAboveEllipsoidMeters;
  volume::exaggerateGrid(g, 2.5);
  for (std::size_t n = 0; n < before.size(); ++n) EXPECT_FLOAT_EQ(g.heightAboveEllipsoidMeters[n], 2.5f * before[n]);
  EXPECT_TRUE(volume::validateVerticalExaggeration(1.0, "x"));
  EXPECT_FALSE(volume::validateVerticalExaggeration(0.0, "x"));
  EXPECT_FALSE(volume::validateVerticalExaggeration(NAN, "x"));
  EXPECT_FALSE(volume::validateVerticalExaggeration(1000.0, "x"));
}
