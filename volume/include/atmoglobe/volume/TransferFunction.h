#pragma once
// Transfer function for direct volume rendering of a radar field: value -> colour and opacity.
//
// GL-free; the GPU marcher (shaders/) and the CPU reference (ReferenceRenderer.h) apply the
// same rules:
//  - colour: the ColorTable's RGB of the value (8-bit / 255);
//  - opacity per `opacityReferenceMeters` of path: a linear ramp in the value, 0 at and below
//    opacityZeroValue, maxOpacity at and above opacityFullValue, times the table's alpha / 255;
//  - a step of s metres takes alpha_s = 1 - (1 - alpha)^(s / opacityReferenceMeters), so the
//    optical depth of a path does not depend on the step (opacity correction).
// Only "echo" samples are classified; "no echo" and "no data" contribute nothing.
#include <atmoglobe/volume/ColorTable.h>

#include <glm/glm.hpp>

namespace atmoglobe::volume {

struct TransferFunction {
  ColorTable colors;               ///< RGB, and an alpha multiplier (table alpha / 255), from the value
  double opacityZeroValue = 10.0;  ///< value (field units) at and below which opacity is 0
  double opacityFullValue = 60.0;  ///< value at and above which opacity is maxOpacity
  double maxOpacity = 0.8;         ///< opacity accumulated over opacityReferenceMeters, in [0, 1]
  double opacityReferenceMeters = 1000.0;  ///< (m), > 0

  /// Straight (not premultiplied) RGBA in [0, 1] of an echo value (field units): rgb =
  /// colors.map(value) / 255 (the value narrowed to float, as the table takes it), a =
  /// ramp(value) * colours alpha / 255, ramp linear from 0 at opacityZeroValue to maxOpacity
  /// at opacityFullValue, clamped outside. Non-finite value: (0, 0, 0, 0). Exact.
  glm::dvec4 classify(double value) const;

  /// Opacity of a step of `stepMeters` (m) for an opacity `alpha` per reference length:
  /// 1 - (1 - alpha)^(stepMeters / opacityReferenceMeters); alpha clamped to [0, 1]. Exact.
  double correctedOpacity(double alpha, double stepMeters) const;
};

/// NWS reflectivity colours (nwsReflectivityTable), opacity ramp 10 dBZ -> 60 dBZ, 0.8 per km.
TransferFunction defaultReflectivityTransfer();

}  // namespace atmoglobe::volume
