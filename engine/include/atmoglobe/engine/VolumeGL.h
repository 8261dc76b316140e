#pragma once
// A volume on the GPU, whatever its kind: the interface the ray marcher (VolumeRendererGL.h)
// draws through, and the constants C++ and GLSL share.
//
// Adding a kind of volume to the renderer takes three pieces (volume/README.md):
//  1. a volume::VolumeSampler (GL-free, double: the CPU reference draws it);
//  2. a VolumeGL subclass here: its textures, its uniforms, its empty-space grid;
//  3. a GLSL sampler file shaders/sample_KIND.glsl defining, with the prefix VOL_,
//       vec2 VOL_interval(vec3 eyeRel, vec3 dir, float tMax)  where along the ray data can be (t >= 0, <= tMax)
//       int  VOL_sample(vec3 p, out float value)             STATE_ECHO with the value, or STATE_NOT_ECHO
//       vec3 VOL_debugCoordinates(vec3 p)                    the kind's own coordinates of p (tests)
//     where positions are float32 relative to originEcef() (subtracted in double).
// The marcher includes the file once per volume with VOL_ replaced by that volume's prefix.
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/engine/VolumeLayer.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/OccupancyGrid.h>
#include <atmoglobe/volume/VolumeRenderSettings.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace atmoglobe::engine {

/// Constants shared by C++ and the march shaders, injected as #defines (marchShaderDefines).
struct MarchConstants {
  static constexpr int kTransferEntries = 4096;  ///< TRANSFER_ENTRIES: transfer table entries per volume
  static constexpr int kMaxVolumes = 8;          ///< MAX_VOLUMES: volumes in one march (texture units: 3 + 3 each)
  static constexpr int kStateNotEcho = 0;        ///< STATE_NOT_ECHO: no echo or no data (drawn alike)
  static constexpr int kStateEcho = 1;           ///< STATE_ECHO
  static constexpr int kGridBlock = volume::OccupancyGrid::kBlock;  ///< GRID_BLOCK
  static constexpr int kMaxSweeps = 32;                             ///< MAX_SWEEPS: radar sweeps per volume
  static constexpr int kRayTableBins = 8192;   ///< RAY_TABLE_BINS: azimuth table resolution (360 / 8192 deg)
  static constexpr int kElevationBins = 2048;  ///< ELEVATION_BINS: elevation -> sweep lookup
  /// GPU_NO_DATA: the value of a data texel without an echo value (no data or no echo; what the
  /// reader's NaN and -inf become on the GPU: shaders/README.md, "No data and no echo").
  static constexpr float kNoData = -1.0e38f;
  /// GPU_NO_DATA_BELOW: a value below it is GPU_NO_DATA (far below every measured value and far
  /// above GPU_NO_DATA, so the test needs no float equality).
  static constexpr float kNoDataBelow = -1.0e37f;
};
/// The define entries of MarchConstants, and of the ellipsoid (ShaderConstants.h), for the march.
std::vector<std::string> marchShaderDefines();

/// The generic knobs of one volume layer (a kind's own knobs live on its VolumeGL).
struct VolumeRenderOptions {
  volume::VolumeRenderSettings render;  ///< mode, interpolation, step, transfer, iso, termination
  double imageScale = 1.0;              ///< volume image resolution relative to the frame (0.05..1)
  /// With imageScale < 1, adaptive refinement (docs/volume-rendering.md, "Adaptive refinement"):
  /// the image is marched at imageScale, then every frame pixel whose four nearest small-image
  /// pixels differ by more than this many 8-bit steps (1/255 of premultiplied RGBA, any channel),
  /// or straddle the edge of the globe, is marched again at full resolution; the others take the
  /// small image's bilinear value. < 0: off (the small image upsampled everywhere).
  double refineThreshold = -1.0;
  bool skipEmptySpace = true;  ///< jump over cells of the empty-space grid that cannot contribute
  Classification classification = Classification::Point;  ///< DVR only
  /// DVR of a volume with a far-field extent (VolumeGL::farFieldExtent): drawn from its far field
  /// where every pixel over it is wide enough (FarFieldGL.h).
  FarField farField = FarField::Off;
};

/// Where a volume's data can be, for its far field (FarFieldGL.h): a latitude/longitude box and
/// the height above the ellipsoid above which it has none.
struct FarFieldExtent {
  double southDeg = 0.0, northDeg = 0.0;
  double westDeg = 0.0, eastDeg = 0.0;  ///< east > west; east - west <= 360
  double topMeters = 0.0;
};

/// Uniform locations of one program, looked up once per name and kept.
class UniformCacheGL {
 public:
  explicit UniformCacheGL(unsigned int program = 0) : program_(program) {}
  int operator()(const std::string& name);

 private:
  unsigned int program_ = 0;
  std::unordered_map<std::string, int> locations_;
};

/// Where a volume's sampler binds: its uniforms' prefix, its first texture unit.
struct SamplerBindingGL {
  UniformCacheGL* uniforms = nullptr;
  std::string prefix;  ///< "v0_", "v1_", ...
  int firstUnit = 0;
  unsigned int nearestSampler = 0;  ///< a sampler object with nearest filtering, clamp to edge
  int slot = 0;                     ///< the volume's index in the march (VOL_INDEX): its buffer binding point
};

/// An empty-space grid on the GPU: one R16F 3-D texture, the cells (z < cells.z) and above them
/// the blocks (z >= cells.z, x < blocks.x, y < blocks.y). Values rounded up to half floats, so
/// the grid stays conservative.
class OccupancyGridGL {
 public:
  OccupancyGridGL() = default;
  explicit OccupancyGridGL(volume::OccupancyGrid grid);
  ~OccupancyGridGL();
  OccupancyGridGL(OccupancyGridGL&& other) noexcept;
  OccupancyGridGL& operator=(OccupancyGridGL&& other) noexcept;
  unsigned int texture() const { return texture_; }
  const volume::OccupancyGrid& grid() const { return grid_; }
  /// A copy, its texture copied on the GPU (glCopyImageSubData). Error: the copy failed.
  Result<OccupancyGridGL> copyGL() const;
  /// The cells of each range computed again from that range's sources
  /// (volume::rebuildOccupancyCells), and only those cells and the blocks over them uploaded.
  void rebuildCells(const std::vector<volume::OccupancyCellRange>& ranges,
                    const std::vector<std::vector<std::span<const volume::OccupancyBox>>>& sources);
  std::size_t gpuBytes() const { return gpuBytes_; }

 private:
  volume::OccupancyGrid grid_;
  unsigned int texture_ = 0;
  std::size_t gpuBytes_ = 0;
};

class VolumeGL {
 public:
  VolumeGL();
  virtual ~VolumeGL() = default;
  VolumeGL(const VolumeGL&) = delete;
  VolumeGL& operator=(const VolumeGL&) = delete;
  /// The kind's GLSL sampler file (shaders/sample_KIND.glsl).
  virtual std::string_view samplerShaderFile() const = 0;
  /// Compile-time constants of this volume's sampler for these options ("NAME VALUE", without
  /// the prefix); part of the program variant.
  virtual std::vector<std::string> samplerDefines(const VolumeRenderOptions& options) const = 0;
  /// The double-precision origin the sampler's float positions are relative to.
  virtual glm::dvec3 originEcef() const = 0;
  /// Sets the sampler's own uniforms (its geometry and its texture units, from
  /// binding.firstUnit on). The renderer calls it only when a program's volume slot held another
  /// volume or this volume's uniformVersion() changed, so a static scene sets them once.
  virtual void setSamplerUniforms(const SamplerBindingGL& binding) const = 0;
  /// Binds its textures (and sampler objects) from binding.firstUnit on, every draw (texture
  /// units are shared by every program); at most kSamplerUnits.
  virtual void bindSamplerTextures(const SamplerBindingGL& binding, const VolumeRenderOptions& options) const = 0;
  static constexpr int kSamplerUnits = 2;
  /// Unique for the life of the process (a new volume at a freed address is a new id).
  std::uint64_t id() const { return id_; }
  /// Changes whenever what setSamplerUniforms sets changes.
  std::uint64_t uniformVersion() const { return uniformVersion_; }
  virtual volume::ValueRange valueRange() const = 0;
  /// GPU bytes of all its textures, the empty-space grid included.
  virtual std::size_t gpuBytes() const = 0;
  virtual std::string description() const = 0;
  /// The kind's double-precision CPU sampler of the same data (the reference renderer draws
  /// the volume through it: `render --reference`, tests). Lives as long as this volume.
  virtual const volume::VolumeSampler& referenceSampler() const = 0;
  const OccupancyGridGL& occupancy() const { return occupancy_; }
  /// Where its data can be, for a far field (FarFieldGL.h); none: the kind has no far field.
  virtual std::optional<FarFieldExtent> farFieldExtent() const { return std::nullopt; }

 protected:
  void uniformsChanged() { ++uniformVersion_; }
  OccupancyGridGL occupancy_;

 private:
  std::uint64_t id_ = 0;
  std::uint64_t uniformVersion_ = 0;
};

/// An artificial GPU memory limit for one volume texture (bytes), from the environment variable
/// ATMOGLOBE_MAX_TEXTURE_BYTES (0: none): a texture larger than it is treated as
/// GL_OUT_OF_MEMORY (tests of the lower-resolution fallback; llvmpipe does not run out).
std::size_t textureByteLimit();
/// Clears pending GL errors; then outOfMemoryGL() says whether GL_OUT_OF_MEMORY came since.
void clearErrorsGL();
bool outOfMemoryGL();
/// "12.3 MB" (10^6 bytes), for messages.
std::string megabytes(std::size_t bytes);

/// GL texture of `target` (GL_TEXTURE_2D, GL_TEXTURE_3D, ...) with nearest filtering, or the given
/// `filter` (GL_LINEAR), and clamp-to-edge wrapping (a helper for VolumeGL kinds).
unsigned int makeVolumeTextureGL(unsigned int target);
unsigned int makeVolumeTextureGL(unsigned int target, int filter);

}  // namespace atmoglobe::engine
