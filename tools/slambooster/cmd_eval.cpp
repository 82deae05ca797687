// Placeholder: replaced by the eval work in this session.
#include "core/error.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

void addEvalCommand(CLI::App& app) {
  auto* sub = app.add_subcommand("eval", "(not yet built)");
  sub->callback([] { throw Error("'eval' is not built yet"); });
}

}  // namespace sb::cli
