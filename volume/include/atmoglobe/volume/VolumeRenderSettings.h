#pragma once
// What the volume renderers (the CPU reference and the GPU marcher) are told to draw, shared by
// every kind of volume. GL-free.
#include <atmoglobe/volume/TransferFunction.h>
#include <atmoglobe/volume/VolumeSampler.h>

namespace atmoglobe::volume {

enum class VolumeRenderMode { Dvr, Mip, Iso };

/// Settings of one volume layer. When several volumes are marched together (ReferenceRenderer.h,
/// "Several volumes"), mode, stepMeters and earlyTerminationAlpha are those of the first layer
/// and must be equal in all (the scene groups layers so); transfer, interpolation and isoValue
/// are per layer.
struct VolumeRenderSettings {
  VolumeRenderMode mode = VolumeRenderMode::Dvr;
  Interpolation interpolation = Interpolation::Linear;
  double stepMeters = 250.0;            ///< sample spacing along the ray (m), > 0
  TransferFunction transfer;            ///< DVR colour/opacity; MIP and ISO colours
  double isoValue = 40.0;               ///< ISO threshold (field units)
  double earlyTerminationAlpha = 0.99;  ///< DVR stops once accumulated alpha >= this (> 1: never)
};

}  // namespace atmoglobe::volume
