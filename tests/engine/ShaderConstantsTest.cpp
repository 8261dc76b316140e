// The constants C++ hands to GLSL (engine/ShaderConstants.h, VolumeGL.h): each define reads back
// as exactly the C++ value narrowed to float. GL-free: the literals are parsed here with strtof,
// as a GLSL compiler reads them.
#include <atmoglobe/engine/ShaderConstants.h>
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <random>
#include <string>

namespace atmoglobe {
namespace {

float readBack(const std::string& literal) {
  char* end = nullptr;
  const float f = std::strtof(literal.c_str(), &end);
  EXPECT_EQ(*end, '\0') << literal;
  return f;
}

// A GLSL float literal: digits with a '.', optional exponent, optional sign (an int has no '.').
bool isFloatLiteral(const std::string& s) {
  return s.find('.') != std::string::npos && s.find_first_not_of("+-.0123456789e") == std::string::npos;
}

std::map<std::string, std::string> byName(const std::vector<std::string>& defines) {
  std::map<std::string, std::string> out;
  for (const std::string& d : defines) {
    const std::size_t space = d.find(' ');
    EXPECT_NE(space, std::string::npos) << d;
    EXPECT_TRUE(out.emplace(d.substr(0, space), d.substr(space + 1)).second) << "defined twice: " << d;
  }
  return out;
}

TEST(ShaderConstants, FloatLiteralsReadBackExactly) {
  const float cases[] = {0.0f,     -0.0f,    1.0f,      6378137.0f, 0.5f,     -1.0e38f,
                         -1.0e37f, 1.0e10f,  -60000.0f, 1.0e-30f,   3.0e-45f, std::numeric_limits<float>::max(),
                         0.1f,     1.0f / 3, 298.25723f};
  for (float x : cases) {
    const std::string s = engine::glslFloatLiteral(x);
    EXPECT_TRUE(isFloatLiteral(s)) << s;
    EXPECT_EQ(readBack(s), x) << s;
  }
  EXPECT_EQ(engine::glslFloatLiteral(6378137.0), "6378137.0");
  EXPECT_EQ(engine::glslFloatLiteral(-1.0e38), "-1.0e+38");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> exponent(-37.0, 38.0);
  for (int i = 0; i < 10000; ++i) {
    const double x = (i % 2 ? -1.0 : 1.0) * std::pow(10.0, exponent(rng));
    const std::string s = engine::glslFloatLiteral(x);
    EXPECT_TRUE(isFloatLiteral(s)) << s;
    EXPECT_EQ(readBack(s), static_cast<float>(x)) << s;
  }
}

TEST(ShaderConstants, EllipsoidDefinesAreTheGlobeConstants) {
  auto d = byName(engine::ellipsoidShaderDefines());
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(readBack(d["WGS84_A"]), static_cast<float>(globe::kWgs84A));
  EXPECT_EQ(readBack(d["WGS84_F"]), static_cast<float>(globe::kWgs84F));
  EXPECT_EQ(readBack(d["WGS84_E2"]), static_cast<float>(globe::kWgs84E2));
  // e^2 = f (2 - f) = 1 - b^2 / a^2: the derived constants agree with their definitions (the
  // second form loses up to a few ulp of 1, 2.2e-16 each, in the subtraction).
  EXPECT_NEAR(globe::kWgs84E2, 1.0 - (globe::kWgs84B * globe::kWgs84B) / (globe::kWgs84A * globe::kWgs84A), 1e-15);
  EXPECT_NEAR(globe::kWgs84E2, 6.69437999014e-3, 1e-14);  // NIMA TR8350.2 table 3.3
  EXPECT_NEAR(globe::kWgs84B, 6356752.3142, 1e-4);        // table 3.3
}

TEST(ShaderConstants, MarchDefinesHoldNoDataAndTheEllipsoid) {
  using C = engine::MarchConstants;
  auto d = byName(engine::marchShaderDefines());
  EXPECT_EQ(readBack(d["GPU_NO_DATA"]), C::kNoData);
  EXPECT_EQ(readBack(d["GPU_NO_DATA_BELOW"]), C::kNoDataBelow);
  EXPECT_LT(C::kNoData, C::kNoDataBelow);
  EXPECT_EQ(d["WGS84_A"], engine::glslFloatLiteral(globe::kWgs84A));
  EXPECT_EQ(d.count("WGS84_E2"), 1u);
  EXPECT_EQ(d["MAX_VOLUMES"], std::to_string(C::kMaxVolumes));
}

}  // namespace
}  // namespace atmoglobe
