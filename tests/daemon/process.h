#pragma once
// Child processes for system tests of slamboosterd: spawn with extra environment and a log file, signal,
// wait with a timeout.

#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

namespace sb::test {

class ChildProcess {
 public:
  // Starts argv[0] (a path) with `env` ("KEY=VALUE") added, stdout+stderr to `logPath`. `inChild` runs in
  // the child before exec (e.g. to set up inherited file descriptors).
  ChildProcess(const std::vector<std::string>& argv, const std::vector<std::string>& env,
               const std::string& logPath, const std::function<void()>& inChild = {});
  ~ChildProcess();  // kills (SIGKILL) and reaps a child still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int sig) const;
  // The exit code; -1 when killed by a signal; -2 when still running after `timeoutSeconds` (then killed).
  int wait(double timeoutSeconds);
  std::string log() const;

 private:
  pid_t pid_ = -1;
  std::string logPath_;
  bool reaped_ = false;
};

// Waits until `path` exists (up to `timeoutSeconds`).
bool waitForPath(const std::string& path, double timeoutSeconds);

}  // namespace sb::test
