// The benchmark programs' command lines (CLI11, as the `atmoglobe` tool's): the number checks and
// the WxH sizes they share, and the parse that ends the program on --help (exit 0) or on a usage
// error (the message names the option and the value; exit 2) before anything is measured.
// Only the programs tools/bench/*.cpp include this: the bench library must not depend on CLI11.
#pragma once

#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::benchcli {

/// A finite number in [min, max] (max defaults to no bound). An integer option's value also has to
/// convert to an int, which CLI11 checks after this.
inline CLI::Validator numberIn(double min, double max = std::numeric_limits<double>::infinity()) {
  std::ostringstream description;
  if (std::isinf(max)) description << ">= " << min;
  else description << "in [" << min << ", " << max << "]";
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) return "'" + text + "' is not a number";
        std::ostringstream bound;
        if (value < min) bound << "'" << text << "' is below " << min;
        else if (value > max) bound << "'" << text << "' is above " << max;
        return bound.str();
      },
      description.str());
}

/// "WxH", both at least 16 (the whole text: "320x180x" and "320x" are refused).
inline bool parseSize(const std::string& text, int& width, int& height) {
  const char* end = text.data() + text.size();
  int w = 0, h = 0;
  const auto [afterW, errW] = std::from_chars(text.data(), end, w);
  if (errW != std::errc{} || afterW == end || *afterW != 'x') return false;
  const auto [afterH, errH] = std::from_chars(afterW + 1, end, h);
  if (errH != std::errc{} || afterH != end || w < 16 || h < 16) return false;
  width = w;
  height = h;
  return true;
}

/// Adds --sizes "WxH,WxH,...": each item as parseSize takes it, at least one; a bad item is a
/// usage error naming it.
inline void addSizesOption(CLI::App& app, std::vector<std::pair<int, int>>& sizes, const std::string& description) {
  app.add_option_function<std::string>(
         "--sizes",
         [&sizes](const std::string& text) {
           std::vector<std::pair<int, int>> list;
           std::stringstream s(text);
           std::string item;
           while (std::getline(s, item, ',')) {
             int w = 0, h = 0;
             if (!parseSize(item, w, h)) throw CLI::ValidationError("--sizes " + item + ": expected WxH, each >= 16");
             list.emplace_back(w, h);
           }
           if (list.empty()) throw CLI::ValidationError("--sizes " + text + ": expected WxH, each >= 16");
           sizes = std::move(list);
         },
         description)
      ->type_name("WxH,...");
}

/// Parses argv into `app`. Returns -1 when the program goes on; else the status to exit with: 0
/// after --help (usage printed), 2 after a usage error (printed with a pointer to --help).
inline int parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return -1;
}

}  // namespace atmoglobe::benchcli
