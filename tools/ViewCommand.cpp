// PLACEHOLDER: replaced by the real `view` subcommand.
#include "Commands.h"

namespace atmoglobe::tools {
Command addViewCommand(CLI::App& root) {
  Command c;
  c.app = root.add_subcommand("view", "(not implemented yet)");
  c.run = [] { return fail("view", "not implemented yet"); };
  return c;
}
}  // namespace atmoglobe::tools
