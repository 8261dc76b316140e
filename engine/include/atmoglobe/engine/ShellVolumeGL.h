#pragma once
// The analytic uniform shell (volume/AnalyticVolume.h) on the GPU: no textures, three uniforms,
// shaders/sample_shell.glsl. A second kind beside radar volumes, drawn by the same marcher; its
// closed-form optical depth checks the GPU path and the CPU reference (tests).
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/volume/AnalyticVolume.h>

#include <memory>

namespace atmoglobe::engine {

class ShellVolumeGL final : public VolumeGL {
 public:
  explicit ShellVolumeGL(const volume::UniformShell& shell);
  const volume::UniformShell& shell() const { return shell_; }
  std::string_view samplerShaderFile() const override { return "sample_shell.glsl"; }
  std::vector<std::string> samplerDefines(const VolumeRenderOptions&) const override { return {}; }
  glm::dvec3 originEcef() const override { return centreEcef_; }
  void setSamplerUniforms(const SamplerBindingGL& binding) const override;
  void bindSamplerTextures(const SamplerBindingGL&, const VolumeRenderOptions&) const override {}
  volume::ValueRange valueRange() const override { return {shell_.value, shell_.value}; }
  std::size_t gpuBytes() const override { return occupancy_.gpuBytes(); }
  std::string description() const override;
  const volume::VolumeSampler& referenceSampler() const override { return sampler_; }

 private:
  volume::UniformShell shell_;
  glm::dvec3 centreEcef_{0.0};
  volume::UniformShellSampler sampler_;
};

}  // namespace atmoglobe::engine
