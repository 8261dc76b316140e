#pragma once
// A radar volume on the GPU in its own polar geometry (no Cartesian resampling): the sweeps as
// texture layers in their native (ray, gate) layout, per-sweep azimuth tables, and the
// empty-space grid; drawn by VolumeRendererGL through shaders/sample_polar.glsl. The sampling
// rule is that of volume/PolarVolume.h, the same as the CPU reference (volume::PolarSampler).
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace atmoglobe::engine {

class RadarVolumeGL final : public VolumeGL {
 public:
  /// `exaggeration`: the scene's vertical exaggeration (volume/VerticalExaggeration.h; 1 = none).
  /// A volume whose values texture the GPU cannot hold (GL_MAX_TEXTURE_SIZE, GL_OUT_OF_MEMORY, or
  /// the limit textureByteLimit() sets) is uploaded with every 2nd gate (volume::decimatePolar;
  /// up to kMaxHalvings times) and a warning line on stderr.
  static Result<std::unique_ptr<RadarVolumeGL>> create(const volume::PolarVolume& volume, double exaggeration = 1.0);
  static constexpr int kMaxHalvings = 4;

  /// What an upload needs, computed on the CPU (no GL call: a worker thread may make it,
  /// engine::ScenePrefetcher): the volume's copy, its samplers, the half-float layers, the
  /// azimuth and elevation tables, the empty-space grid.
  struct Prepared {
    std::shared_ptr<const volume::PolarVolume> polar;
    std::shared_ptr<const volume::PolarSampler> sampler;            ///< over *polar
    std::shared_ptr<const volume::ExaggeratedSampler> exaggerated;  ///< over *sampler, when exaggeration != 1
    double exaggeration = 1.0;
    volume::LocalSphereBeam beamModel;
    glm::ivec2 valuesSize{1};           ///< gates + 1, rays + 1
    std::vector<std::uint32_t> layers;  ///< RG16F texels, sweep after sweep
    std::vector<float> table;           ///< azimuth tables, then the elevation lookup
    glm::vec2 elLookupRange{0.0f, 1.0f};
    volume::OccupancyGrid occupancy;
    std::uint64_t bytes() const;  ///< what it holds (the memory budget)
  };
  /// 1..kMaxSweeps sweeps, else the error create() gives.
  static Status checkDrawable(const volume::PolarVolume& volume);
  /// The CPU part of create (call checkDrawable first). Any thread.
  static std::shared_ptr<const Prepared> prepare(const volume::PolarVolume& volume, double exaggeration = 1.0);
  /// The GL part (GL thread), with create's lower-resolution fallback.
  static Result<std::unique_ptr<RadarVolumeGL>> create(std::shared_ptr<const Prepared> prepared);
  ~RadarVolumeGL() override;
  RadarVolumeGL(const RadarVolumeGL&) = delete;
  RadarVolumeGL& operator=(const RadarVolumeGL&) = delete;

  const volume::PolarVolume& polar() const { return *polar_; }
  BeamApproximation beamApproximation() const { return beam_; }
  void setBeamApproximation(BeamApproximation beam) {
    if (beam != beam_) uniformsChanged();  // the straight-line elevation band is a uniform
    beam_ = beam;
  }

  std::string_view samplerShaderFile() const override { return "sample_polar.glsl"; }
  std::vector<std::string> samplerDefines(const VolumeRenderOptions& options) const override;
  glm::dvec3 originEcef() const override { return beamModel_.antennaEcef; }
  void setSamplerUniforms(const SamplerBindingGL& binding) const override;
  void bindSamplerTextures(const SamplerBindingGL& binding, const VolumeRenderOptions& options) const override;
  volume::ValueRange valueRange() const override { return {polar_->minValue, polar_->maxValue}; }
  std::size_t gpuBytes() const override { return gpuBytes_ + occupancy_.gpuBytes(); }
  std::string description() const override { return polar_->fieldName + " from " + polar_->sourcePath; }
  const volume::VolumeSampler& referenceSampler() const override {
    return exaggerated_ ? static_cast<const volume::VolumeSampler&>(*exaggerated_) : *sampler_;
  }
  double exaggeration() const { return exaggeration_; }

 private:
  RadarVolumeGL() = default;
  /// One try at the prepared resolution; null on GL_OUT_OF_MEMORY.
  static std::unique_ptr<RadarVolumeGL> upload(const std::shared_ptr<const Prepared>& prepared);
  std::shared_ptr<const volume::PolarVolume> polar_;
  std::shared_ptr<const volume::PolarSampler> sampler_;  ///< over *polar_
  double exaggeration_ = 1.0;
  std::shared_ptr<const volume::ExaggeratedSampler> exaggerated_;  ///< over *sampler_ when exaggeration_ != 1
  volume::LocalSphereBeam beamModel_;
  BeamApproximation beam_ = BeamApproximation::EffectiveEarthLocalSphere;
  unsigned int values_ = 0, rayTable_ = 0;  ///< rayTable_: azimuth tables, then the elevation lookup as one more layer
  glm::vec2 valuesSize_{1.0f};              ///< texels per layer (gates + 1, rays + 1)
  glm::vec2 elLookupRange_{0.0f, 1.0f};
  std::size_t gpuBytes_ = 0;
};

}  // namespace atmoglobe::engine
