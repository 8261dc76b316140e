#pragma once
// Values C++ and GLSL share beyond the march's own (MarchConstants, VolumeGL.h): written once in
// C++ and handed to the shaders as #define lines (ShaderProgramGL prepends them), so that no
// shader spells a constant of its own. GL-free.
#include <string>
#include <vector>

namespace atmoglobe::engine {

/// `x` narrowed to float, as a GLSL float literal that reads back as exactly that float: the
/// shortest such digits (std::to_chars, independent of the locale) with a decimal point
/// ("6378137.0", "0.00669438", "-1.0e+38"). Precondition: finite within the float range.
std::string glslFloatLiteral(double x);

/// The WGS84 ellipsoid of globe/Ellipsoid.h narrowed to float, as "NAME VALUE" define entries:
/// WGS84_A (semi-major axis, m), WGS84_F (flattening), WGS84_E2 (first eccentricity squared).
std::vector<std::string> ellipsoidShaderDefines();

}  // namespace atmoglobe::engine
