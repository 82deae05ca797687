// Placeholder: replaced by the synth work in this session.
#include "core/error.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

void addSynthCommand(CLI::App& app) {
  auto* sub = app.add_subcommand("synth", "(not yet built)");
  sub->callback([] { throw Error("'synth' is not built yet"); });
}

}  // namespace sb::cli
