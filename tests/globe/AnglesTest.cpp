// Tests of the shared angle constants and conversions (globe/Angles.h).
#include <atmoglobe/globe/Angles.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace atmoglobe {
namespace {

// Usable in constant expressions (the header promises constexpr).
static_assert(degreesToRadians(180.0) == kPi);
static_assert(radiansToDegrees(kPi) == 180.0);

TEST(Angles, PiIsTheNearestDouble) {
  // 4 atan(1) is correctly rounded by glibc; pi's double neighbours differ from it by 4.4e-16.
  EXPECT_EQ(kPi, 4.0 * std::atan(1.0));
  EXPECT_EQ(kPi, std::acos(-1.0));
}

TEST(Angles, ExactAtTheCardinalAngles) {
  // Multiplying by a power of two is exact, so these hold bit for bit.
  EXPECT_EQ(degreesToRadians(0.0), 0.0);
  EXPECT_EQ(degreesToRadians(90.0), kPi / 2.0);
  EXPECT_EQ(degreesToRadians(-180.0), -kPi);
  EXPECT_EQ(degreesToRadians(360.0), 2.0 * kPi);
  EXPECT_EQ(radiansToDegrees(kPi / 2.0), 90.0);
  EXPECT_EQ(radiansToDegrees(-kPi), -180.0);
  EXPECT_EQ(radiansToDegrees(degreesToRadians(90.0)), 90.0);
}

TEST(Angles, AgreesWithSinAndCos) {
  // 1e-15: a few ulp of values near 1 (one rounding in the conversion, one in sin/cos).
  EXPECT_NEAR(std::sin(degreesToRadians(30.0)), 0.5, 1e-15);
  EXPECT_NEAR(std::cos(degreesToRadians(60.0)), 0.5, 1e-15);
  EXPECT_NEAR(std::tan(degreesToRadians(45.0)), 1.0, 1e-15);
  EXPECT_NEAR(radiansToDegrees(std::atan2(1.0, 1.0)), 45.0, 1e-13);
}

TEST(Angles, RoundTripWithinOneUlp) {
  // Two multiplications by constants each rounded once: within 1 ulp of the input over the
  // angles the engine sees (two turns either way), including the extremes of that range.
  std::mt19937_64 rng(20240610);
  std::uniform_real_distribution<double> angle(-720.0, 720.0);
  for (int i = 0; i < 200000; ++i) {
    const double deg = i == 0 ? 720.0 : i == 1 ? -720.0 : i == 2 ? 1e-300 : angle(rng);
    const double back = radiansToDegrees(degreesToRadians(deg));
    const double ulp = std::nextafter(std::abs(deg), std::numeric_limits<double>::infinity()) - std::abs(deg);
    ASSERT_LE(std::abs(back - deg), ulp) << "deg = " << deg;
  }
}

}  // namespace
}  // namespace atmoglobe
