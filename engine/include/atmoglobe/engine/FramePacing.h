#pragma once
// The viewer's frame pacing while the camera moves, and a summary of its frame times; GL-free.
//
// While the camera moves the volumes are marched at a reduced image scale. A fixed quarter
// scale is not enough everywhere (a global grid from space: 155 ms a frame on llvmpipe), so the
// scale follows the frames: after each moving frame of t ms against a target T,
//   t > T:        scale x max(0.5, sqrt(T / t))   (a volume's cost goes with its pixels, scale^2)
//   t < 0.7 T:    scale x min(1.25, sqrt(0.85 T / t))
// clamped to [kMinScale, kMaxScale] and rounded down to 1/64 (a new size reallocates the volume
// image; a frame over the target always lowers the scale by at least 1/64). The time that does not shrink with the
// scale (globe, map lines, markers) makes a step fall short of the target, so the scale converges over a few frames
// rather than in one.
#include <cstddef>
#include <string>
#include <vector>

namespace atmoglobe::engine {

class MovingImageScale {
 public:
  static constexpr double kMaxScale = 0.25;    ///< the quarter scale of a cheap scene
  static constexpr double kMinScale = 0.0625;  ///< 80 x 45 volume pixels at 1280 x 720
  static constexpr double kTargetMs = 40.0;    ///< the scene's draw; 50 ms is 20 frames a second

  explicit MovingImageScale(double targetMs = kTargetMs) : targetMs_(targetMs) {}
  /// The image scale for the next moving frame.
  double scale() const { return scale_; }
  /// A moving frame drawn at scale() took `sceneMs`.
  void reportMovingFrame(double sceneMs);
  /// Before the first moving frame of a motion: the full-quality march of the view at rest costs
  /// `fullMarchMs` (VolumeRendererGL::fullMarchEstimateMs, scale 1). The scale becomes sqrt((T - F) / fullMarchMs),
  /// F = kFixedMsEstimate for the globe and map lines (at least T / 4 left to the march), clamped
  /// and rounded down to 1/64 as above, so that the first frame is near the target instead of
  /// being drawn at the scale of the last motion. Ignored when fullMarchMs is not positive.
  void seedFromFullMarch(double fullMarchMs);
  static constexpr double kFixedMsEstimate = 20.0;  ///< globe and map lines at 1280x720 on llvmpipe

 private:
  double targetMs_;
  double scale_ = kMaxScale;
};

/// Frame times of a viewer run, moving and at rest apart: count, median, 90th percentile, max.
class FrameTimeSummary {
 public:
  void add(bool moving, double sceneMs) { (moving ? moving_ : rest_).push_back(sceneMs); }
  /// "moving: N frames, median X ms (p90 Y, max Z); at rest: ..." (a part is left out when it has
  /// no frames; empty when neither has).
  std::string text() const;

 private:
  std::vector<double> moving_, rest_;
};

}  // namespace atmoglobe::engine
