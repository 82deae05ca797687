#pragma once
// A serial meter simulated on a pseudo-terminal: the driver opens a symlink (like a udev /dev/serial/by-id/
// link) that points at the pty's slave side; the test writes the meter's bytes into the master side.
// unplug() closes the master (the driver sees end of file, the slave node disappears); replug() creates a new
// pty and points the same symlink at it, as the kernel does when the meter comes back.

#include <string>
#include <string_view>
#include <vector>

#include "power/meter.h"

namespace sb::test {

class PtySimulator {
 public:
  explicit PtySimulator(std::string linkPath);
  ~PtySimulator();
  PtySimulator(const PtySimulator&) = delete;
  PtySimulator& operator=(const PtySimulator&) = delete;

  void write(std::string_view bytes);
  void unplug();
  void replug();
  const std::string& path() const { return link_; }

 private:
  void open();
  void close();

  std::string link_;
  int master_ = -1;
  int slave_ = -1;  // held so that the pty stays configured (raw) until unplugged
};

// Polls `meter` (waiting on its descriptor, at most `timeoutMs` of real time in all) until it has returned
// `count` samples in total into `out`; returns whether it got them.
bool pollUntil(power::Meter& meter, std::vector<power::PowerSample>& out, size_t count, int timeoutMs = 2000);

// Waits until the meter's descriptor is readable and then a little longer, so that all bytes written so far
// are in the tty buffer and the next poll() reads them as one batch.
void settle(power::Meter& meter);

// Polls a few times, waiting up to `waitMs` for data: for checks that nothing (more) arrives.
void pollFor(power::Meter& meter, std::vector<power::PowerSample>& out, int waitMs = 50);

}  // namespace sb::test
