// The GL-free geometry of the volume pipeline: the sampler interface (polar and analytic), the
// empty-space grid's conservativeness, the local-sphere beam model's error against the exact
// inverse, the WGS84 curvature radii, and the reference renderer's rule for several volumes.
#include "SyntheticPolarVolume.h"

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/AnalyticVolume.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/OccupancyGrid.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <span>

namespace {

using namespace atmoglobe;

// 10 PPI sweeps 0.5..9.5 deg, 180 rays of 2 deg, 240 gates of 500 m from 1 km (to 120 km): a
// storm 60 km north-east, echo-free elsewhere.
volume::PolarVolume radarAt(double latDeg, double lonDeg) {
  testutil::SyntheticPolarGeometry g;
  g.latDeg = latDeg;
  g.lonDeg = lonDeg;
  g.antennaHeightMeters = 500.0;
  g.rays = 180;
  g.gates = 240;
  g.firstGateMeters = 1000.0;
  g.gateSpacingMeters = 500.0;
  return testutil::polarOf(testutil::syntheticRadarVolume(g, [](double r, double az, double el) {
    const double x = 60.0 * std::exp(-std::pow((r - 60e3) / 15e3, 2) - std::pow((az - 45.0) / 20.0, 2) -
                                     std::pow((el - 3.0) / 3.0, 2));
    return x < 5.0 ? volume::kNoEcho : static_cast<float>(x);
  }));
}

}  // namespace

TEST(CurvatureRadii, MatchKnownValuesAndEuler) {
  // WGS84 at the equator: M = a (1 - e^2) = 6335439.327 m, N = a; at the pole M = N = a^2 / b.
  EXPECT_NEAR(globe::meridionalRadiusMeters(0.0), 6335439.327, 1e-3);
  EXPECT_NEAR(globe::primeVerticalRadiusMeters(0.0), globe::kWgs84A, 1e-6);
  EXPECT_NEAR(globe::meridionalRadiusMeters(90.0), globe::kWgs84A * globe::kWgs84A / globe::kWgs84B, 1e-3);
  EXPECT_NEAR(globe::primeVerticalRadiusMeters(90.0), globe::kWgs84A * globe::kWgs84A / globe::kWgs84B, 1e-3);
  EXPECT_NEAR(globe::normalSectionRadiusMeters(45.0, 0.0), globe::meridionalRadiusMeters(45.0), 1e-6);
  EXPECT_NEAR(globe::normalSectionRadiusMeters(45.0, 90.0), globe::primeVerticalRadiusMeters(45.0), 1e-6);
  EXPECT_GT(globe::normalSectionRadiusMeters(45.0, 45.0), globe::meridionalRadiusMeters(45.0));
  EXPECT_LT(globe::normalSectionRadiusMeters(45.0, 45.0), globe::primeVerticalRadiusMeters(45.0));
}

// The CPU twin of the GPU's beam inverse against the exact inverse, out to 460 km, at several
// latitudes: the stated bounds of Geolocation.h hold, and the round trip through enuOf is exact.
TEST(LocalSphereBeam, ErrorAgainstTheExactInverseIsWithinTheStatedBounds) {
  const volume::BeamModel model;
  double maxRange = 0.0, maxAz = 0.0, maxEl = 0.0, maxRoundTrip = 0.0;
  for (double lat : {0.0, 33.654, 60.0, 89.9}) {
    const volume::GeolocationSite site{lat, -101.8, 1000.0};
    const volume::LocalSphereBeam beam = volume::localSphereBeam(site, model);
    for (double range : {1e3, 50e3, 150e3, 300e3, 460e3})
      for (double az = 0.5; az < 360.0; az += 37.0)
        for (double el : {0.0, 0.5, 3.0, 10.0, 20.0}) {
          const volume::GatePosition g = volume::geolocateGateExact(site, model, az, el, range);
          const volume::AntennaCoordinates local = beam.antennaCoordinates(beam.enuOfEcef(g.ecef));
          maxRange = std::max(maxRange, std::abs(local.rangeMeters - range));
          double dAz = std::abs(local.azimuthDeg - az);
          maxAz = std::max(maxAz, std::min(dAz, 360.0 - dAz));
          maxEl = std::max(maxEl, std::abs(local.elevationDeg - el));
          const volume::AntennaCoordinates back = beam.antennaCoordinates(beam.enuOf(range, az, el));
          maxRoundTrip =
              std::max({maxRoundTrip, std::abs(back.rangeMeters - range), std::abs(back.elevationDeg - el) * 1e3});
        }
  }
  std::cout << "local sphere vs exact inverse to 460 km: max |range| " << maxRange << " m, |azimuth| " << maxAz
            << " deg, |elevation| " << maxEl << " deg\n";
  EXPECT_LE(maxRange, volume::kLocalSphereMaxRangeErrorMeters);
  EXPECT_LE(maxAz, volume::kLocalSphereMaxAngleErrorDeg);
  EXPECT_LE(maxEl, volume::kLocalSphereMaxAngleErrorDeg);
  // enuOf and antennaCoordinates are inverses of each other (double rounding only).
  EXPECT_LT(maxRoundTrip, 1e-6);
}

// Random points inside every echo are never in a grid cell below their value.
TEST(OccupancyGrid, IsConservativeForRandomPointsInsideEchoes) {
  const volume::PolarVolume v = radarAt(33.654, -101.814);
  const volume::OccupancyGrid grid = volume::buildOccupancyGrid(v);
  ASSERT_EQ(grid.cells, glm::ivec3(256, 256, 32));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> range(1e3, 121e3), az(0.0, 360.0), el(-0.1, 10.1);
  int echoes = 0, violations = 0;
  for (int n = 0; n < 200000; ++n) {
    const double r = range(rng), a = az(rng), e = el(rng);
    const volume::PolarSample s = volume::samplePolar(v, r, a, e, volume::Interpolation::Linear);
    if (s.state != volume::PolarSample::State::Echo) continue;
    ++echoes;
    const glm::dvec3 ecef = volume::geolocateGateExact(v.site, v.beam, a, e, r).ecef;
    if (grid.maxAtLocal(grid.localOfEcef(ecef)) < static_cast<float>(s.value)) ++violations;
  }
  std::cout << echoes << " echo points, " << violations << " in a cell below their value\n";
  ASSERT_GT(echoes, 5000);
  EXPECT_EQ(violations, 0);
  // And the grid is useful: the box is fitted to the echo's support, yet the storm's blob leaves a
  // good part of its cells empty (46 % here).
  std::size_t empty = 0;
  for (float x : grid.maxValues) empty += x == volume::kOccupancyEmptyValue;
  EXPECT_GT(static_cast<double>(empty) / static_cast<double>(grid.maxValues.size()), 0.3);
}

// The cells of a network's empty-space grid follow the boxes' extent, within a total.
TEST(OccupancyGrid, CellsFollowTheExtentWithinTheTotal) {
  const glm::dvec3 target(4000.0, 4000.0, 1000.0);
  auto box = [](glm::dvec3 size) {
    return volume::OccupancyBox{glm::dvec3(-1000.0), glm::dvec3(-1000.0) + size, 1.0f};
  };
  // One radar's 460 km x 460 km x 20 km: 115 + 2 spare across, 20 + 2 up.
  EXPECT_EQ(volume::occupancyCellsFor({box({460e3, 460e3, 20e3})}, target, std::size_t{1} << 23),
            glm::ivec3(117, 117, 22));
  // Two boxes: their union.
  EXPECT_EQ(volume::occupancyCellsFor({box({100e3, 8e3, 4e3}), box({8e3, 200e3, 4e3})}, target, 1u << 23),
            glm::ivec3(27, 52, 8));
  // A continent, 4500 x 2800 km and 500 km deep (the Earth's curvature in a tangent frame): 1127 x
  // 702 x 502 cells wanted, 2^23 allowed; every axis scaled alike (a factor 0.27).
  const glm::ivec3 big = volume::occupancyCellsFor({box({4500e3, 2800e3, 500e3})}, target, std::size_t{1} << 23);
  EXPECT_LE(static_cast<double>(big.x) * big.y * big.z, static_cast<double>(1u << 23));
  EXPECT_GT(static_cast<double>(big.x) * big.y * big.z, 0.95 * static_cast<double>(1u << 23));
  EXPECT_NEAR(static_cast<double>(big.x) / big.y, 1127.0 / 702.0, 0.02);
  EXPECT_NEAR(static_cast<double>(big.y) / big.z, 702.0 / 502.0, 0.02);
  // A flat box keeps its 8 minimum up and gives the room to the other axes.
  const glm::ivec3 flat = volume::occupancyCellsFor({box({4000e3, 4000e3, 1e3})}, target, 80000);
  EXPECT_EQ(flat.z, 8);
  EXPECT_LE(flat.x * flat.y * flat.z, 80000);
  EXPECT_GE(flat.x * flat.y * flat.z, 80000 - 2 * 8 * 100);
  EXPECT_EQ(volume::occupancyCellsFor({}, target, 1000), glm::ivec3(8));
}

// A network step redoes only the cells of the radars that changed: the grid rebuilt within the
// range of a radar's old and new boxes, from the boxes of the radars that reach that range, is
// bit for bit the grid built whole from the new boxes (cells and blocks).
TEST(OccupancyGrid, CellsRebuiltWithinARangeEqualTheGridBuiltWhole) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Eight "radars" of 300 random boxes each within 400 x 400 x 15 km squares on a 4 x 2 pattern
  // 300 km apart (neighbours overlap), values -10..70.
  auto radarBoxes = [&](int k) {
    const glm::dvec3 centre(300e3 * (k % 4), 300e3 * (k / 4), 0.0);
    std::vector<volume::OccupancyBox> boxes;
    for (int i = 0; i < 300; ++i) {
      const glm::dvec3 lo = centre + glm::dvec3(400e3 * (unit(rng) - 0.5), 400e3 * (unit(rng) - 0.5), 12e3 * unit(rng));
      const glm::dvec3 size(30e3 * unit(rng), 8e3 * unit(rng), 3e3 * unit(rng));
      boxes.push_back({lo, lo + size, static_cast<float>(-10.0 + 80.0 * unit(rng))});
    }
    return boxes;
  };
  std::vector<std::vector<volume::OccupancyBox>> radars;
  for (int k = 0; k < 8; ++k) radars.push_back(radarBoxes(k));
  // Anchors that fix the union, so that the layout stays when radar 1 changes.
  radars[0].push_back({glm::dvec3(-260e3, -260e3, -1e3), glm::dvec3(-250e3, -250e3, 0.0), 1.0f});
  radars[7].push_back({glm::dvec3(1150e3, 550e3, 20e3), glm::dvec3(1160e3, 560e3, 21e3), 1.0f});
  auto sourcesOf = [](const std::vector<std::vector<volume::OccupancyBox>>& r) {
    std::vector<std::span<const volume::OccupancyBox>> out;
    for (const auto& b : r) out.emplace_back(b);
    return out;
  };
  auto boundsOf = [](const std::vector<std::vector<volume::OccupancyBox>>& r) {
    volume::OccupancyBox u = volume::occupancyBounds(std::span<const volume::OccupancyBox>());
    for (const auto& b : r) u = volume::occupancyBounds(u, volume::occupancyBounds(b));
    return u;
  };
  const glm::dvec3 origin(6378137.0, 0.0, 0.0);
  const glm::dmat3 frame(glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0));
  const glm::ivec3 cells(120, 90, 30);
  volume::OccupancyGrid grid = volume::buildOccupancyGrid(origin, frame, sourcesOf(radars), boundsOf(radars), cells);
  // The one-list build is the same grid.
  std::vector<volume::OccupancyBox> joined;
  for (const auto& b : radars) joined.insert(joined.end(), b.begin(), b.end());
  EXPECT_EQ(volume::buildOccupancyGrid(origin, frame, joined, cells).maxValues, grid.maxValues);

  const volume::OccupancyBox oldExtent = volume::occupancyBounds(radars[1]);
  radars[1] = radarBoxes(1);
  const volume::OccupancyBox newExtent = volume::occupancyBounds(radars[1]);
  const volume::OccupancyGrid whole =
      volume::buildOccupancyGrid(origin, frame, sourcesOf(radars), boundsOf(radars), cells);
  ASSERT_TRUE(volume::sameOccupancyLayout(volume::occupancyLayout(origin, frame, boundsOf(radars), cells), grid));
  ASSERT_NE(whole.maxValues, grid.maxValues) << "radar 1's new boxes change cells";
  const volume::OccupancyCellRange before = volume::occupancyCellsOf(grid, oldExtent.lo, oldExtent.hi);
  const volume::OccupancyCellRange after = volume::occupancyCellsOf(grid, newExtent.lo, newExtent.hi);
  const volume::OccupancyCellRange range{glm::min(before.first, after.first), glm::max(before.last, after.last)};
  std::vector<std::span<const volume::OccupancyBox>> reaching;
  for (const auto& b : radars) {
    const volume::OccupancyBox e = volume::occupancyBounds(b);
    if (volume::overlaps(volume::occupancyCellsOf(grid, e.lo, e.hi), range)) reaching.emplace_back(b);
  }
  EXPECT_LT(reaching.size(), radars.size()) << "the radars far away are not visited";
  volume::rebuildOccupancyCells(grid, range, reaching);
  EXPECT_EQ(grid.maxValues, whole.maxValues);
  EXPECT_EQ(grid.blockMaxValues, whole.blockMaxValues);
}

// The band of straight elevations holds every beam point out to the clip radius.
TEST(StraightElevationBand, HoldsEveryBeamPoint) {
  const volume::PolarVolume v = radarAt(45.0, 7.0);
  const volume::StraightElevationBand band = volume::straightElevationBand(v);
  const volume::LocalSphereBeam beam = volume::localSphereBeam(v.site, v.beam);
  const double hb = 0.5 * v.beamWidthDeg;
  for (double r = 1e3; r <= v.maxRangeMeters; r += 5e3)
    for (double e : {v.sweeps.front().elevationDeg - hb, v.sweeps.back().elevationDeg + hb}) {
      const glm::dvec3 enu = beam.enuOfEcef(volume::geolocateGateExact(v.site, v.beam, 30.0, e, r).ecef);
      const double chord = glm::length(enu);
      const double elS = radiansToDegrees(std::asin(enu.z / chord));
      EXPECT_GE(elS, band.loDegAt(chord)) << r;
      EXPECT_LE(elS, band.hiDegAt(chord)) << r;
    }
}

// The analytic shell's sampler: its states, and a ray through its centre.
TEST(UniformShell, SamplesAndPathLength) {
  volume::UniformShell shell;
  shell.centre = {10.0, 20.0, 5000.0};
  shell.innerRadiusMeters = 1000.0;
  shell.outerRadiusMeters = 3000.0;
  const volume::UniformShellSampler s(shell);
  const glm::dvec3 c = s.centreEcef();
  EXPECT_EQ(s.sample(c, volume::Interpolation::Linear).state, volume::VolumeSample::State::NoEcho);
  EXPECT_EQ(s.sample(c + glm::dvec3(2000.0, 0, 0), volume::Interpolation::Linear).state,
            volume::VolumeSample::State::Echo);
  EXPECT_EQ(s.sample(c + glm::dvec3(0, 3001.0, 0), volume::Interpolation::Linear).state,
            volume::VolumeSample::State::NoData);
  const glm::dvec3 eye = c + glm::dvec3(0, 0, -10000.0);
  EXPECT_NEAR(s.pathLengthInside(eye, glm::dvec3(0, 0, 1), 0.0, 1e30), 4000.0, 1e-6);
  EXPECT_TRUE(s.provablyEmpty(c + glm::dvec3(5000.0, 0, 0)));
}

// A box of latitudes and longitudes: edges included, longitudes modulo 360 (across the
// antimeridian), a span of 360 every longitude; a sampler outside it has no data inside and the
// inner sampler's samples elsewhere.
TEST(SamplerOutsideBox, HasNoDataInTheBoxAndTheInnerSamplesElsewhere) {
  const volume::LonLatBox seam{170.0, 20.0, -10.0, 10.0};  // 170 E .. 170 W
  EXPECT_TRUE(seam.contains(0.0, 175.0));
  EXPECT_TRUE(seam.contains(0.0, -175.0));
  EXPECT_TRUE(seam.contains(10.0, 190.0));    // edges, a longitude past 180
  EXPECT_TRUE(seam.contains(-10.0, -190.0));  // = 170 E
  EXPECT_FALSE(seam.contains(0.0, -169.0));
  EXPECT_FALSE(seam.contains(0.0, 169.0));
  EXPECT_FALSE(seam.contains(10.001, 175.0));
  const volume::LonLatBox ring{0.0, 360.0, 60.0, 90.0};
  EXPECT_TRUE(ring.contains(70.0, -123.0));
  EXPECT_FALSE(ring.contains(59.0, -123.0));

  volume::UniformShell shell;
  shell.centre = {10.0, 20.0, 5000.0};
  shell.innerRadiusMeters = 1000.0;
  shell.outerRadiusMeters = 3000.0;
  const volume::UniformShellSampler inner(shell);
  // The box holds the shell's northern half (north of its centre's latitude).
  const volume::SamplerOutsideBox outside(inner, volume::LonLatBox{19.0, 2.0, 10.0, 11.0});
  const glm::dvec3 c = inner.centreEcef();
  const glm::dvec3 north = globe::geodeticToEcef({10.015, 20.0, 5000.0});  // 1.66 km north: in the shell
  const glm::dvec3 south = globe::geodeticToEcef({9.985, 20.0, 5000.0});
  EXPECT_EQ(inner.sample(north, volume::Interpolation::Linear).state, volume::VolumeSample::State::Echo);
  EXPECT_EQ(outside.sample(north, volume::Interpolation::Linear).state, volume::VolumeSample::State::NoData);
  const volume::VolumeSample a = outside.sample(south, volume::Interpolation::Linear);
  const volume::VolumeSample b = inner.sample(south, volume::Interpolation::Linear);
  EXPECT_EQ(a.state, volume::VolumeSample::State::Echo);
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(outside.boundingSphere().radiusMeters, inner.boundingSphere().radiusMeters);
  const glm::dvec3 eye = c + glm::dvec3(0, 0, -10000.0);
  const volume::RayInterval ri = outside.rayInterval(eye, glm::dvec3(0, 0, 1));
  EXPECT_EQ(ri.tEnterMeters, inner.rayInterval(eye, glm::dvec3(0, 0, 1)).tEnterMeters);
}

// Two layers: where they do not overlap, each pixel is that layer's own picture exactly.
TEST(ReferenceRenderer, SeveralLayersEqualEachAloneWhereTheyDoNotOverlap) {
  volume::UniformShell a, b;
  a.centre = {0.0, 0.0, 10000.0};
  b.centre = {0.0, 0.3, 10000.0};  // 33 km east
  a.outerRadiusMeters = b.outerRadiusMeters = 12000.0;
  a.value = 30.0;
  b.value = 50.0;
  const volume::UniformShellSampler sa(a), sb(b);
  volume::VolumeRenderSettings st;
  st.transfer = volume::defaultReflectivityTransfer();
  st.stepMeters = 200.0;
  const glm::dvec3 mid = globe::geodeticToEcef({0.0, 0.15, 10000.0});
  const glm::dvec3 eye = globe::geodeticToEcef({-1.0, 0.15, 10000.0});
  const volume::RenderCamera cam = volume::makeLookAtCamera(eye, mid, globe::enuAxes(0.0, 0.15)[2], 30.0, 48, 24);
  const volume::VolumeImage both = volume::renderReference({{&sa, st}, {&sb, st}}, cam, false, 2);
  const volume::VolumeImage onlyA = volume::renderReference({{&sa, st}}, cam, false, 2);
  const volume::VolumeImage onlyB = volume::renderReference({{&sb, st}}, cam, false, 2);
  int single = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 48; ++x) {
      const glm::dvec3 dir = volume::pixelRayDirection(cam, x + 0.5, y + 0.5);
      const bool inA = !sa.rayInterval(eye, dir).empty(), inB = !sb.rayInterval(eye, dir).empty();
      if (inA == inB) continue;
      ++single;
      EXPECT_EQ(both.at(x, y), inA ? onlyA.at(x, y) : onlyB.at(x, y));
    }
  EXPECT_GT(single, 50);
}

// Clusters: spheres that meet share a cluster; clusters' enclosing spheres are disjoint and hold
// their members; back to front is exact: on every ray meeting two clusters, the one drawn later
// (nearer) lies wholly before the other.
TEST(VolumeClusters, DisjointClustersAreOrderedExactlyForEveryRay) {
  using volume::BoundingSphere;
  // A and B meet; C is far; D meets neither A nor B but meets their enclosing sphere.
  const std::vector<BoundingSphere> fixed = {
      {{0, 0, 0}, 1.0}, {{1.5, 0, 0}, 1.0}, {{10, 0, 0}, 1.0}, {{0.75, 2.1, 0}, 0.5}};
  std::vector<volume::VolumeCluster> c = volume::clusterBySphere(fixed);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].members, (std::vector<std::size_t>{0, 1, 3}));
  EXPECT_EQ(c[1].members, (std::vector<std::size_t>{2}));
  volume::sortBackToFront(c, glm::dvec3(-20, 0, 0));
  EXPECT_EQ(c[0].members, (std::vector<std::size_t>{2})) << "C is farthest from an eye at x = -20";

  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checkedRays = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<BoundingSphere> spheres;
    for (int k = 0; k < 6; ++k)
      spheres.push_back({glm::dvec3(u(rng), u(rng), u(rng)) * 300e3, 30e3 + 50e3 * (u(rng) + 1.0)});
    std::vector<volume::VolumeCluster> clusters = volume::clusterBySphere(spheres);
    std::size_t total = 0;
    for (const auto& cl : clusters) {
      total += cl.members.size();
      for (std::size_t m : cl.members)
        EXPECT_LE(glm::length(spheres[m].centreEcef - cl.enclosing.centreEcef) + spheres[m].radiusMeters,
                  cl.enclosing.radiusMeters + 1e-6);
    }
    EXPECT_EQ(total, spheres.size());
    for (std::size_t a = 0; a < clusters.size(); ++a)
      for (std::size_t b = a + 1; b < clusters.size(); ++b)
        EXPECT_GT(glm::length(clusters[a].enclosing.centreEcef - clusters[b].enclosing.centreEcef),
                  clusters[a].enclosing.radiusMeters + clusters[b].enclosing.radiusMeters);
    const glm::dvec3 eye = glm::dvec3(u(rng), u(rng), u(rng)) * 600e3;
    volume::sortBackToFront(clusters, eye);
    for (int r = 0; r < 200; ++r) {
      // Aimed at a random point of a random cluster, so that many rays meet two.
      const auto& aim = clusters[static_cast<std::size_t>(r) % clusters.size()].enclosing;
      const glm::dvec3 dir =
          glm::normalize(aim.centreEcef + glm::dvec3(u(rng), u(rng), u(rng)) * aim.radiusMeters - eye);
      for (std::size_t back = 0; back < clusters.size(); ++back)
        for (std::size_t front = back + 1; front < clusters.size(); ++front) {
          const auto& eb = clusters[back].enclosing;
          const auto& ef = clusters[front].enclosing;
          const volume::RayInterval ib = volume::raySphereInterval(eye, dir, eb.centreEcef, eb.radiusMeters);
          const volume::RayInterval in = volume::raySphereInterval(eye, dir, ef.centreEcef, ef.radiusMeters);
          if (ib.empty() || in.empty() || ib.tExitMeters < 0.0 || in.tExitMeters < 0.0) continue;
          ++checkedRays;
          EXPECT_LE(std::max(in.tEnterMeters, 0.0), std::max(ib.tEnterMeters, 0.0)) << "trial " << trial;
          EXPECT_LE(in.tExitMeters, ib.tEnterMeters + 1e-6) << "the nearer cluster must end before the farther begins";
        }
    }
  }
  EXPECT_GT(checkedRays, 500);
}
