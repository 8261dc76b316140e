#include <atmoglobe/volume/VerticalCoordinate.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Text.h>

#include <udunits2.h>

#include <array>
#include <cmath>
#include <map>
#include <mutex>

namespace atmoglobe::volume {

namespace {

/// The quantities whose units the grid reader converts: pressure (to Pa), length (to m) and
/// geopotential (to m2 s-2).
enum class Quantity { Pressure, Length, Geopotential };

/// UDUNITS-2's unit database, read once, and the factors found so far. UDUNITS-2 is not
/// thread-safe (its parser keeps global state): every call holds `mutex`.
struct UnitDatabase {
  std::mutex mutex;
  ut_system* system = nullptr;
  std::array<ut_unit*, 3> targets{};  ///< Pa, m, m2 s-2 (Quantity order)
  std::string problem;                ///< why the database could not be read ("" when it was)
  std::map<std::pair<std::string, Quantity>, std::optional<double>> factors;

  UnitDatabase() {
    ut_set_error_message_handler(ut_ignore);  // failures are reported by status, not on stderr
    system = ut_read_xml(nullptr);            // $UDUNITS2_XML_PATH, else the installed database
    if (!system) {
      problem = "the UDUNITS-2 unit database could not be read (status " + std::to_string(ut_get_status()) +
                "; Debian: libudunits2-data, or set UDUNITS2_XML_PATH)";
      return;
    }
    const char* symbols[] = {"Pa", "m", "m2 s-2"};
    for (std::size_t i = 0; i < targets.size(); ++i) targets[i] = ut_parse(system, symbols[i], UT_ASCII);
  }
  ~UnitDatabase() {
    for (ut_unit* t : targets) ut_free(t);
    if (system) ut_free_system(system);
  }
};

UnitDatabase& unitDatabase() {
  static UnitDatabase db;
  return db;
}

/// Factor from `units` to the SI unit of `q`, by UDUNITS-2: a unit it parses, convertible to
/// the target by a pure factor (no offset); nullopt otherwise.
std::optional<double> factorToSi(const std::string& units, Quantity q) {
  const std::string text(trimAscii(units));
  if (text.empty()) return std::nullopt;
  UnitDatabase& db = unitDatabase();
  const std::lock_guard<std::mutex> lock(db.mutex);
  if (!db.system) return std::nullopt;
  const auto key = std::make_pair(text, q);
  if (auto it = db.factors.find(key); it != db.factors.end()) return it->second;
  std::optional<double> factor;
  ut_unit* target = db.targets[static_cast<std::size_t>(q)];
  if (ut_unit* u = ut_parse(db.system, text.c_str(), UT_UTF8)) {
    if (target && ut_are_convertible(u, target)) {
      if (cv_converter* c = ut_get_converter(u, target)) {
        const double k = cv_convert_double(c, 1.0);
        if (cv_convert_double(c, 0.0) == 0.0 && std::isfinite(k) && k > 0.0) factor = k;
        cv_free(c);
      }
    }
    ut_free(u);
  }
  // Kept for the next file (a few spellings in practice); bounded, so that a stream of damaged
  // files with ever new unit strings cannot grow it without end.
  if (db.factors.size() < 4096) db.factors.emplace(key, factor);
  return factor;
}

// Lower case, blanks trimmed, each run of blanks inside one space ("Geopotential  Metres" ->
// "geopotential metres").
std::string lowerTrim(const std::string& s) {
  std::string out;
  for (char c : trimAscii(s)) {
    if (!isSpaceAscii(c)) out.push_back(toLowerAscii(c));
    else if (out.back() != ' ') out.push_back(' ');  // not empty: the text starts with a non-blank
  }
  return out;
}

// U.S. Standard Atmosphere 1976 (= ICAO ISA below 32 km): layer base geopotential heights (m')
// and lapse rates (K/m); base temperatures and pressures follow from 288.15 K, 101325 Pa.
constexpr double kR = 287.05287;  // specific gas constant of dry air used by the standard (J kg-1 K-1)
constexpr std::array<double, 7> kBaseH = {0.0, 11000.0, 20000.0, 32000.0, 47000.0, 51000.0, 71000.0};
constexpr std::array<double, 7> kLapse = {-0.0065, 0.0, 0.001, 0.0028, 0.0, -0.0028, -0.002};

struct Layers {
  std::array<double, 7> t{}, p{};
};

const Layers& layers() {
  static const Layers l = [] {
    Layers r;
    r.t[0] = 288.15;
    r.p[0] = 101325.0;
    for (std::size_t i = 1; i < kBaseH.size(); ++i) {
      const double dh = kBaseH[i] - kBaseH[i - 1];
      const double l0 = kLapse[i - 1];
      r.t[i] = r.t[i - 1] + l0 * dh;
      r.p[i] = l0 == 0.0 ? r.p[i - 1] * std::exp(-kStandardGravity * dh / (kR * r.t[i - 1]))
                         : r.p[i - 1] * std::pow(r.t[i] / r.t[i - 1], -kStandardGravity / (kR * l0));
    }
    return r;
  }();
  return l;
}

}  // namespace

std::optional<double> pressureUnitToPascal(const std::string& units) {
  // "mb" is the meteorologists' millibar; UDUNITS-2 reads it as a millibarn (an area).
  if (lowerTrim(units) == "mb") return 100.0;
  return factorToSi(units, Quantity::Pressure);
}

std::optional<double> lengthUnitToMeters(const std::string& units) { return factorToSi(units, Quantity::Length); }

std::optional<double> geopotentialHeightUnitToMeters(const std::string& units) {
  // Geopotential metres are no unit of UDUNITS-2 (a geopotential height is a geopotential / g0,
  // written as a length): the spellings model output uses.
  const std::string u = lowerTrim(units);
  if (u == "gpm" || u == "geopotential meter" || u == "geopotential meters" || u == "geopotential metre" ||
      u == "geopotential metres" || u == "m gpm")
    return 1.0;
  if (u == "gpdm" || u == "dam" || u == "geopotential decameter" || u == "geopotential decameters") return 10.0;
  return std::nullopt;
}

std::optional<double> geopotentialUnitToSi(const std::string& units) {
  return factorToSi(units, Quantity::Geopotential);
}

bool isGeopotentialUnit(const std::string& units) { return geopotentialUnitToSi(units).has_value(); }

const std::string& unitDatabaseProblem() {
  UnitDatabase& db = unitDatabase();
  const std::lock_guard<std::mutex> lock(db.mutex);
  return db.problem;
}

double standardAtmosphereGeopotentialHeightMeters(double pressurePa) {
  const Layers& l = layers();
  std::size_t i = 0;
  while (i + 1 < kBaseH.size() && pressurePa <= l.p[i + 1]) ++i;
  const double lapse = kLapse[i];
  if (lapse == 0.0) return kBaseH[i] - kR * l.t[i] / kStandardGravity * std::log(pressurePa / l.p[i]);
  return kBaseH[i] + l.t[i] / lapse * (std::pow(pressurePa / l.p[i], -kR * lapse / kStandardGravity) - 1.0);
}

double standardAtmospherePressurePa(double h) {
  const Layers& l = layers();
  std::size_t i = 0;
  while (i + 1 < kBaseH.size() && h >= kBaseH[i + 1]) ++i;
  const double lapse = kLapse[i];
  const double dh = h - kBaseH[i];
  if (lapse == 0.0) return l.p[i] * std::exp(-kStandardGravity * dh / (kR * l.t[i]));
  return l.p[i] * std::pow((l.t[i] + lapse * dh) / l.t[i], -kStandardGravity / (kR * lapse));
}

double normalGravity(double latDeg) {
  // WGS84 (TR8350.2 table 3.4): equatorial normal gravity, Somigliana's constant k; e^2 of the ellipsoid.
  constexpr double kGammaE = 9.7803253359, kK = 0.00193185265241;
  const double s = std::sin(degreesToRadians(latDeg));
  return kGammaE * (1.0 + kK * s * s) / std::sqrt(1.0 - globe::kWgs84E2 * s * s);
}

GeopotentialToGeometric::GeopotentialToGeometric(double latDeg) {
  constexpr double kM = 0.00344978650684;  // WGS84 m = omega^2 a^2 b / GM (TR8350.2 table 3.4)
  const double s = std::sin(degreesToRadians(latDeg));
  gammaRatio_ = kStandardGravity / normalGravity(latDeg);
  c1_ = (1.0 + globe::kWgs84F + kM - 2.0 * globe::kWgs84F * s * s) / globe::kWgs84A;
}

double GeopotentialToGeometric::operator()(double geopotentialHeightMeters) const {
  // g0 H = gamma (z - c1 z^2 + z^3 / a^2): the integral of gamma(z) = gamma (1 - 2 c1 z + 3 z^2/a^2).
  constexpr double kInvA2 = 1.0 / (globe::kWgs84A * globe::kWgs84A);
  const double target = gammaRatio_ * geopotentialHeightMeters;
  double z = target;
  for (int it = 0; it < 3; ++it) {  // Newton from z = target: below 1e-6 m after 3 steps up to 100 km
    const double g = z - c1_ * z * z + z * z * z * kInvA2 - target;
    const double dg = 1.0 - 2.0 * c1_ * z + 3.0 * z * z * kInvA2;
    z -= g / dg;
  }
  return z;
}

double geometricFromGeopotentialHeightMeters(double geopotentialHeightMeters, double latDeg) {
  return GeopotentialToGeometric(latDeg)(geopotentialHeightMeters);
}

}  // namespace atmoglobe::volume
