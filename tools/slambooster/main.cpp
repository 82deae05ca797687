// slambooster: the offline tool (replay, evaluation, synthetic sequences, benchmarks).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/input_file.h"
#include "tools/slambooster/commands.h"
#include "tools/slambooster/stop_signals.h"

int main(int argc, char** argv) {
  CLI::App app{"slambooster: KinectFusion with an online approximation controller (offline tool)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(SB_VERSION));
  sb::cli::addRunCommand(app);
  const std::vector<std::string> commandLine(argv, argv + argc);
  sb::cli::addBenchCommand(app, commandLine);
  sb::cli::addDseCommand(app, commandLine);
  sb::cli::addProfileCommand(app, commandLine);
  sb::cli::addEvalCommand(app);
  sb::cli::addEvalMapCommand(app);
  sb::cli::addEnergyCommand(app);
  sb::cli::addSynthCommand(app);
  sb::cli::addCutCommand(app);
  sb::cli::addReportCommand(app);
  sb::cli::addRecordCommand(app);
  sb::cli::addCompareCommand(app);
  sb::cli::addSummaryCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const sb::cli::Interrupted& e) {  // outputs written; exit as the shell reports a signal
    std::cerr << "slambooster: " << sb::printable(e.what()) << "\n";
    return 128 + e.signal();
  } catch (const sb::Error& e) {
    std::cerr << "slambooster: error: " << sb::printable(e.what()) << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "slambooster: internal error: " << sb::printable(e.what()) << "\n";
    return 3;
  }
  return 0;
}
