#pragma once
// Animated output of a time series (render --time-series --animation), GL-free.
//
// GIF through giflib (Debian libgif-dev): each frame quantised to its own 256-colour local
// palette: giflib's median cut (GifQuantizeBuffer) as the start, two Lloyd (k-means) iterations
// over the frame's distinct colours, then every pixel the palette entry NEAREST its colour (so
// a pixel's error is exactly its distance to the palette); no dithering (dither noise would
// flicker from frame to frame),
// a graphics-control block with the frame delay, and the NETSCAPE2.0 extension for looping.
// Written to a temporary beside the target and renamed when complete (volume/AtomicFile.h).
//
// MP4 through ffmpeg when it is on PATH (Debian `ffmpeg`, H.264 via libx264, yuv420p so every
// player plays it): run with posix_spawnp and an argv array (no shell), reading the PNG frames
// the series wrote; absent ffmpeg is an error saying so, which the caller reports as a skip.
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/Result.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

class GifAnimationWriter {
 public:
  /// Starts `path` (a temporary beside it until finish()). delayMs: the time each frame shows
  /// (GIF stores hundredths of a second: rounded, at least 1). loopCount 0: loop forever.
  static Result<std::unique_ptr<GifAnimationWriter>> create(const std::string& path, int widthPx, int heightPx,
                                                            int delayMs, int loopCount = 0);
  /// Appends a frame of the size given to create() (alpha ignored: GIF frames are opaque here).
  Status addFrame(const globe::ImageRGBA8& frame);
  /// Closes the file and renames it into place. Without finish() the temporary is removed.
  Status finish();
  std::size_t frames() const { return frames_; }
  ~GifAnimationWriter();

 private:
  GifAnimationWriter() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_, tempPath_;
  int width_ = 0, height_ = 0, delayCs_ = 1;
  std::size_t frames_ = 0;
};

/// The frames of a GIF file as RGBA images (each frame composited onto the logical screen as
/// giflib decodes it; frames here always cover the whole screen). Errors name the file.
Result<std::vector<globe::ImageRGBA8>> readGifFrames(const std::string& path);

/// The ffmpeg executable on PATH, or "" when there is none.
std::string findFfmpeg();

/// Encodes `framePattern` (printf-style, e.g. "out/loop_%03d.png", frames from 0) into an MP4
/// (H.264, yuv420p, frame size padded to even) at `framesPerSecond`, written atomically to
/// `path`. Errors: no ffmpeg on PATH ("ffmpeg not found on PATH (Debian package ffmpeg)"),
/// ffmpeg failing (its exit status; its own messages go to stderr).
Status encodeMp4(const std::string& framePattern, double framesPerSecond, const std::string& path);

}  // namespace atmoglobe::engine
