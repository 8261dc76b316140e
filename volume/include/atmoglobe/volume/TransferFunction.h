#pragma once
// Transfer function for direct volume rendering of a radar field: value -> colour and opacity.
//
// GL-free; the GPU marcher (shaders/) and the CPU reference (ReferenceRenderer.h) apply the
// same rules:
//  - colour: the ColorTable's RGB of the value (8-bit / 255);
//  - opacity per `opacityReferenceMeters` of path: a linear ramp in the value, 0 at and below
//    opacityZeroValue, maxOpacity at and above opacityFullValue, times the table's alpha / 255;
//    or, where the user edited it (the viewer's transfer-function editor, OpacityEditor.h),
//    piecewise linear through opacity control points (still 0 at and below opacityZeroValue);
//  - a step of s metres takes alpha_s = 1 - (1 - alpha)^(s / opacityReferenceMeters), so the
//    optical depth of a path does not depend on the step (opacity correction).
// Only "echo" samples are classified; "no echo" and "no data" contribute nothing.
#include <atmoglobe/volume/ColorTable.h>

#include <glm/glm.hpp>

#include <vector>

namespace atmoglobe::volume {

struct TransferFunction {
  ColorTable colors;                       ///< RGB, and an alpha multiplier (table alpha / 255), from the value
  double opacityZeroValue = 10.0;          ///< value (field units) at and below which opacity is 0
  double opacityFullValue = 60.0;          ///< value at and above which opacity is maxOpacity
  double maxOpacity = 0.8;                 ///< opacity accumulated over opacityReferenceMeters, in [0, 1]
  double opacityReferenceMeters = 1000.0;  ///< (m), > 0
  /// Opacity control points (value in field units, opacity per reference length in [0, 1]),
  /// values strictly increasing. Empty: the ramp above. Non-empty (at least two): the opacity is
  /// linear between neighbouring points, the end points' opacity beyond them, and 0 at and below
  /// opacityZeroValue (which withOpacityPoints sets to where the curve starts being 0-free, so
  /// that the GPU's "echo above opacityZeroValue" test and the CPU agree); maxOpacity and
  /// opacityFullValue are then only descriptive.
  std::vector<glm::dvec2> opacityPoints;

  /// Straight (not premultiplied) RGBA in [0, 1] of an echo value (field units): rgb =
  /// colors.map(value) / 255 (the value narrowed to float, as the table takes it), a =
  /// ramp(value) * colours alpha / 255, ramp linear from 0 at opacityZeroValue to maxOpacity
  /// at opacityFullValue, clamped outside (or the control points' curve: opacityPoints).
  /// Non-finite value: (0, 0, 0, 0). Exact.
  glm::dvec4 classify(double value) const;

  /// Opacity of a step of `stepMeters` (m) for an opacity `alpha` per reference length:
  /// 1 - (1 - alpha)^(stepMeters / opacityReferenceMeters); alpha clamped to [0, 1]. Exact.
  double correctedOpacity(double alpha, double stepMeters) const;

  /// Extinction coefficient (1/m) of an opacity `alpha` per reference length:
  /// -ln(1 - alpha) / opacityReferenceMeters, so that a path of s metres has opacity
  /// 1 - exp(-extinction * s) = correctedOpacity(alpha, s). alpha is clamped to [0, 1 - 1e-6]
  /// (an opaque entry becomes optical depth 13.8 per reference length).
  double extinctionPerMeter(double alpha) const;
};

/// Cumulative integrals over the value, for pre-integrated classification of linear segments
/// (the GPU marcher's `--classification preintegrated`). The range [lo, hi] is cut into `bins`
/// equal bins classified at their centre values (as the engine's point table is); entry k,
/// k = 0..bins, holds over [lo, lo + k (hi - lo) / bins]
///   rgb: integral of extinction(v) * colour(v) dv,   a: integral of extinction(v) dv
/// (extinction in 1/m, v in field units). A path of length d along which the value goes
/// linearly from v0 to v1 then has the optical depth tau = d (A(v1) - A(v0)) / (v1 - v0)
/// exactly for this piecewise-constant classification, A being the table interpolated
/// linearly; its colour is approximated by the extinction-weighted mean colour times the
/// opacity 1 - exp(-tau) (exact when the colour is constant along the path; the error of the
/// approximation is measured against the CPU reference in docs/bench-volume.md).
/// Requires bins >= 1 and hi > lo.
std::vector<glm::dvec4> transferIntegralTable(const TransferFunction& tf, double lo, double hi, int bins);

/// `tf` stretched so that its colour table spans [lo, hi] (field units) instead of its first to
/// last stop: the table is remapped linearly through its scale/offset (ColorTable's table-unit
/// convention), and the opacity ramp's two values move with it. Precondition: lo < hi, a table
/// with at least two stops (otherwise `tf` is returned unchanged).
TransferFunction withValueRange(const TransferFunction& tf, double lo, double hi);

/// `tf` with a user's opacity ramp: zero and full values (field units), and where given the
/// maximum opacity (0..1) and its reference length (m).
TransferFunction withOpacityRamp(const TransferFunction& tf, const std::vector<double>& zeroFullMaxPerMeters);

/// `tf` with opacity control points (see TransferFunction::opacityPoints; sorted by value here,
/// opacities clamped to [0, 1]); opacityZeroValue becomes the value below which the curve is 0
/// (the last of its leading zero-opacity points; -1e30 when the first point is not 0),
/// opacityFullValue the first point of the largest opacity, maxOpacity that opacity. Fewer than
/// two points: the points are cleared (the ramp applies).
TransferFunction withOpacityPoints(const TransferFunction& tf, std::vector<glm::dvec2> points);

/// The opacity curve of `tf` as control points: its opacityPoints, else the ramp's two corners
/// (opacityZeroValue, 0) and (opacityFullValue, maxOpacity). What the editor starts from.
std::vector<glm::dvec2> opacityCurveOf(const TransferFunction& tf);

/// NWS reflectivity colours (nwsReflectivityTable), opacity ramp 10 dBZ -> 60 dBZ, 0.8 per km.
TransferFunction defaultReflectivityTransfer();

}  // namespace atmoglobe::volume
