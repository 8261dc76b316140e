// Between two time steps of a forecast grid (GridVolume.h).
#include <atmoglobe/volume/CfTime.h>
#include <atmoglobe/volume/GridVolume.h>

#include <cmath>
#include <limits>

namespace atmoglobe::volume {

std::string interpolateIsoTime(const std::string& fromIso, const std::string& toIso, double fraction) {
  auto from = parseCfTimeUnits("seconds since " + fromIso, "proleptic_gregorian");
  auto to = parseCfTimeUnits("seconds since " + toIso, "proleptic_gregorian");
  if (!from || !to) return {};
  const double span = static_cast<double>(to->referenceSeconds - from->referenceSeconds) +
                      (to->referenceFractionSeconds - from->referenceFractionSeconds);
  return cfTimeToIso8601(*from, fraction * span);
}

Result<GridVolume> interpolateGridSteps(const GridVolume& a, const GridVolume& b, double fraction) {
  if (!(fraction >= 0.0 && fraction <= 1.0))
    return makeError(a.path + ": time fraction " + std::to_string(fraction) + " is outside [0, 1]");
  if (a.variable != b.variable || a.nx != b.nx || a.ny != b.ny || a.nz != b.nz || a.curvilinear != b.curvilinear ||
      a.lonDeg != b.lonDeg || a.latDeg != b.latDeg || a.rowLengthPoints != b.rowLengthPoints ||
      a.rowFirstLonDeg != b.rowFirstLonDeg || a.rowSpacingDeg != b.rowSpacingDeg ||
      a.values.size() != b.values.size() || a.heightAboveEllipsoidMeters.size() != b.heightAboveEllipsoidMeters.size())
    return makeError(a.path + ": the two time steps to interpolate differ in variable, region or shape");
  GridVolume out = a;
  out.valueMin = std::numeric_limits<float>::quiet_NaN();
  out.valueMax = std::numeric_limits<float>::quiet_NaN();
  const double wa = 1.0 - fraction;
  for (std::size_t n = 0; n < out.values.size(); ++n) {
    const double v = wa * static_cast<double>(a.values[n]) + fraction * static_cast<double>(b.values[n]);
    out.values[n] = static_cast<float>(v);  // NaN in either stays NaN
    if (std::isfinite(out.values[n])) {
      if (!(out.valueMin <= out.values[n])) out.valueMin = out.values[n];
      if (!(out.valueMax >= out.values[n])) out.valueMax = out.values[n];
    }
    out.heightAboveEllipsoidMeters[n] =
        static_cast<float>(wa * static_cast<double>(a.heightAboveEllipsoidMeters[n]) +
                           fraction * static_cast<double>(b.heightAboveEllipsoidMeters[n]));
  }
  if (a.pressurePa.size() == a.values.size() && b.pressurePa.size() == a.values.size()) {
    for (std::size_t n = 0; n < out.pressurePa.size(); ++n)
      out.pressurePa[n] = static_cast<float>(wa * static_cast<double>(a.pressurePa[n]) +
                                             fraction * static_cast<double>(b.pressurePa[n]));
  } else {
    out.pressurePa.clear();
  }
  out.bytesRead = a.bytesRead + b.bytesRead;
  if (!a.validTime.empty() && !b.validTime.empty())
    out.validTime = interpolateIsoTime(a.validTime, b.validTime, fraction);
  return out;
}

}  // namespace atmoglobe::volume
