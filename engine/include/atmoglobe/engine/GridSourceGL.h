#pragma once
// A forecast grid layer (VolumeSourceGL.h): one variable of a model file, its time steps the
// layer's steps (only the step shown is read: GridReader.h), interpolated linearly between two
// steps when asked. Colours and opacity stay those of the step first loaded (or of the
// description's range), so the frames of a series compare.
#include <atmoglobe/engine/GridVolumeGL.h>
#include <atmoglobe/engine/VolumeSourceGL.h>
#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/GridVolume.h>

#include <cstdint>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::engine {

/// A grid's step as the renderer draws it, CPU side only (no GL: safe on a worker thread; the
/// readers hold the netCDF library lock while they call netCDF-C, io/NetcdfLock.h, so the GL
/// thread's coastline reads and reloads never overlap them): read (variable, crop box columns),
/// cropped, vertically exaggerated by `exaggeration`.
Result<volume::GridVolume> prepareGridStep(const VolumeLayerDescription& description, std::size_t step,
                                           double exaggeration);

class GridSourceGL final : public VolumeSourceGL {
 public:
  /// Reads the variable and time step `description` names, places and uploads it.
  static Result<std::unique_ptr<GridSourceGL>> open(const VolumeLayerDescription& description, SourceContext context);

  const VolumeGL& volume() const override { return *volume_; }
  const GridVolumeGL& gridVolume() const { return *volume_; }
  /// The level of detail marched (volume/GridDetail.h): the coarser copy chosen for the last
  /// camera, built on first use and kept while the step is shown; volume() stays the grid itself
  /// (the readout and the memory budget's data).
  ///
  /// A grid too large for the GPU (drawn at lower resolution: GridVolumeGL::unreducedGrid) is
  /// drawn from the window of columns and rows in view (engine::visibleGridWindow, widened by an
  /// eighth on each side so that small moves keep it) at full resolution where that window has no
  /// more columns x rows than the grid as uploaded (so it fits where that did); the window is made
  /// again when the view leaves it. Both follow `level_of_detail` (off: the grid as uploaded).
  ///
  /// Where that window (or the grid as uploaded, where no window is finer) is coarser than the
  /// grid, the part of the view nearest the eye is drawn with it at full resolution
  /// (engine::nearGridWindow, as many columns x rows as the grid as uploaded; not for reduced
  /// grids): volumes() then gives the near window and the coarser one, whose hole (holeOf) is the
  /// near window's latitude/longitude box, so every point is drawn from exactly one of them.
  std::vector<const VolumeGL*> volumes() const override;
  std::optional<volume::LonLatBox> holeOf(const VolumeGL* volume) const override;
  void chooseDetail(const Camera& camera, bool background) override;
  /// The near window drawn at full resolution for the last camera (empty: none).
  volume::GridWindow nearWindow() const { return nearUsed_ ? near_->window : volume::GridWindow{}; }
  /// The level chosen for the last camera (0: the grid itself).
  int detailLevel() const { return detailLevel_; }
  /// The window of the grid drawn for the last camera (empty: the grid as uploaded, or a coarser copy).
  volume::GridWindow viewWindow() const;
  std::string title() const override { return "grid " + volume_->grid().variable; }
  std::vector<std::string> fieldChoices() const override;
  std::string fieldShown() const override { return volume_->grid().variable; }
  volume::ValueRange colourRange() const override { return firstRange_; }
  volume::ValueHistogram histogram(int bins) const override;

  Result<std::vector<std::string>> times() const override;
  TimeMatching timeMatching() const override { return TimeMatching::SameValidTime; }
  bool interpolatesInTime() const override { return true; }
  std::size_t step() const override { return step_; }
  /// The fraction (0..1) of the way to step() + 1 shown (0: the step itself).
  double stepFraction() const { return stepFraction_; }
  Status showStep(std::size_t step, double fraction, SourceContext context) override;
  std::unique_ptr<StepPreparer> preparer(double exaggeration) const override;

  Status setDescription(const VolumeLayerDescription& description, SourceContext context) override;
  Status applyExaggeration(SourceContext context) override;

  LegendPart legendPart() const override;
  LayerMemory memory() const override;
  std::optional<std::string> readoutAt(const glm::dvec3& eyeEcef, const glm::dvec3& dir, double tMaxMeters,
                                       double stepMeters) const override;
  std::string loadNote() const override;

 private:
  GridSourceGL() = default;
  /// Read afresh with `d` (another variable, crop or exaggeration): every cached step is stale.
  Status reload(const VolumeLayerDescription& d, std::size_t step, double fraction, SourceContext context);
  /// The step's CPU data: from its GPU volume's twin in the cache, the cache, or read (and cached).
  Result<std::shared_ptr<const volume::GridVolume>> stepData(std::size_t step, SourceContext context);
  /// The step ready for upload: from the cache (a ScenePrefetcher's), or read and prepared now (and cached).
  Result<std::shared_ptr<const GridVolumeGL::Prepared>> stepPrepared(std::size_t step, SourceContext context);
  std::shared_ptr<GridVolumeGL> volume_;  ///< shared with the step cache (memory budget)
  std::size_t step_ = 0;                  ///< time step shown (index on the file's axis)
  double stepFraction_ = 0.0;             ///< > 0: that far (0..1) towards step_ + 1, interpolated
  bool synthetic_ = false;                ///< the file says SYNTHETIC
  std::string mosaicRule_;                ///< a radar mosaic's overlap rule (atmoglobe mosaic), else empty
  volume::ValueRange firstRange_{};       ///< the values of the step first loaded (its colours' range)
  mutable std::optional<std::vector<std::string>> variables_;  ///< the file's variables on a grid, once asked
  /// An ensemble statistic's members for the readout, read at its first use for the volume shown
  /// (each member's values on the statistic's geometry and drawn heights), or why not.
  struct MemberGrids {
    const void* volume = nullptr;  ///< the GridVolumeGL they were read for
    std::vector<std::pair<long, volume::GridVolume>> grids;
    std::vector<std::unique_ptr<volume::GridSampler>> samplers;
    std::string note;  ///< set when the members are not kept (too large, not readable)
  };
  mutable std::shared_ptr<MemberGrids> members_;
  // Level of detail: the coarser copies of volume_ (index L - 1 for level L, null until built),
  // the volume they were made from, the level chosen for the last camera.
  std::vector<std::shared_ptr<GridVolumeGL>> detail_;
  const void* detailOf_ = nullptr;
  int detailLevel_ = 0;
  /// A copy being made on a worker thread (chooseDetail in the background): its level, the
  /// volume it is of, and its CPU part when done.
  struct DetailBuild {
    int level = 0;
    std::uint64_t of = 0;  ///< the id (VolumeGL::id) of the grid volume it is of
    std::future<std::shared_ptr<const GridVolumeGL::Prepared>> prepared;
  };
  std::optional<DetailBuild> building_;
  /// The view's window of a grid too large for the GPU (volumes()): the volume it is of, the
  /// window, every how many columns and rows it keeps (1: full resolution; 2, 4 ...: a window that
  /// fits only at that resolution, still finer than the grid as uploaded), the GPU copy; and one
  /// being made on a worker thread.
  struct ViewWindow {
    std::uint64_t of = 0;  ///< the id (VolumeGL::id) of the grid volume it is of
    volume::GridWindow window;
    std::size_t factor = 1;
    std::shared_ptr<GridVolumeGL> volume;
  };
  std::optional<ViewWindow> window_;
  bool windowUsed_ = false;  ///< window_ covers the last camera's view
  struct WindowBuild {
    std::uint64_t of = 0;  ///< the id (VolumeGL::id) of the grid volume it is of
    volume::GridWindow window;
    std::size_t factor = 1;
    std::future<std::shared_ptr<const GridVolumeGL::Prepared>> prepared;
  };
  std::optional<WindowBuild> windowBuilding_;
  /// The near window at full resolution (volumes()), its latitude/longitude box, whether the last
  /// camera draws it, one being made, and the camera its place was last found for.
  std::optional<ViewWindow> near_;
  volume::LonLatBox nearBox_;
  bool nearUsed_ = false;
  std::optional<WindowBuild> nearBuilding_;
  /// A near window the GPU took only at a lower resolution (not made again for that grid).
  struct NearRefused {
    std::uint64_t of = 0;
    volume::GridWindow window;
  };
  std::optional<NearRefused> nearRefused_;
  std::vector<double> nearKey_;
  const void* nearOf_ = nullptr;
  volume::GridWindow nearInSight_;
  std::vector<double> viewKey_;     ///< the camera the window in view was last found for
  const void* viewOf_ = nullptr;    ///< and the grid
  volume::GridWindow viewInSight_;  ///< what visibleGridWindow gave then
  void chooseCoarserCopy(const Camera& camera, bool background);
  void chooseViewWindow(const Camera& camera, bool background);
  void chooseNearWindow(const Camera& camera, bool background);
  /// The view's window where it is drawn, else the grid as uploaded (around a near window: the
  /// coarser level).
  const GridVolumeGL& windowOrGrid() const;
  /// Every how many of the grid's columns windowOrGrid() keeps (1: full resolution).
  std::size_t windowOrGridFactor() const;
  const MemberGrids& memberGrids() const;
};

/// The level of detail a grid marches for `camera` at `imageScale` (volume/GridDetail.h): by the
/// footprint of a pixel where the grid's bounding sphere is nearest the eye, at most
/// volume::maxDetailLevel. What GridSourceGL::chooseDetail takes and the bench measures.
int gridDetailLevelFor(const GridVolumeGL& grid, const Camera& camera, double imageScale);
/// Level `level`'s copy of `grid` (volume::coarsenGrid with that level's factors) on the GPU.
Result<std::unique_ptr<GridVolumeGL>> createGridDetail(const volume::GridVolume& grid, int level);

}  // namespace atmoglobe::engine
