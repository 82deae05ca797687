// summary.json's typed sub-objects (report/run_summary.h) against the JSON their owners write elsewhere: the
// energy totals have the keys of power/energy_json.h (STATUS, `slambooster energy --json`) plus the meter's
// name and device, and the knobs the shape of frames.jsonl's, so that a key renamed on one side fails here.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "power/energy_json.h"
#include "report/run_summary.h"
#include "runtime/frame_log_sink.h"

namespace {

std::set<std::string> keys(const nlohmann::json& j) {
  std::set<std::string> out;
  for (auto it = j.begin(); it != j.end(); ++it) out.insert(it.key());
  return out;
}

}  // namespace

TEST_CASE("summary sections: the energy keys are the energy totals' plus meter and device", "[runtime][summary]") {
  sb::RunSummary s;
  s.energy.emplace();
  std::set<std::string> expected = keys(sb::power::energyTotalsJson(sb::power::EnergyTotals{}, {}));
  expected.insert({"meter", "device"});
  CHECK(keys(s.toJson()["energy"]) == expected);
}

TEST_CASE("summary sections: the initial knobs are written as frames.jsonl writes a frame's", "[runtime][summary]") {
  const sb::Knobs k{4, 1e-4, {8, 5, 4}, 1, 5};
  sb::RunSummary s;
  s.knobs = k;
  CHECK(s.toJson()["knobs"] == nlohmann::json::parse(R"({"csr": 4, "icp": 1e-4, "pd": [8, 5, 4], "tr": 1, "ir": 5})"));
  CHECK(sb::knobsToJson(k) == s.toJson()["knobs"]);
}
