#pragma once
// A forecast grid on the GPU in its own geometry (no Cartesian resampling): values and level
// heights as 3-D textures in the grid's (column, row, level) layout, lookup tables from longitude
// and latitude (rectilinear) or from (latitude, longitude) (curvilinear) to fractional grid
// indices, and an empty-space grid; drawn by VolumeRendererGL through shaders/sample_grid.glsl.
// The sampling rule is volume::GridSampler's (its CPU twin, the reference).
//
// Texture layout: a grid that wraps in longitude gets one more column (a copy of column 0), so
// the seam is an ordinary cell; a global grid gets a row below and above (its pole columns: the
// end rows' means, volume::GridSampler), so the polar caps are ordinary cells too. A reduced grid
// (rows of different lengths) is held padded to its longest row + 1: each row's copy of its
// column 0 follows its last point (when it wraps), the texels beyond are no data (with the
// height of the row's last closed column: finite); its lookup texture holds the latitude table
// and a row table (each closed row's columns, first longitude and spacing), the shader's
// VOL_REDUCED variant finding each row's own column.
// Levels: after the grid's levels the 3-D texture holds volume::GridLevelIndex's brackets (per
// cell and height bin, the level pairs a sample can lie between; 4 bins per texel, two 12-bit
// codes loMin | span << 8 per float, exact in float), and the lookup texture one more row, the
// height-to-bin map: a sample finds its level in one fetch and a bisection of usually 0 or 1
// steps instead of one among all the levels.
// Precision: the shader works on float32 ECEF (origin + position) converted to latitude,
// longitude and height by Bowring's formula, about 0.5 m at the Earth's radius; the lookup
// tables are sampled linearly (exact for uniform axes). Both errors are measured against the
// double path (GridMarchTest).
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/GridVolume.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace atmoglobe::engine {

class GridVolumeGL final : public VolumeGL {
 public:
  /// Uploads `grid` (copied: the volume keeps its CPU twin for the reference). A grid whose
  /// texture the GPU cannot hold (GL_MAX_3D_TEXTURE_SIZE, GL_OUT_OF_MEMORY, or the limit
  /// textureByteLimit() sets) is uploaded at half the resolution (volume::decimateGrid; up to
  /// kMaxHalvings times) with a warning line on stderr. Errors: an empty grid, a grid too large
  /// even then.
  static Result<std::unique_ptr<GridVolumeGL>> create(const volume::GridVolume& grid);
  static constexpr int kMaxHalvings = 4;
  /// The grid as given to create() when it had to be drawn at lower resolution (the view's
  /// window of it can be drawn at full resolution: GridSourceGL::chooseDetail); null otherwise.
  const std::shared_ptr<const volume::GridVolume>& unreducedGrid() const { return unreduced_; }

  /// What an upload needs, computed on the CPU (no GL call: a worker thread may make it,
  /// engine::ScenePrefetcher): the grid's copy and sampler, the texels, lookup tables and
  /// empty-space grid.
  struct Prepared {
    std::shared_ptr<const volume::GridVolume> grid;
    std::shared_ptr<const volume::GridSampler> sampler;  ///< over *grid
    glm::dvec3 origin{0.0};
    glm::ivec3 textureSize{1};
    int rowOffset = 0;
    glm::vec2 lonRange{0.0f}, latRange{0.0f};
    glm::ivec2 lookupSize{1};       ///< the tables' size; the texture has one row more (the level map)
    std::vector<glm::vec2> texels;  ///< RG32F: value (or the missing mark), height; then the level slices
    int levelSlices = 0;            ///< slices after the levels holding the level brackets, 4 bins each
    std::vector<float> lookup;      ///< R32F rows (rectilinear, reduced) or RG32F pairs (curvilinear), then
                                    ///< the level map row (reference level at equal height steps)
    glm::vec4 levelMap{0.0f};       ///< lowest height, entries - 1 per metre, binsPerLevel, bins
    volume::OccupancyGrid occupancy;
    std::uint64_t bytes() const;  ///< what it holds (the memory budget)
  };
  /// A drawable grid (at least 2 x 2 x 2), else the error create() gives.
  static Status checkDrawable(const volume::GridVolume& grid);
  /// The CPU part of create (call checkDrawable first). Any thread.
  static std::shared_ptr<const Prepared> prepare(const volume::GridVolume& grid);
  /// The GL part (GL thread), with create's lower-resolution fallback.
  static Result<std::unique_ptr<GridVolumeGL>> create(std::shared_ptr<const Prepared> prepared);
  ~GridVolumeGL() override;

  const volume::GridVolume& grid() const { return *grid_; }
  std::string_view samplerShaderFile() const override { return "sample_grid.glsl"; }
  std::vector<std::string> samplerDefines(const VolumeRenderOptions& options) const override;
  glm::dvec3 originEcef() const override { return origin_; }
  void setSamplerUniforms(const SamplerBindingGL& binding) const override;
  void bindSamplerTextures(const SamplerBindingGL& binding, const VolumeRenderOptions& options) const override;
  volume::ValueRange valueRange() const override { return sampler_->valueRange(); }
  std::size_t gpuBytes() const override { return gpuBytes_ + occupancy_.gpuBytes(); }
  std::string description() const override { return sampler_->description(); }
  const volume::VolumeSampler& referenceSampler() const override { return *sampler_; }

 private:
  GridVolumeGL() = default;
  /// One try at the prepared resolution; `tooLarge` says why when the GPU cannot hold it.
  static Result<std::unique_ptr<GridVolumeGL>> upload(const std::shared_ptr<const Prepared>& prepared,
                                                      const std::string& name, std::string* tooLarge);
  std::shared_ptr<const volume::GridVolume> grid_;
  std::shared_ptr<const volume::GridVolume> unreduced_;  ///< see unreducedGrid()
  std::shared_ptr<const volume::GridSampler> sampler_;
  glm::dvec3 origin_{0.0};
  unsigned int values_ = 0, heights_ = 0, lookup_ = 0;  ///< lookup_: 2-D; rectilinear: row 0 longitude, row 1 latitude
  glm::ivec3 textureSize_{1};                           ///< columns, rows, levels of values_/heights_
  int rowOffset_ = 0;                                   ///< 1 when the grid has pole rows
  glm::vec2 lonRange_{0.0f}, latRange_{0.0f};           ///< the lookup tables' domains (deg)
  glm::ivec2 lookupSize_{1};
  int levelSlices_ = 0;
  glm::vec4 levelMap_{0.0f};
  std::size_t gpuBytes_ = 0;
};

}  // namespace atmoglobe::engine
