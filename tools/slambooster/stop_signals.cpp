#include "tools/slambooster/stop_signals.h"

#include <csignal>

namespace sb::cli {

namespace {

volatile std::sig_atomic_t g_received = 0;

void onSignal(int signal) {
  g_received = signal;  // async-signal-safe
  // The next one acts as usual (a second Ctrl-C still kills a run that does not stop).
  std::signal(signal, SIG_DFL);
}

}  // namespace

StopSignals::StopSignals() {
  g_received = 0;
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sa.sa_flags = SA_RESTART;  // reads of the sequence carry on; the frame loop checks the flag
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &oldInt_);
  sigaction(SIGTERM, &sa, &oldTerm_);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &oldInt_, nullptr);
  sigaction(SIGTERM, &oldTerm_, nullptr);
}

int StopSignals::received() const {
  return g_received;
}

}  // namespace sb::cli
