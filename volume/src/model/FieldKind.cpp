// Field kinds, the default field and default colours (FieldKind.h).
#include <atmoglobe/volume/FieldKind.h>

#include <atmoglobe/globe/Text.h>
#include <atmoglobe/volume/ColorTable.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

namespace atmoglobe::volume {
namespace {

/// A variable's own name, lower case: netCDF-4 paths ("/forecast/QRAIN") lose their groups.
std::string ownName(const std::string& name) {
  const std::size_t slash = name.find_last_of('/');
  return toLowerAscii(slash == std::string::npos ? name : name.substr(slash + 1));
}

// Known names per kind, lower case; for reflectivity in order of preference.
const std::vector<std::string> kReflectivityNames = {"dbzh",
                                                     "reflectivity",
                                                     "ref",
                                                     "dbz",
                                                     "dbzhc",
                                                     "th",
                                                     "dbzh_clean",
                                                     "corrected_reflectivity",
                                                     "reflectivity_horizontal",
                                                     "zh",
                                                     "z",
                                                     "dz",
                                                     "cz",
                                                     "dbzv",
                                                     "tv"};
const std::vector<std::string> kVelocityNames = {
    "vradh", "vrad", "vel", "velocity", "v", "vr", "vradv", "corrected_velocity", "vraddh", "dealiased_velocity"};
const std::vector<std::string> kWidthNames = {"wradh", "wrad", "sw", "spectrum_width", "w", "wradv", "width"};
const std::vector<std::string> kZdrNames = {"zdr", "differential_reflectivity", "dr"};
const std::vector<std::string> kRhoNames = {"rhohv", "rho", "cross_correlation_ratio", "cc", "rhohv_corr"};
const std::vector<std::string> kPhiNames = {"phidp", "phi", "differential_phase", "uphidp"};
const std::vector<std::string> kKdpNames = {"kdp", "specific_differential_phase"};

bool contains(const std::vector<std::string>& list, const std::string& s) {
  return std::find(list.begin(), list.end(), s) != list.end();
}

bool isDbz(const std::string& units) { return toLowerAscii(units) == "dbz"; }

bool isMetresPerSecond(const std::string& units) {
  const std::string u = toLowerAscii(units);
  return u == "m/s" || u == "m s-1" || u == "m.s-1" || u == "meters per second" || u == "metres per second" ||
         u == "meters_per_second" || u == "meter/second" || u == "meters/second";
}

ColorStop blend(double value, Rgba8 a, Rgba8 b) { return ColorStop{value, a, b}; }

// Diverging velocity colours over +-v: towards the radar (negative) green, away red, near zero a
// translucent grey; alpha grows with |velocity| so that the fast flow shows through slow echo.
ColorTable velocityTable(double v) {
  const Rgba8 darkGreen{0, 90, 0, 255}, green{0, 220, 0, 235}, paleGreen{150, 230, 150, 110}, grey{140, 140, 140, 60},
      paleRed{235, 150, 150, 110}, red{235, 0, 0, 235}, darkRed{120, 0, 0, 255};
  return ColorTable("Velocity", "m/s",
                    {blend(-v, darkGreen, green), blend(-0.5 * v, green, paleGreen), blend(-0.1 * v, paleGreen, grey),
                     blend(0.0, grey, paleRed), blend(0.1 * v, paleRed, red), blend(0.5 * v, red, darkRed),
                     blend(v, darkRed, darkRed)});
}

ColorTable spectrumWidthTable() {
  return ColorTable(
      "Spectrum width", "m/s",
      {blend(0.0, {120, 120, 120, 255}, {200, 200, 200, 255}), blend(4.0, {200, 200, 200, 255}, {255, 230, 0, 255}),
       blend(8.0, {255, 230, 0, 255}, {255, 120, 0, 255}), blend(12.0, {255, 120, 0, 255}, {200, 0, 0, 255}),
       blend(16.0, {200, 0, 0, 255}, {200, 0, 0, 255})});
}

ColorTable zdrTable() {
  return ColorTable(
      "ZDR", "dB",
      {blend(-2.0, {90, 0, 140, 255}, {40, 60, 220, 255}), blend(0.0, {40, 60, 220, 255}, {0, 190, 120, 255}),
       blend(1.0, {0, 190, 120, 255}, {240, 230, 0, 255}), blend(2.0, {240, 230, 0, 255}, {255, 140, 0, 255}),
       blend(3.0, {255, 140, 0, 255}, {220, 0, 0, 255}), blend(5.0, {220, 0, 0, 255}, {255, 0, 220, 255}),
       blend(8.0, {255, 0, 220, 255}, {255, 0, 220, 255})});
}

// Most of the colours above 0.9, where rain (0.97-1) and mixed phase / debris (< 0.9) separate.
ColorTable rhohvTable() {
  return ColorTable(
      "RhoHV", "",
      {blend(0.2, {60, 0, 100, 255}, {30, 60, 200, 255}), blend(0.7, {30, 60, 200, 255}, {0, 200, 220, 255}),
       blend(0.85, {0, 200, 220, 255}, {0, 190, 60, 255}), blend(0.93, {0, 190, 60, 255}, {240, 230, 0, 255}),
       blend(0.97, {240, 230, 0, 255}, {255, 120, 0, 255}), blend(0.99, {255, 120, 0, 255}, {220, 0, 0, 255}),
       blend(1.0, {220, 0, 0, 255}, {255, 0, 220, 255}), blend(1.05, {255, 0, 220, 255}, {255, 0, 220, 255})});
}

ColorTable kdpTable() {
  return ColorTable(
      "KDP", "deg/km",
      {blend(-2.0, {120, 120, 120, 255}, {160, 160, 160, 255}), blend(0.0, {160, 160, 160, 255}, {0, 190, 220, 255}),
       blend(1.0, {0, 190, 220, 255}, {0, 190, 60, 255}), blend(2.0, {0, 190, 60, 255}, {240, 230, 0, 255}),
       blend(4.0, {240, 230, 0, 255}, {220, 0, 0, 255}), blend(8.0, {220, 0, 0, 255}, {220, 0, 0, 255})});
}

// The file's Nyquist velocity; else the largest |value| of the field (velocities are coded
// within +-Nyquist, so that is the next best scale); else 30 m/s.
double velocityScale(double nyquistMps, const ValueRange& range) {
  if (std::isfinite(nyquistMps) && nyquistMps > 0.0) return nyquistMps;
  const double m = std::max(std::abs(range.minValue), std::abs(range.maxValue));
  return std::isfinite(m) && m > 0.5 ? m : 30.0;
}

// Opacity: the table's alpha only (the ramp is full from the first stop on).
TransferFunction tableAlphaOnly(ColorTable table, double maxOpacity) {
  TransferFunction t;
  const double first = table.stops().empty() ? 0.0 : table.stops().front().value;
  t.colors = std::move(table);
  t.opacityZeroValue = first - 2.0;
  t.opacityFullValue = first - 1.0;
  t.maxOpacity = maxOpacity;
  return t;
}

TransferFunction ramp(ColorTable table, double zero, double full, double maxOpacity) {
  TransferFunction t;
  t.colors = std::move(table);
  t.opacityZeroValue = zero;
  t.opacityFullValue = full;
  t.maxOpacity = maxOpacity;
  return t;
}

}  // namespace

const char* toString(FieldKind kind) {
  switch (kind) {
    case FieldKind::Reflectivity: return "reflectivity";
    case FieldKind::Velocity: return "radial velocity";
    case FieldKind::SpectrumWidth: return "spectrum width";
    case FieldKind::DifferentialReflectivity: return "differential reflectivity";
    case FieldKind::CorrelationCoefficient: return "correlation coefficient";
    case FieldKind::DifferentialPhase: return "differential phase";
    case FieldKind::SpecificDifferentialPhase: return "specific differential phase";
    case FieldKind::Other: return "other";
  }
  return "other";
}

FieldKindEvidence classifyField(const FieldInfo& f) {
  const std::string sn = toLowerAscii(f.standardName);
  struct ByStandardName {
    const char* name;
    FieldKind kind;
  };
  for (const ByStandardName& s : {ByStandardName{"equivalent_reflectivity_factor", FieldKind::Reflectivity},
                                  {"radial_velocity_of_scatterers_away_from_instrument", FieldKind::Velocity},
                                  {"doppler_spectrum_width", FieldKind::SpectrumWidth},
                                  {"log_differential_reflectivity_hv", FieldKind::DifferentialReflectivity},
                                  {"cross_correlation_ratio_hv", FieldKind::CorrelationCoefficient},
                                  {"differential_phase_hv", FieldKind::DifferentialPhase},
                                  {"specific_differential_phase_hv", FieldKind::SpecificDifferentialPhase}}) {
    if (sn == s.name) return {s.kind, std::string("CF standard_name ").append(s.name)};
  }
  const std::string n = ownName(f.name);
  struct ByName {
    const std::vector<std::string>* names;
    FieldKind kind;
  };
  for (const ByName& b : {ByName{&kReflectivityNames, FieldKind::Reflectivity},
                          {&kVelocityNames, FieldKind::Velocity},
                          {&kWidthNames, FieldKind::SpectrumWidth},
                          {&kZdrNames, FieldKind::DifferentialReflectivity},
                          {&kRhoNames, FieldKind::CorrelationCoefficient},
                          {&kPhiNames, FieldKind::DifferentialPhase},
                          {&kKdpNames, FieldKind::SpecificDifferentialPhase}}) {
    if (contains(*b.names, n)) return {b.kind, std::string("name ").append(f.name)};
  }
  // Descriptive names with a qualifier (uncorrected_cross_correlation_ratio, corrected_velocity ...).
  struct ByPart {
    const char* part;
    FieldKind kind;
  };
  for (const ByPart& b : {ByPart{"specific_differential_phase", FieldKind::SpecificDifferentialPhase},
                          {"differential_phase", FieldKind::DifferentialPhase},
                          {"differential_reflectivity", FieldKind::DifferentialReflectivity},
                          {"cross_correlation_ratio", FieldKind::CorrelationCoefficient},
                          {"spectrum_width", FieldKind::SpectrumWidth},
                          {"velocity", FieldKind::Velocity}}) {
    if (n.find(b.part) != std::string::npos)
      return {b.kind, std::string("name ").append(f.name).append(" (holds \"").append(b.part).append("\")")};
  }
  if (isDbz(f.units)) return {FieldKind::Reflectivity, std::string("units ").append(f.units)};
  if (isMetresPerSecond(f.units)) {
    if (n.find("width") != std::string::npos || n.find("wrad") != std::string::npos)
      return {FieldKind::SpectrumWidth, std::string("units ").append(f.units).append(" and a name that says width")};
    return {FieldKind::Velocity, std::string("units ").append(f.units)};
  }
  if (toLowerAscii(f.units) == "deg/km" || toLowerAscii(f.units) == "degrees/km")
    return {FieldKind::SpecificDifferentialPhase, std::string("units ").append(f.units)};
  if (n.rfind("reflectivity", 0) == 0 || n.rfind("dbz", 0) == 0)
    return {FieldKind::Reflectivity, std::string("name ").append(f.name).append(" (starts like a reflectivity name)")};
  return {FieldKind::Other, "not recognised by standard_name, name or units"};
}

DefaultField chooseDefaultFieldWithReason(const std::vector<FieldInfo>& fields) {
  if (fields.empty()) return {};
  // Rank of a name in the reflectivity preference list (unknown names after all known ones).
  auto rank = [](const FieldInfo& f) {
    const auto it = std::find(kReflectivityNames.begin(), kReflectivityNames.end(), toLowerAscii(f.name));
    return static_cast<std::size_t>(it - kReflectivityNames.begin());
  };
  auto best = [&](auto&& accept, const char* why) -> DefaultField {
    const FieldInfo* pick = nullptr;
    for (const FieldInfo& f : fields)
      if (accept(f) && (!pick || rank(f) < rank(*pick))) pick = &f;
    if (!pick) return {};
    return {pick->name, std::string(why)};
  };
  if (DefaultField d =
          best([](const FieldInfo& f) { return toLowerAscii(f.standardName) == "equivalent_reflectivity_factor"; },
               "reflectivity by its CF standard_name equivalent_reflectivity_factor");
      !d.name.empty())
    return d;
  if (DefaultField d = best([](const FieldInfo& f) { return isDbz(f.units); }, "reflectivity by its units dBZ");
      !d.name.empty())
    return d;
  if (DefaultField d = best([](const FieldInfo& f) { return contains(kReflectivityNames, toLowerAscii(f.name)); },
                            "reflectivity by its name");
      !d.name.empty())
    return d;
  if (DefaultField d = best(
          [](const FieldInfo& f) {
            const std::string n = toLowerAscii(f.name);
            return n.rfind("reflectivity", 0) == 0 || n.rfind("dbz", 0) == 0;
          },
          "reflectivity by the start of its name");
      !d.name.empty())
    return d;
  return {fields.front().name, "no reflectivity field (by standard_name, units or name): the first field"};
}

TransferFunction defaultTransferFor(FieldKind kind, double nyquistMps, const ValueRange& range) {
  switch (kind) {
    case FieldKind::Reflectivity: return defaultReflectivityTransfer();
    case FieldKind::Velocity: return tableAlphaOnly(velocityTable(velocityScale(nyquistMps, range)), 0.5);
    case FieldKind::SpectrumWidth: return ramp(spectrumWidthTable(), 1.0, 10.0, 0.5);
    case FieldKind::DifferentialReflectivity: return tableAlphaOnly(zdrTable(), 0.3);
    case FieldKind::CorrelationCoefficient: return ramp(rhohvTable(), 0.5, 0.9, 0.3);
    case FieldKind::DifferentialPhase: return tableAlphaOnly(cividisTable(0.0, 360.0), 0.3);
    case FieldKind::SpecificDifferentialPhase: return ramp(kdpTable(), 0.0, 3.0, 0.5);
    case FieldKind::Other: break;
  }
  double lo = range.minValue, hi = range.maxValue;
  if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo)) {
    lo = std::isfinite(lo) ? lo : 0.0;
    hi = lo + 1.0;
  }
  return ramp(cividisTable(lo, hi), lo, hi, 0.5);
}

VariableAmount variableAmountOf(const FieldInfo& f) {
  const std::string sn = toLowerAscii(f.standardName), n = ownName(f.name), u = toLowerAscii(f.units);
  auto has = [](const std::string& s, const char* part) { return s.find(part) != std::string::npos; };
  for (const char* part : {"cloud_liquid_water", "cloud_ice", "rain", "snow", "graupel", "hail", "precipitation",
                           "cloud_area_fraction", "cloud_condensed_water"})
    if (has(sn, part)) return VariableAmount::ZeroBased;
  if (!sn.empty()) return VariableAmount::Smooth;  // a standard_name that names none of them
  static const std::vector<std::string> kNames{
      "qcloud", "qrain", "qice", "qsnow", "qgraup", "qhail", "cldfra",         // WRF
      "clwc",   "ciwc",  "crwc", "cswc",  "cc",     "tp",    "cp",     "lsp",  // ECMWF (GRIB short names)
      "qc",     "qi",    "qr",   "qs",    "qg",     "qh",    "clc"};           // ICON / COSMO
  if (std::find(kNames.begin(), kNames.end(), n) != kNames.end()) return VariableAmount::ZeroBased;
  if (u == "mm" || u == "kg m-2" || u == "kg m**-2" || u == "kg/m2" || u == "kg/m^2") return VariableAmount::ZeroBased;
  return VariableAmount::Smooth;
}

const char* toString(VariableAmount amount) {
  return amount == VariableAmount::ZeroBased ? "zero-based amount" : "smooth field";
}

TransferFunction defaultTransferForVariable(const FieldInfo& field, const ValueRange& range) {
  double lo = range.minValue, hi = range.maxValue;
  if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo)) {
    lo = std::isfinite(lo) ? lo : 0.0;
    hi = lo + 1.0;
  }
  if (variableAmountOf(field) == VariableAmount::ZeroBased && hi > 0.0) {
    lo = std::min(lo, 0.0);
    return ramp(cividisTable(lo, hi), 0.02 * hi, 0.25 * hi, 0.9);
  }
  return ramp(cividisTable(lo, hi), lo + 0.5 * (hi - lo), hi, 0.05);
}

namespace {

// A CF standard_name that is not a radar moment's makes the field a model variable whatever its
// name (W, V and T are radar names too: upward_air_velocity is not a spectrum width).
FieldKind colourKind(const FieldInfo& f) {
  if (!f.standardName.empty() && classifyField(FieldInfo{{}, {}, f.standardName}).kind == FieldKind::Other)
    return FieldKind::Other;
  return classifyField(f).kind;
}

}  // namespace

std::string defaultColorsFor(const FieldInfo& field) {
  const FieldKind kind = colourKind(field);
  if (kind == FieldKind::Reflectivity) return "NWS";
  if (kind != FieldKind::Other) return "auto";
  const std::string sn = toLowerAscii(field.standardName), n = ownName(field.name), u = toLowerAscii(field.units);
  auto has = [](const std::string& s, const char* part) { return s.find(part) != std::string::npos; };
  if (has(sn, "temperature") || n == "t" || n == "t2" || n == "tk" || u == "k" || u == "degc" || u == "celsius")
    return "turbo";
  if (has(sn, "humidity") || has(sn, "water_vapor") || n == "qvapor" || n == "rh" || n == "rhumidity") return "greens";
  if (has(sn, "cloud") || n == "qcloud" || n == "qice" || n == "qsnow") return "grayscale";
  return "viridis";
}

Result<TransferFunction> transferForField(const std::string& colors, const FieldInfo& field, double nyquistMps,
                                          const ValueRange& range) {
  const FieldKind kind = colourKind(field);
  std::string c = toLowerAscii(colors);
  if ((c.empty() || c == "auto") && kind == FieldKind::Other) c = toLowerAscii(defaultColorsFor(field));
  // Model variables (and radar fields of no known kind): the ramp by what they measure.
  auto kindDefault = [&] {
    return kind == FieldKind::Other ? defaultTransferForVariable(field, range)
                                    : defaultTransferFor(kind, nyquistMps, range);
  };
  if (c.empty() || c == "auto") return kindDefault();
  if (c == "nws") return defaultReflectivityTransfer();
  if (c == "velocity") return defaultTransferFor(FieldKind::Velocity, nyquistMps, range);
  TransferFunction t = kindDefault();
  using TableMaker = ColorTable (*)(double, double);
  struct Named {
    const char* name;
    TableMaker make;
  };
  for (const Named& m : {Named{"cividis", &cividisTable}, Named{"viridis", &viridisTable}, Named{"turbo", &turboTable},
                         Named{"grayscale", &grayscaleTable}, Named{"greens", &greensTable}}) {
    if (c != m.name) continue;
    // Over the kind's range (reflectivity -10..70 dBZ; Other: the field's values).
    const auto& stops = t.colors.stops();
    const double lo = kind == FieldKind::Reflectivity ? -10.0 : stops.front().value;
    const double hi = kind == FieldKind::Reflectivity ? 70.0 : stops.back().value;
    t.colors = m.make(lo, hi > lo ? hi : lo + 1.0);
    return t;
  }
  auto table = readPalFile(colors);
  if (!table) return table.forwardError();
  t.colors = std::move(*table);
  return t;
}

}  // namespace atmoglobe::volume
