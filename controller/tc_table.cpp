#include "controller/tc_table.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"

namespace sb {

std::vector<TcEntry> paretoFront(std::vector<TcEntry> c) {
  std::sort(c.begin(), c.end(), [](const TcEntry& a, const TcEntry& b) {
    return a.speedup != b.speedup ? a.speedup > b.speedup : a.ateM < b.ateM;
  });
  // From the fastest down, keep an entry only when it is more accurate than every faster one kept.
  std::vector<TcEntry> front;
  for (const TcEntry& e : c)
    if (front.empty() || e.ateM < front.back().ateM) front.push_back(e);
  std::reverse(front.begin(), front.end());
  return front;
}

nlohmann::json tcTableToJson(const TcTable& t) {
  nlohmann::json entries = nlohmann::json::array();
  for (const TcEntry& e : t.entries)
    entries.push_back({{"knobs", formatKnobs(e.knobs)}, {"ms_per_frame", e.msPerFrame}, {"speedup", e.speedup},
                       {"ate_m", e.ateM}});
  return {{"reference_ms_per_frame", t.referenceMsPerFrame}, {"sequences", t.sequences}, {"entries", entries}};
}

TcTable tcTableFromJson(const nlohmann::json& j, const std::string& where) {
  TcTable t;
  try {
    t.referenceMsPerFrame = j.at("reference_ms_per_frame").get<double>();
    if (j.contains("sequences")) t.sequences = j.at("sequences").get<std::vector<std::string>>();
    for (const auto& e : j.at("entries")) {
      TcEntry entry;
      entry.knobs = parseKnobs(e.at("knobs").get<std::string>());
      entry.msPerFrame = e.at("ms_per_frame").get<double>();
      entry.speedup = e.at("speedup").get<double>();
      entry.ateM = e.at("ate_m").get<double>();
      t.entries.push_back(entry);
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": not a tc configuration table (" + e.what() + "); build one with `slambooster profile`");
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  if (t.entries.empty()) throw Error(where + ": the tc configuration table has no entries");
  std::sort(t.entries.begin(), t.entries.end(), [](const TcEntry& a, const TcEntry& b) { return a.speedup < b.speedup; });
  return t;
}

TcTable loadTcTable(const std::string& path) {
  const std::string problem = pathProblem(path);
  if (!problem.empty())
    throw Error("tc table " + quoteForMessage(path) + " " + problem + " (build it with `slambooster profile`)");
  try {
    return tcTableFromJson(readJsonConfig(path, "tc table"), path);  // the one settings-file loader
  } catch (const nlohmann::json::exception& e) {
    throw Error("tc table '" + path + "' is not valid JSON: " + e.what());
  }
}

}  // namespace sb
