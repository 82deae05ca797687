#pragma once
// Two numbers into a message (the odometry's "why" strings).

#include <cstdio>
#include <string>

namespace sb::odometry {

inline std::string formatNumbers(const char* fmt, double a, double b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

}  // namespace sb::odometry
