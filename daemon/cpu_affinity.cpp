#include "daemon/cpu_affinity.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.h"

namespace sb::daemon {

namespace {

bool readNumber(const std::string& path, long long& out) {
  std::ifstream in(path);
  return static_cast<bool>(in >> out);
}

std::vector<int> allowedCpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

}  // namespace

std::vector<int> parseCpuList(const std::string& text) {
  const std::string usage =
      "CPU list '" + text + "' is not valid; expected \"auto\", \"all\" or e.g. \"4-7\" or \"0,2-3\"";
  std::set<int> cpus;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto dash = item.find('-');
    const std::string a = item.substr(0, dash);
    const std::string b = dash == std::string::npos ? a : item.substr(dash + 1);
    const auto isNumber = [](const std::string& s) {
      return !s.empty() && s.size() <= 4 && s.find_first_not_of("0123456789") == std::string::npos;
    };
    if (!isNumber(a) || !isNumber(b)) throw Error(usage);
    const int lo = std::stoi(a), hi = std::stoi(b);
    if (lo > hi || hi >= CPU_SETSIZE) throw Error(usage);
    for (int c = lo; c <= hi; ++c) cpus.insert(c);
  }
  if (cpus.empty()) throw Error(usage);
  return {cpus.begin(), cpus.end()};
}

std::string formatCpuList(const std::vector<int>& cpus) {
  std::string s;
  for (size_t i = 0; i < cpus.size();) {
    size_t j = i;
    while (j + 1 < cpus.size() && cpus[j + 1] == cpus[j] + 1) ++j;
    s += (s.empty() ? "" : ",") + std::to_string(cpus[i]);
    if (j > i) s += "-" + std::to_string(cpus[j]);
    i = j + 1;
  }
  return s;
}

void validateCpuSpec(const std::string& spec) {
  if (spec != "auto" && spec != "all") parseCpuList(spec);
}

std::vector<int> detectBigCores(const std::string& dir) {
  // Online CPUs: the cpuN directories whose "online" file is not 0 (cpu0 often has no such file).
  std::vector<int> cpus;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 4 || name.compare(0, 3, "cpu") != 0 ||
        name.find_first_not_of("0123456789", 3) != std::string::npos || name.size() > 7)
      continue;
    long long online = 1;
    readNumber(entry.path().string() + "/online", online);
    if (online) cpus.push_back(std::stoi(name.substr(3)));
  }
  std::sort(cpus.begin(), cpus.end());
  for (const char* metric : {"/cpu_capacity", "/cpufreq/cpuinfo_max_freq"}) {
    std::vector<std::pair<int, long long>> values;
    for (int c : cpus) {
      long long v = 0;
      if (readNumber(dir + "/cpu" + std::to_string(c) + metric, v)) values.emplace_back(c, v);
    }
    if (values.size() != cpus.size() || values.empty()) continue;  // not known for every CPU
    long long best = 0;
    for (const auto& [c, v] : values) best = std::max(best, v);
    std::vector<int> big;
    for (const auto& [c, v] : values)
      if (v == best) big.push_back(c);
    if (big.size() < cpus.size()) return big;
  }
  return cpus;
}

std::vector<int> resolveCpus(const std::string& spec, const std::string& sysfsCpuDir) {
  const std::vector<int> allowed = allowedCpus();
  std::vector<int> wanted = spec == "all"    ? allowed
                            : spec == "auto" ? detectBigCores(sysfsCpuDir)
                                             : parseCpuList(spec);
  std::vector<int> cpus;
  for (int c : wanted)
    if (std::find(allowed.begin(), allowed.end(), c) != allowed.end()) cpus.push_back(c);
  if (cpus.empty()) {
    if (spec == "auto") return allowed;  // detection found nothing usable: run anywhere
    throw Error("slam.cpus = \"" + spec + "\": none of these CPUs is available to the daemon (available: " +
                formatCpuList(allowed) + ")");
  }
  return cpus;
}

void pinCurrentThread(const std::vector<int>& cpus) {
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus) CPU_SET(c, &set);
  const int r = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
  if (r != 0)
    throw Error("cannot pin the SLAM thread to CPUs " + formatCpuList(cpus) + ": " + std::strerror(r));
}

}  // namespace sb::daemon
