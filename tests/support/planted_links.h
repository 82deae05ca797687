#pragma once
// Links planted in an output directory before a run (issue 44 S3), shared by the tool's and the daemon's
// tests: each name becomes a symlink to a victim file outside the directory, every fourth one dangling (its
// target must not come to exist: O_CREAT through the link would make it). After the run, touchedVictims
// lists every victim whose bytes changed and every dangling target that appeared.
//
//   sb::test::PlantedLinks planted = sb::test::plantLinks(out, victims, names);
//   ... the run ...
//   CHECK(sb::test::touchedVictims(planted).empty());

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "tests/support/files.h"

namespace sb::test {

struct PlantedLinks {
  std::map<std::string, std::string> before;  // victim -> its bytes
  std::vector<std::string> dangling;          // targets that must not come to exist
};

// Makes OUT/NAME a symlink to VICTIMS/vN for each name (directories OUT/... must exist).
inline PlantedLinks plantLinks(const std::string& out, const std::string& victims,
                               const std::vector<std::string>& names) {
  PlantedLinks p;
  int n = 0;
  for (const std::string& name : names) {
    const std::string victim = victims + "/v" + std::to_string(++n);
    if (n % 4 == 0) {
      p.dangling.push_back(victim);
    } else {
      std::ofstream(victim) << "victim " << n << " (" << name << ")\n";
      p.before[victim] = readText(victim);
    }
    std::filesystem::create_symlink(victim, out + "/" + name);
  }
  return p;
}

// "VICTIM changed" or "VICTIM was created" for each victim written through a link; empty when none was.
inline std::vector<std::string> touchedVictims(const PlantedLinks& p) {
  std::vector<std::string> touched;
  for (const auto& [victim, bytes] : p.before)
    if (readText(victim) != bytes) touched.push_back(victim + " changed");
  for (const std::string& victim : p.dangling)
    if (std::filesystem::exists(std::filesystem::symlink_status(victim))) touched.push_back(victim + " was created");
  return touched;
}

}  // namespace sb::test
