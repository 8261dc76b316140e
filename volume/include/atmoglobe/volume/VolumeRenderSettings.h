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
  double stepMeters = 250.0;  ///< sample spacing along the ray (m), > 0
  /// > 0: the step follows the cells (StepRule.h): about this many samples per cell crossed,
  /// never more than at stepMeters; 0: the fixed step. Each layer's own where layers are marched
  /// together (a sample's step is the smallest any of them asks for there).
  double samplesPerCell = 0.0;
  TransferFunction transfer;            ///< DVR colour/opacity; MIP and ISO colours
  double isoValue = 40.0;               ///< ISO threshold (field units)
  double earlyTerminationAlpha = 0.99;  ///< DVR stops once accumulated alpha >= this (> 1: never)
};

}  // namespace atmoglobe::volume
