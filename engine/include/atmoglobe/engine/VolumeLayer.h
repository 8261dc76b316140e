#pragma once
// One description of a volume layer, whatever its kind (a radar volume or a forecast grid):
// source, field, colours, range, opacity, crop, mode, quality knobs, label and time. The
// scene JSON ("radars"/"grids"), the CLI (--radar/--grid), the viewer's panel and the scene
// renderer all hold this one type; the parts only one kind reads are marked so. GL-free.
//
// Enumerated settings are enums; `nameOf` / `parseName` give the spellings the scene JSON, the
// CLI and the panel use ("dvr", "4/3", ...), from one table per enum.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/Crop.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/RadarNetwork.h>
#include <atmoglobe/volume/VolumeRenderSettings.h>

#include <glm/glm.hpp>

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::engine {

/// What a volume layer reads and how its samples are placed.
enum class VolumeKind {
  Radar,  ///< sweeps of gates (volume/RadarReader.h), sampled in antenna coordinates
  Grid,   ///< a forecast grid (volume/GridReader.h), sampled in its own columns and levels
};

/// How DVR classifies the field between samples.
enum class Classification {
  Point,          ///< each sample alone, over one step (post-classification; what the reference does at 100 m)
  Preintegrated,  ///< neighbouring samples as a linear segment, integrated exactly in opacity
                  ///< (volume::transferIntegralTable)
};

/// Whether a volume seen from far away is drawn from its far field (engine/FarFieldGL.h): its
/// emission and absorption integrated down the vertical in horizontal slabs once, then laid along
/// each pixel's ray, instead of a march per pixel. Radar networks only.
enum class FarField {
  Off,   ///< always marched
  Auto,  ///< the far field where every pixel over the volume spans FarFieldGL::kMinFootprintMeters or more
};

/// How the GPU maps a point to a radar's antenna coordinates (radars only).
enum class BeamApproximation {
  /// The effective-Earth model (ke, R from the volume's BeamModel) on a local sphere whose
  /// radius is the ellipsoid's normal-section radius in the sample's azimuth, in float32:
  /// volume::LocalSphereBeam, whose double twin's error against the exact inverse is stated in
  /// volume/Geolocation.h; the float error is measured by RadarMarchTest.
  EffectiveEarthLocalSphere,
  /// Straight lines from the antenna, no Earth curvature, no refraction (what several open
  /// 3-D radar viewers do); for comparison only.
  StraightLine,
};

/// The spelling of each value in the scene JSON, the CLI and the panel: "radar"/"grid";
/// "dvr"/"mip"/"iso"; "nearest"/"linear"; "point"/"preintegrated"; "4/3"/"straight".
const char* nameOf(VolumeKind kind);
const char* nameOf(volume::VolumeRenderMode mode);
const char* nameOf(volume::Interpolation interpolation);
const char* nameOf(Classification classification);
const char* nameOf(BeamApproximation beam);
const char* nameOf(FarField farField);

/// Every value of an enum, in its table's order (the choices offered and listed in messages).
template <class E>
const std::vector<E>& allValues();

template <>
const std::vector<VolumeKind>& allValues<VolumeKind>();
template <>
const std::vector<volume::VolumeRenderMode>& allValues<volume::VolumeRenderMode>();
template <>
const std::vector<volume::Interpolation>& allValues<volume::Interpolation>();
template <>
const std::vector<Classification>& allValues<Classification>();
template <>
const std::vector<BeamApproximation>& allValues<BeamApproximation>();
template <>
const std::vector<FarField>& allValues<FarField>();

/// The value spelled `name` (exactly, as nameOf writes it), or nullopt.
template <class E>
std::optional<E> parseName(std::string_view name) {
  for (E value : allValues<E>())
    if (name == nameOf(value)) return value;
  return std::nullopt;
}

/// `"a", "b", "c"`: the choices of an enum for messages.
template <class E>
std::string quotedNames() {
  std::string out;
  for (E value : allValues<E>()) out += (out.empty() ? "\"" : ", \"") + std::string(nameOf(value)) + "\"";
  return out;
}

/// What users set on the look and extent of any volume layer (JSON keys "range", "opacity",
/// "crop", "crop_heights_m"; CLI --range/--opacity/--crop/--crop-heights and their --grid- twins).
struct VolumeLayerSettings {
  /// The colour table's span (min, max; field units). Empty: the kind's default (reflectivity
  /// -10..70 dBZ, velocity +-Nyquist, model variables their values' range).
  std::optional<glm::dvec2> valueRange;
  /// Opacity ramp: [zero, full] values (field units): opacity 0 at and below zero, the maximum
  /// at and above full; optionally [.., max] (0..1, per reference length) and [.., .., .., per_m]
  /// (the reference length, m). Empty: the kind's default ramp.
  std::vector<double> opacity;
  /// Opacity control points (value, opacity per reference length) from the viewer's
  /// transfer-function editor (volume::withOpacityPoints; applied after range and ramp). Empty:
  /// none. Not a scene key.
  std::vector<glm::dvec2> opacityPoints;
  /// Crop box: latitude/longitude and heights above sea level; outside it nothing is drawn
  /// (grids read only its columns). Default: everything.
  volume::CropBox crop;
};

/// A volume to ray-march (VolumeRendererGL.h; readers: volume/RadarLoad.h, volume/GridReader.h).
struct VolumeLayerDescription {
  VolumeKind kind = VolumeKind::Radar;
  /// Radar: a file, or one volume split over files or a loop (a directory, glob or comma list),
  /// or a network: a set holding several sites (and times), drawn as one volume
  /// (RadarNetworkSourceGL.h).
  /// Grid: a CF or WRF netCDF file or a GRIB (1 or 2) file.
  std::string path;
  /// The radar field or grid variable; empty: the file's default (reflectivity for radars).
  std::string field;
  /// Grids: the step first shown: empty (the first), an index ("3") or an ISO 8601 UTC time.
  /// Radars: unused (a loop's steps are its files).
  std::string time;
  /// Grids: the ensemble member (GRIB `number`, as `atmoglobe info` lists them); -1: the first.
  int member = -1;
  /// Grids: a statistic over every ensemble member instead of one (volume::EnsembleStatistic;
  /// scene "ensemble", CLI --ensemble: mean, spread, min, max, prob:>=VALUE).
  std::optional<volume::EnsembleStatistic> ensemble;
  /// Grids: the index read along each dimension that is neither horizontal, vertical nor time
  /// (netCDF; volume::GridReadOptions::extraIndex); unnamed dimensions: 0.
  std::map<std::string, std::size_t> gridIndex;
  /// "auto" (by the field's kind), a colour table by name (case ignored) or a .pal file.
  std::string colors = "auto";
  volume::VolumeRenderMode mode = volume::VolumeRenderMode::Dvr;
  volume::Interpolation interpolation = volume::Interpolation::Linear;
  /// Ray-march step (m). Layers of one step are integrated together where they overlap.
  double stepMeters = 250.0;
  /// Grids: > 0 the step follows the cells, about this many samples per cell crossed, never
  /// shorter than stepMeters (volume/StepRule.h); 0: the fixed step. Unset: the kind's default
  /// (samplesPerCellOf).
  std::optional<double> samplesPerCell;
  double imageScale = 1.0;  ///< volume image resolution relative to the frame (0.05..1)
  /// With imageScale < 1: pixels whose neighbourhood in the small image varies by more than this
  /// many 8-bit steps are marched at full resolution (VolumeRenderOptions::refineThreshold);
  /// < 0: off. Scene "refine_threshold", CLI --refine-threshold.
  double refineThreshold = -1.0;
  /// Grids: march a coarser copy where a pixel spans several grid columns (volume/GridDetail.h;
  /// scene "level_of_detail", CLI --grid-lod on|off). Off: always the grid itself.
  bool levelOfDetail = true;
  /// Grids drawn from a window of the columns in view at a resolution coarser than the grid (too
  /// large for the GPU): the columns nearest the eye drawn at full resolution with it (engine::
  /// GridSourceGL; scene "near_window", CLI --grid-near-window on|off). Off: one resolution throughout.
  bool nearWindow = true;
  /// The isosurface value (field units). Empty: the kind's default (defaultIsoValue).
  std::optional<double> isoValue;
  Classification classification = Classification::Point;  ///< DVR only
  /// Radar networks seen from far away: drawn from their far field (engine/FarFieldGL.h; scene
  /// "far_field", CLI --far-field auto|off). Off: always marched. Empty: the command's default
  /// (auto in the viewer, which makes the slabs over frames: setUnsetFarField; off elsewhere, as
  /// in `render`, whose one frame would pay for making them).
  std::optional<FarField> farField;
  BeamApproximation beam = BeamApproximation::EffectiveEarthLocalSphere;  ///< radars only
  std::string label;  ///< radars: the site marker's label; empty: the site name from the file
  /// Radar networks: how overlapping radars make one value (volume/RadarNetwork.h; not Integrate).
  /// Unset: WeightedMean.
  std::optional<volume::OverlapRule> overlap;
  /// Radar networks: at each time, every site's latest volume at most this many minutes old.
  double windowMinutes = 10.0;
  bool useGeoid = true;  ///< heights above sea level to the ellipsoid through EGM96
  VolumeLayerSettings settings;
};

/// The step rule's samples per cell a grid takes unless its description sets one: 2 (errors
/// against a fine fixed-step reference in docs/grids.md, "The step rule").
inline constexpr double kDefaultGridSamplesPerCell = 2.0;
/// The description's samplesPerCell, else its kind's default (grids kDefaultGridSamplesPerCell,
/// radars 0: no rule for their cells yet).
double samplesPerCellOf(const VolumeLayerDescription& d);

/// The isosurface value a layer without one gets: radars 40 (dBZ), grids the middle of the
/// values' range.
double defaultIsoValue(VolumeKind kind, double minValue, double maxValue);

/// Checks the settings (range min < max, opacity 2..4 finite numbers with zero != full, max in
/// [0, 1], per_m > 0, the crop box). `where` starts the message.
Status validateVolumeLayerSettings(const VolumeLayerSettings& settings, const std::string& where);

/// The one check of a volume layer, both kinds: step 1..1e6 m, image scale 0.05..1, a finite iso
/// value, kind-only keys left empty on the other kind, then the settings.
Status validateVolumeLayer(const VolumeLayerDescription& layer, const std::string& where);

/// What changed between two descriptions of one layer, and so what applying it needs.
enum class LayerChange {
  None,     ///< nothing that shows changed
  Options,  ///< render options only (transfer function, mode, iso value, step, scale, beam...)
  Reload,   ///< the data: the file is read again (field / variable, time, datum, crop box)
};
LayerChange layerChange(const VolumeLayerDescription& before, const VolumeLayerDescription& after);

}  // namespace atmoglobe::engine
