// atmoglobe: command-line front end. Each subcommand lives in its own file.
#include "Commands.h"

#include <iostream>
#include <vector>

namespace atmoglobe::tools {
int fail(std::string_view command, std::string_view message) {
  std::cerr << "atmoglobe " << command << ": " << message << "\n";
  return 1;
}
}  // namespace atmoglobe::tools

int main(int argc, char** argv) {
  using namespace atmoglobe::tools;
  CLI::App app{"atmoglobe: a WGS84 virtual globe for weather radar and forecast volumes", "atmoglobe"};
  app.set_version_flag("--version", ATMOGLOBE_VERSION);
  app.require_subcommand(1);
  std::vector<Command> commands;
  commands.push_back(addTilesCommand(app));
  commands.push_back(addRenderCommand(app));
  commands.push_back(addViewCommand(app));
  commands.push_back(addInfoCommand(app));
  commands.push_back(addGatesCommand(app));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  for (const Command& c : commands) {
    if (c.app && c.app->parsed()) return c.run();
  }
  return 2;
}
