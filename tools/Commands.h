#pragma once
// Each subcommand registers itself on the root CLI11 app and returns how to run it.
#include <CLI/CLI.hpp>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace atmoglobe::tools {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;  ///< returns the process exit code
};

Command addTilesCommand(CLI::App& root);
Command addRenderCommand(CLI::App& root);
Command addViewCommand(CLI::App& root);
Command addInfoCommand(CLI::App& root);
Command addGatesCommand(CLI::App& root);
Command addExportConesCommand(CLI::App& root);
Command addSynthCommand(CLI::App& root);
Command addBenchCommand(CLI::App& root);
Command addConvertCommand(CLI::App& root);
Command addSliceCommand(CLI::App& root);
Command addMosaicCommand(CLI::App& root);

/// Embedded files from assets/ (default scene...), by file name.
std::optional<std::string_view> embeddedAsset(std::string_view fileName);

/// Adds `--grid-index NAME=I` (repeatable) to `app`: the index read along a grid dimension that
/// is neither horizontal, vertical nor time (a netCDF `month` axis, an ensemble dimension;
/// GridReadOptions::extraIndex), listed by `atmoglobe info`. A malformed value is a usage error.
CLI::Option* addGridIndexOption(CLI::App* app, std::map<std::string, std::size_t>& out);

/// Prints "atmoglobe <command>: <message>" to stderr and returns exit code 1.
int fail(std::string_view command, std::string_view message);

}  // namespace atmoglobe::tools
