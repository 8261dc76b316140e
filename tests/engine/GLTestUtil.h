#pragma once
// Shared by the GL tests: one headless EGL context per test executable, image helpers,
// and the default imagery pyramid built once from the Debian world image.
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/ImageryPyramid.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

namespace atmoglobe::testutil {

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

}  // namespace atmoglobe::testutil
