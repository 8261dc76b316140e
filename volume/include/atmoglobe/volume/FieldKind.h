#pragma once
// What a radar field is, by meaning rather than by one spelling, and how it is drawn by default.
//
// Kind of a field, in this order of evidence:
//  1. its CF standard_name (CfRadial): equivalent_reflectivity_factor,
//     radial_velocity_of_scatterers_away_from_instrument, doppler_spectrum_width,
//     log_differential_reflectivity_hv, cross_correlation_ratio_hv, differential_phase_hv,
//     specific_differential_phase_hv (CF standard name table; CfRadial 1.4 section 6);
//  2. its name, in any case, among the names the common writers use (ODIM_H5 quantities DBZH,
//     TH, VRADH, WRADH, ZDR, RHOHV, PHIDP, KDP; NEXRAD moments REF, VEL, SW, ZDR, RHO, PHI;
//     CfRadial/Py-ART names reflectivity, velocity, spectrum_width, ...);
//  3. its units (dBZ; m/s with a name that says width -> spectrum width; deg/km -> KDP).
//
// Default field of a file (ReadOptions::fieldName empty): the reflectivity field chosen by
// standard_name, else by units dBZ, else by a known reflectivity name in any case, else a name
// starting with "reflectivity" or "dbz"; several candidates of one kind of evidence: the one
// earliest in kReflectivityNames (DBZH before TH, the uncorrected total power), else the first in
// the file. No reflectivity at all: the first field. The reason is given for `info`.
//
// Default colours and opacity by kind (defaultTransferFor): reflectivity the NWS table; velocity a
// diverging green (towards the radar) / red (away) table centred on zero over +-Nyquist (when the
// file gives none: the largest |value| of the field, else 30 m/s), more opaque the faster;
// spectrum width 0..16 m/s; ZDR -2..8 dB; RhoHV 0.2..1.05 with most of the colours above 0.9;
// PhiDP 0..360 deg; KDP -2..8 deg/km; other fields (model variables) by meaning, over their value
// range (defaultColorsFor: turbo for temperature, greens for humidity, grayscale for cloud,
// viridis otherwise). A table the user names still wins.
#include <atmoglobe/volume/RadarVolume.h>
#include <atmoglobe/volume/TransferFunction.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <string>
#include <vector>

namespace atmoglobe::volume {

enum class FieldKind {
  Reflectivity,
  Velocity,
  SpectrumWidth,
  DifferentialReflectivity,
  CorrelationCoefficient,
  DifferentialPhase,
  SpecificDifferentialPhase,
  Other,
};
const char* toString(FieldKind kind);

/// The kind of a field and the evidence ("CF standard_name equivalent_reflectivity_factor",
/// "name VRADH", "units dBZ").
struct FieldKindEvidence {
  FieldKind kind = FieldKind::Other;
  std::string reason;
};
FieldKindEvidence classifyField(const FieldInfo& field);

/// The default field (see the file comment) and why; name empty if there are no fields.
struct DefaultField {
  std::string name;
  std::string reason;
};
DefaultField chooseDefaultFieldWithReason(const std::vector<FieldInfo>& fields);

/// The transfer function for a field of `kind` (colours and opacity, file comment).
/// `nyquistMps`: the velocity scale (NaN or <= 0: the largest |value| in `range`, else 30 m/s);
/// `range`: the field's values (velocity without Nyquist, Other).
TransferFunction defaultTransferFor(FieldKind kind, double nyquistMps, const ValueRange& range);

/// How a model variable (a field of kind Other) is drawn by default, by what it measures:
///  - ZeroBased: an amount that is zero where there is none and matters where there is some:
///    hydrometeor mixing ratios and mass fractions (cloud water and ice, rain, snow, graupel, hail:
///    CF standard_names with "cloud_liquid_water", "cloud_ice", "rain", "snow", "graupel", "hail";
///    WRF QCLOUD, QRAIN, QICE, QSNOW, QGRAUP, QHAIL; ECMWF clwc, ciwc, crwc, cswc; ICON qc, qi, qr,
///    qs, qg), cloud cover (cloud_area_fraction, cc, clc, CLDFRA) and precipitation (standard_names
///    with "precipitation"; tp, cp, lsp; units mm, kg m-2). Colours over 0 .. the largest value;
///    transparent up to 2 % of it, opacity rising to 0.5 per km at half of it: no slab where the
///    model has none, the cores opaque.
///  - Smooth: anything else (temperature, geopotential, wind, pressure, humidity): a field with a
///    value everywhere. Colours over its range; transparent up to the middle of the range, rising to
///    0.05 per km at its top: the upper half shows as a haze through which the globe and its
///    coastlines stay visible (a vertical 30 km column at the top value: 1 - 0.95^30 = 79 %, at
///    three quarters of the range 54 %).
enum class VariableAmount { ZeroBased, Smooth };
VariableAmount variableAmountOf(const FieldInfo& field);
const char* toString(VariableAmount amount);
/// The default transfer function of a model variable (above) over its values `range`.
TransferFunction defaultTransferForVariable(const FieldInfo& field, const ValueRange& range);

/// The default colour table of a field for "auto": by kind (above); for other fields (model
/// variables) by standard_name, name or units: temperature -> "turbo", humidity -> "greens",
/// cloud water and ice -> "grayscale", anything else -> "viridis".
std::string defaultColorsFor(const FieldInfo& field);

/// The transfer function a user's colour choice gives for a field: "auto" (defaultColorsFor),
/// "NWS" (the reflectivity table and ramp), "cividis", "viridis", "turbo", "grayscale", "greens"
/// (over -10..70 for reflectivity, else the kind's range or the field's values), "velocity" (the
/// diverging table over +-Nyquist), or a GR/WCT .pal file (with the kind's opacity ramp). Errors:
/// the .pal file's.
Result<TransferFunction> transferForField(const std::string& colors, const FieldInfo& field, double nyquistMps,
                                          const ValueRange& range);

}  // namespace atmoglobe::volume
