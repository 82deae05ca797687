#pragma once
// The subcommands of `slambooster`. Each add*Command registers one subcommand and its callback on the app;
// callbacks throw sb::Error for user-facing failures (printed by main, exit code 1).

#include <CLI/CLI.hpp>

namespace sb::cli {

void addRunCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addDseCommand(CLI::App& app);
void addProfileCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addEnergyCommand(CLI::App& app);
void addSynthCommand(CLI::App& app);
void addReportCommand(CLI::App& app);
void addRecordCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);

}  // namespace sb::cli
