#include <atmoglobe/engine/ShaderConstants.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <cassert>
#include <charconv>
#include <cmath>
#include <limits>

namespace atmoglobe::engine {

std::string glslFloatLiteral(double x) {
  assert(std::isfinite(x) && std::abs(x) <= std::numeric_limits<float>::max());
  const float f = static_cast<float>(x);  // GLSL float is binary32: say the value it will hold
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, f);
  assert(error == std::errc());
  std::string text(buffer, end);
  // A literal without '.' would be an int ("6378137") or lack one before the exponent ("1e+38").
  if (text.find('.') == std::string::npos) {
    const std::size_t e = text.find('e');
    text.insert(e == std::string::npos ? text.size() : e, ".0");
  }
  return text;
}

std::vector<std::string> ellipsoidShaderDefines() {
  return {"WGS84_A " + glslFloatLiteral(globe::kWgs84A), "WGS84_F " + glslFloatLiteral(globe::kWgs84F),
          "WGS84_E2 " + glslFloatLiteral(globe::kWgs84E2)};
}

}  // namespace atmoglobe::engine
