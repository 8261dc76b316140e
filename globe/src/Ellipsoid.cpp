#include <atmoglobe/globe/Ellipsoid.h>

#include <atmoglobe/globe/Angles.h>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/Geodesic.hpp>

#include <cmath>
#include <string>
#include <utility>

namespace atmoglobe::globe {

namespace {
const GeographicLib::Geocentric& earth() { return GeographicLib::Geocentric::WGS84(); }
const GeographicLib::Geodesic& geodesic() { return GeographicLib::Geodesic::WGS84(); }
}  // namespace

Status validateGeodetic(const Geodetic& p, const char* what) {
  if (!std::isfinite(p.latDeg) || !std::isfinite(p.lonDeg) || !std::isfinite(p.heightMeters)) {
    return makeError(std::string(what) + ": latitude, longitude and height must be finite numbers");
  }
  if (p.latDeg < -90.0 || p.latDeg > 90.0) {
    return makeError(std::string(what) + ": latitude " + std::to_string(p.latDeg) + " deg is outside [-90, 90]");
  }
  return Ok{};
}

glm::dvec3 geodeticToEcef(const Geodetic& p) {
  assert(std::isfinite(p.latDeg) && p.latDeg >= -90.0 && p.latDeg <= 90.0);
  double x = 0, y = 0, z = 0;
  earth().Forward(p.latDeg, p.lonDeg, p.heightMeters, x, y, z);
  return {x, y, z};
}

Geodetic ecefToGeodetic(const glm::dvec3& ecef) {
  Geodetic g;
  earth().Reverse(ecef.x, ecef.y, ecef.z, g.latDeg, g.lonDeg, g.heightMeters);
  return g;
}

glm::dmat3 enuAxes(double latDeg, double lonDeg) {
  const double phi = degreesToRadians(latDeg), lambda = degreesToRadians(lonDeg);
  const double sphi = std::sin(phi), cphi = std::cos(phi);
  const double slam = std::sin(lambda), clam = std::cos(lambda);
  const glm::dvec3 east(-slam, clam, 0.0);
  const glm::dvec3 north(-sphi * clam, -sphi * slam, cphi);
  const glm::dvec3 up(cphi * clam, cphi * slam, sphi);
  return glm::dmat3(east, north, up);  // columns
}

glm::dmat4 enuToEcef(const Geodetic& origin) {
  const glm::dmat3 r = enuAxes(origin.latDeg, origin.lonDeg);
  glm::dmat4 m(r);
  m[3] = glm::dvec4(geodeticToEcef(origin), 1.0);
  return m;
}

glm::dvec3 surfaceNormal(double latDeg, double lonDeg) { return enuAxes(latDeg, lonDeg)[2]; }

double wrapLongitudeDeg(double lonDeg) {
  double w = std::fmod(lonDeg + 180.0, 360.0);
  if (w < 0) w += 360.0;
  return w - 180.0;
}

GeodesicPoint geodesicDirect(double latDeg, double lonDeg, double azimuthDeg, double distanceMeters) {
  GeodesicPoint out{};
  geodesic().Direct(latDeg, lonDeg, azimuthDeg, distanceMeters, out.latDeg, out.lonDeg, out.azimuthDeg);
  return out;
}

GeodesicLine geodesicInverse(double lat1Deg, double lon1Deg, double lat2Deg, double lon2Deg) {
  GeodesicLine out{};
  geodesic().Inverse(lat1Deg, lon1Deg, lat2Deg, lon2Deg, out.distanceMeters, out.azimuth1Deg, out.azimuth2Deg);
  return out;
}

double geocentricRadiusMeters(double latDeg) {
  const double phi = degreesToRadians(latDeg);
  const double a = kWgs84A, b = kWgs84B;
  const double c = std::cos(phi), s = std::sin(phi);
  const double num = (a * a * c) * (a * a * c) + (b * b * s) * (b * b * s);
  const double den = (a * c) * (a * c) + (b * s) * (b * s);
  return std::sqrt(num / den);
}

namespace {
// 1 - e^2 sin^2(lat).
double curvatureDenominator(double latDeg) {
  const double s = std::sin(degreesToRadians(latDeg));
  return 1.0 - kWgs84E2 * s * s;
}
}  // namespace

double meridionalRadiusMeters(double latDeg) {
  const double w2 = curvatureDenominator(latDeg);
  return kWgs84A * (1.0 - kWgs84E2) / (w2 * std::sqrt(w2));
}

double primeVerticalRadiusMeters(double latDeg) { return kWgs84A / std::sqrt(curvatureDenominator(latDeg)); }

double normalSectionRadiusMeters(double latDeg, double azimuthDeg) {
  const double a = degreesToRadians(azimuthDeg);
  const double c = std::cos(a), s = std::sin(a);
  return 1.0 / (c * c / meridionalRadiusMeters(latDeg) + s * s / primeVerticalRadiusMeters(latDeg));
}

std::optional<glm::dvec3> intersectRayEllipsoid(const glm::dvec3& originEcef, const glm::dvec3& direction,
                                                double heightMeters) {
  // Scale space so the (raised) ellipsoid becomes the unit sphere, then solve the quadratic.
  const glm::dvec3 radii(kWgs84A + heightMeters, kWgs84A + heightMeters, kWgs84B + heightMeters);
  const glm::dvec3 o = originEcef / radii, d = direction / radii;
  const double a = glm::dot(d, d), b = 2.0 * glm::dot(o, d), c = glm::dot(o, o) - 1.0;
  const double disc = b * b - 4.0 * a * c;
  if (a <= 0.0 || disc < 0.0) return std::nullopt;
  const double sq = std::sqrt(disc);
  // Numerically stable roots (no cancellation when b ~ sqrt(disc)).
  const double q = -0.5 * (b + std::copysign(sq, b));
  double t0 = q / a, t1 = (q != 0.0) ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  const double t = t0 >= 0.0 ? t0 : t1;
  if (t < 0.0) return std::nullopt;
  return originEcef + t * direction;
}

}  // namespace atmoglobe::globe
