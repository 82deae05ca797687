#pragma once
// The subcommands of `slambooster`. Each add*Command registers one subcommand and its callback on the app;
// callbacks throw sb::Error for user-facing failures (printed by main, exit code 1).

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace sb::cli {

void addRunCommand(CLI::App& app);
// The matrix commands get the process's command line (argv) for the plans they write (matrix_plan.h).
void addBenchCommand(CLI::App& app, const std::vector<std::string>& commandLine);
void addDseCommand(CLI::App& app, const std::vector<std::string>& commandLine);
void addProfileCommand(CLI::App& app, const std::vector<std::string>& commandLine);
void addEvalCommand(CLI::App& app);
void addEvalMapCommand(CLI::App& app);  // the navigation grid against a synthetic corridor's truth
void addEnergyCommand(CLI::App& app);
void addSynthCommand(CLI::App& app);
void addCutCommand(CLI::App& app);
void addReportCommand(CLI::App& app);
void addRecordCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addSummaryCommand(CLI::App& app);

}  // namespace sb::cli
