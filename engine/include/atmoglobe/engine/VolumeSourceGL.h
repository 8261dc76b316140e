#pragma once
// A volume layer as the scene renderer holds it, whatever its kind: one interface above the GPU
// volumes (VolumeGL) that radars and grids implement (RadarSourceGL.h, GridSourceGL.h), so the
// renderer, the control panel, the cursor readout, the scene's time axis, the background loader
// and the CLI hold one list of layers and never ask which kind a layer is.
//
// A source owns what its kind needs to read, step, reload and describe its data; the renderer owns
// the memory budget (volume::StepCache) and the scene's vertical exaggeration, and hands both in
// through a SourceContext. Every step a source shows goes through the cache under the keys of
// stepKey(), so steps not shown are dropped beyond the budget and read again when needed
// (docs/memory.md).
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/engine/VolumeLayer.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/map/GeoLines.h>
#include <atmoglobe/volume/RadarVolume.h>
#include <atmoglobe/volume/StepCache.h>
#include <atmoglobe/volume/ValueHistogram.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {
class GeoidGrid;
}

namespace atmoglobe::engine {

/// What the renderer lends a source for a load, a step or a reload.
struct SourceContext {
  volume::StepCache& cache;  ///< the memory budget of every layer's steps
  double exaggeration;       ///< the scene's vertical exaggeration (1 = none)
  std::size_t layer;         ///< the source's index in the renderer's list (its cache keys)
};

/// The cache key of a layer's step: "layer:3:17:gpu" (`gpu`: the uploaded volume with its CPU
/// twin; else the CPU data prepared ahead); `fraction` > 0: an interpolated frame "layer:3:17+0.25:gpu".
std::string stepKey(std::size_t layer, std::size_t step, bool gpu, double fraction = 0.0);
/// The start every key of one layer shares (StepCache::erasePrefix drops them all).
std::string stepKeyPrefix(std::size_t layer);

/// How a layer's times meet the scene's time axis (SceneTime.h).
enum class TimeMatching {
  SameValidTime,    ///< the step whose valid time is the axis time (to the second), else stays (model steps)
  LatestAtOrBefore  ///< the latest step at or before the axis time (what a forecaster sees live: radar loops)
};

/// One layer's part of a frame's legend (SceneRendererGL::legendFor).
struct LegendPart {
  std::string title;     ///< "KTLX  DBZH", "QRAIN (forecast grid)"
  std::string subtitle;  ///< "KTLX volume start 2013-05-20 20:00 UTC"
  LegendKey key;
  bool synthetic = false;  ///< the file says SYNTHETIC
};

/// What ScenePrefetcher lends a preparer: the cache it loads into and the layer's index (its keys).
struct PrepareContext {
  volume::StepCache& cache;
  std::size_t layer;
};

/// Prepares a source's steps on a worker thread, CPU side only (no GL, no access to the source:
/// it holds copies of what it needs), for ScenePrefetcher.
class StepPreparer {
 public:
  virtual ~StepPreparer() = default;
  struct Prepared {
    /// What the source's showStep finds under stepKey(.., false); null when the preparer put what
    /// it read under keys of its own (a network's volumes, shared between its steps).
    std::shared_ptr<const void> data;
    std::uint64_t bytes = 0;  ///< of data, else of what was put: the estimate of the next step
  };
  /// Step `step` read and made ready for upload; nullopt when it cannot be (the GL thread reads
  /// it again when shown and says why).
  virtual std::optional<Prepared> prepare(std::size_t step, const PrepareContext& context) const = 0;
};

/// What one volume layer holds in memory (the control panel's "loaded" table).
struct LayerMemory {
  std::string name;            ///< "radar KTLX DBZH", "grid /dbz"
  std::uint64_t cpuBytes = 0;  ///< the CPU copy kept for the reference and readout (values, heights)
  std::uint64_t gpuBytes = 0;  ///< its textures (VolumeGL::gpuBytes: values, tables, empty-space grid)
};

class VolumeSourceGL {
 public:
  virtual ~VolumeSourceGL() = default;
  VolumeSourceGL(const VolumeSourceGL&) = delete;
  VolumeSourceGL& operator=(const VolumeSourceGL&) = delete;

  /// The description as added or last applied (setDescription).
  const VolumeLayerDescription& description() const { return description_; }
  VolumeKind kind() const { return description_.kind; }
  /// Render options: colours, opacity, mode, step. The viewer lowers imageScale while moving.
  const VolumeRenderOptions& options() const { return options_; }
  VolumeRenderOptions& options() { return options_; }
  /// Drawn (the control panel switches layers off).
  bool visible = true;

  /// The GPU volume shown now (with its CPU twin: VolumeGL::referenceSampler).
  virtual const VolumeGL& volume() const = 0;
  /// Every GPU volume the layer draws: volume() alone, except for a radar network split into
  /// clusters apart (RadarNetworkSourceGL).
  virtual std::vector<const VolumeGL*> volumes() const { return {&volume()}; }
  /// Where one of volumes() has no data in this frame (VolumeLayerGL::hole): a grid's far part
  /// around its near part drawn at a finer resolution (GridSourceGL). Default: none.
  virtual std::optional<volume::LonLatBox> holeOf(const VolumeGL* volume) const {
    (void)volume;
    return std::nullopt;
  }
  /// Picks what volumes() gives for a frame of `camera` (grids: a coarser copy where a pixel spans
  /// several grid columns at the layer's own image scale, GridSourceGL). Called by the scene before it
  /// marches; the default keeps volume(). `background`: what is not ready yet is made on a worker
  /// thread meanwhile (the viewer: frames never wait for it) instead of now (render, scripts).
  virtual void chooseDetail(const Camera& camera, bool background) {
    (void)camera;
    (void)background;
  }
  /// "radar KTLX  DBZH", "grid QRAIN": the panel's and the memory table's name.
  virtual std::string title() const = 0;
  /// The fields (radar) or variables (grid) the file holds, for the panel's choice; the one
  /// shown is fieldShown().
  virtual std::vector<std::string> fieldChoices() const = 0;
  virtual std::string fieldShown() const = 0;
  /// The values the colours span when the description sets no range (the panel's sliders).
  virtual volume::ValueRange colourRange() const = 0;
  /// The histogram of the values shown (the transfer-function editor).
  virtual volume::ValueHistogram histogram(int bins) const = 0;

  // --- Time ---
  /// The layer's own times (ISO 8601 UTC), metadata only: a radar loop's volumes, a grid file's
  /// steps; one or none when it has no time axis.
  virtual Result<std::vector<std::string>> times() const = 0;
  virtual TimeMatching timeMatching() const = 0;
  /// Whether a step between two times is interpolated (grids) or shows the step's own (radars).
  virtual bool interpolatesInTime() const = 0;
  /// The index of the step shown on times().
  virtual std::size_t step() const = 0;
  /// Shows step `step`, `fraction` (0..1, interpolating sources only) towards step + 1, from the
  /// cache or read now; the render options stay, so frames compare.
  virtual Status showStep(std::size_t step, double fraction, SourceContext context) = 0;
  /// A preparer of this source's steps for a background thread (copies of what it needs).
  virtual std::unique_ptr<StepPreparer> preparer(double exaggeration) const = 0;

  // --- Live edits (LayerEdit.h says which change needs what) ---
  /// Applies an edited description of the same kind (validated by the caller): render options
  /// only, or the data read again (another field, time, datum or crop box). On error the source
  /// is unchanged.
  virtual Status setDescription(const VolumeLayerDescription& description, SourceContext context) = 0;
  /// The scene's vertical exaggeration changed (context.exaggeration): re-upload or read again.
  virtual Status applyExaggeration(SourceContext context) = 0;

  // --- What the frame and the user are told ---
  virtual LegendPart legendPart() const = 0;
  virtual LayerMemory memory() const = 0;
  /// The readout line of the first value along eye + t dir, t < tMax, searched with `stepMeters`
  /// (Readout.h); nullopt where the ray meets none.
  virtual std::optional<std::string> readoutAt(const glm::dvec3& eyeEcef, const glm::dvec3& dir, double tMaxMeters,
                                               double stepMeters) const = 0;
  /// A marker drawn at the layer's site (radars), else null.
  virtual const Marker* siteMarker() const { return nullptr; }
  /// Every site marker the layer draws (a radar's one, a network's each): siteMarker() by default.
  virtual std::vector<Marker> siteMarkers() const {
    const Marker* m = siteMarker();
    return m ? std::vector<Marker>{*m} : std::vector<Marker>{};
  }
  /// Map context drawn with the layer when range rings are on (a radar's rings and spokes).
  virtual std::vector<map::GeoPolyline> rangeRings() const { return {}; }
  /// A line for the user after loading (datum used, bytes read, heights).
  virtual std::string loadNote() const = 0;

 protected:
  VolumeSourceGL() = default;
  VolumeLayerDescription description_;
  VolumeRenderOptions options_;
};

/// Reads, places and uploads the layer `description` names (the one place a kind picks its
/// source: adding a kind adds a line here). The first step shown goes into context.cache.
Result<std::unique_ptr<VolumeSourceGL>> openVolumeSource(const VolumeLayerDescription& description,
                                                         SourceContext context);

/// Render options of a volume layer description, either kind, for the field it loaded (colours by
/// the field's kind unless the description names a table: volume::transferForField; .pal errors;
/// `nyquistMps` NaN where the field has none); colours span `range` unless the description
/// sets one; no iso value: defaultIsoValue over `range`.
Result<VolumeRenderOptions> layerRenderOptions(const VolumeLayerDescription& description,
                                               const volume::FieldInfo& field, double nyquistMps,
                                               const volume::ValueRange& range);

/// The transfer function of a layer: the field's (transferForField: colours by kind unless
/// named) stretched to the user's value range and given the user's opacity ramp, where set.
Result<volume::TransferFunction> transferForLayer(const std::string& colors, const VolumeLayerSettings& settings,
                                                  const volume::FieldInfo& field, double nyquistMps,
                                                  const volume::ValueRange& range);

/// Whether the layer's crop box cuts anything, and the EGM96 grid for its heights above sea level
/// (null when not needed). Shared by the sources' reads.
bool isCropped(const VolumeLayerSettings& settings);
Result<const volume::GeoidGrid*> cropGeoid(const VolumeLayerSettings& settings, bool useGeoid);

/// A variable or field name as shown: netCDF paths ("/dbz") without the root.
std::string displayName(std::string name);

}  // namespace atmoglobe::engine
