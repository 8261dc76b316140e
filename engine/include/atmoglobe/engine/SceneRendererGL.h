#pragma once
// Renders a scene: the globe, then the volume layers (one list of VolumeSourceGL, radars and
// grids alike, ray-marched together, occluded by the globe's depth), then markers (stations and
// radar sites). The headless render loop waits until
// every tile has the imagery it wants.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GlobeRendererGL.h>
#include <atmoglobe/engine/GltfModelRendererGL.h>
#include <atmoglobe/engine/GridSourceGL.h>
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/MapRendererGL.h>
#include <atmoglobe/engine/MarkerRendererGL.h>
#include <atmoglobe/engine/RadarSourceGL.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SliceRendererGL.h>
#include <atmoglobe/engine/SurfaceFieldGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/engine/VolumeSourceGL.h>
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

struct SceneFrameStats {
  GlobeFrameStats globe;
  MapFrameStats map;
  double cpuMilliseconds = 0.0;   ///< time to issue the frame (without waiting for the GPU)
  double referenceSeconds = 0.0;  ///< time of the CPU reference volumes (setReferenceVolumes), else 0
};

class SceneRendererGL {
 public:
  static Result<std::unique_ptr<SceneRendererGL>> create(std::shared_ptr<globe::TileImageLoader> loader,
                                                         const GlobeRenderOptions& globeOptions = {});
  /// Reads, places and uploads a volume layer of either kind (openVolumeSource, VolumeSourceGL.h).
  /// The layer is appended to the one list of volume layers; the pointer stays valid.
  Result<VolumeSourceGL*> addVolume(const VolumeLayerDescription& description);
  /// Appends a source made elsewhere (tests, benchmarks: RadarSourceGL::fromVolume).
  VolumeSourceGL& addSource(std::unique_ptr<VolumeSourceGL> source);
  /// The volume layers, in the order added.
  std::size_t volumeLayerCount() const { return layers_.size(); }
  VolumeSourceGL& layer(std::size_t index) { return *layers_.at(index); }
  const VolumeSourceGL& layer(std::size_t index) const { return *layers_.at(index); }
  /// Layer `index` as its kind's source (RadarSourceGL, GridSourceGL), or null when it is another kind.
  template <class Source>
  const Source* layerAs(std::size_t index) const {
    return dynamic_cast<const Source*>(layers_.at(index).get());
  }
  /// Shows layer `index` at its time step `step` (only that step is read), or, with `fraction`
  /// in (0, 1), interpolated that far towards step + 1 where the layer interpolates in time
  /// (grids: volume::interpolateGridSteps; both steps are read). The layer keeps its render
  /// options (colours and opacity of the step first loaded), so frames of a series compare.
  Status setLayerStep(std::size_t index, std::size_t step, double fraction = 0.0);
  /// The memory budget of the layers' time steps and loop volumes (CPU data and GPU textures;
  /// volume::StepCache, docs/memory.md): steps not shown are dropped least recently used beyond
  /// it and read again when shown. Default: volume::defaultMemoryBudgetBytes().
  void setMemoryBudget(std::uint64_t bytes) { cache_->setBudget(bytes); }
  volume::StepCache& stepCache() { return *cache_; }
  const std::shared_ptr<volume::StepCache>& sharedStepCache() const { return cache_; }
  /// Samples a slice (CAPPI or cross-section) of the volume it names and draws it on the globe
  /// (SliceRendererGL.h); returns a line for the user.
  Result<std::string> addSlice(const SliceLayerDescription& description);
  /// Reads a grid's 2-D field and drapes it on the globe with its contours (SurfaceFieldGL.h);
  /// returns a line for the user.
  Result<std::string> addSurface(const SurfaceLayerDescription& description);
  const std::vector<std::unique_ptr<SurfaceFieldGL>>& surfaces() const { return surfaces_; }
  /// Applies an edited description to surface layer `index` (the viewer's panel): the data read
  /// again when it asks for other data (sameSurfaceData: variable, time, member or statistic,
  /// pressure or level, wind), else the loaded data drawn under the new colours, range, opacity
  /// and contours. The layer's visibility is kept. On error the layer is unchanged.
  Status setSurfaceDescription(std::size_t index, const SurfaceLayerDescription& description);
  /// Grids' coarser copies (level of detail) made on a worker thread while frames go on with
  /// what is ready (the interactive viewer), instead of before the frame that needs them (the
  /// default: render, scripts and tests draw the same picture every time).
  void setDetailInBackground(bool background) { detailInBackground_ = background; }
  /// Switches surface layer `index` on or off.
  void setSurfaceVisible(std::size_t index, bool visible);
  /// The scene's vertical exaggeration (volume/VerticalExaggeration.h; 1 = none): radars, grids,
  /// slices and markers are drawn at that many times their height above the ellipsoid, so they
  /// stay aligned. Call before adding layers (it applies to layers added afterwards; an error
  /// once any volume or slice is loaded). Cone models (.glb) are drawn as exported.
  Status setVerticalExaggeration(double factor);
  double verticalExaggeration() const { return exaggeration_; }
  // --- Live edits (the viewer's control panel; LayerEdit.h says what each change needs) ---
  /// Applies an edited description to volume layer `index`: render
  /// options only (colours, opacity range / ramp / control points, mode, iso value, step, image
  /// scale, interpolation, beam, classification) or, for another field / variable, time, datum
  /// or crop box, the data read again (a radar loop: its steps found again for that field; the
  /// step shown kept). The kind cannot change. On error the layer is unchanged.
  Status setVolumeDescription(std::size_t index, const VolumeLayerDescription& description);
  /// The description of volume layer `index`.
  const VolumeLayerDescription& volumeDescription(std::size_t index) const;
  /// Changes the vertical exaggeration of a loaded scene: each layer re-uploaded from its CPU
  /// copy (radars) or read again (grids: their heights are exaggerated in place). An error (nothing changed)
  /// when the scene has slices (they keep the factor they were sampled with).
  Status changeVerticalExaggeration(double factor);
  /// The order volume layers are handed to the marcher (which layer's mode and step lead where
  /// volumes overlap, VolumeRendererGL::draw): a permutation of 0..volumeLayerCount()-1;
  /// default the order added. Errors: not a permutation.
  Status setVolumeOrder(const std::vector<std::size_t>& order);
  std::vector<std::size_t> volumeOrder() const;
  /// CPU and GPU bytes per volume layer.
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
  /// Volumes refined over several frames (the viewer at rest): each renderFrame marches volume
  /// tiles for at most `budgetMs` (VolumeRendererGL::drawProgressive), the rest of the picture
  /// showing a coarse preview until done. 0 (the default): every frame's volumes whole.
  void setProgressiveBudget(double budgetMs) { progressiveBudgetMs_ = budgetMs; }
  /// Whether the last frame's volumes were complete (always true without a budget, a progressive
  /// one or the far field's: VolumeRendererGL::setFarFieldBuildBudgetMs).
  bool volumesComplete() const { return volumesComplete_; }
  /// The viewer at rest while its volumes refine: the caller vouches that nothing in the scene
  /// changed since the last frame but the volumes' refinement (no motion, input, edit or time
  /// step). A frame with the last one's camera and target size then starts from the background
  /// kept then (colour and depth of everything drawn before the volumes: globe, models, slices,
  /// surfaces, map lines; kept from a refining frame whose imagery and lines were complete)
  /// instead of drawing it again: the same picture, without the globe and map lines' cost (40-56
  /// ms of a 1280x720 continental frame on llvmpipe). Off by default. This class's own changes
  /// (adding or editing layers, surfaces, slices, models, overlays, steps) invalidate the kept
  /// background; changes made through the accessors (map(), globe(), layer(i)) are the caller's
  /// to report by passing false.
  void setBackgroundReuse(bool allowed) { backgroundReuse_ = allowed; }
  /// Frames that started from the kept background.
  std::size_t backgroundsReused() const { return backgroundsReused_; }
  GlobeRendererGL& globe() { return *globe_; }
  VolumeRendererGL& volumeRenderer() { return *volumeRenderer_; }

 private:
  SceneRendererGL() = default;
  std::unique_ptr<GlobeRendererGL> globe_;
  std::unique_ptr<MarkerRendererGL> markers_;
  std::unique_ptr<VolumeRendererGL> volumeRenderer_;
  std::vector<std::unique_ptr<VolumeSourceGL>> layers_;
  std::vector<std::unique_ptr<GltfModelRendererGL>> models_;
  std::unique_ptr<SliceRendererGL> slices_;
  std::vector<std::unique_ptr<SurfaceFieldGL>> surfaces_;
  bool detailInBackground_ = false;
  std::unique_ptr<MapRendererGL> map_;
  bool rangeRings_ = false;
  std::size_t layersWithRings_ = 0;
  int referenceThreads_ = 0;
  double progressiveBudgetMs_ = 0.0;
  bool volumesComplete_ = true;
  double exaggeration_ = 1.0;
  /// What was drawn before the volumes in a refining frame (setBackgroundReuse).
  struct KeptBackground {
    std::unique_ptr<FramebufferGL> image;  ///< colour and depth as the target's
    int colorFormat = 0;                   ///< its colour's sized format (GL enum)
    CameraPose pose;
    double fovYDeg = 0.0;
    std::uint64_t version = 0;
    bool valid = false;
    GlobeFrameStats globe;
    MapFrameStats map;
  };
  KeptBackground background_;
  bool backgroundReuse_ = false;
  std::size_t backgroundsReused_ = 0;
  /// Bumped by every change this class makes to the scene (a background kept before is stale).
  std::uint64_t version_ = 0;
  bool backgroundMatches(const Camera& camera, const FramebufferGL& target) const;
  void keepBackground(const Camera& camera, const FramebufferGL& target, const SceneFrameStats& stats);
  std::vector<std::size_t> volumeOrder_;  ///< empty: the order added
  std::shared_ptr<volume::StepCache> cache_ = std::make_shared<volume::StepCache>();
  SourceContext contextFor(std::size_t index) { return SourceContext{*cache_, exaggeration_, index}; }
};

}  // namespace atmoglobe::engine
