// Crop boxes: what is cut is exactly what lies outside, by the kind's own geometry (grid cell
// centres; radar gate centres located by the exact geolocation path).
#include "SyntheticGridVolume.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/volume/Crop.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/TransferFunction.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace atmoglobe;
using volume::CropBox;

TEST(Crop, LonLatBoxesWrapAtTheAntimeridian) {
  CropBox box;
  box.southDeg = -10;
  box.northDeg = 10;
  box.westDeg = 170;
  box.eastDeg = -170;  // across the antimeridian: 20 degrees wide
  EXPECT_TRUE(box.containsLonLat(0, 175));
  EXPECT_TRUE(box.containsLonLat(0, -175));
  EXPECT_TRUE(box.containsLonLat(0, 185));
  EXPECT_FALSE(box.containsLonLat(0, 0));
  EXPECT_FALSE(box.containsLonLat(0, 160));
  EXPECT_FALSE(box.containsLonLat(11, 175));
  EXPECT_TRUE(CropBox{}.containsLonLat(90, 0));
  CropBox bad = box;
  bad.bottomMeters = 5000;
  bad.topMeters = 1000;
  EXPECT_FALSE(volume::validateCropBox(bad, "x"));
  bad = box;
  bad.northDeg = -20;
  EXPECT_FALSE(volume::validateCropBox(bad, "x"));
}

TEST(Crop, GridValuesOutsideBecomeNoData) {
  auto g = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 0.5, 9), testutil::evenlySpaced(40.0, 0.5, 7),
      testutil::evenlySpaced(0.0, 1000.0, 10), [](double, double) { return 200.0; },
      [](double lat, double lon, double h) { return lat + lon + h / 1000.0; });
  const auto original = g.values;
  CropBox box;
  box.southDeg = 40.9;
  box.northDeg = 42.1;
  box.westDeg = 0.9;
  box.eastDeg = 3.1;
  box.bottomMeters = 1500;
  box.topMeters = 6200;
  const std::size_t cut = volume::cropGrid(g, box, nullptr);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < g.nz; ++k)
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i < g.nx; ++i) {
        const double h = g.heightMeters(k, j, i);
        const bool inside = g.latDeg[j] >= 40.9 && g.latDeg[j] <= 42.1 && g.lonDeg[i] >= 0.9 && g.lonDeg[i] <= 3.1 &&
                            h >= 1500 && h <= 6200;
        if (inside) {
          EXPECT_EQ(g.value(k, j, i), original[g.index(k, j, i)]);
          ++kept;
        } else {
          EXPECT_TRUE(std::isnan(g.value(k, j, i)));
        }
      }
  // Rows 41, 41.5, 42 x columns 1, 1.5, ..., 3 x levels at 2200..6200 m: 3 x 5 x 5.
  EXPECT_EQ(kept, 3u * 5u * 5u);
  EXPECT_EQ(cut, g.values.size() - kept);
  EXPECT_FLOAT_EQ(g.valueMin, 41.0f + 1.0f + 2.2f);
}

TEST(Crop, RadarGatesOutsideBecomeNoDataByTheExactGeolocation) {
  testutil::SyntheticPolarGeometry geo;
  geo.sweeps = 4;
  geo.rays = 72;
  geo.gates = 200;
  geo.gateSpacingMeters = 1000.0;
  const auto radar = testutil::syntheticRadarVolume(geo, [](double, double, double) { return 30.0f; });
  auto polar = testutil::polarOf(radar);
  CropBox box;
  box.southDeg = geo.latDeg - 0.5;
  box.northDeg = geo.latDeg + 1.0;
  box.westDeg = geo.lonDeg - 1.2;
  box.eastDeg = geo.lonDeg + 0.3;
  box.bottomMeters = 1500.0;
  box.topMeters = 5000.0;
  const std::size_t cut = volume::cropPolar(polar, box, nullptr);
  std::size_t kept = 0, disagree = 0;
  for (std::size_t k = 0; k < polar.sweeps.size(); ++k) {
    const auto& s = polar.sweeps[k];
    for (int ray = 0; ray < s.rayCount; ++ray)
      for (int gate = 0; gate < s.gateCount; ++gate) {
        const volume::GatePosition p =
            volume::geolocateGateExact(polar.site, polar.beam, s.azimuthDeg[static_cast<std::size_t>(ray)],
                                       s.elevationDeg, s.firstGateRangeMeters + s.gateSpacingMeters * gate);
        const bool inside = box.containsLonLat(p.latDeg, p.lonDeg) && p.heightMeters >= 1500.0 &&
                            p.heightMeters <= 5000.0;
        const float v = polar.values[(k * static_cast<std::size_t>(polar.maxRays) + static_cast<std::size_t>(ray)) *
                                         static_cast<std::size_t>(polar.maxGates) +
                                     static_cast<std::size_t>(gate)];
        kept += std::isnan(v) ? 0u : 1u;
        // cropPolar and the exact path share the beam model and the geodesic: they agree on every
        // gate except where a gate centre lies within a millimetre of a face.
        disagree += inside == !std::isnan(v) ? 0u : 1u;
      }
  }
  EXPECT_EQ(disagree, 0u);
  EXPECT_GT(kept, 100u);
  EXPECT_GT(cut, kept);
  EXPECT_EQ(polar.minValue, 30.0f);
}

TEST(TransferSettings, ValueRangeStretchesTheTableAndTheRamp) {
  const volume::TransferFunction nws = volume::defaultReflectivityTransfer();
  const auto& stops = nws.colors.stops();
  const double a = stops.front().value, b = stops.back().value;
  const volume::TransferFunction t = volume::withValueRange(nws, 0.0, 100.0);
  auto same = [](const volume::Rgba8& x, const volume::Rgba8& y) {
    return x.r == y.r && x.g == y.g && x.b == y.b && x.a == y.a;
  };
  // New value v shows the old table at a + v (b - a) / 100.
  for (double v : {0.0, 12.5, 50.0, 77.7, 100.0}) {
    const double old = a + v * (b - a) / 100.0;
    EXPECT_TRUE(same(t.colors.map(static_cast<float>(v)), nws.colors.map(static_cast<float>(old)))) << v;
  }
  EXPECT_NEAR(t.opacityZeroValue, (nws.opacityZeroValue - a) * 100.0 / (b - a), 1e-9);
  EXPECT_NEAR(t.opacityFullValue, (nws.opacityFullValue - a) * 100.0 / (b - a), 1e-9);
  const volume::TransferFunction r = volume::withOpacityRamp(nws, {20.0, 50.0, 0.5, 2000.0});
  EXPECT_EQ(r.opacityZeroValue, 20.0);
  EXPECT_EQ(r.opacityFullValue, 50.0);
  EXPECT_EQ(r.maxOpacity, 0.5);
  EXPECT_EQ(r.opacityReferenceMeters, 2000.0);
  EXPECT_NEAR(r.classify(35.0).a, 0.25 * nws.colors.map(35.0f).a / 255.0, 1e-12);
}
