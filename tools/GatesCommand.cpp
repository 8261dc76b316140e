// PLACEHOLDER: replaced by the real `gates` subcommand.
#include "Commands.h"

namespace atmoglobe::tools {
Command addGatesCommand(CLI::App& root) {
  Command c;
  c.app = root.add_subcommand("gates", "(not implemented yet)");
  c.run = [] { return fail("gates", "not implemented yet"); };
  return c;
}
}  // namespace atmoglobe::tools
