#pragma once
// One exception type for every user-facing failure. The message must say what was wrong, where (file, frame,
// key) and what to do; callers at the top level print it and exit non-zero.

#include <stdexcept>
#include <string>

namespace sb {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace sb
