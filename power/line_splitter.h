#pragma once
// Turns a serial byte stream into lines: splits at '\n', strips a trailing '\r', drops the first line after a
// (re)open (it may have started before we did), and drops over-long lines (garbage, a stuck device) by
// resynchronising at the next newline.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sb::power {

class LineSplitter {
 public:
  explicit LineSplitter(size_t maxLineBytes = 256) : maxLineBytes_(maxLineBytes) {}

  // Forget buffered bytes; with dropFirstLine, discard everything up to and including the next '\n'.
  void reset(bool dropFirstLine);

  // Appends complete lines (without "\r\n") to `out`.
  void push(const char* data, size_t n, std::vector<std::string>& out);

  uint64_t droppedLines() const { return dropped_; }  // partial first lines and over-long lines

 private:
  size_t maxLineBytes_;
  std::string buffer_;
  bool discarding_ = false;  // inside a line that is being dropped
  uint64_t dropped_ = 0;
};

}  // namespace sb::power
