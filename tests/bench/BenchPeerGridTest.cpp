// The peer's polar-to-Cartesian resampler (tools/bench: PeerGrid.h): its fast inverse against
// the exact inverse (volume::antennaCoordinatesExact) with an error bound derived below, and the
// resampled grid's values against the values at the exact antenna coordinates.
#include <atmoglobe/bench/PeerGrid.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace atmoglobe::bench {
namespace {

constexpr double kDeg = kPi / 180.0;

// THE BOUND. The fast inverse replaces the Earth near the site by a sphere of radius
// rs = sqrt(M N) (M, N: meridional and prime-vertical radii at the site) touching it below the
// antenna, and reads a point's height above that sphere and its arc distance on it. Along
// azimuth az the ellipsoid curves with the normal-section radius R_az = 1 / (cos^2 az / M +
// sin^2 az / N), between M and N, so |rs / R_az - 1| <= eps = sqrt(N / M) - 1 (e'^2 cos^2 lat / 2
// to first order: 0.0034 at the equator, 0 at the pole); and the curvature changes along the
// path with latitude (M(phi) = a (1 - e^2) / (1 - e^2 sin^2 phi)^1.5: dM/dphi = 3 e^2 M sin phi cos phi,
// d2M/dphi2 ~ 3 e^2 M cos 2phi, to first order in e^2). Integrating the curvature difference twice
// along the ground distance s gives the ellipsoid's departure from the sphere, to first order
// in e^2 (terms in s^2, s^3, s^4):
//   d(s) = s^2 eps / (2 rs) + e^2 |sin phi cos phi| s^3 / (2 M^2) + e^2 s^4 / (8 M^3)
// (at 460 km: 56 m at the equator; 14 + 3.5 m at 60 deg; 0.1 m at the pole), and once, the
// angle between the ellipsoid's normal and the sphere's radius at distance s:
//   tau(s) = s eps / rs + 3 e^2 |sin phi cos phi| s^2 / (2 M^2) + e^2 s^3 / (2 M^3).
// For a point at ground distance s, height h, slant range r and elevation e:
//  - its height above the sphere is off by dh <= d(s);
//  - its arc distance is off by (R_az - rs)(theta - sin theta) ~ eps rs theta^3 / 6
//    (theta = s / rs), and by h tau(s) because its height is along the ellipsoid's normal;
//  - (r, e) from (h, s) under the beam model (Doviak & Zrnic 1993, eq. 2.28): dh = sin e dr +
//    r cos e de and ds = cos e dr - r sin e de to first order, so dr <= sin e dh + cos e ds and
//    de <= (cos e dh + sin e ds) / r (rad);
//  - azimuth: the fast inverse's is the azimuth of the site's normal section through the point;
//    the exact path's is the geodesic's, which differs by ~ e'^2 theta^2 / 12 (rad), and the
//    point's normal leans out of that plane by up to e'^2 theta / 2: h e'^2 theta / 2 sideways
//    at distance s.
// Terms of higher order in e^2 or theta are covered by a factor 1.5 on each bound. The exact
// inverse is itself good to 1 mm (GeolocationTest.InverseRoundTrip): 1 mm of position is added
// to each bound (1e-3 m of range, 1e-3 / r rad of elevation, 1e-3 / s rad of azimuth).
struct Bound {
  double rangeMeters, elevationDeg, azimuthDeg;
};

Bound fastInverseBound(double siteLatDeg, double rangeMeters, double elevationDeg, double groundMeters,
                       double heightMeters) {
  const double m = globe::meridionalRadiusMeters(siteLatDeg), n = globe::primeVerticalRadiusMeters(siteLatDeg);
  const double rs = std::sqrt(m * n);
  const double eps = std::sqrt(n / m) - 1.0;
  const double ep2 = globe::kWgs84F * (2.0 - globe::kWgs84F) / ((1.0 - globe::kWgs84F) * (1.0 - globe::kWgs84F));
  const double phi = siteLatDeg * kDeg, e2 = globe::kWgs84F * (2.0 - globe::kWgs84F);
  const double sc = std::abs(std::sin(phi) * std::cos(phi));
  const double s = groundMeters, theta = s / rs, h = std::max(0.0, heightMeters);
  const double dh =
      s * s * eps / (2.0 * rs) + e2 * sc * s * s * s / (2.0 * m * m) + e2 * s * s * s * s / (8.0 * m * m * m);
  const double tau = s * eps / rs + 3.0 * e2 * sc * s * s / (2.0 * m * m) + e2 * s * s * s / (2.0 * m * m * m);
  const double ds = eps * rs * theta * theta * theta / 6.0 + h * tau;
  const double e = elevationDeg * kDeg;
  const double dr = std::abs(std::sin(e)) * dh + std::cos(e) * ds;
  const double de = (std::cos(e) * dh + std::abs(std::sin(e)) * ds) / rangeMeters;
  const double daz = ep2 * theta * theta / 12.0 + (s > 0.0 ? h * ep2 * theta / 2.0 / s : 0.0);
  const double floorMeters = 1e-3;
  return {1.5 * dr + floorMeters, (1.5 * de + floorMeters / rangeMeters) / kDeg,
          (1.5 * daz + floorMeters / std::max(s, 1.0)) / kDeg};
}

volume::PolarVolume siteVolume(double latDeg, double lonDeg, double antennaHeightMeters, double maxRangeMeters) {
  volume::PolarVolume v;
  v.site = {latDeg, lonDeg, antennaHeightMeters};
  v.maxRangeMeters = maxRangeMeters;
  return v;
}

// Random points by the exact forward path (a geodesic per point), out to 460 km at elevations
// 0..20 deg, at sites from the equator to near the pole (KLBB's latitude among them): the fast
// inverse is within the bound at every one.
TEST(BenchPeerGrid, FastInverseWithinItsBoundOfTheExactInverse) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ur(1e3, 460e3), uaz(0.0, 360.0), uel(0.0, 20.0);
  for (double lat : {0.0, 33.6541, -35.661, 60.0, 89.9}) {
    SCOPED_TRACE(lat);
    const volume::PolarVolume v = siteVolume(lat, -101.8, 1000.0, 470e3);
    const FastInverse inv = fastInverseFor(v);
    const glm::dmat3 enu = globe::enuAxes(lat, -101.8);
    const glm::dvec3 site = globe::geodeticToEcef({lat, -101.8, 1000.0});
    double worst[3] = {0.0, 0.0, 0.0};  // measured / bound
    for (int i = 0; i < 20000; ++i) {
      const double r = ur(rng), az = uaz(rng), el = uel(rng);
      const volume::GatePosition p = volume::geolocateGateExact(v.site, v.beam, az, el, r);
      const volume::AntennaCoordinates exact = volume::antennaCoordinatesExact(v.site, v.beam, p.ecef);
      const volume::AntennaCoordinates fast = inv(glm::transpose(enu) * (p.ecef - site));
      double hBeam = 0.0, s = 0.0;
      volume::beamHeightAndGroundDistance(r, el, 0.0, volume::effectiveEarthRadiusMeters(v.beam, lat), &hBeam, &s);
      const Bound b = fastInverseBound(lat, r, el, s, p.heightMeters);
      double daz = std::abs(fast.azimuthDeg - exact.azimuthDeg);
      daz = std::min(daz, 360.0 - daz);
      ASSERT_LE(std::abs(fast.rangeMeters - exact.rangeMeters), b.rangeMeters)
          << "r " << r << " az " << az << " el " << el;
      ASSERT_LE(std::abs(fast.elevationDeg - exact.elevationDeg), b.elevationDeg)
          << "r " << r << " az " << az << " el " << el;
      ASSERT_LE(daz, b.azimuthDeg) << "r " << r << " az " << az << " el " << el;
      worst[0] = std::max(worst[0], std::abs(fast.rangeMeters - exact.rangeMeters) / b.rangeMeters);
      worst[1] = std::max(worst[1], std::abs(fast.elevationDeg - exact.elevationDeg) / b.elevationDeg);
      worst[2] = std::max(worst[2], daz / b.azimuthDeg);
    }
    std::cout << "lat " << lat << ": measured / bound: range " << worst[0] << ", elevation " << worst[1] << ", azimuth "
              << worst[2] << "\n";
  }
}

// A small volume whose value is the gate's range in km (constant across rays and sweeps), so the
// linear sampling rule reproduces range / 1000 exactly between the first and last gate centres:
// a voxel's value is then the fast inverse's range, and its difference from the value at the
// exact antenna coordinates is the range error / 1000, held to the bound above.
volume::PolarVolume rangeVolume() {
  volume::RadarVolume rv;
  rv.format = "test";
  rv.sourcePath = "range.nc";
  rv.beamWidthDeg = 1.0;
  rv.loadedField = volume::FieldInfo{"RANGE", "km", {}};
  rv.fields = {rv.loadedField};
  for (int k = 0; k < 10; ++k) {
    volume::Sweep s;
    s.indexInFile = k;
    s.fixedAngleDeg = 0.5 + k;
    s.mode = volume::SweepMode::Ppi;
    s.firstGateRangeMeters = 1000.0;
    s.gateSpacingMeters = 500.0;
    s.gateCount = 119;  // last centre 60 km
    for (int r = 0; r < 120; ++r) {
      s.azimuthDeg.push_back(static_cast<float>(3.0 * r + 1.5));
      s.elevationDeg.push_back(static_cast<float>(s.fixedAngleDeg));
      for (std::uint32_t g = 0; g < s.gateCount; ++g)
        s.values.push_back(static_cast<float>(s.gateRangeMeters(g) / 1000.0));
    }
    rv.sweeps.push_back(std::move(s));
  }
  volume::SiteResolution site;
  site.site = {33.6541, -101.8142, 1000.0};
  Result<volume::PolarVolume> v = volume::buildPolarVolume(rv, site, volume::BeamModel{});
  EXPECT_TRUE(v.ok()) << (v.ok() ? "" : v.error());
  return v.ok() ? *v : volume::PolarVolume{};
}

TEST(BenchPeerGrid, ResampledValuesFollowTheExactInverseWithinTheBound) {
  const volume::PolarVolume v = rangeVolume();
  ASSERT_FALSE(v.sweeps.empty());
  constexpr float kEmpty = -1000.0f;
  std::vector<float> values;
  const PeerGrid g = buildPeerGrid(v, kEmpty, -999.0, 4e6, 2, &values);
  ASSERT_GT(g.nx, 0);
  EXPECT_EQ(g.spacingMeters, 500.0);  // the finest gate spacing, not coarsened under 4e6 voxels
  EXPECT_TRUE(g.coarsenedReason.empty()) << g.coarsenedReason;
  ASSERT_EQ(values.size(), static_cast<std::size_t>(g.nx) * g.ny * g.nz);

  const glm::dmat3 enu = globe::enuAxes(v.site.latDeg, v.site.lonDeg);
  const glm::dvec3 site = globe::geodeticToEcef({v.site.latDeg, v.site.lonDeg, v.site.antennaHeightEllipsoidMeters});
  const double re = volume::effectiveEarthRadiusMeters(v.beam, v.site.latDeg);
  const double firstCentre = 1000.0, lastCentre = 1000.0 + 118 * 500.0;
  std::size_t compared = 0, echo = 0, stateDiffers = 0;
  double worst = 0.0;
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const float value = values[(static_cast<std::size_t>(k) * g.ny + static_cast<std::size_t>(j)) * g.nx +
                                   static_cast<std::size_t>(i)];
        const glm::dvec3 p = g.originEnu + g.spacingMeters * glm::dvec3(i, j, k);
        const volume::AntennaCoordinates a = volume::antennaCoordinatesExact(v.site, v.beam, site + enu * p);
        const volume::PolarSample exact =
            volume::samplePolar(v, a.rangeMeters, a.azimuthDeg, a.elevationDeg, volume::Interpolation::Linear);
        const bool gridEcho = value != kEmpty;
        echo += gridEcho;
        if (gridEcho != (exact.state == volume::PolarSample::State::Echo)) {
          ++stateDiffers;  // a beam edge or the range's end between the fast and the exact coordinates
          continue;
        }
        if (!gridEcho || a.rangeMeters < firstCentre || a.rangeMeters > lastCentre) continue;
        double h = 0.0, s = 0.0;
        volume::beamHeightAndGroundDistance(a.rangeMeters, a.elevationDeg, v.site.antennaHeightEllipsoidMeters, re, &h,
                                            &s);
        const Bound b = fastInverseBound(v.site.latDeg, a.rangeMeters, a.elevationDeg, s, h);
        // float32 storage of values up to 60 km: half an ulp is 2e-6 km; the gate values and
        // the grid value are each rounded once.
        const double tolerance = b.rangeMeters / 1000.0 + 1e-5;
        const double diff = std::abs(static_cast<double>(value) - exact.value);
        ASSERT_LE(diff, tolerance) << "voxel " << i << "," << j << "," << k << " range " << a.rangeMeters;
        worst = std::max(worst, diff / tolerance);
        ++compared;
      }
  std::cout << compared << " voxels compared, " << echo << " with echo, " << stateDiffers
            << " with another state at the exact coordinates; worst difference / bound " << worst << "\n";
  EXPECT_GT(compared, 100000u);
  EXPECT_LT(static_cast<double>(stateDiffers), 1e-3 * static_cast<double>(echo));

  // The errors the grid reports (20000 random voxels) are the inverse's: within the bound at the
  // far corner of the box (dr <= dh + ds whatever the elevation).
  const double sMax = std::hypot(std::max(std::abs(g.originEnu.x), std::abs(g.originEnu.x + g.nx * g.spacingMeters)),
                                 std::max(std::abs(g.originEnu.y), std::abs(g.originEnu.y + g.ny * g.spacingMeters)));
  const double hMax = g.originEnu.z + g.nz * g.spacingMeters + v.site.antennaHeightEllipsoidMeters;
  const Bound far = fastInverseBound(v.site.latDeg, sMax, 90.0, sMax, hMax);     // e = 90: dr = 1.5 dh + floor ...
  const Bound farFlat = fastInverseBound(v.site.latDeg, sMax, 0.0, sMax, hMax);  // ... e = 0: 1.5 ds + floor
  EXPECT_GT(g.maxRangeErrorMeters, 0.0);
  EXPECT_LE(g.maxRangeErrorMeters, far.rangeMeters + farFlat.rangeMeters);
}

}  // namespace
}  // namespace atmoglobe::bench
