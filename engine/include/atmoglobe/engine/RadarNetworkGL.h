#pragma once
// A radar network on the GPU as one volume (volume/RadarNetwork.h): every radar's sweeps in its own
// polar geometry as tiles of one texture array, their azimuth and elevation tables, per-radar and
// per-sweep records and the coverage index in a shader storage buffer; drawn by VolumeRendererGL
// through shaders/sample_network.glsl, where a sample visits only the radars its coverage cell
// lists and combines them by the overlap rule. The CPU reference draws the same network through
// volume::RadarNetworkSampler (the same index and rule, in double).
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/OccupancyGrid.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarNetwork.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace atmoglobe::engine {

/// What a network's upload needs of one radar beyond its values, made on the CPU alone (GL-free:
/// a worker thread may make it, and a step that shows the radar again reuses it): its empty-space
/// grid's occupied runs and its sweeps' azimuth tables. Made at one vertical exaggeration.
struct NetworkRadarParts {
  double exaggeration = 1.0;
  glm::dvec3 occupancyOriginEcef{0.0};
  glm::dmat3 occupancyToEcef{1.0};            ///< the radar's empty-space frame (east, north, up columns)
  std::vector<volume::OccupancyBox> runs;     ///< runs of occupied cells along x, in that frame
  std::vector<std::vector<float>> rayTables;  ///< per sweep: volume::rayCoordinateTable
  /// Above the ellipsoid, the highest corner of its occupied cells (runs): no echo above it
  /// (-infinity: no echo anywhere).
  double echoTopMeters = -std::numeric_limits<double>::infinity();
  std::uint64_t bytes() const;
};

class RadarNetworkGL final : public VolumeGL {
 public:
  /// The parts of `radar` at `exaggeration` (validated by the caller).
  static std::shared_ptr<const NetworkRadarParts> prepareRadar(const volume::PolarVolume& radar, double exaggeration);
  /// Uploads `radars` (1 or more, each of 1..MarchConstants::kMaxSweeps sweeps, one field `kind`)
  /// under `rule` (not Integrate: the march's rule for separate volumes). Errors: those of
  /// volume::makeRadarNetworkSampler; a tile or table larger than the GPU's texture limits; out
  /// of GPU memory. `exaggeration` != 1: drawn at that vertical exaggeration
  /// (volume/VerticalExaggeration.h): each radar maps a drawn point back to its true height on its
  /// local sphere, as a radar layer does; the reference is the network sampler seen through
  /// volume::ExaggeratedSampler (exact).
  /// `parts`: prepareRadar's of each radar in order, made at `exaggeration`; empty: made here.
  /// `previous`: a network of the same sites (the step shown before) whose values texture serves
  /// where its layout is this one's (the same sweep counts, tile size and tiles per layer,
  /// exaggeration): only the tiles of radars whose volume is not previous's (another shared_ptr)
  /// are packed and uploaded. With PreviousTexture::TakeOver the texture is taken over:
  /// `previous` then draws nothing (drawable() false) and must be dropped. With ::Copy (a loop
  /// that keeps its steps) it is copied on the GPU (glCopyImageSubData) where at least one radar
  /// is unchanged, and `previous` draws on. Otherwise `previous` is left as it was and everything
  /// is uploaded.
  enum class PreviousTexture { TakeOver, Copy };
  static Result<std::unique_ptr<RadarNetworkGL>> create(
      std::vector<std::shared_ptr<const volume::PolarVolume>> radars, volume::OverlapRule rule, volume::FieldKind kind,
      double exaggeration = 1.0, std::vector<std::shared_ptr<const NetworkRadarParts>> parts = {},
      RadarNetworkGL* previous = nullptr, PreviousTexture use = PreviousTexture::TakeOver);
  /// The radars split into the clusters whose clip spheres meet (volume::clusterBySphere), one
  /// network each, largest first: the marcher draws clusters apart in passes of their own, each
  /// with its own tight ray interval and empty-space grid (a national network with sites in
  /// Alaska, Hawaii, Guam and Europe would otherwise be one volume spanning the globe).
  /// A cluster of the same sites as one of `previous` (the step shown before) is that network
  /// itself, shared, where it still draws and holds the same volumes (the same shared_ptrs) at the
  /// same rule, kind and exaggeration: nothing of it is built or uploaded again. Otherwise it
  /// takes that network's texture over or copies it, as create() does; a network once kept whole
  /// is held by several steps and is copied, never taken over.
  static Result<std::vector<std::shared_ptr<RadarNetworkGL>>> createByCluster(
      const std::vector<std::shared_ptr<const volume::PolarVolume>>& radars, volume::OverlapRule rule,
      volume::FieldKind kind, double exaggeration = 1.0,
      const std::vector<std::shared_ptr<const NetworkRadarParts>>& parts = {},
      const std::vector<std::shared_ptr<RadarNetworkGL>>& previous = {},
      PreviousTexture use = PreviousTexture::TakeOver);
  ~RadarNetworkGL() override;
  RadarNetworkGL(const RadarNetworkGL&) = delete;
  RadarNetworkGL& operator=(const RadarNetworkGL&) = delete;

  std::string_view samplerShaderFile() const override { return "sample_network.glsl"; }
  std::vector<std::string> samplerDefines(const VolumeRenderOptions& options) const override;
  glm::dvec3 originEcef() const override { return origin_; }
  void setSamplerUniforms(const SamplerBindingGL& binding) const override;
  void bindSamplerTextures(const SamplerBindingGL& binding, const VolumeRenderOptions& options) const override;
  volume::ValueRange valueRange() const override { return sampler_->valueRange(); }
  std::size_t gpuBytes() const override { return gpuBytes_ + occupancy_.gpuBytes(); }
  std::string description() const override { return sampler_->description(); }
  /// The coverage index's box, up to the highest echo (the highest corner of any radar's occupied
  /// empty-space cells), or the highest beam if that is lower; none without echoes.
  std::optional<FarFieldExtent> farFieldExtent() const override;
  const volume::VolumeSampler& referenceSampler() const override {
    return exaggerated_ ? static_cast<const volume::VolumeSampler&>(*exaggerated_) : *sampler_;
  }
  /// The network at true scale (its coverage index and rule).
  const volume::RadarNetworkSampler& network() const { return *sampler_; }
  double exaggeration() const { return exaggeration_; }
  /// Radars whose tiles this network's creation uploaded (all of them unless it took over or
  /// copied a previous step's texture).
  int radarsUploaded() const { return radarsUploaded_; }
  /// Cells of the empty-space grid this network's creation computed: all of them, or where a
  /// previous step's grid served, those of the changed radars' old and new boxes (a cell in the
  /// ranges of two changed radars counted twice).
  std::size_t occupancyCellsBuilt() const { return occupancyCellsBuilt_; }
  /// Cells of its empty-space grid.
  std::size_t occupancyCells() const { return occupancy_.grid().maxValues.size(); }
  /// Whether it still draws (false once a later step took its texture over).
  bool drawable() const { return values_ != 0; }

 private:
  RadarNetworkGL() = default;
  std::vector<std::shared_ptr<const volume::PolarVolume>> radars_;
  std::unique_ptr<volume::RadarNetworkSampler> sampler_;
  volume::FieldKind kind_ = volume::FieldKind::Reflectivity;
  double exaggeration_ = 1.0;
  std::unique_ptr<volume::ExaggeratedSampler> exaggerated_;  ///< the reference when exaggerated
  glm::dvec3 origin_{0.0};
  unsigned int values_ = 0, rayTable_ = 0, buffer_ = 0;
  glm::vec2 valuesSize_{1.0f};
  int tileWidth_ = 1, tileHeight_ = 1, tilesPerLayer_ = 1, layers_ = 1, rayTableRows_ = 1;
  int radarsUploaded_ = 0;
  int sweepBase_ = 0, cellBase_ = 0, memberBase_ = 0;
  std::vector<volume::OccupancyBox> radarBoxBounds_;  ///< per radar, the union of its boxes in the grid's frame
  std::size_t occupancyCellsBuilt_ = 0;
  bool keptByLaterSteps_ = false;  ///< createByCluster kept it whole for a later step: never taken over
  int maxListed_ = 0;              ///< the most radars a coverage cell lists (a variant constant of the march)
  glm::vec4 enclosing_{0.0f}, top_{0.0f};
  double topRadiusMeters_ = 0.0;  ///< from the Earth's centre: above every beam (top_, in double)
  double echoTopMeters_ = 0.0;    ///< above the ellipsoid: the radars' highest echo (NetworkRadarParts)
  std::size_t gpuBytes_ = 0;
};

}  // namespace atmoglobe::engine
