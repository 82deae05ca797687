#include "tools/slambooster/machines.h"

#include <algorithm>

namespace sb::cli {

namespace {

void addOnce(std::vector<std::string>& list, const std::string& item) {
  if (std::find(list.begin(), list.end(), item) == list.end()) list.push_back(item);
}

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& i : items) text += (text.empty() ? "" : "; ") + i;
  return text;
}

}  // namespace

MachineMix machineMix(const std::vector<RunSummary>& summaries) {
  MachineMix mix;
  for (const RunSummary& s : summaries) {
    if (!s.machine || s.machine->cpuModel.empty()) {
      addOnce(mix.kinds, "unknown machine (a run from before summaries recorded it)");
      addOnce(mix.hosts, "unknown");
      continue;
    }
    const MachineInfo& m = *s.machine;
    const auto known = [](const std::string& v) { return v.empty() ? std::string("?") : v; };
    const std::string backend = known(m.backend), device = known(m.device), cpu = m.cpuModel;
    // The CPU backend's device is the CPU itself: named once.
    addOnce(mix.kinds, cpu + ", " + std::to_string(m.threadsUsed) + " threads, " + backend +
                           (device == cpu ? " backend" : " " + device));
    addOnce(mix.hosts, known(m.host));
  }
  std::sort(mix.kinds.begin(), mix.kinds.end());
  std::sort(mix.hosts.begin(), mix.hosts.end());
  return mix;
}

std::string MachineMix::note(const std::string& comparing) const {
  if (kinds.empty()) return "";
  if (mixed())
    return "Mixed machines: these runs were timed on " + std::to_string(kinds.size()) + " kinds of machine (" +
           joined(kinds) + "; hosts " + joined(hosts) + "), so " + comparing +
           " compare times taken on different machines; rerun on one kind of machine before trusting them.";
  return "Machine: " + kinds.front() + " (" + std::to_string(hosts.size()) +
         (hosts.size() == 1 ? " host: " : " hosts: ") + joined(hosts) + ").";
}

}  // namespace sb::cli
