#include <atmoglobe/engine/AnimationWriter.h>

#include <atmoglobe/volume/AtomicFile.h>

#include <gif_lib.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <unordered_map>

extern char** environ;

namespace atmoglobe::engine {

namespace {
std::string gifError(int code) {
  const char* s = GifErrorString(code);
  return s ? s : "giflib error " + std::to_string(code);
}
}  // namespace

struct GifAnimationWriter::Impl {
  GifFileType* gif = nullptr;
};

Result<std::unique_ptr<GifAnimationWriter>> GifAnimationWriter::create(const std::string& path, int widthPx,
                                                                       int heightPx, int delayMs, int loopCount) {
  if (widthPx < 1 || heightPx < 1 || widthPx > 65535 || heightPx > 65535)
    return makeError(path + ": a GIF frame must be 1..65535 pixels on each side, got " + std::to_string(widthPx) + "x" +
                     std::to_string(heightPx));
  if (delayMs < 0 || loopCount < 0 || loopCount > 65535)
    return makeError(path + ": GIF delay must be >= 0 ms and loop count 0..65535");
  auto temp = volume::temporaryPathBeside(path);
  if (!temp) return temp.forwardError();
  std::unique_ptr<GifAnimationWriter> w(new GifAnimationWriter());
  w->impl_ = std::make_unique<Impl>();
  w->path_ = path;
  w->tempPath_ = *temp;
  w->width_ = widthPx;
  w->height_ = heightPx;
  w->delayCs_ = std::max(1, static_cast<int>(std::lround(delayMs / 10.0)));
  int error = 0;
  w->impl_->gif = EGifOpenFileName(temp->c_str(), true, &error);
  if (!w->impl_->gif) return makeError(path + ": cannot create the GIF: " + gifError(error));
  EGifSetGifVersion(w->impl_->gif, true);  // GIF89a: the delay and loop extensions
  if (EGifPutScreenDesc(w->impl_->gif, widthPx, heightPx, 8, 0, nullptr) == GIF_ERROR)
    return makeError(path + ": " + gifError(w->impl_->gif->Error));
  // NETSCAPE2.0 application extension: sub-block 1, loop count (little-endian; 0 = forever).
  const unsigned char app[] = {'N', 'E', 'T', 'S', 'C', 'A', 'P', 'E', '2', '.', '0'};
  const unsigned char loop[] = {1, static_cast<unsigned char>(loopCount & 0xff),
                                static_cast<unsigned char>((loopCount >> 8) & 0xff)};
  if (EGifPutExtensionLeader(w->impl_->gif, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
      EGifPutExtensionBlock(w->impl_->gif, sizeof app, app) == GIF_ERROR ||
      EGifPutExtensionBlock(w->impl_->gif, sizeof loop, loop) == GIF_ERROR ||
      EGifPutExtensionTrailer(w->impl_->gif) == GIF_ERROR)
    return makeError(path + ": " + gifError(w->impl_->gif->Error));
  return w;
}

Status GifAnimationWriter::addFrame(const globe::ImageRGBA8& frame) {
  if (!impl_->gif) return makeError(path_ + ": the GIF is already finished");
  if (frame.width != width_ || frame.height != height_)
    return makeError(path_ + ": frame " + std::to_string(frames_) + " is " + std::to_string(frame.width) + "x" +
                     std::to_string(frame.height) + ", the animation " + std::to_string(width_) + "x" +
                     std::to_string(height_));
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  std::vector<GifByteType> r(n), g(n), b(n), indices(n);
  for (std::size_t i = 0; i < n; ++i)
    r[i] = frame.pixels[4 * i], g[i] = frame.pixels[4 * i + 1], b[i] = frame.pixels[4 * i + 2];
  ColorMapObject* map = GifMakeMapObject(256, nullptr);
  if (!map) return makeError(path_ + ": out of memory for a colour map");
  int colours = 256;
  if (GifQuantizeBuffer(static_cast<unsigned>(width_), static_cast<unsigned>(height_), &colours, r.data(), g.data(),
                        b.data(), indices.data(), map->Colors) == GIF_ERROR) {
    GifFreeMapObject(map);
    return makeError(path_ + ": frame " + std::to_string(frames_) + ": colour quantisation failed");
  }
  // giflib's median cut gives each colour its box's entry, which is not always the nearest
  // (radar colours next to imagery: errors of 100 levels measured). Refine: two Lloyd (k-means)
  // iterations over the frame's distinct colours, then every colour to its NEAREST entry
  // (squared RGB distance), so each pixel's error is exactly its distance to the palette.
  std::unordered_map<std::uint32_t, std::uint32_t> counts;  // rgb -> pixels
  for (std::size_t i = 0; i < n; ++i) ++counts[std::uint32_t(r[i]) << 16 | std::uint32_t(g[i]) << 8 | b[i]];
  auto nearest = [&](std::uint32_t rgb) {
    const int cr = int(rgb >> 16), cg = int((rgb >> 8) & 0xff), cb = int(rgb & 0xff);
    int best = 0, bestD = 1 << 30;
    for (int k = 0; k < colours; ++k) {
      const int dr = cr - map->Colors[k].Red, dg = cg - map->Colors[k].Green, db = cb - map->Colors[k].Blue;
      const int d = dr * dr + dg * dg + db * db;
      if (d < bestD) bestD = d, best = k;
    }
    return static_cast<GifByteType>(best);
  };
  std::unordered_map<std::uint32_t, GifByteType> assigned;
  for (int iteration = 0; iteration < 3; ++iteration) {
    assigned.clear();
    for (const auto& [rgb, count] : counts) assigned[rgb] = nearest(rgb);
    if (iteration == 2) break;
    std::vector<double> sum(static_cast<std::size_t>(colours) * 4, 0.0);
    for (const auto& [rgb, count] : counts) {
      double* s = &sum[std::size_t{assigned[rgb]} * 4];
      s[0] += double(rgb >> 16) * count, s[1] += double((rgb >> 8) & 0xff) * count, s[2] += double(rgb & 0xff) * count;
      s[3] += count;
    }
    for (int k = 0; k < colours; ++k) {
      const double* s = &sum[static_cast<std::size_t>(k) * 4];
      if (s[3] <= 0.0) continue;  // unused entry: kept
      map->Colors[k].Red = static_cast<GifByteType>(std::lround(s[0] / s[3]));
      map->Colors[k].Green = static_cast<GifByteType>(std::lround(s[1] / s[3]));
      map->Colors[k].Blue = static_cast<GifByteType>(std::lround(s[2] / s[3]));
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    indices[i] = assigned[std::uint32_t(r[i]) << 16 | std::uint32_t(g[i]) << 8 | b[i]];
  GraphicsControlBlock gcb{};
  gcb.DisposalMode = DISPOSE_DO_NOT;
  gcb.UserInputFlag = false;
  gcb.DelayTime = delayCs_;
  gcb.TransparentColor = NO_TRANSPARENT_COLOR;
  GifByteType extension[4];
  const std::size_t len = EGifGCBToExtension(&gcb, extension);
  bool ok = EGifPutExtension(impl_->gif, GRAPHICS_EXT_FUNC_CODE, static_cast<int>(len), extension) != GIF_ERROR &&
            EGifPutImageDesc(impl_->gif, 0, 0, width_, height_, false, map) != GIF_ERROR;
  for (int y = 0; ok && y < height_; ++y)
    ok = EGifPutLine(impl_->gif, indices.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width_),
                     width_) != GIF_ERROR;
  GifFreeMapObject(map);
  if (!ok) return makeError(path_ + ": frame " + std::to_string(frames_) + ": " + gifError(impl_->gif->Error));
  ++frames_;
  return Ok{};
}

Status GifAnimationWriter::finish() {
  if (!impl_->gif) return makeError(path_ + ": the GIF is already finished");
  int error = 0;
  const int st = EGifCloseFile(impl_->gif, &error);
  impl_->gif = nullptr;
  if (st == GIF_ERROR) {
    std::remove(tempPath_.c_str());
    return makeError(path_ + ": closing the GIF: " + gifError(error));
  }
  auto committed = volume::commitTemporary(tempPath_, path_);
  tempPath_.clear();
  return committed;
}

GifAnimationWriter::~GifAnimationWriter() {
  if (impl_ && impl_->gif) {
    int error = 0;
    EGifCloseFile(impl_->gif, &error);
  }
  if (!tempPath_.empty()) std::remove(tempPath_.c_str());
}

Result<std::vector<globe::ImageRGBA8>> readGifFrames(const std::string& path) {
  int error = 0;
  GifFileType* gif = DGifOpenFileName(path.c_str(), &error);
  if (!gif) return makeError(path + ": cannot open the GIF: " + gifError(error));
  if (DGifSlurp(gif) == GIF_ERROR) {
    const std::string message = path + ": not a readable GIF: " + gifError(gif->Error);
    DGifCloseFile(gif, &error);
    return makeError(message);
  }
  std::vector<globe::ImageRGBA8> frames;
  globe::ImageRGBA8 screen = globe::ImageRGBA8::filled(gif->SWidth, gif->SHeight, {0, 0, 0, 255});
  for (int k = 0; k < gif->ImageCount; ++k) {
    const SavedImage& im = gif->SavedImages[k];
    const ColorMapObject* map = im.ImageDesc.ColorMap ? im.ImageDesc.ColorMap : gif->SColorMap;
    const GifImageDesc& d = im.ImageDesc;
    if (!map || d.Left < 0 || d.Top < 0 || d.Left + d.Width > gif->SWidth || d.Top + d.Height > gif->SHeight) {
      DGifCloseFile(gif, &error);
      return makeError(path + ": frame " + std::to_string(k) + " has no colour map or lies outside the screen");
    }
    for (int y = 0; y < d.Height; ++y)
      for (int x = 0; x < d.Width; ++x) {
        const int index = im.RasterBits[static_cast<std::size_t>(y) * static_cast<std::size_t>(d.Width) +
                                        static_cast<std::size_t>(x)];
        if (index >= map->ColorCount) continue;
        const GifColorType c = map->Colors[index];
        screen.set(d.Left + x, d.Top + y, {c.Red, c.Green, c.Blue, 255});
      }
    frames.push_back(screen);
  }
  DGifCloseFile(gif, &error);
  return frames;
}

std::string findFfmpeg() {
  const char* pathEnv = std::getenv("PATH");
  std::stringstream dirs(pathEnv ? pathEnv : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    if (dir.empty()) continue;
    const std::string candidate = dir + "/ffmpeg";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

Status encodeMp4(const std::string& framePattern, double framesPerSecond, const std::string& path) {
  const std::string ffmpeg = findFfmpeg();
  if (ffmpeg.empty()) return makeError(path + ": no MP4 written: ffmpeg not found on PATH (Debian package ffmpeg)");
  if (!(framesPerSecond > 0.0 && framesPerSecond <= 120.0)) return makeError(path + ": frame rate must be in (0, 120]");
  auto temp = volume::temporaryPathBeside(path);
  if (!temp) return temp.forwardError();
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", framesPerSecond);
  // H.264 in yuv420p needs even sizes: pad by at most one pixel.
  std::vector<std::string> args = {ffmpeg,
                                   "-nostdin",
                                   "-y",
                                   "-loglevel",
                                   "error",
                                   "-framerate",
                                   rate,
                                   "-start_number",
                                   "0",
                                   "-i",
                                   framePattern,
                                   "-vf",
                                   "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                   "-c:v",
                                   "libx264",
                                   "-pix_fmt",
                                   "yuv420p",
                                   "-movflags",
                                   "+faststart",
                                   "-f",
                                   "mp4",
                                   *temp};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::cout.flush();
  std::cerr.flush();
  pid_t pid = 0;
  if (const int st = posix_spawn(&pid, ffmpeg.c_str(), nullptr, nullptr, argv.data(), environ); st != 0)
    return makeError(path + ": cannot start " + ffmpeg + ": " + std::strerror(st));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::remove(temp->c_str());
    return makeError(path + ": ffmpeg failed (" +
                     (WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                        : "signal " + std::to_string(WTERMSIG(status))) +
                     "); its messages are above");
  }
  return volume::commitTemporary(*temp, path);
}

}  // namespace atmoglobe::engine
