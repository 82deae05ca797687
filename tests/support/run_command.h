#pragma once
// Runs a shell command for system tests of the built tools and captures its exit code and output.

#include <string>

namespace sb::test {

struct CommandResult {
  int exitCode = -1;   // -1 when the command did not exit normally
  std::string output;  // stdout and stderr together
};

CommandResult runCommand(const std::string& command);

}  // namespace sb::test
