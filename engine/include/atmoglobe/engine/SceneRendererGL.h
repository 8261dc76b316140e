#pragma once
// Renders a scene: the globe, then radar volumes (ray-marched, occluded by the globe's
// depth), then markers (stations and radar sites). The headless render loop waits until
// every tile has the imagery it wants.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GlobeRendererGL.h>
#include <atmoglobe/engine/GltfModelRendererGL.h>
#include <atmoglobe/engine/GridVolumeGL.h>
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/MapRendererGL.h>
#include <atmoglobe/engine/MarkerRendererGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SliceRendererGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/TileImageLoader.h>
#include <atmoglobe/volume/StepCache.h>

#include <cstdint>
#include <memory>

namespace atmoglobe::engine {

/// Opens the scene's imagery layers (bottom first) behind one asynchronous loader.
/// A scene without imagery gets an empty loader (the globe shows its base colour).
Result<std::shared_ptr<globe::TileImageLoader>> openImagery(const std::vector<ImageryLayerDescription>& layers,
                                                            const globe::TileImageLoaderOptions& options);

/// The transfer function of a layer: the field's (transferForField: colours by kind unless
/// named) stretched to the user's value range and given the user's opacity ramp, where set.
Result<volume::TransferFunction> transferForLayer(const std::string& colors, const VolumeLayerSettings& settings,
                                                  const volume::FieldInfo& field, double nyquistMps,
                                                  const volume::ValueRange& range);

/// Render options of a volume layer description, either kind, for the field it loaded (colours by
/// the field's kind unless the description names a table: volume::transferForField; .pal errors;
/// `nyquistMps` NaN where the field has none); colours span `range` unless the description
/// sets one; no iso value: defaultIsoValue over `range`.
Result<VolumeRenderOptions> layerRenderOptions(const VolumeLayerDescription& description,
                                               const volume::FieldInfo& field, double nyquistMps,
                                               const volume::ValueRange& range);

struct SceneFrameStats {
  GlobeFrameStats globe;
  MapFrameStats map;
  double cpuMilliseconds = 0.0;   ///< time to issue the frame (without waiting for the GPU)
  double referenceSeconds = 0.0;  ///< time of the CPU reference volumes (setReferenceVolumes), else 0
};

/// A radar loaded for rendering: its GPU volume, its options and its site marker.
struct RadarLayerGL {
  std::shared_ptr<RadarVolumeGL> volume;  ///< shared with the step cache (memory budget)
  VolumeRenderOptions options;
  Marker siteMarker;
  std::string datumNote;               ///< which vertical datum / geoid undulation was used
  std::string siteName;                ///< as the file names it
  std::string timeIso8601;             ///< volume start
  bool synthetic = false;              ///< the file says SYNTHETIC
  VolumeLayerDescription description;  ///< as added
  /// A radar loop (a directory, glob or list holding several times of one site): each time's
  /// files (a comma list loadRadar reads as one volume) and volume time, oldest first; empty for
  /// one volume. `step` is the one shown (the latest when added).
  std::vector<std::string> loopFiles, loopTimes;
  std::size_t step = 0;
  // For the control panel (setVolumeDescription): the fields the file holds, the field loaded
  // and the velocity scale its colours were made with, whether it is drawn.
  std::vector<std::string> fields;
  volume::FieldInfo loadedField;
  double nyquistMps = 0.0;
  bool visible = true;
};

/// A forecast grid loaded for rendering: its GPU volume (with its CPU twin) and its options.
struct GridLayerGL {
  std::shared_ptr<GridVolumeGL> volume;  ///< shared with the step cache (memory budget)
  VolumeRenderOptions options;
  VolumeLayerDescription description;  ///< as added (its `time` is the step first loaded)
  std::size_t step = 0;                ///< time step shown (index on the file's axis)
  bool synthetic = false;              ///< the file says SYNTHETIC
  double stepFraction = 0.0;           ///< > 0: that far (0..1) towards step + 1, interpolated
  volume::ValueRange firstRange{};     ///< the values of the step first loaded (its colours' range)
  bool visible = true;                 ///< drawn (the control panel switches layers off)
};

/// What one volume layer holds in memory (the control panel's "loaded" table).
struct LayerMemory {
  std::string name;            ///< "radar KTLX DBZH", "grid /dbz"
  std::uint64_t cpuBytes = 0;  ///< the CPU copy kept for the reference and readout (values, heights)
  std::uint64_t gpuBytes = 0;  ///< its textures (VolumeGL::gpuBytes: values, tables, empty-space grid)
};

class SceneRendererGL {
 public:
  static Result<std::unique_ptr<SceneRendererGL>> create(std::shared_ptr<globe::TileImageLoader> loader,
                                                         const GlobeRenderOptions& globeOptions = {});
  /// Reads, places and uploads a volume layer of either kind (addRadar or addGrid by its kind).
  Status addVolume(const VolumeLayerDescription& description);
  /// Reads, places and uploads a radar volume (the only field asked for is decoded).
  Result<const RadarLayerGL*> addRadar(const VolumeLayerDescription& description);
  std::vector<RadarLayerGL>& radars() { return radars_; }
  const std::vector<RadarLayerGL>& radars() const { return radars_; }
  /// Reads the variable and time step a grid layer names (only that hyperslab: GridReader.h),
  /// places and uploads it. Drawn with the radars in one march where they overlap. The pointer
  /// returned (as addRadar's) is valid until the next layer is added.
  Result<const GridLayerGL*> addGrid(const VolumeLayerDescription& description);
  std::vector<GridLayerGL>& grids() { return grids_; }
  const std::vector<GridLayerGL>& grids() const { return grids_; }
  /// Shows grid `index` at time step `step` of its file (only that step is read), or, with
  /// `fraction` in (0, 1), interpolated that far towards step + 1 (volume::interpolateGridSteps;
  /// both steps are read). The layer keeps its render options: colours and opacity stay those of
  /// the step first loaded (or of the description's range), so frames of a series compare.
  Status setGridStep(std::size_t index, std::size_t step, double fraction = 0.0);
  /// Shows radar `index` (a loop) at its volume `step` (RadarLayerGL::loopFiles; only that
  /// volume is read), keeping its render options so frames compare.
  Status setRadarStep(std::size_t index, std::size_t step);
  /// The memory budget of the layers' time steps and loop volumes (CPU data and GPU textures;
  /// volume::StepCache, docs/memory.md): steps not shown are dropped least recently used beyond
  /// it and read again when shown. Default: volume::defaultMemoryBudgetBytes().
  void setMemoryBudget(std::uint64_t bytes) { cache_->setBudget(bytes); }
  volume::StepCache& stepCache() { return *cache_; }
  const std::shared_ptr<volume::StepCache>& sharedStepCache() const { return cache_; }
  /// Samples a slice (CAPPI or cross-section) of the volume it names and draws it on the globe
  /// (SliceRendererGL.h); returns a line for the user.
  Result<std::string> addSlice(const SliceLayerDescription& description);
  /// The scene's vertical exaggeration (volume/VerticalExaggeration.h; 1 = none): radars, grids,
  /// slices and markers are drawn at that many times their height above the ellipsoid, so they
  /// stay aligned. Call before adding layers (it applies to layers added afterwards; an error
  /// once any volume or slice is loaded). Cone models (.glb) are drawn as exported.
  Status setVerticalExaggeration(double factor);
  double verticalExaggeration() const { return exaggeration_; }
  // --- Live edits (the viewer's control panel; LayerEdit.h says what each change needs) ---
  /// Applies an edited description to volume layer `index` (the single index below): render
  /// options only (colours, opacity range / ramp / control points, mode, iso value, step, image
  /// scale, interpolation, beam, classification) or, for another field / variable, time, datum
  /// or crop box, the data read again (a radar loop: its steps found again for that field; the
  /// step shown kept). The kind cannot change. On error the layer is unchanged.
  Status setVolumeDescription(std::size_t index, const VolumeLayerDescription& description);
  /// The description of volume layer `index` (the single index below).
  const VolumeLayerDescription& volumeDescription(std::size_t index) const;
  /// Changes the vertical exaggeration of a loaded scene: radars re-uploaded from their CPU
  /// copy, grids read again (their heights are exaggerated in place). An error (nothing changed)
  /// when the scene has slices (they keep the factor they were sampled with).
  Status changeVerticalExaggeration(double factor);
  /// Volume layers in a single index: radars 0..R-1, then grids R..R+G-1.
  std::size_t volumeLayerCount() const { return radars_.size() + grids_.size(); }
  /// The order volume layers are handed to the marcher (which layer's mode and step lead where
  /// volumes overlap, VolumeRendererGL::draw): a permutation of 0..volumeLayerCount()-1;
  /// default radars then grids. Errors: not a permutation.
  Status setVolumeOrder(const std::vector<std::size_t>& order);
  std::vector<std::size_t> volumeOrder() const;
  /// CPU and GPU bytes per volume layer, in the single index.
  std::vector<LayerMemory> layerMemory() const;

  /// The legend of the frame `camera` shows (Legend.h): a key per volume layer, the sites /
  /// grids with their fields and valid times in UTC, the scale at the image centre (none when
  /// the centre is sky), and SYNTHETIC when any layer's file says so.
  FrameLegend legendFor(const Camera& camera) const;
  /// Map context (MapRendererGL.h), drawn after the globe, models and slices, before the volumes:
  /// GSHHG coastlines and borders (off until set; an error names a missing GSHHG file), user vector
  /// files (returns a line for the user), range rings and spokes around each radar (every 50 km to
  /// its maximum range, every 30 deg).
  Status setMapContext(bool enabled);
  Result<std::string> addOverlay(const MapOverlayDescription& overlay);
  void setRangeRings(bool enabled) { rangeRings_ = enabled; }
  MapRendererGL& map() { return *map_; }
  /// Loads a georeferenced .glb (e.g. from `atmoglobe export-cones`) to draw over the globe.
  Status addModel(const std::string& glbPath);

  /// Clears `target` and draws the frame into it.
  SceneFrameStats renderFrame(const Camera& camera, const std::vector<Marker>& markers, const FramebufferGL& target);
  /// Renders until the imagery for this view is complete (or `maxPasses` passes), then
  /// reads the image back.
  Result<globe::ImageRGBA8> renderToImage(const Camera& camera, const std::vector<Marker>& markers,
                                          FramebufferGL& target, int maxPasses = 64,
                                          SceneFrameStats* lastStats = nullptr);
  /// threads > 0: volumes are drawn by the CPU reference renderer with that many threads
  /// (VolumeRendererGL::drawReference) instead of the GPU marcher; everything else in the frame
  /// (globe, models, markers, labels) is drawn as always. 0: the GPU marcher (default).
  void setReferenceVolumes(int threads) { referenceThreads_ = threads; }
  GlobeRendererGL& globe() { return *globe_; }
  VolumeRendererGL& volumeRenderer() { return *volumeRenderer_; }

 private:
  SceneRendererGL() = default;
  std::unique_ptr<GlobeRendererGL> globe_;
  std::unique_ptr<MarkerRendererGL> markers_;
  std::unique_ptr<VolumeRendererGL> volumeRenderer_;
  std::vector<RadarLayerGL> radars_;
  std::vector<GridLayerGL> grids_;
  std::vector<std::unique_ptr<GltfModelRendererGL>> models_;
  std::unique_ptr<SliceRendererGL> slices_;
  std::unique_ptr<MapRendererGL> map_;
  bool rangeRings_ = false;
  std::size_t radarsWithRings_ = 0;
  int referenceThreads_ = 0;
  double exaggeration_ = 1.0;
  std::vector<std::size_t> volumeOrder_;  ///< empty: radars then grids
  Status setRadarDescription(std::size_t radarIndex, const VolumeLayerDescription& description);
  Status setGridDescription(std::size_t gridIndex, const VolumeLayerDescription& description);
  Status reloadRadar(std::size_t index, const VolumeLayerDescription& description);
  Status reloadGrid(std::size_t index, const VolumeLayerDescription& description, std::size_t step, double fraction);
  std::shared_ptr<volume::StepCache> cache_ = std::make_shared<volume::StepCache>();
  /// Grid `index`'s step, CPU side: from its GPU volume's twin, the cache, or read (and cached).
  Result<std::shared_ptr<const volume::GridVolume>> gridStepData(std::size_t index, std::size_t step);
  /// Grid `index`'s step ready for upload: from the cache (a ScenePrefetcher's), or read and prepared now (and cached).
  Result<std::shared_ptr<const GridVolumeGL::Prepared>> gridStepPrepared(std::size_t index, std::size_t step);
};

}  // namespace atmoglobe::engine
