#pragma once
// WGS84 ellipsoid: geodetic <-> ECEF, local frames and geodesics.
//
// The one place atmoglobe calls GeographicLib for the Earth model. GeographicLib's
// exceptions and its NaN results for latitudes outside [-90, 90] stop here: every
// function either has a documented precondition (asserted) or returns a Result.
//
// Accuracy: GeographicLib::Geocentric is accurate to a few nanometres within 5000 km
// of the surface; Geodesic to about 15 nm (Karney 2013).
#include <atmoglobe/globe/Result.h>

#include <glm/glm.hpp>

#include <optional>

namespace atmoglobe::globe {

/// WGS84 defining constants (NIMA TR8350.2, 3rd ed., table 3.1), the only spelling of them: C++
/// uses these and GLSL gets them as defines (engine/ShaderConstants.h).
inline constexpr double kWgs84A = 6378137.0;            ///< semi-major axis (m)
inline constexpr double kWgs84F = 1.0 / 298.257223563;  ///< flattening
/// Derived (table 3.3).
inline constexpr double kWgs84B = kWgs84A * (1.0 - kWgs84F);   ///< semi-minor axis (m)
inline constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);  ///< first eccentricity squared, 1 - b^2 / a^2

/// A point given by WGS84 geodetic coordinates.
struct Geodetic {
  double latDeg = 0.0;        ///< geodetic latitude (degrees, [-90, 90])
  double lonDeg = 0.0;        ///< longitude (degrees, any value; east positive)
  double heightMeters = 0.0;  ///< height above the WGS84 ellipsoid (m)
};

/// Checks a geodetic position from outside (file, command line): finite values and a
/// latitude in [-90, 90]. `what` names the source for the message.
Status validateGeodetic(const Geodetic& p, const char* what);

/// Geodetic -> Earth-centred Earth-fixed (m). Precondition: validateGeodetic passed.
glm::dvec3 geodeticToEcef(const Geodetic& p);

/// ECEF (m) -> geodetic. Longitude in [-180, 180]. Any finite ECEF point is valid
/// (the centre of the Earth maps to latitude +-90 deg by GeographicLib's convention).
Geodetic ecefToGeodetic(const glm::dvec3& ecef);

/// Rotation whose columns are the local east, north and up unit vectors (in ECEF) at
/// the given geodetic latitude/longitude (degrees). Up is the ellipsoid normal.
glm::dmat3 enuAxes(double latDeg, double lonDeg);

/// 4x4 transform from a local east-north-up frame at `origin` to ECEF (m).
glm::dmat4 enuToEcef(const Geodetic& origin);

/// Outward ellipsoid normal at a geodetic latitude/longitude (degrees).
glm::dvec3 surfaceNormal(double latDeg, double lonDeg);

/// Wraps a longitude to [-180, 180).
double wrapLongitudeDeg(double lonDeg);

/// Solution of the direct geodesic problem on WGS84.
struct GeodesicPoint {
  double latDeg;
  double lonDeg;
  double azimuthDeg;  ///< forward azimuth at the end point (degrees clockwise from north)
};

/// Walks the WGS84 geodesic from (latDeg, lonDeg) with initial azimuth `azimuthDeg`
/// (clockwise from north) for `distanceMeters`. Accuracy ~15 nm.
GeodesicPoint geodesicDirect(double latDeg, double lonDeg, double azimuthDeg, double distanceMeters);

/// Solution of the inverse geodesic problem on WGS84.
struct GeodesicLine {
  double distanceMeters;
  double azimuth1Deg;  ///< azimuth at the first point (degrees clockwise from north)
  double azimuth2Deg;  ///< azimuth at the second point
};

GeodesicLine geodesicInverse(double lat1Deg, double lon1Deg, double lat2Deg, double lon2Deg);

/// WGS84 geocentric radius at geodetic latitude `latDeg` (m):
/// R = sqrt(((a^2 cos)^2 + (b^2 sin)^2) / ((a cos)^2 + (b sin)^2)).
double geocentricRadiusMeters(double latDeg);

/// WGS84 radius of curvature in the meridian at geodetic latitude `latDeg` (m):
/// M = a (1 - e^2) / (1 - e^2 sin^2(lat))^(3/2) (NIMA TR8350.2, 3rd ed., section 4).
double meridionalRadiusMeters(double latDeg);

/// WGS84 radius of curvature in the prime vertical at geodetic latitude `latDeg` (m):
/// N = a / sqrt(1 - e^2 sin^2(lat)) (NIMA TR8350.2, 3rd ed., section 4).
double primeVerticalRadiusMeters(double latDeg);

/// Radius of curvature of the WGS84 normal section at latitude `latDeg` in the direction
/// `azimuthDeg` (clockwise from north), by Euler's theorem: 1 / (cos^2(az) / M + sin^2(az) / N) (m).
double normalSectionRadiusMeters(double latDeg, double azimuthDeg);

/// First intersection (ECEF, m) of the ray origin + t*direction, t >= 0, with the
/// ellipsoid raised by heightMeters (axes a+h, a+h, b+h); nullopt if it misses.
/// `direction` need not be unit length. Used for picking (what is under the cursor).
std::optional<glm::dvec3> intersectRayEllipsoid(const glm::dvec3& originEcef, const glm::dvec3& direction,
                                                double heightMeters = 0.0);

}  // namespace atmoglobe::globe
