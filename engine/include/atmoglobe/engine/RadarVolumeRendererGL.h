#pragma once
// Radar volumes ray-marched on the GPU in their own polar geometry (no Cartesian
// resampling): RadarVolumeGL holds the sweeps as texture layers in their native
// (ray, gate) layout; RadarVolumeRendererGL marches them (shaders/radar_march.frag) into a
// volume image, optionally at a lower resolution, and lays it over the globe. The sampling
// rule and transfer function are those of volume/PolarVolume.h and TransferFunction.h, the
// same as the CPU reference renderer (volume/ReferenceRenderer.h).
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <epoxy/gl.h>

#include <map>
#include <memory>

namespace atmoglobe::engine {

/// How the marcher maps a point to antenna coordinates.
enum class BeamApproximation {
  /// The effective-Earth model (ke, R from the volume's BeamModel) on a local sphere whose
  /// radius is the ellipsoid's normal-section radius in the sample's azimuth; float32.
  /// Its error against the exact inverse is measured by RadarMarchTest.
  EffectiveEarthLocalSphere,
  /// Straight lines from the antenna, no Earth curvature, no refraction (what several open
  /// 3-D radar viewers do); for comparison only.
  StraightLine,
};

/// How DVR classifies the field between samples.
enum class Classification {
  Point,          ///< each sample alone, over one step (post-classification; what the reference does at 100 m)
  Preintegrated,  ///< neighbouring samples as a linear segment, integrated exactly in opacity (volume::transferIntegralTable)
};

struct RadarRenderOptions {
  volume::VolumeRenderSettings render;  ///< mode, interpolation, step, transfer, iso, termination
  double imageScale = 1.0;              ///< volume image resolution relative to the frame (0.1..1)
  BeamApproximation beam = BeamApproximation::EffectiveEarthLocalSphere;
  bool skipEmptySpace = true;           ///< jump over cells of the ENU max grid that cannot contribute
  Classification classification = Classification::Point;  ///< DVR only
};

/// The reference renderer's camera for an engine camera (same convention, plain data).
volume::RenderCamera referenceCameraFor(const Camera& camera);

/// The GPU copy of one PolarVolume.
class RadarVolumeGL {
 public:
  static Result<std::unique_ptr<RadarVolumeGL>> create(const volume::PolarVolume& volume);
  ~RadarVolumeGL();
  RadarVolumeGL(const RadarVolumeGL&) = delete;
  RadarVolumeGL& operator=(const RadarVolumeGL&) = delete;

  const volume::PolarVolume& polar() const { return *polar_; }
  /// GPU bytes of all textures (values, azimuth tables, elevation lookup, empty-space grid).
  std::size_t gpuBytes() const { return gpuBytes_; }

  /// Azimuth table resolution (360 / 8192 = 0.044 deg); must match RAY_TABLE_BINS in radar_march.frag.
  static constexpr int kRayTableBins = 8192;
  static constexpr int kElevationBins = 2048;  ///< must match ELEVATION_BINS in radar_march.frag
  static constexpr int kMaxSweeps = 32;
  static constexpr int kGridBlock = 8;  ///< must match GRID_BLOCK in radar_march.frag

 private:
  friend class RadarVolumeRendererGL;
  RadarVolumeGL() = default;
  std::shared_ptr<const volume::PolarVolume> polar_;
  GLuint values_ = 0, rayTable_ = 0, coarse_ = 0;  // coarse_: the empty-space grid
  GLuint blocks_ = 0;                               ///< its max over kGridBlock^3 cells
  glm::vec2 valuesSize_{1.0f};                    ///< texels per layer (gates + 1, rays + 1)
  GLuint elLookup_ = 0;
  glm::vec2 elLookupRange_{0.0f, 1.0f};
  glm::vec3 gridMinEnu_{0.0f}, gridCellSize_{1.0f};  ///< empty-space grid in the site's ENU frame (m)
  glm::ivec3 gridCells_{1};
  std::size_t gpuBytes_ = 0;
};

class RadarVolumeRendererGL {
 public:
  static Result<std::unique_ptr<RadarVolumeRendererGL>> create();
  ~RadarVolumeRendererGL();

  /// Marches `volume` for `camera` into an internal RGBA16F image at options.imageScale,
  /// occluded by `globeDepthTexture` (reverse-Z depth of the frame), and blends it
  /// (premultiplied) into `target`. Leaves `target` bound.
  void draw(const Camera& camera, const RadarVolumeGL& volume, const RadarRenderOptions& options,
            const FramebufferGL& target);

  /// Debug/measurement: for each pixel, the antenna coordinates (range m, azimuth deg,
  /// elevation deg) the shader computes for the point at distance tMeters along the pixel's
  /// ray. RGBA32F read back, row 0 = top.
  std::vector<glm::vec4> antennaCoordinatesAt(const Camera& camera, const RadarVolumeGL& volume,
                                              BeamApproximation beam, double tMeters);

  /// The last volume image (premultiplied RGBA, float), row 0 = top.
  std::vector<glm::vec4> readVolumeImage() const;

  /// The march program specialised for mode (0 DVR, 1 MIP, 2 iso, 3 debug), interpolation
  /// (0 nearest, 1 linear), beam (0 4/3-Earth, 1 straight), empty-space skipping (0/1) and,
  /// for DVR, classification (0 point, 1 pre-integrated): compiled on first use and kept. Null
  /// with the compile log on stderr (once) if it fails.
  const ShaderProgramGL* marchProgram(int mode, int interpolation, int beam, int skipEmpty, int preintegrated = 0);

 private:
  RadarVolumeRendererGL() = default;
  /// Binds the march program variant for `options` (or the debug variant when `debugMode`)
  /// and sets its uniforms and textures; false if that variant failed to compile (reported once).
  bool setUniforms(const Camera& camera, const RadarVolumeGL& volume, const RadarRenderOptions& options,
                   GLuint depthTexture, bool debugMode = false);
  void ensureTarget(int widthPx, int heightPx, GLenum format);

  std::map<int, ShaderProgramGL> marchPrograms_;
  std::map<int, std::string> marchErrors_;
  const ShaderProgramGL* march_ = nullptr;  ///< the variant of the current draw
  ShaderProgramGL composite_;
  GLuint vao_ = 0;
  GLuint transfer_ = 0;
  GLuint transferIntegral_ = 0;  ///< pre-integrated DVR: volume::transferIntegralTable, linear filter
  GLuint nearestSampler_ = 0;  ///< for the values texture with --interpolation nearest (its own filter is linear)
  std::unique_ptr<FramebufferGL> volumeTarget_;
  GLenum volumeFormat_ = 0;
  GLuint emptyDepth_ = 0;
};

}  // namespace atmoglobe::engine
