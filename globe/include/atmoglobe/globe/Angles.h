#pragma once
// Angles: the one definition of pi and of the degree <-> radian conversions.
//
// Every library uses these instead of its own `kDegToRad`, `M_PI` (a POSIX extension, not
// standard C++) or a spelled-out 3.14159...: one place to read how a conversion rounds.
// Like Result.h it sits in namespace atmoglobe (not atmoglobe::globe) because every library
// needs it and globe is the bottom of the dependency graph.
//
// Rounding: kPi is the double nearest pi (std::numbers::pi). Each conversion is one
// multiplication by a constant rounded once (pi/180 or 180/pi); 180 deg converts to exactly kPi,
// and a degree -> radian -> degree round trip is within 1 ulp (tests/globe/AnglesTest.cpp).
#include <numbers>

namespace atmoglobe {

/// pi (radians in half a turn), the double nearest the real number.
inline constexpr double kPi = std::numbers::pi;

/// Degrees -> radians.
constexpr double degreesToRadians(double degrees) { return degrees * (kPi / 180.0); }

/// Radians -> degrees.
constexpr double radiansToDegrees(double radians) { return radians * (180.0 / kPi); }

}  // namespace atmoglobe
