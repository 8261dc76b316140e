// atmoglobe: command-line front end. Each subcommand lives in its own file.
#include "Commands.h"

#include <atmoglobe/Version.h>

#include <iostream>
#include <vector>

namespace atmoglobe::tools {
CLI::Option* addGridIndexOption(CLI::App* app, std::map<std::string, std::size_t>& out) {
  return app
      ->add_option_function<std::vector<std::string>>(
          "--grid-index",
          [&out](const std::vector<std::string>& values) {
            for (const std::string& v : values) {
              const auto eq = v.find('=');
              std::size_t used = 0;
              unsigned long long index = 0;
              bool ok = eq != std::string::npos && eq > 0 && eq + 1 < v.size();
              if (ok) {
                try {
                  index = std::stoull(v.substr(eq + 1), &used);
                } catch (const std::exception&) {
                  ok = false;
                }
              }
              if (!ok || used != v.size() - eq - 1 || v[eq + 1] == '-')
                throw CLI::ValidationError("--grid-index", "'" + v + "' is not NAME=INDEX (e.g. month=6)");
              out[v.substr(0, eq)] = static_cast<std::size_t>(index);
            }
          },
          "Grids: the index read along a dimension that is neither horizontal, vertical nor time, NAME=INDEX "
          "(repeatable; e.g. month=6; the dimensions and their default 0 are listed by `atmoglobe info`)")
      ->type_name("NAME=I");
}

int fail(std::string_view command, std::string_view message) {
  std::cerr << "atmoglobe " << command << ": " << message << "\n";
  return 1;
}
}  // namespace atmoglobe::tools

int main(int argc, char** argv) {
  using namespace atmoglobe::tools;
  CLI::App app{"atmoglobe: a WGS84 virtual globe for weather radar and forecast volumes", "atmoglobe"};
  app.set_version_flag("--version", "atmoglobe " ATMOGLOBE_VERSION_STRING);
  app.require_subcommand(1);
  std::vector<Command> commands;
  commands.push_back(addTilesCommand(app));
  commands.push_back(addRenderCommand(app));
  commands.push_back(addViewCommand(app));
  commands.push_back(addInfoCommand(app));
  commands.push_back(addGatesCommand(app));
  commands.push_back(addExportConesCommand(app));
  commands.push_back(addConvertCommand(app));
  commands.push_back(addSynthCommand(app));
  commands.push_back(addBenchCommand(app));
  commands.push_back(addSliceCommand(app));
  commands.push_back(addMosaicCommand(app));
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    for (const Command& c : commands) known = known || c.app->get_name() == argv[1];
    if (!known) {
      std::cerr << "atmoglobe: unknown command \"" << argv[1] << "\" (see atmoglobe --help)\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and version exit 0; every usage error exits 2 (bad input files exit 1).
    return app.exit(e) == 0 ? 0 : 2;
  }
  for (const Command& c : commands) {
    if (c.app && c.app->parsed()) return c.run();
  }
  return 2;
}
