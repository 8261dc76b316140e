#pragma once
// Where a radar gate is: antenna coordinates (range, azimuth, elevation) <-> WGS84.
//
// The model (the 4/3 effective-Earth model of Doviak & Zrnic 1993, eq. 2.28):
//   - the beam is a circle of effective Earth radius Re = ke * R, with R either a fixed sphere
//     radius or, by default, the WGS84 geocentric radius at the site latitude (as wradlib);
//   - gate height h = sqrt(r^2 + (Re+h0)^2 + 2 r (Re+h0) sin(theta)) - Re, above the datum of h0;
//   - ground (arc) distance s = Re * asin(r cos(theta) / (Re + h));
//   - horizontal position: the WGS84 geodesic from the site with the ray's azimuth, s metres long
//     (an ellipsoidal azimuthal-equidistant map centred on the site, as wradlib);
//   - ECEF from (lat, lon, h) on WGS84 (GeographicLib through globe/Ellipsoid.h).
// Heights: h0 is the antenna height above the WGS84 ellipsoid (resolveSite converts from mean sea
// level with EGM96), so gate heights are above the ellipsoid too.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// The standard refraction factor ke of the effective-Earth model: 4/3 for the standard
/// atmosphere's refractivity gradient (Doviak & Zrnic 1993, section 2.2). The default of every
/// beam model (BeamModel, `--ke`).
inline constexpr double kEffectiveEarthFactor = 4.0 / 3.0;

/// Effective-Earth-radius beam propagation model.
struct BeamModel {
  double ke = kEffectiveEarthFactor;        ///< refraction factor (1: straight beam over a sphere of radius R)
  std::optional<double> earthRadiusMeters;  ///< R (m); nullopt: WGS84 geocentric radius at the site latitude
};

/// ke finite and > 0, R (if given) finite and > 0. `what` names the source for the message.
Status validateBeamModel(const BeamModel& model, const char* what);

/// Re = ke * R (m) for a site at geodetic latitude `siteLatDeg`.
double effectiveEarthRadiusMeters(const BeamModel& model, double siteLatDeg);

/// A radar site ready for geolocation: WGS84 latitude/longitude (degrees), antenna height above
/// the WGS84 ellipsoid (m).
struct GeolocationSite {
  double latDeg = 0.0;
  double lonDeg = 0.0;
  double antennaHeightEllipsoidMeters = 0.0;
};

/// How the antenna height was brought to the ellipsoid.
struct SiteResolution {
  GeolocationSite site;
  double geoidUndulationMeters = 0.0;  ///< N added to the MSL height (0 when not applied)
  bool geoidApplied = false;
  std::string datumNote;  ///< one line for users: which datum, which undulation
};

/// Antenna height above the ellipsoid from a RadarSite. Heights above mean sea level get the EGM96
/// undulation (defaultEgm96Grid()) unless useGeoid is false, in which case the MSL height is used
/// as if it were ellipsoidal (error = -N, up to about 100 m; the note says so). Errors: non-finite
/// or out-of-range coordinates, missing geoid grid (message names the file).
Result<SiteResolution> resolveSite(const RadarSite& site, bool useGeoid);
/// Same with an explicit geoid grid (nullptr: no geoid conversion).
Result<SiteResolution> resolveSite(const RadarSite& site, const GeoidGrid* geoid);

struct GatePosition {
  double latDeg = 0.0;        ///< WGS84 geodetic latitude (degrees)
  double lonDeg = 0.0;        ///< longitude (degrees, [-180, 180])
  double heightMeters = 0.0;  ///< beam-centre height above the WGS84 ellipsoid (m)
  glm::dvec3 ecef{0.0};       ///< ECEF (m)
};

/// Beam-centre height above the datum of `antennaHeightMeters` and ground (arc) distance along
/// the effective sphere (m), for slant range `rangeMeters` (m) at elevation `elevationDeg`
/// (Doviak & Zrnic 2.28). Closed form; exact within the model.
void beamHeightAndGroundDistance(double rangeMeters, double elevationDeg, double antennaHeightMeters,
                                 double effectiveRadiusMeters, double* heightMeters, double* groundDistanceMeters);

/// Exact path: double precision, one WGS84 geodesic (GeographicLib Direct, ~15 nm) per gate.
/// Azimuth in degrees clockwise from north, elevation in degrees, range in m (gate centre).
/// Precondition: finite arguments, site from resolveSite, model validated.
GatePosition geolocateGateExact(const GeolocationSite& site, const BeamModel& model, double azimuthDeg,
                                double elevationDeg, double rangeMeters);

/// Fast path for a whole sweep. ECEF (m) of every gate, ray-major (ecefOut[ray * gateCount + gate]).
///
/// Per ray, the gate position is a smooth function of range along the ray; it is sampled exactly
/// (geodesic + model) at kFastChebyshevNodes Chebyshev nodes spanning the sweep's gate ranges and
/// represented by a Chebyshev series per ECEF axis (per-ray table of coefficients). A per-gate table
/// holds the Chebyshev basis at each gate range (shared by all rays), so the per-gate work is 3
/// short dot products, contiguous and vectorisable. Per-ray elevations are honoured exactly.
///
/// Measured error against geolocateGateExact (GeolocationTest.FastPath*, bench_radar_read_geolocate):
/// max 1.5e-8 m over all 6,003,360 gates of the KLBB NEXRAD REF volume (ranges to 459.9 km) and
/// max 1.6e-8 m over synthetic 460 km sweeps at sites at 89.99 N/S, 90 N, on the antimeridian, at
/// elevations -1..90 deg, ke 1 and 4/3. Stated bound (asserted by the tests): kFastPathMaxErrorMeters
/// = 1e-6 m. Speed: ~50x the exact path (1.1e8 vs 2.2e6 gates/s, docs/bench-radar.md).
/// Sweeps with fewer gates than nodes use the exact path. Precondition: finite angles, site and
/// model as for the exact path.
void geolocateSweepFast(const GeolocationSite& site, const BeamModel& model, const Sweep& sweep,
                        std::vector<glm::dvec3>* ecefOut);

/// Number of Chebyshev nodes per ray used by geolocateSweepFast.
inline constexpr int kFastChebyshevNodes = 12;
/// Stated bound on |fast - exact| ECEF distance (m), checked by the tests (see above).
inline constexpr double kFastPathMaxErrorMeters = 1e-6;

/// Antenna coordinates of a point relative to the site.
struct AntennaCoordinates {
  double rangeMeters = 0.0;   ///< slant range along the (curved) beam model (m)
  double azimuthDeg = 0.0;    ///< [0, 360) clockwise from north (0 directly above the site)
  double elevationDeg = 0.0;  ///< degrees above horizontal
};

/// Inverse of geolocateGateExact: ECEF point (m) -> (range, azimuth, elevation) under the same
/// model (Doviak & Zrnic 1993, eq. 2.28, rewritten with sin^2(gamma/2) to avoid cancellation). Round trip with the
/// forward path is within 1 mm (GeolocationTest.InverseRoundTrip).
AntennaCoordinates antennaCoordinatesExact(const GeolocationSite& site, const BeamModel& model, const glm::dvec3& ecef);

/// The beam model on a local sphere: what the GPU marcher evaluates per sample (in float32,
/// shaders/sample_polar.glsl), here in double as its CPU twin. A point's horizontal position is
/// taken on the sphere whose radius is the WGS84 normal-section radius at the site in the
/// point's azimuth (globe::normalSectionRadiusMeters), instead of the geodesic of the exact path;
/// heights and ranges follow the effective-Earth model (Doviak & Zrnic 1993, eq. 2.28) as in the
/// exact path. Coordinates are in the site's ENU frame (m, origin at the antenna).
///
/// Measured error of the inverse against antennaCoordinatesExact (GeolocationTest.LocalSphere*,
/// points out to 460 km at elevations 0..20 deg, sites at 0, 33.7, 60 and 89.9 deg latitude):
/// see kLocalSphereMaxRangeErrorMeters and kLocalSphereMaxAngleErrorDeg.
struct LocalSphereBeam {
  glm::dvec3 antennaEcef{0.0};
  glm::dmat3 enuToEcef{1.0};               ///< columns east, north, up at the site
  double antennaHeightMeters = 0.0;        ///< h0 above the ellipsoid (m)
  double meridionalRadiusMeters = 0.0;     ///< M at the site (m)
  double primeVerticalRadiusMeters = 0.0;  ///< N at the site (m)
  double effectiveRadiusMeters = 0.0;      ///< Re = ke R (m)

  /// Antenna coordinates of a point given in the site's ENU frame (m).
  AntennaCoordinates antennaCoordinates(const glm::dvec3& enu) const;
  /// The forward map: ENU position (m) of (range, azimuth, elevation).
  glm::dvec3 enuOf(double rangeMeters, double azimuthDeg, double elevationDeg) const;
  /// The forward map in its two factors, for many points that share ranges and elevations or
  /// azimuths (an empty-space grid's boxes): what depends on range and elevation only (the
  /// beam's height and ground distance) and what depends on azimuth only (its direction and
  /// normal-section radius). enuOf(along(r, el), across(az)) equals enuOf(r, az, el) exactly.
  struct Along {
    double heightMeters = 0.0, groundDistanceMeters = 0.0;
  };
  struct Across {
    double cosAzimuth = 1.0, sinAzimuth = 0.0, normalSectionRadiusMeters = 0.0;
  };
  Along along(double rangeMeters, double elevationDeg) const;
  Across across(double azimuthDeg) const;
  glm::dvec3 enuOf(const Along& a, const Across& c) const;
  /// Vertical exaggeration on the local sphere (VerticalExaggeration.h): the point at height h
  /// above the sphere (of this azimuth's normal-section radius) moved along the sphere's normal
  /// to height e h (exaggerateEnu), and back (unexaggerateEnu). Exact inverses of each other.
  glm::dvec3 exaggerateEnu(const glm::dvec3& enu, double factor) const;
  glm::dvec3 unexaggerateEnu(const glm::dvec3& enu, double factor) const;
  /// ECEF -> the site's ENU frame (m).
  glm::dvec3 enuOfEcef(const glm::dvec3& ecef) const { return glm::transpose(enuToEcef) * (ecef - antennaEcef); }
};
LocalSphereBeam localSphereBeam(const GeolocationSite& site, const BeamModel& model);

/// Stated bounds of |local sphere - exact| for the inverse out to 460 km (checked by the tests;
/// measured: 2.15 m in range, 0.0048 deg in azimuth (at 89.9 deg latitude), 0.0005 deg in
/// elevation; the GPU's float32 version adds rounding: 2.1 m, 0.0014 deg, 0.0008 deg on the
/// RadarMarch test's view).
inline constexpr double kLocalSphereMaxRangeErrorMeters = 5.0;
inline constexpr double kLocalSphereMaxAngleErrorDeg = 0.01;

}  // namespace atmoglobe::volume
