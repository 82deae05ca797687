#pragma once
// Numbers into a message (the odometry's "why" strings).

#include <cstdio>
#include <string>

namespace sb::odometry {

template <typename... Numbers>
std::string formatNumbers(const char* fmt, Numbers... numbers) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, static_cast<double>(numbers)...);
  return buf;
}

}  // namespace sb::odometry
