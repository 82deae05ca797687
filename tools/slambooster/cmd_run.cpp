// Placeholder: replaced by the run work in this session.
#include "core/error.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

void addRunCommand(CLI::App& app) {
  auto* sub = app.add_subcommand("run", "(not yet built)");
  sub->callback([] { throw Error("'run' is not built yet"); });
}

}  // namespace sb::cli
