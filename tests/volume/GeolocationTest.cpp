// Gate geolocation: worked examples, an independent oracle (PROJ), extremes, inverse, fast path.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/NexradReader.h>
#include <atmoglobe/volume/RadarReader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace atmoglobe::volume {
namespace {

double lonDiffDeg(double a, double b) { return std::abs(globe::wrapLongitudeDeg(a - b)); }

// --- wradlib's test_bin_altitude / test_bin_distance (wradlib/tests/test_georef.py),
// re = 6370040 m, ke = 4/3, site height 0. Values printed to 8 (height) and 8/7 (distance)
// decimals: the tolerance is half a unit in the last printed digit.
TEST(Geolocation, WradlibWorkedExampleFixedRadius) {
  BeamModel model;
  model.earthRadiusMeters = 6370040.0;
  const double re = effectiveEarthRadiusMeters(model, 0.0);
  EXPECT_DOUBLE_EQ(re, 6370040.0 * 4.0 / 3.0);
  double h = 0, s = 0;
  beamHeightAndGroundDistance(10000.0, 2.0, 0.0, re, &h, &s);
  EXPECT_NEAR(h, 354.87448647, 0.5e-8);
  EXPECT_NEAR(s, 9993.49302358, 0.5e-8);
  beamHeightAndGroundDistance(100000.0, 2.0, 0.0, re, &h, &s);
  EXPECT_NEAR(h, 4077.66415017, 0.5e-8);
  EXPECT_NEAR(s, 99893.4281037, 0.5e-7);
}

// --- wradlib's WGS84-site-radius fixture (coord_transform_data in wradlib/tests/test_georef.py):
// site 48 N 9 E, 0 m, r = 111 km, ke 4/3, R = WGS84 geocentric radius at 48 N. wradlib's local
// xyz is (s sin az, s cos az, h) in an ellipsoidal azimuthal-equidistant map, so |x| or |y| is our
// ground distance s and z our height.
// Tolerances: half a unit in the last printed digit.
TEST(Geolocation, WradlibWorkedExampleWgs84SiteRadius) {
  const GeolocationSite site{48.0, 9.0, 0.0};
  const BeamModel model;  // ke 4/3, R = geocentric radius at the site
  const double re = effectiveEarthRadiusMeters(model, site.latDeg);
  double h = 0, s = 0;

  beamHeightAndGroundDistance(111000.0, 0.0, 0.0, re, &h, &s);
  EXPECT_NEAR(s, 110993.6738, 0.5e-4);
  EXPECT_NEAR(h, 725.7159843, 0.5e-7);
  GatePosition p = geolocateGateExact(site, model, 0.0, 0.0, 111000.0);
  EXPECT_NEAR(p.latDeg, 48.99814438, 0.5e-8);
  EXPECT_NEAR(p.lonDeg, 9.0, 1e-12);

  p = geolocateGateExact(site, model, 90.0, 0.0, 111000.0);
  EXPECT_NEAR(p.lonDeg, 10.48716091, 0.5e-8);
  EXPECT_NEAR(p.latDeg, 47.99037251, 0.5e-8);

  beamHeightAndGroundDistance(111000.0, 0.5, 0.0, re, &h, &s);
  EXPECT_NEAR(s, 110976.7856, 0.5e-4);
  EXPECT_NEAR(h, 1694.22337134, 0.5e-8);
  p = geolocateGateExact(site, model, 270.0, 0.5, 111000.0);
  EXPECT_NEAR(p.lonDeg, 7.51306531, 0.5e-8);

  EXPECT_NEAR(globe::geocentricRadiusMeters(50.0), 6365631.51753728, 0.5e-8);
}

// --- What the model choice is worth: beam height at 0.5 deg, R = 6371 km, h0 = 0, ke 4/3 and 1,
// from Doviak & Zrnic (1993) eq. 2.28 evaluated in Python 3 (math.sqrt, math.sin) and rounded to
// whole metres (tolerance 0.5 m).
TEST(Geolocation, ReferenceModelChoiceTable) {
  struct Row {
    double rangeMeters, ke43, ke1;
  };
  constexpr Row rows[] = {{100e3, 1461, 1657}, {230e3, 5119, 6156}, {460e3, 16453, 20587}};
  for (const Row& row : rows) {
    double h = 0, s = 0;
    beamHeightAndGroundDistance(row.rangeMeters, 0.5, 0.0, 6371000.0 * 4.0 / 3.0, &h, &s);
    EXPECT_NEAR(h, row.ke43, 0.5) << row.rangeMeters;
    beamHeightAndGroundDistance(row.rangeMeters, 0.5, 0.0, 6371000.0, &h, &s);
    EXPECT_NEAR(h, row.ke1, 0.5) << row.rangeMeters;
  }
}

// --- Exact path against an independent computation. For each case: s and h from the model
// formula evaluated in Python 3 (double, math.asin form of Doviak & Zrnic 1993 eq. 2.28,
// R = WGS84 geocentric radius at the site, ke 4/3); lat/lon from PROJ's geodesic tool
//   echo "LAT LON AZ S" | geod +ellps=WGS84 -f %.12f
// and ECEF from PROJ
//   echo "LAT2 LON2 H" | cs2cs -d 6 EPSG:4979 EPSG:4978
// (script: the commands above in a loop; PROJ 9.1.1, Debian 12).
struct OracleCase {
  double latDeg, lonDeg, h0, azDeg, elDeg, rangeM, sM, hM, lat2Deg, lon2Deg, x, y, z;
};
constexpr OracleCase kOracle[] = {
    {33.6541, -101.8142, 1002.822484, 45.0, 0.5, 230000.0, /*s*/ 229853.683022, /*h*/ 6121.437822,
     /*lat*/ 35.106484732833, /*lon*/ -100.031567756247, /*ecef*/ -910782.374515, -5148713.751723, 3651058.152149},
    {89.99, 0.0, 30.0, 0.0, 0.0, 460000.0, /*s*/ 459547.520883, /*h*/ 12503.566566,
     /*lat*/ 85.895584506401, /*lon*/ 180.000000000000, /*ecef*/ -458933.536738, 0.000000, 6352811.008121},
    {-89.99, 120.0, 2800.0, 180.0, 1.0, 300000.0, /*s*/ 299545.416026, /*h*/ 13336.736136,
     /*lat*/ -87.328140126229, /*lon*/ -60.000000000000, /*ecef*/ 149471.015423, -258891.392971, -6363117.567674},
    {10.0, 180.0, 50.0, 90.0, 0.5, 460000.0, /*s*/ 459315.498325, /*h*/ 16490.424826,
     /*lat*/ 9.973649937195, /*lon*/ -175.810894666281, /*ecef*/ -6281791.999415, -460105.074810, 1100234.253563},
    {-35.661, 149.512, 1401.879732, 300.25, 19.5, 125000.0, /*s*/ 117227.529077, /*h*/ 43940.797757,
     /*lat*/ -35.123575403937, /*lon*/ 148.401027325016, /*ecef*/ -4478847.775394, 2755294.836176, -3674369.701404},
};

TEST(Geolocation, ExactPathMatchesProjWithinOneMillimetre) {
  const BeamModel model;
  for (const OracleCase& c : kOracle) {
    SCOPED_TRACE("site " + std::to_string(c.latDeg) + " " + std::to_string(c.lonDeg));
    const GeolocationSite site{c.latDeg, c.lonDeg, c.h0};
    double h = 0, s = 0;
    beamHeightAndGroundDistance(c.rangeM, c.elDeg, c.h0, effectiveEarthRadiusMeters(model, c.latDeg), &h, &s);
    // Python printed 6 decimals: 1e-6 m.
    EXPECT_NEAR(s, c.sM, 1e-6);
    EXPECT_NEAR(h, c.hM, 1e-6);
    const GatePosition p = geolocateGateExact(site, model, c.azDeg, c.elDeg, c.rangeM);
    // geod printed 12 decimals of a degree (~0.1 um); s was rounded to 1 um: 1e-10 deg (~11 um).
    EXPECT_NEAR(p.latDeg, c.lat2Deg, 1e-10);
    EXPECT_LE(lonDiffDeg(p.lonDeg, c.lon2Deg), 1e-10);
    EXPECT_NEAR(p.heightMeters, c.hM, 1e-6);
    // The bar for a gate position: within 1 mm of the independent ECEF.
    EXPECT_LE(glm::length(p.ecef - glm::dvec3(c.x, c.y, c.z)), 1e-3);
  }
}

// --- Extremes: poles, antimeridian, elevation 0 and 90, range 0, ke 1: finite, sensible results.
TEST(Geolocation, ExtremesAreFiniteAndSensible) {
  const GeolocationSite sites[] = {{89.99, 0.0, 10.0}, {-89.99, 0.0, 2800.0},   {0.0, 180.0, 0.0},
                                   {0.0, -180.0, 0.0}, {45.0, 179.9999, 100.0}, {90.0, 0.0, 0.0},
                                   {-90.0, 33.0, 0.0}};
  for (double ke : {1.0, 4.0 / 3.0}) {
    BeamModel model;
    model.ke = ke;
    for (const GeolocationSite& site : sites) {
      const glm::dvec3 siteEcef = globe::geodeticToEcef({site.latDeg, site.lonDeg, site.antennaHeightEllipsoidMeters});
      const glm::dvec3 up = globe::surfaceNormal(site.latDeg, site.lonDeg);
      for (double az : {0.0, 90.0, 180.0, 270.0, 359.9}) {
        for (double el : {-0.5, 0.0, 45.0, 90.0}) {
          for (double r : {0.0, 1.0, 230e3, 460e3}) {
            const GatePosition p = geolocateGateExact(site, model, az, el, r);
            SCOPED_TRACE("lat " + std::to_string(site.latDeg) + " lon " + std::to_string(site.lonDeg) + " az " +
                         std::to_string(az) + " el " + std::to_string(el) + " r " + std::to_string(r));
            ASSERT_TRUE(std::isfinite(p.latDeg) && std::isfinite(p.lonDeg) && std::isfinite(p.heightMeters));
            ASSERT_TRUE(std::isfinite(p.ecef.x) && std::isfinite(p.ecef.y) && std::isfinite(p.ecef.z));
            EXPECT_LE(std::abs(p.latDeg), 90.0);
            EXPECT_GE(p.lonDeg, -180.0);
            EXPECT_LE(p.lonDeg, 180.0);
            const double dist = glm::length(p.ecef - siteEcef);
            if (r == 0.0) {
              // Range 0 is the antenna itself (nm: the ECEF conversion's rounding).
              EXPECT_LT(dist, 1e-6);
              EXPECT_NEAR(p.heightMeters, site.antennaHeightEllipsoidMeters, 1e-6);
            } else {
              // The model bends the beam along a circle of radius >= Re/(1 - 1/ke)... and maps it
              // onto the ellipsoid; the straight-line distance from the antenna stays within 0.5 %
              // of the slant range (measured worst ~0.1 % at 460 km, 90 deg: the ellipsoid's normal
              // and the sphere's differ): a wrong axis or a degree/radian slip would be far off.
              EXPECT_NEAR(dist, r, 5e-3 * r);
            }
            if (el == 90.0) {
              // Straight up the ellipsoid normal: h = h0 + r, position = antenna + r * up.
              EXPECT_NEAR(p.heightMeters, site.antennaHeightEllipsoidMeters + r, 1e-6);
              EXPECT_LT(glm::length(p.ecef - (siteEcef + r * up)), 1e-6);
            }
          }
        }
      }
    }
  }
}

// --- Inverse: forward then inverse then forward again lands within 1 mm, over random samples
// including the extremes (seeded, reproducible).
TEST(Geolocation, InverseRoundTripsTheForwardWithinOneMillimetre) {
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const BeamModel models[] = {BeamModel{}, BeamModel{1.0, std::nullopt}, BeamModel{4.0 / 3.0, 6371000.0}};
  double worstPos = 0, worstRange = 0;
  for (int i = 0; i < 3000; ++i) {
    GeolocationSite site{u(rng) * 180.0 - 90.0, u(rng) * 360.0 - 180.0, u(rng) * 3000.0 - 50.0};
    if (i % 10 == 0) site.latDeg = (i % 20 == 0) ? 89.99 : -89.99;
    if (i % 10 == 1) site.lonDeg = (i % 20 == 1) ? 180.0 : -180.0;
    const BeamModel& model = models[i % 3];
    const double az = u(rng) * 360.0;
    double el = u(rng) * 20.0 - 1.0;
    if (i % 7 == 0) el = 90.0;
    if (i % 11 == 0) el = 0.0;
    double r = u(rng) * 460e3;
    if (i % 13 == 0) r = 0.0;
    const GatePosition p = geolocateGateExact(site, model, az, el, r);
    const AntennaCoordinates a = antennaCoordinatesExact(site, model, p.ecef);
    ASSERT_TRUE(std::isfinite(a.rangeMeters) && std::isfinite(a.azimuthDeg) && std::isfinite(a.elevationDeg));
    EXPECT_GE(a.azimuthDeg, 0.0);
    EXPECT_LT(a.azimuthDeg, 360.0);
    const GatePosition q = geolocateGateExact(site, model, a.azimuthDeg, a.elevationDeg, a.rangeMeters);
    worstPos = std::max(worstPos, glm::length(q.ecef - p.ecef));
    worstRange = std::max(worstRange, std::abs(a.rangeMeters - r));
    EXPECT_LE(glm::length(q.ecef - p.ecef), 1e-3) << "sample " << i;
    EXPECT_LE(std::abs(a.rangeMeters - r), 1e-3) << "sample " << i;
    if (r > 1000.0 && el < 89.0) {
      EXPECT_NEAR(a.elevationDeg, el, 1e-6) << "sample " << i;
      EXPECT_LE(lonDiffDeg(a.azimuthDeg, az), 1e-6) << "sample " << i;
    }
  }
  RecordProperty("worst_position_m", std::to_string(worstPos));
  RecordProperty("worst_range_m", std::to_string(worstRange));
}

// --- Fast path against the exact one.
double maxFastError(const GeolocationSite& site, const BeamModel& model, const Sweep& sweep) {
  std::vector<glm::dvec3> fast;
  geolocateSweepFast(site, model, sweep, &fast);
  EXPECT_EQ(fast.size(), sweep.rayCount() * sweep.gateCount);
  double worst = 0;
  for (std::size_t i = 0; i < sweep.rayCount(); ++i) {
    for (std::uint32_t g = 0; g < sweep.gateCount; ++g) {
      const GatePosition e =
          geolocateGateExact(site, model, sweep.azimuthDeg[i], sweep.elevationDeg[i], sweep.gateRangeMeters(g));
      const double err = glm::length(fast[i * sweep.gateCount + g] - e.ecef);
      if (!(err <= worst)) worst = err;  // NaN-safe: a NaN makes worst NaN and fails below
    }
  }
  return worst;
}

TEST(Geolocation, FastPathWithinStatedBoundOnSyntheticExtremes) {
  const GeolocationSite sites[] = {{89.99, 0.0, 10.0},  {-89.99, 120.0, 2800.0},      {10.0, 180.0, 50.0},
                                   {0.0, -179.99, 0.0}, {33.6541, -101.8142, 1002.8}, {90.0, 0.0, 0.0}};
  double worst = 0;
  for (double ke : {1.0, 4.0 / 3.0}) {
    BeamModel model;
    model.ke = ke;
    for (const GeolocationSite& site : sites) {
      for (double el : {-1.0, 0.0, 0.5, 19.5, 60.0, 90.0}) {
        Sweep sweep;
        sweep.firstGateRangeMeters = 125.0;
        sweep.gateSpacingMeters = 250.0;
        sweep.gateCount = 1840;  // to 460 km
        for (int a = 0; a < 72; ++a) {
          sweep.azimuthDeg.push_back(static_cast<float>(a * 5.0 + 0.25));
          // Per-ray elevations jitter like real antennas (+-0.1 deg).
          sweep.elevationDeg.push_back(static_cast<float>(el + 0.1 * std::sin(a)));
        }
        const double err = maxFastError(site, model, sweep);
        worst = std::max(worst, err);
        EXPECT_LE(err, kFastPathMaxErrorMeters)
            << "site " << site.latDeg << " " << site.lonDeg << " el " << el << " ke " << ke;
      }
    }
  }
  RecordProperty("worst_fast_error_m", std::to_string(worst));
  std::printf("fast path worst error (synthetic): %.3g m\n", worst);
}

TEST(Geolocation, FastPathWithinStatedBoundOnNexradVolume) {
  const std::string path = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
  SKIP_WITHOUT_TEST_DATA(path);
  Result<RadarVolume> vol = readNexradLevel2(path, ReadOptions{});
  ASSERT_TRUE(vol.ok()) << vol.error();
  Result<SiteResolution> site = resolveSite(vol->site, true);
  ASSERT_TRUE(site.ok()) << site.error();
  double worst = 0;
  std::size_t gates = 0;
  for (const Sweep& sweep : vol->sweeps) {
    worst = std::max(worst, maxFastError(site->site, BeamModel{}, sweep));
    gates += sweep.rayCount() * sweep.gateCount;
  }
  EXPECT_GT(gates, 5'000'000u);  // every gate of the REF volume was compared
  EXPECT_LE(worst, kFastPathMaxErrorMeters);
  std::printf("fast path worst error over %zu NEXRAD gates: %.3g m\n", gates, worst);
}

TEST(Geolocation, FastPathWithinStatedBoundOnOdimAndCfRadialVolumes) {
  // Every gate of every sweep of the other real files (read through format detection).
  const char* files[] = {"radar_odim/40_20181220_060630.pvol.h5", "radar_odim/bewid.pvol.hdf",
                         "radar_cfradial/MLL2217907250U.003.nc", "radar_cfradial/example_plot_ppi_single_sweep.nc",
                         "radar_cfradial/cfrad.20211011_201733.023_to_20211011_201745.299_DOW8_RHI.nc"};
  for (const char* f : files) {
    const std::string path = atmoglobe_test::testDataPath(f);
    SKIP_WITHOUT_TEST_DATA(path);
    Result<RadarVolume> vol = readRadarVolume(path, ReadOptions{});
    ASSERT_TRUE(vol.ok()) << vol.error();
    Result<SiteResolution> site = resolveSite(vol->site, true);
    ASSERT_TRUE(site.ok()) << site.error();
    double worst = 0;
    for (const Sweep& sweep : vol->sweeps) worst = std::max(worst, maxFastError(site->site, BeamModel{}, sweep));
    EXPECT_LE(worst, kFastPathMaxErrorMeters) << f;
    std::printf("fast path worst error, %s: %.3g m\n", f, worst);
  }
}

// --- Site resolution: MSL -> ellipsoid with EGM96, or off.
TEST(Geolocation, ResolveSiteAppliesEgm96OrSaysItDidNot) {
  RadarSite klbb;
  klbb.name = "KLBB";
  klbb.latDeg = 33.6541;
  klbb.lonDeg = -101.8142;
  klbb.antennaHeightMeters = 1029.0;
  klbb.heightDatum = HeightDatum::MeanSeaLevel;
  Result<SiteResolution> withGeoid = resolveSite(klbb, true);
  ASSERT_TRUE(withGeoid.ok()) << withGeoid.error();
  EXPECT_TRUE(withGeoid->geoidApplied);
  // N from PROJ vgridshift (GeoidTest): -26.177516 m.
  EXPECT_NEAR(withGeoid->geoidUndulationMeters, -26.177516, 1e-5);
  EXPECT_NEAR(withGeoid->site.antennaHeightEllipsoidMeters, 1029.0 - 26.177516, 1e-5);
  EXPECT_NE(withGeoid->datumNote.find("EGM96"), std::string::npos) << withGeoid->datumNote;

  Result<SiteResolution> without = resolveSite(klbb, false);
  ASSERT_TRUE(without.ok());
  EXPECT_FALSE(without->geoidApplied);
  EXPECT_EQ(without->site.antennaHeightEllipsoidMeters, 1029.0);
  EXPECT_NE(without->datumNote.find("geoid conversion off"), std::string::npos) << without->datumNote;

  RadarSite ellipsoidal = klbb;
  ellipsoidal.heightDatum = HeightDatum::Ellipsoid;
  Result<SiteResolution> e = resolveSite(ellipsoidal, true);
  ASSERT_TRUE(e.ok());
  EXPECT_FALSE(e->geoidApplied);
  EXPECT_EQ(e->site.antennaHeightEllipsoidMeters, 1029.0);

  RadarSite bad = klbb;
  bad.latDeg = std::nan("");
  EXPECT_FALSE(resolveSite(bad, true).ok());
  bad.latDeg = 91.0;
  Result<SiteResolution> b = resolveSite(bad, true);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().find("KLBB"), std::string::npos) << b.error();
}

TEST(Geolocation, BeamModelValidation) {
  EXPECT_TRUE(validateBeamModel(BeamModel{}, "test").ok());
  EXPECT_FALSE(validateBeamModel(BeamModel{0.0, std::nullopt}, "test").ok());
  EXPECT_FALSE(validateBeamModel(BeamModel{std::nan(""), std::nullopt}, "test").ok());
  EXPECT_FALSE(validateBeamModel(BeamModel{1.0, -5.0}, "test").ok());
}

}  // namespace
}  // namespace atmoglobe::volume
