#pragma once
// Which CPUs the SLAM thread runs on: "auto" picks the big cores of a big.LITTLE system from sysfs (highest
// cpu_capacity, else highest cpufreq/cpuinfo_max_freq; every online CPU when they are all equal or sysfs
// says nothing), "all" every online CPU, or an explicit list like "4-7" or "0,2-3".

#include <string>
#include <vector>

namespace sb::daemon {

// Parses a CPU list ("4-7", "0,2-3"). Throws sb::Error naming the text. Does not check the CPUs exist.
std::vector<int> parseCpuList(const std::string& text);
// The same list back in compact form ("0,2-3").
std::string formatCpuList(const std::vector<int>& cpus);
// Throws sb::Error unless `spec` is "auto", "all" or a valid list.
void validateCpuSpec(const std::string& spec);

// The big cores according to the sysfs tree at `sysfsCpuDir` (normally /sys/devices/system/cpu).
std::vector<int> detectBigCores(const std::string& sysfsCpuDir = "/sys/devices/system/cpu");
// The CPUs for `spec` on this machine, restricted to those the process may run on. Throws sb::Error when an
// explicit list names none of them.
std::vector<int> resolveCpus(const std::string& spec,
                             const std::string& sysfsCpuDir = "/sys/devices/system/cpu");

// Pins the calling thread to `cpus`. Throws sb::Error.
void pinCurrentThread(const std::vector<int>& cpus);

}  // namespace sb::daemon
