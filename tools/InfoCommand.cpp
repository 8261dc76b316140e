// PLACEHOLDER: replaced by the real `info` subcommand.
#include "Commands.h"

namespace atmoglobe::tools {
Command addInfoCommand(CLI::App& root) {
  Command c;
  c.app = root.add_subcommand("info", "(not implemented yet)");
  c.run = [] { return fail("info", "not implemented yet"); };
  return c;
}
}  // namespace atmoglobe::tools
