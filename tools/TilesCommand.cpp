// PLACEHOLDER: replaced by the real `tiles` subcommand.
#include "Commands.h"

namespace atmoglobe::tools {
Command addTilesCommand(CLI::App& root) {
  Command c;
  c.app = root.add_subcommand("tiles", "(not implemented yet)");
  c.run = [] { return fail("tiles", "not implemented yet"); };
  return c;
}
}  // namespace atmoglobe::tools
