#pragma once
// Small helpers for meters that read sysfs attributes (INA231, RAPL): read a number, write a value, with errors
// that name the file and the fix.

#include <string>

namespace sb::power {

// The first whitespace-separated token of the file as a number. Throws sb::Error naming the file (and, for
// permission errors, what to do) when it cannot be read or does not hold a number.
double readSysfsNumber(const std::string& path);
unsigned long long readSysfsCounter(const std::string& path);

// Writes `value` to the file. Throws sb::Error naming the file.
void writeSysfs(const std::string& path, const std::string& value);

}  // namespace sb::power
