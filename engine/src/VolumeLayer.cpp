// One description of a volume layer (VolumeLayer.h): names, defaults, validation, changes.
#include <atmoglobe/engine/VolumeLayer.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace atmoglobe::engine {

const char* nameOf(VolumeKind kind) { return kind == VolumeKind::Radar ? "radar" : "grid"; }

const char* nameOf(volume::VolumeRenderMode mode) {
  switch (mode) {
    case volume::VolumeRenderMode::Dvr: return "dvr";
    case volume::VolumeRenderMode::Mip: return "mip";
    case volume::VolumeRenderMode::Iso: return "iso";
  }
  return "?";
}

const char* nameOf(volume::Interpolation interpolation) {
  return interpolation == volume::Interpolation::Nearest ? "nearest" : "linear";
}

const char* nameOf(FarField farField) { return farField == FarField::Auto ? "auto" : "off"; }

const char* nameOf(Classification classification) {
  return classification == Classification::Preintegrated ? "preintegrated" : "point";
}

const char* nameOf(BeamApproximation beam) { return beam == BeamApproximation::StraightLine ? "straight" : "4/3"; }

template <>
const std::vector<VolumeKind>& allValues<VolumeKind>() {
  static const std::vector<VolumeKind> values{VolumeKind::Radar, VolumeKind::Grid};
  return values;
}
template <>
const std::vector<volume::VolumeRenderMode>& allValues<volume::VolumeRenderMode>() {
  static const std::vector<volume::VolumeRenderMode> values{
      volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso};
  return values;
}
template <>
const std::vector<volume::Interpolation>& allValues<volume::Interpolation>() {
  static const std::vector<volume::Interpolation> values{volume::Interpolation::Nearest, volume::Interpolation::Linear};
  return values;
}
template <>
const std::vector<FarField>& allValues<FarField>() {
  static const std::vector<FarField> values{FarField::Off, FarField::Auto};
  return values;
}

template <>
const std::vector<Classification>& allValues<Classification>() {
  static const std::vector<Classification> values{Classification::Point, Classification::Preintegrated};
  return values;
}
template <>
const std::vector<BeamApproximation>& allValues<BeamApproximation>() {
  static const std::vector<BeamApproximation> values{BeamApproximation::EffectiveEarthLocalSphere,
                                                     BeamApproximation::StraightLine};
  return values;
}

double defaultIsoValue(VolumeKind kind, double minValue, double maxValue) {
  return kind == VolumeKind::Radar ? 40.0 : 0.5 * (minValue + maxValue);
}

Status validateVolumeLayerSettings(const VolumeLayerSettings& s, const std::string& where) {
  if (s.valueRange &&
      !(std::isfinite(s.valueRange->x) && std::isfinite(s.valueRange->y) && s.valueRange->x < s.valueRange->y))
    return makeError(where + ": range must be finite with min < max");
  if (!s.opacity.empty()) {
    const auto& o = s.opacity;
    if (o.size() < 2 || o.size() > 4 || !std::all_of(o.begin(), o.end(), [](double x) { return std::isfinite(x); }))
      return makeError(where + ": opacity must be 2 to 4 finite numbers: zero, full[, max[, per_m]]");
    if (!(o[0] < o[1])) return makeError(where + ": opacity zero value must be below the full value");
    if (o.size() > 2 && !(o[2] >= 0.0 && o[2] <= 1.0)) return makeError(where + ": opacity max must be in 0..1");
    if (o.size() > 3 && !(o[3] > 0.0)) return makeError(where + ": opacity per_m must be > 0");
  }
  return volume::validateCropBox(s.crop, where);
}

double samplesPerCellOf(const VolumeLayerDescription& d) {
  return d.samplesPerCell.value_or(d.kind == VolumeKind::Grid ? kDefaultGridSamplesPerCell : 0.0);
}

Status validateVolumeLayer(const VolumeLayerDescription& d, const std::string& where) {
  if (d.path.empty()) return makeError(where + ": empty path");
  if (!(d.stepMeters >= 1.0 && d.stepMeters <= 1e6)) return makeError(where + ": step must be in 1..1000000 m");
  if (!(d.imageScale >= 0.05 && d.imageScale <= 1.0)) return makeError(where + ": image scale must be in 0.05..1");
  if (!(d.refineThreshold == -1.0 || (d.refineThreshold >= 0.0 && d.refineThreshold <= 255.0)))
    return makeError(where + ": refine threshold must be in 0..255 (8-bit steps), or -1 for off");
  if (d.samplesPerCell && !(*d.samplesPerCell >= 0.0 && *d.samplesPerCell <= 64.0))
    return makeError(where + ": samples per cell must be in 0..64 (0: the fixed step)");
  if (d.isoValue && !std::isfinite(*d.isoValue)) return makeError(where + ": iso value must be finite");
  if (d.kind == VolumeKind::Radar && !d.time.empty())
    return makeError(where + ": a radar has no time to choose (a loop's steps are its files)");
  if (d.kind == VolumeKind::Grid && !d.label.empty()) return makeError(where + ": a grid has no site label");
  if (d.kind == VolumeKind::Grid && d.overlap) return makeError(where + ": an overlap rule is for radar networks");
  if (!(d.windowMinutes > 0.0 && d.windowMinutes <= 1440.0))
    return makeError(where + ": window_minutes must be in (0, 1440]");
  return validateVolumeLayerSettings(d.settings, where);
}

namespace {
bool sameCrop(const volume::CropBox& a, const volume::CropBox& b) {
  return std::tie(a.southDeg, a.northDeg, a.westDeg, a.eastDeg, a.bottomMeters, a.topMeters) ==
         std::tie(b.southDeg, b.northDeg, b.westDeg, b.eastDeg, b.bottomMeters, b.topMeters);
}
bool sameLook(const VolumeLayerSettings& a, const VolumeLayerSettings& b) {
  return a.valueRange == b.valueRange && a.opacity == b.opacity && a.opacityPoints == b.opacityPoints;
}
}  // namespace

LayerChange layerChange(const VolumeLayerDescription& a, const VolumeLayerDescription& b) {
  if (a.kind != b.kind || a.path != b.path || a.field != b.field || a.time != b.time || a.useGeoid != b.useGeoid ||
      !sameCrop(a.settings.crop, b.settings.crop) || a.overlap != b.overlap || a.windowMinutes != b.windowMinutes ||
      a.member != b.member || a.gridIndex != b.gridIndex ||
      (a.ensemble ? volume::toString(*a.ensemble) : "") != (b.ensemble ? volume::toString(*b.ensemble) : ""))
    return LayerChange::Reload;
  if (a.colors != b.colors || a.mode != b.mode || a.interpolation != b.interpolation || a.stepMeters != b.stepMeters ||
      a.samplesPerCell != b.samplesPerCell || a.imageScale != b.imageScale || a.refineThreshold != b.refineThreshold ||
      a.isoValue != b.isoValue || a.beam != b.beam || a.classification != b.classification || a.label != b.label ||
      a.levelOfDetail != b.levelOfDetail || a.nearWindow != b.nearWindow || a.farField != b.farField ||
      !sameLook(a.settings, b.settings))
    return LayerChange::Options;
  return LayerChange::None;
}

}  // namespace atmoglobe::engine
