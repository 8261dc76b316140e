// PLACEHOLDER: replaced by the real `render` subcommand.
#include "Commands.h"

namespace atmoglobe::tools {
Command addRenderCommand(CLI::App& root) {
  Command c;
  c.app = root.add_subcommand("render", "(not implemented yet)");
  c.run = [] { return fail("render", "not implemented yet"); };
  return c;
}
}  // namespace atmoglobe::tools
