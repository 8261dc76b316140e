#pragma once
// ASCII text helpers: the one case folding and the one whitespace trim for the names, units,
// keys and numbers that readers, scene files and the command line compare.
//
// ASCII only and independent of the C locale: A-Z fold to a-z and every other byte (UTF-8
// included) is left as it is; the blanks are the six of the "C" locale's isspace (space, \t, \n,
// \v, \f, \r). File formats (CF, ODIM, NEXRAD, .pal) define their keywords in ASCII, so a
// locale set by a host program must not change how they compare.
// Like Angles.h it sits in namespace atmoglobe because every library needs it.
#include <string>
#include <string_view>

namespace atmoglobe {

/// `c` with A-Z mapped to a-z; any other byte unchanged.
constexpr char toLowerAscii(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

/// `text` with A-Z mapped to a-z; any other byte unchanged.
std::string toLowerAscii(std::string_view text);

/// A number for messages and titles: at most 10 significant digits, no trailing zeros ("%.10g":
/// 273.15, 500, 1e-05).
std::string numberText(double value);

/// True for the six ASCII blanks: space, \t, \n, \v, \f, \r.
constexpr bool isSpaceAscii(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

/// `text` without its leading and trailing ASCII blanks: a view into `text` (keep what it views
/// alive; copy into a std::string to keep the result of a temporary).
std::string_view trimAscii(std::string_view text);

/// `text` lower-cased with every ASCII blank removed ("Geopotential Height" -> "geopotentialheight").
std::string toLowerAsciiWithoutBlanks(std::string_view text);

/// Equality with A-Z and a-z taken as the same.
bool equalsIgnoringCaseAscii(std::string_view a, std::string_view b);

}  // namespace atmoglobe
