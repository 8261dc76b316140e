// Cone meshes: vertices on the beam surface, rim at the geolocated last gate, texture mapping
// by azimuth, triangle budget.
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/ConeExport.h>
#include <atmoglobe/volume/ConeMesh.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/SweepImage.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

using namespace atmoglobe;
using namespace atmoglobe::volume;

namespace {

// A PPI sweep with `rays` rays at slightly irregular azimuths (jitter up to +-0.2 of the spacing),
// gates first + g * spacing, values cycling through -10..70 dBZ with no-echo and no-data holes.
Sweep syntheticSweep(int rays, double elevationDeg, std::uint32_t gates, double firstMeters, double spacingMeters,
                     double azimuthOffsetDeg = 0.3) {
  Sweep s;
  s.fixedAngleDeg = elevationDeg;
  s.firstGateRangeMeters = firstMeters;
  s.gateSpacingMeters = spacingMeters;
  s.gateCount = gates;
  const double step = 360.0 / rays;
  for (int i = 0; i < rays; ++i) {
    const double jitter = 0.2 * step * std::sin(i * 1.7);
    double a = std::fmod(azimuthOffsetDeg + i * step + jitter + 360.0, 360.0);
    s.azimuthDeg.push_back(static_cast<float>(a));
    s.elevationDeg.push_back(static_cast<float>(elevationDeg));
    for (std::uint32_t g = 0; g < gates; ++g) {
      float v = static_cast<float>(std::fmod(g * 0.37 + i * 0.5, 80.0) - 10.0);
      if ((g + static_cast<std::uint32_t>(i)) % 17 == 0) v = kNoEcho;
      if ((g * 7 + static_cast<std::uint32_t>(i)) % 29 == 0) v = kNoData;
      s.values.push_back(v);
    }
  }
  return s;
}

GeolocationSite siteAt(double latDeg, double lonDeg, double hEllipsoid) {
  GeolocationSite s;
  s.latDeg = latDeg;
  s.lonDeg = lonDeg;
  s.antennaHeightEllipsoidMeters = hEllipsoid;
  return s;
}

glm::dvec3 toEcef(const GeolocationSite& site, const glm::vec3& enu) {
  const glm::dmat4 m = globe::enuToEcef(globe::Geodetic{site.latDeg, site.lonDeg, site.antennaHeightEllipsoidMeters});
  return glm::dvec3(m * glm::dvec4(glm::dvec3(enu), 1.0));
}

// Elevation of an ECEF point seen from the antenna under the effective-Earth-radius model (Doviak &
// Zrnic 1993, eq. 2.28, solved for range and elevation), written here independently of the
// library's geolocation: ground distance s from the geodesic inverse, height h above the
// ellipsoid, gamma = s / Re, rho1 = Re + h0, rho2 = Re + h,
// theta = atan2(rho2 cos gamma - rho1, rho2 sin gamma).
struct Inverse {
  double elevationDeg, azimuthDeg, groundMeters;
};
Inverse inverseBeam(const GeolocationSite& site, double ke, const glm::dvec3& ecef) {
  const globe::Geodetic g = globe::ecefToGeodetic(ecef);
  const globe::GeodesicLine line = globe::geodesicInverse(site.latDeg, site.lonDeg, g.latDeg, g.lonDeg);
  const double re = ke * globe::geocentricRadiusMeters(site.latDeg);
  const double gamma = line.distanceMeters / re;
  const double rho1 = re + site.antennaHeightEllipsoidMeters, rho2 = re + g.heightMeters;
  return {radiansToDegrees(std::atan2(rho2 * std::cos(gamma) - rho1, rho2 * std::sin(gamma))), line.azimuth1Deg,
          line.distanceMeters};
}

}  // namespace

// Every vertex of a bent cone lies on its sweep's beam surface: the elevation recomputed from the
// vertex's ECEF position by the inverse model is the sweep's elevation within 0.01 deg.
// Tolerance: float32 vertices are off by <= 0.016 m (ConeMesh.h); at the nearest vertex (first gate,
// 125 m here, where the float ulp is 7.6e-6 m) that is < 1e-5 deg, so a 0.01 deg bound leaves a
// wide margin -- a wrong model (ke 1 instead of 4/3) misses it by 0.3 deg at 100 km.
TEST(ConeMesh, EveryVertexOnBeamSurface) {
  const GeolocationSite site = siteAt(33.65, -101.81, 1000.0);
  for (double el : {0.5, 3.1, 19.5}) {
    const Sweep sw = syntheticSweep(360, el, 400, 125.0, 250.0);
    const SweepImage img = makeSweepImage(sw, nwsReflectivityTable(), sw.gateCount);
    const ConeMeshOptions opt;
    const ConeMesh mesh = buildConeMesh(site, sw, img, opt);
    ASSERT_FALSE(mesh.positionsEnu.empty());
    double worst = 0.0;
    for (std::size_t c = 0; c < mesh.columnAzimuthDeg.size(); ++c) {
      for (std::size_t k = 0; k < mesh.rowRangeMeters.size(); ++k) {
        const Inverse inv = inverseBeam(site, 4.0 / 3.0, toEcef(site, mesh.positionsEnu[mesh.vertexIndex(c, k)]));
        worst = std::max(worst, std::abs(inv.elevationDeg - el));
        // The azimuth of the vertex is its column's azimuth (float rounding: < 1e-3 deg at 125 m).
        double dAz = std::fmod(inv.azimuthDeg - mesh.columnAzimuthDeg[c] + 720.0, 360.0);
        if (dAz > 180.0) dAz -= 360.0;
        ASSERT_LT(std::abs(dAz), 1e-3) << "column " << c << " row " << k;
      }
    }
    EXPECT_LT(worst, 0.01) << "elevation " << el;
  }
}

// The same check fails for a cone built with the wrong model: the test can tell them apart.
TEST(ConeMesh, BeamSurfaceCheckDetectsWrongModel) {
  const GeolocationSite site = siteAt(33.65, -101.81, 1000.0);
  const Sweep sw = syntheticSweep(90, 0.5, 400, 125.0, 250.0);
  const SweepImage img = makeSweepImage(sw, nwsReflectivityTable(), sw.gateCount);
  ConeMeshOptions straight;
  straight.straight = true;
  const ConeMesh mesh = buildConeMesh(site, sw, img, straight);
  const glm::vec3 rim = mesh.positionsEnu[mesh.vertexIndex(0, mesh.rowRangeMeters.size() - 1)];
  EXPECT_GT(std::abs(inverseBeam(site, 4.0 / 3.0, toEcef(site, rim)).elevationDeg - 0.5), 0.1);
}

// The rim at azimuth 0 is within 1 m of the geolocated last gate (geolocateGateExact) and, for the
// wradlib worked example (wradlib/tests/test_georef.py, coord_transform_data: site 9 E 48 N 0 m,
// r 111 km, az 0, el 0, ke 4/3 -> latitude 48.99814438, height 725.7159843 m), within 0.02 m of
// the published position.
// Tolerances: float32 ENU rounding <= 0.004 m per axis at 111 km; 1e-7 deg of latitude = 0.011 m.
TEST(ConeMesh, RimAtAzimuthZeroIsTheLastGate) {
  const GeolocationSite site = siteAt(48.0, 9.0, 0.0);
  const Sweep sw = syntheticSweep(360, 0.0, 111, 1000.0, 1000.0);  // last gate centre at 111 km
  const SweepImage img = makeSweepImage(sw, nwsReflectivityTable(), sw.gateCount);
  const ConeMesh mesh = buildConeMesh(site, sw, img, ConeMeshOptions{});
  std::size_t col = mesh.columnAzimuthDeg.size();
  for (std::size_t c = 0; c < mesh.columnAzimuthDeg.size(); ++c) {
    if (std::abs(std::remainder(mesh.columnAzimuthDeg[c], 360.0)) < 1e-9) col = c;
  }
  ASSERT_LT(col, mesh.columnAzimuthDeg.size()) << "no vertex column at azimuth 0";
  const std::size_t last = mesh.rowRangeMeters.size() - 1;
  EXPECT_DOUBLE_EQ(mesh.rowRangeMeters[last], 111000.0);
  const glm::dvec3 rim = toEcef(site, mesh.positionsEnu[mesh.vertexIndex(col, last)]);
  const GatePosition gate = geolocateGateExact(site, BeamModel{}, 0.0, 0.0, 111000.0);
  EXPECT_LT(glm::length(rim - gate.ecef), 1.0);
  const globe::Geodetic g = globe::ecefToGeodetic(rim);
  EXPECT_NEAR(g.latDeg, 48.99814438, 1e-7);
  EXPECT_NEAR(g.lonDeg, 9.0, 1e-7);
  EXPECT_NEAR(g.heightMeters, 725.7159843, 0.02);
}

// Rim at azimuth 0 for every sweep of a 0.5..19.5 deg volume at another site and a long range.
TEST(ConeMesh, RimMatchesGeolocationForEverySweep) {
  const GeolocationSite site = siteAt(-33.7, 151.2, 190.0);
  for (double el : {0.5, 0.9, 1.3, 2.4, 6.4, 19.5}) {
    const Sweep sw = syntheticSweep(720, el, 1832, 2125.0, 250.0);
    const SweepImage img = makeSweepImage(sw, nwsReflectivityTable(), sw.gateCount);
    const ConeMesh mesh = buildConeMesh(site, sw, img, ConeMeshOptions{});
    std::size_t col = mesh.columnAzimuthDeg.size();
    for (std::size_t c = 0; c < mesh.columnAzimuthDeg.size(); ++c)
      if (std::abs(std::remainder(mesh.columnAzimuthDeg[c], 360.0)) < 1e-9) col = c;
    ASSERT_LT(col, mesh.columnAzimuthDeg.size());
    const glm::dvec3 rim = toEcef(site, mesh.positionsEnu[mesh.vertexIndex(col, mesh.rowRangeMeters.size() - 1)]);
    const GatePosition gate = geolocateGateExact(site, BeamModel{}, 0.0, el, sw.gateRangeMeters(sw.gateCount - 1));
    EXPECT_LT(glm::length(rim - gate.ecef), 1.0) << "elevation " << el;
    EXPECT_LE(mesh.triangleCount(), static_cast<std::size_t>(kGoogleEarthMaxTrianglesPerModel));
  }
}

// Straight cone: (r cos el sin az, r cos el cos az, r sin el), float rounding only.
TEST(ConeMesh, StraightConeIsTheFlatFormula) {
  const GeolocationSite site = siteAt(10.0, 20.0, 50.0);
  const Sweep sw = syntheticSweep(360, 2.4, 800, 125.0, 250.0);
  const SweepImage img = makeSweepImage(sw, nwsReflectivityTable(), sw.gateCount);
  ConeMeshOptions opt;
  opt.straight = true;
  const ConeMesh mesh = buildConeMesh(site, sw, img, opt);
  for (std::size_t c = 0; c < mesh.columnAzimuthDeg.size(); c += 7) {
    for (std::size_t k = 0; k < mesh.rowRangeMeters.size(); ++k) {
      const double r = mesh.rowRangeMeters[k];
      const double az = degreesToRadians(mesh.columnAzimuthDeg[c]), el = degreesToRadians(2.4);
      const glm::dvec3 want(r * std::cos(el) * std::sin(az), r * std::cos(el) * std::cos(az), r * std::sin(el));
      EXPECT_LT(glm::length(glm::dvec3(mesh.positionsEnu[mesh.vertexIndex(c, k)]) - want), 0.02);
    }
  }
}

// Google Earth's per-model limit holds for small, typical and very dense sweeps.
TEST(ConeMesh, TriangleBudget) {
  const GeolocationSite site = siteAt(50.0, 5.0, 100.0);
  for (int rays : {1, 7, 360, 720, 1440, 7200}) {
    const Sweep sw = syntheticSweep(rays, 1.0, 100, 500.0, 1000.0);
    const SweepImage img = makeSweepImage(sw, nwsReflectivityTable(), sw.gateCount);
    const ConeMesh mesh = buildConeMesh(site, sw, img, ConeMeshOptions{});
    EXPECT_LE(mesh.triangleCount(), static_cast<std::size_t>(kGoogleEarthMaxTrianglesPerModel)) << rays << " rays";
    EXPECT_GE(mesh.triangleCount(), 6u) << rays << " rays";
    EXPECT_EQ(mesh.indices.size() % 3, 0u);
    for (std::uint32_t i : mesh.indices) ASSERT_LT(i, mesh.positionsEnu.size());
    ConeMeshOptions small;
    small.maxTriangles = 500;
    EXPECT_LE(buildConeMesh(site, sw, img, small).triangleCount(), 500u) << rays << " rays";
  }
}

// Texture rows follow azimuth, not ray index: with irregular spacing, the v of a ray's azimuth
// falls inside that ray's row, and a sector scan gets transparent gap rows.
TEST(ConeMesh, TextureMapsByAzimuth) {
  Sweep sw = syntheticSweep(8, 1.0, 4, 500.0, 1000.0);
  // Irregular azimuths, deliberately unsorted: a sector 0..4 deg, two rays at 90/91 and one at 180.
  const float az[] = {180.0f, 0.0f, 3.0f, 1.0f, 91.0f, 90.0f, 4.0f, 2.5f};
  for (int i = 0; i < 8; ++i) sw.azimuthDeg[static_cast<std::size_t>(i)] = az[i];
  for (std::size_t i = 0; i < sw.values.size(); ++i) sw.values[i] = 40.0f;  // all opaque
  const SweepImage img = makeSweepImage(sw, nwsReflectivityTable(), sw.gateCount);
  ASSERT_EQ(img.width, 4);
  for (int i = 0; i < 8; ++i) {
    const double v = sweepImageV(img, az[i]);
    const int row = static_cast<int>(std::floor(v * img.height));
    ASSERT_LT(row, img.height);
    EXPECT_EQ(img.rowRay[static_cast<std::size_t>(row)], i) << "azimuth " << az[i];
  }
  // Rows sorted by azimuth and tiling one turn.
  for (std::size_t r = 1; r < img.rowStartAzimuthDeg.size(); ++r)
    EXPECT_DOUBLE_EQ(img.rowStartAzimuthDeg[r], img.rowEndAzimuthDeg[r - 1]);
  EXPECT_DOUBLE_EQ(img.rowEndAzimuthDeg.back() - img.rowStartAzimuthDeg.front(), 360.0);
  // Boundary between the 0 and 1 deg rays at 0.5 deg (midpoint), v exactly at the row edge.
  EXPECT_NEAR(sweepImageV(img, 0.5),
              static_cast<double>(std::find(img.rowRay.begin(), img.rowRay.end(), 3) - img.rowRay.begin()) / img.height,
              1e-12);
  // Spacings 1, 1.5, 0.5, 1, 86, 1, 89, 180: median 1.5, so the 86, 89 and 180 deg gaps (> 3.75)
  // become transparent rows.
  int gaps = 0;
  for (std::size_t r = 0; r < img.rowRay.size(); ++r) {
    if (img.rowRay[r] >= 0) continue;
    ++gaps;
    for (int x = 0; x < img.width; ++x)
      EXPECT_EQ(img.rgba[(r * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(x)) * 4 + 3], 0);
  }
  EXPECT_EQ(gaps, 3);
  // u: gate centres map to texel centres.
  EXPECT_NEAR(sweepImageU(img, 500.0), 0.125, 1e-12);
  EXPECT_NEAR(sweepImageU(img, 3500.0), 0.875, 1e-12);
}

// A real volume (NEXRAD KLBB): vertices of the lowest sweep on the beam surface, rim at the gate.
TEST(ConeMesh, RealNexradVolume) {
  const std::string path = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
  SKIP_WITHOUT_TEST_DATA(path);
  Result<RadarVolume> vol = readRadarVolume(path, ReadOptions{});
  ASSERT_TRUE(vol.ok()) << vol.error();
  ConeExportOptions opt;
  opt.sweepIndices = {0};
  Result<ConeScene> scene = buildConeScene(*vol, nwsReflectivityTable(), opt);
  ASSERT_TRUE(scene.ok()) << scene.error();
  const Cone& cone = scene->cones.front();
  const Sweep& sw = vol->sweeps[0];
  const GeolocationSite& site = scene->site.site;
  double worst = 0.0;
  for (const glm::vec3& p : cone.mesh.positionsEnu)
    worst = std::max(worst, std::abs(inverseBeam(site, 4.0 / 3.0, toEcef(site, p)).elevationDeg - sw.fixedAngleDeg));
  EXPECT_LT(worst, 0.01);
  std::size_t col = 0;
  for (std::size_t c = 0; c < cone.mesh.columnAzimuthDeg.size(); ++c)
    if (std::abs(std::remainder(cone.mesh.columnAzimuthDeg[c], 360.0)) < 1e-9) col = c;
  const glm::dvec3 rim =
      toEcef(site, cone.mesh.positionsEnu[cone.mesh.vertexIndex(col, cone.mesh.rowRangeMeters.size() - 1)]);
  const GatePosition gate =
      geolocateGateExact(site, BeamModel{}, 0.0, sw.fixedAngleDeg, sw.gateRangeMeters(sw.gateCount - 1));
  EXPECT_LT(glm::length(rim - gate.ecef), 1.0);
  EXPECT_LE(cone.mesh.triangleCount(), static_cast<std::size_t>(kGoogleEarthMaxTrianglesPerModel));
}
