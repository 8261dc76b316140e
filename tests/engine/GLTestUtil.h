#pragma once
// Shared by the GL tests: one headless EGL context per test executable, image helpers,
// and the default imagery pyramid built once from the Debian world image.
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GridSourceGL.h>
#include <atmoglobe/engine/RadarSourceGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/ImageryPyramid.h>
#include <atmoglobe/volume/VolumeImage.h>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <iostream>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::testutil {

/// A renderer's volume layer as its kind (a failed test, not a crash, when it is another kind).
inline const engine::RadarSourceGL& radarOf(const engine::VolumeSourceGL* layer) {
  const auto* radar = dynamic_cast<const engine::RadarSourceGL*>(layer);
  if (!radar) {
    ADD_FAILURE() << "the layer is not a radar";
    std::abort();
  }
  return *radar;
}
inline const engine::GridSourceGL& gridOf(const engine::VolumeSourceGL* layer) {
  const auto* grid = dynamic_cast<const engine::GridSourceGL*>(layer);
  if (!grid) {
    ADD_FAILURE() << "the layer is not a grid";
    std::abort();
  }
  return *grid;
}
inline const volume::PolarVolume& polarOf(const engine::VolumeSourceGL* layer) {
  return radarOf(layer).radarVolume().polar();
}
inline const volume::GridVolume& gridVolumeOf(const engine::VolumeSourceGL* layer) {
  return gridOf(layer).gridVolume().grid();
}

/// The headless context, created on first use and kept for the whole run (GL tests in
/// one executable run sequentially on the main thread).
inline engine::HeadlessContextGL& glContext() {
  static std::unique_ptr<engine::HeadlessContextGL> context = [] {
    auto c = engine::HeadlessContextGL::create();
    if (!c) {
      ADD_FAILURE() << "no headless GL context: " << c.error();
      std::abort();
    }
    return std::move(*c);
  }();
  return *context;
}

inline std::string testOutputDir() {
  const std::string dir = std::string(ATMOGLOBE_TEST_OUTPUT_DIR);
  std::filesystem::create_directories(dir);
  return dir;
}

/// The world image Debian's xplanet-images installs (test.sh installs it).
inline const char* kWorldImage = "/usr/share/xplanet/images/earth.jpg";

/// A pyramid of kWorldImage under the test output directory, built on first use.
inline std::string worldPyramidDir() {
  static const std::string dir = [] {
    const std::string d = testOutputDir() + "/earth-pyramid";
    auto s = globe::buildPyramid(kWorldImage, d, {});
    if (!s) {
      ADD_FAILURE() << s.error();
      std::abort();
    }
    return d;
  }();
  return dir;
}

/// Binds `fb` and clears it for reverse-Z drawing (depth 0 = infinitely far, GL_GREATER),
/// colour black, as the scene renderer does.
inline void beginReverseZ(const engine::FramebufferGL& fb) {
  fb.bind();
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glClearColor(0, 0, 0, 1);
  glClearDepth(0.0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

/// Mean of the RGB channels of image over the square block of half-size r around (cx, cy).
inline glm::dvec3 blockMean(const globe::ImageRGBA8& image, int cx, int cy, int r) {
  glm::dvec3 sum(0.0);
  int n = 0;
  for (int y = cy - r; y <= cy + r; ++y) {
    for (int x = cx - r; x <= cx + r; ++x) {
      const glm::u8vec4 p = image.at(x, y);
      sum += glm::dvec3(p.r, p.g, p.b);
      ++n;
    }
  }
  return sum / static_cast<double>(n);
}

/// Compares a rendered frame with tests/golden/<name>.png (the rule and its justification are
/// in GoldenImageTest.cpp): mean |diff| <= 1 per channel and at most 0.5 % of pixels off by
/// more than 24. Writes <name>.actual.png (and .diff.png on failure) to the test output
/// directory and adds a failure naming them.
inline void expectMatchesGolden(const std::string& name, const globe::ImageRGBA8& actual) {
  const std::string goldenPath = std::string(ATMOGLOBE_SOURCE_DIR) + "/tests/golden/" + name + ".png";
  const std::string actualPath = testOutputDir() + "/" + name + ".actual.png";
  ASSERT_TRUE(globe::writePng(actualPath, actual));
  auto golden = globe::decodeImageFile(goldenPath);
  if (!golden || golden->width != actual.width || golden->height != actual.height) {
    ADD_FAILURE() << (golden ? goldenPath + ": wrong size" : golden.error()) << " (review " << actualPath
                  << ", then tests/promote-golden.sh)";
    return;
  }
  const int w = actual.width, h = actual.height;
  globe::ImageRGBA8 diff = globe::ImageRGBA8::filled(w, h, {0, 0, 0, 255});
  double sumAbs = 0.0;
  int bad = 0, maxDiff = 0, differing = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const glm::ivec3 d = glm::abs(glm::ivec3(glm::ivec4(actual.at(x, y))) - glm::ivec3(glm::ivec4(golden->at(x, y))));
      sumAbs += d.r + d.g + d.b;
      const int m = std::max({d.r, d.g, d.b});
      if (m > 24) ++bad;
      maxDiff = std::max(maxDiff, m);
      differing += m > 0;
      const auto v = static_cast<std::uint8_t>(std::min(255, m * 8));
      diff.set(x, y, {v, v, v, 255});
    }
  }
  const double meanAbs = sumAbs / (3.0 * w * h);
  const double badFraction = static_cast<double>(bad) / (w * h);
  std::cout << "golden " << name << ": " << differing << " of " << w * h << " pixels differ, max " << maxDiff
            << " (8-bit), mean |diff| " << meanAbs << "\n";
  if (meanAbs > 1.0 || badFraction > 0.005) {
    const std::string diffPath = testOutputDir() + "/" + name + ".diff.png";
    EXPECT_TRUE(globe::writePng(diffPath, diff));
    ADD_FAILURE() << name << ": mean |diff| " << meanAbs << ", pixels off by >24: " << 100.0 * badFraction
                  << " %; actual " << actualPath << ", diff " << diffPath;
  }
}

/// The marcher's volume image of `layers` for a camera (no globe: empty depth), premultiplied,
/// row 0 = top: what the GPU-against-reference tests compare.
inline volume::VolumeImage renderVolumesGpu(engine::VolumeRendererGL& renderer, const engine::Camera& camera,
                                            const std::vector<engine::VolumeLayerGL>& layers) {
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  EXPECT_TRUE(fb);
  (*fb)->bind();
  glClearDepth(0.0);
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  renderer.draw(camera, layers, **fb);
  const std::vector<glm::vec4> img = renderer.readVolumeImage();
  volume::VolumeImage out;
  out.widthPx = camera.widthPx();
  out.heightPx = camera.heightPx();
  for (const glm::vec4& c : img) out.rgbaPremultiplied.push_back(glm::dvec4(c));
  return out;
}

}  // namespace atmoglobe::testutil
