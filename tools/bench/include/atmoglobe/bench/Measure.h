#pragma once
// Measuring: GPU frame times (median of frames ended by glFinish) and the error of an image
// against the CPU reference (volume::compareImages on 8-bit steps).
#include <atmoglobe/bench/Cells.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/VolumeImage.h>

#include <vector>

namespace atmoglobe::bench {

/// Median (mean of the two middle values for an even count); NaN for none.
double median(std::vector<double> v);

struct GpuRun {
  double medianMs = 0.0;
  globe::ImageRGBA8 image;  ///< the composited frame (what the user sees), over black
};

/// Draws `volume` alone over black into `target` (the globe is not drawn: empty depth, so
/// nothing occludes the volume, as in the reference with occlusion off) with the beam
/// approximation `beam`; one untimed warm-up frame when `warmUp`, then `frames` timed frames,
/// each ended by glFinish. The image is the last frame's composite: for imageScale < 1 that is
/// the marcher's small image upsampled bilinearly by the composite pass, exactly what a user sees.
/// `beam` applies to radar volumes only. `depth` (GL rows, bottom first; ellipsoidDepth), when
/// given, is written into the target's depth before each frame, outside the timed part, instead
/// of clearing it: the globe's depth without drawing the globe.
GpuRun timeFramesGL(engine::VolumeRendererGL& renderer, const engine::Camera& camera, engine::VolumeGL& volume,
                    const engine::VolumeRenderOptions& options, engine::BeamApproximation beam,
                    engine::FramebufferGL& target, int frames, bool warmUp = true,
                    const std::vector<float>* depth = nullptr);

/// The median time (ms) of `frames` frames of `layers` drawn together over black into `target`,
/// each ended by glFinish, after one untimed warm-up frame (programs, transfer rows): the
/// stand-alone benches of several volumes (bench_volume_overlap, bench_radar_network). `depth`
/// (GL rows, bottom first; ellipsoidDepth), when given, is put into the target's depth before each
/// frame, untimed, so that the rays end at the ground as the globe would end them.
double timeLayersGL(engine::VolumeRendererGL& renderer, const engine::Camera& camera,
                    const std::vector<engine::VolumeLayerGL>& layers, const engine::FramebufferGL& target, int frames,
                    const std::vector<float>* depth = nullptr);
/// Puts `depth` (GL rows, bottom first) into the target's depth.
void uploadDepthGL(const engine::FramebufferGL& target, const std::vector<float>& depth);
/// Binds `target` and clears its colour to opaque black and, without `depth` (already uploaded),
/// its depth to the far plane: the start of a frame of timeLayersGL.
void clearTargetGL(const engine::FramebufferGL& target, const std::vector<float>* depth = nullptr);
/// timeFramesGL for every cell, frames taken round-robin over the cells (frame 1 of every
/// cell, then frame 2, ...) after one untimed round: a slow spell of a shared machine then
/// lands on every cell alike instead of on whichever cells it happened to overlap (in per-cell
/// runs one cell's median came out 2x its neighbours' now and then). Per cell: the median and
/// the last frame.
/// `transfer`: what the cells draw with (optionsFor's default reflectivity table when null).
std::vector<GpuRun> timeCellsRoundRobinGL(engine::VolumeRendererGL& renderer, const engine::Camera& camera,
                                          engine::VolumeGL& volume, const std::vector<Cell>& cells,
                                          engine::FramebufferGL& target, int frames,
                                          const std::vector<float>* depth = nullptr,
                                          const volume::TransferFunction* transfer = nullptr);

/// 8-bit RGBA (premultiplied, as read back) -> the reference's double image, / 255.
volume::VolumeImage fromRgba8(const globe::ImageRGBA8& img);
/// The reference's image over black, rounded to 8 bits, opaque (for PNGs).
globe::ImageRGBA8 toRgba8(const volume::VolumeImage& img);

}  // namespace atmoglobe::bench
