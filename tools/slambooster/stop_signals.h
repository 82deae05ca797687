#pragma once
// Ctrl-C and SIGTERM for a long offline command: while a StopSignals lives, SIGINT and SIGTERM only set a
// flag; the command finishes the frame in hand, writes its outputs and exits 128 + the signal (Interrupted).
// The previous handlers come back when it is destroyed (a second signal then acts as usual).

#include <signal.h>

#include <string>

#include "core/error.h"

namespace sb::cli {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The signal received (SIGINT, SIGTERM), or 0.
  int received() const;
  static std::string name(int signal) {
    return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "signal";
  }

 private:
  struct sigaction oldInt_ {
  }, oldTerm_{};
};

// Thrown after a command stopped early for a signal with its outputs written; main exits 128 + signal.
class Interrupted : public Error {
 public:
  Interrupted(int signal, const std::string& what) : Error(what), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

}  // namespace sb::cli
