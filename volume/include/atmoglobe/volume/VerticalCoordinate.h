#pragma once
// The vertical side of forecast grids: units, the standard atmosphere, geopotential to
// geometric height. Pure functions, double precision; the grid reader (GridReader.h) turns every
// vertical coordinate into a height above the WGS84 ellipsoid with them (rules: docs/grids.md).
#include <optional>
#include <string>

namespace atmoglobe::volume {

/// Standard gravity g0 (m s-2): the constant that defines geopotential height (WMO; CF's
/// `geopotential_height`; ERA `z` / g0). Geopotential Phi (m2 s-2) -> geopotential height Phi/g0.
inline constexpr double kStandardGravity = 9.80665;

/// The gravity WRF uses everywhere (module_model_constants: g = 9.81). WRF's (PH+PHB)/9.81 is
/// its height above sea level: its terrain height HGT equals PHB/9.81 at the lowest W level.
inline constexpr double kWrfGravity = 9.81;

/// Units are read by UDUNITS-2 (its database: SI and common units with prefixes, plurals and
/// the usual spellings of powers: "hPa", "millibars", "kilometres", "m**2 s**-2", "J/kg" ...);
/// symbols are case-sensitive ("PA" is no pressure). A unit converted needs a pure factor
/// (no offset). Thread-safe.
///
/// Factor to Pa of a pressure unit, or nullopt. Also "mb" (the meteorologists' millibar, which
/// UDUNITS-2 reads as a millibarn).
std::optional<double> pressureUnitToPascal(const std::string& units);

/// Factor to metres of a length unit ("m", "metres", "km", "ft" ...), or nullopt. "gpm" / "gpdm"
/// (geopotential metres / decametres) are not lengths: see geopotentialHeightUnitToMeters.
std::optional<double> lengthUnitToMeters(const std::string& units);

/// Factor to geopotential metres of "gpm", "gpdm", "dam", "geopotential meter(s)" ..., or nullopt
/// (spellings of model output: UDUNITS-2 has no geopotential metre).
std::optional<double> geopotentialHeightUnitToMeters(const std::string& units);

/// Factor to m2 s-2 of a geopotential unit (m2 s-2, m**2 s**-2, m^2/s^2, J kg-1, J/kg ...), or
/// nullopt.
std::optional<double> geopotentialUnitToSi(const std::string& units);
/// geopotentialUnitToSi(units) has a value.
bool isGeopotentialUnit(const std::string& units);

/// Why UDUNITS-2's database could not be read ("" when it was): every conversion above then
/// gives nullopt, and messages about units quote this.
const std::string& unitDatabaseProblem();

/// Geopotential height (m') of pressure `pressurePa` in the standard atmosphere: ICAO / U.S.
/// Standard Atmosphere 1976, its seven layers to 84.852 km (lapse rates -6.5, 0, +1, +2.8, 0,
/// -2.8, -2 K/km from 288.15 K, 101325 Pa at 0 m'; R = 287.05287 J kg-1 K-1, g0 = 9.80665),
/// extended beyond both ends with the outer layers. An approximation for a real atmosphere:
/// real heights of a pressure level differ by up to a few hundred metres. Precondition: p > 0.
double standardAtmosphereGeopotentialHeightMeters(double pressurePa);

/// Inverse of standardAtmosphereGeopotentialHeightMeters: pressure (Pa) at geopotential height H.
double standardAtmospherePressurePa(double geopotentialHeightMeters);

/// Geometric height (m above sea level) of geopotential height H (m') at geodetic latitude
/// `latDeg`: solves g0 H = integral of gamma(lat, z) dz from 0 to z, with WGS84 normal gravity
/// above the ellipsoid to second order in z (NIMA TR8350.2, 3rd ed., eq. 4-3:
/// gamma(z) = gamma(lat) [1 - 2/a (1 + f + m - 2 f sin^2 lat) z + 3 z^2 / a^2]). Gravity anomalies
/// (tens of mGal, i.e. ~1e-4 of g) are ignored: an error of ~1e-4 z, 1 m at 10 km.
double geometricFromGeopotentialHeightMeters(double geopotentialHeightMeters, double latDeg);

/// The same for many heights at one latitude: the latitude terms computed once.
class GeopotentialToGeometric {
 public:
  explicit GeopotentialToGeometric(double latDeg);
  double operator()(double geopotentialHeightMeters) const;

 private:
  double gammaRatio_ = 1.0;  ///< g0 / gamma(lat)
  double c1_ = 0.0;          ///< (1 + f + m - 2 f sin^2 lat) / a
};

/// WGS84 normal gravity on the ellipsoid at geodetic latitude `latDeg` (m s-2), Somigliana's
/// closed formula with the WGS84 constants (NIMA TR8350.2, 3rd ed., eq. 4-1).
double normalGravity(double latDeg);

}  // namespace atmoglobe::volume
