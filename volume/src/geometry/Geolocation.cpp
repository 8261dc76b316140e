#include <atmoglobe/volume/Geolocation.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/GeodesicLine.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>

namespace atmoglobe::volume {

namespace {

std::string formatMeters(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f m", v);
  return buf;
}
}  // namespace

Status validateBeamModel(const BeamModel& model, const char* what) {
  if (!std::isfinite(model.ke) || model.ke <= 0.0) {
    return makeError(std::string(what) + ": refraction factor ke must be a finite number > 0");
  }
  if (model.earthRadiusMeters && (!std::isfinite(*model.earthRadiusMeters) || *model.earthRadiusMeters <= 0.0)) {
    return makeError(std::string(what) + ": Earth radius must be a finite number of metres > 0");
  }
  return Ok{};
}

double effectiveEarthRadiusMeters(const BeamModel& model, double siteLatDeg) {
  const double r = model.earthRadiusMeters ? *model.earthRadiusMeters : globe::geocentricRadiusMeters(siteLatDeg);
  return model.ke * r;
}

Result<SiteResolution> resolveSite(const RadarSite& site, const GeoidGrid* geoid) {
  const globe::Geodetic g{site.latDeg, site.lonDeg, site.antennaHeightMeters};
  const std::string what = "radar site" + (site.name.empty() ? std::string() : " " + site.name);
  if (Status s = globe::validateGeodetic(g, what.c_str()); !s) return s.forwardError();
  SiteResolution out;
  out.site = {site.latDeg, site.lonDeg, site.antennaHeightMeters};
  if (site.heightDatum == HeightDatum::Ellipsoid) {
    out.datumNote = "antenna height " + formatMeters(site.antennaHeightMeters) + " given above the WGS84 ellipsoid";
    return out;
  }
  if (geoid == nullptr) {
    out.datumNote = "antenna height " + formatMeters(site.antennaHeightMeters) +
                    " above mean sea level used as height above the WGS84 ellipsoid (geoid conversion off: "
                    "heights are off by minus the geoid undulation, up to ~100 m)";
    return out;
  }
  out.geoidUndulationMeters = geoid->undulationMeters(site.latDeg, site.lonDeg);
  out.geoidApplied = true;
  out.site.antennaHeightEllipsoidMeters = site.antennaHeightMeters + out.geoidUndulationMeters;
  out.datumNote = "antenna height " + formatMeters(site.antennaHeightMeters) +
                  " above mean sea level + EGM96 undulation " + formatMeters(out.geoidUndulationMeters) + " (" +
                  geoid->path() + ") = " + formatMeters(out.site.antennaHeightEllipsoidMeters) +
                  " above the WGS84 ellipsoid";
  return out;
}

Result<SiteResolution> resolveSite(const RadarSite& site, bool useGeoid) {
  if (!useGeoid || site.heightDatum == HeightDatum::Ellipsoid)
    return resolveSite(site, static_cast<const GeoidGrid*>(nullptr));
  const Result<GeoidGrid>& grid = defaultEgm96Grid();
  if (!grid) return grid.forwardError();
  return resolveSite(site, &grid.value());
}

void beamHeightAndGroundDistance(double rangeMeters, double elevationDeg, double antennaHeightMeters,
                                 double effectiveRadiusMeters, double* heightMeters, double* groundDistanceMeters) {
  const double theta = degreesToRadians(elevationDeg);
  const double rho1 = effectiveRadiusMeters + antennaHeightMeters;
  const double sinT = std::sin(theta), cosT = std::cos(theta);
  // (Re+h)^2 = (r sin + rho1)^2 + (r cos)^2: same as D&Z 2.28, written as a sum of squares so it
  // cannot go negative through rounding.
  const double up = rangeMeters * sinT + rho1;
  const double across = rangeMeters * cosT;
  const double rho2 = std::hypot(up, across);
  *heightMeters = rho2 - effectiveRadiusMeters;
  // s = Re * asin(r cos / (Re+h)) = Re * atan2(r cos, r sin + rho1); atan2 stays accurate near 90 deg.
  *groundDistanceMeters = effectiveRadiusMeters * std::atan2(across, up);
}

GatePosition geolocateGateExact(const GeolocationSite& site, const BeamModel& model, double azimuthDeg,
                                double elevationDeg, double rangeMeters) {
  assert(std::isfinite(azimuthDeg) && std::isfinite(elevationDeg) && std::isfinite(rangeMeters));
  const double re = effectiveEarthRadiusMeters(model, site.latDeg);
  double h = 0, s = 0;
  beamHeightAndGroundDistance(rangeMeters, elevationDeg, site.antennaHeightEllipsoidMeters, re, &h, &s);
  const globe::GeodesicPoint p = globe::geodesicDirect(site.latDeg, site.lonDeg, azimuthDeg, s);
  GatePosition out;
  out.latDeg = p.latDeg;
  out.lonDeg = globe::wrapLongitudeDeg(p.lonDeg);
  out.heightMeters = h;
  out.ecef = globe::geodeticToEcef({p.latDeg, p.lonDeg, h});
  return out;
}

void geolocateSweepFast(const GeolocationSite& site, const BeamModel& model, const Sweep& sweep,
                        std::vector<glm::dvec3>* ecefOut) {
  assert(ecefOut != nullptr);
  const std::size_t rays = sweep.rayCount();
  const std::size_t gates = sweep.gateCount;
  assert(sweep.elevationDeg.size() == rays);
  ecefOut->resize(rays * gates);
  if (rays == 0 || gates == 0) return;
  const double r0 = sweep.gateRangeMeters(0);
  const double r1 = sweep.gateRangeMeters(static_cast<std::uint32_t>(gates - 1));
  if (gates < static_cast<std::size_t>(kFastChebyshevNodes) || !(r1 > r0)) {
    // Fewer gates than nodes: the exact path is cheaper than building the series.
    for (std::size_t i = 0; i < rays; ++i) {
      for (std::size_t g = 0; g < gates; ++g) {
        (*ecefOut)[i * gates + g] = geolocateGateExact(site, model, sweep.azimuthDeg[i], sweep.elevationDeg[i],
                                                       sweep.gateRangeMeters(static_cast<std::uint32_t>(g)))
                                        .ecef;
      }
    }
    return;
  }
  constexpr int kN = kFastChebyshevNodes;
  const double mid = 0.5 * (r0 + r1), half = 0.5 * (r1 - r0);
  // Chebyshev nodes (first kind) in range, and cos(pi k (j + 1/2) / N) for the coefficients.
  std::array<double, kN> nodeRange{};
  std::array<std::array<double, kN>, kN> cosTable{};
  for (int j = 0; j < kN; ++j) {
    nodeRange[j] = mid + half * std::cos(kPi * (j + 0.5) / kN);
    for (int k = 0; k < kN; ++k) cosTable[k][j] = std::cos(kPi * k * (j + 0.5) / kN);
  }
  // Per-gate table: T_k(x_g), k-major so the per-ray loop runs over contiguous gates.
  std::vector<double> basis(static_cast<std::size_t>(kN) * gates);
  for (std::size_t g = 0; g < gates; ++g) {
    const double x = std::clamp((sweep.gateRangeMeters(static_cast<std::uint32_t>(g)) - mid) / half, -1.0, 1.0);
    double tPrev = 1.0, t = x;
    basis[g] = 1.0;
    if (kN > 1) basis[gates + g] = x;
    for (int k = 2; k < kN; ++k) {
      const double tNext = 2.0 * x * t - tPrev;
      basis[static_cast<std::size_t>(k) * gates + g] = tNext;
      tPrev = t;
      t = tNext;
    }
  }
  const double re = effectiveEarthRadiusMeters(model, site.latDeg);
  // Nodes are positioned with one GeographicLib::GeodesicLine per ray: Position() along a line is
  // several times cheaper than a fresh Direct() and gives the same geodesic (globe::geodesicDirect
  // has no line form, hence the direct GeographicLib use here).
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  std::vector<double> accX(gates), accY(gates), accZ(gates);
  for (std::size_t i = 0; i < rays; ++i) {
    assert(std::isfinite(sweep.azimuthDeg[i]) && std::isfinite(sweep.elevationDeg[i]));
    const GeographicLib::GeodesicLine line = geod.Line(
        site.latDeg, site.lonDeg, sweep.azimuthDeg[i],
        GeographicLib::Geodesic::LATITUDE | GeographicLib::Geodesic::LONGITUDE | GeographicLib::Geodesic::DISTANCE_IN);
    std::array<glm::dvec3, kN> f{};
    for (int j = 0; j < kN; ++j) {
      double h = 0, s = 0, lat = 0, lon = 0;
      beamHeightAndGroundDistance(nodeRange[j], sweep.elevationDeg[i], site.antennaHeightEllipsoidMeters, re, &h, &s);
      line.Position(s, lat, lon);
      f[j] = globe::geodeticToEcef({lat, lon, h});
    }
    std::array<glm::dvec3, kN> c{};
    for (int k = 0; k < kN; ++k) {
      glm::dvec3 sum(0.0);
      for (int j = 0; j < kN; ++j) sum += f[j] * cosTable[k][j];
      c[k] = sum * ((k == 0 ? 1.0 : 2.0) / kN);
    }
    std::fill(accX.begin(), accX.end(), c[0].x);
    std::fill(accY.begin(), accY.end(), c[0].y);
    std::fill(accZ.begin(), accZ.end(), c[0].z);
    for (int k = 1; k < kN; ++k) {
      const double* b = &basis[static_cast<std::size_t>(k) * gates];
      const double cx = c[k].x, cy = c[k].y, cz = c[k].z;
      for (std::size_t g = 0; g < gates; ++g) {
        accX[g] += cx * b[g];
        accY[g] += cy * b[g];
        accZ[g] += cz * b[g];
      }
    }
    glm::dvec3* out = &(*ecefOut)[i * gates];
    for (std::size_t g = 0; g < gates; ++g) out[g] = {accX[g], accY[g], accZ[g]};
  }
}

AntennaCoordinates antennaCoordinatesExact(const GeolocationSite& site, const BeamModel& model,
                                           const glm::dvec3& ecef) {
  const globe::Geodetic p = globe::ecefToGeodetic(ecef);
  const globe::GeodesicLine inv = globe::geodesicInverse(site.latDeg, site.lonDeg, p.latDeg, p.lonDeg);
  const double re = effectiveEarthRadiusMeters(model, site.latDeg);
  const double gamma = inv.distanceMeters / re;
  const double rho1 = re + site.antennaHeightEllipsoidMeters;
  const double rho2 = re + p.heightMeters;
  const double sinHalf = std::sin(0.5 * gamma);
  const double dRho = p.heightMeters - site.antennaHeightEllipsoidMeters;
  AntennaCoordinates out;
  out.rangeMeters = std::sqrt(dRho * dRho + 4.0 * rho1 * rho2 * sinHalf * sinHalf);
  // theta = atan2(rho2 cos(gamma) - rho1, rho2 sin(gamma)), with rho2 cos - rho1 = dRho - 2 rho2 sin^2(gamma/2).
  out.elevationDeg = radiansToDegrees(std::atan2(dRho - 2.0 * rho2 * sinHalf * sinHalf, rho2 * std::sin(gamma)));
  double az = inv.distanceMeters > 0.0 ? inv.azimuth1Deg : 0.0;
  az = std::fmod(az, 360.0);
  if (az < 0) az += 360.0;
  out.azimuthDeg = az >= 360.0 ? 0.0 : az;
  return out;
}

}  // namespace atmoglobe::volume

namespace atmoglobe::volume {

LocalSphereBeam localSphereBeam(const GeolocationSite& site, const BeamModel& model) {
  LocalSphereBeam b;
  b.antennaEcef = globe::geodeticToEcef(globe::Geodetic{site.latDeg, site.lonDeg, site.antennaHeightEllipsoidMeters});
  b.enuToEcef = globe::enuAxes(site.latDeg, site.lonDeg);
  b.antennaHeightMeters = site.antennaHeightEllipsoidMeters;
  b.meridionalRadiusMeters = globe::meridionalRadiusMeters(site.latDeg);
  b.primeVerticalRadiusMeters = globe::primeVerticalRadiusMeters(site.latDeg);
  b.effectiveRadiusMeters = effectiveEarthRadiusMeters(model, site.latDeg);
  return b;
}

AntennaCoordinates LocalSphereBeam::antennaCoordinates(const glm::dvec3& l) const {
  const double dh = std::hypot(l.x, l.y);
  double az = radiansToDegrees(std::atan2(l.x, l.y));
  if (az < 0.0) az += 360.0;
  // The sphere of the normal-section radius in this azimuth (Euler), touching the ellipsoid's
  // tangent plane under the antenna: height above it and arc distance along it.
  const double ca = dh > 0.0 ? l.y / dh : 1.0, sa = dh > 0.0 ? l.x / dh : 0.0;
  const double rAlpha = 1.0 / (ca * ca / meridionalRadiusMeters + sa * sa / primeVerticalRadiusMeters);
  const double rc = rAlpha + antennaHeightMeters;
  const double w = l.z + rc;
  const double dl = std::sqrt(dh * dh + w * w);
  // |centre -> point| - rc without cancellation.
  const double h = antennaHeightMeters + (dh * dh + l.z * l.z + 2.0 * l.z * rc) / (dl + rc);
  const double s = rAlpha * std::atan2(dh, w);
  // The effective-Earth inverse in the form of antennaCoordinatesExact (sin^2(gamma/2)).
  const double re = effectiveRadiusMeters;
  const double gamma = s / re;
  const double rho1 = re + antennaHeightMeters, rho2 = re + h;
  const double sg = std::sin(0.5 * gamma);
  const double dz = h - antennaHeightMeters;
  AntennaCoordinates out;
  out.rangeMeters = std::sqrt(dz * dz + 4.0 * rho1 * rho2 * sg * sg);
  out.azimuthDeg = az >= 360.0 ? 0.0 : az;
  out.elevationDeg = radiansToDegrees(std::atan2(dz - 2.0 * rho2 * sg * sg, rho2 * std::sin(gamma)));
  return out;
}

LocalSphereBeam::Along LocalSphereBeam::along(double rangeMeters, double elevationDeg) const {
  Along a;
  beamHeightAndGroundDistance(rangeMeters, elevationDeg, antennaHeightMeters, effectiveRadiusMeters, &a.heightMeters,
                              &a.groundDistanceMeters);
  return a;
}

LocalSphereBeam::Across LocalSphereBeam::across(double azimuthDeg) const {
  const double az = degreesToRadians(azimuthDeg);
  Across c;
  c.cosAzimuth = std::cos(az);
  c.sinAzimuth = std::sin(az);
  c.normalSectionRadiusMeters = 1.0 / (c.cosAzimuth * c.cosAzimuth / meridionalRadiusMeters +
                                       c.sinAzimuth * c.sinAzimuth / primeVerticalRadiusMeters);
  return c;
}

glm::dvec3 LocalSphereBeam::enuOf(const Along& a, const Across& c) const {
  const double rAlpha = c.normalSectionRadiusMeters;
  const double psi = a.groundDistanceMeters / rAlpha, d = rAlpha + a.heightMeters;
  const double horizontal = d * std::sin(psi);
  return {horizontal * c.sinAzimuth, horizontal * c.cosAzimuth, d * std::cos(psi) - (rAlpha + antennaHeightMeters)};
}

glm::dvec3 LocalSphereBeam::enuOf(double rangeMeters, double azimuthDeg, double elevationDeg) const {
  return enuOf(along(rangeMeters, elevationDeg), across(azimuthDeg));
}

namespace {
// Height above the local sphere of `enu`'s azimuth and the sphere's outward unit normal there.
void localSphereHeightAndNormal(const LocalSphereBeam& b, const glm::dvec3& l, double* h, glm::dvec3* n) {
  const double dh = std::hypot(l.x, l.y);
  const double ca = dh > 0.0 ? l.y / dh : 1.0, sa = dh > 0.0 ? l.x / dh : 0.0;
  const double rAlpha = 1.0 / (ca * ca / b.meridionalRadiusMeters + sa * sa / b.primeVerticalRadiusMeters);
  const double rc = rAlpha + b.antennaHeightMeters;
  const double w = l.z + rc;
  const double dl = std::sqrt(dh * dh + w * w);
  *h = b.antennaHeightMeters + (dh * dh + l.z * l.z + 2.0 * l.z * rc) / (dl + rc);
  *n = glm::dvec3(l.x, l.y, w) / dl;
}
}  // namespace

glm::dvec3 LocalSphereBeam::exaggerateEnu(const glm::dvec3& enu, double factor) const {
  double h = 0.0;
  glm::dvec3 n{0.0};
  localSphereHeightAndNormal(*this, enu, &h, &n);
  return enu + (factor - 1.0) * h * n;
}

glm::dvec3 LocalSphereBeam::unexaggerateEnu(const glm::dvec3& enu, double factor) const {
  double h = 0.0;
  glm::dvec3 n{0.0};
  localSphereHeightAndNormal(*this, enu, &h, &n);
  return enu - (1.0 - 1.0 / factor) * h * n;
}

}  // namespace atmoglobe::volume
