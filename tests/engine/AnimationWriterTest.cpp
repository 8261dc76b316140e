// Animated GIF of a time series (AnimationWriter.h): the frame count, and the decoded frames
// against the frames given, within what a 256-colour palette per frame can do.
#include <atmoglobe/engine/AnimationWriter.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

using namespace atmoglobe;

namespace {
std::string outPath(const std::string& name) { return ATMOGLOBE_TEST_OUTPUT_DIR + "/" + name; }

struct ErrorStats {
  double meanAbs = 0.0;
  int maxAbs = 0;
};
ErrorStats compare(const globe::ImageRGBA8& a, const globe::ImageRGBA8& b) {
  ErrorStats s;
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4)
    for (int c = 0; c < 3; ++c, ++n) {
      const int e = std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c]));
      sum += e;
      s.maxAbs = std::max(s.maxAbs, e);
    }
  s.meanAbs = sum / static_cast<double>(n);
  return s;
}
// The same frame through a fixed 256-colour palette (3-3-2 bits, each value to the nearest level
// of its channel): what a GIF without an adaptive palette would show.
ErrorStats fixedPaletteError(const globe::ImageRGBA8& a) {
  globe::ImageRGBA8 q = a;
  for (std::size_t i = 0; i < q.pixels.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      const int levels = c == 2 ? 3 : 7;  // 8, 8 and 4 levels
      const double v = std::round(q.pixels[i + c] / 255.0 * levels) / levels * 255.0;
      q.pixels[i + c] = static_cast<std::uint8_t>(std::lround(v));
    }
  return compare(a, q);
}
}  // namespace

TEST(GifAnimation, FramesOnTheFiveBitLatticeRoundTripExactly) {
  // giflib's quantiser works on 5 bits per channel and gives a colour its own palette entry when
  // a frame has at most 256 distinct 5-bit colours: values that are multiples of 8 then come
  // back exactly. Three frames of 200 colours each (different ones per frame: local palettes).
  std::vector<globe::ImageRGBA8> frames;
  for (int f = 0; f < 3; ++f) {
    globe::ImageRGBA8 im = globe::ImageRGBA8::filled(97, 61, {0, 0, 0, 255});
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        const int k = (x / 5 + 20 * (y / 7) + f * 37) % 200;
        im.set(x, y,
               {static_cast<std::uint8_t>(8 * (k % 32)), static_cast<std::uint8_t>(8 * ((k / 32 + f) % 32)),
                static_cast<std::uint8_t>(8 * ((k * 7) % 32)), 255});
      }
    frames.push_back(im);
  }
  const std::string path = outPath("lattice.gif");
  auto w = engine::GifAnimationWriter::create(path, 97, 61, 250);
  ASSERT_TRUE(w) << w.error();
  for (const auto& f : frames) ASSERT_TRUE((*w)->addFrame(f));
  ASSERT_TRUE((*w)->finish());
  auto decoded = engine::readGifFrames(path);
  ASSERT_TRUE(decoded) << decoded.error();
  ASSERT_EQ(decoded->size(), frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) EXPECT_EQ(decoded->at(f).pixels, frames[f].pixels) << "frame " << f;
}

TEST(GifAnimation, RenderedFramesDecodeWithinPaletteQuantisationError) {
  // Real renders (the reviewed golden frames: imagery, coastlines, radar DVR and MIP) as the
  // steps of a series, cut to a common size.
  std::vector<globe::ImageRGBA8> frames;
  for (const char* name :
       {"globe_europe_africa", "north_pole_antimeridian", "oblique_alps_horizon", "radar_au40_mip", "radar_klbb_dvr"}) {
    auto im = globe::decodeImageFile(std::string(ATMOGLOBE_SOURCE_DIR) + "/tests/golden/" + name + ".png");
    ASSERT_TRUE(im) << im.error();
    globe::ImageRGBA8 cut = globe::ImageRGBA8::filled(200, 112, {0, 0, 0, 255});
    for (int y = 0; y < 112; ++y)
      for (int x = 0; x < 200; ++x) {
        auto p = im->at(x, y);
        cut.set(x, y, {p.r, p.g, p.b, 255});
      }
    frames.push_back(cut);
  }
  const std::string path = outPath("rendered.gif");
  auto w = engine::GifAnimationWriter::create(path, 200, 112, 200);
  ASSERT_TRUE(w) << w.error();
  for (const auto& f : frames) ASSERT_TRUE((*w)->addFrame(f));
  EXPECT_EQ((*w)->frames(), frames.size());
  ASSERT_TRUE((*w)->finish());
  auto decoded = engine::readGifFrames(path);
  ASSERT_TRUE(decoded) << decoded.error();
  ASSERT_EQ(decoded->size(), frames.size());  // one GIF frame per step
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const ErrorStats gif = compare(frames[f], decoded->at(f)), fixed = fixedPaletteError(frames[f]);
    std::set<std::uint32_t> colours;
    for (std::size_t i = 0; i < frames[f].pixels.size(); i += 4)
      colours.insert(std::uint32_t(frames[f].pixels[i]) << 16 | std::uint32_t(frames[f].pixels[i + 1]) << 8 |
                     frames[f].pixels[i + 2]);
    std::cout << "frame " << f << ": " << colours.size() << " colours; GIF mean |error| " << gif.meanAbs << " max "
              << gif.maxAbs << "; fixed 3-3-2 palette mean " << fixed.meanAbs << " max " << fixed.maxAbs << "\n";
    // Tolerance, exact: the palette quantisation error of a pixel is its colour's distance to
    // the nearest of the frame's 256 palette colours, and the writer maps every pixel to that
    // nearest entry. So each decoded pixel must be a palette colour (one of the colours the
    // decoded frame uses: at most 256) no farther from the original than any other of them.
    std::set<std::uint32_t> palette;
    const auto& d = decoded->at(f).pixels;
    for (std::size_t i = 0; i < d.size(); i += 4)
      palette.insert(std::uint32_t(d[i]) << 16 | std::uint32_t(d[i + 1]) << 8 | d[i + 2]);
    EXPECT_LE(palette.size(), 256u);
    std::size_t farther = 0;
    for (std::size_t i = 0; i < d.size(); i += 4) {
      const auto& o = frames[f].pixels;
      auto dist = [&](int r, int g, int b) {
        return (r - o[i]) * (r - o[i]) + (g - o[i + 1]) * (g - o[i + 1]) + (b - o[i + 2]) * (b - o[i + 2]);
      };
      const int got = dist(d[i], d[i + 1], d[i + 2]);
      for (std::uint32_t p : palette)
        if (dist(int(p >> 16), int((p >> 8) & 0xff), int(p & 0xff)) < got) {
          ++farther;
          break;
        }
    }
    EXPECT_EQ(farther, 0u) << "frame " << f << ": pixels not on their nearest palette colour";
    // And the adaptive palette beats a fixed 256-colour one on the same frame (measured here).
    EXPECT_LT(gif.meanAbs, fixed.meanAbs) << "frame " << f;
    // Quantisation moves colours, never the picture: a decode of another frame (or the frames
    // out of order) is far off (mean error of tens of levels between these renders).
    if (f > 0) {
      EXPECT_GT(compare(frames[f], decoded->at(f - 1)).meanAbs, 4 * gif.meanAbs);
    }
  }
}

TEST(GifAnimation, BadFramesAndFilesNameThePath) {
  const std::string path = outPath("bad.gif");
  auto w = engine::GifAnimationWriter::create(path, 10, 10, 100);
  ASSERT_TRUE(w);
  auto st = (*w)->addFrame(globe::ImageRGBA8::filled(11, 10, {0, 0, 0, 255}));
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().find("bad.gif"), std::string::npos) << st.error();
  w->reset();  // never finished: no file is left
  EXPECT_FALSE(std::filesystem::exists(path));
  auto r = engine::readGifFrames(std::string(ATMOGLOBE_SOURCE_DIR) + "/tests/golden/radar_klbb_dvr.png");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("radar_klbb_dvr.png"), std::string::npos) << r.error();
}

TEST(Mp4Animation, WithoutFfmpegTheErrorSaysSoAndAFailingFfmpegLeavesNoFile) {
  const std::string dir = ATMOGLOBE_TEST_OUTPUT_DIR + "/fake-path";
  std::filesystem::create_directories(dir);
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  setenv("PATH", dir.c_str(), 1);  // no ffmpeg there
  EXPECT_EQ(engine::findFfmpeg(), "");
  auto st = engine::encodeMp4(dir + "/f_%03d.png", 4.0, outPath("none.mp4"));
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().find("ffmpeg not found on PATH"), std::string::npos) << st.error();
  // An "ffmpeg" that fails (a copy of false(1)): started through posix_spawn, its exit status
  // reported, nothing left at the target or beside it.
  std::filesystem::copy_file("/bin/false", dir + "/ffmpeg", std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(engine::findFfmpeg(), dir + "/ffmpeg");
  st = engine::encodeMp4(dir + "/f_%03d.png", 4.0, outPath("failed.mp4"));
  setenv("PATH", saved.c_str(), 1);
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().find("ffmpeg failed (exit 1)"), std::string::npos) << st.error();
  EXPECT_FALSE(std::filesystem::exists(outPath("failed.mp4")));
}
