#include "power/line_splitter.h"

namespace sb::power {

void LineSplitter::reset(bool dropFirstLine) {
  buffer_.clear();
  discarding_ = dropFirstLine;
}

void LineSplitter::push(const char* data, size_t n, std::vector<std::string>& out) {
  for (size_t i = 0; i < n; ++i) {
    const char c = data[i];
    if (c == '\n') {
      if (discarding_) {
        ++dropped_;
        discarding_ = false;
      } else {
        if (!buffer_.empty() && buffer_.back() == '\r') buffer_.pop_back();
        out.push_back(buffer_);
      }
      buffer_.clear();
      continue;
    }
    if (discarding_) continue;
    buffer_.push_back(c);
    if (buffer_.size() > maxLineBytes_) {
      buffer_.clear();
      discarding_ = true;
    }
  }
}

}  // namespace sb::power
