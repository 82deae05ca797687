#pragma once
// Opening a USB serial meter: raw termios (8N1, no flow control, no echo, no line editing or CR/LF mapping),
// non-blocking, at the given baud rate.

#include <string>

#include "core/unique_fd.h"

namespace sb::power {

struct SerialOpenResult {
  UniqueFd fd;          // valid on success
  int errnum = 0;       // errno of the failing call
  std::string error;    // what failed, where, and what to do (empty on success)
};

// Never throws; the caller decides whether a failure is fatal (at start) or a retry (after unplugging).
SerialOpenResult openSerialPort(const std::string& path, int baud);

// True for the baud rates openSerialPort accepts (9600 ... 921600).
bool isSupportedBaud(int baud);

}  // namespace sb::power
