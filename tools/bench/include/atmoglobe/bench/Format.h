#pragma once
// Numbers as the bench writes them, in its reports and in the reference cache's keys.
#include <string>

namespace atmoglobe::bench {

/// printf "%.*g": `precision` significant digits, shortest of fixed and exponent notation.
/// The cache keys (ReferenceCache.h) are built with the default precision: changing it renames
/// every cached reference.
std::string formatG(double v, int precision = 10);

}  // namespace atmoglobe::bench
